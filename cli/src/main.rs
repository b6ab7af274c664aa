//! `telescopic`: the command line over the `telescopic` library. It parses arguments into
//! the library's option structs, calls it, and prints; see `docs/cli.md`.

mod commands;
mod flags;

/// The environment variable that sets the jobs' memory budget (bytes, or `512M`, `16G`).
const MEMORY_BUDGET_VARIABLE: &str = "TELESCOPIC_MEMORY_BUDGET";

/// The jobs' memory budget (bytes): [`MEMORY_BUDGET_VARIABLE`], else the library's default.
fn memory_budget() -> anyhow::Result<u64> {
    let text = std::env::var(MEMORY_BUDGET_VARIABLE).ok();
    Ok(telescopic::run::memory::parse_budget(
        MEMORY_BUDGET_VARIABLE,
        text.as_deref(),
    )?)
}

use std::sync::atomic::{AtomicBool, Ordering};

/// Whether descriptor 1 was closed when the process started.
static STDOUT_CLOSED: AtomicBool = AtomicBool::new(false);

/// Runs before Rust's runtime, which would put `/dev/null` on a closed standard output and
/// hide that the output is lost: a constructor in `.init_array` (hand-written: a dependency
/// for one function pointer is not worth it).
extern "C" fn record_closed_stdout() {
    // SAFETY: F_GETFD only queries the descriptor's flags.
    STDOUT_CLOSED.store(
        unsafe { libc::fcntl(1, libc::F_GETFD) } == -1,
        Ordering::Relaxed,
    );
}

#[used]
#[unsafe(link_section = ".init_array")]
static RECORD_CLOSED_STDOUT: extern "C" fn() = record_closed_stdout;

fn main() -> std::process::ExitCode {
    if STDOUT_CLOSED.load(Ordering::Relaxed) {
        telescopic::io::output::note_stdout_closed_at_start();
    }
    // Ctrl-C or SIGTERM: a sweep stops between runs (keeping every finished row); anything
    // else, or a second signal, removes the output files still being written and stops (130)
    let _ = ctrlc::set_handler(|| {
        if telescopic::interrupt::request() {
            eprintln!("\ninterrupt: stopping after the runs in progress (again to stop at once)");
            return;
        }
        telescopic::io::output::remove_partial_files();
        let kept = telescopic::io::output::kept_files();
        if kept.is_empty() {
            eprintln!("interrupted: no partial output file was left");
        } else {
            for path in kept {
                eprintln!(
                    "interrupted: the finished runs are kept in {} (run again with --resume)",
                    path.display()
                );
            }
        }
        std::process::exit(130);
    });
    let cli = commands::Cli::parse_arguments();
    match cli.run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", flags::in_flags(&format!("{e:#}")));
            // stopped by Ctrl-C or SIGTERM (a sweep between runs): the shell's 128 + SIGINT
            let interrupted = matches!(
                e.downcast_ref::<telescopic::Error>(),
                Some(telescopic::Error::Interrupted(_))
            );
            std::process::ExitCode::from(if interrupted { 130 } else { 1 })
        }
    }
}
