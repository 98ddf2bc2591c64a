//! Import of OpenSim's own models (`../shared/reference/models/opensim/`, skipped when
//! absent) and of the shipped models, checked against numbers OpenSim 4.6 computed
//! (`tests/data/opensim/`, written by `tools/opensim_reference/`).

use serde_json::Value;
use std::path::{Path, PathBuf};
use stride_model::osim::load_osim;
use stride_model::{Model, MotionType};

fn opensim_models() -> Option<PathBuf> {
    let p = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/reference/models/opensim"
    ));
    if p.is_dir() {
        Some(p)
    } else {
        eprintln!("skipping: OpenSim models not found at {}", p.display());
        None
    }
}

fn data(name: &str) -> Value {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/opensim")
        .join(name);
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

fn shipped(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data/models")
        .join(rel)
}

fn check_motion_types(model: &Model, file: &str, want: &Value) {
    let want = want[file]
        .as_object()
        .unwrap_or_else(|| panic!("{file}: no reference motion types"));
    assert_eq!(
        model.coordinates.len(),
        want.len(),
        "{file}: coordinate count"
    );
    for c in &model.coordinates {
        let expected = match want[&c.name].as_str() {
            Some("Rotational") => MotionType::Rotational,
            Some("Translational") => MotionType::Translational,
            Some("Coupled") => MotionType::Coupled,
            other => panic!("{file}: {}: reference motion type {other:?}", c.name),
        };
        assert_eq!(c.motion_type, expected, "{file}: {}", c.name);
    }
}

#[test]
fn motion_types_equal_opensims() {
    let want = data("motion_types.json");
    for rel in [
        "subject1/subject1_v2.osim",
        "falisse2022/Falisse_et_al_2022.osim",
        "gait1018/gait1018.osim",
        "dhondt2024/DHondt_et_al_2024_4seg.osim",
    ] {
        let p = shipped(rel);
        let file = p.file_name().unwrap().to_str().unwrap().to_string();
        check_motion_types(&load_osim(&p).unwrap(), &file, &want);
    }
    let Some(dir) = opensim_models() else { return };
    for rel in [
        "gait2392_millard2012muscle.osim",
        "gait10dof18musc.osim",
        "Rajagopal2016.osim",
        "FullBodyModel_Hamner2010_v2_0.osim",
        "gait2392_pipeline/subject01_simbody.osim",
        "moco_example2DWalking/2D_gait.osim",
    ] {
        let p = dir.join(rel);
        let file = p.file_name().unwrap().to_str().unwrap().to_string();
        let model = load_osim(&p).unwrap_or_else(|e| panic!("{e}"));
        check_motion_types(&model, &file, &want);
    }
}

/// Moco's example model keeps its muscles, contacts and actuator in `<components>`.
#[test]
fn moco_2d_gait_reads_its_components() {
    let Some(dir) = opensim_models() else { return };
    let m = load_osim(&dir.join("moco_example2DWalking/2D_gait.osim")).unwrap();
    assert_eq!(m.muscles.len(), 18);
    assert_eq!(m.contacts.len(), 4);
    assert_eq!(m.actuators.len(), 1);
    assert_eq!(m.actuators[0].name, "lumbarAct");
    assert!(m
        .muscles
        .iter()
        .all(|mu| mu.kind == stride_model::MuscleKind::DeGrooteFregly2016));
    let heel = m
        .contacts
        .iter()
        .find(|c| c.name == "contactHeel_r")
        .unwrap();
    assert_eq!(m.bodies[heel.body].name, "calcn_r");
    // Nothing is left unread but the rigid-tendon option of the 18 muscles and visual
    // or bookkeeping content.
    for u in &m.unsupported {
        assert!(
            u.reason.starts_with("ignore_tendon_compliance") || u.element == "(visual/bookkeeping)",
            "{u:?}"
        );
    }
    let rigid = m
        .unsupported
        .iter()
        .filter(|u| u.reason.starts_with("ignore_tendon_compliance"))
        .count();
    assert_eq!(rigid, 18);
}

fn two_link_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/opensim/two_link_components.osim")
}

/// Muscle–tendon length of a path polynomial at pose `q`, and its moment arm −∂l/∂q about
/// coordinate `c` (by the exact derivative of each monomial).
fn poly_length_and_arm(p: &stride_model::PathPolynomial, q: &[f64], c: usize) -> (f64, f64) {
    if !p.coordinates.contains(&c) {
        let (l, _) = poly_length_and_arm(p, q, p.coordinates[0]);
        return (l, 0.0);
    }
    let (mut l, mut dl) = (0.0, 0.0);
    for (e, coef) in p.exponents.iter().zip(&p.coefficients) {
        let mut term = *coef;
        let mut d = *coef;
        for (j, &k) in p.coordinates.iter().enumerate() {
            let x = q[k];
            term *= x.powi(e[j] as i32);
            d *= if k == c {
                if e[j] == 0 {
                    0.0
                } else {
                    e[j] as f64 * x.powi(e[j] as i32 - 1)
                }
            } else {
                x.powi(e[j] as i32)
            };
        }
        l += term;
        dl += d;
    }
    (l, -dl)
}

#[test]
fn function_based_paths_and_expression_force_equal_opensims() {
    let m = load_osim(&two_link_path()).unwrap_or_else(|e| panic!("{e}"));
    let r = data("two_link_components.json");
    assert_eq!(m.muscles.len(), 2);
    assert_eq!(m.coordinate_forces.len(), 1);
    let spring = &m.coordinate_forces[0];
    assert_eq!(
        (spring.name.as_str(), spring.coordinate),
        ("knee_spring", m.coordinate_index("knee_angle").unwrap())
    );
    let stride_model::CoordinateForceLaw::Expression(e) = &spring.law else {
        panic!("{:?}", spring.law)
    };
    for s in r["samples"].as_array().unwrap() {
        let q: Vec<f64> = s["q"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        let u: Vec<f64> = s["u"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        let tau = s["spring_generalised_forces"].as_array().unwrap();
        let got = e.eval(&[q[spring.coordinate], u[spring.coordinate]]);
        let want = tau[spring.coordinate].as_f64().unwrap();
        assert!(
            (got - want).abs() <= 1e-10 * want.abs().max(1.0),
            "{got} vs {want}"
        );
        assert_eq!(tau[1 - spring.coordinate].as_f64().unwrap(), 0.0);
        for mu in &m.muscles {
            let p = mu.path_function.as_ref().expect("function-based path");
            assert!(mu.path.is_empty());
            let want = &s[&mu.name];
            for c in 0..2 {
                let (l, arm) = poly_length_and_arm(p, &q, c);
                let wl = want["length"].as_f64().unwrap();
                let wa = want["moment_arms"][c].as_f64().unwrap();
                assert!((l - wl).abs() < 1e-12, "{} length {l} vs {wl}", mu.name);
                assert!(
                    (arm - wa).abs() < 1e-10,
                    "{} arm {c}: {arm} vs {wa}",
                    mu.name
                );
            }
        }
    }
}

fn parse_err(text: &str) -> String {
    let e = stride_model::osim::parse_osim(text, "bad.osim")
        .unwrap_err()
        .to_string();
    assert!(!e.contains('\n'), "{e}");
    assert!(e.starts_with("bad.osim:"), "{e}");
    e
}

#[test]
fn bad_expression_and_polynomial_are_one_line_errors() {
    let text = std::fs::read_to_string(two_link_path()).unwrap();
    let bad = text.replacen("-40*(q-0.5)", "-40*(q-0.5", 1);
    let e = parse_err(&bad);
    assert!(e.contains("knee_spring") && e.contains("unbalanced"), "{e}");
    let bad = text.replacen("0.1*exp(-q/0.2)", "0.1*floor(q)", 1);
    assert!(parse_err(&bad).contains("unknown function `floor`"));
    let bad = text.replacen("2.5*qdot", "2.5*speed", 1);
    assert!(parse_err(&bad).contains("unknown variable `speed`"));
    let bad = text.replacen("<dimension>1</dimension>", "<dimension>2</dimension>", 1);
    let e = parse_err(&bad);
    assert!(
        e.contains("monoarticular") && e.contains("coordinate"),
        "{e}"
    );
}
