//! Advisory file locks (`flock`, Linux and macOS) that say who holds them: the holder of an
//! exclusive lock writes its process id into the lock file, so that a refused process can
//! name it. The system releases a lock when its holder exits, also on `kill -9`.

use std::fs::File;
use std::io::{Read as _, Seek as _, Write as _};
use std::os::fd::AsRawFd as _;
use std::os::unix::fs::MetadataExt as _;
use std::path::{Path, PathBuf};

use crate::process::this_host;

/// Whether the open `file` is the file now at `path` (same device and inode).
fn same_file(file: &File, path: &Path) -> bool {
    match (file.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

/// A lock held on a file until dropped.
#[derive(Debug)]
pub struct FileLock {
    file: File,
    path: PathBuf,
    mode: LockMode,
}

/// Why a lock was not taken.
#[derive(Debug, thiserror::Error)]
pub enum LockError {
    /// Another process holds the lock.
    #[error("{path}: in use by another stride process{}", holder_text(*.holder, .host.as_deref()))]
    Held {
        /// Lock file.
        path: String,
        /// Process id written by the holder, when known.
        holder: Option<u32>,
        /// Host written by the holder, when known.
        host: Option<String>,
    },
    /// The lock file could not be opened or locked.
    #[error("{path}: cannot lock ({reason})")]
    Io {
        /// Lock file.
        path: String,
        /// The system's reason.
        reason: String,
    },
}

/// ` (process id P on HOST)` for a lock holder, as far as known; empty when unknown.
pub fn holder_text(pid: Option<u32>, host: Option<&str>) -> String {
    match (pid, host) {
        (Some(p), Some(h)) => format!(" (process id {p} on {h})"),
        (Some(p), None) => format!(" (process id {p})"),
        _ => String::new(),
    }
}

/// How a lock is shared.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LockMode {
    /// One holder, no shared holders (e.g. a whole-study run).
    Exclusive,
    /// Any number of shared holders, no exclusive one (e.g. runners of single cases, each
    /// of which also takes an exclusive lock on its case).
    Shared,
}

impl FileLock {
    /// Take the lock on `path` (created if missing) without waiting; an exclusive holder
    /// records its process id and host in the file. A lock file removed or replaced by its
    /// previous holder while this process opened it is opened again, so that two processes
    /// never hold locks on two files of one name.
    pub fn try_lock(path: &Path, mode: LockMode) -> Result<FileLock, LockError> {
        let io = |e: std::io::Error| LockError::Io {
            path: path.display().to_string(),
            reason: e.to_string(),
        };
        for _ in 0..8 {
            let mut file = std::fs::OpenOptions::new()
                .read(true)
                .write(true)
                .create(true)
                .truncate(false)
                .open(path)
                .map_err(io)?;
            let op = match mode {
                LockMode::Exclusive => libc::LOCK_EX,
                LockMode::Shared => libc::LOCK_SH,
            } | libc::LOCK_NB;
            // SAFETY: flock on a file descriptor this function owns.
            if unsafe { libc::flock(file.as_raw_fd(), op) } != 0 {
                let e = std::io::Error::last_os_error();
                if e.raw_os_error() != Some(libc::EWOULDBLOCK) {
                    return Err(io(e));
                }
                let mut text = String::new();
                let _ = file.read_to_string(&mut text);
                let mut words = text.split_whitespace();
                return Err(LockError::Held {
                    path: path.display().to_string(),
                    holder: words.next().and_then(|p| p.parse().ok()),
                    host: words.next().map(str::to_string),
                });
            }
            if !same_file(&file, path) {
                continue;
            }
            if mode == LockMode::Exclusive {
                file.set_len(0).map_err(io)?;
                file.rewind().map_err(io)?;
                writeln!(file, "{} {}", std::process::id(), this_host()).map_err(io)?;
                file.flush().map_err(io)?;
            }
            return Ok(FileLock {
                file,
                path: path.to_path_buf(),
                mode,
            });
        }
        Err(io(std::io::Error::other(
            "the lock file keeps being replaced",
        )))
    }

    /// The lock file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Replace the lock file's text (an exclusive holder describing itself).
    pub fn set_text(&self, text: &str) -> std::io::Result<()> {
        let mut f = &self.file;
        f.set_len(0)?;
        f.rewind()?;
        f.write_all(text.as_bytes())?;
        f.flush()
    }

    /// Set the lock file's modification time to now (a holder's heartbeat).
    pub fn touch(&self) -> std::io::Result<()> {
        self.file.set_modified(std::time::SystemTime::now())
    }
}

impl Drop for FileLock {
    fn drop(&mut self) {
        if self.mode == LockMode::Exclusive {
            // the process id is stale from now on
            let _ = self.file.set_len(0);
        }
        // SAFETY: unlocking the descriptor owned by this lock (closing it would as well).
        unsafe {
            libc::flock(self.file.as_raw_fd(), libc::LOCK_UN);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_exclusive_lock_is_refused_with_the_holder_and_freed_on_drop() {
        let p = std::env::temp_dir().join(format!("stride-lock-{}", std::process::id()));
        let held = FileLock::try_lock(&p, LockMode::Exclusive).unwrap();
        // flock locks belong to the open file: a second open in this process conflicts too
        let e = FileLock::try_lock(&p, LockMode::Exclusive).unwrap_err();
        assert!(
            matches!(e, LockError::Held { holder: Some(pid), .. } if pid == std::process::id()),
            "{e}"
        );
        assert!(e.to_string().contains(&format!(
            "process id {} on {}",
            std::process::id(),
            this_host()
        )));
        assert!(FileLock::try_lock(&p, LockMode::Shared).is_err());
        drop(held);
        let a = FileLock::try_lock(&p, LockMode::Shared).unwrap();
        let b = FileLock::try_lock(&p, LockMode::Shared).unwrap();
        assert!(FileLock::try_lock(&p, LockMode::Exclusive).is_err());
        drop((a, b));
        // a lock file removed by its holder before release is not locked by a late opener
        let held = FileLock::try_lock(&p, LockMode::Exclusive).unwrap();
        std::fs::remove_file(&p).unwrap();
        let second = FileLock::try_lock(&p, LockMode::Exclusive).unwrap();
        assert!(same_file(&second.file, &p) && !same_file(&held.file, &p));
        drop((held, second));
        std::fs::remove_file(&p).unwrap();
    }
}
