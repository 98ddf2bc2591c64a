//! The system IPOPT library as a [`Solver`] backend (cargo feature `ipopt`), through its C
//! interface with the MUMPS linear solver.
//!
//! Needs `coinor-libipopt-dev` and `pkg-config` at build time (see `build.rs`). Problem
//! evaluations are timed on stride's side; the wall-clock limit and the observer are enforced
//! from IPOPT's intermediate callback (so they act once per iteration). IPOPT's C interface
//! reports neither linear-solver time nor factorisation counts: those fields stay zero.
//! Solves are serialised by a process-wide lock because Debian's sequential MUMPS (with its
//! fake MPI layer) is not safe to run from several threads at once.

pub mod ffi;

use std::cell::{Cell, RefCell};
use std::ffi::{c_int, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Mutex;

use ffi::{Bool, Index, Number, UserDataPtr};

use crate::backends::monitor::{Monitor, StopReason};
use crate::backends::residuals::residuals;
use crate::backends::setup::{prepare, Prepared};
use crate::backends::timed::TimedNlp;
use crate::nlp::{check_finite, Nlp, NlpFunction};
use crate::observer::Observer;
use crate::solver::{
    HessianMode, IterationRecord, MuStrategy, SolveError, SolveResult, SolveStatus, Solver,
    SolverOptions,
};

/// Serialises IPOPT solves within the process (sequential MUMPS is not thread-safe).
static IPOPT_LOCK: Mutex<()> = Mutex::new(());

/// The system-IPOPT backend (MUMPS); `linear_solver` may name another IPOPT linear solver.
#[derive(Debug, Clone)]
pub struct IpoptSolver {
    /// IPOPT `linear_solver` option (default "mumps", the one Debian ships).
    pub linear_solver: String,
}

impl Default for IpoptSolver {
    fn default() -> Self {
        IpoptSolver {
            linear_solver: "mumps".into(),
        }
    }
}

/// One IPOPT option value.
#[derive(Debug, Clone, PartialEq)]
pub enum OptionValue {
    /// A string option.
    Str(String),
    /// A numeric option.
    Num(f64),
    /// An integer option.
    Int(i32),
}

/// The IPOPT options equivalent to the shared options (keyword, value).
pub fn ipopt_options(
    o: &SolverOptions,
    linear_solver: &str,
) -> Result<Vec<(&'static str, OptionValue)>, SolveError> {
    use OptionValue::{Int, Num, Str};
    super::setup::reject_ipm_only(o, "IPOPT")?;
    let int = |name: &'static str, v: usize| {
        i32::try_from(v).map_err(|_| SolveError::InvalidOption {
            name,
            reason: format!("{v} does not fit IPOPT's 32-bit integer"),
        })
    };
    let mut v = vec![
        ("tol", Num(o.tol)),
        ("max_iter", Int(int("max_iter", o.max_iter)?)),
        (
            "print_level",
            Int(match o.print_level {
                0 => 0,
                1 => 3,
                _ => 5,
            }),
        ),
        ("acceptable_tol", Num(o.acceptable_tol)),
        (
            "acceptable_iter",
            Int(int("acceptable_iter", o.acceptable_iter)?),
        ),
        ("constr_viol_tol", Num(o.constr_viol_tol)),
        ("dual_inf_tol", Num(o.dual_inf_tol)),
        ("compl_inf_tol", Num(o.compl_inf_tol)),
        (
            "mu_strategy",
            Str(match o.mu_strategy {
                MuStrategy::Monotone => "monotone".into(),
                MuStrategy::Adaptive => "adaptive".into(),
            }),
        ),
        ("mu_init", Num(o.mu_init)),
        (
            "nlp_scaling_method",
            Str(if o.nlp_scaling {
                "gradient-based".into()
            } else {
                "none".into()
            }),
        ),
        ("nlp_scaling_max_gradient", Num(o.nlp_scaling_max_gradient)),
        ("bound_push", Num(o.bound_push)),
        ("bound_frac", Num(o.bound_push)),
        ("linear_solver", Str(linear_solver.into())),
    ];
    if o.warm_start {
        // bound multipliers μ_init / slack, as the pure-Rust interior point's warm start
        v.push(("bound_mult_init_method", Str("mu-based".into())));
    }
    match o.hessian {
        HessianMode::Exact => v.push(("hessian_approximation", Str("exact".into()))),
        HessianMode::LimitedMemory { history } | HessianMode::Hybrid { history } => {
            v.push(("hessian_approximation", Str("limited-memory".into())));
            v.push((
                "limited_memory_max_history",
                Int(int("limited_memory_max_history", history)?),
            ));
        }
    }
    Ok(v)
}

/// Everything the C callbacks need, reached through IPOPT's `user_data` pointer.
struct Ctx<'a, 'p, 'o> {
    nlp: &'a TimedNlp<'p>,
    prep: &'a Prepared,
    monitor: RefCell<Monitor<'o>>,
    last_iter: Cell<Index>,
    panicked: Cell<bool>,
}

/// A read-only slice from an IPOPT pointer (empty when `len` is 0, whatever the pointer).
///
/// # Safety
/// When `len > 0`, `p` must point to `len` valid numbers.
unsafe fn slice<'s, T>(p: *const T, len: usize) -> &'s [T] {
    if len == 0 || p.is_null() {
        &[]
    } else {
        // SAFETY: guaranteed by the caller.
        unsafe { std::slice::from_raw_parts(p, len) }
    }
}

/// A mutable slice from an IPOPT pointer (empty when `len` is 0).
///
/// # Safety
/// When `len > 0`, `p` must point to `len` valid, unaliased numbers.
unsafe fn slice_mut<'s, T>(p: *mut T, len: usize) -> &'s mut [T] {
    if len == 0 || p.is_null() {
        &mut []
    } else {
        // SAFETY: guaranteed by the caller.
        unsafe { std::slice::from_raw_parts_mut(p, len) }
    }
}

/// Runs `f` on the context behind `ud`, turning panics into a failed evaluation.
///
/// # Safety
/// `ud` must point to the live `Ctx` of the running solve.
unsafe fn with_ctx(ud: UserDataPtr, f: impl FnOnce(&Ctx) -> bool) -> Bool {
    // SAFETY: guaranteed by the caller; only shared references are formed.
    let ctx = unsafe { &*(ud as *const Ctx) };
    match catch_unwind(AssertUnwindSafe(|| f(ctx))) {
        Ok(ok) => Bool::from(ok),
        Err(_) => {
            ctx.panicked.set(true);
            0
        }
    }
}

unsafe extern "C" fn eval_f(
    n: Index,
    x: *mut Number,
    _new_x: Bool,
    obj: *mut Number,
    ud: UserDataPtr,
) -> Bool {
    unsafe {
        with_ctx(ud, |c| {
            let x = slice(x, n as usize);
            match c.nlp.objective(x) {
                Ok(f) if f.is_finite() => {
                    *obj = f;
                    true
                }
                _ => false,
            }
        })
    }
}

unsafe extern "C" fn eval_grad_f(
    n: Index,
    x: *mut Number,
    _new_x: Bool,
    grad: *mut Number,
    ud: UserDataPtr,
) -> Bool {
    unsafe {
        with_ctx(ud, |c| {
            let g = slice_mut(grad, n as usize);
            c.nlp.gradient(slice(x, n as usize), g).is_ok()
                && check_finite(NlpFunction::Gradient, g).is_ok()
        })
    }
}

unsafe extern "C" fn eval_g(
    n: Index,
    x: *mut Number,
    _new_x: Bool,
    m: Index,
    g: *mut Number,
    ud: UserDataPtr,
) -> Bool {
    unsafe {
        with_ctx(ud, |c| {
            let g = slice_mut(g, m as usize);
            c.nlp.constraints(slice(x, n as usize), g).is_ok()
                && check_finite(NlpFunction::Constraints, g).is_ok()
        })
    }
}

unsafe extern "C" fn eval_jac_g(
    n: Index,
    x: *mut Number,
    _new_x: Bool,
    _m: Index,
    nele: Index,
    i_row: *mut Index,
    j_col: *mut Index,
    values: *mut Number,
    ud: UserDataPtr,
) -> Bool {
    unsafe {
        with_ctx(ud, |c| {
            let nele = nele as usize;
            if values.is_null() {
                let s = &c.prep.structures.jacobian;
                let (rows, cols) = (slice_mut(i_row, nele), slice_mut(j_col, nele));
                for k in 0..nele {
                    rows[k] = s.rows[k] as Index;
                    cols[k] = s.cols[k] as Index;
                }
                true
            } else {
                let v = slice_mut(values, nele);
                c.nlp.jacobian_values(slice(x, n as usize), v).is_ok()
                    && check_finite(NlpFunction::Jacobian, v).is_ok()
            }
        })
    }
}

unsafe extern "C" fn eval_h(
    n: Index,
    x: *mut Number,
    _new_x: Bool,
    obj_factor: Number,
    m: Index,
    lambda: *mut Number,
    _new_lambda: Bool,
    nele: Index,
    i_row: *mut Index,
    j_col: *mut Index,
    values: *mut Number,
    ud: UserDataPtr,
) -> Bool {
    unsafe {
        with_ctx(ud, |c| {
            let nele = nele as usize;
            if values.is_null() {
                let s = &c.prep.structures.hessian;
                let (rows, cols) = (slice_mut(i_row, nele), slice_mut(j_col, nele));
                for k in 0..nele {
                    rows[k] = s.rows[k] as Index;
                    cols[k] = s.cols[k] as Index;
                }
                true
            } else {
                let v = slice_mut(values, nele);
                let lam = slice(lambda, m as usize);
                c.nlp
                    .hessian_values(slice(x, n as usize), obj_factor, lam, v)
                    .is_ok()
                    && check_finite(NlpFunction::Hessian, v).is_ok()
            }
        })
    }
}

#[allow(clippy::too_many_arguments)]
unsafe extern "C" fn intermediate(
    _alg_mod: Index,
    iter_count: Index,
    obj_value: Number,
    inf_pr: Number,
    inf_du: Number,
    mu: Number,
    d_norm: Number,
    regularization_size: Number,
    alpha_du: Number,
    alpha_pr: Number,
    ls_trials: Index,
    ud: UserDataPtr,
) -> Bool {
    unsafe {
        with_ctx(ud, |c| {
            c.last_iter.set(iter_count);
            if c.panicked.get() {
                return false;
            }
            let rec = IterationRecord {
                objective: obj_value,
                inf_pr,
                inf_du,
                mu,
                step_norm: d_norm,
                alpha_pr,
                alpha_du,
                regularisation: regularization_size,
                ls_trials: ls_trials.max(0) as usize,
                ..IterationRecord::default()
            };
            c.monitor.borrow_mut().record(rec)
        })
    }
}

/// Owns an `IpoptProblem` and frees it on drop.
struct Problem(ffi::IpoptProblem);
impl Drop for Problem {
    fn drop(&mut self) {
        // SAFETY: created by CreateIpoptProblem and freed exactly once.
        unsafe { ffi::FreeIpoptProblem(self.0) }
    }
}

impl Problem {
    /// Sets one option, failing with the option's name when IPOPT rejects it.
    fn set(&self, name: &'static str, value: &OptionValue) -> Result<(), SolveError> {
        let key = CString::new(name).expect("option names have no NUL");
        // SAFETY: the handle is live; IPOPT copies the strings.
        let ok = unsafe {
            match value {
                OptionValue::Num(v) => ffi::AddIpoptNumOption(self.0, key.as_ptr() as *mut _, *v),
                OptionValue::Int(v) => ffi::AddIpoptIntOption(self.0, key.as_ptr() as *mut _, *v),
                OptionValue::Str(s) => {
                    let val = CString::new(s.as_str()).map_err(|_| SolveError::InvalidOption {
                        name,
                        reason: "contains a NUL byte".into(),
                    })?;
                    ffi::AddIpoptStrOption(self.0, key.as_ptr() as *mut _, val.as_ptr() as *mut _)
                }
            }
        };
        if ok == 0 {
            return Err(SolveError::InvalidOption {
                name,
                reason: format!("IPOPT rejected the value {value:?}"),
            });
        }
        Ok(())
    }
}

/// Maps IPOPT's return code to the shared status, or to an error for definition problems.
fn map_status(
    code: c_int,
    stop: Option<StopReason>,
    panicked: bool,
) -> Result<SolveStatus, SolveError> {
    use ffi::status::*;
    Ok(match code {
        SOLVE_SUCCEEDED => SolveStatus::Optimal,
        SOLVED_TO_ACCEPTABLE_LEVEL => SolveStatus::Acceptable,
        INFEASIBLE_PROBLEM_DETECTED => SolveStatus::Infeasible,
        SEARCH_DIRECTION_BECOMES_TOO_SMALL => SolveStatus::SmallStep,
        DIVERGING_ITERATES => SolveStatus::Diverging,
        USER_REQUESTED_STOP if panicked => {
            SolveStatus::Failed("a problem function panicked".into())
        }
        USER_REQUESTED_STOP => match stop {
            Some(StopReason::TimeLimit) => SolveStatus::TimeLimit,
            Some(StopReason::ObserverPanic) => {
                SolveStatus::Failed("the iteration observer panicked".into())
            }
            _ => SolveStatus::Interrupted,
        },
        FEASIBLE_POINT_FOUND => SolveStatus::Failed("IPOPT: feasible point found".into()),
        MAXIMUM_ITERATIONS_EXCEEDED => SolveStatus::MaxIterations,
        MAXIMUM_CPUTIME_EXCEEDED | MAXIMUM_WALLTIME_EXCEEDED => SolveStatus::TimeLimit,
        RESTORATION_FAILED => SolveStatus::Failed("IPOPT: restoration failed".into()),
        ERROR_IN_STEP_COMPUTATION => SolveStatus::Failed("IPOPT: error in step computation".into()),
        INVALID_NUMBER_DETECTED => {
            SolveStatus::Failed("IPOPT: invalid number (NaN/Inf) in problem functions".into())
        }
        NOT_ENOUGH_DEGREES_OF_FREEDOM => {
            return Err(SolveError::Backend(
                "IPOPT: not enough degrees of freedom (more equality constraints than free \
                 variables)"
                    .into(),
            ))
        }
        INVALID_PROBLEM_DEFINITION => {
            return Err(SolveError::Backend(
                "IPOPT: invalid problem definition".into(),
            ))
        }
        INVALID_OPTION => return Err(SolveError::Backend("IPOPT: invalid option".into())),
        other => SolveStatus::Failed(format!("IPOPT: return code {other}")),
    })
}

/// Converts a size to IPOPT's 32-bit index, or explains which size is too large.
fn index(what: &'static str, v: usize) -> Result<Index, SolveError> {
    Index::try_from(v).map_err(|_| {
        SolveError::Backend(format!("{what} = {v} exceeds IPOPT's 32-bit index range"))
    })
}

impl Solver for IpoptSolver {
    fn name(&self) -> &str {
        "ipopt"
    }

    fn solve(
        &self,
        nlp: &dyn Nlp,
        options: &SolverOptions,
        observer: &mut dyn Observer,
    ) -> Result<SolveResult, SolveError> {
        let opts = ipopt_options(options, &self.linear_solver)?;
        let prep = prepare(nlp)?;
        let (n, m) = (nlp.n(), nlp.m());
        let nele_jac = index("Jacobian nonzeros", prep.structures.jacobian.nnz())?;
        let nele_hess = match options.hessian {
            HessianMode::Exact => index("Hessian nonzeros", prep.structures.hessian.nnz())?,
            HessianMode::LimitedMemory { .. } | HessianMode::Hybrid { .. } => 0,
        };
        let (ni, mi) = (index("n", n)?, index("m", m)?);
        let mut b = prep.bounds.clone();
        let _lock = IPOPT_LOCK.lock().unwrap_or_else(|e| e.into_inner());
        // SAFETY: bound arrays have lengths n and m and are copied by IPOPT.
        let raw = unsafe {
            ffi::CreateIpoptProblem(
                ni,
                b.x_l.as_mut_ptr(),
                b.x_u.as_mut_ptr(),
                mi,
                b.g_l.as_mut_ptr(),
                b.g_u.as_mut_ptr(),
                nele_jac,
                nele_hess,
                0,
                eval_f,
                eval_g,
                eval_grad_f,
                eval_jac_g,
                eval_h,
            )
        };
        if raw.is_null() {
            return Err(SolveError::Backend(
                "IPOPT: CreateIpoptProblem returned null".into(),
            ));
        }
        let problem = Problem(raw);
        if options.print_level == 0 {
            // Suppresses the banner; harmless if this IPOPT does not know the option.
            let _ = problem.set("sb", &OptionValue::Str("yes".into()));
        }
        for (name, value) in &opts {
            problem.set(name, value)?;
        }
        // SAFETY: the handle is live and the callback has the C signature IPOPT expects.
        unsafe { ffi::SetIntermediateCallback(problem.0, intermediate) };

        let timed = TimedNlp::new(nlp);
        let ctx = Ctx {
            nlp: &timed,
            prep: &prep,
            monitor: RefCell::new(Monitor::new(observer, options.time_limit)),
            last_iter: Cell::new(0),
            panicked: Cell::new(false),
        };
        let mut x = prep.x0.clone();
        let mut g = vec![0.0; m];
        let mut obj = f64::NAN;
        let mut lambda = vec![0.0; m];
        let mut z_l = vec![0.0; n];
        let mut z_u = vec![0.0; n];
        // SAFETY: all arrays have the sizes declared to CreateIpoptProblem; `ctx` outlives
        // the call and the callbacks only form shared references to it.
        let code = unsafe {
            ffi::IpoptSolve(
                problem.0,
                x.as_mut_ptr(),
                g.as_mut_ptr(),
                &mut obj,
                lambda.as_mut_ptr(),
                z_l.as_mut_ptr(),
                z_u.as_mut_ptr(),
                &ctx as *const Ctx as UserDataPtr,
            )
        };
        drop(problem);
        drop(_lock);
        let Ctx {
            monitor,
            last_iter,
            panicked,
            ..
        } = ctx;
        let monitor = monitor.into_inner();
        let time_total = monitor.start.elapsed();
        let status = map_status(code, monitor.stop, panicked.get())?;
        let counts = timed.counts();
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
            Ok(r) => (r.constraint_violation, r.dual_infeasibility),
            Err(_) => (f64::NAN, f64::NAN),
        };
        Ok(SolveResult {
            status,
            iterations: last_iter.get().max(0) as usize,
            objective: obj,
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
    use crate::solver::ControlFlow;

    #[test]
    fn hs071_exact_hessian() {
        let r = run(&IpoptSolver::default(), &Hs071, &SolverOptions::default());
        assert_hs071(&r);
        assert_eq!(r.log.len(), r.iterations + 1, "log has iteration 0 too");
    }

    #[test]
    fn hs071_limited_memory() {
        let o = SolverOptions {
            hessian: HessianMode::LimitedMemory { history: 6 },
            ..SolverOptions::default()
        };
        assert_hs071(&run(&IpoptSolver::default(), &Hs071, &o));
    }

    #[test]
    fn hs071_warm_start_option_is_accepted() {
        // mu-based bound multipliers from a small μ: IPOPT takes the option and converges
        let o = SolverOptions {
            warm_start: true,
            mu_init: 1e-3,
            ..SolverOptions::default()
        };
        assert_hs071(&run(&IpoptSolver::default(), &Hs071, &o));
    }

    #[test]
    fn rosenbrock() {
        let r = run(
            &IpoptSolver::default(),
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
        let r = IpoptSolver::default()
            .solve(&Rosenbrock, &SolverOptions::default(), &mut obs)
            .unwrap();
        assert_eq!(r.status, SolveStatus::Interrupted);
        assert_eq!(r.log.len(), 3);
    }

    #[test]
    fn hybrid_hessian_is_an_option_error() {
        let o = SolverOptions {
            hessian: HessianMode::Hybrid { history: 6 },
            ..SolverOptions::default()
        };
        let e = ipopt_options(&o, "mumps").unwrap_err();
        assert!(
            matches!(
                e,
                SolveError::InvalidOption {
                    name: "hessian",
                    ..
                }
            ),
            "{e}"
        );
    }

    #[test]
    fn unknown_linear_solver_is_an_option_error() {
        let s = IpoptSolver {
            linear_solver: "no-such-solver".into(),
        };
        let mut obs = |_: &IterationRecord| ControlFlow::Continue(());
        let e = s
            .solve(&Hs071, &SolverOptions::default(), &mut obs)
            .unwrap_err();
        assert!(
            matches!(
                e,
                SolveError::InvalidOption {
                    name: "linear_solver",
                    ..
                }
            ),
            "{e}"
        );
    }
}
