//! Fitting a model with a coupled coordinate (the kneecap model of
//! `tools/opensim_reference/paths_coupled_small.py`, `q_cap = f(q_knee)`): random poses
//! never sample the coupled coordinate, they take the constraint's value (checked against
//! OpenSim's at its 200 reference poses), and the polynomials span the independent
//! coordinates only and meet the 3 mm tolerance with the chain rule in their moment arms.

use std::path::Path;
use stride_geometry::{fit_model, random_poses, FitModelOptions, PathGeometry};

fn model() -> stride_model::Model {
    let p = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/coupled_model.osim");
    stride_model::osim::load_osim(Path::new(p)).unwrap()
}

/// OpenSim's (q_knee, q_cap) pairs of the reference poses.
fn opensim_cap() -> Vec<(f64, f64)> {
    let p = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/opensim_paths/coupled_model_poses.csv"
    );
    let text = std::fs::read_to_string(p).unwrap();
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            (v[1], v[2])
        })
        .collect()
}

#[test]
fn coupled_coordinate_follows_the_constraint_in_random_poses() {
    let m = model();
    let (knee, cap) = (
        m.coordinate_index("q_knee").unwrap(),
        m.coordinate_index("q_cap").unwrap(),
    );
    let poses = random_poses(&m, 200, 5);
    // Every coupled value lies inside the image of the spline over the knee's range.
    for s in 0..poses.len() {
        let q = poses.pose(s);
        assert!((-0.95..=0.15).contains(&q[cap]), "pose {s}: {q:?}");
    }
    // At OpenSim's knee angles, the coupled value is OpenSim's.
    let mut q = poses.pose(0).to_vec();
    let geo = PathGeometry::new(&m).unwrap();
    let mut worst = 0.0f64;
    for (k, c) in opensim_cap() {
        q[knee] = k;
        q[cap] = f64::NAN;
        geo.couplers.apply(&mut q);
        worst = worst.max((q[cap] - c).abs());
    }
    assert!(worst < 1e-8, "coupled value off OpenSim's by {worst} rad");
}

#[test]
fn fit_spans_independent_coordinates_only() {
    let m = model();
    let poses = random_poses(&m, 400, 7);
    let report = fit_model(&m, &poses, &FitModelOptions::default()).unwrap();
    for row in &report.rows {
        println!(
            "{}: {:?}, order {}, length RMSE {:.4} mm, moment-arm RMSE {:.4} mm",
            row.muscle, row.spanned, row.order, row.rms_length_mm, row.max_rms_moment_arm_mm
        );
        assert!(!row.spanned.iter().any(|c| c == "q_cap"), "{row:?}");
        assert!(row.spanned.iter().any(|c| c == "q_knee"), "{row:?}");
        assert!(row.meets_tolerance, "{row:?}");
    }
    let over = report.rows.iter().find(|r| r.muscle == "over_cap").unwrap();
    assert_eq!(over.spanned, ["q_hip", "q_knee"]);
}
