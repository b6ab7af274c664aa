//! `telescopic`: the command line over the `telescopic` library. It parses arguments into
//! the library's option structs, calls it, and prints; see `docs/cli.md`.

mod cli;

use clap::Parser;

fn main() -> std::process::ExitCode {
    // Ctrl-C or SIGTERM: remove the output files still being written, then stop (130).
    let _ = ctrlc::set_handler(|| {
        telescopic::output::remove_partial_files();
        eprintln!("interrupted: no partial output file was left");
        std::process::exit(130);
    });
    let cli = cli::Cli::parse();
    match cli.run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}
