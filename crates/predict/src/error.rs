//! Why a prediction or the writing of its results failed.

use std::path::Path;

/// Why a prediction failed.
#[derive(Debug, thiserror::Error)]
pub enum PredictError {
    /// The problem could not be built.
    #[error(transparent)]
    Problem(#[from] stride_ocp::problem::ProblemError),
    /// A guess could not be built.
    #[error(transparent)]
    Guess(#[from] stride_ocp::guess::GuessError),
    /// A tracking problem could not be built or solved.
    #[error(transparent)]
    Track(#[from] stride_ocp::tracking::TrackError),
    /// An impossible presolve mesh.
    #[error("presolve_mesh {0}")]
    Presolve(String),
    /// The solver refused the problem.
    #[error("solver: {0}")]
    Solver(String),
    /// Reading earlier results failed.
    #[error("reading {path}: {reason}")]
    Read {
        /// Path.
        path: String,
        /// Why.
        reason: String,
    },
    /// Writing results failed.
    #[error("writing {path}: {reason}")]
    Write {
        /// Path.
        path: String,
        /// Why.
        reason: String,
    },
}

/// A write error naming `path`.
pub fn write_err(path: &Path, e: impl ToString) -> PredictError {
    PredictError::Write {
        path: path.display().to_string(),
        reason: e.to_string(),
    }
}

/// A read error naming `path`.
pub fn read_err(path: &Path, e: impl ToString) -> PredictError {
    PredictError::Read {
        path: path.display().to_string(),
        reason: e.to_string(),
    }
}
