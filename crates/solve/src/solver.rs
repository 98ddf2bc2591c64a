//! The Solver trait, its options and its result type.
//!
//! Every backend (stride's own interior-point method, ripopt, system IPOPT) implements
//! [`Solver`] with the same [`SolverOptions`], the same per-iteration [`IterationRecord`]s
//! and the same [`SolveResult`], so they can be compared on the same [`Nlp`].

use std::time::Duration;

use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::nlp::{EvalError, Nlp, NlpError};
use crate::observer::Observer;
pub use crate::observer::{ControlFlow, IterationRecord, SolveStatus};

/// How the solver obtains the Hessian of the Lagrangian.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum HessianMode {
    /// Exact second derivatives from [`Nlp::hessian_values`].
    Exact,
    /// Limited-memory BFGS (compact representation) with `history` correction pairs.
    LimitedMemory {
        /// Number of stored correction pairs (IPOPT default 6).
        history: usize,
    },
    /// Limited-memory BFGS with `history` pairs until μ has sat at its floor for a few
    /// iterations, then the exact Hessian for the rest of the solve (pure-Rust interior
    /// point only; decision 0002).
    Hybrid {
        /// Number of stored correction pairs of the limited-memory phase.
        history: usize,
    },
}

impl HessianMode {
    /// The correction pairs of the limited-memory phase, None for the exact Hessian.
    pub fn history(&self) -> Option<usize> {
        match *self {
            HessianMode::Exact => None,
            HessianMode::LimitedMemory { history } | HessianMode::Hybrid { history } => {
                Some(history)
            }
        }
    }

    /// Whether the solve starts with the exact Hessian.
    pub fn starts_exact(&self) -> bool {
        matches!(self, HessianMode::Exact)
    }
}

/// Sparse symmetric factorisation of the KKT matrix of the pure-Rust interior point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum LinearSolver {
    /// faer's supernodal LDLᵀ without pivoting (inertia from D; decision 0002).
    #[default]
    Ldlt,
    /// faer's Bunch–Kaufman LBLᵀ with pivoting (slower; for experiments).
    Lblt,
}

/// How the barrier parameter μ is updated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum MuStrategy {
    /// Fiacco–McCormick: decrease μ once the barrier subproblem is solved to κ_ε·μ.
    Monotone,
    /// Adaptive: choose μ every iteration from the complementarity (Mehrotra-style probing).
    Adaptive,
}

/// When the adaptive μ strategy of the pure-Rust interior point falls back to (and leaves)
/// its monotone mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum MuGlobalisation {
    /// Free mode needs the scaled max-norm optimality error to fall by 1e-4 within four
    /// iterations; fixed mode lasts until its barrier problem is solved, and μ never goes
    /// below tol/10 before the iterate is primal and dual feasible.
    ScaledError,
    /// IPOPT's `kkt-error`: the same test on the mean squared primal-dual error, and fixed
    /// mode left as soon as it holds again.
    KktError,
    /// IPOPT's default `obj-constr-filter`: free mode lasts while every iterate is accepted
    /// by a filter of the objectives and constraint violations of the earlier free-mode
    /// iterates (margin 1e-5 × min(1, error)); fixed mode is left as soon as one is again.
    /// μ never goes below min(tol, compl_inf_tol)/(κ_ε + 1), in either mode.
    ObjConstrFilter,
}

/// How the adaptive μ strategy of the pure-Rust interior point picks μ in free mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum MuOracle {
    /// Mehrotra's probing heuristic: σ = (complementarity after the affine step /
    /// average complementarity)³.
    Probing,
    /// IPOPT's default `quality-function`: σ minimising the linearised mean squared
    /// optimality error after the step, by golden-section search.
    QualityFunction,
}

/// Fill-reducing ordering of the KKT matrix of the pure-Rust interior point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum KktOrdering {
    /// Nested dissection along the problem's chain of blocks (mesh intervals) when it
    /// declares them ([`crate::nlp::Nlp::blocks`]), minimum degree otherwise.
    #[default]
    Auto,
    /// Approximate minimum degree on the whole matrix.
    MinimumDegree,
}

/// Solver settings shared by all backends (defaults follow IPOPT's).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct SolverOptions {
    /// Relative convergence tolerance on the scaled NLP error (IPOPT `tol`, default 1e-8).
    pub tol: f64,
    /// Maximum number of iterations.
    pub max_iter: usize,
    /// Exact or limited-memory Hessian.
    pub hessian: HessianMode,
    /// Detail of the diagnostics: the pure-Rust interior point sends the
    /// [`crate::observer::Diagnostic`] events of level ≤ `print_level` to the observer (0
    /// none, 1 summary, 2 restoration steps, 3 every stage's internals); the other backends
    /// print their own output at their matching levels.
    pub print_level: u32,
    /// Wall-clock limit for the solve (None: unlimited).
    pub time_limit: Option<Duration>,
    /// "Acceptable" tolerance on the scaled NLP error (IPOPT default 1e-6).
    pub acceptable_tol: f64,
    /// Consecutive acceptable iterations that terminate with `Acceptable` (default 15).
    pub acceptable_iter: usize,
    /// Absolute tolerance on the unscaled constraint violation (default 1e-4).
    pub constr_viol_tol: f64,
    /// Absolute tolerance on the unscaled dual infeasibility (default 1).
    pub dual_inf_tol: f64,
    /// Absolute tolerance on the unscaled complementarity (default 1e-4).
    pub compl_inf_tol: f64,
    /// Barrier parameter update rule.
    pub mu_strategy: MuStrategy,
    /// Initial barrier parameter (default 0.1).
    pub mu_init: f64,
    /// Exponent θ_μ of the monotone decrease μ ← max(floor, min(κ_μ μ, μ^θ_μ)), κ_μ = 0.2,
    /// in [1, 2] (default 1.5, IPOPT `mu_superlinear_decrease_power`); 1 makes the decrease
    /// linear, so that μ does not jump far below the value at which the termination test
    /// already holds (the IPOPT backend ignores it).
    pub mu_superlinear_power: f64,
    /// Adaptive μ safeguard of the pure-Rust interior point: in free mode μ stays above
    /// min(average complementarity, factor × max(scaled primal, dual infeasibility)).
    /// None (default): 0.01 with the exact Hessian, 0 (off, IPOPT's default) with the
    /// limited-memory Hessian (decision 0002); the IPOPT backend ignores it.
    pub mu_safeguard: Option<f64>,
    /// Globalisation of the adaptive μ strategy of the pure-Rust interior point. None
    /// (default): `ScaledError` with the exact Hessian, `ObjConstrFilter` with the
    /// limited-memory Hessian (decision 0002); the IPOPT backend ignores it.
    pub mu_globalisation: Option<MuGlobalisation>,
    /// Free-mode μ oracle of the adaptive strategy of the pure-Rust interior point (default
    /// `Probing`: IPOPT's default quality function diverged on the quasi-random 10-interval
    /// gait problem, decision 0002; the IPOPT backend ignores it).
    pub mu_oracle: MuOracle,
    /// Soft restoration of the pure-Rust interior point (IPOPT): when the filter line search
    /// fails, first accept the primal-dual step to the fraction-to-boundary limits if it
    /// reduces the barrier problem's primal-dual error (default true; the IPOPT backend
    /// ignores it).
    pub soft_restoration: bool,
    /// Watchdog of the pure-Rust interior point (IPOPT `watchdog_shortened_iter_trigger`):
    /// after this many consecutive shortened steps, take up to 3 full steps judged against
    /// the point where the watchdog started, and return there if none is acceptable
    /// (default 10; 0 disables it; the IPOPT backend ignores it).
    pub watchdog_trigger: usize,
    /// KKT ordering of the pure-Rust interior point (default `Auto`: chain dissection for
    /// collocation problems, 2.4× faster factorisations of the 50-interval gait KKT than
    /// minimum degree, decision 0002; the IPOPT backend ignores it).
    pub kkt_ordering: KktOrdering,
    /// KKT linear solver of the pure-Rust interior point (default `Ldlt`; the other
    /// backends ignore it).
    pub linear_solver: LinearSolver,
    /// Pure-Rust interior point with the limited-memory Hessian: end the solve with
    /// [`SolveStatus::MuFloor`] once μ has reached its floor, instead of converging the
    /// quasi-Newton model or switching to the exact Hessian (default false): the coarse
    /// stage of mesh sequencing only needs a starting point (the IPOPT backend ignores it).
    pub stop_at_mu_floor: bool,
    /// Pure-Rust interior point: at most this many centrality correctors (Gondzio) per
    /// iteration, each one more solve with the iteration's factorisation, kept when it
    /// lengthens the fraction-to-boundary step (default 0; the IPOPT backend ignores it).
    pub centrality_correctors: usize,
    /// Apply gradient-based NLP scaling (IPOPT default).
    pub nlp_scaling: bool,
    /// Largest gradient entry after scaling (IPOPT `nlp_scaling_max_gradient`, 100).
    pub nlp_scaling_max_gradient: f64,
    /// Bound push/frac for moving the initial point into the interior (default 1e-2).
    pub bound_push: f64,
    /// Initial bound multipliers μ_init / (distance to the bound)
    /// instead of 1, so that a starting point near an optimum (a continuation guess) starts
    /// on the central path of a small `mu_init` instead of far from it (default false; use
    /// with a small `mu_init` and `bound_push`; IPOPT: `bound_mult_init_method mu-based`).
    pub warm_start: bool,
    /// Worker threads for the problem's function evaluations during a solve: stride's
    /// predictions and studies run each solve in a thread pool of this size (0: one thread
    /// per core). The backends' KKT factorisations run on one thread.
    pub threads: usize,
}

impl SolverOptions {
    /// The adaptive-μ globalisation in effect: the one set, or the default of the Hessian
    /// mode.
    pub fn mu_globalisation_in_effect(&self) -> MuGlobalisation {
        self.mu_globalisation.unwrap_or(match self.hessian {
            HessianMode::Exact => MuGlobalisation::ScaledError,
            HessianMode::LimitedMemory { .. } | HessianMode::Hybrid { .. } => {
                MuGlobalisation::ObjConstrFilter
            }
        })
    }

    /// The μ safeguard factor in effect: the one set, or the default of the Hessian mode.
    pub fn mu_safeguard_factor(&self) -> f64 {
        self.mu_safeguard.unwrap_or(match self.hessian {
            HessianMode::Exact => 0.01,
            HessianMode::LimitedMemory { .. } | HessianMode::Hybrid { .. } => 0.0,
        })
    }
}

impl Default for SolverOptions {
    fn default() -> Self {
        SolverOptions {
            tol: 1e-8,
            max_iter: 3000,
            hessian: HessianMode::Exact,
            print_level: 0,
            time_limit: None,
            acceptable_tol: 1e-6,
            acceptable_iter: 15,
            constr_viol_tol: 1e-4,
            dual_inf_tol: 1.0,
            compl_inf_tol: 1e-4,
            mu_strategy: MuStrategy::Monotone,
            mu_init: 0.1,
            mu_superlinear_power: 1.5,
            mu_safeguard: None,
            mu_globalisation: None,
            mu_oracle: MuOracle::Probing,
            soft_restoration: true,
            watchdog_trigger: 10,
            kkt_ordering: KktOrdering::Auto,
            linear_solver: LinearSolver::Ldlt,
            stop_at_mu_floor: false,
            centrality_correctors: 0,
            nlp_scaling: true,
            nlp_scaling_max_gradient: 100.0,
            bound_push: 1e-2,
            warm_start: false,
            threads: 1,
        }
    }
}

/// The outcome of a solve: the point, multipliers, statistics and timings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SolveResult {
    /// How the solve ended.
    pub status: SolveStatus,
    /// Number of iterations performed.
    pub iterations: usize,
    /// Objective value at `x`.
    pub objective: f64,
    /// Max-norm of the unscaled constraint violation at `x` (bounds and constraints).
    pub constraint_violation: f64,
    /// Max-norm of the unscaled dual infeasibility at `x`.
    pub dual_infeasibility: f64,
    /// Final primal point.
    pub x: Vec<f64>,
    /// Constraint multipliers (IPOPT sign convention: ∇f + Jᵀλ − z_l + z_u = 0).
    pub lambda: Vec<f64>,
    /// Lower-bound multipliers (≥ 0).
    pub z_l: Vec<f64>,
    /// Upper-bound multipliers (≥ 0).
    pub z_u: Vec<f64>,
    /// Total wall-clock time.
    pub time_total: Duration,
    /// Time spent in problem function evaluations.
    pub time_evaluations: Duration,
    /// Time spent factorising and solving the KKT system.
    pub time_linear_solver: Duration,
    /// Time spent in the symbolic analysis of the KKT matrix (part of `time_linear_solver`).
    pub time_symbolic: Duration,
    /// Number of KKT numeric factorisations.
    pub factorizations: usize,
    /// Time spent in the numeric KKT factorisations (part of `time_linear_solver`; zero when
    /// the backend does not report it).
    pub time_factorisation: Duration,
    /// Triangular solves with the KKT factor (one pass over the factor each, for one or
    /// several right-hand sides); 0 when the backend does not report them.
    #[serde(default)]
    pub solves: usize,
    /// Time in those solves (part of `time_linear_solver`; zero when not reported).
    #[serde(default)]
    pub time_solves: Duration,
    /// Number of objective evaluations.
    pub objective_evaluations: usize,
    /// Iteration from which the exact Hessian replaced the limited-memory one
    /// ([`HessianMode::Hybrid`]); `None` when it never did.
    #[serde(default)]
    pub exact_hessian_from: Option<usize>,
    /// The iteration log.
    pub log: Vec<IterationRecord>,
}

impl SolveResult {
    /// Time spent in the solver itself outside evaluations and linear algebra.
    pub fn time_other(&self) -> Duration {
        self.time_total
            .saturating_sub(self.time_evaluations)
            .saturating_sub(self.time_linear_solver)
    }

    /// Time in the KKT factorisations and solves, or None when the backend does not report
    /// it (no factorisation counted and zero time).
    pub fn reported_linear_solver_time(&self) -> Option<Duration> {
        (self.factorizations > 0 || !self.time_linear_solver.is_zero())
            .then_some(self.time_linear_solver)
    }
}

/// A solve that could not start or was aborted by an error (not a non-converged run, which
/// is a [`SolveResult`] with a non-success status).
#[derive(Debug, Clone, Error, PartialEq)]
pub enum SolveError {
    /// The problem definition is malformed.
    #[error("invalid problem: {0}")]
    InvalidProblem(#[from] NlpError),
    /// A problem function failed at the initial point (where no recovery is possible).
    #[error("evaluation failed at the initial point: {0}")]
    InitialEvaluation(EvalError),
    /// The options are inconsistent.
    #[error("invalid option {name}: {reason}")]
    InvalidOption {
        /// Option name.
        name: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// The backend is unavailable or failed internally.
    #[error("solver backend error: {0}")]
    Backend(String),
}

/// A nonlinear-programming solver.
pub trait Solver {
    /// Short name of the backend (e.g. "stride-ipm").
    fn name(&self) -> &str;
    /// Whether the backend takes [`SolverOptions::warm_start`] (bound multipliers on the
    /// central path of μ_init); callers leave the option off otherwise.
    fn supports_warm_start(&self) -> bool {
        true
    }
    /// Solves `nlp`, calling `observer` after every iteration (return `Break` to stop) and
    /// with the diagnostic events the backend emits.
    fn solve(
        &self,
        nlp: &dyn Nlp,
        options: &SolverOptions,
        observer: &mut dyn Observer,
    ) -> Result<SolveResult, SolveError>;
}
