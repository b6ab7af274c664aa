//! What a plan is asked for: the move's limits, the tolerance, the robust set and the
//! feedback, with their defaults and checks.

use super::robust::RobustRange;
use crate::control::design::velocity::VelocityDesign;
use crate::run::SimulationOptions;
use crate::{Error, OptionName, Result};
use telescopic_runtime::SCurve;

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

impl MoveLimits {
    /// The time-optimal jerk-limited move within these limits, from rest at 0 m at `start`
    /// (s).
    pub fn curve(&self, start: f64) -> SCurve {
        SCurve {
            start,
            from: 0.0,
            distance: self.distance,
            v_max: self.v_max,
            a_max: self.a_max,
            j_max: self.j_max,
        }
    }
}

/// The default tolerance on `tip_rel` (m).
pub const DEFAULT_TOLERANCE_M: f64 = 0.005;
/// The default share of the tolerance a pick keeps in reserve.
pub const DEFAULT_MARGIN: f64 = 0.2;
/// The default time simulated after the longest candidate arrives (s).
pub const DEFAULT_SETTLE_S: f64 = 10.0;
/// The default number of check plants.
pub const DEFAULT_CHECKS: usize = 4;
/// Most check plants.
pub const MAX_CHECKS: usize = 256;

/// Options of [`super::plan_move`].
#[derive(Debug, Clone, PartialEq)]
pub struct PlanOptions {
    /// The move.
    pub limits: MoveLimits,
    /// How still the load must be: `tip_rel` within this of its final rest (m, default 0.005).
    pub tolerance: f64,
    /// The share of the tolerance the pick keeps in reserve (0 to 0.9, default 0.2): the
    /// best candidate is the one with the shortest worst cycle within `(1 - margin)
    /// tolerance`, so that a residual just under the tolerance does not win.
    pub margin: f64,
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

/// The tolerance a pick ranks on (m): `tolerance` (m) less its share `margin`.
pub fn pick_tolerance(tolerance: f64, margin: f64) -> f64 {
    (1.0 - margin) * tolerance
}

impl PlanOptions {
    /// The tolerance the pick ranks on (m): the options' tolerance less its margin.
    pub fn pick_tolerance(&self) -> f64 {
        pick_tolerance(self.tolerance, self.margin)
    }

    /// The defaults for `limits`.
    pub fn new(limits: MoveLimits) -> Self {
        PlanOptions {
            limits,
            tolerance: DEFAULT_TOLERANCE_M,
            margin: DEFAULT_MARGIN,
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
        if !(self.margin.is_finite() && (0.0..=0.9).contains(&self.margin)) {
            return Err(Error::option(
                OptionName::MoveMargin,
                format!(
                    "{}: the margin is a share of the tolerance, 0 to 0.9",
                    self.margin
                ),
            ));
        }
        if !(self.settle_s.is_finite() && self.settle_s >= 1.0 && self.settle_s <= 1000.0) {
            return Err(Error::option(
                OptionName::Settle,
                format!("{}: must be 1 to 1000 s", self.settle_s),
            ));
        }
        if let Some(f) = self.force_limit {
            positive(f, OptionName::ForceLimit, "the force limit")?;
        }
        if let Some(design) = &self.feedback {
            design.check()?;
        }
        if self.checks > MAX_CHECKS {
            return Err(Error::option(
                OptionName::Checks,
                format!("{}: at most {MAX_CHECKS} check plants", self.checks),
            ));
        }
        Ok(())
    }
}
