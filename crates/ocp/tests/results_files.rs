//! Result files of a prediction: written atomically, readable as OpenSim storage files whose
//! column labels are the model's coordinate names. The "solution" here is the data-informed
//! guess (a physically meaningful walking cycle), so the files can be checked without a solve.

use std::time::Duration;
use stride_model::storage::Storage;
use stride_ocp::{
    data, experimental::Kinematics, guess::GuessKind, predict, problem::GaitProblem,
    settings::ProblemSettings,
};
use stride_solve::solver::{SolveResult, SolveStatus, SolverOptions};

#[test]
fn results_are_valid_storage_files() {
    let model = stride_model::default_model::default_model();
    let settings = ProblemSettings {
        mesh_intervals: 10,
        ..Default::default()
    };
    let walking = data::walking_half_cycle();
    let problem = GaitProblem::new(&model, &settings, &walking).unwrap();
    let kin = Kinematics::from_storage(&walking, &problem.gait, "walking").unwrap();
    let x = problem
        .initial_guess(GuessKind::DataInformedWalking, Some(&kin))
        .unwrap();
    let result = SolveResult {
        status: SolveStatus::Optimal,
        iterations: 0,
        objective: 0.0,
        constraint_violation: 0.0,
        dual_infeasibility: 0.0,
        x,
        lambda: Vec::new(),
        z_l: Vec::new(),
        z_u: Vec::new(),
        time_total: Duration::ZERO,
        time_evaluations: Duration::ZERO,
        time_linear_solver: Duration::ZERO,
        time_symbolic: Duration::ZERO,
        time_factorisation: Duration::ZERO,
        solves: 0,
        time_solves: Duration::ZERO,
        factorizations: 0,
        objective_evaluations: 0,
        exact_hessian_from: None,
        log: Vec::new(),
    };
    let solved = vec![predict::Solved {
        report: predict::GuessReport::new(GuessKind::DataInformedWalking, &result),
        result,
    }];
    let dir = std::env::temp_dir().join(format!("stride-results-{}", std::process::id()));
    let out = dir.join("run");
    let summary = predict::write_results(
        &problem,
        &solved,
        Some(0),
        "test",
        &SolverOptions::default(),
        &out,
    )
    .unwrap();
    let motion = Storage::read(&out.join("motion.mot")).unwrap();
    assert_eq!(motion.in_degrees, Some(true));
    assert_eq!(motion.rows.len(), 20, "full cycle = 2N samples");
    for c in &model.coordinates {
        assert!(motion.column_index(&c.name).is_some(), "column {}", c.name);
    }
    assert!(motion.column_index("soleus_r/activation").is_some());
    let grf = Storage::read(&out.join("grf.mot")).unwrap();
    assert!(grf.column_index("r_ground_force_vy").is_some());
    // The experimental walking cycle starts at a heel strike and has about one body weight
    // of vertical force on average over a cycle.
    let o = summary.outcomes.unwrap();
    assert!(o.stride_length > 0.8 && o.stride_length < 2.0, "{o:?}");
    // Condition measures of the experimental kinematics: trunk sway near the subject's
    // 3.0° (range of the mean series of walking_trunk_sway.csv). The guess is not
    // dynamically consistent (the feet sink into the ground for most of the cycle), so only
    // the presence of the stance measures is checked here.
    let m = &o.conditions;
    let sway = m.trunk_sway.unwrap();
    assert!(sway > 2.0 && sway < 5.0, "trunk sway {sway}");
    for leg in [&m.right, &m.left] {
        assert!(
            leg.peak_knee_flexion.is_some()
                && leg.early_stance_ankle_plantarflexion_torque.is_some()
        );
    }
    for f in [
        "summary.json",
        "joint_angles.csv",
        "activations.csv",
        "excitations.csv",
        "grf.csv",
        "trunk_sway.csv",
    ] {
        assert!(out.join(f).exists(), "{f}");
    }
    // The solver options are recorded with the results.
    let json = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(
        json.contains("\"solver_options\"") && json.contains("\"exact_hessian_tail\""),
        "summary.json without the solver options"
    );
    // No temporary folder left behind.
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains("partial"))
        .collect();
    assert!(leftovers.is_empty());
    std::fs::remove_dir_all(&dir).unwrap();
}
