//! Tracking problems (FORMULATION 12.6): the transcribed NLP's derivatives against finite
//! differences, the tracking errors against hand-computed values, and the errors a bad
//! trial or setting gives (naming the file and the column or window).

use std::path::PathBuf;
use stride_ocp::tracking::{TrackError, TrackSettings, TrackingProblem};
use stride_predict::track_output::Channel;
use stride_solve::nlp::{check_derivatives, DerivativeCheckOptions, Nlp};

fn small(settings: TrackSettings) -> Result<TrackingProblem, TrackError> {
    let model = stride_model::default_model::default_model();
    TrackingProblem::new(&model, &settings)
}

#[test]
fn tracking_derivatives_match_finite_differences() {
    let mut tp = small(TrackSettings {
        mesh_intervals: 3,
        window: [3.45, 3.6],
        ..Default::default()
    })
    .unwrap();
    for (i, xi) in tp.x0.iter_mut().enumerate() {
        *xi += 1e-3 * ((i as f64 * 0.7548776662).fract() - 0.5);
    }
    let tr = tp.transcription().unwrap();
    let x = tp.x0.clone();
    // the data-informed guess has large contact and torque errors (objective ~1e5): with a
    // step of 1e-5 the rounding of the objective (~2e-16 · 1e5 / 1e-5 = 2e-6) sets the
    // tolerance of the gradient (a larger step's truncation fails the contact Jacobian)
    let step = 1e-5;
    let first = check_derivatives(
        &tr,
        &x,
        &DerivativeCheckOptions {
            max_columns: 400,
            tol: 3e-6,
            step,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(
        first.mismatches.is_empty(),
        "{:?}",
        &first.mismatches[..first.mismatches.len().min(5)]
    );
    let lambda: Vec<f64> = (0..tr.m())
        .map(|i| ((i as f64 * 0.5698402910).fract() - 0.5) * 2.0)
        .collect();
    // tolerance as for the prediction's transcription (friction smoothing makes third
    // derivatives large, hence the finite-difference truncation error)
    let report = check_derivatives(
        &tr,
        &x,
        &DerivativeCheckOptions {
            max_columns: 400,
            lambda: Some(lambda),
            obj_factor: 0.7,
            tol: 1e-4,
            step,
        },
    )
    .unwrap();
    assert!(
        report.mismatches.is_empty(),
        "{:?}",
        &report.mismatches[..report.mismatches.len().min(5)]
    );
}

#[test]
fn tracking_problem_has_no_boundary_rows_and_a_fixed_duration() {
    let tp = small(TrackSettings {
        mesh_intervals: 3,
        ..Default::default()
    })
    .unwrap();
    let tr = tp.transcription().unwrap();
    let l = &tp.problem.layout;
    // collocation and path constraints of 9 points, continuity of 3 intervals, nothing else
    let ns = l.n_states();
    let n_path = tp.node().unwrap().n_outputs() - 1;
    assert_eq!(tr.m(), 9 * (ns + n_path) + 3 * ns);
    let (mut xl, mut xu) = (vec![0.0; tr.n()], vec![0.0; tr.n()]);
    let (mut gl, mut gu) = (vec![0.0; tr.m()], vec![0.0; tr.m()]);
    tr.bounds(&mut xl, &mut xu, &mut gl, &mut gu);
    let d = 4.25 - 3.45;
    assert_eq!((xl[l.tf()], xu[l.tf()]), (d, d));
}

#[test]
fn tracking_errors_match_hand_computed_values() {
    let c = Channel {
        name: "a".into(),
        unit: "deg",
        model: vec![1.0, 2.0, 4.0],
        measured: vec![1.0, 3.0, 5.0],
    };
    let e = c.error();
    // residuals 0, −1, −1: RMSE √(2/3); measured mean 3, SS_tot 8, R² = 1 − 2/8
    assert!((e.rmse - (2.0f64 / 3.0).sqrt()).abs() < 1e-15);
    assert!((e.r2 - 0.75).abs() < 1e-15);
}

#[test]
fn a_tracked_column_that_names_no_coordinate_is_an_error() {
    let e = small(TrackSettings {
        mesh_intervals: 3,
        coordinates: Some(vec!["knee_angle_r".into(), "knee_flexion".into()]),
        ..Default::default()
    })
    .err()
    .unwrap()
    .to_string();
    assert!(
        e.contains("gait_1_ik.mot") && e.contains("`knee_flexion`"),
        "{e}"
    );
}

#[test]
fn a_window_outside_the_data_is_an_error() {
    let e = small(TrackSettings {
        mesh_intervals: 3,
        window: [4.0, 5.0],
        ..Default::default()
    })
    .err()
    .unwrap()
    .to_string();
    assert!(
        e.contains("gait_1_ik.mot") && e.contains("window [4, 5]"),
        "{e}"
    );
}

#[test]
fn a_grf_file_without_the_expected_columns_is_an_error() {
    let dir = std::env::temp_dir().join(format!("stride_track_grf_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let src = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../ocp/data");
    let grf = std::fs::read_to_string(src.join("gait_1_grf.mot")).unwrap();
    let bad = dir.join("grf.mot");
    std::fs::write(&bad, grf.replace("1_ground_force_vy", "1_ground_force_fy")).unwrap();
    let e = small(TrackSettings {
        mesh_intervals: 3,
        motion: Some(src.join("gait_1_ik.mot")),
        grf: Some(bad.clone()),
        ..Default::default()
    })
    .err()
    .unwrap()
    .to_string();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(
        e.contains("grf.mot") && e.contains("`1_ground_force_vy`"),
        "{e}"
    );
}
