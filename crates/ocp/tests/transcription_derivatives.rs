//! The transcribed NLP's gradient, Jacobian and Lagrangian Hessian (tape node function plus
//! the hand-derived collocation, continuity, symmetry, speed and cost-normalisation parts)
//! against central finite differences, at a perturbed data-informed guess.

use stride_ocp::{
    data, experimental::Kinematics, guess::GuessKind, node::NodeModel, problem::GaitProblem,
    settings::ProblemSettings, tape_node::TapeNode, transcription::Transcription,
};
use stride_solve::nlp::{check_derivatives, DerivativeCheckOptions, Nlp};

#[test]
fn transcription_derivatives_match_finite_differences() {
    let model = stride_model::default_model::default_model();
    let settings = ProblemSettings {
        mesh_intervals: 3,
        ..Default::default()
    };
    let walking = data::walking_half_cycle();
    let problem = GaitProblem::new(&model, &settings, &walking).unwrap();
    let kin = Kinematics::from_storage(&walking, &problem.gait, "walking").unwrap();
    let mut x = problem
        .initial_guess(GuessKind::DataInformedWalking, Some(&kin))
        .unwrap();
    // Deterministic perturbation so that no variable sits at a special value.
    for (i, xi) in x.iter_mut().enumerate() {
        *xi += 1e-3 * ((i as f64 * 0.7548776662).fract() - 0.5);
    }
    let node = NodeModel::new(&problem).unwrap();
    let tape = TapeNode::for_problem(&problem, &node, &x).unwrap();
    let tr = Transcription::new(problem, tape, x.clone());
    let lambda: Vec<f64> = (0..tr.m())
        .map(|i| ((i as f64 * 0.5698402910).fract() - 0.5) * 2.0)
        .collect();
    // First derivatives: relative 1e-6.
    let first = check_derivatives(
        &tr,
        &x,
        &DerivativeCheckOptions {
            max_columns: 400,
            tol: 1e-6,
            ..Default::default()
        },
    )
    .unwrap();
    println!(
        "gradient and Jacobian: {} columns, max scaled error {:.2e}",
        first.columns_checked, first.max_error
    );
    assert!(
        first.mismatches.is_empty(),
        "{:?}",
        &first.mismatches[..first.mismatches.len().min(5)]
    );
    // Hessian: finite differences of the Lagrangian gradient carry truncation errors of
    // order h²·f''' where the friction smoothing √(v²+10⁻⁵) makes third derivatives with
    // respect to the (scaled) speeds very large; 1e-4 separates those from real errors
    // (the tape's Hessians are checked against hyper-dual numbers to 1e-10 in stride-ad).
    let opts = DerivativeCheckOptions {
        max_columns: 400,
        lambda: Some(lambda),
        obj_factor: 0.7,
        tol: 1e-4,
        ..Default::default()
    };
    let report = check_derivatives(&tr, &x, &opts).unwrap();
    println!(
        "checked {} columns, max scaled error {:.2e}",
        report.columns_checked, report.max_error
    );
    for m in report.mismatches.iter().take(10) {
        println!("{m:?}");
    }
    assert!(report.mismatches.is_empty(), "derivative mismatches");
}
