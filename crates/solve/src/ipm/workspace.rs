//! The data of one interior-point solve, apart from the method: the [`Ipm`] type and the
//! workspace of each of its stages, allocated before the first iteration (Pinocchio's
//! model/data split: the problem and the options are the model, this is the data).
//!
//! Only the types live here. Each stage adds its constructor and methods in its own file
//! (`barrier`, `direction`, `correctors`, `line_search`, …) and [`super::algorithm`]
//! builds an `Ipm` and runs the iteration, so this module depends on the lower modules
//! (iterate, KKT system, L-BFGS, filter, scaled problem) and on no stage.

use std::time::Instant;

use crate::ipm::filter::{Filter, LsReference};
use crate::ipm::inertia::KktSystem;
use crate::ipm::iterate::Iterate;
use crate::ipm::lbfgs::{Lbfgs, LowRankCorrection};
use crate::ipm::linsys::SolveCounts;
use crate::ipm::scaled::ScaledNlp;
use crate::nlp::Bounds;
use crate::observer::Emitter;
use crate::solver::{IterationRecord, MuGlobalisation, MuOracle, SolverOptions};

/// The interior-point method on one problem: options, scaled problem, observer and the
/// workspace of every stage.
pub(super) struct Ipm<'a> {
    /// The solver options.
    pub o: &'a SolverOptions,
    /// When the solve started (total time, time limit).
    pub start: Instant,
    /// The problem with its gradient-based scaling and evaluation counts.
    pub prob: ScaledNlp<'a>,
    /// Variable and constraint bounds of the problem as it states them.
    pub bounds: Bounds,
    /// Sends iteration records and diagnostic events to the observer.
    pub emitter: Emitter<'a>,
    /// The current iterate (primal, multipliers, values and derivatives).
    pub st: Iterate,
    /// The KKT matrix, its factorisation and inertia correction.
    pub kkt: KktSystem<'a>,
    /// Newton steps of the iteration.
    pub newton: Newton,
    /// Centrality correctors.
    pub corr: Correctors,
    /// The barrier parameter μ and its strategy state.
    pub barrier: Barrier,
    /// Filter line-search state and trial-point buffers.
    pub ls: LineSearch,
    /// Optimality measures of the current iterate.
    pub opt: Optimality,
    /// The limited-memory Hessian, None while the exact Hessian is in use.
    pub lbfgs: Option<Quasi>,
    /// Whether the exact Hessian is in use.
    pub exact: bool,
    /// The primal point after a step.
    pub x_new: Vec<f64>,
    /// Counters of the solve.
    pub stats: Stats,
    /// Index of the current iteration (0 at the starting point).
    pub iter: usize,
    /// One record per iteration so far.
    pub log: Vec<IterationRecord>,
    /// Step data of the last iteration, for the next record.
    pub last_rec: IterationRecord,
    /// Consecutive iterations meeting the acceptable tolerances (`acceptable_iter`).
    pub acceptable_count: usize,
}

/// Optimality measures of the current iterate (scaled unless noted).
#[derive(Default)]
pub(super) struct Optimality {
    /// Equality residuals r.
    pub r: Vec<f64>,
    /// Lagrangian gradient ∇L over w.
    pub gl: Vec<f64>,
    /// ‖∇L‖∞.
    pub inf_du: f64,
    /// ‖r‖∞.
    pub inf_pr: f64,
    /// Dual and complementarity scalings s_d, s_c of the optimality error.
    pub s_d: f64,
    pub s_c: f64,
    /// Scaled optimality error E₀ (eq. 5).
    pub err0: f64,
    /// Unscaled constraint violation.
    pub inf_pr_u: f64,
    /// Whether the iterate is primal and dual feasible to the tolerances.
    pub feasible: bool,
}

/// The limited-memory Hessian and the buffers of its update.
pub(super) struct Quasi {
    /// The compact L-BFGS matrix.
    pub lbfgs: Lbfgs,
    /// x and ∇ₓL(x, λ_new) before the step.
    pub prev_x: Vec<f64>,
    pub prev_grad_lag: Vec<f64>,
    /// ∇ₓL after the step.
    pub tmp_n: Vec<f64>,
    /// Correction pair (s, y) restricted to the nonlinear variables.
    pub s_pair: Vec<f64>,
    pub y_pair: Vec<f64>,
}

/// Counters of a solve beyond the linear algebra's.
#[derive(Default)]
pub(super) struct Stats {
    /// Feasibility restorations.
    pub restorations: usize,
    /// Steps accepted by soft restoration.
    pub soft_steps: usize,
    /// Solve counts when the exact Hessian took over.
    pub counts_at_switch: SolveCounts,
    /// Iteration where the exact Hessian took over.
    pub exact_from: Option<usize>,
    /// Factorisations before the current iteration.
    pub factorizations_before: usize,
}

/// State of the barrier parameter across iterations.
pub(super) struct Barrier {
    /// Current μ.
    pub mu: f64,
    /// Fraction-to-boundary factor τ = max(0.99, 1 − μ) of the current iteration.
    pub tau: f64,
    /// Whether the adaptive strategy was asked for.
    pub want_adaptive: bool,
    /// Free (oracle) mode of the adaptive strategy; false: monotone (fixed) mode.
    pub adaptive: bool,
    /// Globalisation of the adaptive strategy.
    pub globalisation: MuGlobalisation,
    /// Free-mode oracle.
    pub oracle: MuOracle,
    /// Optimality errors of the last free-mode iterations (`kkt-error` references).
    pub(super) free_refs: Vec<f64>,
    /// (objective, θ) of the accepted free-mode iterates (`obj-constr-filter`).
    pub(super) mu_filter: Vec<(f64, f64)>,
    /// Consecutive iterations with μ at its floor (hybrid Hessian, μ-floor stop).
    pub floor_iters: usize,
}

/// A primal-dual step: primal (with slacks), constraint-multiplier and bound-multiplier
/// parts (the last two may be empty where only dw, dλ are kept).
#[derive(Default)]
pub(super) struct Step {
    /// Primal step over w = (x, s).
    pub dw: Vec<f64>,
    /// Constraint-multiplier step.
    pub dlam: Vec<f64>,
    /// Lower-bound multiplier step.
    pub dzl: Vec<f64>,
    /// Upper-bound multiplier step.
    pub dzu: Vec<f64>,
}

/// Buffers of the Newton steps of one iteration.
pub(super) struct Newton {
    /// The search direction of the iteration.
    pub main: Step,
    /// Step for μ = 0 (or for μ in fixed mode) from the iteration's block solve.
    pub aff: Step,
    /// Step for μ = average complementarity from the block solve.
    pub avg: Step,
    /// Second-order-correction step.
    pub soc: Step,
    /// Slack residuals of the last right-hand side.
    pub(super) r_s: Vec<f64>,
    /// Right-hand sides (then solutions) of the block solve, their slack residuals, and a
    /// copy of the block.
    pub(super) early_rhs: Vec<f64>,
    pub(super) early_rs: Vec<f64>,
    pub(super) early_block: Vec<f64>,
    /// The limited-memory correction of this iteration's factorisation, in use when
    /// `correction_active`.
    pub(super) correction: LowRankCorrection,
    pub(super) correction_active: bool,
    /// Whether `aff` (and `avg`) hold this iteration's block-solved steps.
    pub early_ready: bool,
}

/// Complementarity targets beyond μ of the kept correctors and of the one being tried,
/// with the tried direction.
pub(super) struct Correctors {
    /// Kept targets t_L, t_U.
    pub tl: Vec<f64>,
    pub tu: Vec<f64>,
    /// Targets of the corrector being tried.
    pub tl_c: Vec<f64>,
    pub tu_c: Vec<f64>,
    /// The direction of the corrector being tried.
    pub trial: Step,
    /// Whether the iteration's direction carries kept targets.
    pub targets_on: bool,
    /// Correctors kept over the solve.
    pub kept: usize,
}

/// Line-search state across iterations and the trial-point buffers.
pub(super) struct LineSearch {
    /// The filter of the current μ.
    pub filter: Filter,
    /// θ_max and θ_min, set from θ at the first iterate.
    pub theta_max: f64,
    pub theta_min: f64,
    /// The active watchdog, if any.
    pub watchdog: Option<Watchdog>,
    /// Consecutive shortened steps (the watchdog trigger).
    pub shortened_steps: usize,
    /// Watchdog starts and returns over the solve.
    pub watchdog_starts: usize,
    pub watchdog_returns: usize,
    /// Consecutive failed line searches.
    pub failures: usize,
    /// The last accepted step was at round-off level (IPOPT's tiny-step flag).
    pub tiny_step: bool,
    /// Trial point w + α d, its constraint values and residual.
    pub wt: Vec<f64>,
    pub ct: Vec<f64>,
    pub rt: Vec<f64>,
    /// Accumulated residual of the second-order correction.
    pub soc_rhs_r: Vec<f64>,
    /// Lagrangian gradient at the trial iterate of soft restoration.
    pub gl_trial: Vec<f64>,
}

/// What the watchdog keeps from the iteration where it started: the iterate, its search
/// direction and line-search references, so that it can return there.
pub(super) struct Watchdog {
    pub(super) st: Iterate,
    pub(super) dw: Vec<f64>,
    pub(super) dlam: Vec<f64>,
    pub(super) reference: LsReference,
    pub(super) alpha_max: f64,
    pub(super) alpha_min: f64,
    pub(super) mu: f64,
    /// full steps taken so far without one acceptable to the watchdog's references
    pub(super) trials: usize,
}

/// Entries reserved for the per-iteration lists (iteration log, filters), so that they do
/// not grow during the iteration: one per iteration up to `max_iter`, at most 100,000.
pub(super) fn iteration_capacity(o: &SolverOptions) -> usize {
    o.max_iter.min(100_000) + 1
}
