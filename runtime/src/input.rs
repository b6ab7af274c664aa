//! Input files read with a size cap, checked before reading (a regular file's length) and
//! while reading (a device or pipe such as `/dev/zero` has no length), so a wrong path can
//! never fill the memory.

use std::io::Read;
use std::path::Path;

/// Largest scene, sweep or controller file (bytes): 16 MiB, far above any real one.
pub const MAX_TEXT_INPUT_BYTES: u64 = 16 << 20;

/// Reads `path` as UTF-8 text of at most `cap` bytes.
///
/// # Errors
/// The I/O error, or `InvalidData` for a file over the cap (its size and the cap named) or
/// one that is not UTF-8 text.
pub fn read_text(path: &Path, cap: u64) -> std::io::Result<String> {
    let bytes = read_bytes(path, cap)?;
    String::from_utf8(bytes).map_err(|e| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!(
                "not UTF-8 text (byte {} is invalid)",
                e.utf8_error().valid_up_to()
            ),
        )
    })
}

/// Reads `path` whole, at most `cap` bytes.
///
/// # Errors
/// The I/O error, or `InvalidData` for a file over the cap (its size and the cap named).
pub fn read_bytes(path: &Path, cap: u64) -> std::io::Result<Vec<u8>> {
    let too_big = |size: String| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("{size} bytes, more than the {cap} bytes this kind of input may have"),
        )
    };
    let file = std::fs::File::open(path)?;
    let meta = file.metadata()?;
    if meta.is_dir() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "is a directory, not a file",
        ));
    }
    if meta.is_file() && meta.len() > cap {
        return Err(too_big(meta.len().to_string()));
    }
    let mut bytes = Vec::new();
    file.take(cap + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > cap {
        return Err(too_big(format!("over {cap}")));
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_device_without_length_is_cut_at_the_cap() {
        let e = read_text(Path::new("/dev/zero"), 1000).unwrap_err();
        assert!(e.to_string().contains("more than the 1000 bytes"), "{e}");
    }

    #[test]
    fn a_file_over_the_cap_is_refused_before_reading() {
        let path = std::env::temp_dir().join(format!("telescopic-cap-{}", std::process::id()));
        std::fs::write(&path, "x".repeat(101)).unwrap();
        let e = read_text(&path, 100).unwrap_err();
        assert!(e.to_string().starts_with("101 bytes"), "{e}");
        assert_eq!(read_text(&path, 101).unwrap().len(), 101);
        std::fs::remove_file(&path).unwrap();
    }
}
