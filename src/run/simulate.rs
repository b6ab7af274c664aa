//! Simulating a scene: the prepared run, its integration, and the companion run of a
//! refined model that estimates the truncation error; with a total accuracy, the search
//! for the model size ([`super::total_accuracy`]).

use super::error_budget::{self, ErrorBudget};
use super::options::SimulationOptions;
use super::prepared::PreparedRun;
use super::simulation::Simulation;
use crate::report::{Phase, Reporter};
use crate::run::models::ModelChoice;
use crate::{Error, Result};
use telescopic_runtime::Scene;

/// Simulates `scene` with `options`: chooses the model and the method, checks that the run
/// fits the resource limits and is affordable, integrates from rest, collects every sample,
/// and estimates the run's error ([`crate::run::error_budget`]). With
/// [`SimulationOptions::accuracy`] (and not [`SimulationOptions::modes_as_given`]) it also
/// picks the basis and the modes per section ([`crate::run::total_accuracy`]).
///
/// # Errors
/// [`Error`] for bad options, a model that cannot be had, an unaffordable run (with the
/// estimate), or a failed integration (time, method, likely cause).
pub fn simulate_scene(
    scene: &Scene,
    options: &SimulationOptions,
    reporter: &dyn Reporter,
) -> Result<Simulation> {
    if options.accuracy.is_some() && !options.modes_as_given {
        return crate::run::total_accuracy::simulate_for_accuracy(scene, options, reporter);
    }
    // with the companion run, the run is the first part of the progress
    let main_share = if options.error_estimate {
        COMPANION_SPLIT
    } else {
        1.0
    };
    let main = Phase {
        inner: reporter,
        share: (0.0, main_share),
    };
    let run = PreparedRun::new(scene, options, &main)?;
    let trajectory = run.integrate(&main)?;
    let mut simulation = run.into_simulation(trajectory);
    if options.error_estimate {
        let companion = Phase {
            inner: reporter,
            share: (main_share, 1.0),
        };
        simulation.error = Some(estimate_error(scene, options, &simulation, &companion)?);
    }
    Ok(simulation)
}

/// The share of a run's progress before its companion run starts (the companion, with more
/// modes, takes one to three times as long on the shipped scenes).
const COMPANION_SPLIT: f64 = 0.4;

/// The error budget of `simulation`, a run of `scene` with `options`: its integration part
/// from the plan, its truncation part from a companion run of the refined model.
///
/// # Errors
/// A failed companion run (an unaffordable one is reported as missing instead).
pub fn estimate_error(
    scene: &Scene,
    options: &SimulationOptions,
    simulation: &Simulation,
    reporter: &dyn Reporter,
) -> Result<ErrorBudget> {
    let window = error_budget::window(&scene.params, &simulation.trajectory);
    let mut budget = ErrorBudget {
        window,
        integration_m: simulation.plan.integration_error_m,
        integration_statistics: simulation.plan.integration_statistics_rel,
        truncation: None,
        missing: None,
    };
    let Some(refined) = error_budget::refined(&scene.params) else {
        budget.missing = Some(format!(
            "every section has {} modes, the most there are",
            telescopic_runtime::MAX_MODES
        ));
        return Ok(budget);
    };
    let mut companion_scene = scene.clone();
    companion_scene.params = refined;
    let companion_options = SimulationOptions {
        error_estimate: false,
        coordinates: false,
        // a generated model of the refined size may not exist: the registry falls back
        model: match options.model {
            ModelChoice::Generated => ModelChoice::Auto,
            other => other,
        },
        ..options.clone()
    };
    let prepared = PreparedRun::new(&companion_scene, &companion_options, &crate::Silent)?;
    match prepared.integrate(reporter) {
        Ok(companion) => {
            budget.truncation = Some(error_budget::truncation(
                &simulation.trajectory,
                &companion,
                companion_scene.params.modes(),
                window,
            ));
        }
        Err(Error::Unaffordable { reason, .. }) => {
            budget.missing = Some(format!("the refined model's run is unaffordable: {reason}"));
        }
        Err(e) => return Err(e),
    }
    Ok(budget)
}
