//! stride-ad: the derivative layer.
//!
//! [`Scalar`] is the number type all model functions are generic over. The rest of the
//! crate records such functions once and evaluates exact sparse Jacobians and Hessians.

pub mod dual;
pub mod elementary;
pub mod scalar;

pub use dual::{Dual, HyperDual};
pub use scalar::{smooth_step, Scalar, UnaryFn};
