//! Output files named by the user (`--out FILE` of `stride view` and `stride model paths`):
//! an existing file is replaced only when asked to.

use anyhow::bail;
use std::path::Path;

/// Check that `path` may be written: it must not exist, or (with `force`) be a file, which
/// is then replaced. Called before the file is written; nothing is written on an error.
pub fn check_new_file(path: &Path, force: bool) -> anyhow::Result<()> {
    match std::fs::symlink_metadata(path) {
        Err(_) => Ok(()),
        Ok(m) if m.is_dir() => bail!("{}: is a folder; name a file to write", path.display()),
        Ok(_) if force => Ok(()),
        Ok(_) => bail!(
            "{}: exists; use --force to replace it, or choose another file",
            path.display()
        ),
    }
}
