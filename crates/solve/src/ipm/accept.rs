//! Taking the accepted step: the primal point of the trial, λ ← λ + α dλ, the bound
//! multipliers z ← z + α_z dz kept within [μ/(κ_Σ s), κ_Σ μ/s] of their complementarity
//! targets (Wächter & Biegler 2006, eq. 16), the derivatives at the new point and the
//! limited-memory update with the pair s = Δx, y = Δ∇ₓL(·, λ_new) on the nonlinear variables.
// Index loops over several parallel arrays are clearer than zipped iterators here.
#![allow(clippy::needless_range_loop)]

use crate::ipm::inertia::KktStructure;
use crate::ipm::iterate::Iterate;
use crate::ipm::lbfgs::dot;
use crate::ipm::line_search::Trial;
use crate::ipm::workspace::{Ipm, Quasi};
use crate::observer::Diagnostic;
use crate::solver::SolveStatus;

/// Safeguard factor κ_Σ for the bound multipliers.
const KAPPA_SIGMA: f64 = 1e10;

/// out = ∇f + Jᵀλ over x at the iterate's gradient, Jacobian and multipliers.
fn grad_lag_x(st: &Iterate, s: &KktStructure, out: &mut [f64]) {
    out.copy_from_slice(&st.grad);
    for k in 0..st.jv.len() {
        out[s.jac_cols[k]] += st.jv[k] * st.lam[s.jac_rows[k]];
    }
}

impl Ipm<'_> {
    /// Moves to the trial point of `trial` (in `ls.wt`, `ls.ct`) with dual step size
    /// `alpha_z` and evaluates the derivatives there; Some(status) if an evaluation fails.
    pub(super) fn accept_step(&mut self, trial: &Trial, alpha_z: f64) -> Option<SolveStatus> {
        let (mu, alpha) = (self.barrier.mu, trial.alpha);
        let n = self.st.n;
        if let Some(q) = &mut self.lbfgs {
            q.prev_x.copy_from_slice(&self.st.w[..n]);
        }
        let (st, step) = (&mut self.st, &self.newton.main);
        st.w.copy_from_slice(&self.ls.wt);
        st.f = trial.f_t;
        st.c.copy_from_slice(&self.ls.ct);
        for i in 0..st.m {
            st.lam[i] += alpha * step.dlam[i];
        }
        for j in 0..st.big_n {
            if st.has_l[j] {
                let sl = st.w[j] - st.wl[j];
                st.zl[j] = (st.zl[j] + alpha_z * step.dzl[j])
                    .clamp(mu / (KAPPA_SIGMA * sl), KAPPA_SIGMA * mu / sl);
            }
            if st.has_u[j] {
                let su = st.wu[j] - st.w[j];
                st.zu[j] = (st.zu[j] + alpha_z * step.dzu[j])
                    .clamp(mu / (KAPPA_SIGMA * su), KAPPA_SIGMA * mu / su);
            }
        }
        if let Some(q) = &mut self.lbfgs {
            // ∇ₓL(x_old, λ_new) with the old gradient and Jacobian
            grad_lag_x(st, &self.kkt.structure, &mut q.prev_grad_lag);
        }
        if let Some(status) = self.evaluate_derivatives() {
            return Some(status);
        }
        self.update_lbfgs();
        None
    }

    /// The Hessian (exact mode), gradient and Jacobian at the new point. The Hessian first:
    /// a problem may get its Jacobian from the Hessian's sweeps and keep it for the gradient
    /// and Jacobian at the same point.
    fn evaluate_derivatives(&mut self) -> Option<SolveStatus> {
        let (st, x) = (&mut self.st, &mut self.x_new);
        x.copy_from_slice(&st.w[..st.n]);
        if self.exact {
            if let Err(e) = self.prob.hessian(x, 1.0, &st.lam, &mut st.hv) {
                return Some(SolveStatus::Failed(format!(
                    "Hessian evaluation failed: {e}"
                )));
            }
        }
        let ev = self
            .prob
            .gradient(x, &mut st.grad)
            .and_then(|_| self.prob.jacobian(x, &mut st.jv));
        if let Err(e) = ev {
            return Some(SolveStatus::Failed(format!(
                "derivative evaluation failed: {e}"
            )));
        }
        None
    }

    /// The L-BFGS update with the pair of the step just taken.
    fn update_lbfgs(&mut self) {
        let Some(q) = &mut self.lbfgs else { return };
        let (st, s) = (&self.st, &self.kkt.structure);
        grad_lag_x(st, s, &mut q.tmp_n);
        let Quasi {
            lbfgs,
            prev_x,
            prev_grad_lag,
            tmp_n,
            s_pair,
            y_pair,
        } = q;
        for j in 0..st.n {
            (s_pair[j], y_pair[j]) = if s.nonlinear[j] {
                (self.x_new[j] - prev_x[j], tmp_n[j] - prev_grad_lag[j])
            } else {
                (0.0, 0.0)
            };
        }
        let kept = lbfgs.update(s_pair, y_pair);
        if self.emitter.wants(3) {
            self.emitter.emit(Diagnostic::LbfgsPair {
                kept,
                stored: lbfgs.len(),
                sigma: lbfgs.sigma,
                sy: dot(s_pair, y_pair),
            });
        }
    }
}
