//! `telescopic-codegen`: the [`telescopic_codegen::Builder`] as a command, for output that
//! is committed (what a crate builds from without running Symbolica).
//!
//! ```text
//! telescopic-codegen write  MODELS.toml DIR [--no-renderings]   generate into DIR
//! telescopic-codegen verify MODELS.toml DIR [--no-renderings]   check DIR against a fresh generation
//! ```
//!
//! Progress goes to stderr; stdout stays empty (Symbolica's banner included).

use std::process::ExitCode;
use telescopic_codegen::Builder;

/// The environment variable that names the Symbolica lock file.
const LOCK_VARIABLE: &str = "TELESCOPIC_SYMBOLICA_LOCK";

const USAGE: &str = "usage: telescopic-codegen write|verify MODELS.toml DIR [--no-renderings]";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let renderings = !args.iter().any(|a| a == "--no-renderings");
    let positional: Vec<&String> = args.iter().filter(|a| !a.starts_with("--")).collect();
    let unknown: Vec<&String> = args
        .iter()
        .filter(|a| a.starts_with("--") && *a != "--no-renderings")
        .collect();
    let ([command, models, dir], []) = (positional.as_slice(), unknown.as_slice()) else {
        eprintln!("{USAGE}");
        return ExitCode::from(2);
    };
    let mut builder = Builder::new().models_file(models).renderings(renderings);
    // the lock file every cooperating generator process shares, when not the default
    if let Some(lock) = std::env::var_os(LOCK_VARIABLE) {
        builder = builder.symbolica_lock(lock);
    }
    let start = std::time::Instant::now();
    let result = match command.as_str() {
        "write" => builder.write_to(dir).map(|w| {
            eprintln!(
                "{} configurations in {:.2} s: {} files written, {} unchanged, {} removed",
                w.keys.len(),
                start.elapsed().as_secs_f64(),
                w.changed.len(),
                w.unchanged,
                w.removed.len()
            );
            for path in w.changed.iter().chain(&w.removed) {
                eprintln!("  {}", path.display());
            }
        }),
        "verify" => builder.verify(dir).map(|()| {
            eprintln!("{dir} is what the generator makes from {models}");
        }),
        _ => {
            eprintln!("{USAGE}");
            return ExitCode::from(2);
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
