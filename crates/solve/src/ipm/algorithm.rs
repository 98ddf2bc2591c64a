//! The primal-dual barrier iteration after Wächter & Biegler 2006: least-squares initial
//! constraint multipliers, filter line search with second-order correction, a simplified
//! feasibility restoration, inertia correction, iterative refinement of the KKT solves, adaptive μ with a
//! KKT-error progress check; see docs/decisions/0002-solver.md.
//!
//! Problem seen by the iteration (all quantities scaled, see [`ScaledNlp`]):
//! variables w = (x, s) with slacks s for the inequality rows, bounds L <= w <= U, and
//! equality residuals r(w) = c(x) − (g for equality rows, s for inequality rows) = 0.
// Index loops over several parallel arrays are clearer than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use std::ops::ControlFlow;
use std::time::{Duration, Instant};

use crate::ipm::kkt::KktPattern;
use crate::ipm::lbfgs::{dot, Lbfgs, LowRankCorrection};
use crate::ipm::linsys::{Counted, Inertia, KktSolver, LinearSolverError, SolveCounts};
use crate::ipm::mu_oracle::choose_sigma;
use crate::ipm::ordering::{kkt_ordering, ordering_blocks};
use crate::ipm::scaled::ScaledNlp;
use crate::nlp::{validate_bounds, validate_structures, BlockStructure, EvalError, Nlp, Sparsity};
use crate::solver::{
    HessianMode, IterationRecord, MuGlobalisation, MuOracle, MuStrategy, SolveError, SolveResult,
    SolveStatus, SolverOptions,
};

const NO_SLACK: usize = usize::MAX;
/// IPOPT's s_max for the scaled optimality error.
const S_MAX: f64 = 100.0;
/// Barrier-subproblem tolerance factor κ_ε.
const KAPPA_EPS: f64 = 10.0;
/// Linear μ decrease factor κ_μ.
const KAPPA_MU: f64 = 0.2;
/// Superlinear μ decrease exponent θ_μ.
const THETA_MU: f64 = 1.5;
/// Safeguard factor κ_Σ for the bound multipliers.
const KAPPA_SIGMA: f64 = 1e10;
/// Armijo constant η_φ of the filter line search.
const ETA_PHI: f64 = 1e-8;
/// Filter margin on the constraint violation γ_θ.
const GAMMA_THETA: f64 = 1e-5;
/// Filter margin on the barrier function γ_φ.
const GAMMA_PHI: f64 = 1e-8;
/// Switching-condition constants δ, s_θ, s_φ.
const SWITCH_DELTA: f64 = 1.0;
const S_THETA: f64 = 1.1;
const S_PHI: f64 = 2.3;
/// Safety factor γ_α for the minimum step size.
const GAMMA_ALPHA: f64 = 0.05;
/// Second-order correction: at most this many corrections, each reducing θ by κ_soc.
const MAX_SOC: usize = 4;
const KAPPA_SOC: f64 = 0.99;
/// Adaptive μ: reference KKT errors kept in free mode, and the reduction required.
const FREE_MODE_REFS: usize = 4;
const FREE_MODE_RED: f64 = 0.9999;
/// Adaptive μ: fixed-mode μ as a fraction of the average complementarity.
const FIXED_MU_FACTOR: f64 = 0.8;
/// Iterations with μ at its floor before the exact Hessian takes over a limited-memory solve
/// (`SolverOptions::exact_hessian_tail`).
const EXACT_TAIL_AFTER: usize = 3;
/// Iterative refinement: at most this many steps, down to this relative residual.
const MAX_REFINE: usize = 10;
const REFINE_TOL: f64 = 1e-10;
/// KKT diagonal of a fixed variable (x_l = x_u), which keeps its step at zero.
const FIXED_DIAG: f64 = 1e20;
/// Least-squares constraint multipliers larger than this are discarded (IPOPT
/// `constr_mult_init_max`).
const CONSTR_MULT_INIT_MAX: f64 = 1000.0;
/// Constant regularisation of the constraint block (quasi-definiteness).
const DELTA_C: f64 = 1e-9;
/// First nonzero Hessian regularisation δ_w of a solve (IPOPT's δ̄_w⁰; the inertia
/// correction then follows IPOPT's rule with the three factors below).
const REG_FIRST: f64 = 1e-4;
/// Divisor of the last δ_w for the first nonzero trial of a later iteration (κ_w⁻ = 1/3).
const REG_DECREASE: f64 = 3.0;
/// Factor of δ_w after a failed trial before any iteration was regularised (κ̄_w⁺).
const REG_INCREASE_FIRST: f64 = 100.0;
/// Factor of δ_w after a failed trial once an iteration was regularised (κ_w⁺).
const REG_INCREASE: f64 = 8.0;
/// Inertia correction in the exact-Hessian tail of a hybrid solve: after a regularised
/// iteration the next one starts from δ_w_last/`REG_DECREASE` instead of 0 while that is at
/// least this large.
const REG_SKIP_ZERO_MIN: f64 = 1e-8;
/// A warm-started solve starts from δ_w_last/`REG_DECREASE` after a regularised iteration
/// only while its scaled optimality error is above this: far from a solution (a long descent
/// from a poor coarse optimum) the trial with 0 fails again; near one, the unregularised
/// Newton step is what converges fast.
const WARM_SKIP_ZERO_ERROR: f64 = 1e-2;

/// Centrality correctors (Gondzio 1996): products outside [β_min μ, β_max μ] are corrected.
const CORRECTOR_BETA_MIN: f64 = 0.1;
const CORRECTOR_BETA_MAX: f64 = 10.0;
/// A corrector aims at the step size min(1, CORRECTOR_AIM_FACTOR α + CORRECTOR_AIM_ADD).
const CORRECTOR_AIM_FACTOR: f64 = 2.0;
const CORRECTOR_AIM_ADD: f64 = 0.1;
/// A corrected direction is kept if its step size is at least this factor times the
/// previous one's.
const CORRECTOR_GAIN: f64 = 1.1;

/// Margin factor of the obj-constr-filter μ globalisation (IPOPT `filter_margin_fact`).
const MU_FILTER_MARGIN: f64 = 1e-5;
/// Largest barrier parameter of the adaptive strategy.
const MU_MAX: f64 = 1e5;

/// Full steps the watchdog takes before it returns to its starting point (IPOPT
/// `watchdog_trial_iter_max`).
const WATCHDOG_TRIAL_MAX: usize = 3;

/// Reference values of the filter line search at the point a step starts from: constraint
/// violation θ (1-norm, scaled), barrier objective φ and its directional derivative ∇φᵀd;
/// with the solve's bounds θ_min (switching condition) and θ_max (largest θ accepted).
#[derive(Clone, Copy)]
struct LsReference {
    theta: f64,
    phi: f64,
    gphi_d: f64,
    theta_min: f64,
    theta_max: f64,
}

impl LsReference {
    /// Filter acceptance of a trial point (θ, φ) at step size α (Wächter & Biegler 2006):
    /// None if rejected, else Some(whether the step passed the Armijo test of the
    /// switching condition, in which case the filter is not augmented).
    fn accepts(&self, alpha: f64, theta: f64, phi: f64, filter: &[(f64, f64)]) -> Option<bool> {
        if !phi.is_finite() || theta > self.theta_max {
            return None;
        }
        if filter.iter().any(|&(ft, fp)| theta >= ft && phi >= fp) {
            return None;
        }
        let switching = self.gphi_d < 0.0
            && alpha * (-self.gphi_d).powf(S_PHI) > SWITCH_DELTA * self.theta.powf(S_THETA);
        let armijo = phi <= self.phi + ETA_PHI * alpha * self.gphi_d;
        if switching && self.theta <= self.theta_min {
            return armijo.then_some(true);
        }
        if theta <= (1.0 - GAMMA_THETA) * self.theta || phi <= self.phi - GAMMA_PHI * self.theta {
            Some(switching && armijo)
        } else {
            None
        }
    }
}

/// What the watchdog keeps from the iteration where it started: the iterate, its search
/// direction and line-search references, so that it can return there.
struct Watchdog {
    st: State,
    dw: Vec<f64>,
    dlam: Vec<f64>,
    reference: LsReference,
    alpha_max: f64,
    alpha_min: f64,
    mu: f64,
    /// full steps taken so far without one acceptable to the watchdog's references
    trials: usize,
}

/// Iterate and workspace of one solve.
#[derive(Clone)]
struct State {
    n: usize,
    m: usize,
    big_n: usize,
    slack_of_row: Vec<usize>,
    row_of_slack: Vec<usize>,
    g_eq: Vec<f64>,
    wl: Vec<f64>,
    wu: Vec<f64>,
    has_l: Vec<bool>,
    has_u: Vec<bool>,
    w: Vec<f64>,
    lam: Vec<f64>,
    zl: Vec<f64>,
    zu: Vec<f64>,
    f: f64,
    grad: Vec<f64>,
    c: Vec<f64>,
    jv: Vec<f64>,
    hv: Vec<f64>,
}

impl State {
    fn residual(&self, w: &[f64], c: &[f64], r: &mut [f64]) {
        for i in 0..self.m {
            let k = self.slack_of_row[i];
            r[i] = if k == NO_SLACK {
                c[i] - self.g_eq[i]
            } else {
                c[i] - w[self.n + k]
            };
        }
    }

    /// ∇f + Aᵀλ over w (without the bound multipliers).
    fn grad_lag_no_z(&self, jac_rows: &[usize], jac_cols: &[usize], out: &mut [f64]) {
        out[..self.n].copy_from_slice(&self.grad);
        out[self.n..].iter_mut().for_each(|v| *v = 0.0);
        for k in 0..self.jv.len() {
            out[jac_cols[k]] += self.jv[k] * self.lam[jac_rows[k]];
        }
        for (k, &i) in self.row_of_slack.iter().enumerate() {
            out[self.n + k] -= self.lam[i];
        }
    }

    /// f + barrier terms at (f, w).
    fn barrier(&self, f: f64, w: &[f64], mu: f64) -> f64 {
        let mut b = f;
        for j in 0..self.big_n {
            if self.has_l[j] {
                b -= mu * (w[j] - self.wl[j]).ln();
            }
            if self.has_u[j] {
                b -= mu * (self.wu[j] - w[j]).ln();
            }
        }
        b
    }

    fn complementarity(&self, mu: f64) -> f64 {
        let mut e = 0.0f64;
        for j in 0..self.big_n {
            if self.has_l[j] {
                e = e.max(((self.w[j] - self.wl[j]) * self.zl[j] - mu).abs());
            }
            if self.has_u[j] {
                e = e.max(((self.wu[j] - self.w[j]) * self.zu[j] - mu).abs());
            }
        }
        e
    }

    /// Primal-dual error of the barrier problem at μ (IPOPT's `curr_primal_dual_system_error`
    /// in the mean-squared form): ‖r‖²/m + ‖∇L‖²/N + mean of (z (w − bound) − μ)², with the
    /// Lagrangian gradient `gl` (bound multipliers included) and residual `r` given.
    fn pd_barrier_error(&self, gl: &[f64], r: &[f64], mu: f64) -> f64 {
        let (pr, du) = self.mean_squared_infeasibilities(gl, r);
        pr + du + self.mean_squared_complementarity(mu)
    }

    /// Mean squared primal infeasibility ‖r‖²/m and dual infeasibility ‖∇L‖²/N.
    fn mean_squared_infeasibilities(&self, gl: &[f64], r: &[f64]) -> (f64, f64) {
        (
            r.iter().map(|v| v * v).sum::<f64>() / self.m.max(1) as f64,
            gl.iter().map(|v| v * v).sum::<f64>() / self.big_n.max(1) as f64,
        )
    }

    /// Mean and mean square of the complementarity products (w + α_p dw − bound)(z + α_d dz)
    /// over all bounds after a primal step α_p dw and a bound-multiplier step α_d dz.
    fn complementarity_after_step(
        &self,
        dw: &[f64],
        dzl: &[f64],
        dzu: &[f64],
        ap: f64,
        ad: f64,
    ) -> (f64, f64) {
        let (mut s, mut s2, mut cnt) = (0.0, 0.0, 0usize);
        for j in 0..self.big_n {
            if self.has_l[j] {
                let p = (self.w[j] + ap * dw[j] - self.wl[j]) * (self.zl[j] + ad * dzl[j]);
                s += p;
                s2 += p * p;
                cnt += 1;
            }
            if self.has_u[j] {
                let p = (self.wu[j] - self.w[j] - ap * dw[j]) * (self.zu[j] + ad * dzu[j]);
                s += p;
                s2 += p * p;
                cnt += 1;
            }
        }
        let c = cnt.max(1) as f64;
        (s / c, s2 / c)
    }

    /// A copy of the iterate without the Hessian values (the copies kept by soft
    /// restoration and the watchdog never need them: the Hessian is evaluated again at
    /// every accepted point before it is used).
    fn clone_without_hessian(&mut self) -> State {
        let hv = std::mem::take(&mut self.hv);
        let copy = self.clone();
        self.hv = hv;
        copy
    }

    /// ∇L over w with the bound multipliers, fixed variables zeroed.
    fn grad_lag(&self, jac_rows: &[usize], jac_cols: &[usize], fixed_x: &[bool], out: &mut [f64]) {
        self.grad_lag_no_z(jac_rows, jac_cols, out);
        for j in 0..self.big_n {
            out[j] += self.zu[j] - self.zl[j];
        }
        for (o, &f) in out[..self.n].iter_mut().zip(fixed_x) {
            if f {
                *o = 0.0;
            }
        }
    }

    /// Mean squared shifted complementarity (z_L (w − w_L) − μ)², (z_U (w_U − w) − μ)² over
    /// all bounds.
    fn mean_squared_complementarity(&self, mu: f64) -> f64 {
        let (mut s, mut cnt) = (0.0, 0usize);
        for j in 0..self.big_n {
            if self.has_l[j] {
                s += ((self.w[j] - self.wl[j]) * self.zl[j] - mu).powi(2);
                cnt += 1;
            }
            if self.has_u[j] {
                s += ((self.wu[j] - self.w[j]) * self.zu[j] - mu).powi(2);
                cnt += 1;
            }
        }
        if cnt == 0 {
            0.0
        } else {
            s / cnt as f64
        }
    }

    fn average_complementarity(&self) -> f64 {
        let (mut s, mut cnt) = (0.0, 0usize);
        for j in 0..self.big_n {
            if self.has_l[j] {
                s += (self.w[j] - self.wl[j]) * self.zl[j];
                cnt += 1;
            }
            if self.has_u[j] {
                s += (self.wu[j] - self.w[j]) * self.zu[j];
                cnt += 1;
            }
        }
        if cnt == 0 {
            0.0
        } else {
            s / cnt as f64
        }
    }
}

fn inf_norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |a, x| a.max(x.abs()))
}

fn one_norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x.abs()).sum()
}

/// Largest α in (0, 1] keeping v + α dv − lo >= (1 − τ)(v − lo) and hi − v − α dv likewise.
fn fraction_to_boundary(st: &State, w: &[f64], dw: &[f64], tau: f64) -> f64 {
    let mut a = 1.0f64;
    for j in 0..st.big_n {
        if st.has_l[j] && dw[j] < 0.0 {
            a = a.min(-tau * (w[j] - st.wl[j]) / dw[j]);
        }
        if st.has_u[j] && dw[j] > 0.0 {
            a = a.min(tau * (st.wu[j] - w[j]) / dw[j]);
        }
    }
    a
}

fn dual_fraction_to_boundary(st: &State, dzl: &[f64], dzu: &[f64], tau: f64) -> f64 {
    let mut a = 1.0f64;
    for j in 0..st.big_n {
        if st.has_l[j] && dzl[j] < 0.0 {
            a = a.min(-tau * st.zl[j] / dzl[j]);
        }
        if st.has_u[j] && dzu[j] < 0.0 {
            a = a.min(-tau * st.zu[j] / dzu[j]);
        }
    }
    a
}

/// Objective at the trial point wt = w + α d (slacks included in `wt`), with the constraint
/// values written into `ct`.
fn evaluate_trial(
    prob: &mut ScaledNlp,
    w: &[f64],
    alpha: f64,
    d: &[f64],
    wt: &mut [f64],
    ct: &mut [f64],
) -> Result<f64, EvalError> {
    for ((t, &x), &dx) in wt.iter_mut().zip(w).zip(d) {
        *t = x + alpha * dx;
    }
    let x = &wt[..prob.nlp.n()];
    let f = prob.objective(x)?;
    prob.constraints(x, ct)?;
    Ok(f)
}

/// Fiacco–McCormick decrease of μ: min(κ_μ μ, μ^θ_μ), not below `floor`.
fn monotone_decrease(mu: f64, floor: f64) -> f64 {
    floor.max((KAPPA_MU * mu).min(mu.powf(THETA_MU)))
}

/// μ on entering the fixed mode of the adaptive strategy: a fraction of the average
/// complementarity (IPOPT `adaptive_mu_monotone_init_factor`).
fn fixed_mode_mu(st: &State, floor: f64) -> f64 {
    (FIXED_MU_FACTOR * st.average_complementarity()).clamp(floor, MU_MAX)
}

/// Right-hand side of the condensed KKT system at barrier parameter μ: first block
/// −(∇f + Jᵀλ − μ/(x−L) + μ/(U−x)) (zero for fixed variables), then −r on rows without a
/// slack and −r − r_s/σ on slack rows; `r_s` receives the slack residuals −λ + barrier
/// terms. Affine in μ. With `targets` (t_L, t_U), bound j's complementarity target is
/// μ + t_L[j] (μ + t_U[j]) instead of μ (centrality correctors).
#[allow(clippy::too_many_arguments)]
fn newton_rhs(
    st: &State,
    mu: f64,
    targets: Option<(&[f64], &[f64])>,
    r: &[f64],
    jac_rows: &[usize],
    jac_cols: &[usize],
    fixed_x: &[bool],
    sigma: &[f64],
    rhs: &mut [f64],
    r_s: &mut [f64],
) {
    let n = st.n;
    rhs[..n].copy_from_slice(&st.grad);
    for k in 0..st.jv.len() {
        rhs[jac_cols[k]] += st.jv[k] * st.lam[jac_rows[k]];
    }
    for j in 0..st.big_n {
        let (ml, mu_u) = match targets {
            Some((tl, tu)) => (mu + tl[j], mu + tu[j]),
            None => (mu, mu),
        };
        let mut b = 0.0;
        if st.has_l[j] {
            b -= ml / (st.w[j] - st.wl[j]);
        }
        if st.has_u[j] {
            b += mu_u / (st.wu[j] - st.w[j]);
        }
        if j < n {
            rhs[j] = if fixed_x[j] { 0.0 } else { -(rhs[j] + b) };
        } else {
            r_s[j - n] = -st.lam[st.row_of_slack[j - n]] + b;
        }
    }
    for (i, &ri) in r.iter().enumerate() {
        let k = st.slack_of_row[i];
        rhs[n + i] = if k == NO_SLACK {
            -ri
        } else {
            -ri - r_s[k] / sigma[n + k].max(1e-20)
        };
    }
}

/// The primal-dual step (dw with slack steps, dlam) from the solution `sol` of the condensed
/// KKT system and the slack residuals `r_s` of its right-hand side.
fn step_from_solution(
    st: &State,
    sol: &[f64],
    r_s: &[f64],
    fixed_x: &[bool],
    sigma: &[f64],
    dw: &mut [f64],
    dlam: &mut [f64],
) {
    let n = st.n;
    dw[..n].copy_from_slice(&sol[..n]);
    for j in 0..n {
        if fixed_x[j] {
            dw[j] = 0.0;
        }
    }
    dlam.copy_from_slice(&sol[n..]);
    for (k, &i) in st.row_of_slack.iter().enumerate() {
        dw[n + k] = (dlam[i] - r_s[k]) / sigma[n + k].max(1e-20);
    }
}

/// out = a + σ (b − a): the step for μ = σ·avg from the steps `a` (μ = 0) and `b` (μ = avg),
/// the KKT right-hand side being affine in μ.
fn combine(a: &[f64], b: &[f64], sigma: f64, out: &mut [f64]) {
    for ((o, &x), &y) in out.iter_mut().zip(a).zip(b) {
        *o = x + sigma * (y - x);
    }
}

/// ∇φ_μ(w)ᵀ dw for the barrier function φ_μ = f − μ Σ ln(slacks to bounds).
fn barrier_directional_derivative(st: &State, mu: f64, dw: &[f64]) -> f64 {
    let mut g = dot(&st.grad, &dw[..st.n]);
    for j in 0..st.big_n {
        if st.has_l[j] {
            g -= mu / (st.w[j] - st.wl[j]) * dw[j];
        }
        if st.has_u[j] {
            g += mu / (st.wu[j] - st.w[j]) * dw[j];
        }
    }
    g
}

/// Primal-dual steps of the bound multipliers for the primal step `dw`; with `targets`
/// (t_L, t_U) the complementarity targets are μ + t_L[j], μ + t_U[j] (centrality
/// correctors), as in [`newton_rhs`].
fn bound_multiplier_steps(
    st: &State,
    mu: f64,
    targets: Option<(&[f64], &[f64])>,
    dw: &[f64],
    dzl: &mut [f64],
    dzu: &mut [f64],
) {
    for j in 0..st.big_n {
        dzl[j] = if st.has_l[j] {
            let sl = st.w[j] - st.wl[j];
            let d = mu / sl - st.zl[j] - st.zl[j] / sl * dw[j];
            targets.map_or(d, |(tl, _)| d + tl[j] / sl)
        } else {
            0.0
        };
        dzu[j] = if st.has_u[j] {
            let su = st.wu[j] - st.w[j];
            let d = mu / su - st.zu[j] + st.zu[j] / su * dw[j];
            targets.map_or(d, |(_, tu)| d + tu[j] / su)
        } else {
            0.0
        };
    }
}

/// Complementarity targets of Gondzio's centrality correction for the step `dw`, `dzl`,
/// `dzu` taken with the enlarged step sizes (ap, ad): each trial product
/// (w + ap dw − L)(z_L + ad dz_L) is moved into [β_min μ, β_max μ] by adding the difference to
/// that bound's target (a decrease by at most β_max μ). Returns the number of products
/// outside the box.
#[allow(clippy::too_many_arguments)]
fn centrality_targets(
    st: &State,
    mu: f64,
    dw: &[f64],
    dzl: &[f64],
    dzu: &[f64],
    ap: f64,
    ad: f64,
    tl: &mut [f64],
    tu: &mut [f64],
) -> usize {
    let (lo, hi) = (CORRECTOR_BETA_MIN * mu, CORRECTOR_BETA_MAX * mu);
    let shift = |v: f64| -> f64 {
        if v < lo {
            lo - v
        } else if v > hi {
            (hi - v).max(-hi)
        } else {
            0.0
        }
    };
    let mut outside = 0usize;
    for j in 0..st.big_n {
        if st.has_l[j] {
            let v = (st.w[j] + ap * dw[j] - st.wl[j]) * (st.zl[j] + ad * dzl[j]);
            let d = shift(v);
            if d != 0.0 {
                outside += 1;
                tl[j] += d;
            }
        }
        if st.has_u[j] {
            let v = (st.wu[j] - st.w[j] - ap * dw[j]) * (st.zu[j] + ad * dzu[j]);
            let d = shift(v);
            if d != 0.0 {
                outside += 1;
                tu[j] += d;
            }
        }
    }
    outside
}

/// res = b − K_true x for the KKT matrix K_reg (lower CSC values `vals`) whose constraint
/// block carries the extra regularisation −diag(`d_c_reg`): K_true = K_reg + diag(0, d_c_reg).
/// Several systems at once, in one pass over the matrix: slot s of `res` (column-major,
/// `pattern.dim` rows) gets column `cols[s]` of `b` and `x`.
fn kkt_residual(
    pattern: &KktPattern,
    vals: &[f64],
    d_c_reg: &[f64],
    cols: &[usize],
    b: &[f64],
    x: &[f64],
    res: &mut [f64],
) {
    let dim = pattern.dim;
    for (s, &c) in cols.iter().enumerate() {
        res[s * dim..(s + 1) * dim].copy_from_slice(&b[c * dim..(c + 1) * dim]);
    }
    for j in 0..dim {
        for p in pattern.col_ptr[j]..pattern.col_ptr[j + 1] {
            let i = pattern.row_idx[p];
            let v = vals[p];
            for (s, &c) in cols.iter().enumerate() {
                let (rs, xc) = (s * dim, c * dim);
                res[rs + i] -= v * x[xc + j];
                if i != j {
                    res[rs + j] -= v * x[xc + i];
                }
            }
        }
    }
    for (s, &c) in cols.iter().enumerate() {
        let (rs, xc) = (s * dim + pattern.n, c * dim + pattern.n);
        for (k, d) in d_c_reg.iter().enumerate() {
            res[rs + k] -= d * x[xc + k];
        }
    }
}

/// Iterative refinement of the `ncols` solutions `x` of K_true x = b (column-major) from
/// the factorisation of K_reg (see [`kkt_residual`]): each column until its residual is
/// below `REFINE_TOL` relative to its right-hand side or stops shrinking, the columns still
/// refining corrected together in one block solve per step. `res` is scratch.
#[allow(clippy::too_many_arguments)]
fn refine_solutions(
    linear: &mut dyn KktSolver,
    pattern: &KktPattern,
    vals: &[f64],
    d_c_reg: &[f64],
    b: &[f64],
    x: &mut [f64],
    ncols: usize,
    res: &mut Vec<f64>,
    debug: bool,
) -> Result<(), LinearSolverError> {
    let dim = pattern.dim;
    res.resize(ncols * dim, 0.0);
    let bnorm: Vec<f64> = b.chunks(dim).map(|c| inf_norm(c).max(1.0)).collect();
    let mut last = vec![f64::INFINITY; ncols];
    let mut active: Vec<usize> = (0..ncols).collect();
    for _ in 0..MAX_REFINE {
        kkt_residual(pattern, vals, d_c_reg, &active, b, x, res);
        // keep the columns that still improve, their residuals packed to the front
        let mut kept = 0;
        for s in 0..active.len() {
            let c = active[s];
            let rn = inf_norm(&res[s * dim..(s + 1) * dim]);
            if debug {
                eprintln!("    refine {c}: |res| = {rn:.3e}, |b| = {:.3e}", bnorm[c]);
            }
            if rn <= REFINE_TOL * bnorm[c] || rn >= 0.9 * last[c] {
                continue;
            }
            last[c] = rn;
            if kept != s {
                res.copy_within(s * dim..(s + 1) * dim, kept * dim);
            }
            active[kept] = c;
            kept += 1;
        }
        active.truncate(kept);
        if kept == 0 {
            break;
        }
        linear.solve_many(&mut res[..kept * dim], kept)?;
        for (s, &c) in active.iter().enumerate() {
            let xc = &mut x[c * dim..(c + 1) * dim];
            for (xi, d) in xc.iter_mut().zip(&res[s * dim..(s + 1) * dim]) {
                *xi += d;
            }
        }
    }
    Ok(())
}

/// Largest number of feasibility-restoration steps after one failed line search.
const MAX_RESTORATION_STEPS: usize = 40;
/// Restoration ends once the violation is below this fraction of its value at entry
/// (IPOPT `required_infeasibility_reduction`).
const RESTORATION_REDUCTION: f64 = 0.9;
/// Relative elastic (Levenberg–Marquardt) weight ε₀ of the restoration steps: the
/// constraint block of their KKT matrix is −ε I with ε = ε₀ ‖r‖∞ at entry, so a step
/// minimises ‖J d + r‖² / (2ε) plus the barrier and proximal terms and exists even where
/// the linearised constraints and bounds conflict.
const RESTORATION_ELASTIC: f64 = 1e-3;

/// Buffers and fixed data that the feasibility restoration shares with the main iteration.
struct Restoration<'a> {
    pattern: &'a KktPattern,
    fixed_x: &'a [bool],
    kvals: &'a mut [f64],
    diag_x: &'a mut [f64],
    d_c: &'a mut [f64],
    rhs: &'a mut [f64],
    zero_h: &'a [f64],
}

/// Simplified feasibility restoration after a failed filter line search: elastic
/// Gauss–Newton steps that reduce θ = ‖r‖₁ (objective replaced by the primal barrier μ Σ ln
/// of the slacks to the bounds plus a proximal term √μ/2 ‖dw‖², zero multipliers), Armijo backtracking on θ, until θ
/// is below 0.9 θ at entry and the point is acceptable to the filter. Returns the restored
/// (w, c, f), or `None` when θ cannot be reduced (a stationary point of the infeasibility).
#[allow(clippy::too_many_arguments)]
fn restore_feasibility(
    prob: &mut ScaledNlp,
    st: &State,
    mu: f64,
    filter: &[(f64, f64)],
    linear: &mut dyn KktSolver,
    buf: Restoration,
    lin_time: &mut Duration,
    factorizations: &mut usize,
    debug: bool,
) -> Option<(Vec<f64>, Vec<f64>, f64)> {
    let (n, m, big_n) = (st.n, st.m, st.big_n);
    let mut w = st.w.clone();
    let mut c = st.c.clone();
    let mut jv = st.jv.clone();
    let mut r = vec![0.0; m];
    st.residual(&w, &c, &mut r);
    let theta_entry = one_norm(&r);
    let mut theta = theta_entry;
    // IPOPT starts its restoration phase with μ_R = max(μ, ‖c‖∞) and ζ = √μ_R
    let mu_r = mu.max(inf_norm(&r));
    let zeta = mu_r.sqrt();
    // elastic weight ε = ε₀ ‖r‖∞ at entry: the penalty gradient r/ε then has entries up to
    // 1/ε₀ whatever the size of the violation (like IPOPT's ℓ₁ penalty ρ = 1000), so the
    // barrier μ_R Σ ln(slack) cannot outweigh it once r is small
    let eps = RESTORATION_ELASTIC * inf_norm(&r).max(f64::MIN_POSITIVE);
    let mut sigma = vec![0.0; big_n];
    let mut dw = vec![0.0; big_n];
    let mut wt = vec![0.0; big_n];
    let mut ct = vec![0.0; m];
    let mut rt = vec![0.0; m];
    let mut bgrad = vec![0.0; big_n];
    for _ in 0..MAX_RESTORATION_STEPS {
        // primal barrier μ Σ ln(slack to bound): gradient and Hessian μ / slack²
        for j in 0..big_n {
            let (mut sg, mut b) = (0.0, 0.0);
            if st.has_l[j] {
                let sl = w[j] - st.wl[j];
                sg += mu_r / (sl * sl);
                b -= mu_r / sl;
            }
            if st.has_u[j] {
                let su = st.wu[j] - w[j];
                sg += mu_r / (su * su);
                b += mu_r / su;
            }
            sigma[j] = sg + zeta;
            bgrad[j] = b;
        }
        for j in 0..n {
            buf.diag_x[j] = if buf.fixed_x[j] { FIXED_DIAG } else { sigma[j] };
        }
        for i in 0..m {
            let k = st.slack_of_row[i];
            buf.d_c[i] = if k == NO_SLACK {
                eps
            } else {
                1.0 / sigma[n + k] + eps
            };
        }
        buf.pattern
            .assemble(buf.kvals, buf.zero_h, &jv, buf.diag_x, buf.d_c);
        let t = Instant::now();
        let ok = linear.factor(buf.kvals).is_ok();
        *factorizations += 1;
        for j in 0..n {
            buf.rhs[j] = if buf.fixed_x[j] { 0.0 } else { -bgrad[j] };
        }
        for i in 0..m {
            let k = st.slack_of_row[i];
            buf.rhs[n + i] = if k == NO_SLACK {
                -r[i]
            } else {
                -r[i] - bgrad[n + k] / sigma[n + k]
            };
        }
        let solved = ok && linear.solve(buf.rhs).is_ok();
        if debug && !solved {
            eprintln!("    restoration: KKT factorisation or solve failed");
        }
        *lin_time += t.elapsed();
        if !solved || buf.rhs.iter().any(|v| !v.is_finite()) {
            return None;
        }
        for j in 0..n {
            dw[j] = if buf.fixed_x[j] { 0.0 } else { buf.rhs[j] };
        }
        for (k, &i) in st.row_of_slack.iter().enumerate() {
            dw[n + k] = (buf.rhs[n + i] - bgrad[n + k]) / sigma[n + k];
        }
        // merit: the function whose Gauss–Newton model the step minimises,
        // ‖r‖² / (2 ε) + μ_R barrier
        let sq = |r: &[f64]| r.iter().map(|v| v * v).sum::<f64>() / (2.0 * eps);
        let barrier = |w: &[f64]| -> f64 {
            let mut b = 0.0;
            for j in 0..big_n {
                if st.has_l[j] {
                    b -= mu_r * (w[j] - st.wl[j]).ln();
                }
                if st.has_u[j] {
                    b -= mu_r * (st.wu[j] - w[j]).ln();
                }
            }
            b
        };
        let merit0 = sq(&r) + barrier(&w);
        let mut alpha = fraction_to_boundary(st, &w, &dw, 0.99);
        let mut accepted = None;
        for _ in 0..30 {
            for j in 0..big_n {
                wt[j] = w[j] + alpha * dw[j];
            }
            if prob.constraints(&wt[..n], &mut ct).is_ok() {
                st.residual(&wt, &ct, &mut rt);
                let theta_t = one_norm(&rt);
                let merit = sq(&rt) + barrier(&wt);
                if merit.is_finite() && merit < merit0 {
                    accepted = Some(theta_t);
                    break;
                }
            }
            alpha *= 0.5;
        }
        if debug {
            eprintln!(
                "    restoration: theta {theta:.3e} -> {:?} (alpha {alpha:.2e}, |dw| {:.2e}, entry {theta_entry:.3e})",
                accepted,
                inf_norm(&dw)
            );
        }
        let theta_t = accepted?;
        w.copy_from_slice(&wt);
        c.copy_from_slice(&ct);
        r.copy_from_slice(&rt);
        theta = theta_t;
        let f = prob.objective(&w[..n]).ok()?;
        let phi = st.barrier(f, &w, mu);
        let in_filter = filter.iter().any(|&(ft, fp)| theta >= ft && phi >= fp);
        if theta <= RESTORATION_REDUCTION * theta_entry && !in_filter {
            return Some((w, c, f));
        }
        prob.jacobian(&w[..n], &mut jv).ok()?;
    }
    None
}

/// Symbolic analysis of the KKT `pattern` (Lagrangian Hessian pattern `hess`) by `linear`,
/// ordered by chain dissection along `blocks` when given.
fn analyse_kkt(
    linear: &mut dyn KktSolver,
    blocks: Option<&BlockStructure>,
    hess: &Sparsity,
    pattern: &KktPattern,
) -> Result<(), SolveError> {
    let ordering = kkt_ordering(blocks, hess, pattern);
    linear
        .analyse(
            pattern.dim,
            &pattern.col_ptr,
            &pattern.row_idx,
            ordering.as_deref(),
        )
        .map_err(|e| SolveError::Backend(e.to_string()))
}

/// Runs the interior-point method on `nlp` with the given KKT linear solver.
pub fn solve(
    nlp: &dyn Nlp,
    options: &SolverOptions,
    observer: &mut dyn FnMut(&IterationRecord) -> ControlFlow<()>,
    linear: &mut dyn KktSolver,
) -> Result<SolveResult, SolveError> {
    let start = Instant::now();
    check_options(options)?;
    let mut counted = Counted::new(linear);
    let linear = &mut counted;
    // solve counts when the exact Hessian took over from L-BFGS
    let mut counts_at_switch = SolveCounts::default();
    let (n, m) = (nlp.n(), nlp.m());
    let bounds = validate_bounds(nlp)?;
    let structures = validate_structures(nlp)?;
    let mut exact = matches!(options.hessian, HessianMode::Exact);
    let mut prob = ScaledNlp::new(nlp, structures.jacobian, structures.hessian);

    // ---- initial point, scaling, slacks --------------------------------------------------
    let mut x0 = vec![0.0; n];
    nlp.initial_point(&mut x0);
    if let Some(i) = x0.iter().position(|v| !v.is_finite()) {
        return Err(SolveError::InitialEvaluation(EvalError::Failed {
            function: crate::nlp::NlpFunction::Objective,
            reason: format!("initial point entry {i} is {}", x0[i]),
        }));
    }
    let relax = |v: f64, sign: f64| v + sign * 1e-8 * v.abs().max(1.0);
    let push = |lo: f64, hi: f64, v: f64| -> f64 {
        let kappa = options.bound_push;
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
    };
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
        x0[j] = push(xl[j], xu[j], x0[j]);
        if bounds.x_l[j] == bounds.x_u[j] {
            // fixed variable: kept at its value, without bounds or multipliers
            fixed_x[j] = true;
            xl[j] = f64::NEG_INFINITY;
            xu[j] = f64::INFINITY;
            x0[j] = bounds.x_l[j];
        }
    }
    if options.nlp_scaling {
        prob.compute_gradient_scaling(&x0, options.nlp_scaling_max_gradient)
            .map_err(SolveError::InitialEvaluation)?;
    }
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
    let ni = row_of_slack.len();
    let big_n = n + ni;
    let mut wl = xl.clone();
    let mut wu = xu.clone();
    for &i in &row_of_slack {
        let s = prob.con_scale[i];
        let (lo, hi) = (bounds.g_l[i] * s, bounds.g_u[i] * s);
        wl.push(if lo.is_finite() { relax(lo, -1.0) } else { lo });
        wu.push(if hi.is_finite() { relax(hi, 1.0) } else { hi });
    }
    let has_l: Vec<bool> = wl.iter().map(|v| v.is_finite()).collect();
    let has_u: Vec<bool> = wu.iter().map(|v| v.is_finite()).collect();

    let mut st = State {
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
    st.w[..n].copy_from_slice(&x0);
    let init = |e| SolveError::InitialEvaluation(e);
    st.f = prob.objective(&x0).map_err(init)?;
    prob.gradient(&x0, &mut st.grad).map_err(init)?;
    prob.constraints(&x0, &mut st.c).map_err(init)?;
    prob.jacobian(&x0, &mut st.jv).map_err(init)?;
    for (k, &i) in st.row_of_slack.clone().iter().enumerate() {
        st.w[n + k] = push(st.wl[n + k], st.wu[n + k], st.c[i]);
    }
    // bound multipliers: 1 (IPOPT), or on the central path of μ_init for a warm start
    let z_init = |gap: f64| {
        if options.warm_start {
            options.mu_init / gap.max(f64::MIN_POSITIVE)
        } else {
            1.0
        }
    };
    for j in 0..big_n {
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
    if exact {
        let (w, lam) = (st.w[..n].to_vec(), st.lam.clone());
        prob.hessian(&w, 1.0, &lam, &mut st.hv).map_err(init)?;
    }

    // ---- KKT pattern and symbolic analysis ---------------------------------------------
    // In limited-memory mode the Hessian entries stay zero. Without a chain ordering they
    // are kept in the pattern anyway: minimum degree on the pattern with the Lagrangian
    // Hessian's structure halves the factor of the gait KKT (51 → 25 million entries at 50
    // intervals); the chain dissection does best without them (14.7 million; decision 0002).
    let mut lin_time = Duration::ZERO;
    let t = Instant::now();
    let blocks = ordering_blocks(nlp, options.kkt_ordering);
    let mut pattern = if !exact && blocks.is_some() {
        KktPattern::new(n, m, &prob.jac, &Sparsity::default())
    } else {
        KktPattern::new(n, m, &prob.jac, &prob.hess)
    };
    analyse_kkt(linear, blocks.as_ref(), &prob.hess, &pattern)?;
    let time_symbolic = t.elapsed();
    lin_time += time_symbolic;

    // ---- workspaces ----------------------------------------------------------------------
    let dim = pattern.dim;
    let mut kvals = vec![0.0; pattern.nnz()];
    let mut diag_x = vec![0.0; n];
    let mut d_c = vec![0.0; m];
    let mut sigma = vec![0.0; big_n];
    let mut rhs = vec![0.0; dim];
    let mut r = vec![0.0; m];
    let mut r_s = vec![0.0; ni];
    let mut gl = vec![0.0; big_n];
    let mut dw = vec![0.0; big_n];
    let mut dlam = vec![0.0; m];
    let mut dzl = vec![0.0; big_n];
    let mut dzu = vec![0.0; big_n];
    let mut wt = vec![0.0; big_n];
    let mut ct = vec![0.0; m];
    // centrality correctors: complementarity targets beyond μ and the trial direction
    let corr_len = if options.centrality_correctors > 0 {
        big_n
    } else {
        0
    };
    let (mut tl, mut tu) = (vec![0.0; corr_len], vec![0.0; corr_len]);
    let (mut tl_c, mut tu_c) = (vec![0.0; corr_len], vec![0.0; corr_len]);
    let (mut dw_c, mut dzl_c, mut dzu_c) = (
        vec![0.0; corr_len],
        vec![0.0; corr_len],
        vec![0.0; corr_len],
    );
    let mut dlam_c = vec![0.0; if corr_len > 0 { m } else { 0 }];
    let mut correctors_kept = 0usize;
    let mut rt = vec![0.0; m];
    let mut lbfgs = match options.hessian {
        HessianMode::LimitedMemory { history } => Some(Lbfgs::new(history)),
        HessianMode::Exact => None,
    };
    // L-BFGS works in the space of the variables that appear nonlinearly (a nonzero
    // Hessian row or column), as IPOPT's `hessian_approximation_space = nonlinear-variables`
    // with the list CasADi passes: linear variables get no B₀ = σI curvature.
    let nonlinear: Vec<bool> = {
        let mut nl = vec![false; n];
        for k in 0..prob.hess.nnz() {
            nl[prob.hess.rows[k]] = true;
            nl[prob.hess.cols[k]] = true;
        }
        nl
    };
    let mut prev_x = vec![0.0; n];
    let mut prev_grad_lag = vec![0.0; n];
    let mut tmp_n = vec![0.0; n];
    // L-BFGS pair (s, y) of the last step, restricted to the nonlinear variables
    let (mut s_pair, mut y_pair) = (vec![0.0; n], vec![0.0; n]);
    let delta_c = DELTA_C;
    let debug = options.print_level >= 3;
    let mut b_save_buf = vec![0.0; dim];
    let mut res_buf = vec![0.0; dim];
    // regularisation δ_c on each constraint row (removed again by iterative refinement)
    let d_c_reg_buf = vec![delta_c; m];
    let mut factorizations = 0usize;
    // numeric factorisations of the main iterations (not the restoration phase's)
    let mut factor_time = Duration::ZERO;
    let mut restorations = 0usize;
    let mut soft_steps = 0usize;
    let mut watchdog: Option<Watchdog> = None;
    let mut shortened_steps = 0usize;
    let mut watchdog_starts = 0usize;
    let mut watchdog_returns = 0usize;
    let zero_h = vec![0.0; prob.hess.nnz()];

    // ---- least-squares constraint multipliers (IPOPT's initialisation) -------------------
    // [I Aᵀ; A 0] (d, λ) = (−(∇f − z_L + z_U), 0) over w = (x, s), slacks condensed.
    {
        diag_x.iter_mut().for_each(|v| *v = 1.0);
        for i in 0..m {
            d_c[i] = if st.slack_of_row[i] == NO_SLACK {
                DELTA_C
            } else {
                1.0 + DELTA_C
            };
        }
        pattern.assemble(&mut kvals, &zero_h, &st.jv, &diag_x, &d_c);
        let t = Instant::now();
        let inertia = linear
            .factor(&kvals)
            .map_err(|e| SolveError::Backend(e.to_string()))?;
        factorizations += 1;
        if inertia.positive == n && inertia.negative == m {
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
            if linear.solve(&mut rhs).is_ok() {
                let lam_ls = &rhs[n..];
                if lam_ls.iter().all(|v| v.is_finite()) && inf_norm(lam_ls) <= CONSTR_MULT_INIT_MAX
                {
                    st.lam.copy_from_slice(lam_ls);
                }
            }
        }
        lin_time += t.elapsed();
        if exact && st.lam.iter().any(|&v| v != 0.0) {
            let (w, lam) = (st.w[..n].to_vec(), st.lam.clone());
            prob.hessian(&w, 1.0, &lam, &mut st.hv).map_err(init)?;
        }
    }

    let mut mu = options.mu_init;
    let mut tau;
    let jac_rows = prob.jac.rows.clone();
    let jac_cols = prob.jac.cols.clone();
    // filter line search state
    let mut filter: Vec<(f64, f64)> = Vec::new();
    let mut filter_mu = f64::NAN;
    let mut theta_max = f64::INFINITY;
    let mut theta_min = 0.0f64;
    let mut soc_rhs_r = vec![0.0; m];
    let mut dw_soc = vec![0.0; big_n];
    let mut dlam_soc = vec![0.0; m];
    let mut delta_w_last = 0.0f64;
    // whether the previous iteration's KKT matrix needed δ_w > 0
    let mut regularised_last = false;
    let mut log: Vec<IterationRecord> = Vec::new();
    let mut acceptable_count = 0usize;
    let mut ls_failures = 0usize;
    let want_adaptive = matches!(options.mu_strategy, MuStrategy::Adaptive);
    // free (probing) mode of the adaptive μ strategy; false: monotone (fixed) mode
    let mut adaptive = want_adaptive;
    // KKT errors of the last free-mode iterations (IPOPT `adaptive_mu_globalization =
    // kkt-error`, 4 reference values, reduction factor 0.9999)
    let mut free_refs: Vec<f64> = Vec::new();
    let globalisation = options.mu_globalisation_in_effect();
    let oracle = options.mu_oracle;
    // steps of the quality-function oracle for μ = 0 and μ = average complementarity
    // (also the steps solved with the limited-memory correction)
    let buf = |len: usize| vec![0.0; len];
    // right-hand sides and slack residuals of those steps, and the block they are solved in
    let (mut early_rhs, mut early_rs, mut early_block) = (Vec::new(), Vec::new(), Vec::new());
    let (mut dw_aff, mut dw_avg) = (buf(big_n), buf(big_n));
    let (mut dlam_aff, mut dlam_avg) = (buf(m), buf(m));
    // (objective, θ) of the accepted free-mode iterates (obj-constr-filter globalisation)
    let mut mu_filter: Vec<(f64, f64)> = Vec::new();
    let status: SolveStatus;
    let mut iter = 0usize;
    let mut last_rec = IterationRecord::default();
    // the last accepted step was at round-off level (IPOPT's tiny-step flag)
    let mut tiny_step = false;
    // iterations with μ at its floor, and where the exact Hessian took over (exact tail)
    let mut floor_iters = 0usize;
    let mut exact_from: Option<usize> = None;

    let mut factorizations_before = factorizations;
    loop {
        // ---- optimality error --------------------------------------------------------------
        st.residual(&st.w, &st.c, &mut r);
        st.grad_lag(&prob.jac.rows, &prob.jac.cols, &fixed_x, &mut gl);
        let inf_du = inf_norm(&gl);
        if debug {
            let (jg, _) = gl.iter().enumerate().fold((0, 0.0f64), |(bj, bv), (j, v)| {
                if v.abs() > bv {
                    (j, v.abs())
                } else {
                    (bj, bv)
                }
            });
            let (il, _) = st
                .lam
                .iter()
                .enumerate()
                .fold((0, 0.0f64), |(bi, bv), (i, v)| {
                    if v.abs() > bv {
                        (i, v.abs())
                    } else {
                        (bi, bv)
                    }
                });
            eprintln!(
                "    max |grad L| at w[{jg}] (slack: {}) = {:.3e}, w = {:.6e} in [{:.6e}, {:.6e}], zl {:.3e}, zu {:.3e}",
                jg >= n, gl[jg], st.w[jg], st.wl[jg], st.wu[jg], st.zl[jg], st.zu[jg]
            );
            eprintln!(
                "    max |lambda| at row {il} (inequality: {}) = {:.3e}",
                st.slack_of_row[il] != NO_SLACK,
                st.lam[il]
            );
            let fixed = (0..n).filter(|&j| st.wu[j] - st.wl[j] < 1e-6).count();
            eprintln!("    variables with bound interval < 1e-6: {fixed}");
        }
        let inf_pr = inf_norm(&r);
        let zsum = one_norm(&st.zl) + one_norm(&st.zu);
        let s_d = (S_MAX.max((one_norm(&st.lam) + zsum) / (m + 2 * big_n).max(1) as f64)) / S_MAX;
        let s_c = (S_MAX.max(zsum / (2 * big_n).max(1) as f64)) / S_MAX;
        let err0 = (inf_du / s_d)
            .max(inf_pr)
            .max(st.complementarity(0.0) / s_c);
        let inf_pr_u = r
            .iter()
            .zip(&prob.con_scale)
            .map(|(v, s)| (v / s).abs())
            .fold(0.0, f64::max);
        let inf_du_u = inf_du / prob.obj_scale;
        let compl_u = st.complementarity(0.0) / prob.obj_scale;
        let rec = IterationRecord {
            iter,
            objective: st.f / prob.obj_scale,
            inf_pr: inf_pr_u,
            inf_du: inf_du_u,
            mu,
            elapsed: start.elapsed(),
            ..last_rec.clone()
        };
        if options.print_level >= 2 {
            eprintln!(
                "{:5} {:+.8e} {:.2e} {:.2e} {:.1e} {:.2e} {:.2e} {:.2e} {:.1e} {}",
                rec.iter,
                rec.objective,
                rec.inf_pr,
                rec.inf_du,
                rec.mu,
                rec.step_norm,
                rec.alpha_pr,
                rec.alpha_du,
                rec.regularisation,
                rec.ls_trials
            );
        }
        log.push(rec.clone());
        if observer(&rec).is_break() {
            status = SolveStatus::Interrupted;
            break;
        }
        if err0 <= options.tol
            && inf_pr_u <= options.constr_viol_tol
            && inf_du_u <= options.dual_inf_tol
            && compl_u <= options.compl_inf_tol
        {
            status = SolveStatus::Optimal;
            break;
        }
        if err0 <= options.acceptable_tol && inf_pr_u <= 1e-2 && compl_u <= 1e-2 {
            acceptable_count += 1;
            if acceptable_count >= options.acceptable_iter {
                status = SolveStatus::Acceptable;
                break;
            }
        } else {
            acceptable_count = 0;
        }
        if iter >= options.max_iter {
            status = SolveStatus::MaxIterations;
            break;
        }
        if let Some(limit) = options.time_limit {
            if start.elapsed() >= limit {
                status = SolveStatus::TimeLimit;
                break;
            }
        }
        if inf_norm(&st.w[..n]) > 1e20 {
            status = SolveStatus::Diverging;
            break;
        }
        // ---- μ floor: tol/10 in the scaled problem while the iterate is not yet primal and
        // dual feasible (a lower μ that early makes iterates hug their bounds); once it is,
        // low enough that the unscaled complementarity test (compl_inf_tol) can be met.
        let feasible = inf_pr_u <= options.constr_viol_tol && inf_du / s_d <= options.tol;
        let mu_floor = if globalisation == MuGlobalisation::ObjConstrFilter {
            // IPOPT's fixed-mode floor min(tol, compl_inf_tol)/(κ_ε + 1), used in free mode
            // too: IPOPT lets free-mode μ fall to mu_min ≈ 1e-11, which on the gait problem
            // made the tail alternate between free-mode steps at μ ≈ 1e-11 (iterates pushed to
            // their bounds) and fixed-mode steps at the floor pulling them back (decision
            // 0002: 10 intervals, L-BFGS, 470 → 400 and 547 → 413 iterations).
            options.tol.min(options.compl_inf_tol * prob.obj_scale) / (KAPPA_EPS + 1.0)
        } else if feasible {
            options.tol.min(options.compl_inf_tol * prob.obj_scale) / 10.0
        } else {
            options.tol / 10.0
        };

        // scaled optimality error of the barrier problem at μ
        let barrier_error = |mu: f64| (inf_du / s_d).max(inf_pr).max(st.complementarity(mu) / s_c);
        if want_adaptive && globalisation == MuGlobalisation::ObjConstrFilter {
            // ---- IPOPT's default globalisation `obj-constr-filter` --------------------------
            // An iterate makes sufficient progress when (f + margin, θ + margin) is not
            // dominated by any (f, θ) of the earlier accepted free-mode iterates.
            let theta = one_norm(&r);
            let margin = MU_FILTER_MARGIN * err0.min(1.0);
            let sufficient = !tiny_step
                && mu_filter
                    .iter()
                    .all(|&(fe, te)| st.f + margin < fe || theta + margin < te);
            if sufficient {
                // stay in (or return to) free mode
                adaptive = true;
                mu_filter.push((st.f, theta));
            } else if adaptive {
                adaptive = false;
                mu = fixed_mode_mu(&st, mu_floor);
            } else if barrier_error(mu) <= KAPPA_EPS * mu || tiny_step {
                // fixed mode: one monotone decrease once the barrier problem is solved
                mu = monotone_decrease(mu, mu_floor);
            }
        } else {
            // ---- adaptive μ globalisation (IPOPT `adaptive_mu_globalization = kkt-error`) ------
            // Progress is measured by the mean squared primal-dual error (IPOPT's
            // `quality_function_pd_system` with the default 2-norm-squared), which must fall below
            // 0.9999 × the largest of the last four reference errors. Free mode is left without
            // such progress; fixed mode is left as soon as it is made again (the references are
            // kept across the switch), so a short fixed-μ phase does not have to solve the whole
            // barrier problem before probing resumes.
            let pd = globalisation == MuGlobalisation::KktError;
            let pd_error = if want_adaptive && pd {
                st.pd_barrier_error(&gl, &r, 0.0)
            } else {
                err0
            };
            let progress = free_refs.len() >= FREE_MODE_REFS
                && free_refs.iter().any(|&r| pd_error <= FREE_MODE_RED * r);
            if adaptive {
                if free_refs.len() >= FREE_MODE_REFS && !progress {
                    adaptive = false;
                    if !pd {
                        free_refs.clear();
                    }
                    mu = fixed_mode_mu(&st, mu_floor);
                } else {
                    free_refs.push(pd_error);
                    if free_refs.len() > FREE_MODE_REFS {
                        free_refs.remove(0);
                    }
                }
            } else if pd && want_adaptive && progress && !feasible && !tiny_step {
                adaptive = true;
                free_refs.push(pd_error);
                if free_refs.len() > FREE_MODE_REFS {
                    free_refs.remove(0);
                }
            }

            // ---- monotone barrier update ------------------------------------------------------
            if !adaptive {
                for _ in 0..20 {
                    if barrier_error(mu) > KAPPA_EPS * mu || mu <= mu_floor {
                        break;
                    }
                    if want_adaptive && ls_failures == 0 && !feasible {
                        // barrier problem solved: back to free mode (once primal and dual
                        // feasible, μ only decreases monotonically: a free-mode probe there
                        // can leave the feasible region and cycle back)
                        adaptive = true;
                        break;
                    }
                    mu = monotone_decrease(mu, mu_floor);
                }
            }
        }

        // ---- exact Hessian for the tail of a limited-memory solve ----------------------------
        // Once μ has sat at its floor for a few iterations only the quasi-Newton model is
        // left to converge, which takes hundreds of iterations on the gait problem; from
        // there the exact Hessian's Newton steps are used (the KKT matrix gets the Hessian
        // pattern and a new symbolic analysis). With `stop_at_mu_floor` the solve ends there.
        if (options.exact_hessian_tail || options.stop_at_mu_floor) && !exact {
            floor_iters = if mu <= mu_floor { floor_iters + 1 } else { 0 };
            if floor_iters >= EXACT_TAIL_AFTER {
                if options.stop_at_mu_floor {
                    status = SolveStatus::MuFloor;
                    break;
                }
                let t = Instant::now();
                exact = true;
                lbfgs = None;
                pattern = KktPattern::new(n, m, &prob.jac, &prob.hess);
                analyse_kkt(linear, blocks.as_ref(), &prob.hess, &pattern)?;
                kvals = vec![0.0; pattern.nnz()];
                lin_time += t.elapsed();
                let (w, lam) = (st.w[..n].to_vec(), st.lam.clone());
                if let Err(e) = prob.hessian(&w, 1.0, &lam, &mut st.hv) {
                    status = SolveStatus::Failed(format!("Hessian evaluation failed: {e}"));
                    break;
                }
                exact_from = Some(iter);
                counts_at_switch = linear.counts;
                if options.print_level >= 1 {
                    eprintln!(
                        "stride-ipm: exact Hessian from iteration {iter} (factor {} entries)",
                        linear.factor_nnz()
                    );
                }
            }
        }

        // ---- KKT matrix: Σ and factorisation with inertia correction -------------------------
        for j in 0..big_n {
            let mut s = 0.0;
            if st.has_l[j] {
                s += st.zl[j] / (st.w[j] - st.wl[j]);
            }
            if st.has_u[j] {
                s += st.zu[j] / (st.wu[j] - st.w[j]);
            }
            sigma[j] = s;
        }
        let b0 = lbfgs.as_ref().map_or(0.0, |l| l.sigma);
        for i in 0..m {
            let k = st.slack_of_row[i];
            d_c[i] = if k == NO_SLACK {
                delta_c
            } else {
                1.0 / sigma[n + k].max(1e-20) + delta_c
            };
        }
        // First trial δ_w: 0, as IPOPT. In the exact-Hessian tail of a hybrid solve, after a
        // regularised iteration, δ_w_last/3 directly (the trial with 0 almost always fails
        // again there: on the 50-interval gait problem, 228 → 155 factorisations in the 103
        // exact-Hessian iterations, same iteration count and optimum; decision 0002). Not
        // from the start of an exact-Hessian solve: at 10 intervals it led to a higher local
        // optimum (303.98 instead of IPOPT's 301.52). Likewise in a warm-started solve (the
        // fine stage of mesh sequencing, continuation cases) while it is far from a solution
        // ([`WARM_SKIP_ZERO_ERROR`]): its long descents from a poor coarse optimum regularise
        // most iterations: 1.73 m/s quasi-random 226 → 212 iterations, 247 → 174 s; 1.83 m/s
        // data-informed running 298 → 285, 310 → 224 s; same optima (decision 0005). Once δ_w
        // has decayed below 1e-8, 0 is tried again.
        let skip_zero = regularised_last
            && (exact_from.is_some() || (options.warm_start && err0 > WARM_SKIP_ZERO_ERROR));
        let reduced = delta_w_last / REG_DECREASE;
        let mut delta_w = if skip_zero && reduced >= REG_SKIP_ZERO_MIN {
            reduced
        } else {
            0.0f64
        };
        let t_lin = Instant::now();
        let mut ok = false;
        for _ in 0..60 {
            for j in 0..n {
                diag_x[j] = if fixed_x[j] {
                    FIXED_DIAG
                } else if nonlinear[j] {
                    sigma[j] + delta_w + b0
                } else {
                    sigma[j] + delta_w
                };
            }
            pattern.assemble(&mut kvals, &st.hv, &st.jv, &diag_x, &d_c);
            let t_factor = Instant::now();
            let inertia = linear
                .factor(&kvals)
                .map_err(|e| SolveError::Backend(e.to_string()))?;
            factor_time += t_factor.elapsed();
            factorizations += 1;
            if debug {
                eprintln!("    delta_w {delta_w:.2e}: inertia {inertia:?} (want {n}, {m})");
            }
            if inertia
                == (Inertia {
                    positive: n,
                    negative: m,
                    zero: 0,
                })
            {
                ok = true;
                break;
            }
            delta_w = if delta_w == 0.0 {
                if delta_w_last == 0.0 {
                    REG_FIRST
                } else {
                    reduced.max(1e-20)
                }
            } else if delta_w_last == 0.0 {
                delta_w * REG_INCREASE_FIRST
            } else {
                delta_w * REG_INCREASE
            };
            if delta_w > 1e40 {
                break;
            }
        }
        lin_time += t_lin.elapsed();
        if !ok {
            status = SolveStatus::Failed("KKT matrix could not be regularised".into());
            break;
        }
        if delta_w > 0.0 {
            delta_w_last = delta_w;
        }
        regularised_last = delta_w > 0.0;
        // The Newton steps this iteration needs are solved together in one block solve (one
        // pass over the factor instead of one per step): in free mode the steps for μ = 0
        // and μ = average complementarity (the step of any μ is their affine combination),
        // in fixed mode the step for μ. With the limited-memory correction the block also
        // holds the correction's columns; with the exact Hessian the steps are refined
        // together. They are left in dw_aff/dlam_aff and dw_avg/dlam_avg.
        let avg = st.average_complementarity();
        let early_mus: &[f64] = if !adaptive {
            &[mu]
        } else if avg > 0.0 {
            &[0.0, avg]
        } else {
            &[]
        };
        let k0 = early_mus.len();
        early_rhs.resize(k0 * dim, 0.0);
        early_rs.resize(k0 * ni, 0.0);
        for (c, &mu_c) in early_mus.iter().enumerate() {
            newton_rhs(
                &st,
                mu_c,
                None,
                &r,
                &jac_rows,
                &jac_cols,
                &fixed_x,
                &sigma,
                &mut early_rhs[c * dim..(c + 1) * dim],
                &mut early_rs[c * ni..(c + 1) * ni],
            );
        }
        let mut early_ok = false;
        let mut early_ready = false;
        let t_early = Instant::now();
        let correction = match &lbfgs {
            Some(lb) if !lb.is_empty() => {
                let c = LowRankCorrection::new(lb, n, dim, |v, k| {
                    early_block.clear();
                    early_block.extend_from_slice(v);
                    early_block.extend_from_slice(&early_rhs);
                    let ok = linear.solve_many(&mut early_block, k + k0).is_ok();
                    v.copy_from_slice(&early_block[..k * dim]);
                    early_rhs.copy_from_slice(&early_block[k * dim..]);
                    early_ok = ok;
                    ok
                });
                if let Some(c) = &c {
                    for sol in early_rhs.chunks_mut(dim) {
                        c.apply(sol);
                    }
                } else {
                    early_ok = false;
                }
                c
            }
            _ => {
                if k0 > 0 {
                    early_block.clear();
                    early_block.extend_from_slice(&early_rhs);
                    early_ok = linear.solve_many(&mut early_rhs, k0).is_ok()
                        && refine_solutions(
                            linear,
                            &pattern,
                            &kvals,
                            &d_c_reg_buf,
                            &early_block,
                            &mut early_rhs,
                            k0,
                            &mut res_buf,
                            debug,
                        )
                        .is_ok();
                }
                None
            }
        };
        lin_time += t_early.elapsed();
        if early_ok && k0 > 0 {
            let outputs = [(&mut dw_aff, &mut dlam_aff), (&mut dw_avg, &mut dlam_avg)];
            for (col, (dw_c, dlam_c)) in outputs.into_iter().take(k0).enumerate() {
                step_from_solution(
                    &st,
                    &early_rhs[col * dim..(col + 1) * dim],
                    &early_rs[col * ni..(col + 1) * ni],
                    &fixed_x,
                    &sigma,
                    dw_c,
                    dlam_c,
                );
            }
            early_ready = true;
        }

        // ---- Newton direction (solves for a given μ) -----------------------------------------
        let b_save = &mut b_save_buf;
        let res = &mut res_buf;
        let d_c_reg = &d_c_reg_buf;
        let mut direction = |st: &State,
                             mu: f64,
                             targets: Option<(&[f64], &[f64])>,
                             r: &[f64],
                             rhs: &mut [f64],
                             dw: &mut [f64],
                             dlam: &mut [f64],
                             lin_time: &mut Duration|
         -> Result<(), SolveError> {
            newton_rhs(
                st, mu, targets, r, &jac_rows, &jac_cols, &fixed_x, &sigma, rhs, &mut r_s,
            );
            let t = Instant::now();
            b_save.copy_from_slice(rhs);
            linear
                .solve(rhs)
                .map_err(|e| SolveError::Backend(e.to_string()))?;
            if let Some(c) = &correction {
                c.apply(rhs);
            } else {
                // iterative refinement against the unregularised constraint block
                refine_solutions(
                    linear, &pattern, &kvals, d_c_reg, b_save, rhs, 1, res, debug,
                )
                .map_err(|e| SolveError::Backend(e.to_string()))?;
            }
            *lin_time += t.elapsed();
            step_from_solution(st, rhs, &r_s, &fixed_x, &sigma, dw, dlam);
            Ok(())
        };

        // ---- adaptive μ: IPOPT's quality function -----------------------------------------
        // the quality-function oracle leaves the final direction in dw, dlam
        let mut direction_ready = false;
        if !adaptive && early_ready {
            // fixed mode: the step for μ came with the correction's block solve
            dw.copy_from_slice(&dw_aff);
            dlam.copy_from_slice(&dlam_aff);
            direction_ready = true;
        }
        if adaptive && oracle == MuOracle::QualityFunction && avg > 0.0 {
            // steps for μ = 0 and μ = avg; the step of σ is their affine combination
            if !early_ready {
                direction(
                    &st,
                    0.0,
                    None,
                    &r,
                    &mut rhs,
                    &mut dw_aff,
                    &mut dlam_aff,
                    &mut lin_time,
                )?;
                direction(
                    &st,
                    avg,
                    None,
                    &r,
                    &mut rhs,
                    &mut dw_avg,
                    &mut dlam_avg,
                    &mut lin_time,
                )?;
            }
            let tau_q = (1.0 - err0).max(0.99);
            let (primal2, dual2) = st.mean_squared_infeasibilities(&gl, &r);
            let quality = |sigma: f64| -> f64 {
                combine(&dw_aff, &dw_avg, sigma, &mut dw);
                bound_multiplier_steps(&st, sigma * avg, None, &dw, &mut dzl, &mut dzu);
                let ap = fraction_to_boundary(&st, &st.w, &dw, tau_q);
                let ad = dual_fraction_to_boundary(&st, &dzl, &dzu, tau_q);
                let c2 = st.complementarity_after_step(&dw, &dzl, &dzu, ap, ad).1;
                (1.0 - ad).powi(2) * dual2 + (1.0 - ap).powi(2) * primal2 + c2
            };
            let sigma = choose_sigma(quality, mu_floor / avg, MU_MAX / avg);
            mu = (sigma * avg).clamp(mu_floor, MU_MAX);
            // the step of the final μ, without a third solve
            combine(&dw_aff, &dw_avg, mu / avg, &mut dw);
            combine(&dlam_aff, &dlam_avg, mu / avg, &mut dlam);
            direction_ready = true;
        } else if adaptive {
            // ---- adaptive μ: Mehrotra probing with the affine-scaling direction -----------
            if early_ready {
                dw.copy_from_slice(&dw_aff);
                dlam.copy_from_slice(&dlam_aff);
            } else {
                direction(
                    &st,
                    0.0,
                    None,
                    &r,
                    &mut rhs,
                    &mut dw,
                    &mut dlam,
                    &mut lin_time,
                )?;
            }
            bound_multiplier_steps(&st, 0.0, None, &dw, &mut dzl, &mut dzu);
            let ap = fraction_to_boundary(&st, &st.w, &dw, 1.0);
            let ad = dual_fraction_to_boundary(&st, &dzl, &dzu, 1.0);
            if avg > 0.0 {
                let aff = st
                    .complementarity_after_step(&dw, &dzl, &dzu, ap, ad)
                    .0
                    .max(0.0);
                let sig = (aff / avg).powi(3).min(1.0);
                // safeguard: far from feasibility a small μ lets iterates hug their bounds
                // and the multipliers run away (quasi-random gait guess); keep μ in
                // proportion to the remaining infeasibility, never above the average
                // complementarity
                let lower = (options.mu_safeguard_factor() * (inf_du / s_d).max(inf_pr)).min(avg);
                mu = (sig * avg).max(lower).clamp(mu_floor, MU_MAX);
                if early_ready {
                    // the step of the final μ, without another solve
                    combine(&dw_aff, &dw_avg, mu / avg, &mut dw);
                    combine(&dlam_aff, &dlam_avg, mu / avg, &mut dlam);
                    direction_ready = true;
                }
            } else {
                mu = mu_floor;
            }
        }
        tau = (1.0 - mu).max(0.99);
        if !direction_ready {
            direction(
                &st,
                mu,
                None,
                &r,
                &mut rhs,
                &mut dw,
                &mut dlam,
                &mut lin_time,
            )?;
        }

        // ---- centrality correctors (Gondzio 1996) ------------------------------------------
        // The step is cut by the fraction-to-boundary rule when some complementarity
        // products would leave the neighbourhood of μ; each corrector moves the targets of
        // those products back into [β_min μ, β_max μ] at an enlarged step size and solves
        // again with the same factorisation, and is kept only if the step size grows.
        let mut targets_on = false;
        if options.centrality_correctors > 0 && mu > 0.0 {
            tl.fill(0.0);
            tu.fill(0.0);
            bound_multiplier_steps(&st, mu, None, &dw, &mut dzl, &mut dzu);
            let mut ap = fraction_to_boundary(&st, &st.w, &dw, tau);
            let mut ad = dual_fraction_to_boundary(&st, &dzl, &dzu, tau);
            for _ in 0..options.centrality_correctors {
                let a = ap.min(ad);
                if a >= 1.0 {
                    break;
                }
                let aim_p = (CORRECTOR_AIM_FACTOR * ap + CORRECTOR_AIM_ADD).min(1.0);
                let aim_d = (CORRECTOR_AIM_FACTOR * ad + CORRECTOR_AIM_ADD).min(1.0);
                tl_c.copy_from_slice(&tl);
                tu_c.copy_from_slice(&tu);
                let outside = centrality_targets(
                    &st, mu, &dw, &dzl, &dzu, aim_p, aim_d, &mut tl_c, &mut tu_c,
                );
                if outside == 0 {
                    break;
                }
                let targets_c = Some((&tl_c[..], &tu_c[..]));
                direction(
                    &st,
                    mu,
                    targets_c,
                    &r,
                    &mut rhs,
                    &mut dw_c,
                    &mut dlam_c,
                    &mut lin_time,
                )?;
                bound_multiplier_steps(&st, mu, targets_c, &dw_c, &mut dzl_c, &mut dzu_c);
                let ap_c = fraction_to_boundary(&st, &st.w, &dw_c, tau);
                let ad_c = dual_fraction_to_boundary(&st, &dzl_c, &dzu_c, tau);
                if debug {
                    eprintln!(
                        "    corrector: {outside} products outside, alpha {ap:.3e}/{ad:.3e} -> {ap_c:.3e}/{ad_c:.3e}"
                    );
                }
                if ap_c.min(ad_c) < CORRECTOR_GAIN * a {
                    break;
                }
                std::mem::swap(&mut dw, &mut dw_c);
                std::mem::swap(&mut dlam, &mut dlam_c);
                std::mem::swap(&mut dzl, &mut dzl_c);
                std::mem::swap(&mut dzu, &mut dzu_c);
                std::mem::swap(&mut tl, &mut tl_c);
                std::mem::swap(&mut tu, &mut tu_c);
                (ap, ad) = (ap_c, ad_c);
                targets_on = true;
                correctors_kept += 1;
            }
        }
        let mut alpha_max = fraction_to_boundary(&st, &st.w, &dw, tau);

        // ---- filter line search with second-order correction (Wächter & Biegler 2006) -------
        let theta0 = one_norm(&r);
        if iter == 0 {
            theta_max = 1e4 * theta0.max(1.0);
            theta_min = 1e-4 * theta0.max(1.0);
        }
        if mu != filter_mu {
            filter.clear();
            filter_mu = mu;
        }
        let phi0 = st.barrier(st.f, &st.w, mu);
        let gphi_d = barrier_directional_derivative(&st, mu, &dw);
        let mut alpha_min = if gphi_d < 0.0 {
            GAMMA_ALPHA
                * GAMMA_THETA
                    .min(GAMMA_PHI * theta0 / -gphi_d)
                    .min(SWITCH_DELTA * theta0.powf(S_THETA) / (-gphi_d).powf(S_PHI))
        } else {
            GAMMA_ALPHA * GAMMA_THETA
        };
        let mut reference = LsReference {
            theta: theta0,
            phi: phi0,
            gphi_d,
            theta_min,
            theta_max,
        };
        let mut alpha = alpha_max;
        let mut trials = 0usize;
        let mut accepted = false;
        tiny_step = false;
        let mut armijo_step = false;
        let mut f_t = st.f;
        // ---- watchdog (IPOPT): after `watchdog_trigger` shortened steps in a row, take full
        // steps, each accepted if the filter accepts it against the references of the
        // watchdog's starting point, else taken anyway up to WATCHDOG_TRIAL_MAX times; then
        // return to the starting point and backtrack along its direction from α_max / 2.
        if watchdog.as_ref().is_some_and(|wd| wd.mu != mu) {
            // the barrier problem changed: the stored references no longer apply
            watchdog = None;
        }
        if watchdog.is_none()
            && options.watchdog_trigger > 0
            && shortened_steps >= options.watchdog_trigger
        {
            watchdog = Some(Watchdog {
                st: st.clone_without_hessian(),
                dw: dw.clone(),
                dlam: dlam.clone(),
                reference,
                alpha_max,
                alpha_min,
                mu,
                trials: 0,
            });
            shortened_steps = 0;
            watchdog_starts += 1;
            if debug {
                eprintln!("    watchdog started");
            }
        }
        let mut watchdog_step = false;
        if let Some(wd) = watchdog.as_mut() {
            trials = 1;
            let ev = evaluate_trial(&mut prob, &st.w, alpha_max, &dw, &mut wt, &mut ct);
            let verdict = ev.as_ref().ok().map(|&f| {
                st.residual(&wt, &ct, &mut rt);
                let phi = st.barrier(f, &wt, mu);
                (
                    f,
                    wd.reference.accepts(alpha_max, one_norm(&rt), phi, &filter),
                )
            });
            match verdict {
                Some((f, Some(a))) => {
                    // progress against the starting point: the watchdog ends here
                    f_t = f;
                    accepted = true;
                    armijo_step = a;
                    reference = wd.reference;
                    watchdog = None;
                }
                Some((f, None)) if wd.trials < WATCHDOG_TRIAL_MAX => {
                    wd.trials += 1;
                    f_t = f;
                    accepted = true;
                    watchdog_step = true;
                }
                _ => {
                    // no acceptable full step: back to the starting point and its direction
                    let wd = watchdog.take().expect("watchdog active");
                    // keep the Hessian buffer: its values are evaluated again at the next
                    // accepted point before the KKT matrix is assembled
                    let hv = std::mem::take(&mut st.hv);
                    st = wd.st;
                    st.hv = hv;
                    dw.copy_from_slice(&wd.dw);
                    dlam.copy_from_slice(&wd.dlam);
                    // the stored direction's bound-multiplier steps are taken at μ alone
                    targets_on = false;
                    reference = wd.reference;
                    alpha_max = wd.alpha_max;
                    alpha_min = wd.alpha_min;
                    st.residual(&st.w, &st.c, &mut r);
                    st.grad_lag(&prob.jac.rows, &prob.jac.cols, &fixed_x, &mut gl);
                    alpha = 0.5 * alpha_max;
                    watchdog_returns += 1;
                    if debug {
                        eprintln!("    watchdog: back to its starting point");
                    }
                }
            }
        }
        let dnorm = inf_norm(&dw);
        let wnorm = inf_norm(&st.w).max(1.0);
        while !accepted {
            trials += 1;
            let ev = evaluate_trial(&mut prob, &st.w, alpha, &dw, &mut wt, &mut ct);
            let mut theta_t = f64::INFINITY;
            if let Ok(f) = ev {
                st.residual(&wt, &ct, &mut rt);
                theta_t = one_norm(&rt);
                let phi = st.barrier(f, &wt, mu);
                if let Some(a) = reference.accepts(alpha, theta_t, phi, &filter) {
                    f_t = f;
                    accepted = true;
                    armijo_step = a;
                    break;
                }
            }
            // only a full step that is already at round-off level is accepted unconditionally
            let tiny = alpha_max * dnorm <= 10.0 * f64::EPSILON * wnorm;
            if tiny && ev.is_ok() {
                f_t = ev.unwrap_or(st.f);
                accepted = true;
                tiny_step = true;
                break;
            }
            // second-order correction after the first trial step was rejected for θ
            if trials == 1 && theta_t.is_finite() && theta_t >= reference.theta {
                let theta0 = reference.theta;
                let mut theta_old = theta0;
                let mut theta_soc = theta_t;
                for i in 0..m {
                    soc_rhs_r[i] = alpha * r[i] + rt[i];
                }
                let mut soc_ok = false;
                for _ in 0..MAX_SOC {
                    if theta_soc > KAPPA_SOC * theta_old && theta_old != theta0 {
                        break;
                    }
                    direction(
                        &st,
                        mu,
                        targets_on.then_some((&tl[..], &tu[..])),
                        &soc_rhs_r,
                        &mut rhs,
                        &mut dw_soc,
                        &mut dlam_soc,
                        &mut lin_time,
                    )?;
                    let a_soc = fraction_to_boundary(&st, &st.w, &dw_soc, tau);
                    let ev = evaluate_trial(&mut prob, &st.w, a_soc, &dw_soc, &mut wt, &mut ct);
                    let Ok(f) = ev else { break };
                    st.residual(&wt, &ct, &mut rt);
                    theta_old = theta_soc;
                    theta_soc = one_norm(&rt);
                    let phi = st.barrier(f, &wt, mu);
                    if let Some(a) = reference.accepts(alpha_max, theta_soc, phi, &filter) {
                        f_t = f;
                        armijo_step = a;
                        soc_ok = true;
                        break;
                    }
                    for i in 0..m {
                        soc_rhs_r[i] = a_soc * soc_rhs_r[i] + rt[i];
                    }
                }
                if soc_ok {
                    dw.copy_from_slice(&dw_soc);
                    dlam.copy_from_slice(&dlam_soc);
                    alpha = 1.0;
                    // the step w + a_soc dw_soc is already in wt: rescale so that α dw = it
                    let a_soc = fraction_to_boundary(&st, &st.w, &dw_soc, tau);
                    dw.iter_mut().for_each(|v| *v *= a_soc);
                    dlam.iter_mut().for_each(|v| *v *= a_soc);
                    accepted = true;
                    break;
                }
            }
            alpha *= 0.5;
            if alpha < alpha_min || trials >= 60 {
                break;
            }
        }
        if accepted && !armijo_step && !watchdog_step {
            filter.push((
                (1.0 - GAMMA_THETA) * reference.theta,
                reference.phi - GAMMA_PHI * reference.theta,
            ));
        }
        // a shortened step counts towards the watchdog trigger
        if accepted && !tiny_step && alpha < alpha_max {
            shortened_steps += 1;
        } else {
            shortened_steps = 0;
        }
        let targets = targets_on.then_some((&tl[..], &tu[..]));
        bound_multiplier_steps(&st, mu, targets, &dw, &mut dzl, &mut dzu);
        let mut alpha_z = dual_fraction_to_boundary(&st, &dzl, &dzu, tau);
        // ---- soft restoration (IPOPT): before the feasibility restoration, take the
        // primal-dual step to the fraction-to-boundary limits if it reduces the primal-dual
        // error of the barrier problem by a factor 1 − 1e-4. Near a solution the filter can
        // reject every trial step of an inexact (quasi-Newton) direction although the step
        // improves optimality, and the feasibility restoration would discard the multipliers.
        let mut soft_step = false;
        if !accepted && options.soft_restoration {
            let a = alpha_max.min(alpha_z);
            // r and gl still hold the residual and Lagrangian gradient of the current point
            let err_now = st.pd_barrier_error(&gl, &r, mu);
            let mut trial = st.clone_without_hessian();
            let mut gl_t = vec![0.0; big_n];
            for j in 0..big_n {
                trial.w[j] = st.w[j] + a * dw[j];
                trial.zl[j] = st.zl[j] + a * dzl[j];
                trial.zu[j] = st.zu[j] + a * dzu[j];
            }
            for i in 0..m {
                trial.lam[i] = st.lam[i] + a * dlam[i];
            }
            let xt = trial.w[..n].to_vec();
            let ev = prob.objective(&xt).and_then(|f| {
                prob.constraints(&xt, &mut trial.c)?;
                prob.gradient(&xt, &mut trial.grad)?;
                prob.jacobian(&xt, &mut trial.jv)?;
                Ok(f)
            });
            if let Ok(f) = ev {
                trial.residual(&trial.w, &trial.c, &mut rt);
                trial.grad_lag(&prob.jac.rows, &prob.jac.cols, &fixed_x, &mut gl_t);
                let err_trial = trial.pd_barrier_error(&gl_t, &rt, mu);
                if debug {
                    eprintln!("    soft restoration: error {err_now:.3e} -> {err_trial:.3e} (alpha {a:.2e})");
                }
                if err_trial.is_finite() && err_trial <= (1.0 - 1e-4) * err_now {
                    wt.copy_from_slice(&trial.w);
                    ct.copy_from_slice(&trial.c);
                    f_t = f;
                    alpha = a;
                    alpha_z = a;
                    accepted = true;
                    soft_step = true;
                    soft_steps += 1;
                }
            }
        }
        if soft_step || !accepted {
            // soft or feasibility restoration: the watchdog starts afresh
            watchdog = None;
            shortened_steps = 0;
        }
        if accepted {
            ls_failures = 0;
        } else {
            ls_failures += 1;
            if adaptive {
                adaptive = false;
                mu = mu.max(st.average_complementarity());
            }
            // feasibility restoration from the current point
            let restored = restore_feasibility(
                &mut prob,
                &st,
                mu,
                &filter,
                linear,
                Restoration {
                    pattern: &pattern,
                    fixed_x: &fixed_x,
                    kvals: &mut kvals,
                    diag_x: &mut diag_x,
                    d_c: &mut d_c,
                    rhs: &mut rhs,
                    zero_h: &zero_h,
                },
                &mut lin_time,
                &mut factorizations,
                options.print_level >= 2,
            );
            if let Some((w_r, c_r, f_r)) = restored {
                restorations += 1;
                wt.copy_from_slice(&w_r);
                ct.copy_from_slice(&c_r);
                f_t = f_r;
                // the multipliers of the old point do not carry over: no λ or z step, λ reset
                // to zero, z recentred on μ (the restoration used the primal barrier)
                alpha = 0.0;
                alpha_z = 0.0;
                st.lam.iter_mut().for_each(|v| *v = 0.0);
                for j in 0..big_n {
                    if st.has_l[j] {
                        st.zl[j] = mu / (wt[j] - st.wl[j]);
                    }
                    if st.has_u[j] {
                        st.zu[j] = mu / (st.wu[j] - wt[j]);
                    }
                }
                filter.clear();
            } else {
                // restoration made no progress either: stop after 3 such failures in a row,
                // else take the shortest trial step, reset the filter and go on
                if ls_failures >= 3 {
                    status = if inf_pr_u > options.constr_viol_tol {
                        SolveStatus::Infeasible
                    } else {
                        SolveStatus::SmallStep
                    };
                    break;
                }
                filter.clear();
                match evaluate_trial(&mut prob, &st.w, alpha, &dw, &mut wt, &mut ct) {
                    Ok(f) => f_t = f,
                    Err(_) => {
                        status = SolveStatus::Failed(
                            "function evaluation failed along the search direction".into(),
                        );
                        break;
                    }
                }
            }
        }

        // ---- accept the step --------------------------------------------------------------
        if lbfgs.is_some() {
            prev_x.copy_from_slice(&st.w[..n]);
        }
        st.w.copy_from_slice(&wt);
        st.f = f_t;
        st.c.copy_from_slice(&ct);
        for i in 0..m {
            st.lam[i] += alpha * dlam[i];
        }
        for j in 0..big_n {
            if st.has_l[j] {
                let sl = st.w[j] - st.wl[j];
                st.zl[j] = (st.zl[j] + alpha_z * dzl[j])
                    .clamp(mu / (KAPPA_SIGMA * sl), KAPPA_SIGMA * mu / sl);
            }
            if st.has_u[j] {
                let su = st.wu[j] - st.w[j];
                st.zu[j] = (st.zu[j] + alpha_z * dzu[j])
                    .clamp(mu / (KAPPA_SIGMA * su), KAPPA_SIGMA * mu / su);
            }
        }
        if lbfgs.is_some() {
            // ∇ₓL(x_old, λ_new) with the old gradient and Jacobian
            prev_grad_lag.copy_from_slice(&st.grad);
            for k in 0..st.jv.len() {
                prev_grad_lag[prob.jac.cols[k]] += st.jv[k] * st.lam[prob.jac.rows[k]];
            }
        }
        let x_new = st.w[..n].to_vec();
        // The Hessian first: a problem may get its Jacobian from the Hessian's sweeps and
        // keep it for the gradient and Jacobian at the same point.
        if exact {
            if let Err(e) = prob.hessian(&x_new, 1.0, &st.lam, &mut st.hv) {
                status = SolveStatus::Failed(format!("Hessian evaluation failed: {e}"));
                break;
            }
        }
        let ev = prob
            .gradient(&x_new, &mut st.grad)
            .and_then(|_| prob.jacobian(&x_new, &mut st.jv));
        if let Err(e) = ev {
            status = SolveStatus::Failed(format!("derivative evaluation failed: {e}"));
            break;
        }
        if let Some(lb) = &mut lbfgs {
            tmp_n.copy_from_slice(&st.grad);
            for k in 0..st.jv.len() {
                tmp_n[prob.jac.cols[k]] += st.jv[k] * st.lam[prob.jac.rows[k]];
            }
            for j in 0..n {
                (s_pair[j], y_pair[j]) = if nonlinear[j] {
                    (x_new[j] - prev_x[j], tmp_n[j] - prev_grad_lag[j])
                } else {
                    (0.0, 0.0)
                };
            }
            let kept = lb.update(&s_pair, &y_pair);
            if debug {
                eprintln!(
                    "    l-bfgs: pair {} ({} stored, sigma {:.3e}, s'y {:.3e})",
                    if kept { "kept" } else { "skipped" },
                    lb.len(),
                    lb.sigma,
                    dot(&s_pair, &y_pair)
                );
            }
        }
        iter += 1;
        last_rec = IterationRecord {
            step_norm: alpha * dnorm,
            alpha_pr: alpha,
            alpha_du: alpha_z,
            regularisation: delta_w,
            ls_trials: trials,
            factorisations: factorizations - factorizations_before,
            ..Default::default()
        };
        factorizations_before = factorizations;
    }

    // ---- result (unscaled) ---------------------------------------------------------------
    st.residual(&st.w, &st.c, &mut r);
    let constraint_violation = r
        .iter()
        .zip(&prob.con_scale)
        .map(|(v, s)| (v / s).abs())
        .fold(0.0, f64::max);
    // Inequality rows: report the violation of g_l <= c <= g_u rather than c − s.
    let mut viol = 0.0f64;
    for i in 0..m {
        let ci = st.c[i] / prob.con_scale[i];
        viol = viol.max(bounds.g_l[i] - ci).max(ci - bounds.g_u[i]);
    }
    let constraint_violation = if ni > 0 {
        viol.max(0.0)
    } else {
        constraint_violation
    };
    st.grad_lag(&prob.jac.rows, &prob.jac.cols, &fixed_x, &mut gl);
    let dual_infeasibility = inf_norm(&gl[..n]) / prob.obj_scale;
    let sf = prob.obj_scale;
    let lambda: Vec<f64> = st
        .lam
        .iter()
        .zip(&prob.con_scale)
        .map(|(l, s)| l * s / sf)
        .collect();
    let result = SolveResult {
        status,
        iterations: iter,
        objective: st.f / sf,
        constraint_violation,
        dual_infeasibility,
        x: st.w[..n].to_vec(),
        lambda,
        z_l: st.zl[..n].iter().map(|z| z / sf).collect(),
        z_u: st.zu[..n].iter().map(|z| z / sf).collect(),
        time_total: start.elapsed(),
        time_evaluations: prob.eval_time,
        time_linear_solver: lin_time,
        time_symbolic,
        time_factorisation: factor_time,
        solves: linear.counts.calls,
        time_solves: linear.counts.time,
        factorizations,
        objective_evaluations: prob.n_obj,
        exact_hessian_from: exact_from,
        log,
    };
    if options.print_level >= 1 {
        eprintln!(
            "stride-ipm: {:?} after {} iterations ({} restorations, {} soft-restoration steps, {} centrality correctors, watchdog {} started / {} returned{}), f = {:.10e}, |c| = {:.2e}, total {:.3} s (eval {:.3} s, linear {:.3} s of which {} factorisations {:.3} s)",
            result.status,
            result.iterations,
            restorations,
            soft_steps,
            correctors_kept,
            watchdog_starts,
            watchdog_returns,
            exact_from.map_or(String::new(), |k| format!(", exact Hessian from iteration {k}")),
            result.objective,
            result.constraint_violation,
            result.time_total.as_secs_f64(),
            result.time_evaluations.as_secs_f64(),
            result.time_linear_solver.as_secs_f64(),
            result.factorizations,
            result.time_factorisation.as_secs_f64()
        );
        let c = linear.counts;
        let tail = exact_from.map_or(String::new(), |_| {
            format!(
                "; exact tail {} calls, {} columns, {:.3} s",
                c.calls - counts_at_switch.calls,
                c.columns - counts_at_switch.columns,
                (c.time - counts_at_switch.time).as_secs_f64()
            )
        });
        eprintln!(
            "stride-ipm: solves {} calls, {} columns, {:.3} s{tail}",
            c.calls,
            c.columns,
            c.time.as_secs_f64()
        );
    }
    Ok(result)
}

fn check_options(o: &SolverOptions) -> Result<(), SolveError> {
    let bad = |name: &'static str, reason: &str| {
        Err(SolveError::InvalidOption {
            name,
            reason: reason.to_string(),
        })
    };
    if o.tol.is_nan() || o.tol <= 0.0 {
        return bad("tol", "must be positive");
    }
    if o.mu_init.is_nan() || o.mu_init <= 0.0 {
        return bad("mu_init", "must be positive");
    }
    if o.mu_safeguard.is_some_and(|f| f.is_nan() || f < 0.0) {
        return bad("mu_safeguard", "must be non-negative");
    }
    if o.bound_push.is_nan() || o.bound_push <= 0.0 || o.bound_push >= 0.5 {
        return bad("bound_push", "must be in (0, 0.5)");
    }
    if let HessianMode::LimitedMemory { history } = o.hessian {
        if history == 0 {
            return bad("hessian", "limited-memory history must be at least 1");
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ipm::linsys::FaerLdlt;

    /// KKT matrix [[H, Jᵀ], [J, −δ_c I]] with H = diag(4, 3, 5), J = [[1, 1, 0], [0, 2, 1]],
    /// factorised with the constraint block regularised by δ_c = 0.01 (far larger than the
    /// solver's, so that refinement has something to remove); the unregularised matrix is
    /// the one refinement solves.
    fn regularised_system() -> (KktPattern, Vec<f64>, FaerLdlt) {
        let jac = Sparsity::new(vec![0, 0, 1, 1], vec![0, 1, 1, 2]);
        let hess = Sparsity::new(vec![], vec![]);
        let pattern = KktPattern::new(3, 2, &jac, &hess);
        let mut vals = vec![0.0; pattern.nnz()];
        pattern.assemble(
            &mut vals,
            &[],
            &[1.0, 1.0, 2.0, 1.0],
            &[4.0, 3.0, 5.0],
            &[0.01, 0.01],
        );
        let mut solver = FaerLdlt::new();
        solver
            .analyse(pattern.dim, &pattern.col_ptr, &pattern.row_idx, None)
            .unwrap();
        solver.factor(&vals).unwrap();
        (pattern, vals, solver)
    }

    /// K_true x for the system above (constraint block zero).
    fn true_product(x: &[f64]) -> Vec<f64> {
        vec![
            4.0 * x[0] + x[3],
            3.0 * x[1] + x[3] + 2.0 * x[4],
            5.0 * x[2] + x[4],
            x[0] + x[1],
            2.0 * x[1] + x[2],
        ]
    }

    #[test]
    fn block_refinement_solves_the_unregularised_system_column_by_column() {
        let (pattern, vals, mut solver) = regularised_system();
        let xs = [
            [1.0, -2.0, 0.5, 3.0, -1.0],
            [0.0, 1.0, 1.0, -2.0, 4.0],
            [2.0, 0.0, -1.0, 0.5, 0.25],
        ];
        let b: Vec<f64> = xs.iter().flat_map(|x| true_product(x)).collect();
        let mut x = b.clone();
        solver.solve_many(&mut x, 3).unwrap();
        // without refinement the regularisation leaves an error of order δ_c
        let before = (0..15)
            .map(|k| (x[k] - xs[k / 5][k % 5]).abs())
            .fold(0.0, f64::max);
        assert!(before > 1e-4, "unrefined error {before}");
        let mut res = Vec::new();
        let d_c_reg = [0.01, 0.01];
        refine_solutions(
            &mut solver,
            &pattern,
            &vals,
            &d_c_reg,
            &b,
            &mut x,
            3,
            &mut res,
            false,
        )
        .unwrap();
        // refinement stops at a residual of REFINE_TOL relative to the right-hand side
        for (c, want) in xs.iter().enumerate() {
            let col = &x[c * 5..(c + 1) * 5];
            let kx = true_product(col);
            let bnorm = inf_norm(&b[c * 5..(c + 1) * 5]).max(1.0);
            let res = (0..5)
                .map(|i| (b[c * 5 + i] - kx[i]).abs())
                .fold(0.0, f64::max);
            assert!(res <= REFINE_TOL * bnorm, "column {c}: residual {res:e}");
            for (got, w) in col.iter().zip(want) {
                assert!((got - w).abs() < 1e-7, "column {c}: {got} vs {w}");
            }
        }
        // the same column refined alone gives the same solution
        let mut x1 = b[5..10].to_vec();
        solver.solve(&mut x1).unwrap();
        refine_solutions(
            &mut solver,
            &pattern,
            &vals,
            &d_c_reg,
            &b[5..10],
            &mut x1,
            1,
            &mut res,
            false,
        )
        .unwrap();
        for (a, c) in x1.iter().zip(&x[5..10]) {
            assert!((a - c).abs() < 1e-12, "{a} vs {c}");
        }
    }
}
