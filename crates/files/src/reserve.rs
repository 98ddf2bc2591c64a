//! Reservations of result folders: one writer per output folder at a time, and the only
//! place where stride keeps what it writes beside a result folder.
//!
//! A process that will write the result folder `DIR/NAME` first reserves it: it creates
//! the work folder `DIR/.stride-work.NAME` and takes the claim [`OWNER`] inside it
//! ([`crate::claim`]: an exclusive `flock` and a line naming host, process and start time,
//! with a heartbeat for other machines). Its staging folder (`partial`, `rewrite`) and the
//! previous result moved aside while the new one is put in place (`old`) live inside the
//! work folder, never loose beside the result. A second process that wants `NAME` finds the
//! claim held and is refused with the holder's name. A work folder whose claim can be taken
//! was left by a process that died: whoever takes it puts a moved-aside result back
//! ([`recover`]) and removes the rest. Nothing else in `DIR` is ever touched.

use crate::claim::{Claim, ClaimError, Holder};
use crate::marker::{foreign_entries, parent_of};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, Weak};

/// Prefix of the work folder of a result folder (`.stride-work.NAME` beside `NAME`).
pub const WORK_PREFIX: &str = ".stride-work.";
/// Claim file inside a work folder, naming the process that holds the reservation.
pub const OWNER: &str = "owner";
/// Name, inside the work folder, of a previous result while it is being replaced.
pub const ASIDE: &str = "old";

/// Why a result folder could not be reserved.
#[derive(Debug, thiserror::Error)]
pub enum ReserveError {
    /// Another process (or this one) is writing the folder.
    #[error(
        "{out}: being written by {holder}; wait for it to finish or choose another output folder"
    )]
    Busy {
        /// Output folder.
        out: String,
        /// The process writing it.
        holder: Holder,
    },
    /// The work folder could not be made or claimed.
    #[error("{path}: cannot write there ({reason})")]
    Io {
        /// Path tried.
        path: String,
        /// The system's reason.
        reason: String,
    },
}

/// The work folder of the result folder `out` (`.stride-work.NAME` beside it).
pub fn work_dir(out: &Path) -> PathBuf {
    let name = out.file_name().and_then(|s| s.to_str()).unwrap_or("out");
    parent_of(out).join(format!("{WORK_PREFIX}{name}"))
}

/// A held reservation's state; released (work folder cleaned and removed) on drop.
#[derive(Debug)]
struct Held {
    out: PathBuf,
    work: PathBuf,
    key: PathBuf,
    claim: Option<Claim>,
}

impl Drop for Held {
    fn drop(&mut self) {
        recover(&self.work, &self.out);
        // remove the claim file while holding it: a process that opens it afterwards makes
        // a new one ([`crate::lock::FileLock::try_lock`] checks it locked the file in place)
        let _ = std::fs::remove_file(self.work.join(OWNER));
        let _ = std::fs::remove_dir(&self.work);
        drop(self.claim.take());
        registry()
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .retain(|(k, w)| k != &self.key && w.strong_count() > 0);
    }
}

/// The exclusive right of this process to write one result folder, until dropped (clones
/// share it). Reserving a folder this process holds already is refused ([`Reservation::take`])
/// or shares the held reservation ([`Reservation::join_or_take`]).
#[derive(Clone, Debug)]
pub struct Reservation(Arc<Held>);

/// The reservations this process holds, by work folder (canonical parent).
fn registry() -> &'static Mutex<Vec<(PathBuf, Weak<Held>)>> {
    static HELD: Mutex<Vec<(PathBuf, Weak<Held>)>> = Mutex::new(Vec::new());
    &HELD
}

impl Reservation {
    /// Reserve the result folder `out` (its parent is created if needed): refused when
    /// another process, or this one, holds it. Leftovers of a dead holder are cleaned up.
    pub fn take(out: &Path) -> Result<Reservation, ReserveError> {
        Self::reserve(out, false)
    }

    /// [`Reservation::take`], or a share of the reservation of `out` this process holds.
    pub fn join_or_take(out: &Path) -> Result<Reservation, ReserveError> {
        Self::reserve(out, true)
    }

    /// The result folder reserved.
    pub fn out(&self) -> &Path {
        &self.0.out
    }

    /// Its work folder (staging folders and the moved-aside previous result live here).
    pub fn work(&self) -> &Path {
        &self.0.work
    }

    fn reserve(out: &Path, join: bool) -> Result<Reservation, ReserveError> {
        let io = |path: &Path, e: &dyn std::fmt::Display| ReserveError::Io {
            path: path.display().to_string(),
            reason: e.to_string(),
        };
        let parent = parent_of(out);
        std::fs::create_dir_all(&parent).map_err(|e| io(&parent, &e))?;
        let work = work_dir(out);
        let key = std::fs::canonicalize(&parent)
            .map_err(|e| io(&parent, &e))?
            .join(work.file_name().unwrap_or_default());
        let mut held = registry().lock().unwrap_or_else(|p| p.into_inner());
        let mine = held
            .iter()
            .find(|(k, _)| *k == key)
            .and_then(|(_, w)| w.upgrade());
        if let Some(mine) = mine {
            // the registry is unlocked before `mine` may be dropped (its drop locks it)
            drop(held);
            return match join {
                true => Ok(Reservation(mine)),
                false => Err(busy(out, &work)),
            };
        }
        let claim = claim_work(out, &work)?;
        recover(&work, out);
        let r = Arc::new(Held {
            out: out.to_path_buf(),
            work,
            key: key.clone(),
            claim: Some(claim),
        });
        held.retain(|(_, w)| w.strong_count() > 0);
        held.push((key, Arc::downgrade(&r)));
        Ok(Reservation(r))
    }
}

/// The claim on the work folder of `out`, made if missing. A claim held for a moment by
/// another process cleaning up (or being released) is tried again a few times.
fn claim_work(out: &Path, work: &Path) -> Result<Claim, ReserveError> {
    let mut last = None;
    for attempt in 0..10 {
        if attempt > 0 {
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
        if let Err(e) = std::fs::create_dir_all(work) {
            last = Some(ReserveError::Io {
                path: work.display().to_string(),
                reason: e.to_string(),
            });
            continue;
        }
        if !is_work_folder(work) {
            return Err(ReserveError::Io {
                path: work.display().to_string(),
                reason: "exists and was not made by stride; move it away".into(),
            });
        }
        match Claim::try_take(&work.join(OWNER), "-") {
            Ok(c) => return Ok(c),
            Err(ClaimError::Held { holder, .. }) => {
                last = Some(ReserveError::Busy {
                    out: out.display().to_string(),
                    holder,
                })
            }
            Err(ClaimError::Io { path, reason }) => last = Some(ReserveError::Io { path, reason }),
        }
    }
    Err(last.expect("at least one attempt"))
}

/// Whether the folder `work` (named like a work folder) is one: empty (being made), or
/// holding a claim file that is empty (being taken) or names a holder.
fn is_work_folder(work: &Path) -> bool {
    let owner = work.join(OWNER);
    let empty = std::fs::read_dir(work).is_ok_and(|mut rd| rd.next().is_none());
    empty
        || std::fs::metadata(&owner).is_ok_and(|m| m.is_file() && m.len() == 0)
        || crate::claim::read_holder(&owner).is_some()
}

/// Refusal of a folder this process reserved already.
fn busy(out: &Path, work: &Path) -> ReserveError {
    ReserveError::Busy {
        out: out.display().to_string(),
        holder: crate::claim::read_holder(&work.join(OWNER)).unwrap_or(Holder {
            host: crate::process::this_host().into(),
            pid: std::process::id(),
            job: "-".into(),
            since: 0,
            heartbeat_age: std::time::Duration::ZERO,
        }),
    }
}

/// Put the work folder `work` of `out` in order for its new holder (or a holder that is
/// done): a previous result moved aside is put back when `out` is missing, else the files
/// in it that stride did not write are moved into `out` and it is removed; staging folders
/// are removed. Only entries of the work folder are touched; an aside folder whose user
/// files cannot be moved (a name taken in `out`) stays.
pub fn recover(work: &Path, out: &Path) {
    let Ok(rd) = std::fs::read_dir(work) else {
        return;
    };
    for e in rd.flatten() {
        let name = e.file_name();
        if name == OWNER {
            continue;
        }
        let path = e.path();
        if name == ASIDE {
            if !out.exists() {
                let _ = std::fs::rename(&path, out);
            } else if move_foreign(&path, out).is_ok() {
                let _ = std::fs::remove_dir_all(&path);
            }
            continue;
        }
        let _ = match path.is_dir() {
            true => std::fs::remove_dir_all(&path),
            false => std::fs::remove_file(&path),
        };
    }
}

/// Move the entries of the result folder `from` that stride did not write into `to`;
/// an error (and nothing more moved) when one of them cannot be moved.
pub(crate) fn move_foreign(from: &Path, to: &Path) -> std::io::Result<()> {
    let foreign = foreign_entries(from).unwrap_or_default();
    for name in foreign {
        let dst = to.join(&name);
        if dst.exists() {
            return Err(std::io::Error::new(
                std::io::ErrorKind::AlreadyExists,
                format!("{}: exists", dst.display()),
            ));
        }
        std::fs::rename(from.join(&name), &dst)?;
    }
    Ok(())
}

/// Clean up after dead processes in `dir`: every work folder whose claim is free (its
/// holder is not running; on another machine, its heartbeat is stale) is put in order
/// ([`recover`]) and removed. Returns the work folders handled. Nothing but work folders
/// is looked at.
pub fn clean_stale(dir: &Path) -> Vec<PathBuf> {
    let mut handled = Vec::new();
    for (original, work) in work_folders(dir) {
        let owner = work.join(OWNER);
        if !owner.is_file() || !is_work_folder(&work) || crate::claim::live_holder(&owner).is_some()
        {
            continue;
        }
        if let Ok(r) = Reservation::take(&dir.join(original)) {
            drop(r);
            handled.push(work);
        }
    }
    handled
}

/// Clean up the work folder of `dir/original` whoever holds it: for the holder of an
/// exclusive claim on `original` (a study case), whose work no other live process can be
/// doing, also on machines whose heartbeats are not stale yet. Returns whether there was one.
pub fn clean_work_of(dir: &Path, original: &str) -> bool {
    let out = dir.join(original);
    let work = work_dir(&out);
    if !work.join(OWNER).is_file() || !is_work_folder(&work) {
        return false;
    }
    recover(&work, &out);
    let _ = std::fs::remove_file(work.join(OWNER));
    let _ = std::fs::remove_dir(&work);
    true
}

/// The work folders in `dir`: (name of the result folder, work folder).
pub fn work_folders(dir: &Path) -> Vec<(String, PathBuf)> {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    rd.flatten()
        .filter(|e| e.file_type().is_ok_and(|t| t.is_dir()))
        .filter_map(|e| {
            let name = e.file_name().to_str()?.to_string();
            let original = name.strip_prefix(WORK_PREFIX)?;
            (!original.is_empty()).then(|| (original.to_string(), e.path()))
        })
        .collect()
}
