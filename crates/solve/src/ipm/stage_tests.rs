//! Tests of single stages of the interior point, observed through its diagnostic events
//! or driven directly on its workspace.

use std::ops::ControlFlow;

use crate::ipm::barrier::{monotone_decrease, KAPPA_EPS};
use crate::ipm::linsys::FaerLdlt;
use crate::ipm::workspace::Ipm;
use crate::ipm::InteriorPoint;
use crate::nlp::{EvalError, Nlp, Sparsity};
use crate::observer::{Diagnostic, Observer};
use crate::problems::{Hs071, WaechterBiegler};
use crate::solver::{IterationRecord, MuStrategy, SolveResult, Solver, SolverOptions};

/// Keeps every record and diagnostic event.
#[derive(Default)]
struct Recorder {
    records: Vec<IterationRecord>,
    events: Vec<Diagnostic>,
}

impl Observer for Recorder {
    fn iteration(&mut self, record: &IterationRecord) -> ControlFlow<()> {
        self.records.push(record.clone());
        ControlFlow::Continue(())
    }
    fn diagnostic(&mut self, event: &Diagnostic) {
        self.events.push(event.clone());
    }
}

fn observed(nlp: &dyn Nlp, o: &SolverOptions) -> (SolveResult, Recorder) {
    let mut rec = Recorder::default();
    let r = InteriorPoint::new().solve(nlp, o, &mut rec).unwrap();
    (r, rec)
}

/// Powell's example of the Maratos effect: min 2(x₀² + x₁² − 1) − x₀ subject to
/// x₀² + x₁² = 1, optimum (1, 0) with λ = −3/2 (∇f + λ∇c = 0). From a point on the circle
/// the full Newton step leaves the circle and increases f: the filter rejects it, and the
/// second-order correction (a step back to the circle) is accepted.
struct Maratos;

impl Nlp for Maratos {
    fn n(&self) -> usize {
        2
    }
    fn m(&self) -> usize {
        1
    }
    fn bounds(&self, xl: &mut [f64], xu: &mut [f64], gl: &mut [f64], gu: &mut [f64]) {
        xl.fill(f64::NEG_INFINITY);
        xu.fill(f64::INFINITY);
        (gl[0], gu[0]) = (0.0, 0.0);
    }
    fn initial_point(&self, x: &mut [f64]) {
        let t: f64 = 0.5;
        (x[0], x[1]) = (t.cos(), t.sin());
    }
    fn objective(&self, x: &[f64]) -> Result<f64, EvalError> {
        Ok(2.0 * (x[0] * x[0] + x[1] * x[1] - 1.0) - x[0])
    }
    fn gradient(&self, x: &[f64], g: &mut [f64]) -> Result<(), EvalError> {
        (g[0], g[1]) = (4.0 * x[0] - 1.0, 4.0 * x[1]);
        Ok(())
    }
    fn constraints(&self, x: &[f64], c: &mut [f64]) -> Result<(), EvalError> {
        c[0] = x[0] * x[0] + x[1] * x[1] - 1.0;
        Ok(())
    }
    fn jacobian_structure(&self) -> Sparsity {
        Sparsity::new(vec![0, 0], vec![0, 1])
    }
    fn jacobian_values(&self, x: &[f64], v: &mut [f64]) -> Result<(), EvalError> {
        (v[0], v[1]) = (2.0 * x[0], 2.0 * x[1]);
        Ok(())
    }
    fn hessian_structure(&self) -> Sparsity {
        Sparsity::new(vec![0, 1], vec![0, 1])
    }
    fn hessian_values(&self, _: &[f64], s: f64, l: &[f64], v: &mut [f64]) -> Result<(), EvalError> {
        let d = 4.0 * s + 2.0 * l[0];
        (v[0], v[1]) = (d, d);
        Ok(())
    }
}

#[test]
fn second_order_correction_overcomes_the_maratos_effect() {
    let o = SolverOptions {
        print_level: 3,
        nlp_scaling: false,
        ..SolverOptions::default()
    };
    let (r, rec) = observed(&Maratos, &o);
    assert!(r.status.is_success(), "{:?}", r.status);
    assert!(
        (r.x[0] - 1.0).abs() < 1e-6 && r.x[1].abs() < 1e-6,
        "{:?}",
        r.x
    );
    assert!((r.lambda[0] + 1.5).abs() < 1e-6, "{:?}", r.lambda);
    let soc: Vec<bool> = rec
        .events
        .iter()
        .filter_map(|e| match e {
            Diagnostic::SecondOrderCorrection { accepted, .. } => Some(*accepted),
            _ => None,
        })
        .collect();
    assert!(soc.contains(&true), "no accepted correction: {soc:?}");
}

#[test]
fn feasibility_restoration_reduces_the_violation_from_the_waechter_biegler_start() {
    let o = SolverOptions {
        print_level: 2,
        soft_restoration: false,
        ..SolverOptions::default()
    };
    let (r, rec) = observed(&WaechterBiegler, &o);
    let steps: Vec<(f64, Option<f64>)> = rec
        .events
        .iter()
        .filter_map(|e| match e {
            Diagnostic::RestorationStep {
                theta, accepted, ..
            } => Some((*theta, *accepted)),
            _ => None,
        })
        .collect();
    assert!(!steps.is_empty(), "no restoration step");
    // every accepted restoration step reduces θ = ‖r‖₁ or keeps it (merit decrease)
    assert!(
        steps.iter().any(|(t, a)| a.is_some_and(|a| a < *t)),
        "{steps:?}"
    );
    assert!(r.status.is_success(), "{:?}", r.status);
    assert!((r.objective - 1.0).abs() < 1e-6, "f = {}", r.objective);
}

#[test]
fn the_monotone_barrier_update_decreases_mu_while_the_barrier_problem_is_solved() {
    // IPOPT's superlinear decrease and the linear one of warm-started exact solves
    for power in [1.5, 1.0] {
        monotone_update_with_power(power);
    }
}

fn monotone_update_with_power(power: f64) {
    let o = SolverOptions {
        mu_strategy: MuStrategy::Monotone,
        mu_superlinear_power: power,
        ..SolverOptions::default()
    };
    let mut quiet = |_: &IterationRecord| ControlFlow::Continue(());
    let mut ldlt = FaerLdlt::new();
    let mut ipm = Ipm::new(&Hs071, &o, &mut quiet, &mut ldlt).unwrap();
    ipm.measure_residuals();
    ipm.measure_optimality();
    let floor = ipm.mu_floor();
    // a large μ: the barrier problem counts as solved (E_μ ≤ κ_ε μ), μ decreases by
    // min(κ_μ μ, μ^θ_μ) until it no longer is
    let mu0 = 1e3;
    ipm.barrier.mu = mu0;
    assert!(ipm.barrier_error(mu0) <= KAPPA_EPS * mu0);
    ipm.update_barrier(floor);
    let mu = ipm.barrier.mu;
    assert!(mu < mu0);
    let mut expected = mu0;
    while ipm.barrier_error(expected) <= KAPPA_EPS * expected && expected > floor {
        expected = monotone_decrease(expected, floor, o.mu_superlinear_power);
    }
    assert_eq!(mu, expected);
    assert!(ipm.barrier_error(mu) > KAPPA_EPS * mu || mu == floor);
    // not solved at the new μ: unchanged by another update
    ipm.update_barrier(floor);
    assert_eq!(ipm.barrier.mu, mu);
}
