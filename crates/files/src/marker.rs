//! The marker of a result folder: the file that says a folder is stride's, what kind of
//! result it holds and which of its entries stride wrote.

use crate::atomic::write_atomic;
use crate::process::temp_owner;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Marker file of a folder written by stride.
pub const MARKER: &str = ".stride-result";

/// What a result folder holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ResultKind {
    /// The files of one prediction (`stride predict`, or one case of a study).
    Prediction,
    /// A study output folder (`stride study`).
    Study,
}

impl ResultKind {
    /// Name used in messages and in the marker.
    pub fn as_str(self) -> &'static str {
        match self {
            ResultKind::Prediction => "prediction",
            ResultKind::Study => "study",
        }
    }
}

/// Content of the marker file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Marker {
    /// What the folder holds.
    pub kind: ResultKind,
    /// Version of stride that wrote it.
    pub version: String,
    /// The entries of the folder stride wrote (file and folder names, sorted); `None` in
    /// markers of versions that did not list them, and for a study folder, which is never
    /// replaced whole.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub files: Option<Vec<String>>,
}

/// `dir`'s marker, if it has a readable one.
pub fn read_marker(dir: &Path) -> Option<Marker> {
    let text = std::fs::read_to_string(dir.join(MARKER)).ok()?;
    serde_json::from_str::<Marker>(&text).ok()
}

/// The kind recorded in `dir`'s marker, if it has a readable one.
pub fn marker_kind(dir: &Path) -> Option<ResultKind> {
    read_marker(dir).map(|m| m.kind)
}

/// Write `dir`'s marker for a result of `kind`, listing `files` as stride's.
pub(crate) fn write_marker_listing(
    dir: &Path,
    kind: ResultKind,
    files: Option<Vec<String>>,
) -> std::io::Result<()> {
    let m = Marker {
        kind,
        version: env!("CARGO_PKG_VERSION").to_string(),
        files,
    };
    let json = serde_json::to_string(&m).map_err(std::io::Error::other)?;
    write_atomic(&dir.join(MARKER), format!("{json}\n").as_bytes())
}

/// Write `dir`'s marker for a result of `kind` without a file list (a study folder, or a
/// staging folder whose list is written when it is put in place).
pub fn write_marker(dir: &Path, kind: ResultKind) -> std::io::Result<()> {
    write_marker_listing(dir, kind, None)
}

/// The entries of `dir` (names, sorted) but its marker and stride's temporary files.
pub(crate) fn entries(dir: &Path) -> std::io::Result<Vec<String>> {
    let mut names: Vec<String> = std::fs::read_dir(dir)?
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n != MARKER && temp_owner(n).is_none())
        .collect();
    names.sort();
    Ok(names)
}

/// The entries of the result folder `dir` that stride did not write (not in its marker's
/// list): kept when the result is replaced. `None` when the marker lists no files (written
/// by an earlier version) or is missing.
pub fn foreign_entries(dir: &Path) -> Option<Vec<String>> {
    let listed = read_marker(dir)?.files?;
    let mut names = entries(dir).ok()?;
    names.retain(|n| !listed.contains(n));
    Some(names)
}

/// Add `name` (a file stride wrote into the finished result folder `dir`, e.g. its viewer
/// page) to the files its marker lists as stride's; nothing when the marker lists none.
pub fn record_file(dir: &Path, name: &str) -> std::io::Result<()> {
    let Some(mut m) = read_marker(dir) else {
        return Ok(());
    };
    let Some(files) = m.files.as_mut() else {
        return Ok(());
    };
    if !files.iter().any(|f| f == name) {
        files.push(name.to_string());
        files.sort();
        write_marker_listing(dir, m.kind, m.files)?;
    }
    Ok(())
}

/// The folder that holds `out` (`.` for a bare name).
pub fn parent_of(out: &Path) -> PathBuf {
    match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}
