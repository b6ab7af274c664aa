//! The sampled controller as self-contained C99, for a machine's controller: one header and
//! one source, fixed-size arrays, no allocation, nothing beyond `math.h`; an init and a step
//! function that compute what the library's sampled laws compute, operation for operation
//! (so the two agree to rounding).
//!
//! [`emit_c`] dispatches on the law: the LQR on the linear filter (`lqr.rs`), on the extended
//! filter (`ekf.rs`) or the strain-rate law (`strain.rs`). Each writes the common part
//! (`common.rs`: banner, header, tables of the schedule, feedforward and rigid reference)
//! with one `append_*`-style step per part, then its fixed functions. Those fixed functions
//! are C source files under `src/control/emit/c/`, included verbatim after the generated
//! tables they read. The velocity-feedback law a plan designs has its own, smaller emitter
//! ([`velocity`]).

pub(crate) mod common;
mod ekf;
mod lqr;
mod strain;
pub mod velocity;

use crate::control::file::schema::{Controller, Estimator};
use crate::{Error, Result};
use std::path::Path;

/// The file names written by [`write_c`].
pub const C_FILES: [&str; 2] = ["telescopic_controller.h", "telescopic_controller.c"];

/// The header and the source of `file`'s sampled controller over `[start, end]` s.
///
/// # Errors
/// [`Error::Input`] when the controller has no sampled part.
pub fn emit_c(file: &Controller, start: f64, end: f64) -> Result<(String, String)> {
    let sampled = file.sampled_part()?;
    if let Some(law) = &sampled.strain_rate {
        return Ok(strain::emit_strain_rate(file, law, start, end));
    }
    if sampled.estimator == Estimator::Extended {
        return ekf::emit_extended(file, start, end);
    }
    if sampled.estimator != Estimator::Linear {
        return Err(Error::input(
            "controller `sampled.estimator`",
            format!(
                "the emitted C runs the linear or the extended filter, not `{}`",
                sampled.estimator
            ),
        ));
    }
    lqr::emit_linear(file, start, end)
}

/// Writes the header and the source into `dir` (each written whole or not at all).
///
/// # Errors
/// As [`emit_c`]; [`Error::Write`] naming a file that cannot be written.
pub fn write_c(file: &Controller, start: f64, end: f64, dir: &Path) -> Result<()> {
    let (header, source) = emit_c(file, start, end)?;
    crate::io::output::write_files_atomically(dir, &C_FILES, [header, source])
}
