//! Import of the reference OpenSim models, checked against the independent tables of
//! `subject1_contact_and_joints.json` (skipped when /work/shared is absent).

// Numbers are copied verbatim from the .osim text (17 significant digits).
#![allow(clippy::excessive_precision)]

use serde_json::Value;
use std::path::PathBuf;
use stride_model::osim::load_osim;
use stride_model::{Function, JointKind, MotionType};

fn reference() -> Option<PathBuf> {
    let p = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/reference"
    ));
    if p.is_dir() {
        Some(p)
    } else {
        eprintln!("skipping: reference data not found at {}", p.display());
        None
    }
}

fn json(p: PathBuf) -> Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap()
}

fn v3(v: &Value) -> [f64; 3] {
    let a = v.as_array().unwrap();
    [f(&a[0]), f(&a[1]), f(&a[2])]
}

/// Equal to 5 significant digits (the JSON rounding), with room for axis normalisation.
fn close5(a: f64, b: f64) -> bool {
    (a - b).abs() <= 6e-5 * a.abs().max(b.abs()) + 1e-12
}

#[test]
fn subject1_v2_bodies_match_full_precision_table() {
    let Some(r) = reference() else { return };
    let m = load_osim(&r.join("models/subject1_v2.osim")).unwrap();
    let j = json(r.join("models/subject1_contact_and_joints.json"));
    let table = j["bodies_osim_full_precision"].as_array().unwrap();
    assert_eq!(m.bodies.len(), 21, "20 bodies + ground");
    assert_eq!(table.len(), 20);
    for b in table {
        let name = b["name"].as_str().unwrap();
        let id = m
            .body_index(name)
            .unwrap_or_else(|| panic!("body {name} missing"));
        let mb = &m.bodies[id];
        assert_eq!(mb.mass, f(&b["mass"]), "{name} mass");
        assert_eq!(mb.com, v3(&b["mass_center"]), "{name} com");
        let mo = v3(&b["inertia_moments"]);
        let pr = v3(&b["inertia_products"]);
        assert_eq!(
            mb.inertia,
            [mo[0], mo[1], mo[2], pr[0], pr[1], pr[2]],
            "{name} inertia"
        );
    }
    // The full-precision masses of the file sum to 62 kg; 61.999948 kg is the sum of the
    // masses rounded to 5 significant digits (the `bodies` table of the JSON).
    let full: f64 = table.iter().map(|b| f(&b["mass"])).sum();
    assert!((m.total_mass() - full).abs() <= 1e-12, "{}", m.total_mass());
    assert!((m.total_mass() - 62.0).abs() <= 1e-6, "{}", m.total_mass());
    let rounded: f64 = j["bodies"]
        .as_array()
        .unwrap()
        .iter()
        .map(|b| f(&b["mass"]))
        .sum();
    assert!((rounded - 61.999948).abs() <= 1e-6, "{rounded}");
    assert_eq!(m.gravity, [0.0, -9.80665, 0.0]);
}

#[test]
fn subject1_v2_joints_match_rounded_table() {
    let Some(r) = reference() else { return };
    let m = load_osim(&r.join("models/subject1_v2.osim")).unwrap();
    let j = json(r.join("models/subject1_contact_and_joints.json"));
    let joints = j["joints"].as_array().unwrap();
    assert_eq!(m.joints.len(), joints.len());
    for jr in joints {
        let name = jr["name"].as_str().unwrap();
        let mj = m.joints.iter().find(|x| x.name == name).unwrap();
        assert_eq!(
            m.bodies[mj.parent].name,
            jr["parent"].as_str().unwrap(),
            "{name}"
        );
        assert_eq!(
            m.bodies[mj.child].name,
            jr["child"].as_str().unwrap(),
            "{name}"
        );
        let pairs = [
            (mj.frame_in_parent.location, "location_in_parent"),
            (mj.frame_in_parent.orientation, "orientation_in_parent"),
            (mj.frame_in_child.location, "location_in_child"),
            (mj.frame_in_child.orientation, "orientation_in_child"),
        ];
        for (mine, key) in pairs {
            let refv = v3(&jr[key]);
            for k in 0..3 {
                assert!(
                    close5(mine[k], refv[k]),
                    "{name} {key}: {mine:?} vs {refv:?}"
                );
            }
        }
        match (&mj.kind, jr["type"].as_str().unwrap()) {
            (JointKind::Weld, "weld") => {}
            (
                JointKind::Custom {
                    rotations,
                    translations,
                },
                "custom",
            ) => {
                let axes = jr["transform_axes"].as_array().unwrap();
                for (k, ax) in rotations.iter().chain(translations.iter()).enumerate() {
                    let a = v3(&axes[k]["axis"]);
                    let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
                    for d in 0..3 {
                        assert!(
                            close5(ax.axis[d], a[d] / n),
                            "{name} axis {k}: {:?} vs {a:?}",
                            ax.axis
                        );
                    }
                    let coord = axes[k]["coordinate"].as_str();
                    assert_eq!(
                        ax.coordinate.map(|c| m.coordinates[c].name.as_str()),
                        coord,
                        "{name} axis {k}"
                    );
                    match axes[k]["function"]["type"].as_str().unwrap() {
                        "linear" => assert_eq!(
                            ax.function,
                            Function::Linear {
                                slope: 1.0,
                                intercept: 0.0
                            }
                        ),
                        "constant" => assert_eq!(ax.function, Function::Constant(0.0)),
                        "multiplier_of_constant" => match &ax.function {
                            Function::Multiplier { scale, function } => {
                                assert_eq!(**function, Function::Constant(0.0));
                                assert!(
                                    close5(*scale, f(&axes[k]["function"]["scale"])),
                                    "{name} scale"
                                );
                            }
                            other => panic!("{name} axis {k}: {other:?}"),
                        },
                        t => panic!("unexpected function type {t}"),
                    }
                }
            }
            (k, t) => panic!("{name}: {k:?} vs {t}"),
        }
    }
    // Joints are in topological order.
    for (k, jn) in m.joints.iter().enumerate() {
        assert!(
            jn.parent == 0 || m.joints[..k].iter().any(|p| p.child == jn.parent),
            "{}",
            jn.name
        );
    }
}

#[test]
fn subject1_v2_coordinates_and_muscles() {
    let Some(r) = reference() else { return };
    let m = load_osim(&r.join("models/subject1_v2.osim")).unwrap();
    let j = json(r.join("models/subject1_contact_and_joints.json"));
    let coords = j["coordinates_external_function_order"].as_array().unwrap();
    assert_eq!(m.coordinates.len(), 31);
    assert_eq!(coords.len(), 31);
    for c in coords {
        let name = c["name"].as_str().unwrap();
        let i = m.coordinate_index(name).unwrap_or_else(|| panic!("{name}"));
        let mc = &m.coordinates[i];
        assert_eq!(
            m.joints[mc.joint].name,
            c["joint"].as_str().unwrap(),
            "{name}"
        );
        let mt = match c["motion_type"].as_str().unwrap() {
            "rotational" => MotionType::Rotational,
            _ => MotionType::Translational,
        };
        assert_eq!(mc.motion_type, mt, "{name}");
        let rg = c["osim_range"].as_array().unwrap();
        assert_eq!(mc.range, [f(&rg[0]), f(&rg[1])], "{name}");
        assert_eq!(mc.default_value, f(&c["osim_default_value"]), "{name}");
        assert_eq!(mc.locked, c["osim_locked"].as_bool().unwrap(), "{name}");
    }
    assert_eq!(m.muscles.len(), 92);
    assert!(m.contacts.is_empty());
    // Muscle parameters equal the independent CSV (same-named muscles).
    let csv = std::fs::read_to_string(r.join("muscles/mt_parameters_subject1.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| header.iter().position(|h| h.contains(n)).unwrap();
    let (cn, cf, cl, cs, ca) = (
        col("muscle"),
        col("max_isometric_force"),
        col("optimal_fiber_length"),
        col("tendon_slack_length"),
        col("pennation"),
    );
    let mut n = 0;
    for l in lines {
        let v: Vec<&str> = l.split(',').collect();
        let mu = &m.muscles[m.muscle_index(v[cn]).unwrap()];
        assert_eq!(mu.max_isometric_force, v[cf].parse::<f64>().unwrap());
        assert_eq!(mu.optimal_fiber_length, v[cl].parse::<f64>().unwrap());
        assert_eq!(mu.tendon_slack_length, v[cs].parse::<f64>().unwrap());
        assert_eq!(mu.pennation_angle_at_optimal, v[ca].parse::<f64>().unwrap());
        assert_eq!(mu.max_contraction_velocity, 10.0);
        n += 1;
    }
    assert_eq!(n, 92);
    let total_points: usize = m.muscles.iter().map(|mu| mu.path.len()).sum();
    assert_eq!(total_points, 288 + 26 + 8);
}

#[test]
fn subject1_v1_has_37_coordinates() {
    let Some(r) = reference() else { return };
    let m = load_osim(&r.join("models/subject1.osim")).unwrap();
    assert_eq!(m.coordinates.len(), 37);
    assert_eq!(m.muscles.len(), 92);
    assert_eq!(m.bodies.len(), 21);
    for name in ["mtp_angle_r", "mtp_angle_l"] {
        assert!(m.coordinate_index(name).is_some(), "{name}");
    }
}

#[test]
fn hamner_loads_with_contacts_and_reports() {
    let Some(r) = reference() else { return };
    let m = load_osim(&r.join("models/Hamner_modified_scaled.osim")).unwrap();
    eprintln!(
        "Hamner: {} bodies, {} joints, {} coordinates, {} muscles, {} contacts, {} unsupported",
        m.bodies.len(),
        m.joints.len(),
        m.coordinates.len(),
        m.muscles.len(),
        m.contacts.len(),
        m.unsupported.len()
    );
    for u in &m.unsupported {
        eprintln!("  {} {} line {}: {}", u.element, u.name, u.line, u.reason);
    }
    assert_eq!(m.coordinates.len(), 31);
    assert!(m.coordinate_index("mtp_angle_r").is_some());
    assert_eq!(m.muscles.len(), 92);
    assert_eq!(m.contacts.len(), 12);
    let c = &m.contacts[0];
    assert_eq!(c.name, "SmoothSphereHalfSpaceForce_s1_r");
    assert_eq!(m.bodies[c.body].name, "calcn_r");
    assert_eq!(c.radius, 0.032);
    assert_eq!(
        c.location,
        [0.0019011578840796601, -0.01, -0.00382630379623308]
    );
    assert_eq!(c.plane_normal, [0.0, 1.0, 0.0]);
    assert_eq!(c.plane_point, [0.0, 0.0, 0.0]);
    assert_eq!(c.parameters.stiffness, 1.0e6);
    assert_eq!(c.parameters.transition_velocity, 0.2);
    assert_eq!(c.parameters.constant_contact_force, 1.0e-5);
    // Hip offset from the PhysicalOffsetFrame.
    let hip = m.joints.iter().find(|j| j.name == "hip_r").unwrap();
    assert_eq!(
        hip.frame_in_parent.location,
        [
            -0.068277800171117939,
            -0.06383539733113007,
            0.08233069400586876
        ]
    );
    assert_eq!(m.bodies[hip.parent].name, "pelvis");
    // The mtp pin joint rotates about z of the calcaneus offset frame.
    let mtp = m.joints.iter().find(|j| j.name == "mtp_r").unwrap();
    let JointKind::Custom { rotations, .. } = &mtp.kind else {
        panic!()
    };
    assert_eq!(rotations[0].axis, [0.0, 0.0, 1.0]);
    assert_eq!(rotations[0].coordinate, m.coordinate_index("mtp_angle_r"));
    // Visual content and markers are counted in the summary entry.
    let s = m
        .unsupported
        .iter()
        .find(|u| u.element == "(visual/bookkeeping)")
        .unwrap();
    assert!(s.reason.contains("47 Marker"), "{}", s.reason);
}
