//! Test problems with known solutions (classic NLPs and a scalable collocation problem).
//!
//! - [`classic`]: Hock–Schittkowski problems (HS071, HS035, HS021, HS006), Rosenbrock on the
//!   unit disk, and an infeasible problem, with their published optima.
//! - [`collocation`]: a pendulum-chain swing-up transcribed with Radau collocation, scalable
//!   to ~60,000 variables, with the block structure of the gait problem.

pub mod classic;
pub mod collocation;

pub use classic::{Hs006, Hs021, Hs035, Hs071, InfeasibleDisk, RosenbrockDisk, WaechterBiegler};
pub use collocation::PendulumChain;

#[cfg(test)]
mod tests;
