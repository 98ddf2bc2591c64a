//! stride's own pure-Rust primal-dual interior-point method.
//!
//! - [`algorithm`]: the barrier iteration (μ update, inertia correction, line search).
//! - [`kkt`]: the condensed KKT matrix pattern and its assembly.
//! - [`linsys`]: the swappable sparse symmetric linear solver (faer LDLᵀ).
//! - [`ordering`]: nested dissection of the KKT matrix along a chain of mesh intervals.
//! - [`lbfgs`]: the compact limited-memory BFGS Hessian and its low-rank KKT correction.
//! - [`scaled`]: gradient-based problem scaling and evaluation accounting.

pub mod algorithm;
mod bottom;
pub mod kkt;
pub mod lbfgs;
pub mod linsys;
mod mu_oracle;
pub mod ordering;
pub mod scaled;

use crate::nlp::Nlp;
use crate::solver::{ControlFlow, IterationRecord, SolveError, SolveResult, Solver, SolverOptions};
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
        observer: &mut dyn FnMut(&IterationRecord) -> ControlFlow,
    ) -> Result<SolveResult, SolveError> {
        // KKT linear solver: faer LDLᵀ (default) or, for experiments, the pivoting
        // LBLᵀ (environment STRIDE_KKT=lblt; see docs/decisions/0002-solver.md)
        match std::env::var("STRIDE_KKT").ok().as_deref() {
            None | Some("ldlt") => algorithm::solve(nlp, options, observer, &mut FaerLdlt::new()),
            Some("lblt") => algorithm::solve(nlp, options, observer, &mut FaerLblt::new()),
            Some(other) => Err(SolveError::InvalidOption {
                name: "STRIDE_KKT",
                reason: format!("`{other}` is not a KKT solver (use `ldlt` or `lblt`)"),
            }),
        }
    }
}

#[cfg(test)]
mod tests;
