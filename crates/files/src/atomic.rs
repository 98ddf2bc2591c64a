//! Atomic file writes: a reader sees the old file or the complete new one, never a part.

use std::io::Write as _;
use std::path::{Path, PathBuf};

/// Write `bytes` to `path` atomically: write a temporary file in the same folder, then
/// rename it over `path`, so readers never see a half-written result file. The temporary
/// file is named by [`crate::process::temp_name`].
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let file_name = path
        .file_name()
        .ok_or_else(|| {
            std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                format!("{}: not a file path", path.display()),
            )
        })?
        .to_string_lossy()
        .into_owned();
    let tmp = dir.join(crate::process::temp_name(&file_name));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        drop(f);
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}
