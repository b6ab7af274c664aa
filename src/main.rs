//! `telescopic`: equations of motion, simulation and eigen analysis of telescopic
//! multi-section beams with clearance. See the README for the commands.

mod choose;
mod cli;
mod converge;
mod equations;
mod modes;
mod plot;
mod shape_errors;
mod simulate;
mod stability;
mod work_precision;

use clap::Parser;

fn main() -> std::process::ExitCode {
    let cli = cli::Cli::parse();
    match cli.run() {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}
