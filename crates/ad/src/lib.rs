//! stride-ad: the derivative layer.
//!
//! [`Scalar`] is the number type all model functions are generic over. The rest of the
//! crate records such functions once and evaluates exact sparse Jacobians and Hessians:
//! - [`Dual`], [`HyperDual`]: forward-mode numbers for tests and directional derivatives;
//! - [`DualVec`]: forward vector mode with `N` directions (compressed Jacobians);
//! - [`Tape`], [`Var`], [`Workspace`]: record once, then values, sparse Jacobian,
//!   gradients and exact sparse Lagrangian Hessians in `f64` without allocation.

pub mod dual;
pub mod dualvec;
pub mod elementary;
pub mod error;
pub mod scalar;
pub mod sparsity;
pub mod tape;

pub use dual::{Dual, HyperDual};
pub use dualvec::DualVec;
pub use error::AdError;
pub use scalar::{smooth_step, Scalar, UnaryFn};
pub use sparsity::Pattern;
pub use tape::{BatchWorkspace, Tape, TapeStats, Var, Workspace, BATCH, LANES};
