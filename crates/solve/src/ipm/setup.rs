//! The starting point of the interior point (IPOPT's initialisation, Wächter & Biegler
//! 2006, section 3.6): bounds relaxed by 1e-8 relative, the initial point pushed into the
//! interior by `bound_push` (κ₁, κ₂), fixed variables taken out, slacks for the inequality
//! rows at their constraint values, bound multipliers 1 (or on the central path of μ_init
//! for a warm start), gradient-based scaling, and least-squares constraint multipliers.
// Index loops over several parallel arrays are clearer than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use std::time::Instant;

use crate::ipm::inertia::{KktSystem, DELTA_C};
use crate::ipm::iterate::{inf_norm, Iterate, NO_SLACK};
use crate::ipm::linsys::KktSolver;
use crate::ipm::scaled::ScaledNlp;
use crate::nlp::{Bounds, EvalError, NlpFunction};
use crate::solver::{SolveError, SolverOptions};

/// Least-squares constraint multipliers larger than this are discarded (IPOPT
/// `constr_mult_init_max`).
const CONSTR_MULT_INIT_MAX: f64 = 1000.0;
/// Relative relaxation of the bounds (IPOPT `bound_relax_factor`).
const BOUND_RELAX: f64 = 1e-8;

/// A bound relaxed outwards (`sign` −1 for a lower, +1 for an upper bound).
fn relax(v: f64, sign: f64) -> f64 {
    v + sign * BOUND_RELAX * v.abs().max(1.0)
}

/// `v` moved into the interior of [lo, hi] by the bound push κ (IPOPT's κ₁ = κ₂ = κ).
fn push(kappa: f64, lo: f64, hi: f64, v: f64) -> f64 {
    let mut v = v;
    if lo.is_finite() {
        let p = if hi.is_finite() {
            (kappa * lo.abs().max(1.0)).min(kappa * (hi - lo))
        } else {
            kappa * lo.abs().max(1.0)
        };
        v = v.max(lo + p);
    }
    if hi.is_finite() {
        let p = if lo.is_finite() {
            (kappa * hi.abs().max(1.0)).min(kappa * (hi - lo))
        } else {
            kappa * hi.abs().max(1.0)
        };
        v = v.min(hi - p);
    }
    if lo.is_finite() && hi.is_finite() && !(v > lo && v < hi) {
        v = 0.5 * (lo + hi);
    }
    v
}

/// The starting primal point: x₀ pushed inside the relaxed bounds x_l, x_u, and which
/// variables are fixed (x_l = x_u: kept at their value, without bounds or multipliers).
pub(super) struct StartingPoint {
    pub x0: Vec<f64>,
    pub xl: Vec<f64>,
    pub xu: Vec<f64>,
    pub fixed_x: Vec<bool>,
}

/// The initial point x₀ of the problem, pushed inside its relaxed bounds.
pub(super) fn initial_point(
    prob: &ScaledNlp,
    bounds: &Bounds,
    o: &SolverOptions,
) -> Result<StartingPoint, SolveError> {
    let n = prob.nlp.n();
    let mut x0 = vec![0.0; n];
    prob.nlp.initial_point(&mut x0);
    if let Some(i) = x0.iter().position(|v| !v.is_finite()) {
        return Err(SolveError::InitialEvaluation(EvalError::Failed {
            function: NlpFunction::Objective,
            reason: format!("initial point entry {i} is {}", x0[i]),
        }));
    }
    let mut fixed_x = vec![false; n];
    let mut xl: Vec<f64> = bounds.x_l.iter().map(|&v| relax(v, -1.0)).collect();
    let mut xu: Vec<f64> = bounds.x_u.iter().map(|&v| relax(v, 1.0)).collect();
    for j in 0..n {
        if !bounds.x_l[j].is_finite() {
            xl[j] = f64::NEG_INFINITY;
        }
        if !bounds.x_u[j].is_finite() {
            xu[j] = f64::INFINITY;
        }
        x0[j] = push(o.bound_push, xl[j], xu[j], x0[j]);
        if bounds.x_l[j] == bounds.x_u[j] {
            fixed_x[j] = true;
            xl[j] = f64::NEG_INFINITY;
            xu[j] = f64::INFINITY;
            x0[j] = bounds.x_l[j];
        }
    }
    Ok(StartingPoint {
        x0,
        xl,
        xu,
        fixed_x,
    })
}

/// The first iterate: slacks for the inequality rows (bounds scaled and relaxed, values
/// pushed inside them), function values and derivatives at `x0` (relaxed bounds `xl`,
/// `xu`), bound multipliers 1, or μ_init/(distance to the bound) for a warm start.
pub(super) fn initial_iterate(
    prob: &mut ScaledNlp,
    bounds: &Bounds,
    (x0, xl, xu): (&[f64], Vec<f64>, Vec<f64>),
    o: &SolverOptions,
) -> Result<Iterate, SolveError> {
    let (n, m) = (prob.nlp.n(), prob.nlp.m());
    let mut slack_of_row = vec![NO_SLACK; m];
    let mut row_of_slack = Vec::new();
    let mut g_eq = vec![0.0; m];
    for i in 0..m {
        if bounds.g_l[i] == bounds.g_u[i] {
            g_eq[i] = bounds.g_l[i] * prob.con_scale[i];
        } else {
            slack_of_row[i] = row_of_slack.len();
            row_of_slack.push(i);
        }
    }
    let big_n = n + row_of_slack.len();
    let (mut wl, mut wu) = (xl, xu);
    for &i in &row_of_slack {
        let s = prob.con_scale[i];
        let (lo, hi) = (bounds.g_l[i] * s, bounds.g_u[i] * s);
        wl.push(if lo.is_finite() { relax(lo, -1.0) } else { lo });
        wu.push(if hi.is_finite() { relax(hi, 1.0) } else { hi });
    }
    let has_l: Vec<bool> = wl.iter().map(|v| v.is_finite()).collect();
    let has_u: Vec<bool> = wu.iter().map(|v| v.is_finite()).collect();
    let mut st = Iterate {
        n,
        m,
        big_n,
        slack_of_row,
        row_of_slack,
        g_eq,
        wl,
        wu,
        has_l,
        has_u,
        w: vec![0.0; big_n],
        lam: vec![0.0; m],
        zl: vec![0.0; big_n],
        zu: vec![0.0; big_n],
        f: 0.0,
        grad: vec![0.0; n],
        c: vec![0.0; m],
        jv: vec![0.0; prob.jac.nnz()],
        hv: vec![0.0; prob.hess.nnz()],
    };
    st.w[..n].copy_from_slice(x0);
    let init = SolveError::InitialEvaluation;
    st.f = prob.objective(x0).map_err(init)?;
    prob.gradient(x0, &mut st.grad).map_err(init)?;
    prob.constraints(x0, &mut st.c).map_err(init)?;
    prob.jacobian(x0, &mut st.jv).map_err(init)?;
    for (k, &i) in st.row_of_slack.iter().enumerate() {
        st.w[n + k] = push(o.bound_push, st.wl[n + k], st.wu[n + k], st.c[i]);
    }
    initial_bound_multipliers(&mut st, o);
    Ok(st)
}

/// Bound multipliers 1 (IPOPT), or on the central path of μ_init for a warm start.
fn initial_bound_multipliers(st: &mut Iterate, o: &SolverOptions) {
    let z_init = |gap: f64| {
        if o.warm_start {
            o.mu_init / gap.max(f64::MIN_POSITIVE)
        } else {
            1.0
        }
    };
    for j in 0..st.big_n {
        st.zl[j] = if st.has_l[j] {
            z_init(st.w[j] - st.wl[j])
        } else {
            0.0
        };
        st.zu[j] = if st.has_u[j] {
            z_init(st.wu[j] - st.w[j])
        } else {
            0.0
        };
    }
}

/// Least-squares constraint multipliers (IPOPT's initialisation): the solution of
/// [I Aᵀ; A 0] (d, λ) = (−(∇f − z_L + z_U), 0) over w = (x, s) with the slacks condensed,
/// kept when the factorisation has the right inertia and ‖λ‖∞ ≤ 1000; else λ stays 0.
pub(super) fn least_squares_multipliers(
    kkt: &mut KktSystem,
    st: &mut Iterate,
) -> Result<(), SolveError> {
    let (n, m) = (st.n, st.m);
    kkt.diag_x.iter_mut().for_each(|v| *v = 1.0);
    for i in 0..m {
        kkt.d_c[i] = if st.slack_of_row[i] == NO_SLACK {
            DELTA_C
        } else {
            1.0 + DELTA_C
        };
    }
    kkt.pattern
        .assemble(&mut kkt.vals, &kkt.zero_h, &st.jv, &kkt.diag_x, &kkt.d_c);
    let t = Instant::now();
    let inertia = kkt
        .linear
        .factor(&kkt.vals)
        .map_err(|e| SolveError::Backend(e.to_string()))?;
    kkt.factorizations += 1;
    if inertia.positive == n && inertia.negative == m {
        let rhs = &mut kkt.rhs;
        for j in 0..n {
            rhs[j] = -(st.grad[j] - st.zl[j] + st.zu[j]);
        }
        for i in 0..m {
            let k = st.slack_of_row[i];
            rhs[n + i] = if k == NO_SLACK {
                0.0
            } else {
                st.zl[n + k] - st.zu[n + k]
            };
        }
        if kkt.linear.solve(rhs).is_ok() {
            let lam_ls = &rhs[n..];
            if lam_ls.iter().all(|v| v.is_finite()) && inf_norm(lam_ls) <= CONSTR_MULT_INIT_MAX {
                st.lam.copy_from_slice(lam_ls);
            }
        }
    }
    kkt.time += t.elapsed();
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn push_moves_the_point_inside_by_kappa_and_centres_a_narrow_interval() {
        // far from the bounds: unchanged
        assert_eq!(push(1e-2, 0.0, 10.0, 5.0), 5.0);
        // on the lower bound 0 of [0, 10]: κ max(|lo|, 1) = 0.01 inside
        assert_eq!(push(1e-2, 0.0, 10.0, 0.0), 0.01);
        // on the upper bound of [-∞, 200]: κ |hi| = 2 inside
        assert_eq!(push(1e-2, f64::NEG_INFINITY, 200.0, 300.0), 198.0);
        // an interval narrower than twice the push: κ (hi − lo) from either bound
        let v = push(0.4, 0.0, 1.0, 0.0);
        assert!((v - 0.4).abs() < 1e-15, "{v}");
        // relaxation outwards by 1e-8 relative (at least absolute)
        assert_eq!(relax(0.0, -1.0), -1e-8);
        assert!((relax(100.0, 1.0) - (100.0 + 1e-6)).abs() < 1e-12);
    }
}
