//! Errors of the muscle layer: invalid parameters, inconsistent polynomials, wrong slice sizes.

use thiserror::Error;

/// What went wrong when building or evaluating a muscle-layer object.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum MuscleError {
    /// A muscle parameter is outside its physical range.
    #[error("muscle `{muscle}`: parameter {parameter} = {value} is invalid ({reason})")]
    InvalidParameter {
        /// Muscle name.
        muscle: String,
        /// Parameter name.
        parameter: &'static str,
        /// Offending value.
        value: f64,
        /// Why it is rejected.
        reason: &'static str,
    },
    /// A path polynomial is internally inconsistent.
    #[error("path polynomial of muscle {muscle}: {reason}")]
    InvalidPolynomial {
        /// Muscle index (position in the model's muscle list).
        muscle: usize,
        /// Description of the inconsistency.
        reason: String,
    },
    /// A slice passed to an evaluator has the wrong length.
    #[error("{what}: expected length {expected}, got {actual}")]
    LengthMismatch {
        /// Which argument.
        what: &'static str,
        /// Required length.
        expected: usize,
        /// Length received.
        actual: usize,
    },
}
