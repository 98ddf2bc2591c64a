//! Claims on one unit of work (a study case) among many writers of a shared folder, also on
//! several machines (cluster nodes): decision 0007.
//!
//! A claim is an exclusive `flock` on a claim file, which the holder fills with a line
//! naming itself (`<host> <pid> <job> <unix start time>`) and whose modification time it
//! refreshes every [`HEARTBEAT`] (the heartbeat). The system releases the lock when the
//! holder dies, also on `kill -9`; the file's text then stays behind, describing a dead
//! holder. A holder is live when the lock is held, or, seen from another machine (whose
//! `flock` the shared file system may not pass on), when its heartbeat is younger than
//! [`STALE_AFTER`]. A clean release empties the file.

use crate::lock::{FileLock, LockError, LockMode};
use crate::process::{process_alive, this_host};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::sync::Arc;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

/// Interval of a holder's heartbeat (claim file modification time refreshed).
pub const HEARTBEAT: Duration = Duration::from_secs(30);
/// Age of the last heartbeat after which a holder on another machine counts as dead.
pub const STALE_AFTER: Duration = Duration::from_secs(120);

/// Who holds (or held) a claim, as written in its claim file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Holder {
    /// Short host name.
    pub host: String,
    /// Process id on that host.
    pub pid: u32,
    /// Batch job (e.g. Slurm `12345_7`), `-` when not run by a scheduler.
    pub job: String,
    /// Start of the claim [s since 1970].
    pub since: u64,
    /// Age of the last heartbeat (time since the file was last modified).
    pub heartbeat_age: Duration,
}

impl std::fmt::Display for Holder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "process {} on {}", self.pid, self.host)?;
        if self.job != "-" {
            write!(f, ", job {}", self.job)?;
        }
        write!(f, ", heartbeat {} s ago", self.heartbeat_age.as_secs())
    }
}

/// Why a claim was not taken.
#[derive(Debug, thiserror::Error)]
pub enum ClaimError {
    /// A live holder has it.
    #[error("{path}: claimed by {holder}")]
    Held {
        /// Claim file.
        path: String,
        /// The holder.
        holder: Holder,
    },
    /// The claim file could not be used.
    #[error("{path}: cannot claim ({reason})")]
    Io {
        /// Claim file.
        path: String,
        /// The system's reason.
        reason: String,
    },
}

/// A claim held until dropped (the heartbeat stops, the file is emptied, the lock released).
#[derive(Debug)]
pub struct Claim {
    lock: Arc<FileLock>,
    stop: Option<mpsc::Sender<()>>,
    beat: Option<std::thread::JoinHandle<()>>,
}

/// The holder written in the claim file `path` and the age of its heartbeat; `None` when
/// the file is missing, empty or not a claim.
pub fn read_holder(path: &Path) -> Option<Holder> {
    let text = std::fs::read_to_string(path).ok()?;
    let modified = std::fs::metadata(path).ok()?.modified().ok()?;
    let mut w = text.split_whitespace();
    let host = w.next()?.to_string();
    let pid = w.next()?.parse().ok()?;
    let job = w.next()?.to_string();
    let since = w.next()?.parse().ok()?;
    Some(Holder {
        host,
        pid,
        job,
        since,
        heartbeat_age: SystemTime::now()
            .duration_since(modified)
            .unwrap_or(Duration::ZERO),
    })
}

/// Whether `holder` (read from a claim file) is still running: on this host, its process
/// exists; on another, its heartbeat is younger than [`STALE_AFTER`].
pub fn is_live(holder: &Holder) -> bool {
    if holder.host == this_host() {
        holder.pid == std::process::id() || process_alive(holder.pid)
    } else {
        holder.heartbeat_age < STALE_AFTER
    }
}

/// The live holder of the claim file `path`, if any (reads only: never locks, so it cannot
/// get in the way of a claim being taken).
pub fn live_holder(path: &Path) -> Option<Holder> {
    read_holder(path).filter(is_live)
}

impl Claim {
    /// Take the claim `path` (created if missing) for this process, named with `job` (`-`
    /// for none), without waiting: refused when another process holds the lock, or when
    /// the file names a live holder on another host (a shared file system that does not
    /// pass `flock` between machines).
    pub fn try_take(path: &Path, job: &str) -> Result<Claim, ClaimError> {
        if let Some(holder) = read_holder(path).filter(|h| h.host != this_host() && is_live(h)) {
            return Err(ClaimError::Held {
                path: path.display().to_string(),
                holder,
            });
        }
        let lock = FileLock::try_lock(path, LockMode::Exclusive).map_err(|e| match e {
            LockError::Held { .. } => ClaimError::Held {
                path: path.display().to_string(),
                holder: read_holder(path).unwrap_or(Holder {
                    host: "?".into(),
                    pid: 0,
                    job: "-".into(),
                    since: 0,
                    heartbeat_age: Duration::ZERO,
                }),
            },
            LockError::Io { path, reason } => ClaimError::Io { path, reason },
        })?;
        let since = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map(|d| d.as_secs())
            .unwrap_or(0);
        let text = format!("{} {} {job} {since}\n", this_host(), std::process::id());
        let io = |e: std::io::Error| ClaimError::Io {
            path: path.display().to_string(),
            reason: e.to_string(),
        };
        lock.set_text(&text).map_err(io)?;
        let lock = Arc::new(lock);
        let (stop, rx) = mpsc::channel::<()>();
        let beating = Arc::clone(&lock);
        let beat = std::thread::spawn(move || {
            while let Err(mpsc::RecvTimeoutError::Timeout) = rx.recv_timeout(HEARTBEAT) {
                let _ = beating.touch();
            }
        });
        Ok(Claim {
            lock,
            stop: Some(stop),
            beat: Some(beat),
        })
    }

    /// The claim file.
    pub fn path(&self) -> PathBuf {
        self.lock.path().to_path_buf()
    }
}

impl Drop for Claim {
    fn drop(&mut self) {
        drop(self.stop.take());
        if let Some(b) = self.beat.take() {
            let _ = b.join();
        }
        // the last reference: FileLock's drop empties the file and releases the lock
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_claim_is_exclusive_names_its_holder_and_is_free_after_drop_or_death() {
        let p = std::env::temp_dir().join(format!("stride-claim-{}", std::process::id()));
        let c = Claim::try_take(&p, "77_3").unwrap();
        let h = live_holder(&p).expect("live");
        assert_eq!(
            (h.host.as_str(), h.pid, h.job.as_str()),
            (this_host(), std::process::id(), "77_3")
        );
        let e = Claim::try_take(&p, "-").unwrap_err();
        assert!(e.to_string().contains("job 77_3"), "{e}");
        drop(c);
        assert_eq!(read_holder(&p), None, "a released claim names nobody");
        // a holder on this host that died: its line stays, it is not live
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let dead = child.id();
        child.wait().unwrap();
        std::fs::write(&p, format!("{} {dead} 5_1 0\n", this_host())).unwrap();
        assert!(read_holder(&p).is_some() && live_holder(&p).is_none());
        drop(Claim::try_take(&p, "-").unwrap());
        // a holder on another host is live while its heartbeat is fresh
        std::fs::write(&p, "elsewhere 1 6_2 0\n").unwrap();
        assert!(live_holder(&p).is_some());
        assert!(matches!(
            Claim::try_take(&p, "-"),
            Err(ClaimError::Held { .. })
        ));
        let old = SystemTime::now() - STALE_AFTER - Duration::from_secs(1);
        std::fs::File::options()
            .write(true)
            .open(&p)
            .unwrap()
            .set_modified(old)
            .unwrap();
        assert!(live_holder(&p).is_none());
        drop(Claim::try_take(&p, "-").unwrap());
        std::fs::remove_file(&p).unwrap();
    }
}
