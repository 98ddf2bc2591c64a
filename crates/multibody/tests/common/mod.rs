//! Test helpers: the subject model rebuilt from the reference JSON (independent of the
//! `.osim` importer), reference-data location and a minimal storage-file reader.
#![allow(dead_code)]

use std::path::PathBuf;

use serde_json::Value;
use stride_model::*;

/// Root of the shared reference data, if present.
pub fn shared() -> Option<PathBuf> {
    let p = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared"));
    if p.join("reference").exists() {
        Some(p)
    } else {
        eprintln!(
            "skipping: shared reference data not found at {}",
            p.display()
        );
        None
    }
}

fn arr3(v: &Value) -> [f64; 3] {
    let a = v.as_array().unwrap();
    [
        a[0].as_f64().unwrap(),
        a[1].as_f64().unwrap(),
        a[2].as_f64().unwrap(),
    ]
}

fn function(v: &Value) -> Function {
    match v["type"].as_str().unwrap() {
        "linear" => Function::Linear {
            slope: v["slope"].as_f64().unwrap(),
            intercept: v["intercept"].as_f64().unwrap(),
        },
        "constant" => Function::Constant(v["value"].as_f64().unwrap()),
        "multiplier_of_constant" => Function::Multiplier {
            scale: v["scale"].as_f64().unwrap(),
            function: Box::new(Function::Constant(v["constant"].as_f64().unwrap())),
        },
        t => panic!("unknown function type {t}"),
    }
}

/// The 31-coordinate subject model of `subject1_contact_and_joints.json` (bodies with
/// full `.osim` precision when `full_precision`), with the 12 contact spheres.
pub fn subject_model(full_precision: bool) -> Option<Model> {
    let root = shared()?;
    let path = root.join("reference/models/subject1_contact_and_joints.json");
    let j: Value = serde_json::from_str(&std::fs::read_to_string(path).ok()?).ok()?;
    let mut m = Model {
        name: "subject1_v2".into(),
        ..Default::default()
    };
    let body_key = if full_precision {
        "bodies_osim_full_precision"
    } else {
        "bodies"
    };
    for b in j[body_key].as_array().unwrap() {
        let im = arr3(&b["inertia_moments"]);
        let ip = arr3(&b["inertia_products"]);
        m.bodies.push(Body {
            name: b["name"].as_str().unwrap().into(),
            mass: b["mass"].as_f64().unwrap(),
            com: arr3(&b["mass_center"]),
            inertia: [im[0], im[1], im[2], ip[0], ip[1], ip[2]],
        });
    }
    for c in j["coordinates_external_function_order"].as_array().unwrap() {
        let r = c["osim_range"].as_array().unwrap();
        m.coordinates.push(Coordinate {
            name: c["name"].as_str().unwrap().into(),
            joint: 0,
            motion_type: if c["motion_type"] == "translational" {
                MotionType::Translational
            } else {
                MotionType::Rotational
            },
            range: [r[0].as_f64().unwrap(), r[1].as_f64().unwrap()],
            default_value: c["osim_default_value"].as_f64().unwrap(),
            locked: c["osim_locked"].as_bool().unwrap(),
        });
    }
    let joints = j["joints"].as_array().unwrap();
    for name in j["joint_add_order"].as_array().unwrap() {
        let jt = joints.iter().find(|x| x["name"] == *name).unwrap();
        let parent = m.body_index(jt["parent"].as_str().unwrap()).unwrap();
        let child = m.body_index(jt["child"].as_str().unwrap()).unwrap();
        let kind = if jt["type"] == "weld" {
            JointKind::Weld
        } else {
            let ax: Vec<TransformAxis> = jt["transform_axes"]
                .as_array()
                .unwrap()
                .iter()
                .map(|a| TransformAxis {
                    axis: arr3(&a["axis"]),
                    coordinate: a["coordinate"]
                        .as_str()
                        .map(|c| m.coordinate_index(c).unwrap()),
                    function: function(&a["function"]),
                })
                .collect();
            let mut it = ax.into_iter();
            let mut next = || it.next().unwrap();
            JointKind::Custom {
                rotations: [next(), next(), next()],
                translations: [next(), next(), next()],
            }
        };
        let ji = m.joints.len();
        if let JointKind::Custom {
            rotations,
            translations,
        } = &kind
        {
            for a in rotations.iter().chain(translations.iter()) {
                if let Some(c) = a.coordinate {
                    m.coordinates[c].joint = ji;
                }
            }
        }
        let off = |l: &str, o: &str| Offset {
            location: jt.get(l).map(arr3).unwrap_or([0.0; 3]),
            orientation: jt.get(o).map(arr3).unwrap_or([0.0; 3]),
        };
        m.joints.push(Joint {
            name: name.as_str().unwrap().into(),
            parent,
            child,
            frame_in_parent: off("location_in_parent", "orientation_in_parent"),
            frame_in_child: off("location_in_child", "orientation_in_child"),
            kind,
        });
    }
    let c = &j["contact"];
    let cp = &c["common_parameters"];
    let params = ContactParameters {
        stiffness: cp["stiffness"].as_f64().unwrap(),
        dissipation: cp["dissipation"].as_f64().unwrap(),
        static_friction: cp["static_friction"].as_f64().unwrap(),
        dynamic_friction: cp["dynamic_friction"].as_f64().unwrap(),
        viscous_friction: cp["viscous_friction"].as_f64().unwrap(),
        transition_velocity: cp["transition_velocity"].as_f64().unwrap(),
        ..Default::default()
    };
    for s in c["spheres"].as_array().unwrap() {
        m.contacts.push(ContactSphere {
            name: s["name"].as_str().unwrap().into(),
            body: m.body_index(s["body"].as_str().unwrap()).unwrap(),
            location: arr3(&s["location_in_body"]),
            radius: s["radius"].as_f64().unwrap(),
            parameters: params,
            plane_point: [0.0; 3],
            plane_normal: arr3(&cp["normal_in_ground"]),
        });
    }
    Some(m)
}

/// A storage (`.mot`/`.sto`) table: column names (without `time`), times and rows.
pub struct Table {
    pub names: Vec<String>,
    pub time: Vec<f64>,
    pub columns: Vec<Vec<f64>>,
    pub in_degrees: bool,
}

impl Table {
    pub fn read(path: &std::path::Path) -> Table {
        let text = std::fs::read_to_string(path).unwrap();
        let mut lines = text.lines();
        let mut in_degrees = false;
        for l in lines.by_ref() {
            if l.trim().starts_with("inDegrees") {
                in_degrees = l.contains("yes");
            }
            if l.trim() == "endheader" {
                break;
            }
        }
        let header: Vec<String> = lines
            .next()
            .unwrap()
            .split_whitespace()
            .map(String::from)
            .collect();
        let mut time = Vec::new();
        let mut columns = vec![Vec::new(); header.len() - 1];
        for l in lines {
            let v: Vec<f64> = l.split_whitespace().map(|x| x.parse().unwrap()).collect();
            if v.len() != header.len() {
                continue;
            }
            time.push(v[0]);
            for (k, c) in columns.iter_mut().enumerate() {
                c.push(v[k + 1]);
            }
        }
        Table {
            names: header[1..].to_vec(),
            time,
            columns,
            in_degrees,
        }
    }
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.names
            .iter()
            .position(|n| n == name)
            .map(|i| self.columns[i].as_slice())
    }
}
