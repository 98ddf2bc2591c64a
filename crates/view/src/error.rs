//! Errors of the viewer: every variant names the file (and column or element) concerned.

use std::path::PathBuf;

/// What went wrong while building a viewer page.
#[derive(Debug, thiserror::Error)]
pub enum ViewError {
    /// A file or folder could not be read.
    #[error("{path}: {what}")]
    Read {
        /// File or folder concerned.
        path: PathBuf,
        /// What failed.
        what: String,
    },
    /// A result file does not fit the model or is inconsistent.
    #[error("{path}: {what}")]
    Content {
        /// File concerned.
        path: PathBuf,
        /// What is wrong, naming the column or element.
        what: String,
    },
    /// The model cannot be posed (missing bodies or coordinates).
    #[error("model: {0}")]
    Model(String),
    /// Invalid options.
    #[error("{0}")]
    Options(String),
    /// A result file that the storage reader refused (its message names the file).
    #[error(transparent)]
    Storage(#[from] stride_model::storage::StorageError),
}

impl ViewError {
    /// A read error for `path`.
    pub(crate) fn read(path: &std::path::Path, what: impl std::fmt::Display) -> Self {
        Self::Read {
            path: path.to_path_buf(),
            what: what.to_string(),
        }
    }

    /// A content error for `path`.
    pub(crate) fn content(path: &std::path::Path, what: impl std::fmt::Display) -> Self {
        Self::Content {
            path: path.to_path_buf(),
            what: what.to_string(),
        }
    }
}
