//! Derivative and structure checks of the test problems (finite differences, published values).

use crate::nlp::{
    check_derivatives, validate_bounds, validate_structures, DerivativeCheckOptions, Nlp,
};
use crate::problems::{Hs006, Hs021, Hs035, Hs071, InfeasibleDisk, PendulumChain, RosenbrockDisk};

fn fd_check(name: &str, nlp: &dyn Nlp, x: &[f64]) {
    let lambda: Vec<f64> = (0..nlp.m()).map(|i| 0.7 - 0.3 * i as f64).collect();
    let opts = DerivativeCheckOptions {
        lambda: Some(lambda),
        obj_factor: 1.3,
        ..DerivativeCheckOptions::default()
    };
    let rep = check_derivatives(nlp, x, &opts).unwrap();
    assert!(
        rep.mismatches.is_empty(),
        "{name}: {:?}",
        &rep.mismatches[..rep.mismatches.len().min(5)]
    );
    assert!(rep.max_error < 1e-5, "{name}: {}", rep.max_error);
}

#[test]
fn classic_derivatives_match_finite_differences() {
    fd_check("HS071", &Hs071, &[1.3, 4.1, 3.2, 1.7]);
    fd_check("Rosenbrock", &RosenbrockDisk, &[0.3, -0.8]);
    fd_check("HS035", &Hs035, &[0.4, 1.1, 0.7]);
    fd_check("HS021", &Hs021, &[3.0, -2.0]);
    fd_check("HS006", &Hs006, &[-0.4, 0.9]);
    fd_check("Infeasible", &InfeasibleDisk, &[0.2, 0.6]);
}

#[test]
fn published_optima_are_feasible_and_match_objective() {
    let mut c = [0.0; 2];
    Hs071.constraints(&Hs071::X_OPT, &mut c).unwrap();
    assert!(c[0] >= 25.0 - 1e-6 && (c[1] - 40.0).abs() < 1e-6, "{c:?}");
    assert!((Hs071.objective(&Hs071::X_OPT).unwrap() - Hs071::F_OPT).abs() < 1e-6);
    let r = RosenbrockDisk::X_OPT;
    assert!((r[0] * r[0] + r[1] * r[1] - 1.0).abs() < 1e-6);
    assert!((RosenbrockDisk.objective(&r).unwrap() - RosenbrockDisk::F_OPT).abs() < 1e-6);
    assert!((Hs035.objective(&Hs035::X_OPT).unwrap() - Hs035::F_OPT).abs() < 1e-12);
    assert!((Hs021.objective(&Hs021::X_OPT).unwrap() - Hs021::F_OPT).abs() < 1e-12);
}

#[test]
fn collocation_problem_is_well_formed_and_derivatives_match() {
    let p = PendulumChain::new(3, 4);
    validate_bounds(&p).unwrap();
    validate_structures(&p).unwrap();
    let mut x = vec![0.0; p.n()];
    p.initial_point(&mut x);
    for (i, v) in x.iter_mut().enumerate() {
        *v += 0.1 * ((i as f64) * 0.37).sin();
    }
    fd_check("PendulumChain", &p, &x);
    assert_eq!(p.n(), PendulumChain::variables_for(3, 4));
}

#[test]
fn radau_coefficients_differentiate_cubics_exactly() {
    // Σ_r C_rj p(τ_r) = p'(τ_j) for p(τ) = τ³ (independent check of FORMULATION 8.2).
    use crate::problems::collocation::{RADAU_B, RADAU_C};
    let tau: [f64; 4] = [0.0, 0.155051025721682, 0.644948974278318, 1.0];
    for j in 0..3 {
        let d: f64 = (0..4).map(|r| RADAU_C[r][j] * tau[r].powi(3)).sum();
        assert!((d - 3.0 * tau[j + 1].powi(2)).abs() < 1e-12);
    }
    // Quadrature integrates τ⁴ over [0, 1] exactly (Radau IIA with 3 points: degree 4).
    let q: f64 = (0..3).map(|j| RADAU_B[j] * tau[j + 1].powi(4)).sum();
    assert!((q - 0.2).abs() < 1e-12);
}
