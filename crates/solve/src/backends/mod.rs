//! Solver backends other than stride's own interior-point method (ripopt, system IPOPT).
//!
//! - [`ripopt`] (cargo feature `ripopt`): the pure-Rust `ripopt` crate, an IPOPT-like
//!   filter line-search interior-point method with the `feral` sparse LDLᵀ factorisation.
//! - [`ipopt`] (cargo feature `ipopt`): the system IPOPT library through its C interface,
//!   with the MUMPS linear solver (needs `coinor-libipopt-dev` and `pkg-config`).
//!
//! Both wrap an [`Nlp`](crate::nlp::Nlp) without copying its data, time every problem
//! evaluation on stride's side ([`timed`]), and report the final constraint violation and
//! dual infeasibility recomputed from the unscaled problem ([`residuals`]) so that all
//! backends are judged by the same yardstick.

#[cfg(all(test, feature = "ipopt"))]
mod agreement;
#[cfg(feature = "ipopt")]
pub mod ipopt;
pub mod monitor;
pub mod residuals;
#[cfg(feature = "ripopt")]
pub mod ripopt;
pub mod setup;
#[cfg(all(test, any(feature = "ripopt", feature = "ipopt")))]
pub(crate) mod tests;
pub mod timed;

use crate::solver::Solver;

/// Every solver backend compiled into this build, by name (for comparisons and the CLI).
#[allow(unused_mut, clippy::vec_init_then_push)]
pub fn available() -> Vec<Box<dyn Solver>> {
    let mut v: Vec<Box<dyn Solver>> = Vec::new();
    #[cfg(feature = "ripopt")]
    v.push(Box::new(ripopt::RipoptSolver::default()));
    #[cfg(feature = "ipopt")]
    v.push(Box::new(ipopt::IpoptSolver::default()));
    v
}
