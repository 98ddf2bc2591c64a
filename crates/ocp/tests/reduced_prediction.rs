//! CI's reduced prediction: the paper's problem on a coarse mesh (10 intervals per half
//! cycle) from the data-informed walking guess, solved to tolerance 1e-4 by the pure-Rust
//! interior point, then written to a result folder.
//!
//! References: IPOPT 3.11.9 with MUMPS solves this same NLP to an objective of 301.52
//! (docs/decisions/0002-solver.md), an independent solver on the identical problem; the gait
//! checks are physical (one body weight on average, a walking cycle with stance and swing).

use std::time::Duration;
use stride_model::storage::Storage;
use stride_ocp::{
    guess::GuessKind,
    predict::{select, solve_guesses, write_results},
    settings::ProblemSettings,
};
use stride_solve::ipm::InteriorPoint;
use stride_solve::solver::{MuStrategy, SolveStatus, SolverOptions};

/// Objective IPOPT reaches on this problem (10 intervals, data-informed guess, tol 1e-4).
const IPOPT_OBJECTIVE: f64 = 301.523;

#[test]
fn coarse_mesh_prediction_converges_and_writes_results() {
    let model = stride_model::default_model::default_model();
    let settings = ProblemSettings {
        mesh_intervals: 10,
        ..Default::default()
    };
    let options = SolverOptions {
        tol: 1e-4,
        mu_strategy: MuStrategy::Adaptive,
        max_iter: 600,
        time_limit: Some(Duration::from_secs(1500)),
        threads: 2,
        ..Default::default()
    };
    let (problem, solved) = solve_guesses(
        &model,
        &settings,
        &[GuessKind::DataInformedWalking],
        &InteriorPoint::new(),
        &options,
        &|_, _| {},
    )
    .expect("solve");
    let r = &solved[0].result;
    eprintln!(
        "reduced prediction: {:?} after {} iterations, f = {}, violation {:e}, {:.1} s",
        r.status,
        r.iterations,
        r.objective,
        r.constraint_violation,
        r.time_total.as_secs_f64()
    );
    assert_eq!(r.status, SolveStatus::Optimal);
    assert!(r.constraint_violation < 1e-4, "{}", r.constraint_violation);
    let rel = (r.objective - IPOPT_OBJECTIVE).abs() / IPOPT_OBJECTIVE;
    assert!(
        rel < 1e-3,
        "objective {} vs IPOPT {IPOPT_OBJECTIVE}",
        r.objective
    );

    let kept = select(&solved);
    assert_eq!(kept, Some(0));
    let dir = std::env::temp_dir().join(format!("stride-reduced-{}", std::process::id()));
    let out = dir.join("run");
    let summary = write_results(&problem, &solved, kept, "ipm", &options, &out).expect("write");
    let o = summary.outcomes.expect("outcomes of the kept solution");
    eprintln!("outcomes: {o:?}");
    assert!((o.speed - 1.33).abs() < 1e-3, "speed {}", o.speed);
    assert!(o.cost_of_transport > 0.0 && o.cost_of_transport.is_finite());
    assert!(o.stride_length > 0.5 && o.stride_length < 2.5);
    // a walking cycle: each foot has stance and swing, one stance phase per cycle
    assert!(o.stance_fraction_right > 0.3 && o.stance_fraction_right < 0.9);
    assert_eq!(o.stance_phases_right, 1);

    let motion = Storage::read(&out.join("motion.mot")).expect("motion.mot");
    assert_eq!(motion.rows.len(), 20, "full cycle = 2N samples");
    for c in &model.coordinates {
        assert!(motion.column_index(&c.name).is_some(), "column {}", c.name);
    }
    let grf = Storage::read(&out.join("grf.mot")).expect("grf.mot");
    // vertical ground reaction force averages one body weight over a cycle
    let vy_r = grf.column_index("r_ground_force_vy").unwrap();
    let vy_l = grf.column_index("l_ground_force_vy").unwrap();
    let mean: f64 = grf.rows.iter().map(|r| r[vy_r] + r[vy_l]).sum::<f64>() / grf.rows.len() as f64;
    let weight = model.total_mass() * 9.81;
    assert!(
        (mean / weight - 1.0).abs() < 0.15,
        "mean vertical GRF {mean} N vs body weight {weight} N"
    );
    for f in [
        "summary.json",
        "joint_angles.csv",
        "joint_torques.csv",
        "grf.csv",
        "activations.csv",
        "solver_log_data-informed-walking.csv",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
