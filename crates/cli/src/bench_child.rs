//! The child processes of `stride bench`: each case runs in its own process, which reports
//! one JSON line; the parent reads it, its wall time and its failure reason.

use anyhow::Context;
use std::process::{Command, Stdio};
use std::time::Instant;

/// Runs a benchmark's child process `cmd`: its report (the last JSON line of its output),
/// or why there is none (exit status and last line of its error output, `|` replaced so
/// that it fits a table cell), and its wall time [s].
pub(crate) fn run_child<T: serde::de::DeserializeOwned>(
    cmd: &mut Command,
) -> anyhow::Result<(Result<T, String>, f64)> {
    let t = Instant::now();
    let out = cmd
        .stdin(Stdio::null())
        .output()
        .context("running the stride executable")?;
    let process_s = t.elapsed().as_secs_f64();
    let stdout = String::from_utf8_lossy(&out.stdout);
    let report = stdout
        .lines()
        .rev()
        .find(|l| l.starts_with('{'))
        .and_then(|l| serde_json::from_str::<T>(l).ok());
    Ok(match report {
        Some(r) if out.status.success() => (Ok(r), process_s),
        _ => {
            let stderr = String::from_utf8_lossy(&out.stderr);
            let why = stderr
                .lines()
                .rev()
                .find(|l| !l.trim().is_empty())
                .unwrap_or("no output")
                .replace('|', "/");
            (Err(format!("failed ({}): {why}", out.status)), process_s)
        }
    })
}

/// Resident-set high-water mark of this process [KiB] (`VmHWM` of /proc/self/status).
pub(crate) fn peak_rss_kib() -> Option<u64> {
    if !cfg!(target_os = "linux") {
        return None;
    }
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
}
