//! Errors of the derivative layer.

use thiserror::Error;

/// What went wrong when recording or evaluating a tape.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum AdError {
    /// A slice passed to a tape method has the wrong length.
    #[error("{what}: expected length {expected}, got {got}")]
    Length {
        /// Which argument (e.g. "inputs x", "multipliers lambda").
        what: &'static str,
        /// The length the tape requires.
        expected: usize,
        /// The length that was passed.
        got: usize,
    },
    /// `Tape::record` was called while another recording was active on this thread.
    #[error("a tape is already being recorded on this thread (nested Tape::record)")]
    NestedRecording,
    /// A workspace made for another tape was passed.
    #[error("workspace was made for a tape with {ws_nodes} nodes, this tape has {tape_nodes}")]
    Workspace {
        /// Nodes of the tape the workspace was made for.
        ws_nodes: usize,
        /// Nodes of this tape.
        tape_nodes: usize,
    },
    /// An output index is out of range.
    #[error("output index {index} out of range (tape has {n_outputs} outputs)")]
    OutputIndex {
        /// The index passed.
        index: usize,
        /// Number of outputs of the tape.
        n_outputs: usize,
    },
    /// The recorded function returned a variable that was not recorded on this tape.
    #[error("output {index} is a variable from another recording")]
    ForeignVariable {
        /// Position of the offending output.
        index: usize,
    },
}

/// Returns `Err(AdError::Length)` unless `got == expected`.
#[inline]
pub(crate) fn check_len(what: &'static str, expected: usize, got: usize) -> Result<(), AdError> {
    if expected == got {
        Ok(())
    } else {
        Err(AdError::Length {
            what,
            expected,
            got,
        })
    }
}
