//! stride's own pure-Rust primal-dual interior-point method (Wächter & Biegler 2006).
//!
//! - [`algorithm`]: the method as a type with one method per stage, and its iteration.
//! - `workspace`: the data of a solve, apart from the method: the `Ipm` type and the
//!   workspace types of its stages, below every stage (each stage file adds its
//!   constructor and methods to them, `algorithm` builds and runs them).
//! - stages: `setup` (starting point), `convergence` (optimality error, termination),
//!   `barrier` (μ update), `inertia` (KKT factorisation with inertia correction),
//!   `direction` (Newton steps, μ oracles), `correctors` (centrality correctors),
//!   `filter` and `line_search` (filter line search, second-order correction, watchdog),
//!   `restoration` (soft and feasibility restoration), `accept` (the step and the L-BFGS
//!   update), `refine` (iterative refinement), `iterate` (the iterate and its measures).
//! - [`kkt`]: the condensed KKT matrix pattern and its assembly.
//! - [`linsys`]: the swappable sparse symmetric linear solver (faer LDLᵀ).
//! - [`ordering`]: nested dissection of the KKT matrix along a chain of mesh intervals.
//! - [`lbfgs`]: the compact limited-memory BFGS Hessian and its low-rank KKT correction.
//! - [`scaled`]: gradient-based problem scaling and evaluation accounting.

mod accept;
pub mod algorithm;
mod barrier;
mod bottom;
mod convergence;
mod correctors;
mod direction;
mod filter;
mod inertia;
mod iterate;
pub mod kkt;
pub mod lbfgs;
mod line_search;
pub mod linsys;
mod mu_oracle;
pub mod ordering;
mod refine;
mod restoration;
mod result;
pub mod scaled;
mod setup;
mod workspace;

use crate::nlp::Nlp;
use crate::observer::Observer;
use crate::solver::{LinearSolver, SolveError, SolveResult, Solver, SolverOptions};
use linsys::{FaerLblt, FaerLdlt};

/// The interior-point solver with faer's sparse LDLᵀ as the KKT linear solver.
#[derive(Debug, Clone, Default)]
pub struct InteriorPoint;

impl InteriorPoint {
    /// A solver with default settings (options are passed to `solve`).
    pub fn new() -> Self {
        InteriorPoint
    }
}

impl Solver for InteriorPoint {
    fn name(&self) -> &str {
        "stride-ipm"
    }

    fn solve(
        &self,
        nlp: &dyn Nlp,
        options: &SolverOptions,
        observer: &mut dyn Observer,
    ) -> Result<SolveResult, SolveError> {
        // faer LDLᵀ (default) or, for experiments, the pivoting LBLᵀ (decision 0002)
        match options.linear_solver {
            LinearSolver::Ldlt => algorithm::solve(nlp, options, observer, &mut FaerLdlt::new()),
            LinearSolver::Lblt => algorithm::solve(nlp, options, observer, &mut FaerLblt::new()),
        }
    }
}

#[cfg(test)]
mod stage_tests;
#[cfg(test)]
mod tests;
