//! Reference tables attached to subject1_v2, checked against the numbers published in
//! FORMULATION.md (sections 1.4, 1.5, 6) and the OCP index → polynomial row map
//! (skipped when /work/shared is absent).

use serde_json::Value;
use std::path::PathBuf;
use stride_model::osim::load_osim;
use stride_model::reference::*;
use stride_model::Model;

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

fn model(r: &std::path::Path) -> Model {
    load_osim(&r.join("models/subject1_v2.osim")).unwrap()
}

#[test]
fn contact_spheres_match_formulation_table() {
    let Some(r) = reference() else { return };
    let mut m = model(&r);
    let n = add_contacts(&mut m, &r.join("models/subject1_contact_and_joints.json")).unwrap();
    assert_eq!(n, 12);
    // FORMULATION 1.5 (right foot; left = z negated).
    let table: [(&str, [f64; 3]); 6] = [
        (
            "calcn",
            [0.00190115788407966, -0.021859, -0.00382630379623308],
        ),
        ("calcn", [0.148386399942063, -0.021859, -0.028713422052654]),
        ("calcn", [0.133001170607051, -0.021859, 0.0516362473449566]),
        ("toes", [0.06, -0.0214476, -0.0187603084619177]),
        ("calcn", [0.0662346661991635, -0.021859, 0.0263641606741698]),
        ("toes", [0.045, -0.0214476, 0.0618569567549652]),
    ];
    for side in ["r", "l"] {
        for (k, (body, loc)) in table.iter().enumerate() {
            let name = format!("sphere_{}_{side}", k + 1);
            let c = m.contacts.iter().find(|c| c.name == name).unwrap();
            assert_eq!(m.bodies[c.body].name, format!("{body}_{side}"), "{name}");
            let z = if side == "r" { loc[2] } else { -loc[2] };
            assert_eq!(c.location, [loc[0], loc[1], z], "{name}");
            assert_eq!(c.radius, 0.032);
            assert_eq!(c.plane_normal, [0.0, 1.0, 0.0]);
            assert_eq!(c.plane_point, [0.0, 0.0, 0.0]);
            let p = c.parameters;
            assert_eq!(
                [
                    p.stiffness,
                    p.dissipation,
                    p.static_friction,
                    p.dynamic_friction
                ],
                [1e6, 2.0, 0.8, 0.8]
            );
            assert_eq!([p.viscous_friction, p.transition_velocity], [0.5, 0.2]);
            assert_eq!(
                [
                    p.constant_contact_force,
                    p.hertz_smoothing,
                    p.hunt_crossley_smoothing
                ],
                [1e-5, 300.0, 50.0]
            );
        }
    }
}

#[test]
fn passive_torques_match_formulation_table() {
    let Some(r) = reference() else { return };
    let mut m = model(&r);
    let n = add_passive_torques(&mut m, &r.join("joints/passive_moments.json")).unwrap();
    assert_eq!(n, 23, "15 exponential + 8 arm damping");
    let get = |name: &str| {
        let c = m.coordinate_index(name).unwrap();
        m.passive_torques
            .iter()
            .find(|p| p.coordinate == c)
            .unwrap()
            .clone()
    };
    // FORMULATION 6.1.
    let rows: [(&str, [f64; 4], [f64; 2]); 9] = [
        ("hip_flexion", [-2.44, 5.05, 1.51, -21.88], [-0.6981, 1.81]),
        ("hip_adduction", [-0.03, 14.94, 0.03, -14.94], [-0.5, 0.5]),
        ("hip_rotation", [-0.03, 14.94, 0.03, -14.94], [-0.92, 0.92]),
        ("knee_angle", [-6.09, 33.94, 11.03, -11.33], [-2.4, 0.13]),
        ("ankle_angle", [-2.03, 38.11, 0.18, -12.12], [-0.74, 0.52]),
        (
            "subtalar_angle",
            [-60.21, 16.32, 60.21, -16.32],
            [-0.65, 0.65],
        ),
        (
            "lumbar_extension",
            [-0.35, 30.72, 0.25, -20.36],
            [-0.5235987755982988, 0.17],
        ),
        (
            "lumbar_bending",
            [-0.25, 20.36, 0.25, -20.36],
            [-0.3490658503988659, 0.3490658503988659],
        ),
        (
            "lumbar_rotation",
            [-0.25, 20.36, 0.25, -20.36],
            [-0.3490658503988659, 0.3490658503988659],
        ),
    ];
    for (base, k, theta) in rows {
        let names: Vec<String> = if base.starts_with("lumbar") {
            vec![base.to_string()]
        } else {
            vec![format!("{base}_l"), format!("{base}_r")]
        };
        for name in names {
            let p = get(&name);
            assert_eq!((p.k, p.theta, p.damping), (k, theta, 0.1), "{name}");
        }
    }
    for name in ARM_COORDINATES {
        let p = get(name);
        assert_eq!((p.k, p.damping), ([0.0; 4], 0.1), "{name}");
    }
    assert!(m
        .coordinate_index("pelvis_tilt")
        .is_some_and(|c| m.passive_torques.iter().all(|p| p.coordinate != c)));
}

#[test]
fn metabolic_parameters_match_formulation_table() {
    let Some(r) = reference() else { return };
    let mut m = model(&r);
    let n = add_metabolic_parameters(&mut m, &r.join("muscles/metabolic_parameters.json")).unwrap();
    assert_eq!(n, 92);
    // FORMULATION 1.4 (sigma in MPa, f_ST).
    for (name, sigma, fst) in [
        ("glut_med1_r", 0.74455, 0.55),
        ("glut_med1_l", 0.74455, 0.55),
        ("soleus_l", 0.62703, 0.803),
        ("rect_fem_r", 0.74936, 0.3865),
        ("ercspn_l", 0.25, 0.6),
        ("extobl_r", 0.25, 0.58),
    ] {
        let mu = &m.muscles[m.muscle_index(name).unwrap()];
        assert_eq!(mu.slow_twitch_fraction, fst, "{name}");
        assert!((mu.specific_tension - sigma * 1e6).abs() < 1e-6, "{name}");
    }
}

#[test]
fn polynomials_follow_the_ocp_row_map() {
    let Some(r) = reference() else { return };
    let mut m = model(&r);
    let path = r.join("muscles/polynomials_subject1.json");
    let n = add_path_polynomials(&mut m, &path).unwrap();
    assert_eq!(n, 92);
    assert_eq!(m.path_polynomials.len(), 92);
    let j: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let rows = j["muscles"].as_array().unwrap();
    let map = j["use_in_ocp"]["mapping_ocp_index_to_row"]
        .as_object()
        .unwrap();
    let idx: Value = serde_json::from_str(
        &std::fs::read_to_string(r.join("muscles/muscle_indices.json")).unwrap(),
    )
    .unwrap();
    let order: Vec<&str> = idx["muscle_order"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_str().or_else(|| x["name"].as_str()).unwrap())
        .collect();
    assert_eq!(order.len(), 92);
    for (k, name) in order.iter().enumerate() {
        let row = map[&(k + 1).to_string()].as_u64().unwrap() as usize;
        let rj = &rows[row - 1];
        let p = m.path_polynomials[m.muscle_index(name).unwrap()]
            .as_ref()
            .unwrap();
        let coefs: Vec<f64> = rj["coefficients"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_f64().unwrap())
            .collect();
        assert_eq!(p.coefficients, coefs, "{name}");
        assert_eq!(p.order as u64, rj["order"].as_u64().unwrap(), "{name}");
        // Coordinates: the row's, with the muscle's side (lumbar shared).
        let side = &name[name.len() - 2..];
        for (c, rc) in p
            .coordinates
            .iter()
            .zip(rj["coordinates"].as_array().unwrap())
        {
            let rc = rc.as_str().unwrap();
            let want = if rc.starts_with("lumbar") {
                rc.to_string()
            } else {
                format!("{}{side}", &rc[..rc.len() - 2])
            };
            assert_eq!(m.coordinates[*c].name, want, "{name}");
        }
    }
    // FORMULATION 1.4: orders of a few fits.
    for (name, order) in [
        ("glut_max3_l", 8),
        ("vas_med_r", 9),
        ("psoas_l", 5),
        ("intobl_l", 5),
    ] {
        assert_eq!(
            m.path_polynomials[m.muscle_index(name).unwrap()]
                .as_ref()
                .unwrap()
                .order,
            order,
            "{name}"
        );
    }
}

#[test]
fn arm_actuators() {
    let Some(r) = reference() else { return };
    let mut m = model(&r);
    assert_eq!(add_arm_actuators(&mut m), 8);
    assert_eq!(m.actuators.len(), 8);
    for a in &m.actuators {
        assert_eq!((a.optimal_force, a.control_range), (150.0, [-1.0, 1.0]));
    }
}

#[test]
fn bad_reference_file_names_location() {
    let Some(r) = reference() else { return };
    let mut m = model(&r);
    let dir = std::env::temp_dir().join(format!("stride_ref_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join("contact.json");
    std::fs::write(
        &p,
        r#"{"contact": {"common_parameters": {"stiffness": 1e6, "dissipation": 2, "static_friction": 0.8,
        "dynamic_friction": 0.8, "viscous_friction": 0.5, "transition_velocity": 0.2,
        "normal_in_ground": [0, 1, 0], "offset": 0},
        "spheres": [{"name": "s", "body": "calcn_x", "location_in_body": [0, 0, 0], "radius": 0.03}]}}"#,
    )
    .unwrap();
    let e = add_contacts(&mut m, &p).unwrap_err().to_string();
    assert!(
        e.contains("contact/spheres/0/body") && e.contains("calcn_x"),
        "{e}"
    );
    std::fs::write(&p, "{\"contact\": ").unwrap();
    let e = add_contacts(&mut m, &p).unwrap_err().to_string();
    assert!(e.contains("invalid JSON") && e.contains("line 1"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}
