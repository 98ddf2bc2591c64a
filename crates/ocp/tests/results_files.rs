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
        json.contains("\"solver_options\"") && json.contains("\"linear_solver\""),
        "summary.json without the solver options"
    );
    // No temporary folder left behind.
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains("partial"))
        .collect();
    assert!(leftovers.is_empty());

    // Rewriting the folder from the same solution gives back the cycle files as written
    // (here: a table edited by hand, the outcomes removed from summary.json), keeps the
    // other files (the solver log, a user's note and subfolder) and lets the caller add files.
    let angles = std::fs::read_to_string(out.join("joint_angles.csv")).unwrap();
    let log = std::fs::read_to_string(out.join("solver_log_data-informed-walking.csv")).unwrap();
    std::fs::write(out.join("joint_angles.csv"), "stale").unwrap();
    std::fs::write(out.join("note.txt"), "kept").unwrap();
    std::fs::create_dir(out.join("notes")).unwrap();
    std::fs::write(out.join("notes").join("a.txt"), "kept too").unwrap();
    let mut summary_json: serde_json::Value = serde_json::from_str(&json).unwrap();
    summary_json["outcomes"] = serde_json::Value::Null;
    std::fs::write(out.join("summary.json"), summary_json.to_string()).unwrap();
    let x = &solved[0].result.x;
    let rewritten = predict::rewrite_results(&problem, x, &out, |cycle, tmp| {
        std::fs::write(tmp.join("extra.txt"), format!("{}", cycle.time.len())).unwrap();
        Ok(())
    })
    .unwrap();
    assert_eq!(rewritten.stride_length, o.stride_length);
    assert_eq!(
        std::fs::read_to_string(out.join("joint_angles.csv")).unwrap(),
        angles
    );
    assert_eq!(
        std::fs::read_to_string(out.join("solver_log_data-informed-walking.csv")).unwrap(),
        log
    );
    assert_eq!(
        std::fs::read_to_string(out.join("note.txt")).unwrap(),
        "kept"
    );
    assert_eq!(
        std::fs::read_to_string(out.join("notes").join("a.txt")).unwrap(),
        "kept too"
    );
    assert_eq!(
        std::fs::read_to_string(out.join("extra.txt")).unwrap(),
        "20"
    );
    let after: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(
        after["outcomes"]["stride_length"].as_f64(),
        Some(o.stride_length)
    );
    assert_eq!(after["guesses"][0]["guess"], "data-informed-walking");
    // A failure while rewriting leaves the folder as it was, with no temporary folder.
    std::fs::write(out.join("joint_angles.csv"), "stale").unwrap();
    let e = predict::rewrite_results(&problem, x, &out, |_, tmp| {
        Err(predict::PredictError::Write {
            path: tmp.display().to_string(),
            reason: "test".into(),
        })
    })
    .unwrap_err();
    assert!(e.to_string().contains("test"), "{e}");
    assert_eq!(
        std::fs::read_to_string(out.join("joint_angles.csv")).unwrap(),
        "stale"
    );
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, ["run"], "only the result folder remains");
    // A folder without summary.json is an error that names the file.
    std::fs::remove_file(out.join("summary.json")).unwrap();
    let e = predict::rewrite_results(&problem, x, &out, |_, _| Ok(())).unwrap_err();
    assert!(e.to_string().starts_with("reading ") && e.to_string().contains("summary.json"));
    std::fs::remove_dir_all(&dir).unwrap();
}
