//! The transcribed NLP's gradient, Jacobian and Lagrangian Hessian (tape node function plus
//! the hand-derived collocation, continuity, symmetry, speed and cost-normalisation parts)
//! against central finite differences, at a perturbed data-informed guess.

use stride_ocp::{
    data, experimental::Kinematics, guess::GuessKind, node::NodeModel, problem::GaitProblem,
    settings::ProblemSettings, tape_node::TapeNode, transcription::Transcription,
};
use stride_solve::nlp::{check_derivatives, DerivativeCheckOptions, Nlp};

/// The 3-interval nominal problem on the tape node function, and its data-informed walking
/// guess moved by `perturbation(i)` in variable `i`.
fn small_transcription(perturbation: impl Fn(usize) -> f64) -> (Transcription<TapeNode>, Vec<f64>) {
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
    for (i, xi) in x.iter_mut().enumerate() {
        *xi += perturbation(i);
    }
    let node = NodeModel::new(&problem).unwrap();
    let tape = TapeNode::for_problem(&problem, &node, &x).unwrap();
    (Transcription::new(problem, tape, x.clone()), x)
}

#[test]
fn transcription_derivatives_match_finite_differences() {
    // Deterministic perturbation so that no variable sits at a special value.
    let (tr, x) = small_transcription(|i| 1e-3 * ((i as f64 * 0.7548776662).fract() - 0.5));
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

/// The Hessian's sweeps also fill the node Jacobians (kept for the gradient and Jacobian at
/// the same point): asking for the Hessian first, or after a move to another point, must
/// give the numbers of the Jacobian's own sweeps, which the test above checks against
/// finite differences.
#[test]
fn hessian_first_gives_the_same_jacobian_and_gradient() {
    let (tr, x) = small_transcription(|_| 0.0);
    let (n, m) = (tr.n(), tr.m());
    let (nj, nh) = (tr.jacobian_structure().nnz(), tr.hessian_structure().nnz());
    let lambda: Vec<f64> = (0..m).map(|i| (i as f64 * 0.37).sin()).collect();
    let moved: Vec<f64> = x
        .iter()
        .enumerate()
        .map(|(i, v)| v + 1e-3 * (i as f64 * 0.61).cos())
        .collect();
    // Jacobian's own sweeps first, then the Hessian, at each point.
    let separate = |p: &[f64]| {
        tr.clear_cache();
        let (mut g, mut j, mut h) = (vec![0.0; n], vec![0.0; nj], vec![0.0; nh]);
        tr.gradient(p, &mut g).unwrap();
        tr.jacobian_values(p, &mut j).unwrap();
        tr.hessian_values(p, 0.8, &lambda, &mut h).unwrap();
        (g, j, h)
    };
    let (g0, j0, h0) = separate(&x);
    let (g1, j1, h1) = separate(&moved);
    // Hessian first: at x from an empty cache, then at the moved point with x cached.
    tr.clear_cache();
    for (p, (g_ref, j_ref, h_ref)) in [(&x, (&g0, &j0, &h0)), (&moved, (&g1, &j1, &h1))] {
        let (mut g, mut j, mut h) = (vec![0.0; n], vec![0.0; nj], vec![0.0; nh]);
        tr.hessian_values(p, 0.8, &lambda, &mut h).unwrap();
        tr.gradient(p, &mut g).unwrap();
        tr.jacobian_values(p, &mut j).unwrap();
        assert_eq!(&h, h_ref, "Hessian");
        assert_eq!(&g, g_ref, "gradient");
        assert_eq!(&j, j_ref, "Jacobian");
    }
    assert_ne!(j0, j1, "the two points must differ");
}
