//! The optimality error of the current iterate, the iteration record and the termination
//! tests.
//!
//! Scaled optimality error (Wächter & Biegler 2006, eq. 5):
//! E₀ = max(‖∇L‖∞ / s_d, ‖r‖∞, ‖ZWe‖∞ / s_c) with s_d = max(s_max, (‖λ‖₁ + ‖z‖₁)/(m + 2N))
//! / s_max and s_c = max(s_max, ‖z‖₁/(2N)) / s_max, s_max = 100. The solve is `Optimal` when
//! E₀ ≤ tol and the unscaled primal, dual and complementarity errors meet their absolute
//! tolerances (IPOPT), `Acceptable` after `acceptable_iter` consecutive iterates with E₀ ≤
//! acceptable_tol (and unscaled primal and complementarity errors ≤ 1e-2).

use crate::ipm::iterate::{inf_norm, one_norm, NO_SLACK};
use crate::ipm::workspace::Ipm;
use crate::observer::Diagnostic;
use crate::solver::{IterationRecord, SolveStatus};

/// IPOPT's s_max for the scaled optimality error.
const S_MAX: f64 = 100.0;
/// Acceptable level of the unscaled primal infeasibility and complementarity.
const ACCEPTABLE_UNSCALED: f64 = 1e-2;
/// Max-norm of x beyond which the iterates count as diverging.
const DIVERGING: f64 = 1e20;

/// Index and absolute value of the entry of largest magnitude (the first on ties).
fn largest(v: &[f64]) -> (usize, f64) {
    v.iter().enumerate().fold((0, 0.0f64), |(bj, bv), (j, x)| {
        if x.abs() > bv {
            (j, x.abs())
        } else {
            (bj, bv)
        }
    })
}

impl Ipm<'_> {
    /// The optimality measures of the current iterate from its residual and Lagrangian
    /// gradient (see [`Ipm::measure_residuals`]).
    pub(super) fn measure_optimality(&mut self) {
        let (st, e) = (&self.st, &mut self.opt);
        let (m, big_n) = (st.m, st.big_n);
        e.inf_du = inf_norm(&e.gl);
        e.inf_pr = inf_norm(&e.r);
        let zsum = one_norm(&st.zl) + one_norm(&st.zu);
        e.s_d = (S_MAX.max((one_norm(&st.lam) + zsum) / (m + 2 * big_n).max(1) as f64)) / S_MAX;
        e.s_c = (S_MAX.max(zsum / (2 * big_n).max(1) as f64)) / S_MAX;
        e.err0 = (e.inf_du / e.s_d)
            .max(e.inf_pr)
            .max(st.complementarity(0.0) / e.s_c);
        e.inf_pr_u =
            e.r.iter()
                .zip(&self.prob.con_scale)
                .map(|(v, s)| (v / s).abs())
                .fold(0.0, f64::max);
        e.feasible = e.inf_pr_u <= self.o.constr_viol_tol && e.inf_du / e.s_d <= self.o.tol;
        if self.emitter.wants(3) {
            self.emit_largest_entries();
        }
    }

    /// The largest entries of ∇L and λ (a diagnostic).
    fn emit_largest_entries(&mut self) {
        let (st, gl) = (&self.st, &self.opt.gl);
        let (jg, _) = largest(gl);
        let (il, _) = largest(&st.lam);
        let narrow = (0..st.n).filter(|&j| st.wu[j] - st.wl[j] < 1e-6).count();
        self.emitter.emit(Diagnostic::LargestEntries {
            index: jg,
            slack: jg >= st.n,
            grad_lag: gl[jg],
            value: st.w[jg],
            lower: st.wl[jg],
            upper: st.wu[jg],
            z_lower: st.zl[jg],
            z_upper: st.zu[jg],
            row: il,
            inequality: st.slack_of_row.get(il).is_some_and(|&k| k != NO_SLACK),
            lambda: st.lam.get(il).copied().unwrap_or(0.0),
            narrow,
        });
    }

    /// Logs the iteration record, passes it to the observer and applies the termination
    /// tests; Some(status) when the solve ends here.
    pub(super) fn record_and_test(&mut self) -> Option<SolveStatus> {
        let (o, e) = (self.o, &self.opt);
        let scale = self.prob.obj_scale;
        let inf_du_u = e.inf_du / scale;
        let compl_u = self.st.complementarity(0.0) / scale;
        let rec = IterationRecord {
            iter: self.iter,
            objective: self.st.f / scale,
            inf_pr: e.inf_pr_u,
            inf_du: inf_du_u,
            mu: self.barrier.mu,
            elapsed: self.start.elapsed(),
            ..self.last_rec.clone()
        };
        self.log.push(rec.clone());
        if self.emitter.iteration(&rec).is_break() {
            return Some(SolveStatus::Interrupted);
        }
        let e = &self.opt;
        if e.err0 <= o.tol
            && e.inf_pr_u <= o.constr_viol_tol
            && inf_du_u <= o.dual_inf_tol
            && compl_u <= o.compl_inf_tol
        {
            return Some(SolveStatus::Optimal);
        }
        if e.err0 <= o.acceptable_tol
            && e.inf_pr_u <= ACCEPTABLE_UNSCALED
            && compl_u <= ACCEPTABLE_UNSCALED
        {
            self.acceptable_count += 1;
            if self.acceptable_count >= o.acceptable_iter {
                return Some(SolveStatus::Acceptable);
            }
        } else {
            self.acceptable_count = 0;
        }
        if self.iter >= o.max_iter {
            return Some(SolveStatus::MaxIterations);
        }
        if o.time_limit
            .is_some_and(|limit| self.start.elapsed() >= limit)
        {
            return Some(SolveStatus::TimeLimit);
        }
        if inf_norm(&self.st.w[..self.st.n]) > DIVERGING {
            return Some(SolveStatus::Diverging);
        }
        None
    }
}
