//! stride-files: how stride writes its results so that an interruption loses nothing.
//!
//! - [`atomic`]: one file written atomically (temporary file, then rename).
//! - [`result_dir`]: result folders: what may be written or replaced, which files are stride's,
//!   a result staged and put in place whole.
//! - [`reserve`]: one writer per result folder, and the work folder beside it that holds
//!   everything stride writes next to a result.
//! - [`marker`]: the marker file that says a folder is a stride result and lists stride's
//!   files in it.
//! - [`lock`]: advisory file locks that name their holder.
//! - [`claim`]: claims on one study case among writers on several machines.
//! - [`process`]: this process as seen by others (host name, temporary-file tag, liveness).

pub mod atomic;
pub mod claim;
pub mod lock;
pub mod marker;
pub mod process;
pub mod reserve;
pub mod result_dir;

pub use atomic::write_atomic;
