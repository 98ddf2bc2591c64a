//! Errors of the geometry crate.

use thiserror::Error;

/// What went wrong while sampling or fitting muscle–tendon geometry.
#[derive(Debug, Error)]
pub enum GeometryError {
    /// Sample arrays have inconsistent sizes.
    #[error("inconsistent fitting samples: {what}")]
    SampleShape {
        /// Description of the mismatch.
        what: String,
    },
    /// The least-squares system has fewer equations than unknowns.
    #[error(
        "{samples} samples are too few for a polynomial of order {order} ({unknowns} coefficients)"
    )]
    TooFewSamples {
        /// Number of poses.
        samples: usize,
        /// Number of coefficients.
        unknowns: usize,
        /// Polynomial order tried.
        order: u32,
    },
    /// Invalid fitting or sampling options.
    #[error("invalid options: {what}")]
    Options {
        /// Description.
        what: String,
    },
    /// A model element refers to something that does not exist or is unsupported.
    #[error("model {what}")]
    Model {
        /// Description including the element name.
        what: String,
    },
    /// A motion file could not be read or mapped onto the model.
    #[error("motion file {path}: {what}")]
    Motion {
        /// File path.
        path: String,
        /// Description including the line or column.
        what: String,
    },
    /// A geometry file could not be read, written or understood.
    #[error("{path}: {what}")]
    File {
        /// File path.
        path: String,
        /// Description.
        what: String,
    },
}
