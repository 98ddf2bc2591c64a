//! Ligament path lengths of `DHondt_et_al_2024_4seg.osim` (26 ligaments; the plantar
//! fasciae wrap over the metatarsal-head cylinders) against OpenSim 4.6 at 50 random
//! states (`tools/opensim_reference/dynamics_reference.py`, data kept in the multibody
//! crate): every length within 0.5 mm RMS and 2 mm at most, as the muscles'. Skipped (with
//! the reason printed) when `../shared` is absent.

use serde_json::Value;
use std::path::PathBuf;
use stride_geometry::kinematics::{BodyPoses, Kinematics};
use stride_geometry::MusclePaths;

#[test]
fn dhondt2024_ligament_lengths_match_opensim() {
    let model_path = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/reference/models/predsim/DHondt_et_al_2024_4seg.osim"
    ));
    if !model_path.exists() {
        eprintln!("skipping: {} not found", model_path.display());
        return;
    }
    let model = stride_model::osim::load_osim(&model_path).unwrap();
    let data = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../multibody/tests/data/opensim/DHondt_et_al_2024_4seg.json"
    );
    let json: Value = serde_json::from_str(&std::fs::read_to_string(data).unwrap()).unwrap();
    let strings = |v: &Value| -> Vec<String> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|s| s.as_str().unwrap().to_string())
            .collect()
    };
    let floats = |v: &Value| -> Vec<f64> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    let coords = strings(&json["coordinates"]);
    let names = strings(&json["ligaments"]["names"]);
    let kin = Kinematics::new(&model).unwrap();
    let paths = MusclePaths::ligaments(&model).unwrap();
    // The same paths without their wraps: the wrapping must matter at these states.
    let mut unwrapped = model.clone();
    unwrapped.ligaments.iter_mut().for_each(|l| l.wraps.clear());
    let straight = MusclePaths::ligaments(&unwrapped).unwrap();
    let mut wrap_effect = 0.0f64;
    let mut poses = BodyPoses::new(kin.n_bodies());
    let mut err = vec![Vec::new(); names.len()];
    for row in json["ligaments"]["states"].as_array().unwrap() {
        let mut q: Vec<f64> = model.coordinates.iter().map(|c| c.default_value).collect();
        for (k, v) in floats(&row["q"]).into_iter().enumerate() {
            q[model.coordinate_index(&coords[k]).unwrap()] = v;
        }
        kin.forward(&q, &mut poses);
        for (k, want) in floats(&row["length"]).into_iter().enumerate() {
            let i = model
                .ligaments
                .iter()
                .position(|l| l.name == names[k])
                .unwrap();
            let l = paths.length(i, &q, &poses);
            err[k].push((l - want) * 1e3);
            wrap_effect = wrap_effect.max((l - straight.length(i, &q, &poses)) * 1e3);
        }
    }
    println!("largest lengthening by wrapping: {wrap_effect:.3} mm");
    assert!(wrap_effect > 1.0, "no state wraps: {wrap_effect} mm");
    let mut failures = Vec::new();
    for (name, e) in names.iter().zip(&err) {
        let rms = (e.iter().map(|x| x * x).sum::<f64>() / e.len() as f64).sqrt();
        let max = e.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        println!("{name}: RMSE {rms:.4} mm, max {max:.4} mm");
        if rms > 0.5 || max > 2.0 {
            failures.push(format!("{name}: RMSE {rms:.3} mm, max {max:.3} mm"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
