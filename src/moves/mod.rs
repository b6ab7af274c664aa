//! Planning a move: the shortest cycle that brings the load to rest within a tolerance,
//! robust over the plants it carries. The vehicle follows a setpoint (the scene's prescribed
//! motion, a position-controlled servo); the candidates are the time-optimal jerk-limited
//! move ([`telescopic_runtime::SCurve`]), that move filtered by each shaper of the ZV/ZVD/EI
//! family ([`shapers`]) designed on the first mode at the target, the same shapers with
//! their spacing following the first mode as the telescopic positions move (scheduled),
//! and an optimized scheduled shaper ([`optimize`]). Every candidate runs on the nonlinear
//! model with clearance on every plant of the robust set ([`robust`]); [`metrics`] reads
//! its cycle time.
//!
//! ```no_run
//! use telescopic::moves::{MoveLimits, PlanOptions, plan_move};
//! use telescopic::{Scene, Silent};
//!
//! let scene = Scene::load("scenes/case-study.toml".as_ref(), &[])?;
//! let options = PlanOptions::new(MoveLimits { distance: 23.0, v_max: 2.5, a_max: 0.7, j_max: 2.0 });
//! let plan = plan_move(&scene, &options, &Silent)?;
//! println!("{}", plan.table());
//! # Ok::<(), telescopic::Error>(())
//! ```

pub mod candidates;
pub mod emit;
pub mod metrics;
pub mod optimize;
mod planner;
pub mod robust;
pub mod shapers;

pub use planner::{first_period, moving_scene, plan as plan_move};
pub use robust::RobustRange;

use crate::control::velocity::{VelocityDesign, VelocityFeedback};
use crate::run::SimulationOptions;
use crate::{Error, OptionName, Result};
use metrics::CycleMetrics;
use std::fmt::Write as _;
use telescopic_runtime::Scene;

/// The default velocity limit (m/s): the case study's drive.
pub const DEFAULT_V_MAX: f64 = 2.5;
/// The default acceleration limit (m/s^2).
pub const DEFAULT_A_MAX: f64 = 0.7;
/// The default jerk limit (m/s^3).
pub const DEFAULT_J_MAX: f64 = 2.0;

/// The move and the drive's limits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoveLimits {
    /// Travel (m); negative moves backwards.
    pub distance: f64,
    /// Velocity limit (m/s).
    pub v_max: f64,
    /// Acceleration limit (m/s^2).
    pub a_max: f64,
    /// Jerk limit (m/s^3).
    pub j_max: f64,
}

/// The default tolerance on `tip_rel` (m).
pub const DEFAULT_TOLERANCE_M: f64 = 0.005;
/// The default time simulated after the longest candidate arrives (s).
pub const DEFAULT_SETTLE_S: f64 = 10.0;
/// The default number of check plants.
pub const DEFAULT_CHECKS: usize = 4;

/// Options of [`plan_move`].
#[derive(Debug, Clone, PartialEq)]
pub struct PlanOptions {
    /// The move.
    pub limits: MoveLimits,
    /// How still the load must be: `tip_rel` within this of its final rest (m, default 0.005).
    pub tolerance: f64,
    /// The robust set: scene values and their ranges (default none: the nominal plant).
    pub robust: Vec<RobustRange>,
    /// Time simulated after the longest candidate arrives (s, default 10).
    pub settle_s: f64,
    /// Optimize the spacing of the best scheduled shaper (default true).
    pub optimize: bool,
    /// Plants inside the robust set the best plan is checked on (default 4; none without a
    /// robust set).
    pub checks: usize,
    /// The drive's force limit (N): a candidate whose reaction exceeds it is not chosen.
    pub force_limit: Option<f64>,
    /// The velocity feedback to evaluate on top of the S-curve and of the best open-loop
    /// candidate (default none).
    pub feedback: Option<VelocityDesign>,
    /// How each run is simulated.
    pub simulation: SimulationOptions,
}

impl PlanOptions {
    /// The defaults for `limits`.
    pub fn new(limits: MoveLimits) -> Self {
        PlanOptions {
            limits,
            tolerance: DEFAULT_TOLERANCE_M,
            robust: Vec::new(),
            settle_s: DEFAULT_SETTLE_S,
            optimize: true,
            checks: DEFAULT_CHECKS,
            force_limit: None,
            feedback: None,
            simulation: SimulationOptions::default(),
        }
    }

    /// Checks every field against its rule.
    ///
    /// # Errors
    /// [`Error::Option`] naming the field.
    pub fn check(&self) -> Result<()> {
        let l = &self.limits;
        let positive = |v: f64, option: OptionName, what: &str| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(Error::option(
                    option,
                    format!("{v}: {what} must be a finite number > 0"),
                ))
            }
        };
        if !(l.distance.is_finite() && l.distance != 0.0 && l.distance.abs() <= 1e4) {
            return Err(Error::option(
                OptionName::Distance,
                format!(
                    "{}: the travel must be finite, not 0, at most 10 km",
                    l.distance
                ),
            ));
        }
        positive(l.v_max, OptionName::MoveLimits, "the velocity limit")?;
        positive(l.a_max, OptionName::MoveLimits, "the acceleration limit")?;
        positive(l.j_max, OptionName::MoveLimits, "the jerk limit")?;
        positive(self.tolerance, OptionName::MoveTolerance, "the tolerance")?;
        if !(self.settle_s.is_finite() && self.settle_s >= 1.0 && self.settle_s <= 1000.0) {
            return Err(Error::option(
                OptionName::Settle,
                format!("{}: must be 1 to 1000 s", self.settle_s),
            ));
        }
        if let Some(f) = self.force_limit {
            positive(f, OptionName::ForceLimit, "the force limit")?;
        }
        Ok(())
    }
}

/// One candidate on one plant.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanRow {
    /// Index into [`MovePlan::candidates`].
    pub candidate: usize,
    /// The plant's name.
    pub plant: String,
    /// What the move achieved there.
    pub metrics: CycleMetrics,
}

/// A finished plan: every candidate on every plant, and the best.
#[derive(Debug, Clone, PartialEq)]
pub struct MovePlan {
    /// The scene planned for.
    pub scene: Scene,
    /// The time-optimal move of a rigid telescope (s): the S-curve's duration.
    pub rigid_limit_s: f64,
    /// The first mode's period at the target (s), vehicle held.
    pub first_period_s: f64,
    /// The end of every run (s).
    pub end_s: f64,
    /// The candidates, in the table's order.
    pub candidates: Vec<candidates::Candidate>,
    /// Each candidate on each evaluated plant.
    pub rows: Vec<PlanRow>,
    /// The best candidate on the plants it was not chosen on.
    pub checks: Vec<PlanRow>,
    /// Index of the best candidate: the shortest worst cycle time within the force limit.
    pub best: usize,
    /// The velocity feedback the candidates marked `feedback` run with, designed on the
    /// nominal plant.
    pub feedback: Option<VelocityFeedback>,
}

impl MovePlan {
    /// The worst cycle time (s) of candidate `i` over `rows`; `None` if a plant never settles.
    pub fn worst_cycle(rows: &[PlanRow], i: usize) -> Option<f64> {
        rows.iter()
            .filter(|r| r.candidate == i)
            .map(|r| r.metrics.cycle_time_s)
            .try_fold(0.0_f64, |w, c| c.map(|c| w.max(c)))
    }

    /// The best plan as a scene file (TOML): the scene with the setpoint as `drive.motion`
    /// and the span of the runs.
    pub fn scene_toml(&self) -> String {
        self.scene_toml_of(self.best)
    }

    /// Candidate `i`'s plan as a scene file (TOML).
    pub fn scene_toml_of(&self, i: usize) -> String {
        let chosen = &self.candidates[i];
        let mut file = planner::moving_file(&self.scene, &chosen.profile, self.end_s);
        file.description = format!("{}: planned move ({})", self.scene.name, chosen.name);
        planner::file_text(&file)
    }

    /// The best plan's feedback file (JSON), when the best plan uses feedback: what
    /// `simulate PLAN.toml --controller PLAN.json` reads.
    pub fn feedback_json(&self) -> Option<String> {
        self.feedback_json_of(self.best)
    }

    /// Candidate `i`'s feedback file (JSON), when it uses feedback.
    pub fn feedback_json_of(&self, i: usize) -> Option<String> {
        self.candidates[i]
            .feedback
            .then_some(self.feedback.as_ref())
            .flatten()
            .map(VelocityFeedback::to_json)
    }

    /// The index of the candidate named `name`.
    ///
    /// # Errors
    /// [`Error::Option`] listing the names.
    pub fn candidate_named(&self, name: &str) -> Result<usize> {
        self.candidates
            .iter()
            .position(|c| c.name == name)
            .ok_or_else(|| {
                let names: Vec<&str> = self.candidates.iter().map(|c| c.name.as_str()).collect();
                Error::option(
                    OptionName::Pick,
                    format!(
                        "no candidate is named {name:?}; the candidates: {}",
                        names.join(", ")
                    ),
                )
            })
    }

    /// The table: every candidate on every plant, the rigid limit, the best and its checks.
    pub fn table(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "rigid limit (time-optimal move of a rigid telescope): {:.2} s; first mode at the \
             target {:.3} Hz (vehicle held)",
            self.rigid_limit_s,
            1.0 / self.first_period_s
        );
        let _ = writeln!(
            out,
            "{:<52} {:<10} {:>7} {:>8} {:>7} {:>8} {:>8} {:>8} {:>9} {:>10} {:>8}",
            "candidate",
            "plant",
            "move s",
            "settle s",
            "cycle s",
            "tip mm",
            "resid mm",
            "drive N",
            "contact N",
            "stress MPa",
            "switches"
        );
        let cell = |v: Option<f64>, digits: usize| {
            v.map_or("never".to_string(), |v| format!("{v:.digits$}"))
        };
        for r in self.rows.iter().chain(&self.checks) {
            let m = &r.metrics;
            let _ = writeln!(
                out,
                "{:<52} {:<10} {:>7.2} {:>8} {:>7} {:>8.1} {:>8.1} {:>8.0} {:>9.0} {:>10} {:>8}",
                self.candidates[r.candidate].name,
                r.plant,
                m.move_time_s,
                cell(m.settling_time_s, 2),
                cell(m.cycle_time_s, 2),
                1e3 * m.peak_tip_move_m,
                1e3 * m.residual_m,
                m.peak_drive_force_n,
                m.peak_contact_force_n,
                m.peak_foot_stress_pa
                    .map_or("-".into(), |s| format!("{:.1}", s / 1e6)),
                m.switches_after_arrival
            );
        }
        let best = &self.candidates[self.best];
        let worst = Self::worst_cycle(&self.rows, self.best);
        let verdict = match worst {
            Some(w) => format!(
                "worst cycle over the evaluated plants {w:.2} s, {:+.1} % of the rigid limit",
                100.0 * (w / self.rigid_limit_s - 1.0)
            ),
            None => format!(
                "the load does not settle on every evaluated plant within {:.1} s; the \
                 smallest worst residual",
                self.end_s
            ),
        };
        let _ = writeln!(out, "best: {} ({verdict})", best.name);
        out
    }
}
