//! Helpers of the command-line tests: run the built `stride` binary and check rejections.

use std::process::{Command, Output};

/// Runs the `stride` binary with `args`.
pub fn stride(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_stride"))
        .args(args)
        .output()
        .expect("running stride")
}

/// Runs `stride` with bad arguments: non-zero exit and one error line containing `needle`.
pub fn rejects(args: &[&str], needle: &str) {
    let out = stride(args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{args:?} succeeded");
    assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
    assert!(err.starts_with("error: "), "{args:?}: {err}");
    assert!(err.contains(needle), "{args:?}: {err}");
}
