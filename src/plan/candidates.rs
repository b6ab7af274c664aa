//! The moves a plan compares: the time-optimal S-curve, the S-curve through each shaper with
//! a fixed period (the first mode's at the target), and through each shaper with the period
//! following the first mode along the move (scheduled).

use super::shapers::Shaper;
use serde::Serialize;
use telescopic_runtime::{PositionSchedule, Profile, SCurve, ShapedProfile, ShapedSetpoint};

/// One candidate move.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Candidate {
    /// `s-curve`, `zvd`, `zvd scheduled`, `optimized (...)`.
    pub name: String,
    /// The setpoint `s(t)` (m).
    pub profile: Profile,
    /// When the setpoint reaches the target (s).
    pub arrival_s: f64,
    /// Whether the velocity feedback of the plan ([`super::MovePlan::feedback`]) corrects
    /// the setpoint.
    pub feedback: bool,
}

impl Candidate {
    /// The same move with the plan's velocity feedback on top.
    pub fn with_feedback(&self) -> Candidate {
        Candidate {
            name: format!("{} + feedback", self.name),
            feedback: true,
            ..self.clone()
        }
    }
}

/// The unshaped S-curve.
pub fn unshaped(curve: &SCurve) -> Candidate {
    Candidate {
        name: "s-curve".into(),
        profile: Profile::Shaped(ShapedProfile::SCurve(curve.clone())),
        arrival_s: curve.start + curve.phases().duration(),
        feedback: false,
    }
}

/// `curve` through `shaper` with impulses spaced by `period` (s, a number or a schedule),
/// the spacing scaled by `stretch` at the start of the move, by `stretch_late` at its end and
/// smoothly between (a schedule's knots; a number takes `stretch`), named `name`.
pub fn shaped(
    name: String,
    curve: &SCurve,
    shaper: Shaper,
    (period, stretch, stretch_late): (&Profile, f64, f64),
) -> Candidate {
    let span = (curve.start, curve.start + curve.phases().duration());
    let scaled = scale_profile(period, (stretch, stretch_late), span);
    let profile = Profile::Shaped(ShapedProfile::Shaped(ShapedSetpoint {
        base: Box::new(Profile::Shaped(ShapedProfile::SCurve(curve.clone()))),
        impulses: shaper.impulses(),
        period: Box::new(scaled.clone()),
    }));
    let arrival_s = arrival(curve, shaper.periods(), &scaled);
    Candidate {
        name,
        profile,
        arrival_s,
        feedback: false,
    }
}

/// `period` times a factor that goes from `early` at `start` to `late` at `end` (s) along a
/// quintic smoothstep, so that the spacing's rate stays small (a number: times `early`).
fn scale_profile(period: &Profile, stretch: (f64, f64), (start, end): (f64, f64)) -> Profile {
    match period {
        Profile::Constant(p) => Profile::Constant(p * stretch.0),
        Profile::Shaped(ShapedProfile::PositionSchedule(s)) => {
            Profile::Shaped(ShapedProfile::PositionSchedule(PositionSchedule {
                stretch: [stretch.0, stretch.1],
                over: [start, end],
                ..s.clone()
            }))
        }
        other => other.clone(),
    }
}

/// When the last impulse's copy of the curve arrives: the `t` with `t - m P(t)` at the
/// curve's end (a contraction while `m P'(t) < 1`; a few iterations settle it).
fn arrival(curve: &SCurve, last_multiple: f64, period: &Profile) -> f64 {
    let end = curve.start + curve.phases().duration();
    let mut t = end + last_multiple * period.value(end);
    for _ in 0..50 {
        let next = end + last_multiple * period.value(t);
        if (next - t).abs() < 1e-12 {
            break;
        }
        t = next;
    }
    t
}
