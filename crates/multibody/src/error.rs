//! Errors of the multibody layer.

use stride_model::function::FunctionError;
use thiserror::Error;

/// Invalid model structure or input sizes found by the multibody layer.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum MultibodyError {
    /// An input or output slice has the wrong length.
    #[error("{what}: expected {expected} values, got {got}")]
    Length {
        /// Which argument.
        what: &'static str,
        /// Expected length.
        expected: usize,
        /// Actual length.
        got: usize,
    },
    /// A joint refers to a body that does not exist or is not yet placed in the tree.
    #[error("joint `{joint}`: {reason}")]
    Topology {
        /// Joint name.
        joint: String,
        /// What is wrong.
        reason: String,
    },
    /// A transform axis has an invalid function, coordinate or axis.
    #[error("joint `{joint}`, transform axis {axis}: {reason}")]
    Axis {
        /// Joint name.
        joint: String,
        /// Axis index (0–2 rotations, 3–5 translations).
        axis: usize,
        /// What is wrong.
        reason: String,
    },
    /// A coordinate function could not be compiled.
    #[error("joint `{joint}`, transform axis {axis}: {source}")]
    Function {
        /// Joint name.
        joint: String,
        /// Axis index.
        axis: usize,
        /// The function error.
        source: FunctionError,
    },
    /// A contact sphere refers to a missing body or has a degenerate plane normal.
    #[error("contact sphere `{sphere}`: {reason}")]
    Contact {
        /// Sphere name.
        sphere: String,
        /// What is wrong.
        reason: String,
    },
    /// A coordinate coupler refers to missing coordinates, forms a chain or has an
    /// invalid function.
    #[error("coordinate coupler `{name}`: {reason}")]
    Coupler {
        /// Constraint name.
        name: String,
        /// What is wrong.
        reason: String,
    },
    /// A body name used for contact grouping does not exist.
    #[error("contact group `{group}`: no body named `{body}`")]
    UnknownBody {
        /// Group name.
        group: String,
        /// Missing body name.
        body: String,
    },
}
