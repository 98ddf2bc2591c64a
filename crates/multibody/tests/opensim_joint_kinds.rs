//! A model with every joint kind (Free, Ball, Gimbal, Universal, Planar, Slider, Pin,
//! Custom with a non-orthogonal rotation axis and NaturalCubicSpline (which OpenSim 4 reads
//! as a SimmSpline), PiecewiseLinearFunction, PolynomialFunction,
//! MultiplierFunction(SimmSpline), LinearFunction and Constant axes, Weld), a
//! CoordinateCouplerConstraint, a CoordinateLimitForce and a SpringGeneralizedForce, built
//! and evaluated by OpenSim (`tools/opensim_reference/skeleton_joints.py`): bodies exact,
//! inverse dynamics with the coupled coordinate eliminated and the coordinate forces within
//! 1e-6 relative (1e-6 absolute below 1). Ball and Free speeds are angle rates in stride;
//! the reference converts OpenSim's angular-velocity speeds and forces to them.

use serde_json::Value;
use std::path::PathBuf;
use stride_model::osim::load_osim;
use stride_model::{Model, MotionType};
use stride_multibody::*;

fn data_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/opensim")
}

fn load() -> (Model, Value) {
    let model = load_osim(&data_dir().join("joint_kinds.osim")).unwrap();
    let text = std::fs::read_to_string(data_dir().join("joint_kinds.json")).unwrap();
    (model, serde_json::from_str(&text).unwrap())
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn names(v: &Value) -> Vec<String> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_str().unwrap().to_string())
        .collect()
}

/// Values of the file (OpenSim state order) in stride's coordinate order.
fn reorder(model: &Model, names: &[String], v: &[f64]) -> Vec<f64> {
    let mut out = vec![0.0; v.len()];
    for (k, x) in v.iter().enumerate() {
        out[model.coordinate_index(&names[k]).unwrap()] = *x;
    }
    out
}

fn rel(got: f64, want: f64) -> f64 {
    (got - want).abs() / want.abs().max(1.0)
}

#[test]
fn importer_reads_every_joint_kind() {
    let (model, json) = load();
    assert_eq!(model.coordinates.len(), names(&json["coordinates"]).len());
    assert_eq!(model.joints.len(), 9);
    let planar: Vec<MotionType> = (0..3)
        .map(|k| {
            let c = model.coordinate_index(&format!("planar_{k}")).unwrap();
            model.coordinates[c].motion_type
        })
        .collect();
    assert_eq!(
        planar,
        [
            MotionType::Rotational,
            MotionType::Translational,
            MotionType::Translational
        ]
    );
    let c3 = model.coordinate_index("c3").unwrap();
    assert_eq!(model.coordinates[c3].motion_type, MotionType::Coupled);
    assert_eq!(model.couplers.len(), 1);
    assert_eq!(model.coordinate_forces.len(), 2);
    for b in json["bodies"].as_array().unwrap() {
        let name = b["name"].as_str().unwrap();
        let mb = &model.bodies[model.body_index(name).unwrap()];
        assert_eq!(mb.mass, b["mass"].as_f64().unwrap(), "{name}");
        assert_eq!(mb.com.to_vec(), floats(&b["com"]), "{name}");
        assert_eq!(mb.inertia.to_vec(), floats(&b["inertia"]), "{name}");
    }
}

#[test]
fn inverse_dynamics_with_coupler_matches_opensim() {
    let (model, json) = load();
    let coords = names(&json["coordinates"]);
    let mut data = Data::<f64>::new(&model).unwrap();
    let mut tau = vec![0.0; model.coordinates.len()];
    let mut worst: f64 = 0.0;
    let rows = json["inverse_dynamics"].as_array().unwrap();
    assert!(rows.len() >= 50);
    for row in rows {
        let q = reorder(&model, &coords, &floats(&row["q"]));
        let v = reorder(&model, &coords, &floats(&row["qdot"]));
        let a = reorder(&model, &coords, &floats(&row["qddot"]));
        inverse_dynamics(&model, &mut data, &q, &v, &a, &mut tau).unwrap();
        let want = reorder(&model, &coords, &floats(&row["tau"]));
        for (g, w) in tau.iter().zip(&want) {
            worst = worst.max(rel(*g, *w));
        }
    }
    println!("joint kinds: inverse dynamics worst relative error {worst:.2e}");
    assert!(worst <= 1e-6, "{worst:.3e}");
}

#[test]
fn coordinate_forces_match_opensim() {
    let (model, json) = load();
    let coords = names(&json["coordinates"]);
    let laws = names(&json["force_laws"]["names"]);
    let mut worst: f64 = 0.0;
    let mut active = 0;
    for row in json["force_laws"]["states"].as_array().unwrap() {
        let q = reorder(&model, &coords, &floats(&row["q"]));
        let v = reorder(&model, &coords, &floats(&row["qdot"]));
        for (k, want) in floats(&row["force"]).into_iter().enumerate() {
            let f = model
                .coordinate_forces
                .iter()
                .find(|f| f.name == laws[k])
                .unwrap();
            let got = elements::coordinate_force(&f.law, q[f.coordinate], v[f.coordinate]);
            worst = worst.max(rel(got, want));
            if want.abs() > 1.0 {
                active += 1;
            }
        }
    }
    println!("joint kinds: coordinate forces worst relative error {worst:.2e}");
    assert!(active > 20, "too few states engage the forces ({active})");
    assert!(worst <= 1e-6, "{worst:.3e}");
}
