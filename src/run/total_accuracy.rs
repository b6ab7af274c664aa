//! [`SimulationOptions::accuracy`] as the whole error against the beams (m): the basis, the modes per
//! section, the method and the tolerance that reach it cheapest.
//!
//! The accuracy is split: a tenth ([`INTEGRATION_SHARE`]) goes to the integration, whose
//! method and tolerance come from the table of measured runs
//! ([`telescopic_runtime::accuracy`]); the rest to the truncation of the model's size. For
//! each basis (the paper's modes, and the modes with static correction shapes) the modes per
//! section grow along [`refined_modes`] from a small start, each size checked by its
//! companion run ([`crate::run::error_budget`]), until the estimate of the whole error in
//! `tip_rel` is within the accuracy over [`ESTIMATE_MARGIN`], every station's moment within
//! [`SimulationOptions::moment_tolerance`] of its peak, and (with clearance) the statistics
//! beyond the pointwise window within [`SimulationOptions::statistics_tolerance`]. Of the two
//! bases' first sizes that pass, the one whose run costs fewer operations (counted from its
//! steps, right-hand sides and matrix factorizations and exponentials, so that the pick does
//! not depend on the machine's load) is kept; its companion run is the check the summary
//! reports. A size whose run already costs four times the best one's ends its basis's search.

use crate::OptionName;
use crate::report::Reporter;
use crate::run::PreparedRun;
use crate::run::error_budget::{self, ErrorBudget, Statistic, refined_modes};
use crate::run::{MethodReason, Simulation, SimulationOptions, plan};
use crate::{Error, Result};
use telescopic_runtime::{Basis, Scene};

/// The whole errors that can be asked for (m): below, the truncation of the largest models
/// that the shipped scenes afford cannot be certified; above, no longer an accuracy.
pub const TOTAL_ACCURACY_RANGE: (f64, f64) = (1e-5, 1e-1);

/// The share of the accuracy given to the integration.
pub const INTEGRATION_SHARE: f64 = 0.1;

/// A size passes when its estimate of the whole error is within the accuracy over this
/// margin: on the shipped scenes the estimate stood between half and 2.7 times the true
/// error against the beams (docs/numerics.md).
pub const ESTIMATE_MARGIN: f64 = 2.0;

/// Where each basis's search starts (modes per section).
const STARTS: [(Basis, usize); 2] = [(Basis::Modes, 4), (Basis::ModesAndStatic, 2)];

/// A size's run is not worth it once it costs this many times the best passing run's.
const COST_CUTOFF: f64 = 4.0;

/// The cost of a run (floating-point operations, roughly) from what it did, for a state of
/// `n` entries: a step or a right-hand side costs a matrix-vector product, a Jacobian, a
/// factorization or a matrix exponential a matrix-matrix one. A count, not a wall time: the
/// pick does not depend on how busy the machine is, so the same scene picks the same size.
fn operation_count(stats: &telescopic_runtime::RunStats, n: usize) -> f64 {
    let (n2, n3) = ((n * n) as f64, (n * n * n) as f64);
    (stats.steps + stats.rhs_evals) as f64 * n2
        + (stats.jacobian_evals + stats.factorizations + stats.exponentials) as f64 * n3
}

/// The state size of `scene`'s model: every coordinate, the vehicle's included, and its rate.
fn state_size(scene: &Scene) -> usize {
    2 * (scene.params.coordinates().iter().sum::<usize>() + 1)
}

/// The statistics that [`SimulationOptions::statistics_tolerance`] bounds. Contact
/// switches, peak contact forces and peak moments beyond the window are reported but not
/// bounded: impacts set them, and against the finite-element beams they scatter by more than
/// 5 % whatever the model's size (docs/numerics.md).
pub const BOUNDED_STATISTICS: [Statistic; 2] = [Statistic::TipRms, Statistic::TipPeak];

/// One size tried.
#[derive(Debug, Clone, PartialEq)]
struct Attempt {
    basis: Basis,
    modes: usize,
    wall: f64,
    /// [`operation_count`] of its run.
    cost: f64,
    /// The estimate of the whole error in `tip_rel` (m).
    total: Option<f64>,
    passed: bool,
}

impl Attempt {
    fn describe(&self) -> String {
        let estimate = self
            .total
            .map_or("not estimated".into(), |e| format!("{e:.1e} m"));
        format!(
            "{} {} ({estimate}, {:.1e} operations, {:.3} s{})",
            self.basis.word(),
            self.modes,
            self.cost,
            self.wall,
            if self.passed { "" } else { ", not within" }
        )
    }
}

/// Simulates `scene` at the whole error `options.accuracy` (m) in `tip_rel`, picking basis,
/// modes, method and tolerance (see the module documentation).
///
/// # Errors
/// [`Error::Option`] for an accuracy or tolerance out of range or an accuracy no size
/// reaches (with the closest estimate), and any error of the runs.
pub fn simulate_for_accuracy(
    scene: &Scene,
    options: &SimulationOptions,
    reporter: &dyn Reporter,
) -> Result<Simulation> {
    let accuracy = options.accuracy.expect("called with an accuracy");
    check_options(accuracy, options)?;
    let integration = SimulationOptions {
        accuracy: Some(accuracy * INTEGRATION_SHARE),
        modes_as_given: true,
        error_estimate: false,
        ..options.clone()
    };
    // refuses bad tolerances and the like before any run
    plan(scene, &integration)?;
    let mut attempts = Vec::new();
    let mut best: Option<(Simulation, f64)> = None;
    for (basis, start) in STARTS {
        let cutoff = best.as_ref().map(|(_, cost)| COST_CUTOFF * cost);
        if let Some(found) = search(
            scene,
            &integration,
            options,
            (basis, start),
            cutoff,
            &mut attempts,
            reporter,
        )? && best.as_ref().is_none_or(|(_, cost)| found.1 < *cost)
        {
            best = Some(found);
        }
    }
    let tried: Vec<String> = attempts.iter().map(Attempt::describe).collect();
    let Some((mut simulation, _)) = best else {
        return Err(Error::option(
            OptionName::Accuracy,
            format!(
                "{accuracy:e} m (with moments within {} % and statistics within {} %) is not \
                 reached by any size tried: {}; ask for a coarser accuracy",
                100.0 * options.moment_tolerance,
                100.0 * options.statistics_tolerance,
                tried.join(", ")
            ),
        ));
    };
    let budget = simulation
        .error
        .as_ref()
        .expect("a passing run has its budget");
    simulation.plan.reason = MethodReason::TotalAccuracy {
        accuracy_m: accuracy,
        estimated_m: budget.total_m().unwrap_or(f64::NAN),
        basis: simulation.basis,
        modes: simulation.modes[0],
        tried,
        integration: Box::new(simulation.plan.reason.clone()),
    };
    Ok(simulation)
}

/// Refuses an accuracy or tolerances out of range.
fn check_options(accuracy: f64, options: &SimulationOptions) -> Result<()> {
    let (low, high) = TOTAL_ACCURACY_RANGE;
    if !(accuracy.is_finite() && (low..=high).contains(&accuracy)) {
        return Err(Error::option_see(
            OptionName::Accuracy,
            format!(
                "must be {low:e} to {high:e} m of tip_rel in all (got {accuracy:e} m); for an \
                 integration accuracy alone keep the scene's modes"
            ),
            OptionName::ModesAsGiven,
        ));
    }
    for (value, name) in [
        (options.moment_tolerance, OptionName::MomentTolerance),
        (
            options.statistics_tolerance,
            OptionName::StatisticsTolerance,
        ),
    ] {
        if !(value > 0.0 && value < 1.0) {
            return Err(Error::option(
                name,
                format!("must be a fraction in (0, 1) (got {value})"),
            ));
        }
    }
    Ok(())
}

/// `scene` with `basis` and `modes` on every section.
fn sized(scene: &Scene, basis: Basis, modes: usize) -> Scene {
    let mut s = scene.clone();
    s.params.basis = basis;
    for section in &mut s.params.sections {
        section.modes = modes;
    }
    s
}

/// One run without an error estimate; `None` when the budget refuses it.
fn run(
    scene: &Scene,
    options: &SimulationOptions,
    reporter: &dyn Reporter,
) -> Result<Option<Simulation>> {
    let prepared = PreparedRun::new(scene, options, &crate::Silent)?;
    match prepared.integrate(reporter) {
        Ok(trajectory) => Ok(Some(prepared.into_simulation(trajectory))),
        Err(Error::Unaffordable { .. }) => Ok(None),
        Err(e) => Err(e),
    }
}

/// The first size of `basis` from `start` whose budget passes, with its run's
/// [`operation_count`];
/// `None` when none does within the cost cutoff or the mode limit.
fn search(
    scene: &Scene,
    integration: &SimulationOptions,
    options: &SimulationOptions,
    (basis, start): (Basis, usize),
    cutoff: Option<f64>,
    attempts: &mut Vec<Attempt>,
    reporter: &dyn Reporter,
) -> Result<Option<(Simulation, f64)>> {
    let mut modes = start;
    let Some(mut current) = run(&sized(scene, basis, modes), integration, reporter)? else {
        return Ok(None);
    };
    loop {
        let stats = &current.trajectory.stats;
        let wall = stats.wall.as_secs_f64();
        let cost = operation_count(stats, state_size(&sized(scene, basis, modes)));
        let refined = refined_modes(modes);
        if refined == modes || cutoff.is_some_and(|c| cost > c) {
            return Ok(None);
        }
        let Some(companion) = run(&sized(scene, basis, refined), integration, reporter)? else {
            return Ok(None);
        };
        let window = error_budget::window(&scene.params, &current.trajectory);
        let budget = ErrorBudget {
            window,
            integration_m: current.plan.integration_error_m,
            integration_statistics: current.plan.integration_statistics_rel,
            truncation: Some(error_budget::truncation(
                &current.trajectory,
                &companion.trajectory,
                vec![refined; scene.params.sections.len()],
                window,
            )),
            missing: None,
        };
        let passed = passes(&budget, options);
        attempts.push(Attempt {
            basis,
            modes,
            wall,
            cost,
            total: budget.total_m(),
            passed,
        });
        if passed {
            current.error = Some(budget);
            return Ok(Some((current, cost)));
        }
        modes = refined;
        current = companion;
    }
}

/// Whether `budget` meets the accuracy and tolerances of `options`.
fn passes(budget: &ErrorBudget, options: &SimulationOptions) -> bool {
    let accuracy = options.accuracy.expect("called with an accuracy");
    budget
        .total_m()
        .is_some_and(|e| e * ESTIMATE_MARGIN <= accuracy)
        && budget
            .worst_moment()
            .is_none_or(|m| m <= options.moment_tolerance)
        && budget
            .worst_statistic(&BOUNDED_STATISTICS)
            .is_none_or(|s| s <= options.statistics_tolerance)
}
