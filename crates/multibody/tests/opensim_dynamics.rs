//! The six reference models through the importer, checked against OpenSim 4.6
//! (`tests/data/opensim/*.json`, written by `tools/opensim_reference/dynamics_reference.py`):
//! body masses, centres of mass and inertias (exact), inverse dynamics with gravity only at
//! 50 random states, inverse dynamics with the smooth sphere contacts and each sphere's
//! force and torque at 50 states near the ground (1e-6 relative, 1e-6 absolute near zero).
//! Skipped when `../shared/reference` is absent.

mod common;

use serde_json::Value;
use stride_model::osim::load_osim;
use stride_model::{Model, PathPointKind};
use stride_multibody::*;

fn reference(file: &str) -> Option<(Model, Value)> {
    let root = common::shared()?;
    let model = load_osim(&root.join("reference/models").join(file)).unwrap();
    let stem = std::path::Path::new(file).file_stem().unwrap();
    let data = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/opensim")
        .join(stem)
        .with_extension("json");
    let json = serde_json::from_str(&std::fs::read_to_string(data).unwrap()).unwrap();
    Some((model, json))
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// Largest error relative to max(|reference|, 1) (so 1e-6 means 1e-6 relative, or 1e-6
/// absolute below 1).
fn worst(got: &[f64], want: &[f64]) -> f64 {
    got.iter()
        .zip(want)
        .map(|(g, w)| (g - w).abs() / w.abs().max(1.0))
        .fold(0.0, f64::max)
}

/// A state of the file (OpenSim coordinate order) in stride's coordinate order.
struct State {
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
}

fn state(model: &Model, names: &[String], row: &Value) -> State {
    let n = model.coordinates.len();
    let mut s = State {
        q: vec![0.0; n],
        v: vec![0.0; n],
        a: vec![0.0; n],
    };
    for (k, (q, (v, a))) in floats(&row["q"])
        .into_iter()
        .zip(floats(&row["qdot"]).into_iter().zip(floats(&row["qddot"])))
        .enumerate()
    {
        let i = model.coordinate_index(&names[k]).unwrap();
        (s.q[i], s.v[i], s.a[i]) = (q, v, a);
    }
    s
}

fn in_file_order(model: &Model, names: &[String], tau: &[f64]) -> Vec<f64> {
    names
        .iter()
        .map(|n| tau[model.coordinate_index(n).unwrap()])
        .collect()
}

fn names(v: &Value) -> Vec<String> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_str().unwrap().to_string())
        .collect()
}

fn check_bodies(model: &Model, json: &Value) {
    let bodies = json["bodies"].as_array().unwrap();
    assert_eq!(bodies.len() + 1, model.bodies.len(), "body count");
    for b in bodies {
        let name = b["name"].as_str().unwrap();
        let mb = &model.bodies[model.body_index(name).unwrap()];
        assert_eq!(mb.mass, b["mass"].as_f64().unwrap(), "{name} mass");
        assert_eq!(mb.com.to_vec(), floats(&b["com"]), "{name} com");
        assert_eq!(mb.inertia.to_vec(), floats(&b["inertia"]), "{name} inertia");
    }
    assert_eq!(model.gravity.to_vec(), floats(&json["gravity"]), "gravity");
}

/// Gravity-only inverse dynamics; returns the worst relative error.
fn check_inverse_dynamics(model: &Model, json: &Value) -> f64 {
    let coords = names(&json["coordinates"]);
    assert_eq!(coords.len(), model.coordinates.len());
    let mut data = Data::<f64>::new(model).unwrap();
    let mut tau = vec![0.0; model.coordinates.len()];
    let mut err: f64 = 0.0;
    let rows = json["inverse_dynamics"].as_array().unwrap();
    assert!(rows.len() >= 50);
    for row in rows {
        let s = state(model, &coords, row);
        data.clear_external();
        inverse_dynamics(model, &mut data, &s.q, &s.v, &s.a, &mut tau).unwrap();
        err = err.max(worst(
            &in_file_order(model, &coords, &tau),
            &floats(&row["tau"]),
        ));
    }
    err
}

/// Inverse dynamics with contacts and per-sphere force and torque about the body origin;
/// returns the worst relative errors (torques, sphere loads).
fn check_contacts(model: &Model, json: &Value) -> (f64, f64) {
    let coords = names(&json["coordinates"]);
    let forces = names(&json["contact"]["forces"]);
    let mut data = Data::<f64>::new(model).unwrap();
    let mut out = SkeletonOutput::new(model, &data);
    let (mut e_tau, mut e_sphere): (f64, f64) = (0.0, 0.0);
    for row in json["contact"]["states"].as_array().unwrap() {
        let s = state(model, &coords, row);
        skeleton_dynamics(model, &mut data, &s.q, &s.v, &s.a, &mut out).unwrap();
        e_tau = e_tau.max(worst(
            &in_file_order(model, &coords, &out.tau),
            &floats(&row["tau"]),
        ));
        for (k, want) in row["spheres"].as_array().unwrap().iter().enumerate() {
            let i = model
                .contacts
                .iter()
                .position(|c| c.name == forces[k])
                .unwrap();
            let sf = &out.spheres[i];
            let origin = data.position[model.contacts[i].body];
            let r = [
                sf.point[0] - origin[0],
                sf.point[1] - origin[1],
                sf.point[2] - origin[2],
            ];
            let f = sf.force;
            let torque = [
                r[1] * f[2] - r[2] * f[1],
                r[2] * f[0] - r[0] * f[2],
                r[0] * f[1] - r[1] * f[0],
            ];
            let got = [f[0], f[1], f[2], torque[0], torque[1], torque[2]];
            e_sphere = e_sphere.max(worst(&got, &floats(want)));
        }
    }
    (e_tau, e_sphere)
}

/// Ligament tension at OpenSim's length, and the straight-line length of the ligaments
/// without wrapping (the wrapped ones are checked in stride-geometry's
/// `opensim_ligaments` test); returns the worst relative errors (tension, length).
fn check_ligaments(model: &Model, json: &Value) -> (f64, f64) {
    let coords = names(&json["coordinates"]);
    let ligs = names(&json["ligaments"]["names"]);
    let mut data = Data::<f64>::new(model).unwrap();
    let (mut e_t, mut e_l): (f64, f64) = (0.0, 0.0);
    let mut compared_lengths = 0;
    for row in json["ligaments"]["states"].as_array().unwrap() {
        let mut q = vec![0.0; model.coordinates.len()];
        for (k, v) in floats(&row["q"]).into_iter().enumerate() {
            q[model.coordinate_index(&coords[k]).unwrap()] = v;
        }
        forward_kinematics(model, &mut data, &q, &vec![0.0; q.len()]).unwrap();
        let lengths = floats(&row["length"]);
        let tensions = floats(&row["tension"]);
        for (k, name) in ligs.iter().enumerate() {
            let l = model.ligaments.iter().find(|l| &l.name == name).unwrap();
            let curve = l.force_length.compile().unwrap();
            let t = elements::ligament_tension(l, &curve, lengths[k]);
            e_t = e_t.max(worst(&[t], &[tensions[k]]));
            if !l.wraps.is_empty() {
                continue;
            }
            assert!(l
                .path
                .iter()
                .all(|p| matches!(p.kind, PathPointKind::Fixed)));
            let pts: Vec<[f64; 3]> = l
                .path
                .iter()
                .map(|p| point_position(&data, p.body, p.location))
                .collect();
            let len: f64 = pts
                .windows(2)
                .map(|w| {
                    let d = [w[1][0] - w[0][0], w[1][1] - w[0][1], w[1][2] - w[0][2]];
                    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
                })
                .sum();
            // Lengths are far below 1 m: compare relative to the length itself.
            e_l = e_l.max((len - lengths[k]).abs() / lengths[k]);
            compared_lengths += 1;
        }
    }
    assert!(compared_lengths > 0);
    (e_t, e_l)
}

fn check_model(file: &str) {
    let Some((model, json)) = reference(file) else {
        return;
    };
    check_bodies(&model, &json);
    let e = check_inverse_dynamics(&model, &json);
    println!("{file}: inverse dynamics worst relative error {e:.2e}");
    assert!(e <= 1e-6, "{file}: inverse dynamics error {e:.3e}");
    if json.get("contact").is_some() {
        let (et, es) = check_contacts(&model, &json);
        println!("{file}: with contacts {et:.2e}, sphere loads {es:.2e}");
        assert!(
            et <= 1e-6,
            "{file}: inverse dynamics with contact error {et:.3e}"
        );
        assert!(es <= 1e-6, "{file}: sphere load error {es:.3e}");
    }
    if json.get("ligaments").is_some() {
        let (et, el) = check_ligaments(&model, &json);
        println!("{file}: ligament tension {et:.2e}, straight-path length {el:.2e}");
        assert!(et <= 1e-6, "{file}: ligament tension error {et:.3e}");
        assert!(el <= 1e-6, "{file}: ligament length error {el:.3e}");
    }
}

#[test]
fn subject1_v2_matches_opensim() {
    check_model("subject1_v2.osim");
}

#[test]
fn subject1_matches_opensim() {
    check_model("subject1.osim");
}

#[test]
fn hamner_matches_opensim() {
    check_model("Hamner_modified_scaled.osim");
}

#[test]
fn falisse_2022_matches_opensim() {
    check_model("predsim/Falisse_et_al_2022.osim");
}

#[test]
fn gait1018_matches_opensim() {
    check_model("predsim/gait1018.osim");
}

#[test]
fn dhondt_2024_matches_opensim() {
    check_model("predsim/DHondt_et_al_2024_4seg.osim");
}
