//! Tests of the backends on small NLPs with published optima (compiled with either backend).

use crate::nlp::{EvalError, Nlp, Sparsity};
use crate::solver::{ControlFlow, IterationRecord, SolveResult, Solver, SolverOptions};

/// Hock–Schittkowski problem 71: min x0 x3 (x0+x1+x2) + x2 s.t. x0x1x2x3 >= 25,
/// Σx² = 40, 1 <= x <= 5; optimum f* = 17.0140173 (Hock & Schittkowski 1981).
pub struct Hs071;

/// HS071's published optimal objective.
pub const HS071_F: f64 = 17.014_017_3;
/// HS071's published optimal point.
pub const HS071_X: [f64; 4] = [1.0, 4.742_999_63, 3.821_149_98, 1.379_408_29];

impl Nlp for Hs071 {
    fn n(&self) -> usize {
        4
    }
    fn m(&self) -> usize {
        2
    }
    fn bounds(&self, x_l: &mut [f64], x_u: &mut [f64], g_l: &mut [f64], g_u: &mut [f64]) {
        x_l.fill(1.0);
        x_u.fill(5.0);
        g_l.copy_from_slice(&[25.0, 40.0]);
        g_u.copy_from_slice(&[f64::INFINITY, 40.0]);
    }
    fn initial_point(&self, x: &mut [f64]) {
        x.copy_from_slice(&[1.0, 5.0, 5.0, 1.0]);
    }
    fn objective(&self, x: &[f64]) -> Result<f64, EvalError> {
        Ok(x[0] * x[3] * (x[0] + x[1] + x[2]) + x[2])
    }
    fn gradient(&self, x: &[f64], g: &mut [f64]) -> Result<(), EvalError> {
        g[0] = x[3] * (2.0 * x[0] + x[1] + x[2]);
        g[1] = x[0] * x[3];
        g[2] = x[0] * x[3] + 1.0;
        g[3] = x[0] * (x[0] + x[1] + x[2]);
        Ok(())
    }
    fn constraints(&self, x: &[f64], c: &mut [f64]) -> Result<(), EvalError> {
        c[0] = x[0] * x[1] * x[2] * x[3];
        c[1] = x.iter().map(|v| v * v).sum();
        Ok(())
    }
    fn jacobian_structure(&self) -> Sparsity {
        Sparsity::new(vec![0, 0, 0, 0, 1, 1, 1, 1], vec![0, 1, 2, 3, 0, 1, 2, 3])
    }
    fn jacobian_values(&self, x: &[f64], v: &mut [f64]) -> Result<(), EvalError> {
        v[..4].copy_from_slice(&[
            x[1] * x[2] * x[3],
            x[0] * x[2] * x[3],
            x[0] * x[1] * x[3],
            x[0] * x[1] * x[2],
        ]);
        for i in 0..4 {
            v[4 + i] = 2.0 * x[i];
        }
        Ok(())
    }
    fn hessian_structure(&self) -> Sparsity {
        let mut s = Sparsity::default();
        for r in 0..4 {
            for c in 0..=r {
                s.push(r, c);
            }
        }
        s
    }
    fn hessian_values(&self, x: &[f64], s: f64, l: &[f64], v: &mut [f64]) -> Result<(), EvalError> {
        // Order: (0,0) (1,0) (1,1) (2,0) (2,1) (2,2) (3,0) (3,1) (3,2) (3,3).
        v[0] = s * 2.0 * x[3] + l[1] * 2.0;
        v[1] = s * x[3] + l[0] * x[2] * x[3];
        v[2] = l[1] * 2.0;
        v[3] = s * x[3] + l[0] * x[1] * x[3];
        v[4] = l[0] * x[0] * x[3];
        v[5] = l[1] * 2.0;
        v[6] = s * (2.0 * x[0] + x[1] + x[2]) + l[0] * x[1] * x[2];
        v[7] = s * x[0] + l[0] * x[0] * x[2];
        v[8] = s * x[0] + l[0] * x[0] * x[1];
        v[9] = l[1] * 2.0;
        Ok(())
    }
}

/// The Rosenbrock function 100 (x1 − x0²)² + (1 − x0)², unconstrained, from (−1.2, 1);
/// minimum 0 at (1, 1).
pub struct Rosenbrock;

impl Nlp for Rosenbrock {
    fn n(&self) -> usize {
        2
    }
    fn m(&self) -> usize {
        0
    }
    fn bounds(&self, x_l: &mut [f64], x_u: &mut [f64], _: &mut [f64], _: &mut [f64]) {
        x_l.fill(f64::NEG_INFINITY);
        x_u.fill(f64::INFINITY);
    }
    fn initial_point(&self, x: &mut [f64]) {
        x.copy_from_slice(&[-1.2, 1.0]);
    }
    fn objective(&self, x: &[f64]) -> Result<f64, EvalError> {
        Ok(100.0 * (x[1] - x[0] * x[0]).powi(2) + (1.0 - x[0]).powi(2))
    }
    fn gradient(&self, x: &[f64], g: &mut [f64]) -> Result<(), EvalError> {
        g[0] = -400.0 * x[0] * (x[1] - x[0] * x[0]) - 2.0 * (1.0 - x[0]);
        g[1] = 200.0 * (x[1] - x[0] * x[0]);
        Ok(())
    }
    fn constraints(&self, _: &[f64], _: &mut [f64]) -> Result<(), EvalError> {
        Ok(())
    }
    fn jacobian_structure(&self) -> Sparsity {
        Sparsity::default()
    }
    fn jacobian_values(&self, _: &[f64], _: &mut [f64]) -> Result<(), EvalError> {
        Ok(())
    }
    fn hessian_structure(&self) -> Sparsity {
        Sparsity::new(vec![0, 1, 1], vec![0, 0, 1])
    }
    fn hessian_values(&self, x: &[f64], s: f64, _: &[f64], v: &mut [f64]) -> Result<(), EvalError> {
        v[0] = s * (1200.0 * x[0] * x[0] - 400.0 * x[1] + 2.0);
        v[1] = s * (-400.0 * x[0]);
        v[2] = s * 200.0;
        Ok(())
    }
}

/// Solves with a silent observer.
pub fn run(solver: &dyn Solver, nlp: &dyn Nlp, o: &SolverOptions) -> SolveResult {
    let mut obs = |_: &IterationRecord| ControlFlow::Continue(());
    solver
        .solve(nlp, o, &mut obs)
        .unwrap_or_else(|e| panic!("{} failed to start: {e}", solver.name()))
}

/// Asserts that `r` is HS071's published optimum with consistent multipliers.
pub fn assert_hs071(r: &SolveResult) {
    assert!(r.status.is_success(), "status {:?}", r.status);
    assert!((r.objective - HS071_F).abs() < 1e-6, "f = {}", r.objective);
    for (a, b) in r.x.iter().zip(HS071_X) {
        assert!((a - b).abs() < 1e-6, "x = {:?}", r.x);
    }
    // IPOPT-style solvers relax bounds by bound_relax_factor = 1e-8 (relative).
    assert!(
        r.constraint_violation < 1e-6,
        "viol {}",
        r.constraint_violation
    );
    // Independent check of the multiplier sign convention: ∇f + Jᵀλ − z_l + z_u = 0.
    assert!(
        r.dual_infeasibility < 1e-6,
        "dual inf {}",
        r.dual_infeasibility
    );
    assert!(!r.log.is_empty() && r.log.len() >= r.iterations);
    assert!(r.time_evaluations <= r.time_total);
}

/// Asserts that `r` is the Rosenbrock minimum (1, 1).
pub fn assert_rosenbrock(r: &SolveResult) {
    assert!(r.status.is_success(), "status {:?}", r.status);
    assert!(r.objective.abs() < 1e-12, "f = {}", r.objective);
    assert!((r.x[0] - 1.0).abs() < 1e-6 && (r.x[1] - 1.0).abs() < 1e-6);
}
