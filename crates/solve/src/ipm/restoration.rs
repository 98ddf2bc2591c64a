//! What happens when the filter line search finds no acceptable step.
//!
//! 1. Soft restoration (IPOPT): take the primal-dual step to the fraction-to-boundary
//!    limits if it reduces the primal-dual error of the barrier problem (mean squared
//!    ‖r‖², ‖∇L‖², complementarity) by a factor 1 − 1e-4. Near a solution the filter can
//!    reject every trial step of an inexact (quasi-Newton) direction although the step
//!    improves optimality, and the feasibility restoration would discard the multipliers.
//! 2. Feasibility restoration (simplified from Wächter & Biegler 2006, section 3.3): elastic
//!    Gauss–Newton steps that reduce θ = ‖r‖₁, with the objective replaced by the primal
//!    barrier μ_R Σ ln of the slacks to the bounds plus a proximal term ζ/2 ‖dw‖² (μ_R =
//!    max(μ, ‖r‖∞), ζ = √μ_R as IPOPT), zero multipliers, and backtracking on the merit
//!    ‖r‖²/(2ε) + barrier, until θ is below 0.9 θ at entry and the point is acceptable to
//!    the filter.
// Index loops over several parallel arrays are clearer than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use std::time::Instant;

use crate::ipm::filter::Filter;
use crate::ipm::inertia::{KktSystem, FIXED_DIAG};
use crate::ipm::iterate::{fraction_to_boundary, inf_norm, one_norm, Iterate, NO_SLACK};
use crate::ipm::line_search::Trial;
use crate::ipm::linsys::KktSolver;
use crate::ipm::scaled::ScaledNlp;
use crate::ipm::workspace::Ipm;
use crate::observer::{Diagnostic, Emitter};

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
/// Relative reduction of the primal-dual error that soft restoration needs.
const SOFT_REDUCTION: f64 = 1e-4;
/// Halvings of one restoration step at most.
const RESTORATION_BACKTRACKS: usize = 30;

/// The point a feasibility restoration ends at: w, its constraint values and objective.
pub(super) struct Restored {
    pub w: Vec<f64>,
    pub c: Vec<f64>,
    pub f: f64,
}

impl Ipm<'_> {
    /// Soft restoration after a failed line search (module docs): on success the trial
    /// point is in `ls.wt`, `ls.ct` and `trial` holds the step sizes.
    pub(super) fn soft_restoration(&mut self, trial: &mut Trial, alpha_z: &mut f64) -> bool {
        let mu = self.barrier.mu;
        let a = trial.alpha_max.min(*alpha_z);
        let Ipm {
            st,
            prob,
            ls,
            newton,
            opt,
            kkt,
            emitter,
            ..
        } = self;
        // opt.r and opt.gl still hold the residual and Lagrangian gradient of the current point
        let err_now = st.pd_barrier_error(&opt.gl, &opt.r, mu);
        // a rare event: the trial iterate (with its Jacobian values) is allocated here and
        // freed after, so that it does not add to the solve's peak memory
        let t = &mut st.clone_without_hessian();
        let step = &newton.main;
        for j in 0..st.big_n {
            t.w[j] = st.w[j] + a * step.dw[j];
            t.zl[j] = st.zl[j] + a * step.dzl[j];
            t.zu[j] = st.zu[j] + a * step.dzu[j];
        }
        for i in 0..st.m {
            t.lam[i] = st.lam[i] + a * step.dlam[i];
        }
        let Ok(f) = evaluate_point(prob, t) else {
            return false;
        };
        t.residual(&t.w, &t.c, &mut ls.rt);
        let s = &kkt.structure;
        t.grad_lag(&s.jac_rows, &s.jac_cols, &s.fixed_x, &mut ls.gl_trial);
        let err_trial = t.pd_barrier_error(&ls.gl_trial, &ls.rt, mu);
        emitter.emit(Diagnostic::SoftRestoration {
            error: err_now,
            trial_error: err_trial,
            alpha: a,
        });
        if !(err_trial.is_finite() && err_trial <= (1.0 - SOFT_REDUCTION) * err_now) {
            return false;
        }
        ls.wt.copy_from_slice(&t.w);
        ls.ct.copy_from_slice(&t.c);
        trial.f_t = f;
        trial.alpha = a;
        *alpha_z = a;
        trial.accepted = true;
        true
    }

    /// Feasibility restoration from the current iterate (module docs); on success the
    /// multipliers are reset (λ = 0, z on the central path of μ) and the filter emptied.
    pub(super) fn feasibility_restoration(&mut self) -> Option<Restored> {
        let mu = self.barrier.mu;
        let restored = restore_feasibility(
            &mut self.prob,
            &self.st,
            mu,
            &self.ls.filter,
            &mut self.kkt,
            &mut self.emitter,
        )?;
        // the multipliers of the old point do not carry over: no λ or z step, λ reset to
        // zero, z recentred on μ (the restoration used the primal barrier)
        let st = &mut self.st;
        st.lam.iter_mut().for_each(|v| *v = 0.0);
        for j in 0..st.big_n {
            if st.has_l[j] {
                st.zl[j] = mu / (restored.w[j] - st.wl[j]);
            }
            if st.has_u[j] {
                st.zu[j] = mu / (st.wu[j] - restored.w[j]);
            }
        }
        self.ls.filter.clear();
        Some(restored)
    }
}

/// Objective, constraints, gradient and Jacobian at the primal part of `t.w`.
fn evaluate_point(prob: &mut ScaledNlp, t: &mut Iterate) -> Result<f64, crate::nlp::EvalError> {
    let x = &t.w[..t.n];
    let f = prob.objective(x)?;
    prob.constraints(x, &mut t.c)?;
    prob.gradient(x, &mut t.grad)?;
    prob.jacobian(x, &mut t.jv)?;
    Ok(f)
}

/// The elastic Gauss–Newton problem of one restoration: barrier weight μ_R, proximal
/// weight ζ and elastic weight ε.
struct Elastic {
    mu_r: f64,
    zeta: f64,
    eps: f64,
}

impl Elastic {
    /// ‖r‖² / (2ε) + μ_R barrier: the function whose Gauss–Newton model the step minimises.
    fn merit(&self, st: &Iterate, r: &[f64], w: &[f64]) -> f64 {
        let sq = r.iter().map(|v| v * v).sum::<f64>() / (2.0 * self.eps);
        let mut b = 0.0;
        for j in 0..st.big_n {
            if st.has_l[j] {
                b -= self.mu_r * (w[j] - st.wl[j]).ln();
            }
            if st.has_u[j] {
                b -= self.mu_r * (st.wu[j] - w[j]).ln();
            }
        }
        sq + b
    }

    /// The step dw at w (residual r, Jacobian values jv) from the elastic KKT system, or
    /// None when its factorisation or solve fails.
    fn step(
        &self,
        st: &Iterate,
        (w, r, jv): (&[f64], &[f64], &[f64]),
        kkt: &mut KktSystem,
        dw: &mut [f64],
        emitter: &mut Emitter,
    ) -> Option<()> {
        let (n, m, big_n) = (st.n, st.m, st.big_n);
        let (mut sigma, mut bgrad) = (vec![0.0; big_n], vec![0.0; big_n]);
        // primal barrier μ Σ ln(slack to bound): gradient and Hessian μ / slack²
        for j in 0..big_n {
            let (mut sg, mut b) = (0.0, 0.0);
            if st.has_l[j] {
                let sl = w[j] - st.wl[j];
                sg += self.mu_r / (sl * sl);
                b -= self.mu_r / sl;
            }
            if st.has_u[j] {
                let su = st.wu[j] - w[j];
                sg += self.mu_r / (su * su);
                b += self.mu_r / su;
            }
            sigma[j] = sg + self.zeta;
            bgrad[j] = b;
        }
        let fixed_x = &kkt.structure.fixed_x;
        for j in 0..n {
            kkt.diag_x[j] = if fixed_x[j] { FIXED_DIAG } else { sigma[j] };
        }
        for i in 0..m {
            let k = st.slack_of_row[i];
            kkt.d_c[i] = if k == NO_SLACK {
                self.eps
            } else {
                1.0 / sigma[n + k] + self.eps
            };
        }
        kkt.pattern
            .assemble(&mut kkt.vals, &kkt.zero_h, jv, &kkt.diag_x, &kkt.d_c);
        let t = Instant::now();
        let ok = kkt.linear.factor(&kkt.vals).is_ok();
        kkt.factorizations += 1;
        for j in 0..n {
            kkt.rhs[j] = if fixed_x[j] { 0.0 } else { -bgrad[j] };
        }
        for i in 0..m {
            let k = st.slack_of_row[i];
            kkt.rhs[n + i] = if k == NO_SLACK {
                -r[i]
            } else {
                -r[i] - bgrad[n + k] / sigma[n + k]
            };
        }
        let solved = ok && kkt.linear.solve(&mut kkt.rhs).is_ok();
        if !solved {
            emitter.emit(Diagnostic::RestorationLinearSolveFailed);
        }
        kkt.time += t.elapsed();
        if !solved || kkt.rhs.iter().any(|v| !v.is_finite()) {
            return None;
        }
        for j in 0..n {
            dw[j] = if fixed_x[j] { 0.0 } else { kkt.rhs[j] };
        }
        for (k, &i) in st.row_of_slack.iter().enumerate() {
            dw[n + k] = (kkt.rhs[n + i] - bgrad[n + k]) / sigma[n + k];
        }
        Some(())
    }
}

/// Feasibility restoration from `st` at barrier parameter `mu` (module docs). Returns the
/// restored point, or `None` when θ cannot be reduced (a stationary point of the
/// infeasibility).
fn restore_feasibility(
    prob: &mut ScaledNlp,
    st: &Iterate,
    mu: f64,
    filter: &Filter,
    kkt: &mut KktSystem,
    emitter: &mut Emitter,
) -> Option<Restored> {
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
    // elastic weight ε = ε₀ ‖r‖∞ at entry: the penalty gradient r/ε then has entries up to
    // 1/ε₀ whatever the size of the violation (like IPOPT's ℓ₁ penalty ρ = 1000), so the
    // barrier μ_R Σ ln(slack) cannot outweigh it once r is small
    let elastic = Elastic {
        mu_r,
        zeta: mu_r.sqrt(),
        eps: RESTORATION_ELASTIC * inf_norm(&r).max(f64::MIN_POSITIVE),
    };
    let mut dw = vec![0.0; big_n];
    let mut wt = vec![0.0; big_n];
    let mut ct = vec![0.0; m];
    let mut rt = vec![0.0; m];
    for _ in 0..MAX_RESTORATION_STEPS {
        elastic.step(st, (&w, &r, &jv), kkt, &mut dw, emitter)?;
        let merit0 = elastic.merit(st, &r, &w);
        let mut alpha = fraction_to_boundary(st, &w, &dw, 0.99);
        let mut accepted = None;
        for _ in 0..RESTORATION_BACKTRACKS {
            for j in 0..big_n {
                wt[j] = w[j] + alpha * dw[j];
            }
            if prob.constraints(&wt[..n], &mut ct).is_ok() {
                st.residual(&wt, &ct, &mut rt);
                let theta_t = one_norm(&rt);
                let merit = elastic.merit(st, &rt, &wt);
                if merit.is_finite() && merit < merit0 {
                    accepted = Some(theta_t);
                    break;
                }
            }
            alpha *= 0.5;
        }
        emitter.emit(Diagnostic::RestorationStep {
            theta,
            accepted,
            alpha,
            step_norm: inf_norm(&dw),
            theta_entry,
        });
        theta = accepted?;
        w.copy_from_slice(&wt);
        c.copy_from_slice(&ct);
        r.copy_from_slice(&rt);
        let f = prob.objective(&w[..n]).ok()?;
        let phi = st.barrier(f, &w, mu);
        if theta <= RESTORATION_REDUCTION * theta_entry && !filter.dominates(theta, phi) {
            return Some(Restored { w, c, f });
        }
        prob.jacobian(&w[..n], &mut jv).ok()?;
    }
    None
}
