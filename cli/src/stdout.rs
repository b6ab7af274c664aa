//! Standard output as the command's output: refused when it is closed, so that output is
//! never lost with exit code 0.

use std::io::Write;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

/// Whether descriptor 1 was closed when the process started.
static CLOSED_AT_START: AtomicBool = AtomicBool::new(false);

/// Runs before Rust's runtime, which would put `/dev/null` on a closed standard output and
/// hide that the output is lost: a constructor in `.init_array` (hand-written: a dependency
/// for one function pointer is not worth it).
extern "C" fn record_closed_stdout() {
    CLOSED_AT_START.store(closed_now(), Ordering::Relaxed);
}

#[used]
#[unsafe(link_section = ".init_array")]
static RECORD_CLOSED_STDOUT: extern "C" fn() = record_closed_stdout;

/// Whether descriptor 1 is closed now.
fn closed_now() -> bool {
    // SAFETY: F_GETFD only queries the descriptor's flags.
    unsafe { libc::fcntl(1, libc::F_GETFD) == -1 }
}

/// Fails when standard output is closed (now or when the process started): writes to it
/// would be discarded silently.
pub fn check_stdout_open() -> anyhow::Result<()> {
    if closed_now() || CLOSED_AT_START.load(Ordering::Relaxed) {
        anyhow::bail!(
            "writing to standard output: standard output is closed; give an output file instead"
        );
    }
    Ok(())
}

/// Writes `path` whole (the library's [`telescopic::io::output::write_to`]), or standard
/// output when `path` is `None` and it is open.
pub fn write_to(
    path: Option<&Path>,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> anyhow::Result<()> {
    if path.is_none() {
        check_stdout_open()?;
    }
    Ok(telescopic::io::output::write_to(path, fill)?)
}
