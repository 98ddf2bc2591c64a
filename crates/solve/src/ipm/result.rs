//! The result of a solve in the units of the unscaled problem, and its summary event.

use crate::ipm::iterate::inf_norm;
use crate::ipm::workspace::Ipm;
use crate::observer::{Diagnostic, SolveSummary};
use crate::solver::{SolveResult, SolveStatus};

impl Ipm<'_> {
    /// Unscaled constraint violation at the current iterate: for inequality rows the
    /// violation of g_l ≤ c ≤ g_u rather than of c − s = 0.
    fn constraint_violation(&mut self) -> f64 {
        self.measure_residuals();
        let (st, scale) = (&self.st, &self.prob.con_scale);
        if st.row_of_slack.is_empty() {
            return self
                .opt
                .r
                .iter()
                .zip(scale)
                .map(|(v, s)| (v / s).abs())
                .fold(0.0, f64::max);
        }
        let b = &self.bounds;
        let mut viol = 0.0f64;
        for (i, (&c, s)) in st.c.iter().zip(scale).enumerate() {
            let ci = c / s;
            viol = viol.max(b.g_l[i] - ci).max(ci - b.g_u[i]);
        }
        viol.max(0.0)
    }

    /// The result of the solve that ended with `status` (multipliers in IPOPT's sign
    /// convention, unscaled), after the summary event.
    pub(super) fn result(mut self, status: SolveStatus) -> SolveResult {
        let constraint_violation = self.constraint_violation();
        let (st, sf) = (&self.st, self.prob.obj_scale);
        let dual_infeasibility = inf_norm(&self.opt.gl[..st.n]) / sf;
        let lambda: Vec<f64> = st
            .lam
            .iter()
            .zip(&self.prob.con_scale)
            .map(|(l, s)| l * s / sf)
            .collect();
        let kkt = &self.kkt;
        let result = SolveResult {
            status,
            iterations: self.iter,
            objective: st.f / sf,
            constraint_violation,
            dual_infeasibility,
            x: st.w[..st.n].to_vec(),
            lambda,
            z_l: st.zl[..st.n].iter().map(|z| z / sf).collect(),
            z_u: st.zu[..st.n].iter().map(|z| z / sf).collect(),
            time_total: self.start.elapsed(),
            time_evaluations: self.prob.eval_time,
            time_linear_solver: kkt.time,
            time_symbolic: kkt.time_symbolic,
            time_factorisation: kkt.factor_time,
            solves: kkt.linear.counts.calls,
            time_solves: kkt.linear.counts.time,
            factorizations: kkt.factorizations,
            objective_evaluations: self.prob.n_obj,
            exact_hessian_from: self.stats.exact_from,
            log: {
                let mut log = std::mem::take(&mut self.log);
                log.shrink_to_fit();
                log
            },
        };
        if self.emitter.wants(1) {
            let summary = self.summary(&result);
            self.emitter.emit(Diagnostic::Summary(Box::new(summary)));
        }
        result
    }

    /// The summary of the solve that gave `result`.
    fn summary(&self, result: &SolveResult) -> SolveSummary {
        let c = self.kkt.linear.counts;
        let at = self.stats.counts_at_switch;
        SolveSummary {
            status: result.status.clone(),
            iterations: result.iterations,
            restorations: self.stats.restorations,
            soft_steps: self.stats.soft_steps,
            correctors: self.corr.kept,
            watchdog_starts: self.ls.watchdog_starts,
            watchdog_returns: self.ls.watchdog_returns,
            exact_from: self.stats.exact_from,
            objective: result.objective,
            violation: result.constraint_violation,
            total: result.time_total,
            evaluations: result.time_evaluations,
            linear: result.time_linear_solver,
            factorisations: result.factorizations,
            factorisation_time: result.time_factorisation,
            solves: (c.calls, c.columns, c.time),
            tail_solves: self
                .stats
                .exact_from
                .map(|_| (c.calls - at.calls, c.columns - at.columns, c.time - at.time)),
        }
    }
}
