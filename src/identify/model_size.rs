//! The model a fit runs: the smallest size whose own error against the beams is below every
//! recorded sensor's noise, so that the fitted values do not absorb the model's truncation.
//! It climbs the ladder of sizes with the static correction shapes (4, 6, 9, 14, 21 modes
//! per section), each run with its companion of the next size, until every sensor's
//! truncation estimate ([`crate::run::error_budget::Truncation`], its largest over the
//! record) is within [`NOISE_BAND`] deviations of its noise. The
//! accuracy search's floor (1e-5 m in `tip_rel`) is too coarse for this: a strain gauge's
//! curvature at a clamped foot converges slower than the tip.

use super::record::Record;
use crate::Result;
use crate::run::{ModelSize, Simulation, SimulationOptions, simulate_scene};
use telescopic_runtime::{Basis, Output, Scene};

/// The smallest size the ladder starts from.
pub const FIRST_SIZE: ModelSize = ModelSize {
    basis: Basis::ModesAndStatic,
    modes: 4,
};

/// A sensor's truncation estimate (its largest over the record) must be within this many
/// noise deviations: the band the noise itself fills over a record of thousands of samples.
pub const NOISE_BAND: f64 = 3.0;

/// The model a fit runs, and how its error compares with the record's noise.
#[derive(Debug, Clone, PartialEq)]
pub struct FitModel {
    /// Basis and modes per section.
    pub size: ModelSize,
    /// Each sensor's truncation estimate in its unit (`None`: not estimated), in the
    /// record's order.
    pub errors: Vec<Option<f64>>,
    /// Whether every sensor's estimate is within its noise.
    pub within_noise: bool,
}

/// The model for fitting `record` with `noise` (per sensor) on `driven` (`asked`: this
/// size, checked but kept), and its run at the scene's values.
///
/// # Errors
/// Errors of the runs.
pub fn fit_model(
    driven: &Scene,
    record: &Record,
    noise: &[f64],
    asked: Option<ModelSize>,
    reporter: &dyn crate::Reporter,
) -> Result<(FitModel, Simulation)> {
    let sizes = match asked {
        Some(size) => vec![size],
        None => crate::run::total_accuracy::ladder(FIRST_SIZE.basis, FIRST_SIZE.modes),
    };
    let options = SimulationOptions {
        modes_as_given: true,
        ..SimulationOptions::default()
    };
    let mut best = None;
    for size in sizes {
        let simulation = simulate_scene(&size.apply(driven), &options, &crate::Silent)?;
        let errors = sensor_errors(&simulation, record);
        let within_noise = errors
            .iter()
            .zip(noise)
            .all(|(e, sigma)| e.is_some_and(|e| e <= NOISE_BAND * sigma));
        let unknown = errors.iter().all(Option::is_none);
        reporter.note(&format!(
            "fit model {size}: {}",
            if within_noise {
                "every sensor's truncation is within its noise"
            } else {
                "a sensor's truncation exceeds its noise"
            }
        ));
        // the last size has no companion: keep the one before it
        if unknown && best.is_some() {
            break;
        }
        let model = FitModel {
            size,
            errors,
            within_noise,
        };
        best = Some((model, simulation));
        if within_noise {
            break;
        }
    }
    Ok(best.expect("a ladder has a first size"))
}

/// Each of `record`'s sensors' truncation estimate in `simulation`.
fn sensor_errors(simulation: &Simulation, record: &Record) -> Vec<Option<f64>> {
    let truncation = simulation
        .error
        .as_ref()
        .and_then(|e| e.truncation.as_ref());
    record
        .sensors
        .iter()
        .map(|(output, _)| {
            let t = truncation?;
            if *output == Output::TipRel {
                return Some(t.tip_m);
            }
            let name = output.to_string();
            t.outputs.iter().find(|(c, _)| *c == name).map(|(_, e)| *e)
        })
        .collect()
}
