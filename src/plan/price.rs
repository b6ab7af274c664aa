//! What a plan costs, priced from its options before any work: the first-mode schedule's
//! eigen analyses, and the runs (candidates x plants x evaluations, then the checks) with
//! their samples. A plan above either bound is refused naming what to change.

use super::options::PlanOptions;
use super::robust::evaluated_plant_count;
use super::shapers::Shaper;
use crate::{Error, OptionName, Result};
use telescopic_runtime::Scene;

/// Spacing of the first mode's samples along the move (s).
pub const SCHEDULE_STEP_S: f64 = 0.25;

/// The schedule reaches this far past the arrival (s).
pub const SCHEDULE_PAST_ARRIVAL_S: f64 = 8.0;

/// Evaluations the optimizer may make (each runs every evaluated plant).
pub const OPTIMIZER_BUDGET: usize = 24;

/// Evaluations the matched move's optimizer may make: its residual is sharply tuned in its
/// two stretches, so it gets more than the shaper's.
pub const MATCHED_BUDGET: usize = 48;

/// Most eigen analyses of a first-mode schedule: a move of about 490 s.
pub const MAX_SCHEDULE_POINTS: usize = 2000;

/// Most output samples of all a plan's runs together (about an hour of runs on two cores
/// for case-study; a robust plan over three ranges takes about 1e7).
pub const MAX_PLAN_SAMPLES: f64 = 1e8;

/// The work of a plan, counted before it starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanPrice {
    /// The time-optimal move's duration (s).
    pub move_s: f64,
    /// Eigen analyses of the first-mode schedule.
    pub schedule_points: usize,
    /// Runs on the nonlinear model, at most (the optimizer may stop early).
    pub runs: usize,
    /// Each run's span (s), at least: the move and the settling time (the shapers' delay
    /// comes on top).
    pub run_span_s: f64,
    /// Output samples of all runs together, at least.
    pub samples: f64,
}

impl PlanPrice {
    /// The price of planning on `scene` with `options` (whose fields are checked).
    pub fn of(scene: &Scene, options: &PlanOptions) -> PlanPrice {
        let move_s = options.limits.curve(scene.time.start).phases().duration();
        let schedule_s = move_s + SCHEDULE_PAST_ARRIVAL_S;
        let schedule_points = (schedule_s / SCHEDULE_STEP_S).ceil().min(1e12) as usize + 1;
        // the S-curve, the matched move, each shaper fixed and scheduled
        let candidates = 2 + 2 * Shaper::ALL.len();
        let evaluations = candidates
            + if options.optimize {
                OPTIMIZER_BUDGET + MATCHED_BUDGET
            } else {
                0
            }
            + if options.feedback.is_some() { 2 } else { 0 };
        let checks = if options.robust.is_empty() {
            0
        } else {
            options.checks
        };
        let runs = evaluations * evaluated_plant_count(options.robust.len()) + checks;
        let run_span_s = move_s + options.settle_s;
        let samples = runs as f64 * run_span_s / scene.time.sample;
        PlanPrice {
            move_s,
            schedule_points,
            runs,
            run_span_s,
            samples,
        }
    }

    /// The price within the bounds.
    ///
    /// # Errors
    /// [`Error::Option`] naming what to change: the move's limits for a schedule too long,
    /// the robust set, the checks, the optimizer or the settling time for too many samples.
    pub fn check(&self) -> Result<()> {
        if self.schedule_points > MAX_SCHEDULE_POINTS {
            return Err(Error::option(
                OptionName::MoveLimits,
                format!(
                    "the move takes {:.0} s: its first-mode schedule needs {} eigen analyses, \
                     at most {MAX_SCHEDULE_POINTS} (a move of about {:.0} s); raise the \
                     velocity or acceleration limit, or shorten the distance",
                    self.move_s,
                    self.schedule_points,
                    MAX_SCHEDULE_POINTS as f64 * SCHEDULE_STEP_S - SCHEDULE_PAST_ARRIVAL_S
                ),
            ));
        }
        if self.samples > MAX_PLAN_SAMPLES {
            return Err(Error::option(
                OptionName::Robust,
                format!(
                    "the plan would make {} runs of at least {:.0} s each, {:.1e} samples, \
                     at most {MAX_PLAN_SAMPLES:.0e}: give fewer robust ranges or checks, \
                     plan without the optimizer, settle for less time, or sample the scene \
                     more coarsely (time.sample)",
                    self.runs, self.run_span_s, self.samples
                ),
            ));
        }
        Ok(())
    }

    /// In a line, e.g. `up to 35 runs of at least 23 s (8.1e5 samples) after 88 eigen
    /// analyses`.
    pub fn describe(&self) -> String {
        format!(
            "up to {} runs of at least {:.0} s ({:.1e} samples) after {} eigen analyses",
            self.runs, self.run_span_s, self.samples, self.schedule_points
        )
    }
}
