//! `telescopic`: the command line over the `telescopic` library. It parses arguments into
//! the library's option structs, calls it, and prints; see `docs/cli.md`.

mod commands;
mod flags;
mod signals;
mod stdout;

/// The environment variable that sets the jobs' memory budget (bytes, or `512M`, `16G`).
const MEMORY_BUDGET_VARIABLE: &str = "TELESCOPIC_MEMORY_BUDGET";

/// The jobs' memory budget (bytes): [`MEMORY_BUDGET_VARIABLE`], else the library's default.
fn memory_budget() -> anyhow::Result<u64> {
    let text = std::env::var(MEMORY_BUDGET_VARIABLE).ok();
    Ok(telescopic::run::memory::parse_budget(text.as_deref())?)
}

fn main() -> std::process::ExitCode {
    signals::install();
    let cli = commands::Cli::parse_arguments();
    match cli.run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", flags::describe(&e));
            // stopped by Ctrl-C or SIGTERM (a sweep between runs): the shell's 128 + SIGINT
            let interrupted = matches!(
                e.downcast_ref::<telescopic::Error>(),
                Some(telescopic::Error::Interrupted { .. } | telescopic::Error::Stopped { .. })
            );
            std::process::ExitCode::from(if interrupted { 130 } else { 1 })
        }
    }
}
