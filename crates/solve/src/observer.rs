//! What a solve reports while it runs: one [`IterationRecord`] per iteration (the observer
//! may stop the solve there) and typed [`Diagnostic`] events about the solver's internals.
//!
//! Library code never prints: a caller that wants the events on a terminal implements
//! [`Observer::diagnostic`] and formats them (the `Display` of [`Diagnostic`] gives one
//! line per event). Which events a solve emits is set by `SolverOptions::print_level`.

use std::fmt;
use std::time::Duration;

use crate::pivots::Inertia;
use serde::{Deserialize, Serialize};
use std::ops::ControlFlow as StdControlFlow;

/// What the observer callback tells the solver after each iteration.
pub type ControlFlow = StdControlFlow<()>;

/// How a solve ended.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum SolveStatus {
    /// Converged to `tol`.
    Optimal,
    /// Converged to the acceptable level `acceptable_tol` for `acceptable_iter` iterations.
    Acceptable,
    /// Hit `max_iter`.
    MaxIterations,
    /// Hit `time_limit`.
    TimeLimit,
    /// Converged to a point of locally minimal constraint violation that is infeasible.
    Infeasible,
    /// The observer asked to stop.
    Interrupted,
    /// The step became too small to make progress.
    SmallStep,
    /// Iterates diverged (|x| huge) — problem probably unbounded.
    Diverging,
    /// Any other failure, with a reason.
    Failed(String),
    /// μ reached its floor with the limited-memory Hessian and the solve stopped there, as
    /// asked (`SolverOptions::stop_at_mu_floor`): near an optimum, not converged to `tol`.
    MuFloor,
}

impl SolveStatus {
    /// Whether the status counts as converged (Optimal or Acceptable).
    pub fn is_success(&self) -> bool {
        matches!(self, SolveStatus::Optimal | SolveStatus::Acceptable)
    }

    /// Whether the point is good enough to start a finer or neighbouring problem from
    /// (converged, or stopped at the μ floor on request).
    pub fn is_usable_start(&self) -> bool {
        self.is_success() || matches!(self, SolveStatus::MuFloor)
    }
}

/// One line of the iteration log (in the units of the unscaled problem unless noted).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct IterationRecord {
    /// Iteration number (0 = initial point).
    pub iter: usize,
    /// Objective value f(x).
    pub objective: f64,
    /// Primal infeasibility: max constraint (incl. slack) violation.
    pub inf_pr: f64,
    /// Dual infeasibility: max-norm of the Lagrangian gradient (scaled problem).
    pub inf_du: f64,
    /// Barrier parameter μ.
    pub mu: f64,
    /// Max-norm of the primal step.
    pub step_norm: f64,
    /// Primal step length.
    pub alpha_pr: f64,
    /// Dual step length.
    pub alpha_du: f64,
    /// Hessian regularisation δ_w added for inertia correction (0 if none).
    pub regularisation: f64,
    /// Number of line-search trial points.
    pub ls_trials: usize,
    /// Numeric factorisations of the KKT matrix in the iteration that led here (inertia
    /// corrections included; 0 where the backend does not report them).
    #[serde(default)]
    pub factorisations: usize,
    /// Wall-clock time since the solve started.
    pub elapsed: Duration,
}

impl IterationRecord {
    /// The record as one line of an iteration table: iteration, objective, primal and dual
    /// infeasibility, μ, step norm, primal and dual step sizes, regularisation, line-search
    /// trials.
    pub fn table_line(&self) -> String {
        format!(
            "{:5} {:+.8e} {:.2e} {:.2e} {:.1e} {:.2e} {:.2e} {:.2e} {:.1e} {}",
            self.iter,
            self.objective,
            self.inf_pr,
            self.inf_du,
            self.mu,
            self.step_norm,
            self.alpha_pr,
            self.alpha_du,
            self.regularisation,
            self.ls_trials
        )
    }
}

/// Receives the progress of a solve.
pub trait Observer {
    /// Called after every iteration with its record; `Break` stops the solve
    /// ([`SolveStatus::Interrupted`]).
    fn iteration(&mut self, record: &IterationRecord) -> ControlFlow;
    /// Called for each diagnostic event the solve emits (default: ignored).
    fn diagnostic(&mut self, _event: &Diagnostic) {}
}

/// Any closure over the iteration records is an observer that ignores the diagnostics.
impl<F: FnMut(&IterationRecord) -> ControlFlow> Observer for F {
    fn iteration(&mut self, record: &IterationRecord) -> ControlFlow {
        self(record)
    }
}

/// A diagnostic event of the pure-Rust interior point, with the `print_level` from which
/// it is emitted ([`Diagnostic::level`]). Quantities are those of the scaled problem unless
/// noted.
#[derive(Debug, Clone, PartialEq)]
pub enum Diagnostic {
    /// The exact Hessian took over a hybrid solve at `iteration`; the KKT factor now has
    /// `factor_entries` entries (level 1).
    ExactHessianFrom {
        /// First iteration with the exact Hessian.
        iteration: usize,
        /// Entries of the new symbolic factor.
        factor_entries: usize,
    },
    /// End-of-solve summary of the interior point's safeguards and times (level 1).
    Summary(Box<SolveSummary>),
    /// One step of the feasibility restoration (level 2): constraint violation θ (1-norm)
    /// before the step, after it (None: no decrease of the restoration merit found), the
    /// last step size tried, the max-norm of the step and θ at entry to the restoration.
    RestorationStep {
        /// θ before the step.
        theta: f64,
        /// θ after the accepted step, or None.
        accepted: Option<f64>,
        /// Last step size tried.
        alpha: f64,
        /// Max-norm of the step direction.
        step_norm: f64,
        /// θ when the restoration started.
        theta_entry: f64,
    },
    /// The restoration's KKT factorisation or solve failed (level 2).
    RestorationLinearSolveFailed,
    /// Largest entries of the optimality conditions at the current iterate (level 3):
    /// the Lagrangian gradient's largest entry, at variable `index` (a slack when `slack`)
    /// with its value, bounds and bound multipliers; the largest constraint multiplier; the
    /// variables whose bound interval is narrower than 1e-6.
    LargestEntries {
        /// Variable of the largest |∇L| entry.
        index: usize,
        /// Whether that variable is a slack.
        slack: bool,
        /// ∇L there.
        grad_lag: f64,
        /// The variable's value.
        value: f64,
        /// Its lower bound.
        lower: f64,
        /// Its upper bound.
        upper: f64,
        /// Its lower-bound multiplier.
        z_lower: f64,
        /// Its upper-bound multiplier.
        z_upper: f64,
        /// Constraint row of the largest |λ|.
        row: usize,
        /// Whether that row is an inequality.
        inequality: bool,
        /// λ there.
        lambda: f64,
        /// Variables with a bound interval below 1e-6.
        narrow: usize,
    },
    /// One factorisation of the inertia correction (level 3): Hessian regularisation δ_w,
    /// the inertia found and the one wanted (n positive, m negative), and for a wrong
    /// inertia in a solve that checks the step (warm-started exact solves), whether the
    /// factor was kept for it.
    InertiaTrial {
        /// δ_w of the trial.
        delta_w: f64,
        /// Inertia of the factorised KKT matrix.
        inertia: Inertia,
        /// Wanted positive eigenvalues (variables).
        positive: usize,
        /// Wanted negative eigenvalues (constraints).
        negative: usize,
        /// Whether the Newton step was usable: positive curvature and at least half of it
        /// takeable within the bounds (None: not checked).
        step_check: Option<bool>,
    },
    /// One iterative-refinement residual of the KKT solve of right-hand side `column`
    /// (level 3).
    Refinement {
        /// Right-hand side within its block.
        column: usize,
        /// Max-norm of the residual.
        residual: f64,
        /// Max-norm of the right-hand side (at least 1).
        rhs_norm: f64,
    },
    /// A centrality corrector tried (level 3): products outside the neighbourhood of μ, and
    /// the primal and dual step sizes before and with the corrector.
    Corrector {
        /// Complementarity products outside [β_min μ, β_max μ].
        outside: usize,
        /// (primal, dual) step sizes before.
        before: (f64, f64),
        /// (primal, dual) step sizes with the corrector.
        after: (f64, f64),
    },
    /// A second-order correction tried (level 3): constraint violation θ of the corrected
    /// trial point and whether the filter accepted it.
    SecondOrderCorrection {
        /// θ at the corrected trial point.
        theta: f64,
        /// Whether the corrected point was accepted.
        accepted: bool,
    },
    /// The watchdog started (level 3).
    WatchdogStarted,
    /// The watchdog returned to its starting point (level 3).
    WatchdogReturned,
    /// Soft restoration tried a step (level 3): primal-dual error of the barrier problem
    /// before and at the trial point, and the step size.
    SoftRestoration {
        /// Error at the current point.
        error: f64,
        /// Error at the trial point.
        trial_error: f64,
        /// Step size.
        alpha: f64,
    },
    /// An L-BFGS correction pair offered (level 3): whether it was kept, the pairs stored,
    /// the initial scaling σ and sᵀy.
    LbfgsPair {
        /// Whether the pair was kept.
        kept: bool,
        /// Pairs stored after the update.
        stored: usize,
        /// Initial scaling σ of B₀ = σI.
        sigma: f64,
        /// sᵀy of the pair.
        sy: f64,
    },
}

/// Counts and times of one interior-point solve (unscaled objective and violation).
#[derive(Debug, Clone, PartialEq)]
pub struct SolveSummary {
    /// How the solve ended.
    pub status: SolveStatus,
    /// Iterations performed.
    pub iterations: usize,
    /// Feasibility restorations.
    pub restorations: usize,
    /// Soft-restoration steps.
    pub soft_steps: usize,
    /// Centrality correctors kept.
    pub correctors: usize,
    /// Watchdog starts.
    pub watchdog_starts: usize,
    /// Watchdog returns to its starting point.
    pub watchdog_returns: usize,
    /// Iteration where the exact Hessian took over, if it did.
    pub exact_from: Option<usize>,
    /// Final objective.
    pub objective: f64,
    /// Final constraint violation (max-norm).
    pub violation: f64,
    /// Total time.
    pub total: Duration,
    /// Time in function evaluations.
    pub evaluations: Duration,
    /// Time in the KKT linear solver.
    pub linear: Duration,
    /// Numeric factorisations.
    pub factorisations: usize,
    /// Time in the numeric factorisations.
    pub factorisation_time: Duration,
    /// Solve calls with the factor, right-hand-side columns and their time.
    pub solves: (usize, usize, Duration),
    /// The same for the exact-Hessian tail (when there was one).
    pub tail_solves: Option<(usize, usize, Duration)>,
}

impl Diagnostic {
    /// The smallest `SolverOptions::print_level` at which the event is emitted.
    pub fn level(&self) -> u32 {
        match self {
            Diagnostic::ExactHessianFrom { .. } | Diagnostic::Summary(_) => 1,
            Diagnostic::RestorationStep { .. } | Diagnostic::RestorationLinearSolveFailed => 2,
            _ => 3,
        }
    }
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Diagnostic::ExactHessianFrom {
                iteration,
                factor_entries,
            } => write!(
                f,
                "stride-ipm: exact Hessian from iteration {iteration} (factor {factor_entries} entries)"
            ),
            Diagnostic::Summary(s) => s.fmt(f),
            Diagnostic::RestorationStep {
                theta,
                accepted,
                alpha,
                step_norm,
                theta_entry,
            } => write!(
                f,
                "    restoration: theta {theta:.3e} -> {accepted:?} (alpha {alpha:.2e}, |dw| {step_norm:.2e}, entry {theta_entry:.3e})"
            ),
            Diagnostic::RestorationLinearSolveFailed => {
                write!(f, "    restoration: KKT factorisation or solve failed")
            }
            Diagnostic::LargestEntries { .. } => self.fmt_largest(f),
            Diagnostic::InertiaTrial {
                delta_w,
                inertia,
                positive,
                negative,
                step_check,
            } => {
                write!(
                    f,
                    "    delta_w {delta_w:.2e}: inertia {inertia:?} (want {positive}, {negative})"
                )?;
                match step_check {
                    Some(true) => write!(f, ", step usable: kept"),
                    Some(false) => write!(f, ", step not usable"),
                    None => Ok(()),
                }
            }
            Diagnostic::Refinement {
                column,
                residual,
                rhs_norm,
            } => write!(
                f,
                "    refine {column}: |res| = {residual:.3e}, |b| = {rhs_norm:.3e}"
            ),
            Diagnostic::Corrector {
                outside,
                before,
                after,
            } => write!(
                f,
                "    corrector: {outside} products outside, alpha {:.3e}/{:.3e} -> {:.3e}/{:.3e}",
                before.0, before.1, after.0, after.1
            ),
            Diagnostic::SecondOrderCorrection { theta, accepted } => write!(
                f,
                "    second-order correction: theta {theta:.3e}, {}",
                if *accepted { "accepted" } else { "rejected" }
            ),
            Diagnostic::WatchdogStarted => write!(f, "    watchdog started"),
            Diagnostic::WatchdogReturned => write!(f, "    watchdog: back to its starting point"),
            Diagnostic::SoftRestoration {
                error,
                trial_error,
                alpha,
            } => write!(
                f,
                "    soft restoration: error {error:.3e} -> {trial_error:.3e} (alpha {alpha:.2e})"
            ),
            Diagnostic::LbfgsPair {
                kept,
                stored,
                sigma,
                sy,
            } => write!(
                f,
                "    l-bfgs: pair {} ({stored} stored, sigma {sigma:.3e}, s'y {sy:.3e})",
                if *kept { "kept" } else { "skipped" }
            ),
        }
    }
}

impl Diagnostic {
    fn fmt_largest(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let Diagnostic::LargestEntries {
            index,
            slack,
            grad_lag,
            value,
            lower,
            upper,
            z_lower,
            z_upper,
            row,
            inequality,
            lambda,
            narrow,
        } = self
        else {
            return Ok(());
        };
        writeln!(
            f,
            "    max |grad L| at w[{index}] (slack: {slack}) = {grad_lag:.3e}, w = {value:.6e} in [{lower:.6e}, {upper:.6e}], zl {z_lower:.3e}, zu {z_upper:.3e}"
        )?;
        writeln!(
            f,
            "    max |lambda| at row {row} (inequality: {inequality}) = {lambda:.3e}"
        )?;
        write!(f, "    variables with bound interval < 1e-6: {narrow}")
    }
}

impl fmt::Display for SolveSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "stride-ipm: {:?} after {} iterations ({} restorations, {} soft-restoration steps, {} centrality correctors, watchdog {} started / {} returned{}), f = {:.10e}, |c| = {:.2e}, total {:.3} s (eval {:.3} s, linear {:.3} s of which {} factorisations {:.3} s)",
            self.status,
            self.iterations,
            self.restorations,
            self.soft_steps,
            self.correctors,
            self.watchdog_starts,
            self.watchdog_returns,
            self.exact_from
                .map_or(String::new(), |k| format!(", exact Hessian from iteration {k}")),
            self.objective,
            self.violation,
            self.total.as_secs_f64(),
            self.evaluations.as_secs_f64(),
            self.linear.as_secs_f64(),
            self.factorisations,
            self.factorisation_time.as_secs_f64()
        )?;
        let (calls, columns, time) = self.solves;
        write!(
            f,
            "stride-ipm: solves {calls} calls, {columns} columns, {:.3} s",
            time.as_secs_f64()
        )?;
        if let Some((calls, columns, time)) = self.tail_solves {
            write!(
                f,
                "; exact tail {calls} calls, {columns} columns, {:.3} s",
                time.as_secs_f64()
            )?;
        }
        Ok(())
    }
}

/// An observer with the diagnostic level of a solve: builds and sends only the events of
/// that level or below.
pub(crate) struct Emitter<'o> {
    observer: &'o mut dyn Observer,
    level: u32,
}

impl<'o> Emitter<'o> {
    /// Events of level ≤ `level` go to `observer`.
    pub(crate) fn new(observer: &'o mut dyn Observer, level: u32) -> Self {
        Emitter { observer, level }
    }

    /// Whether events of `level` are emitted.
    pub(crate) fn wants(&self, level: u32) -> bool {
        level <= self.level
    }

    /// Sends `event` to the observer if its level is emitted.
    pub(crate) fn emit(&mut self, event: Diagnostic) {
        if self.wants(event.level()) {
            self.observer.diagnostic(&event);
        }
    }

    /// Passes an iteration record to the observer.
    pub(crate) fn iteration(&mut self, record: &IterationRecord) -> ControlFlow {
        self.observer.iteration(record)
    }
}
