//! One real, tiny study (mesh 8, the fewest samples the filter of the partial guess takes; 4 iterations): a quasi-random case at 1.33 m/s and the
//! full- and partial-solution continuation cases at 1.43 m/s that start from its last
//! iterate. The solves end "not converged"; the test checks the plumbing: result files,
//! `solution.json`, continuation sources, index and report.

use std::path::Path;
use std::time::Duration;
use stride_solve::solver::{MuStrategy, SolverOptions};
use stride_study::predict_runner::{
    check_cases, measures_from_solution, rewrite_case, PredictRunner, Rewritten, SOLUTION_FILE,
};
use stride_study::runner::{run_study, RunOptions};
use stride_study::spec;
use stride_study::store::Store;

#[test]
fn tiny_real_study_runs_continuation_cases_from_written_solutions() {
    let out = std::env::temp_dir().join(format!("stride-study-e2e-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let text = r#"
[study]
name = "tiny"
output = "unused"
jobs = 2
continue_from_unconverged = true
[base]
mesh_intervals = 8
[grid]
speed = [1.33, 1.43]
guesses = ["quasi-random", "full-os", "partial-os"]
"#;
    let study = spec::parse(text, Path::new("tiny.toml")).unwrap();
    assert_eq!(study.cases.len(), 4);
    let model = stride_model::default_model::default_model();
    check_cases(&model, &study.cases, Some(4)).unwrap();
    assert!(check_cases(&model, &study.cases, Some(8)).is_err());
    let store = Store::open(&out, &study, false).unwrap();
    let runner = PredictRunner {
        model,
        solver: Box::new(stride_solve::ipm::InteriorPoint::new()),
        options: SolverOptions {
            max_iter: 4,
            tol: 1e-4,
            mu_strategy: MuStrategy::Adaptive,
            time_limit: Some(Duration::from_secs(20)),
            threads: 1,
            ..Default::default()
        },
        write_unconverged: true,
        // the 4-iteration coarse solves do not converge: the fine solves start cold
        presolve_mesh: Some(4),
    };
    let summary = run_study(
        &study,
        &store,
        &runner,
        &RunOptions {
            jobs: 2,
            progress: None,
            retry_failed: false,
            only: None,
        },
    )
    .unwrap();
    assert_eq!(summary.ran, 4);
    for name in ["speed_1.33__qr", "speed_1.43__fos", "speed_1.43__pos"] {
        let r = store.record(name).unwrap().unwrap();
        assert!(r.iterations.is_some(), "{name}: {}", r.reason);
        assert!(r.solution_written, "{name}");
        assert!(out.join("cases").join(name).join(SOLUTION_FILE).exists());
        assert!(out.join("cases").join(name).join("summary.json").exists());
    }
    // Each case's summary and solver log name the guess it really started from.
    for (name, guess) in [
        ("speed_1.33__qr", "quasi-random"),
        ("speed_1.43__fos", "full-os"),
        ("speed_1.43__pos", "partial-os"),
    ] {
        let dir = out.join("cases").join(name);
        let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
        let s: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(s["guesses"][0]["guess"], guess, "{name}");
        // standard and partial-solution guesses are presolved on the coarse mesh (here
        // unconverged after 4 iterations, so not used); full-solution continuations start
        // from their source instead
        let presolve = &s["guesses"][0]["presolve"];
        if guess != "full-os" {
            assert_eq!(presolve["mesh_intervals"], 4, "{name}");
            assert_eq!(presolve["used"], false, "{name}");
            assert_eq!(presolve["iterations"], 4, "{name}");
        } else {
            assert!(presolve.is_null(), "{name}: {presolve}");
        }
        assert!(
            dir.join(format!("solver_log_{guess}.csv")).exists(),
            "{name}"
        );
        // a full-solution continuation starts warm (small μ, bound multipliers on its
        // central path), and its summary records the options it was solved with
        let warm = &s["solver_options"];
        assert_eq!(warm["warm_start"], guess == "full-os", "{name}");
        assert_eq!(
            warm["mu_init"].as_f64() == Some(0.1),
            guess != "full-os",
            "{name}"
        );
    }
    let fos = store.record("speed_1.43__fos").unwrap().unwrap();
    assert_eq!(fos.continued_from.as_deref(), Some("speed_1.33__qr"));
    let report = stride_study::report::report_folder(&out).unwrap();
    assert_eq!(report.cases, 4);
    // The condition measures can be recomputed from a written solution; a solution that
    // does not fit the problem of its settings is an error that says so.
    let case = out.join("cases").join("speed_1.33__qr");
    let m = measures_from_solution(&runner.model, &case).unwrap();
    assert!(m.trunk_sway.is_some_and(|s| s.is_finite() && s >= 0.0));
    // Rewriting case folders: one without a kept solution is left as it is; one with a kept
    // solution (here the unconverged iterate marked as kept) gets the cycle files and a
    // solution whose cycle is the reconstructed one.
    let pos = out.join("cases").join("speed_1.43__pos");
    assert_eq!(rewrite_case(&runner.model, &pos), Ok(Rewritten::NoSolution));
    assert!(!pos.join("motion.mot").exists());
    let summary_path = case.join("summary.json");
    let mut summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&summary_path).unwrap()).unwrap();
    summary["kept_guess"] = "quasi-random".into();
    std::fs::write(&summary_path, summary.to_string()).unwrap();
    assert_eq!(rewrite_case(&runner.model, &case), Ok(Rewritten::Rewritten));
    assert!(case.join("motion.mot").exists() && case.join("joint_angles.csv").exists());
    let rewritten: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&summary_path).unwrap()).unwrap();
    assert!(rewritten["outcomes"]["stride_length"].is_number());
    let text = std::fs::read_to_string(case.join(SOLUTION_FILE)).unwrap();
    let sol: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(
        sol["cycle_time"].as_array().unwrap().len(),
        16,
        "full cycle = 2N"
    );
    assert!(case.join("solver_log_quasi-random.csv").exists());
    let mut sol: serde_json::Value = serde_json::from_str(&text).unwrap();
    sol["x"].as_array_mut().unwrap().pop();
    let bad = out.join("bad");
    std::fs::create_dir_all(&bad).unwrap();
    std::fs::write(bad.join(SOLUTION_FILE), sol.to_string()).unwrap();
    let e = measures_from_solution(&runner.model, &bad).unwrap_err();
    assert!(e.contains("variables"), "{e}");
    let _ = std::fs::remove_dir_all(&out);
}
