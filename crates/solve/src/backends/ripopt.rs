//! The pure-Rust `ripopt` interior-point solver as a [`Solver`] backend (cargo feature
//! `ripopt`).
//!
//! ripopt follows IPOPT's filter line-search algorithm; its KKT systems are factorised by
//! the pure-Rust multifrontal LDLᵀ `feral` (dense Bunch–Kaufman below 110 unknowns). Options
//! map one-to-one to ripopt's, except two that ripopt fixes: the L-BFGS history (6 pairs)
//! and the acceptable tolerance (1e-6); other values are rejected with
//! [`SolveError::InvalidOption`]. ripopt does not report linear-solver time or factorisation
//! counts, so those result fields stay zero.

use std::ffi::c_void;

use ripopt::{NlpProblem, NlpScalingMethod};

use crate::backends::monitor::{intermediate_callback, Monitor, StopReason};
use crate::backends::residuals::residuals;
use crate::backends::setup::{prepare, Prepared};
use crate::backends::timed::TimedNlp;
use crate::nlp::{check_finite, Nlp, NlpFunction};
use crate::observer::Observer;
use crate::solver::{
    HessianMode, MuStrategy, SolveError, SolveResult, SolveStatus, Solver, SolverOptions,
};

/// L-BFGS history length that ripopt hard-codes (IPOPT's default).
pub const RIPOPT_LBFGS_HISTORY: usize = 6;
/// Acceptable tolerance that ripopt hard-codes (IPOPT's default).
pub const RIPOPT_ACCEPTABLE_TOL: f64 = 1e-6;

/// The ripopt backend; `extra` tweaks ripopt-specific options after the shared ones are set.
#[derive(Clone, Default)]
pub struct RipoptSolver {
    /// Optional hook applied to ripopt's own options last (e.g. `linear_solver`).
    pub extra: Option<fn(&mut ripopt::SolverOptions)>,
}

impl std::fmt::Debug for RipoptSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RipoptSolver")
            .field("extra", &self.extra.is_some())
            .finish()
    }
}

/// Translates the shared options into ripopt's, rejecting what ripopt cannot honour.
pub fn ripopt_options(o: &SolverOptions) -> Result<ripopt::SolverOptions, SolveError> {
    if o.tol <= 0.0 || o.tol.is_nan() {
        return Err(SolveError::InvalidOption {
            name: "tol",
            reason: format!("must be > 0, got {}", o.tol),
        });
    }
    super::setup::reject_ipm_only(o, "ripopt")?;
    if o.warm_start {
        return Err(SolveError::InvalidOption {
            name: "warm_start",
            reason: "ripopt always starts its bound multipliers at 1; use the stride-ipm or \
                     IPOPT backend for a warm start"
                .into(),
        });
    }
    let mut r = ripopt::SolverOptions {
        tol: o.tol,
        max_iter: o.max_iter,
        print_level: match o.print_level {
            0 => 0,
            1 => 3,
            _ => 5,
        },
        mu_init: o.mu_init,
        mu_strategy_adaptive: o.mu_strategy == MuStrategy::Adaptive,
        acceptable_iter: o.acceptable_iter,
        constr_viol_tol: o.constr_viol_tol,
        dual_inf_tol: o.dual_inf_tol,
        compl_inf_tol: o.compl_inf_tol,
        nlp_scaling_method: if o.nlp_scaling {
            NlpScalingMethod::Gradient
        } else {
            NlpScalingMethod::None
        },
        nlp_scaling_max_gradient: o.nlp_scaling_max_gradient,
        bound_push: o.bound_push,
        bound_frac: o.bound_push,
        max_wall_time: o.time_limit.map_or(0.0, |d| d.as_secs_f64()),
        ..ripopt::SolverOptions::default()
    };
    if let HessianMode::LimitedMemory { history } = o.hessian {
        if history != RIPOPT_LBFGS_HISTORY {
            return Err(SolveError::InvalidOption {
                name: "hessian",
                reason: format!(
                    "ripopt keeps exactly {RIPOPT_LBFGS_HISTORY} L-BFGS pairs, got {history}"
                ),
            });
        }
        r.hessian_approximation_lbfgs = true;
    }
    if o.acceptable_tol != RIPOPT_ACCEPTABLE_TOL {
        return Err(SolveError::InvalidOption {
            name: "acceptable_tol",
            reason: format!(
                "ripopt fixes the acceptable tolerance at {RIPOPT_ACCEPTABLE_TOL:e}, got {:e}",
                o.acceptable_tol
            ),
        });
    }
    Ok(r)
}

/// Maps ripopt's final status onto the shared one (`stop` says whether we stopped it).
fn map_status(s: ripopt::SolveStatus, stop: Option<StopReason>) -> SolveStatus {
    use ripopt::SolveStatus as R;
    match s {
        R::Optimal => SolveStatus::Optimal,
        R::Acceptable => SolveStatus::Acceptable,
        R::Infeasible | R::LocalInfeasibility => SolveStatus::Infeasible,
        R::MaxIterations => SolveStatus::MaxIterations,
        R::MaxTimeExceeded => SolveStatus::TimeLimit,
        R::DivergingIterates => SolveStatus::Diverging,
        R::StopAtTinyStep => SolveStatus::SmallStep,
        R::UserRequestedStop => match stop {
            Some(StopReason::TimeLimit) => SolveStatus::TimeLimit,
            Some(StopReason::ObserverPanic) => {
                SolveStatus::Failed("the iteration observer panicked".into())
            }
            _ => SolveStatus::Interrupted,
        },
        R::NumericalError => SolveStatus::Failed("ripopt: numerical error".into()),
        R::RestorationFailed => SolveStatus::Failed("ripopt: restoration failed".into()),
        R::EvaluationError => SolveStatus::Failed("ripopt: evaluation error".into()),
        R::InternalError => SolveStatus::Failed("ripopt: internal error".into()),
    }
}

/// Our [`Nlp`] seen through ripopt's problem trait (evaluation errors become `false`).
struct Adapter<'a, 'p> {
    nlp: &'a TimedNlp<'p>,
    prep: &'a Prepared,
}

impl NlpProblem for Adapter<'_, '_> {
    fn num_variables(&self) -> usize {
        self.nlp.inner().n()
    }
    fn num_constraints(&self) -> usize {
        self.nlp.inner().m()
    }
    fn bounds(&self, x_l: &mut [f64], x_u: &mut [f64]) {
        x_l.copy_from_slice(&self.prep.bounds.x_l);
        x_u.copy_from_slice(&self.prep.bounds.x_u);
    }
    fn constraint_bounds(&self, g_l: &mut [f64], g_u: &mut [f64]) {
        g_l.copy_from_slice(&self.prep.bounds.g_l);
        g_u.copy_from_slice(&self.prep.bounds.g_u);
    }
    fn initial_point(&self, x0: &mut [f64]) {
        x0.copy_from_slice(&self.prep.x0);
    }
    fn objective(&self, x: &[f64], _new_x: bool, obj: &mut f64) -> bool {
        match self.nlp.objective(x) {
            Ok(f) if f.is_finite() => {
                *obj = f;
                true
            }
            _ => false,
        }
    }
    fn gradient(&self, x: &[f64], _new_x: bool, grad: &mut [f64]) -> bool {
        self.nlp.gradient(x, grad).is_ok() && check_finite(NlpFunction::Gradient, grad).is_ok()
    }
    fn constraints(&self, x: &[f64], _new_x: bool, g: &mut [f64]) -> bool {
        self.nlp.constraints(x, g).is_ok() && check_finite(NlpFunction::Constraints, g).is_ok()
    }
    fn jacobian_structure(&self) -> (Vec<usize>, Vec<usize>) {
        let s = &self.prep.structures.jacobian;
        (s.rows.clone(), s.cols.clone())
    }
    fn jacobian_values(&self, x: &[f64], _new_x: bool, vals: &mut [f64]) -> bool {
        self.nlp.jacobian_values(x, vals).is_ok()
            && check_finite(NlpFunction::Jacobian, vals).is_ok()
    }
    fn hessian_structure(&self) -> (Vec<usize>, Vec<usize>) {
        let s = &self.prep.structures.hessian;
        (s.rows.clone(), s.cols.clone())
    }
    fn hessian_values(
        &self,
        x: &[f64],
        _new_x: bool,
        obj_factor: f64,
        lambda: &[f64],
        vals: &mut [f64],
    ) -> bool {
        self.nlp.hessian_values(x, obj_factor, lambda, vals).is_ok()
            && check_finite(NlpFunction::Hessian, vals).is_ok()
    }
}

/// Clears ripopt's thread-local intermediate callback when dropped (also on panic).
struct CallbackGuard;
impl Drop for CallbackGuard {
    fn drop(&mut self) {
        ripopt::intermediate::set_intermediate_callback(None);
    }
}

impl Solver for RipoptSolver {
    fn name(&self) -> &str {
        "ripopt"
    }
    fn supports_warm_start(&self) -> bool {
        false
    }

    fn solve(
        &self,
        nlp: &dyn Nlp,
        options: &SolverOptions,
        observer: &mut dyn Observer,
    ) -> Result<SolveResult, SolveError> {
        let mut ropts = ripopt_options(options)?;
        if let Some(extra) = self.extra {
            extra(&mut ropts);
        }
        let prep = prepare(nlp)?;
        let timed = TimedNlp::new(nlp);
        let adapter = Adapter {
            nlp: &timed,
            prep: &prep,
        };
        let mut monitor = Monitor::new(observer, options.time_limit);
        let r = {
            let _guard = CallbackGuard;
            ripopt::intermediate::set_intermediate_callback(Some((
                intermediate_callback,
                &mut monitor as *mut Monitor as *mut c_void,
            )));
            ripopt::solve(&adapter, &ropts)
        };
        let time_total = monitor.start.elapsed();
        let counts = timed.counts();
        let mut status = map_status(r.status, monitor.stop);
        if r.status == ripopt::SolveStatus::EvaluationError {
            if let Some(e) = timed.first_error() {
                status = SolveStatus::Failed(format!("ripopt: evaluation error: {e}"));
            }
        }
        let (n, m) = (nlp.n(), nlp.m());
        let fix = |v: Vec<f64>, len: usize| if v.len() == len { v } else { vec![0.0; len] };
        let x = if r.x.len() == n { r.x } else { prep.x0.clone() };
        let lambda = fix(r.constraint_multipliers, m);
        let z_l = fix(r.bound_multipliers_lower, n);
        let z_u = fix(r.bound_multipliers_upper, n);
        let res = residuals(
            nlp,
            &prep.bounds,
            &prep.structures.jacobian,
            &x,
            &lambda,
            &z_l,
            &z_u,
        );
        let (constraint_violation, dual_infeasibility) = match res {
            Ok(res) => (res.constraint_violation, res.dual_infeasibility),
            Err(_) => (f64::NAN, f64::NAN),
        };
        Ok(SolveResult {
            status,
            iterations: r.iterations,
            objective: r.objective,
            constraint_violation,
            dual_infeasibility,
            x,
            lambda,
            z_l,
            z_u,
            time_total,
            time_evaluations: counts.time,
            time_linear_solver: Default::default(),
            time_symbolic: Default::default(),
            time_factorisation: Default::default(),
            solves: 0,
            time_solves: Default::default(),
            factorizations: 0,
            objective_evaluations: counts.objective,
            exact_hessian_from: None,
            log: monitor.log,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::backends::tests::{assert_hs071, assert_rosenbrock, run, Hs071, Rosenbrock};
    use crate::solver::{ControlFlow, IterationRecord};

    #[test]
    fn hs071_exact_hessian() {
        let r = run(&RipoptSolver::default(), &Hs071, &SolverOptions::default());
        assert_hs071(&r);
        assert!(r.objective_evaluations > 0);
    }

    #[test]
    fn hs071_limited_memory() {
        let o = SolverOptions {
            hessian: HessianMode::LimitedMemory { history: 6 },
            ..SolverOptions::default()
        };
        assert_hs071(&run(&RipoptSolver::default(), &Hs071, &o));
    }

    #[test]
    fn rosenbrock() {
        let r = run(
            &RipoptSolver::default(),
            &Rosenbrock,
            &SolverOptions::default(),
        );
        assert_rosenbrock(&r);
    }

    #[test]
    fn observer_break_interrupts() {
        let mut obs = |r: &IterationRecord| {
            if r.iter >= 2 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        };
        let r = RipoptSolver::default()
            .solve(&Rosenbrock, &SolverOptions::default(), &mut obs)
            .unwrap();
        assert_eq!(r.status, SolveStatus::Interrupted);
        assert_eq!(r.log.len(), 3);
    }

    #[test]
    fn unsupported_options_are_rejected() {
        let o = SolverOptions {
            hessian: HessianMode::LimitedMemory { history: 10 },
            ..SolverOptions::default()
        };
        let e = ripopt_options(&o).unwrap_err();
        assert!(matches!(
            e,
            SolveError::InvalidOption {
                name: "hessian",
                ..
            }
        ));
        let o = SolverOptions {
            acceptable_tol: 1e-3,
            ..SolverOptions::default()
        };
        assert!(ripopt_options(&o).is_err());
        let o = SolverOptions {
            hessian: HessianMode::Hybrid { history: 6 },
            ..SolverOptions::default()
        };
        let e = ripopt_options(&o).unwrap_err();
        assert!(matches!(
            e,
            SolveError::InvalidOption {
                name: "hessian",
                ..
            }
        ));
        // no multiplier initialisation: the warm start is refused and not advertised
        let o = SolverOptions {
            warm_start: true,
            ..SolverOptions::default()
        };
        let e = ripopt_options(&o).unwrap_err();
        assert!(matches!(
            e,
            SolveError::InvalidOption {
                name: "warm_start",
                ..
            }
        ));
        assert!(!RipoptSolver::default().supports_warm_start());
    }
}
