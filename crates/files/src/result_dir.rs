//! Result folders: where stride may write, how a result is staged and put in place, and
//! the cleanup of what killed runs left behind.
//!
//! stride writes a result only into a folder that does not exist yet, an empty folder, or a
//! folder it recognises as its own result: one holding the marker file [`MARKER`] (a small
//! JSON with the kind of result and the stride version), or a result folder written before
//! the marker existed. Anything else (a folder holding a user's files, a regular file) is
//! refused before any work starts. A result is written into one hidden sibling folder
//! (`.NAME.partial-<host>-<pid>`, see [`stage`]) that replaces the output folder only when
//! complete ([`commit`]); staging folders of processes that no longer run are removed by
//! the next run on the same host ([`clean_stale`]). The host name keeps the staging folders
//! of two machines writing one shared folder (cluster nodes) apart, even when their
//! process ids are equal.

use crate::atomic::write_atomic;
use crate::process::{owner_tag, process_alive, this_host};
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
}

/// What is at an output path now.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Existing {
    /// Nothing, or an empty folder: stride may write there.
    Free,
    /// A stride result of this kind.
    Own(ResultKind),
}

/// Why an output folder cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// The path is a file (or something else that is not a folder).
    #[error("{0}: exists and is not a folder; choose another output folder")]
    NotAFolder(String),
    /// The folder holds files stride did not write.
    #[error("{path}: exists and is not a stride result folder (it holds `{example}`); stride writes only into new or empty folders and its own results: choose another output folder")]
    Foreign {
        /// Output folder.
        path: String,
        /// One of the entries found.
        example: String,
    },
    /// A stride result of another kind.
    #[error("{path}: holds a stride {found} result, not a {wanted} result; choose another output folder")]
    OtherKind {
        /// Output folder.
        path: String,
        /// Kind found.
        found: &'static str,
        /// Kind to be written.
        wanted: &'static str,
    },
    /// A previous result that is replaced only when asked to.
    #[error(
        "{0}: holds a previous result; use --force to replace it, or choose another output folder"
    )]
    Occupied(String),
    /// A path that cannot be replaced (the current folder, a root, `..`).
    #[error("{0}: cannot be an output folder (it is the current folder, one of its parents or a root); name a folder below it, e.g. `{0}/result`")]
    Unusable(String),
    /// The folder (or its parent) cannot be written.
    #[error("{path}: cannot write there ({reason})")]
    NotWritable {
        /// Path tried.
        path: String,
        /// The system's reason.
        reason: String,
    },
}

/// Whether `dir` is a result folder written before the marker existed: a prediction
/// (`summary.json` with its solver fields, only result files) or a study (`study.hash`).
fn legacy_kind(dir: &Path, names: &[String]) -> Option<ResultKind> {
    if names.iter().any(|n| n == "study.hash") && dir.join("cases").is_dir() {
        return Some(ResultKind::Study);
    }
    let summary = std::fs::read_to_string(dir.join("summary.json")).ok()?;
    let v: serde_json::Value = serde_json::from_str(&summary).ok()?;
    let result_file = |n: &String| {
        let ext = n.rsplit('.').next().unwrap_or("");
        matches!(ext, "csv" | "json" | "mot" | "svg" | "png") && dir.join(n).is_file()
    };
    (v.get("guesses").is_some()
        && v.get("solver_options").is_some()
        && names.iter().all(result_file))
    .then_some(ResultKind::Prediction)
}

/// The kind recorded in `dir`'s marker, if it has a readable one.
pub fn marker_kind(dir: &Path) -> Option<ResultKind> {
    let text = std::fs::read_to_string(dir.join(MARKER)).ok()?;
    serde_json::from_str::<Marker>(&text).ok().map(|m| m.kind)
}

/// Write `dir`'s marker for a result of `kind`.
pub fn write_marker(dir: &Path, kind: ResultKind) -> std::io::Result<()> {
    let m = Marker {
        kind,
        version: env!("CARGO_PKG_VERSION").to_string(),
    };
    let json = serde_json::to_string(&m).map_err(std::io::Error::other)?;
    write_atomic(&dir.join(MARKER), format!("{json}\n").as_bytes())
}

/// Whether `out` names the current folder, one of its parents, or a root.
fn is_unusable(out: &Path) -> bool {
    if out.file_name().is_none() {
        return true;
    }
    match (std::fs::canonicalize(out), std::env::current_dir()) {
        (Ok(o), Ok(cwd)) => cwd.starts_with(&o),
        _ => false,
    }
}

/// What is at `out`, for writing a result of `kind` there: free, or a stride result of the
/// same kind; an error for a file, a folder with other content, another kind of result, or
/// the current folder.
pub fn inspect(out: &Path, kind: ResultKind) -> Result<Existing, OutputError> {
    let show = || out.display().to_string();
    if is_unusable(out) {
        return Err(OutputError::Unusable(show()));
    }
    let meta = match std::fs::symlink_metadata(out) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Existing::Free),
        Err(e) => return Err(not_writable(out, e)),
        Ok(m) => m,
    };
    if !meta.is_dir() {
        return Err(OutputError::NotAFolder(show()));
    }
    let mut names: Vec<String> = std::fs::read_dir(out)
        .map_err(|e| not_writable(out, e))?
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    if names.is_empty() {
        return Ok(Existing::Free);
    }
    let found = match marker_kind(out) {
        Some(k) => k,
        None => legacy_kind(out, &names).ok_or_else(|| OutputError::Foreign {
            path: show(),
            example: names[0].clone(),
        })?,
    };
    if found != kind {
        return Err(OutputError::OtherKind {
            path: show(),
            found: found.as_str(),
            wanted: kind.as_str(),
        });
    }
    Ok(Existing::Own(found))
}

fn not_writable(path: &Path, e: impl ToString) -> OutputError {
    OutputError::NotWritable {
        path: path.display().to_string(),
        reason: e.to_string(),
    }
}

/// The folder that holds `out` (`.` for a bare name).
pub fn parent_of(out: &Path) -> PathBuf {
    match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Check before any work that a result can be put at `out`: its parent is created if
/// needed and must take a new folder, and an existing `out` must take new entries (a
/// read-only or immutable folder cannot be replaced). Stale staging entries of dead
/// processes in both are removed ([`clean_stale`]).
pub fn check_writable(out: &Path) -> Result<(), OutputError> {
    let parent = parent_of(out);
    std::fs::create_dir_all(&parent).map_err(|e| not_writable(&parent, e))?;
    clean_stale(&parent);
    let probe = staging_path(out, "probe");
    std::fs::create_dir(&probe).map_err(|e| not_writable(&parent, e))?;
    let _ = std::fs::remove_dir(&probe);
    if out.is_dir() {
        clean_stale(out);
        let probe = out.join(format!(".stride.probe-{}", owner_tag()));
        std::fs::File::create(&probe).map_err(|e| not_writable(out, e))?;
        let _ = std::fs::remove_file(&probe);
    }
    Ok(())
}

/// Hidden sibling of `out` named after it, a tag and this process:
/// `.NAME.TAG-<host>-<pid>`.
fn staging_path(out: &Path, tag: &str) -> PathBuf {
    let name = out.file_name().and_then(|s| s.to_str()).unwrap_or("out");
    parent_of(out).join(format!(".{name}.{tag}-{}", owner_tag()))
}

/// A fresh staging folder beside `out` (`.NAME.TAG-<host>-<pid>`, e.g. tag `partial`) holding the
/// marker of `kind`; staging folders of dead processes beside it are removed first.
pub fn stage(out: &Path, tag: &str, kind: ResultKind) -> std::io::Result<PathBuf> {
    let parent = parent_of(out);
    std::fs::create_dir_all(&parent)?;
    clean_stale(&parent);
    let tmp = staging_path(out, tag);
    let _ = std::fs::remove_dir_all(&tmp);
    std::fs::create_dir(&tmp)?;
    if let Err(e) = write_marker(&tmp, kind) {
        let _ = std::fs::remove_dir_all(&tmp);
        return Err(e);
    }
    Ok(tmp)
}

/// Write a result of `kind` to `out` whole: `write` fills a fresh staging folder beside `out`
/// ([`stage`], tag e.g. `partial`), which then replaces `out` ([`commit`]); when `write`
/// fails the staging folder is removed and `out` stays as it was. `io` turns a failure to
/// stage or commit (an I/O error at `out`) into the caller's error. This is the one path by
/// which a result folder is written.
pub fn write_staged<T, E>(
    out: &Path,
    tag: &str,
    kind: ResultKind,
    io: impl Fn(std::io::Error) -> E,
    write: impl FnOnce(&Path) -> Result<T, E>,
) -> Result<T, E> {
    let tmp = stage(out, tag, kind).map_err(&io)?;
    match write(&tmp) {
        Ok(v) => {
            commit(&tmp, out).map_err(io)?;
            Ok(v)
        }
        Err(e) => {
            let _ = std::fs::remove_dir_all(&tmp);
            Err(e)
        }
    }
}

/// Put the complete staging folder `tmp` in place of `out` (which is free or a stride
/// result, see [`inspect`]): the old folder is moved aside (`.NAME.old-<host>-<pid>`), `tmp`
/// renamed into its place and the old folder removed. If the rename fails the old folder is
/// put back and `tmp` removed: `out` is the old result or the new one, never a mix.
pub fn commit(tmp: &Path, out: &Path) -> std::io::Result<()> {
    let aside = staging_path(out, "old");
    let had_out = out.exists();
    let result = (|| {
        if had_out {
            let _ = std::fs::remove_dir_all(&aside);
            std::fs::rename(out, &aside)?;
        }
        if let Err(e) = std::fs::rename(tmp, out) {
            if had_out {
                let _ = std::fs::rename(&aside, out);
            }
            return Err(e);
        }
        Ok(())
    })();
    match result {
        Ok(()) => {
            if had_out {
                let _ = std::fs::remove_dir_all(&aside);
            }
            Ok(())
        }
        Err(e) => {
            let _ = std::fs::remove_dir_all(tmp);
            Err(e)
        }
    }
}

/// Who made a staging entry, and for what.
struct Staging<'a> {
    /// Host named in the entry (`None`: a name without host, from an older version).
    host: Option<&'a str>,
    /// Process id.
    pid: u32,
    /// The tag (`.partial-`, `.old-`, …).
    tag: &'static str,
    /// The name of the folder or file it stands for.
    original: &'a str,
}

/// Parse a staging name `.NAME.TAG-<host>-<pid>` (or `.NAME.TAG-<pid>`, or a temporary
/// file `.NAME.tmp-<host>-<pid>` of [`crate::atomic::write_atomic`]) with TAG one of
/// stride's.
fn staging_of(name: &str) -> Option<Staging<'_>> {
    let rest = name.strip_prefix('.')?;
    for tag in [".partial-", ".rewrite-", ".probe-", ".old-", ".tmp"] {
        if let Some(at) = rest.rfind(tag) {
            let owner = &rest[at + tag.len()..];
            let owner = owner.strip_prefix('-').unwrap_or(owner);
            let (host, pid) = match owner.rsplit_once('-') {
                Some((h, p)) if !h.is_empty() => (Some(h), p),
                _ => (None, owner),
            };
            return Some(Staging {
                host,
                pid: pid.parse().ok()?,
                tag,
                original: &rest[..at],
            });
        }
    }
    None
}

/// Remove the staging folders and temporary files in `dir` left by stride processes of this
/// host that no longer run (those of other hosts are left: their processes cannot be
/// checked from here); an old result moved aside by a killed [`commit`] is put back when
/// its folder is missing. Returns the entries handled.
pub fn clean_stale(dir: &Path) -> Vec<PathBuf> {
    clean_where(dir, |s| {
        s.host.is_none_or(|h| h == this_host())
            && s.pid != std::process::id()
            && !process_alive(s.pid)
    })
}

/// Remove every staging entry in `dir` that stands for `original` (of any host and
/// process but this one), restoring a moved-aside old result as [`clean_stale`] does: for
/// the holder of an exclusive claim on `original`, whose entries no other live process can
/// be writing.
pub fn clean_staging_of(dir: &Path, original: &str) -> Vec<PathBuf> {
    let me = owner_tag();
    clean_where(dir, |s| {
        s.original == original && s.host.map(|h| format!("{h}-{}", s.pid)) != Some(me.clone())
    })
}

fn clean_where(dir: &Path, stale: impl Fn(&Staging) -> bool) -> Vec<PathBuf> {
    let mut handled = Vec::new();
    let Ok(rd) = std::fs::read_dir(dir) else {
        return handled;
    };
    for e in rd.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(s) = staging_of(&name) else {
            continue;
        };
        if !stale(&s) {
            continue;
        }
        let path = e.path();
        let original = dir.join(s.original);
        if s.tag == ".old-"
            && !s.original.is_empty()
            && !original.exists()
            && std::fs::rename(&path, &original).is_ok()
        {
            handled.push(path);
            continue;
        }
        let removed = if path.is_dir() {
            std::fs::remove_dir_all(&path)
        } else {
            std::fs::remove_file(&path)
        };
        if removed.is_ok() {
            handled.push(path);
        }
    }
    handled
}

/// The first of `out`, `out-2`, `out-3`, … that is free ([`Existing::Free`]).
pub fn next_free(out: &Path, kind: ResultKind) -> PathBuf {
    let name = out.file_name().and_then(|s| s.to_str()).unwrap_or("out");
    (1..)
        .map(|i| {
            if i == 1 {
                out.to_path_buf()
            } else {
                out.with_file_name(format!("{name}-{i}"))
            }
        })
        .find(|p| matches!(inspect(p, kind), Ok(Existing::Free)))
        .expect("some numbered name is free")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("stride-resultdir-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn user_folders_and_files_are_refused_stride_results_recognised() {
        let d = scratch("inspect");
        let p = ResultKind::Prediction;
        assert_eq!(inspect(&d.join("new"), p).unwrap(), Existing::Free);
        std::fs::create_dir(d.join("empty")).unwrap();
        assert_eq!(inspect(&d.join("empty"), p).unwrap(), Existing::Free);
        std::fs::create_dir(d.join("thesis")).unwrap();
        std::fs::write(d.join("thesis/draft.txt"), "draft").unwrap();
        let e = inspect(&d.join("thesis"), p).unwrap_err().to_string();
        assert!(
            e.contains("not a stride result folder") && e.contains("draft.txt"),
            "{e}"
        );
        std::fs::write(d.join("file"), "x").unwrap();
        assert!(matches!(
            inspect(&d.join("file"), p),
            Err(OutputError::NotAFolder(_))
        ));
        std::fs::create_dir(d.join("res")).unwrap();
        write_marker(&d.join("res"), p).unwrap();
        std::fs::write(d.join("res/summary.json"), "{}").unwrap();
        assert_eq!(inspect(&d.join("res"), p).unwrap(), Existing::Own(p));
        let e = inspect(&d.join("res"), ResultKind::Study)
            .unwrap_err()
            .to_string();
        assert!(e.contains("stride prediction result, not a study"), "{e}");
        // a result folder written before the marker existed
        std::fs::create_dir(d.join("legacy")).unwrap();
        std::fs::write(
            d.join("legacy/summary.json"),
            r#"{"guesses":[],"solver_options":{}}"#,
        )
        .unwrap();
        std::fs::write(d.join("legacy/grf.csv"), "t\n").unwrap();
        assert_eq!(inspect(&d.join("legacy"), p).unwrap(), Existing::Own(p));
        std::fs::write(d.join("legacy/notes.txt"), "mine").unwrap();
        assert!(inspect(&d.join("legacy"), p).is_err());
        assert!(matches!(
            inspect(Path::new("."), p),
            Err(OutputError::Unusable(_))
        ));
        assert_eq!(next_free(&d.join("res"), p), d.join("res-2"));
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn stale_staging_of_dead_processes_is_removed_and_an_old_result_restored() {
        let d = scratch("stale");
        // a pid that is not running: a child that has exited and been reaped
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let dead = child.id();
        child.wait().unwrap();
        let me = std::process::id();
        for n in [
            format!(".r.partial-{dead}"),
            format!(".r.partial-{me}"),
            format!(".q.old-{dead}"),
        ] {
            std::fs::create_dir(d.join(n)).unwrap();
        }
        std::fs::write(d.join(format!(".index.csv.tmp{dead}")), "x").unwrap();
        std::fs::write(d.join("keep.partial-1"), "user file").unwrap();
        // another node's staging, with the same process id as a dead one here
        let other = format!(".r.partial-other-node-{dead}");
        std::fs::create_dir(d.join(&other)).unwrap();
        let handled = clean_stale(&d);
        assert_eq!(handled.len(), 3, "{handled:?}");
        assert!(d.join(&other).exists(), "another host's staging is left");
        assert!(!d.join(format!(".r.partial-{dead}")).exists());
        assert!(d.join(format!(".r.partial-{me}")).exists());
        assert!(d.join("q").is_dir(), "the result moved aside is put back");
        assert!(d.join("keep.partial-1").exists());
        // the holder of a claim on `r` removes every staging folder of `r` but its own
        let mine = stage(&d.join("r"), "partial", ResultKind::Prediction).unwrap();
        let removed = clean_staging_of(&d, "r");
        assert!(removed.contains(&d.join(&other)), "{removed:?}");
        assert!(mine.exists() && mine.to_string_lossy().contains(&owner_tag()));
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn commit_replaces_an_old_result_whole() {
        let d = scratch("commit");
        let out = d.join("out");
        let tmp = stage(&out, "partial", ResultKind::Prediction).unwrap();
        std::fs::write(tmp.join("a.csv"), "1").unwrap();
        commit(&tmp, &out).unwrap();
        let tmp = stage(&out, "partial", ResultKind::Prediction).unwrap();
        std::fs::write(tmp.join("b.csv"), "2").unwrap();
        commit(&tmp, &out).unwrap();
        assert!(!out.join("a.csv").exists() && out.join("b.csv").exists());
        assert_eq!(marker_kind(&out), Some(ResultKind::Prediction));
        let left: Vec<_> = std::fs::read_dir(&d).unwrap().flatten().collect();
        assert_eq!(left.len(), 1, "{left:?}");
        std::fs::remove_dir_all(&d).unwrap();
    }
}
