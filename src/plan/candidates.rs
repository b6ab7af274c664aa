//! The moves a plan compares: the time-optimal S-curve, the S-curve through each shaper with
//! a fixed period (the first mode's at the target), and through each shaper with the period
//! following the first mode along the move (scheduled), and the matched move whose
//! acceleration and deceleration each span whole periods of the first mode.

use super::shapers::Shaper;
use serde::Serialize;
use telescopic_runtime::{
    JerkSegments, PositionSchedule, Profile, SCurve, ShapedProfile, ShapedSetpoint,
};

/// The name of the matched move ([`matched`]) in a plan.
pub const MATCHED_NAME: &str = "matched s-curve";

/// Passes that match the acceleration and the deceleration to the mean period where each
/// lies (each pass moves the deceleration, which moves its period).
const MATCHING_PASSES: usize = 8;

/// Points of the midpoint rule of a pulse's mean frequency.
const MEAN_FREQUENCY_POINTS: usize = 32;

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

/// A matched move ([`matched`]) and how it was matched.
#[derive(Debug, Clone, PartialEq)]
pub struct Matched {
    /// The move.
    pub candidate: Candidate,
    /// The periods of the first mode the boxes of the acceleration and of the braking span.
    pub periods: [f64; 2],
    /// The acceleration and the braking (m/s^2): what a drive is set to.
    pub accelerations: [f64; 2],
}

/// The matched move: the S-curve's cruise velocity and jerk, with an acceleration of its own
/// for each half. A half's pulse of acceleration is the convolution of a box `a/j` long
/// with a box `v/a` long; a box of whole periods of the first mode has a zero of its
/// spectrum at the mode, so a linear mode of that period is left at rest by construction,
/// without the delay a shaper adds. The box `v/a` spans as few periods as the acceleration
/// limit allows. Where the period (`period`, s, a number or a schedule) changes along a
/// pulse, the box spans whole periods of the pulse's mean frequency. `stretch` scales the
/// boxes of the two halves for the optimizer; the acceleration never exceeds the limit.
/// Returns the move named `name`; `None` where the limits leave the move no cruise.
pub fn matched(
    name: &str,
    curve: &SCurve,
    period: &Profile,
    stretch: (f64, f64),
) -> Option<Matched> {
    let v = curve.v_max;
    let limits = (curve.a_max.min((v * curve.j_max).sqrt()), curve.j_max);
    let place = (curve.start, curve.from, curve.distance);
    let mut halves = [limits; 2];
    let mut periods: Option<[f64; 2]> = None;
    let mut segments = JerkSegments::trapezoidal(place, v, halves)?;
    for _ in 0..MATCHING_PASSES {
        let end = curve.start + segments.duration();
        let pulse = |(a, j): (f64, f64)| v / a + a / j;
        let frequencies = [
            mean_frequency(period, (curve.start, curve.start + pulse(halves[0]))),
            mean_frequency(period, (end - pulse(halves[1]), end)),
        ];
        // the fewest whole periods within the limits, counted once
        let counts =
            *periods.get_or_insert(frequencies.map(|f| (v * f / limits.0).ceil().max(1.0)));
        let stretches = [stretch.0, stretch.1];
        for (i, half) in halves.iter_mut().enumerate() {
            let a = v * frequencies[i] / (counts[i] * stretches[i]);
            *half = (a.min(limits.0), limits.1);
        }
        segments = JerkSegments::trapezoidal(place, v, halves)?;
    }
    let candidate = Candidate {
        name: name.to_string(),
        arrival_s: curve.start + segments.duration(),
        profile: Profile::Shaped(ShapedProfile::JerkSegments(segments)),
        feedback: false,
    };
    Some(Matched {
        candidate,
        periods: periods?,
        accelerations: halves.map(|h| h.0),
    })
}

/// The mean frequency (Hz) of `period` (s) over `(from, to)` (s).
fn mean_frequency(period: &Profile, (from, to): (f64, f64)) -> f64 {
    let n = MEAN_FREQUENCY_POINTS;
    let h = (to - from) / n as f64;
    (0..n)
        .map(|i| 1.0 / period.value(from + (i as f64 + 0.5) * h))
        .sum::<f64>()
        / n as f64
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
