//! Result folders: where stride may write, how a result is staged and put in place, and
//! which files of a result folder are stride's.
//!
//! stride writes a result only into a folder that does not exist yet, an empty folder, or a
//! folder holding the marker file [`MARKER`] (a small JSON with the kind of result, the
//! stride version and the files stride wrote there). Anything else (a folder holding a
//! user's files, a regular file) is refused before any work starts. A result is written by
//! the holder of the folder's reservation ([`crate::reserve`]) into a staging folder inside
//! its work folder, which replaces the output folder only when complete ([`commit`]). When
//! a previous result is replaced, the files in it that its marker does not list (a user's
//! notes, an analysis) are moved into the new result: only stride's own files are replaced.
//! Temporary files ([`crate::process::temp_name`]) of dead processes are removed only
//! from folders stride owns ([`clean_temp_files`]).

use crate::marker::{entries, write_marker_listing};
#[doc(inline)]
pub use crate::marker::{
    foreign_entries, marker_kind, parent_of, read_marker, record_file, write_marker, Marker,
    ResultKind, MARKER,
};
use crate::process::{process_alive, temp_name, temp_owner, this_host};
use crate::reserve::{Reservation, ASIDE};
use std::path::{Path, PathBuf};

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
    /// Another process is writing the folder, or it cannot be reserved.
    #[error(transparent)]
    Reserve(#[from] crate::reserve::ReserveError),
    /// A previous result whose marker does not list stride's files.
    #[error("{0}: holds a result of an earlier stride version that does not list the files it wrote, so --force cannot tell them from yours; move the folder away or choose another output folder")]
    Unlisted(String),
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
    let found = marker_kind(out).ok_or_else(|| OutputError::Foreign {
        path: show(),
        example: names[0].clone(),
    })?;
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

/// Check before any work that a result can be put at `out`: its parent is created if
/// needed, and an existing `out` must take new entries (a read-only or immutable folder
/// cannot be replaced). Work folders of dead processes in the parent are cleaned up
/// ([`crate::reserve::clean_stale`]), and so are temporary files of dead processes in an
/// existing `out` (a stride result: [`inspect`] comes first).
pub fn check_writable(out: &Path) -> Result<(), OutputError> {
    let parent = parent_of(out);
    std::fs::create_dir_all(&parent).map_err(|e| not_writable(&parent, e))?;
    crate::reserve::clean_stale(&parent);
    if out.is_dir() {
        crate::reserve::clean_stale(out);
        clean_temp_files(out);
        let probe = out.join(temp_name("probe"));
        std::fs::File::create(&probe).map_err(|e| not_writable(out, e))?;
        let _ = std::fs::remove_file(&probe);
    }
    Ok(())
}

/// A fresh staging folder `TAG` (e.g. `partial`) in the work folder of the reservation
/// `res`, holding the marker of `kind`.
pub fn stage(res: &Reservation, tag: &str, kind: ResultKind) -> std::io::Result<PathBuf> {
    let tmp = res.work().join(tag);
    let _ = std::fs::remove_dir_all(&tmp);
    std::fs::create_dir(&tmp)?;
    if let Err(e) = write_marker(&tmp, kind) {
        let _ = std::fs::remove_dir_all(&tmp);
        return Err(e);
    }
    Ok(tmp)
}

/// Write a result of `kind` to `out` whole: `out` is reserved (or the reservation this
/// process holds on it is used, [`Reservation::join_or_take`]), `write` fills a fresh
/// staging folder ([`stage`], tag e.g. `partial`), which then replaces `out` ([`commit`]);
/// when `write` fails the staging folder is removed and `out` stays as it was. `io` turns
/// a failure to reserve, stage or commit into the caller's error. This is the one path by
/// which a result folder is written.
pub fn write_staged<T, E>(
    out: &Path,
    tag: &str,
    kind: ResultKind,
    io: impl Fn(std::io::Error) -> E,
    write: impl FnOnce(&Path) -> Result<T, E>,
) -> Result<T, E> {
    let res = Reservation::join_or_take(out).map_err(|e| io(std::io::Error::other(e)))?;
    let tmp = stage(&res, tag, kind).map_err(&io)?;
    match write(&tmp) {
        Ok(v) => {
            commit(&res, &tmp, kind).map_err(io)?;
            Ok(v)
        }
        Err(e) => {
            let _ = std::fs::remove_dir_all(&tmp);
            Err(e)
        }
    }
}

/// Put the complete staging folder `tmp` (in the work folder of `res`) in place of the
/// reserved folder, which is free or a stride result of `kind` ([`inspect`]). The marker
/// of the new folder lists its files as stride's. A previous result is moved into the work
/// folder, `tmp` renamed into its place, the previous result's files that stride did not
/// write ([`foreign_entries`]) moved into the new folder, and the rest removed. Refused,
/// before anything changes, when such a file has the name of a new result file. If the
/// rename fails the old folder is put back and `tmp` removed: the folder is the old result
/// or the new one, never a mix.
pub fn commit(res: &Reservation, tmp: &Path, kind: ResultKind) -> std::io::Result<()> {
    let out = res.out();
    let aside = res.work().join(ASIDE);
    let had_out = out.exists();
    let result = (|| {
        let files = entries(tmp)?;
        if had_out {
            let foreign = foreign_entries(out).unwrap_or_default();
            if let Some(n) = foreign.iter().find(|n| files.contains(n)) {
                return Err(std::io::Error::new(
                    std::io::ErrorKind::AlreadyExists,
                    format!("{}: `{n}` was not written by stride and the new result has a file of that name; move it away and run again", out.display()),
                ));
            }
        }
        write_marker_listing(tmp, kind, Some(files))?;
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
    if let Err(e) = result {
        let _ = std::fs::remove_dir_all(tmp);
        return Err(e);
    }
    // the user's files of the old result join the new one; should one not move, the old
    // folder stays in the work folder and the next holder tries again
    if had_out && crate::reserve::move_foreign(&aside, out).is_ok() {
        let _ = std::fs::remove_dir_all(&aside);
    }
    Ok(())
}

pub use crate::reserve::clean_stale;

/// Remove the temporary files ([`crate::process::temp_name`]) of this host's dead
/// processes from `dir`, a folder stride owns (a result folder, a study folder and its
/// `cases`); those of other hosts are left (their processes cannot be checked from here).
/// Returns the files removed.
pub fn clean_temp_files(dir: &Path) -> Vec<PathBuf> {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    rd.flatten()
        .filter(|e| {
            let name = e.file_name();
            temp_owner(&name.to_string_lossy()).is_some_and(|(host, pid)| {
                host == this_host() && pid != std::process::id() && !process_alive(pid)
            })
        })
        .map(|e| e.path())
        .filter(|p| std::fs::remove_file(p).is_ok())
        .collect()
}

/// Reserve the first of `out`, `out-2`, `out-3`, … that is free ([`Existing::Free`]) and
/// not being written by another process.
pub fn reserve_next_free(out: &Path, kind: ResultKind) -> Result<Reservation, OutputError> {
    let name = out.file_name().and_then(|s| s.to_str()).unwrap_or("out");
    for i in 1.. {
        let p = match i {
            1 => out.to_path_buf(),
            _ => out.with_file_name(format!("{name}-{i}")),
        };
        if !matches!(inspect(&p, kind), Ok(Existing::Free)) {
            continue;
        }
        match Reservation::take(&p) {
            Ok(r) => return Ok(r),
            Err(crate::reserve::ReserveError::Busy { .. }) => continue,
            Err(e) => return Err(e.into()),
        }
    }
    unreachable!("some numbered name is free")
}
