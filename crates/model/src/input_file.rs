//! Reading an input file a user names, with a size cap: a device such as `/dev/zero`, a
//! pipe or a huge file gets a clear error before memory runs out, and a folder where a
//! file is expected is named as such.

use std::path::Path;

/// Largest text settings file read (model settings, prediction and tracking files)
/// [bytes]; real ones are a few kB.
pub const MAX_SETTINGS_BYTES: u64 = 16 << 20;

/// The bytes of the input file `path`, refusing a file larger than `limit` bytes (or one
/// that is not a regular file) before reading it.
pub fn read_limited(path: &Path, limit: u64) -> std::io::Result<Vec<u8>> {
    use std::io::Read as _;
    let file = std::fs::File::open(path)?;
    let meta = file.metadata()?;
    if meta.is_dir() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "is a folder, not a file",
        ));
    }
    if meta.len() > limit {
        return Err(too_large(meta.len(), limit));
    }
    let mut bytes = Vec::new();
    // a device or pipe reports no length: stop one byte past the limit
    file.take(limit + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(too_large(bytes.len() as u64, limit));
    }
    Ok(bytes)
}

/// The UTF-8 text of the input file `path`, at most `limit` bytes (see [`read_limited`]).
pub fn read_text_limited(path: &Path, limit: u64) -> std::io::Result<String> {
    let bytes = read_limited(path, limit)?;
    String::from_utf8(bytes).map_err(|e| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!(
                "is not UTF-8 text (invalid byte at offset {})",
                e.utf8_error().valid_up_to()
            ),
        )
    })
}

fn too_large(size: u64, limit: u64) -> std::io::Error {
    std::io::Error::new(
        std::io::ErrorKind::InvalidData,
        format!(
            "file of {:.1} MB is larger than the {} MB accepted",
            size as f64 / 1048576.0,
            limit >> 20
        ),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_folders_and_large_files_are_refused_before_reading_them_whole() {
        let e = read_limited(Path::new("/dev/zero"), 1 << 20).unwrap_err();
        assert!(
            e.to_string().contains("larger than the 1 MB accepted"),
            "{e}"
        );
        let dir = std::env::temp_dir();
        let e = read_limited(&dir, 1 << 20).unwrap_err();
        assert_eq!(e.to_string(), "is a folder, not a file");
        let f = dir.join(format!("stride-input-file-{}.txt", std::process::id()));
        std::fs::write(&f, b"abc\xff").unwrap();
        assert_eq!(read_limited(&f, 4).unwrap(), b"abc\xff");
        assert!(read_limited(&f, 3).is_err());
        let e = read_text_limited(&f, 4).unwrap_err();
        assert!(
            e.to_string()
                .contains("not UTF-8 text (invalid byte at offset 3)"),
            "{e}"
        );
        std::fs::remove_file(&f).unwrap();
    }
}
