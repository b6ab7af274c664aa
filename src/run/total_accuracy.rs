//! [`SimulationOptions::accuracy`] as the whole error against the beams (m): the basis, the modes per
//! section, the method and the tolerance that reach it cheapest.
//!
//! The accuracy is split: a tenth ([`INTEGRATION_SHARE`]) goes to the integration, whose
//! method and tolerance come from the table of measured runs
//! ([`telescopic_runtime::analysis::accuracy`]); the rest to the truncation of the model's size. Each
//! basis (the paper's modes, and the modes with static correction shapes) has a ladder of
//! sizes, the modes per section growing along [`refined_modes`] from a small start; a size is
//! checked by its companion run, the next size of its ladder ([`crate::run::error_budget`]):
//! it passes when the estimate of the whole error in `tip_rel` is within the accuracy over
//! [`ESTIMATE_MARGIN`], every station's moment within
//! [`SimulationOptions::moment_tolerance`] of its peak, and (with clearance) the statistics
//! beyond the pointwise window within [`SimulationOptions::statistics_tolerance`].
//!
//! Without clearance the size is predicted before any run ([`crate::run::predicted_size`]:
//! the scene's modal surrogate against the largest size's), that size is run with its
//! companion, and the ladder of its basis is refined from there only when the companion
//! rejects it. When nothing is predicted (clearance, whose impacts the surrogate does not
//! see), or the predicted ladder ends without a passing size, the search is best-first by
//! cost: it runs each ladder's first size, then always checks
//! the cheapest size not yet checked, counted in operations
//! ([`telescopic_runtime::RunStats::operations`]: steps, right-hand sides, factorizations and
//! matrix exponentials, so the pick does not depend on the machine's load). A ladder ends at
//! its first passing size, or at a size that costs more than a passing one (the costs grow
//! along a ladder, so nothing above it could win). The passing size of least cost is kept;
//! its companion run is the check the summary reports. No companion is run for a size that
//! cannot win, and a run is stopped as soon as it costs more than a passing size
//! ([`telescopic_runtime::Settings::max_operations`]): the first ladder's first size is
//! checked before the next ladder starts, so that when it passes, the other ladders' first
//! runs stop early. The pick is the same as with every run completed: only sizes that cost
//! more than a passing one are cut short.
//!
//! The predicted size and the first ladder's first size run beside their companions (the
//! check that follows at once; [`crate::report::both`]): where two cores are free the two
//! runs take the time of the longer. Every run is deterministic, so the pick does not depend
//! on which finishes first.
//!
//! The search tells its reporter which size of how many it runs, and notes each size's
//! verdict with the check that rejected it; the summary names every size tried, why it was
//! rejected, and the whole search's runs and wall time.

use crate::OptionName;
use crate::report::Reporter;
use crate::run::PreparedRun;
use crate::run::error_budget::{ErrorBudget, Statistic, refined_modes};
use crate::run::method::{companion_integration, companion_options};
use crate::run::predicted_size::{SizePrediction, predict_size};
use crate::run::{MethodReason, ModelSize, Simulation, SimulationOptions, plan};
use crate::{Error, Result};
use std::time::Instant;
use telescopic_runtime::{Basis, Scene, SimError};

/// The whole errors that can be asked for (m): below, the truncation of the largest models
/// that the shipped scenes afford cannot be certified; above, no longer an accuracy.
pub const TOTAL_ACCURACY_RANGE: (f64, f64) =
    telescopic_runtime::analysis::accuracy::WHOLE_ACCURACY_RANGE;

/// The share of the accuracy given to the integration.
pub const INTEGRATION_SHARE: f64 = 0.1;

/// A size passes when its estimate of the whole error is within the accuracy over this
/// margin: on the shipped scenes the estimate stood between half and 2.7 times the true
/// error against the beams (docs/numerics.md).
pub const ESTIMATE_MARGIN: f64 = 2.0;

/// Where each basis's ladder starts (modes per section).
const STARTS: [(Basis, usize); 2] = [(Basis::Modes, 4), (Basis::ModesAndStatic, 2)];

/// The statistics that [`SimulationOptions::statistics_tolerance`] bounds. Contact
/// switches, peak contact forces and peak moments beyond the window are reported but not
/// bounded: impacts set them, and against the finite-element beams they scatter by more than
/// 5 % whatever the model's size (docs/numerics.md).
pub const BOUNDED_STATISTICS: [Statistic; 2] = [Statistic::TipRms, Statistic::TipPeak];

/// Why a size's budget fails the accuracy asked for: the first check that fails, with the
/// numbers it compared.
#[derive(Debug, Clone, PartialEq)]
pub enum Rejection {
    /// The estimate of the whole error in `tip_rel` times [`ESTIMATE_MARGIN`] exceeds the
    /// accuracy (m, m).
    Tip {
        /// The estimate (m).
        estimated_m: f64,
        /// The accuracy asked for (m).
        accuracy_m: f64,
    },
    /// A station's moment truncation exceeds the moment tolerance (fractions of its peak).
    Moment {
        /// The worst station's estimate (1).
        relative: f64,
        /// [`SimulationOptions::moment_tolerance`] (1).
        tolerance: f64,
    },
    /// A bounded statistic beyond the window exceeds the statistics tolerance (fractions).
    Statistics {
        /// The worst of [`BOUNDED_STATISTICS`] (1).
        relative: f64,
        /// [`SimulationOptions::statistics_tolerance`] (1).
        tolerance: f64,
    },
    /// The size's run or its companion's is refused by the work budget.
    Unaffordable,
    /// The size's run costs more than a passing size's: it cannot be the cheapest.
    CostlierThanPassing,
    /// The size's run was stopped as soon as it cost more than a passing size's
    /// ([`telescopic_runtime::Settings::max_operations`]).
    StoppedCostlier,
    /// The size has the most modes there are: no companion can check it.
    NoCompanion,
}

impl std::fmt::Display for Rejection {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Rejection::Tip {
                estimated_m,
                accuracy_m,
            } => write!(
                f,
                "tip_rel estimate {estimated_m:.1e} m x {ESTIMATE_MARGIN} above {accuracy_m:e} m"
            ),
            Rejection::Moment {
                relative,
                tolerance,
            } => write!(
                f,
                "a moment's truncation {:.1} % above {:.1} %",
                100.0 * relative,
                100.0 * tolerance
            ),
            Rejection::Statistics {
                relative,
                tolerance,
            } => write!(
                f,
                "statistics of tip_rel beyond the window {:.1} % above {:.1} %",
                100.0 * relative,
                100.0 * tolerance
            ),
            Rejection::Unaffordable => write!(f, "unaffordable (the work budget refuses it)"),
            Rejection::CostlierThanPassing => {
                write!(f, "costs more than a passing size, not checked")
            }
            Rejection::StoppedCostlier => write!(
                f,
                "stopped once it cost more than a passing size (its operations so far), not \
                 checked"
            ),
            Rejection::NoCompanion => write!(f, "the most modes there are: no companion"),
        }
    }
}

/// One size tried.
#[derive(Debug, Clone, PartialEq)]
struct Attempt {
    size: ModelSize,
    wall: f64,
    /// [`telescopic_runtime::RunStats::operations`] of its run; 0 when it did not run.
    cost: f64,
    /// The estimate of the whole error in `tip_rel` (m).
    total: Option<f64>,
    /// `None` when it passed.
    rejection: Option<Rejection>,
}

impl Attempt {
    fn describe(&self) -> String {
        let estimate = self
            .total
            .map_or("not estimated".into(), |e| format!("{e:.1e} m"));
        let verdict = match &self.rejection {
            None => "passes".to_string(),
            Some(r) => format!("rejected: {r}"),
        };
        format!(
            "{} {} ({estimate}, {:.1e} operations, {:.3} s; {verdict})",
            self.size.basis.word(),
            self.size.modes,
            self.cost,
            self.wall,
        )
    }
}

/// The sizes a basis's search may try from `start`, in order: `start` refined by
/// [`refined_modes`] until the rule stops growing (the last has no companion).
pub(crate) fn ladder(basis: Basis, start: usize) -> Vec<ModelSize> {
    let mut sizes = vec![ModelSize {
        basis,
        modes: start,
    }];
    loop {
        let last = sizes[sizes.len() - 1].modes;
        let next = refined_modes(last);
        if next == last {
            return sizes;
        }
        sizes.push(ModelSize { basis, modes: next });
    }
}

/// What the search reports: its reporter, and the sizes counted over every basis so that
/// each run is named as size `k` of `n`.
struct SearchProgress<'a> {
    reporter: &'a dyn Reporter,
    /// Sizes with a companion over every basis's ladder.
    total: usize,
    /// The most runs the search can make: every size of every ladder once.
    max_runs: usize,
    /// Sizes checked so far.
    done: std::cell::Cell<usize>,
    /// Runs made so far (sizes and companions).
    runs: std::cell::Cell<usize>,
}

impl SearchProgress<'_> {
    /// A reporter for the run of `size` (the size being checked, or its companion).
    fn run_reporter(&self, size: ModelSize, role: &str) -> SearchStep<'_> {
        self.step(1, format!("{role} {size}"))
    }

    /// A reporter for the runs of `size` and its companion `refined` made at once.
    fn pair_reporter(&self, size: ModelSize, refined: ModelSize) -> SearchStep<'_> {
        self.step(2, format!("running {size} and its companion {refined}"))
    }

    /// A reporter for the next `span` runs, doing `what`.
    fn step(&self, span: usize, what: String) -> SearchStep<'_> {
        let index = self.runs.get();
        self.runs.set(index + span);
        SearchStep {
            inner: self.reporter,
            // the search's fraction done, counted against its most runs: it never goes back
            done: (index as f64, self.max_runs as f64),
            span: span as f64,
            label: format!(
                "accuracy search, size {} of at most {}: {what}",
                self.done.get() + 1,
                self.total
            ),
        }
    }

    /// Notes the verdict on `attempt`.
    fn verdict(&self, attempt: &Attempt) {
        self.done.set(self.done.get() + 1);
        self.reporter.note(&format!(
            "accuracy search, size {} of at most {}: {}",
            self.done.get(),
            self.total,
            attempt.describe()
        ));
    }
}

/// A run's reporter inside the search: its start names the size, its progress is the
/// search's.
struct SearchStep<'a> {
    inner: &'a dyn Reporter,
    label: String,
    /// Runs before this one, and the most runs the search can make.
    done: (f64, f64),
    /// The runs this step makes (a size and its companion at once: 2).
    span: f64,
}

impl Reporter for SearchStep<'_> {
    fn start(&self, _what: &str) {
        self.inner.start(&self.label);
    }
    fn progress(&self, fraction: f64) {
        let (before, most) = self.done;
        // a prediction its companion rejects may add runs beyond the most counted: stay at 1
        self.inner
            .progress(((before + self.span * fraction.clamp(0.0, 1.0)) / most).min(1.0));
    }
    fn finish(&self) {
        self.inner.finish();
    }
    fn note(&self, line: &str) {
        self.inner.note(line);
    }
    fn stop_requested(&self) -> bool {
        self.inner.stop_requested()
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
    let started = Instant::now();
    let accuracy = options.accuracy.expect("called with an accuracy");
    check_options(accuracy, options)?;
    let integration = integration_options(options);
    // refuses bad tolerances and the like before any run
    let run_plan = plan(scene, &integration)?;
    let prediction = prediction(scene, accuracy);
    // a size's companion ends its steps on every sample and is integrated finer, so that
    // the difference holds the run's interpolation and integration errors too
    let (companion, finer) = companion_options(scene, &integration, &run_plan);
    let (total, max_runs) = search_extent(&prediction, finer);
    let progress = SearchProgress {
        reporter,
        total,
        max_runs,
        done: std::cell::Cell::new(0),
        runs: std::cell::Cell::new(0),
    };
    reporter.note(&format!("accuracy search: {prediction}"));
    let mut attempts = Vec::new();
    let best = search(
        scene,
        (&integration, (&companion, finer), options),
        &prediction,
        &mut attempts,
        &progress,
    )?;
    let tried: Vec<String> = attempts.iter().map(Attempt::describe).collect();
    let Some(mut simulation) = best else {
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
    let confirmed = matches!(prediction, SizePrediction::Predicted { size, .. }
        if size.basis == simulation.basis && size.modes == simulation.modes[0]);
    simulation.plan.reason = MethodReason::TotalAccuracy {
        accuracy_m: accuracy,
        estimated_m: budget.total_m().unwrap_or(f64::NAN),
        basis: simulation.basis,
        modes: simulation.modes[0],
        prediction,
        confirmed,
        tried,
        search_runs: progress.runs.get(),
        search_s: started.elapsed().as_secs_f64(),
        integration: Box::new(simulation.plan.reason.clone()),
    };
    Ok(simulation)
}

/// The options of a size's run in the search for `options.accuracy`: the size as given,
/// integrated to the accuracy's integration share, no estimate of its own.
pub(crate) fn integration_options(options: &SimulationOptions) -> SimulationOptions {
    let accuracy = options.accuracy.expect("called with an accuracy");
    // the share, within the integration's own range (0.1 x the top 0.1 m rounds above 1e-2)
    let integration_m = (accuracy * INTEGRATION_SHARE)
        .min(telescopic_runtime::analysis::accuracy::ACCURACY_RANGE.1);
    SimulationOptions {
        accuracy: Some(integration_m),
        modes_as_given: true,
        error_estimate: false,
        ..options.clone()
    }
}

/// The size predicted for `accuracy` (m) before any run ([`predict_size`]): among every
/// size with a companion on the ladders, against the largest size of the static shapes'.
fn prediction(scene: &Scene, accuracy: f64) -> SizePrediction {
    let ladders: Vec<Vec<ModelSize>> = STARTS
        .iter()
        .map(|&(basis, start)| ladder(basis, start))
        .collect();
    let candidates: Vec<ModelSize> = ladders
        .iter()
        .flat_map(|l| l[..l.len() - 1].iter().copied())
        .collect();
    let reference = *ladders[ladders.len() - 1]
        .last()
        .expect("a ladder has a size");
    predict_size(scene, accuracy / ESTIMATE_MARGIN, &candidates, reference)
}

/// The most sizes the search checks and the most runs it makes: every size of every
/// ladder, and before them the predicted size's own ladder from that size on. A rejected
/// size's companion is the next size's run, unless the companions are integrated `finer`
/// than the sizes' runs: then each size checked takes two runs.
fn search_extent(prediction: &SizePrediction, finer: bool) -> (usize, usize) {
    let mut ladders: Vec<Vec<ModelSize>> = STARTS
        .iter()
        .map(|&(basis, start)| ladder(basis, start))
        .collect();
    if let SizePrediction::Predicted { size, .. } = prediction {
        ladders.push(ladder(size.basis, size.modes));
    }
    let sizes: usize = ladders.iter().map(|l| l.len() - 1).sum();
    let runs = match finer {
        true => 2 * sizes,
        false => sizes + ladders.len(),
    };
    (sizes, runs)
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

/// What one run of the search gave.
enum Outcome {
    /// The run, complete.
    Ran(Box<Simulation>),
    /// The work budget refused it, with its error.
    Unaffordable(Box<Error>),
    /// It was stopped as soon as it cost more than the cap: the operations and the wall
    /// time (s) so far.
    OverCap(f64, f64),
}

/// One run without an error estimate, stopped once it costs more than `cap` operations.
fn run(
    scene: &Scene,
    options: &SimulationOptions,
    cap: f64,
    reporter: &dyn Reporter,
) -> Result<Outcome> {
    let started = Instant::now();
    let mut prepared = PreparedRun::new(scene, options, &crate::Silent)?;
    prepared.plan.settings.max_operations = cap;
    match prepared.integrate(reporter) {
        Ok(trajectory) => Ok(Outcome::Ran(Box::new(prepared.into_simulation(trajectory)))),
        Err(e @ Error::Unaffordable { .. }) => Ok(Outcome::Unaffordable(Box::new(e))),
        Err(Error::Simulation {
            error: SimError::OverBudget { operations, .. },
            ..
        }) => Ok(Outcome::OverCap(
            operations,
            started.elapsed().as_secs_f64(),
        )),
        Err(e) => Err(e),
    }
}

/// One basis's ladder in the search: the size reached and its run.
struct Rung {
    ladder: Vec<ModelSize>,
    /// Index in `ladder` of the size whose run is `run`.
    at: usize,
    run: Simulation,
    /// Its companion's run when it was made beside it.
    companion: Option<Outcome>,
}

impl Rung {
    fn cost(&self) -> f64 {
        self.run.trajectory.stats.operations()
    }

    fn attempt(&self, total: Option<f64>, rejection: Option<Rejection>) -> Attempt {
        Attempt {
            size: self.ladder[self.at],
            wall: self.run.trajectory.stats.wall.as_secs_f64(),
            cost: self.cost(),
            total,
            rejection,
        }
    }
}

/// The search of the module documentation: the predicted size when its ladder passes, else
/// the best-first search's passing run of least cost, with its budget; `None` when no size
/// passes. Every size checked or dropped is pushed to
/// `attempts` with its verdict.
fn search(
    scene: &Scene,
    (integration, (companion, finer), options): (
        &SimulationOptions,
        (&SimulationOptions, bool),
        &SimulationOptions,
    ),
    prediction: &SizePrediction,
    attempts: &mut Vec<Attempt>,
    progress: &SearchProgress,
) -> Result<Option<Simulation>> {
    let mut search = Search {
        scene,
        integration,
        companion,
        finer,
        options,
        progress,
        rungs: Vec::new(),
        best: None,
        refused: None,
    };
    if let SizePrediction::Predicted { size, .. } = prediction {
        // the predicted size and its companion first; along its ladder only if that fails
        search.start_checked(ladder(size.basis, size.modes), None, attempts)?;
        while search.check_cheapest(attempts)? {}
        if let Some((simulation, _)) = search.best {
            return Ok(Some(simulation));
        }
    }
    // the first ladder's first size is checked before the next ladder starts, so that a
    // passing size caps the runs of the others; the next ladder's first size runs ahead,
    // capped by the first size's cost, on the core its run leaves free while its companion
    // still runs
    let [(basis, start), (next_basis, next_start)] = STARTS;
    let next = ladder(next_basis, next_start);
    let ahead = search.start_checked(ladder(basis, start), Some(next[0]), attempts)?;
    match ahead {
        // the cap it ran under is the one the next ladder's start has now: the same run
        Some((cap, outcome)) if cap == search.cap() => search.keep(next, outcome?, None, attempts),
        _ => search.start(next, attempts)?,
    }
    while search.check_cheapest(attempts)? {}
    // when the work budget refuses every size, its refusal says why (the stable step)
    let all_refused = attempts
        .iter()
        .all(|a| a.rejection == Some(Rejection::Unaffordable));
    if let (None, true, Some(refusal)) = (&search.best, all_refused, search.refused) {
        return Err(*refusal);
    }
    Ok(search.best.map(|(simulation, _)| simulation))
}

/// A size run ahead of its turn: the cap it ran under (operations) and its outcome.
type Ahead = (f64, Result<Outcome>);

/// The state of the search: the ladders' sizes run but not yet checked, and the passing
/// run of least cost with that cost (operations).
struct Search<'a> {
    scene: &'a Scene,
    integration: &'a SimulationOptions,
    /// The companions' options: steps ending on every sample, integrated finer where
    /// `finer` ([`companion_options`]).
    companion: &'a SimulationOptions,
    /// Whether the companions are integrated finer than the sizes' runs.
    finer: bool,
    options: &'a SimulationOptions,
    progress: &'a SearchProgress<'a>,
    rungs: Vec<Rung>,
    best: Option<(Simulation, f64)>,
    /// The work budget's first refusal of a run.
    refused: Option<Box<Error>>,
}

impl Search<'_> {
    /// Runs the first size of `ladder` (stopped past [`Search::cap`]) and keeps it to be
    /// checked, or records why it cannot be.
    fn start(&mut self, ladder: Vec<ModelSize>, attempts: &mut Vec<Attempt>) -> Result<()> {
        let first = ladder[0];
        let step = self.progress.run_reporter(first, "running");
        let outcome = run(
            &first.apply(self.scene),
            self.integration,
            self.cap(),
            &step,
        )?;
        self.keep(ladder, outcome, None, attempts);
        Ok(())
    }

    /// Keeps the run `outcome` of `ladder`'s first size (with its `companion`'s run when it
    /// was made beside it) to be checked, or records why it cannot be.
    fn keep(
        &mut self,
        ladder: Vec<ModelSize>,
        outcome: Outcome,
        companion: Option<Outcome>,
        attempts: &mut Vec<Attempt>,
    ) {
        let (first, progress) = (ladder[0], self.progress);
        match outcome {
            Outcome::Ran(run) => self.rungs.push(Rung {
                ladder,
                at: 0,
                run: *run,
                companion,
            }),
            Outcome::Unaffordable(e) => {
                self.refused.get_or_insert(e);
                record(
                    attempts,
                    progress,
                    not_checked(first, Rejection::Unaffordable, (0.0, 0.0)),
                );
            }
            Outcome::OverCap(cost, wall) => record(
                attempts,
                progress,
                not_checked(first, Rejection::StoppedCostlier, (cost, wall)),
            ),
        }
    }

    /// Runs the first size of `ladder` and its companion at once (the companion is the
    /// size's check, made next), then checks it. With `ahead`, that size runs after the
    /// first on the same core, capped by the first's cost: the cap and its outcome.
    fn start_checked(
        &mut self,
        ladder: Vec<ModelSize>,
        ahead: Option<ModelSize>,
        attempts: &mut Vec<Attempt>,
    ) -> Result<Option<Ahead>> {
        let first = ladder[0];
        let Some(&refined) = ladder.get(1) else {
            self.start(ladder, attempts)?;
            return self.check_cheapest(attempts).map(|_| None);
        };
        let (scene, integration, cap) = (self.scene, self.integration, self.cap());
        let companion_options = self.companion;
        let (size_run, companion) = crate::report::both(
            &self.progress.pair_reporter(first, refined),
            0.5,
            |r| {
                let outcome = run(&first.apply(scene), integration, cap, r)?;
                let ahead = match (&outcome, ahead) {
                    (Outcome::Ran(done), Some(size)) => {
                        let cap = cap.min(done.trajectory.stats.operations());
                        // its progress would go back within the pair's: it reports none, and
                        // stops when the caller asks
                        let quiet = crate::report::StopOnly(r);
                        Some((cap, run(&size.apply(scene), integration, cap, &quiet)))
                    }
                    _ => None,
                };
                Ok::<_, Error>((outcome, ahead))
            },
            |r| run(&refined.apply(scene), companion_options, f64::INFINITY, r),
        );
        let (size_run, ahead) = size_run?;
        let companion = match size_run {
            Outcome::Ran(_) => Some(companion?),
            _ => None,
        };
        if ahead.is_some() {
            // counted as the search's runs are
            self.progress.runs.set(self.progress.runs.get() + 1);
        }
        self.keep(ladder, size_run, companion, attempts);
        self.check_cheapest(attempts)?;
        Ok(ahead)
    }

    /// The most a run may cost and still win: the passing size's cost.
    fn cap(&self) -> f64 {
        self.best.as_ref().map_or(f64::INFINITY, |(_, cost)| *cost)
    }

    /// Checks the cheapest size not yet checked by its companion; false when none is left.
    fn check_cheapest(&mut self, attempts: &mut Vec<Attempt>) -> Result<bool> {
        let Some(i) = cheapest(&self.rungs) else {
            return Ok(false);
        };
        let (scene, progress) = (self.scene, self.progress);
        let mut rung = self.rungs.swap_remove(i);
        if rung.cost() > self.cap() {
            let attempt = rung.attempt(None, Some(Rejection::CostlierThanPassing));
            record(attempts, progress, attempt);
            return Ok(true);
        }
        let Some(&refined) = rung.ladder.get(rung.at + 1) else {
            let attempt = rung.attempt(None, Some(Rejection::NoCompanion));
            record(attempts, progress, attempt);
            return Ok(true);
        };
        let outcome = match rung.companion.take() {
            Some(outcome) => outcome,
            None => {
                let step = progress.run_reporter(refined, "its companion");
                run(&refined.apply(scene), self.companion, f64::INFINITY, &step)?
            }
        };
        let companion = match outcome {
            Outcome::Ran(companion) => *companion,
            Outcome::Unaffordable(_) | Outcome::OverCap(..) => {
                let attempt = rung.attempt(None, Some(Rejection::Unaffordable));
                record(attempts, progress, attempt);
                return Ok(true);
            }
        };
        let modes = vec![refined.modes; scene.params.sections.len()];
        let integration = companion_integration(&rung.run.plan, &companion.plan);
        let budget = rung
            .run
            .budget_against(scene, &companion.trajectory, modes, integration);
        let rejection = rejection(&budget, self.options);
        let attempt = rung.attempt(budget.total_m(), rejection.clone());
        record(attempts, progress, attempt);
        if rejection.is_none() {
            let cost = rung.cost();
            let mut passing = rung.run;
            passing.error = Some(budget);
            if cost < self.cap() {
                self.best = Some((passing, cost));
            }
        } else if self.finer {
            // integrated finer than a size's run, the companion cannot stand for the next
            // size's run: that size runs afresh
            self.start(rung.ladder[rung.at + 1..].to_vec(), attempts)?;
        } else {
            self.rungs.push(Rung {
                ladder: rung.ladder,
                at: rung.at + 1,
                run: companion,
                companion: None,
            });
        }
        Ok(true)
    }
}

/// Index of the rung of least cost (ties to the first).
fn cheapest(rungs: &[Rung]) -> Option<usize> {
    (0..rungs.len()).min_by(|&a, &b| rungs[a].cost().total_cmp(&rungs[b].cost()))
}

/// The verdict on a size whose own run was not checked for `rejection` (refused by the
/// work budget, or stopped once it cost more than a passing size), with its operations
/// and wall time (s) so far.
fn not_checked(size: ModelSize, rejection: Rejection, (cost, wall): (f64, f64)) -> Attempt {
    Attempt {
        size,
        wall,
        cost,
        total: None,
        rejection: Some(rejection),
    }
}

/// Notes `attempt` and keeps it.
fn record(attempts: &mut Vec<Attempt>, progress: &SearchProgress, attempt: Attempt) {
    progress.verdict(&attempt);
    attempts.push(attempt);
}

/// Why `budget` fails the accuracy and tolerances of `options`; `None` when it meets them.
fn rejection(budget: &ErrorBudget, options: &SimulationOptions) -> Option<Rejection> {
    let accuracy_m = options.accuracy.expect("called with an accuracy");
    let estimated_m = budget.total_m().unwrap_or(f64::INFINITY);
    if estimated_m * ESTIMATE_MARGIN > accuracy_m {
        return Some(Rejection::Tip {
            estimated_m,
            accuracy_m,
        });
    }
    if let Some(relative) = budget.worst_moment()
        && relative > options.moment_tolerance
    {
        return Some(Rejection::Moment {
            relative,
            tolerance: options.moment_tolerance,
        });
    }
    match budget.worst_statistic(&BOUNDED_STATISTICS) {
        Some(relative) if relative > options.statistics_tolerance => Some(Rejection::Statistics {
            relative,
            tolerance: options.statistics_tolerance,
        }),
        _ => None,
    }
}
