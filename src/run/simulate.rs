//! Simulating a scene: the prepared run, its integration, and the companion run of a
//! refined model that estimates the truncation error (beside the run, where a core is free:
//! [`crate::report::both`]); with a total accuracy, the search for the model size
//! ([`super::total_accuracy`]).

use super::error_budget::{self, ErrorBudget};
use super::method::{Plan, companion_integration, companion_options};
use super::options::SimulationOptions;
use super::prepared::PreparedRun;
use super::reuse::{self, Lookup, Record};
use super::simulation::Simulation;
use super::trajectory::Trajectory;
use crate::report::Reporter;
use crate::{Error, Result};
use telescopic_runtime::Scene;

/// Simulates `scene` with `options`: chooses the model and the method, checks that the run
/// fits the resource limits and is affordable, integrates from rest, collects every sample,
/// and estimates the run's error ([`crate::run::error_budget`]). With
/// [`SimulationOptions::accuracy`] (and not [`SimulationOptions::modes_as_given`]) it also
/// picks the basis and the modes per section ([`crate::run::total_accuracy`]). With
/// [`SimulationOptions::reuse`], a repeated run of the same scene and options makes its one
/// run and reuses the budget (and the pick) its first run kept ([`crate::run::reuse`]).
///
/// # Errors
/// [`Error`] for bad options, a model that cannot be had, an unaffordable run (with the
/// estimate), or a failed integration (time, method, likely cause).
pub fn simulate_scene(
    scene: &Scene,
    options: &SimulationOptions,
    reporter: &dyn Reporter,
) -> Result<Simulation> {
    let Some(dir) = options.reuse.as_deref().filter(|_| options.error_estimate) else {
        return simulate_afresh(scene, options, reporter);
    };
    let identity = reuse::identity(scene, options);
    match reuse::load(dir, &identity) {
        Lookup::Found(record) => {
            let path = reuse::record_path(dir, &identity);
            match rerun(scene, options, *record, path, reporter)? {
                Ok(simulation) => return Ok(simulation),
                Err(stale) => reporter.note(&stale),
            }
        }
        Lookup::Unreadable(why) => {
            reporter.note(&format!(
                "error budget not reused (unreadable record {why})"
            ));
        }
        Lookup::Missing => {}
    }
    let simulation = simulate_afresh(scene, options, reporter)?;
    if let Some(record) = Record::of(&simulation)
        && let Err(why) = reuse::store(dir, &identity, &record)
    {
        reporter.note(&format!("error budget not kept for reuse ({why})"));
    }
    Ok(simulation)
}

/// The run `record` belongs to, made again: the picked size's run for an accuracy search's
/// record, else the scene's. `Ok(Err(why))` when its outputs differ from the record's (a
/// stale record: the caller estimates afresh).
///
/// # Errors
/// The run's own error.
fn rerun(
    scene: &Scene,
    options: &SimulationOptions,
    record: Record,
    path: std::path::PathBuf,
    reporter: &dyn Reporter,
) -> Result<std::result::Result<Simulation, String>> {
    // a record is read from disk: one whose kind does not fit the options is stale, not a
    // reason to fail
    let searched = options.accuracy.is_some() && !options.modes_as_given;
    let (sized, run_options) = match (&record.pick, searched) {
        (Some(pick), true) => (
            pick.size.apply(scene),
            super::total_accuracy::integration_options(options),
        ),
        (None, false) => (scene.clone(), options.clone()),
        _ => {
            return Ok(Err(format!(
                "error budget not reused: the record {} does not fit these options: \
                 estimating afresh",
                path.display()
            )));
        }
    };
    let run = PreparedRun::new(&sized, &run_options, reporter)?;
    let trajectory = run.integrate(reporter)?;
    let mut simulation = run.into_simulation(trajectory);
    if reuse::outputs_digest(&simulation.trajectory) != record.outputs {
        return Ok(Err(format!(
            "error budget not reused: this run's outputs differ from those of the record \
             {}: estimating afresh",
            path.display()
        )));
    }
    if let Some(pick) = record.pick {
        reporter.note(&format!(
            "accuracy search: reused the pick {} {} of {}",
            pick.size.basis.word(),
            pick.size.modes,
            path.display()
        ));
        simulation.plan.reason = pick.reason(simulation.plan.reason);
    }
    simulation.error = Some(ErrorBudget {
        reused: Some(path),
        ..record.budget
    });
    Ok(Ok(simulation))
}

/// [`simulate_scene`] without reuse: the run and its companion, or the accuracy search.
fn simulate_afresh(
    scene: &Scene,
    options: &SimulationOptions,
    reporter: &dyn Reporter,
) -> Result<Simulation> {
    if options.accuracy.is_some() && !options.modes_as_given {
        return crate::run::total_accuracy::simulate_for_accuracy(scene, options, reporter);
    }
    if !options.error_estimate {
        let run = PreparedRun::new(scene, options, reporter)?;
        let trajectory = run.integrate(reporter)?;
        return Ok(run.into_simulation(trajectory));
    }
    // the run and its companion at once: the companion needs only the scene and the plan
    let run_plan = super::method::plan(scene, options)?;
    let (simulation, companion) = crate::report::both(
        reporter,
        COMPANION_SPLIT,
        |main| -> Result<Simulation> {
            let run = PreparedRun::new(scene, options, main)?;
            let trajectory = run.integrate(main)?;
            Ok(run.into_simulation(trajectory))
        },
        |companion| companion_run(scene, options, &run_plan, companion),
    );
    let mut simulation = simulation?;
    simulation.error = Some(budget_of(scene, &simulation, companion?));
    Ok(simulation)
}

/// The share of a run's progress beside its companion's (the companion, with more modes,
/// takes one to three times as long on the shipped scenes).
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
    Ok(budget_of(
        scene,
        simulation,
        companion_run(scene, options, &simulation.plan, reporter)?,
    ))
}

/// What became of a companion run: its trajectory, or why there is none.
enum Companion {
    /// The refined model's run, with its modes per section and, when it was integrated
    /// finer than the run, its own stored integration error (m).
    Ran(Trajectory, Vec<usize>, Option<f64>),
    /// No companion: why.
    Missing(String),
}

/// The companion run of `scene` with `options` (planned as `run`): the refined model, no
/// estimate of its own, integrated finer where the run's integration was picked
/// ([`crate::run::method::companion_options`]).
///
/// # Errors
/// A failed companion run (an unaffordable one is [`Companion::Missing`]).
fn companion_run(
    scene: &Scene,
    options: &SimulationOptions,
    run: &Plan,
    reporter: &dyn Reporter,
) -> Result<Companion> {
    let Some(refined) = error_budget::refined(&scene.params) else {
        return Ok(Companion::Missing(format!(
            "every section has {} modes, the most there are",
            telescopic_runtime::MAX_MODES
        )));
    };
    let mut companion_scene = scene.clone();
    companion_scene.params = refined;
    let (companion_options, _) = companion_options(scene, options, run);
    let prepared = PreparedRun::new(&companion_scene, &companion_options, &crate::Silent)?;
    let integration = companion_integration(run, &prepared.plan);
    match prepared.integrate(reporter) {
        Ok(companion) => Ok(Companion::Ran(
            companion,
            companion_scene.params.modes(),
            integration,
        )),
        Err(Error::Unaffordable { reason, .. }) => Ok(Companion::Missing(format!(
            "the refined model's run is unaffordable: {reason}"
        ))),
        Err(e) => Err(e),
    }
}

/// The error budget of `simulation` from its `companion`.
fn budget_of(scene: &Scene, simulation: &Simulation, companion: Companion) -> ErrorBudget {
    match companion {
        Companion::Ran(trajectory, modes, integration) => {
            simulation.budget_against(scene, &trajectory, modes, integration)
        }
        Companion::Missing(why) => ErrorBudget {
            window: error_budget::window(&scene.params, &simulation.trajectory),
            integration_m: simulation.plan.integration_error_m,
            integration_statistics: simulation.plan.integration_statistics_rel,
            truncation: None,
            missing: Some(why),
            reused: None,
        },
    }
}
