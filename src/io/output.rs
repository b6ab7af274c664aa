//! Output files: written completely or not at all, and CSV text.
//!
//! A regular file goes to a temporary file beside its final path (`.NAME.tmp-PID`) and is
//! renamed into place when complete, so an error leaves the old file or none; a symlink's
//! target is the file written. A character device (`/dev/null`) or a FIFO is written as a
//! stream and never replaced; anything else (a directory, a block device) is refused. The
//! temporary file's name ([`temporary_path`]: the final name and the process id) lets a
//! signal handler of the caller's find and remove what an interrupted process left.

use crate::{Error, Result};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The temporary path beside `path` that [`write_atomically`] writes first.
pub fn temporary_path(path: &Path) -> PathBuf {
    let dir = parent_dir(path);
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    dir.join(format!(".{name}.tmp-{}", std::process::id()))
}

/// Whether `path` is a temporary file that [`write_atomically`] of this process writes (what a
/// signal handler removes when it stops the process).
pub fn is_temporary_of_this_process(path: &Path) -> bool {
    let suffix = format!(".tmp-{}", std::process::id());
    path.file_name()
        .and_then(|n| n.to_str())
        .is_some_and(|n| n.starts_with('.') && n.ends_with(&suffix))
}

/// The directory a file path lives in (`.` for a bare name).
pub fn parent_dir(path: &Path) -> &Path {
    path.parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
}

/// Where an output path leads: a regular file (or a new one) replaced whole, or a stream
/// (a character device such as `/dev/null`, or a FIFO) written through in place.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Destination {
    /// A regular file, replaced atomically; the path is the symlink's target when `path`
    /// was a symlink, so the link stays and its target is written.
    File(PathBuf),
    /// A character device or FIFO, opened for writing and never replaced.
    Stream(PathBuf),
}

impl Destination {
    /// Classifies `path`: symlinks are followed; a directory, a block device or a socket is
    /// refused.
    ///
    /// # Errors
    /// A message saying what `path` is and what an output may be.
    pub fn of(path: &Path) -> std::result::Result<Self, String> {
        use std::os::unix::fs::FileTypeExt;
        if path.file_name().is_none() {
            return Err("is a directory, not a file name".into());
        }
        let link = std::fs::symlink_metadata(path);
        let target = match &link {
            Ok(m) if m.file_type().is_symlink() => std::fs::canonicalize(path)
                .map_err(|e| format!("is a symbolic link whose target cannot be reached ({e})"))?,
            _ => path.to_owned(),
        };
        let Ok(meta) = std::fs::metadata(&target) else {
            return Ok(Destination::File(target));
        };
        let kind = meta.file_type();
        if kind.is_file() {
            Ok(Destination::File(target))
        } else if kind.is_char_device() || kind.is_fifo() {
            Ok(Destination::Stream(target))
        } else {
            let what = if kind.is_dir() {
                "a directory"
            } else if kind.is_block_device() {
                "a block device"
            } else {
                "a socket"
            };
            Err(format!(
                "is {what}; an output is a regular file (replaced whole), a character device \
                 such as /dev/null or a FIFO (written as a stream)"
            ))
        }
    }
}

/// Checks before any work that `path` can be written: a regular file (new or existing) in
/// an existing, writable directory, or a character device or FIFO.
///
/// # Errors
/// [`Error::Destination`] naming the path and the problem.
pub fn check_writable(path: &Path) -> Result<()> {
    let bad = |rule: String| {
        Err(Error::Destination {
            path: path.to_path_buf(),
            rule,
        })
    };
    let file = match Destination::of(path) {
        Ok(Destination::Stream(_)) => return Ok(()),
        Ok(Destination::File(file)) => file,
        Err(why) => return bad(why),
    };
    let dir = parent_dir(&file);
    if !dir.is_dir() {
        return bad(format!("the directory {} does not exist", dir.display()));
    }
    // probe with the same kind of temporary file the real write uses
    let probe = dir.join(format!(".telescopic-probe-{}", std::process::id()));
    match std::fs::File::create(&probe) {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => bad(format!(
            "the directory {} is not writable ({e})",
            dir.display()
        )),
    }
}

/// Refuses an output that is one of the command's inputs, however spelled (the same file
/// on disk: device and inode), so that writing the output cannot destroy an input.
///
/// # Errors
/// [`Error::Destination`] naming the input it would overwrite.
pub fn check_not_an_input(out: &Path, inputs: &[&Path]) -> Result<()> {
    use std::os::unix::fs::MetadataExt;
    let Ok(out_meta) = std::fs::metadata(out) else {
        return Ok(()); // a new file is no input
    };
    if !out_meta.is_file() {
        return Ok(()); // a stream is written through, never replaced
    }
    for input in inputs {
        if let Ok(m) = std::fs::metadata(input)
            && (m.dev(), m.ino()) == (out_meta.dev(), out_meta.ino())
        {
            return Err(Error::Destination {
                path: out.to_path_buf(),
                rule: format!(
                    "is the input {}: writing it would destroy the input; choose another file",
                    input.display()
                ),
            });
        }
    }
    Ok(())
}

/// Writes each of `texts` into `dir` under the matching one of `names`, each file whole or
/// not at all ([`write_atomically`]): an emitted header and source.
///
/// # Errors
/// [`Error::Write`] naming the first file that cannot be written.
pub fn write_files_atomically<const N: usize>(
    dir: &Path,
    names: &[&str; N],
    texts: [String; N],
) -> Result<()> {
    for (name, text) in names.iter().zip(texts) {
        write_atomically(&dir.join(name), |w| w.write_all(text.as_bytes()))?;
    }
    Ok(())
}

/// Writes `path`: a regular file through a temporary file in the same directory, renamed
/// when `fill` succeeded (removed otherwise, so no partial file is left at `path`); a
/// character device or FIFO directly, as a stream.
///
/// # Errors
/// [`Error::Write`] naming the file.
pub fn write_atomically(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    let write_error = |error| Error::Write {
        path: path.to_owned(),
        error,
    };
    let file = match Destination::of(path) {
        Ok(Destination::File(file)) => file,
        Ok(Destination::Stream(stream)) => return write_stream(&stream, fill).map_err(write_error),
        Err(why) => return Err(write_error(std::io::Error::other(why))),
    };
    let tmp = temporary_path(&file);
    let result = (|| -> std::io::Result<()> {
        let handle = std::fs::File::create(&tmp)?;
        let mut w = std::io::BufWriter::new(handle);
        fill(&mut w)?;
        w.into_inner().map_err(|e| e.into_error())?.sync_all()?;
        std::fs::rename(&tmp, &file)
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(write_error(e));
    }
    Ok(())
}

/// Writes a character device or FIFO in place (no truncation, no rename).
fn write_stream(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> std::io::Result<()> {
    let handle = std::fs::OpenOptions::new().write(true).open(path)?;
    let mut w = std::io::BufWriter::new(handle);
    fill(&mut w)?;
    w.flush()
}

/// Writes to `path` atomically, or to standard output when `path` is `None`.
///
/// # Errors
/// [`Error::Write`] or [`Error::Stdout`] (a broken standard output).
pub fn write_to(
    path: Option<&Path>,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    match path {
        Some(p) => write_atomically(p, fill),
        None => {
            let stdout = std::io::stdout();
            let mut w = std::io::BufWriter::new(stdout.lock());
            fill(&mut w).and_then(|()| w.flush()).map_err(Error::Stdout)
        }
    }
}

/// A number as CSV text: shortest round-trip digits, positional for moderate magnitudes and
/// with an exponent for tiny or huge ones.
pub fn csv_number(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || (1e-4..1e7).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}
