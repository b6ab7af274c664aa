//! Output files: written completely or not at all, and CSV text.
//!
//! A regular file goes to a temporary file beside its final path (`.NAME.tmp-PID`) and is
//! renamed into place when complete, so an error leaves the old file or none; a symlink's
//! target is the file written. A character device (`/dev/null`) or a FIFO is written as a
//! stream and never replaced; anything else (a directory, a block device) is refused. The
//! temporary files in progress are registered, so a signal handler can remove them
//! ([`remove_partial_files`]): `tempfile`'s cleanup runs on drop, which an interrupted
//! process never reaches, hence this small hand-written registry.

use crate::{Error, Result};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Temporary files being written now (removed by [`remove_partial_files`]).
static IN_PROGRESS: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

fn registry() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    // a panic while holding the lock leaves a list that is still valid
    IN_PROGRESS.lock().unwrap_or_else(|e| e.into_inner())
}

/// Removes every temporary file still being written; for a SIGINT/SIGTERM handler, which
/// then exits. Returns how many were removed.
pub fn remove_partial_files() -> usize {
    let mut files = registry();
    let removed = files
        .iter()
        .filter(|p| std::fs::remove_file(p).is_ok())
        .count();
    files.clear();
    removed
}

/// Work files that an interrupt keeps (a sweep's finished rows), for the handler's message.
static KEPT: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Registers a work file that an interrupt keeps (see [`kept_files`]).
pub fn keep_on_interrupt(path: &Path) {
    KEPT.lock()
        .unwrap_or_else(|e| e.into_inner())
        .push(path.to_owned());
}

/// Unregisters a work file once it is done with.
pub fn forget_kept(path: &Path) {
    KEPT.lock()
        .unwrap_or_else(|e| e.into_inner())
        .retain(|p| p != path);
}

/// The work files an interrupt now would keep, for a signal handler's message.
pub fn kept_files() -> Vec<PathBuf> {
    KEPT.lock().unwrap_or_else(|e| e.into_inner()).clone()
}

/// The temporary path beside `path` that [`write_atomically`] writes first.
pub fn temporary_path(path: &Path) -> PathBuf {
    let dir = parent_dir(path);
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    dir.join(format!(".{name}.tmp-{}", std::process::id()))
}

/// The directory a file path lives in (`.` for a bare name).
fn parent_dir(path: &Path) -> &Path {
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
/// an existing, writable directory, or a character device or FIFO. `option` names the flag
/// in the error.
///
/// # Errors
/// [`Error::Option`] naming the option, the path and the problem.
pub fn check_writable(option: &str, path: &Path) -> Result<()> {
    let bad = |why: String| Err(Error::option(option, format!("{}: {why}", path.display())));
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
/// [`Error::Option`] naming `option` and the input it would overwrite.
pub fn check_not_an_input(option: &str, out: &Path, inputs: &[&Path]) -> Result<()> {
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
            return Err(Error::option(
                option,
                format!(
                    "{} is the input {}: writing it would destroy the input; choose another file",
                    out.display(),
                    input.display()
                ),
            ));
        }
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
    registry().push(tmp.clone());
    let result = (|| -> std::io::Result<()> {
        let handle = std::fs::File::create(&tmp)?;
        let mut w = std::io::BufWriter::new(handle);
        fill(&mut w)?;
        w.into_inner().map_err(|e| e.into_error())?.sync_all()?;
        std::fs::rename(&tmp, &file)
    })();
    registry().retain(|p| p != &tmp);
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
/// [`Error::Write`] or [`Error::Stdout`] (a closed or broken standard output included).
pub fn write_to(
    path: Option<&Path>,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<()> {
    match path {
        Some(p) => write_atomically(p, fill),
        None => {
            check_stdout_open()?;
            let stdout = std::io::stdout();
            let mut w = std::io::BufWriter::new(stdout.lock());
            fill(&mut w).and_then(|()| w.flush()).map_err(Error::Stdout)
        }
    }
}

/// Set by a binary that found its standard output closed when the process started (see
/// [`note_stdout_closed_at_start`]).
static STDOUT_CLOSED_AT_START: std::sync::atomic::AtomicBool =
    std::sync::atomic::AtomicBool::new(false);

/// Records that standard output was closed when the process started. Rust's runtime puts
/// `/dev/null` on a closed descriptor 1 before `main` runs, so only code that ran earlier (a
/// binary's constructor) can know; such a binary calls this at the start of `main`.
pub fn note_stdout_closed_at_start() {
    STDOUT_CLOSED_AT_START.store(true, std::sync::atomic::Ordering::Relaxed);
}

/// Fails when standard output is closed: writes to it would be discarded silently (by the
/// standard library, or into the `/dev/null` the runtime put in its place), which would lose
/// the output with exit code 0.
///
/// # Errors
/// [`Error::Stdout`].
pub fn check_stdout_open() -> Result<()> {
    // SAFETY: F_GETFD only queries the descriptor's flags.
    let closed_now = unsafe { libc::fcntl(1, libc::F_GETFD) } == -1;
    if closed_now || STDOUT_CLOSED_AT_START.load(std::sync::atomic::Ordering::Relaxed) {
        return Err(Error::Stdout(std::io::Error::other(
            "standard output is closed; give an output file instead",
        )));
    }
    Ok(())
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
