//! Time profiles for telescopic positions `a_k(t)`, the drive force `F(t)` and a prescribed
//! vehicle motion `s(t)`.
//!
//! In a scene file a profile is a number (constant) or a table with a `kind`:
//!
//! ```toml
//! force = 100.0
//! force = { kind = "piecewise-constant", times = [0, 4, 8, 12], values = [100, 0, -100, 0] }
//! force = { kind = "piecewise-linear", times = [0, 1], values = [0, 100] }
//! position = { kind = "smoothstep", start = 0, end = 12, from = 0.35, to = 1.15 }
//! motion = { kind = "s-curve", start = 0, distance = 23, v_max = 2.5, a_max = 0.7, j_max = 2 }
//! motion = { kind = "shaped", base = { kind = "s-curve", ... }, impulses = [[0.5, 0], [0.5, 0.5]], period = 1.75 }
//! ```
//!
//! Piecewise profiles hold their first value before the first time and their last value
//! after the last one; piecewise-constant takes `values[i]` on `[times[i], times[i+1])`.
//! The smoothstep is the quintic `from + (to - from)(10u^3 - 15u^4 + 6u^5)`,
//! `u = (t - start)/(end - start)`, constant outside `[start, end]`. The S-curve is the
//! time-optimal jerk-limited move ([`crate::setpoint::SCurve`]); a shaped setpoint is
//! `sum_i A_i base(t - m_i P(t))`, impulses of amplitude `A_i` at multiples `m_i` of a period
//! `P(t)` that may follow the telescopic positions ([`ShapedSetpoint`]).

use crate::setpoint::SCurve;
use serde::de::{self, Deserializer, MapAccess, Visitor};
use serde::{Deserialize, Serialize};
use std::fmt;

/// A scalar function of time.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Profile {
    /// The same value at all times.
    Constant(f64),
    /// A profile with a shape.
    Shaped(ShapedProfile),
}

/// The profiles with a shape, tagged by `kind` in scene files.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum ShapedProfile {
    /// `{ kind = "constant", value = v }`.
    Constant {
        /// The value.
        value: f64,
    },
    /// Steps: `values[i]` on `[times[i], times[i+1])`.
    PiecewiseConstant {
        /// Switching times (s), strictly increasing.
        times: Vec<f64>,
        /// One value per time.
        values: Vec<f64>,
    },
    /// Linear interpolation between `(times[i], values[i])`.
    PiecewiseLinear {
        /// Knot times (s), strictly increasing.
        times: Vec<f64>,
        /// One value per time.
        values: Vec<f64>,
    },
    /// Quintic smoothstep from `from` at `start` to `to` at `end` (zero rate and acceleration
    /// at both ends).
    Smoothstep {
        /// Start time (s).
        start: f64,
        /// End time (s), after `start`.
        end: f64,
        /// Value before and at `start`.
        from: f64,
        /// Value at and after `end`.
        to: f64,
    },
    /// A smooth monotone interpolation of `(times[i], values[i])`: cubic between the
    /// points with slopes by Fritsch and Butland (the harmonic mean of the neighbouring
    /// secants, zero at an extremum and at both ends), so its rate is continuous and it
    /// never overshoots the points.
    PiecewiseCubic {
        /// Knot times (s), strictly increasing.
        times: Vec<f64>,
        /// One value per time.
        values: Vec<f64>,
    },
    /// The time-optimal jerk-limited move.
    SCurve(SCurve),
    /// A setpoint filtered by an input shaper.
    Shaped(ShapedSetpoint),
    /// A value scheduled on a telescopic position (a shaper's period).
    PositionSchedule(crate::position_schedule::PositionSchedule),
}

/// A setpoint filtered by an input shaper: `sum_i A_i base(t - m_i P(t))`, impulses of
/// amplitude `A_i` (summing to 1) at multiples `m_i` of the period `P(t)` (s).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShapedSetpoint {
    /// The raw setpoint.
    pub base: Box<Profile>,
    /// `[amplitude, multiple of the period]` per impulse.
    pub impulses: Vec<[f64; 2]>,
    /// The period `P(t)` (s) the impulses are spaced by: a number, or a piecewise-linear
    /// profile that follows the first mode as the telescopic positions move.
    pub period: Box<Profile>,
}

impl ShapedSetpoint {
    /// `(value, rate, acceleration)` at `t`: exact where the period's second derivative is
    /// that of its profile (zero between the knots of a piecewise-linear one).
    fn state(&self, t: f64) -> (f64, f64, f64) {
        let (period, period_rate) = (self.period.value(t), self.period.rate(t));
        let period_acceleration = self.period.acceleration(t);
        let (mut x, mut v, mut a) = (0.0, 0.0, 0.0);
        for &[amplitude, multiple] in &self.impulses {
            let delayed = t - multiple * period;
            let stretch = 1.0 - multiple * period_rate;
            let (bx, bv, ba) = self.base.eval(delayed);
            x += amplitude * bx;
            v += amplitude * bv * stretch;
            a += amplitude * (ba * stretch * stretch - bv * multiple * period_acceleration);
        }
        (x, v, a)
    }

    /// Times where the shaped setpoint's acceleration may jump: the base's switches delayed
    /// by each impulse (by the period at the switch: exact for a constant period, close for
    /// a scheduled one) and the period's knots.
    fn breakpoints(&self) -> Vec<f64> {
        let switches = self.base.breakpoints();
        let mut out: Vec<f64> = self
            .impulses
            .iter()
            .flat_map(|&[_, m]| switches.iter().map(move |&b| b + m * self.period.value(b)))
            .chain(self.period.breakpoints())
            .collect();
        out.sort_by(f64::total_cmp);
        out.dedup();
        out
    }
}

impl<'de> Deserialize<'de> for Profile {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ProfileVisitor;
        impl<'de> Visitor<'de> for ProfileVisitor {
            type Value = Profile;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(
                    "a number, or a table with kind = \"constant\", \"piecewise-constant\", \
                     \"piecewise-linear\", \"piecewise-cubic\", \"smoothstep\", \"s-curve\", \"shaped\" \
                     or \"position-schedule\"",
                )
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Profile, E> {
                Ok(Profile::Constant(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Profile, E> {
                Ok(Profile::Constant(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Profile, E> {
                Ok(Profile::Constant(v as f64))
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Profile, A::Error> {
                ShapedProfile::deserialize(de::value::MapAccessDeserializer::new(map))
                    .map(Profile::Shaped)
            }
        }
        deserializer.deserialize_any(ProfileVisitor)
    }
}

impl Profile {
    /// `(value, rate, acceleration)` at time `t` (s), in one evaluation.
    pub fn state(&self, t: f64) -> (f64, f64, f64) {
        self.eval(t)
    }

    /// Value at time `t` (s).
    pub fn value(&self, t: f64) -> f64 {
        self.eval(t).0
    }

    /// Rate `d/dt` at time `t` (per s); one-sided (from the right) at kinks.
    pub fn rate(&self, t: f64) -> f64 {
        self.eval(t).1
    }

    /// Second derivative at time `t` (per s^2); zero for piecewise profiles between knots.
    pub fn acceleration(&self, t: f64) -> f64 {
        self.eval(t).2
    }

    /// True when the profile does not change in time.
    pub fn is_constant(&self) -> bool {
        match self {
            Profile::Constant(_) | Profile::Shaped(ShapedProfile::Constant { .. }) => true,
            Profile::Shaped(ShapedProfile::PiecewiseConstant { values, .. })
            | Profile::Shaped(ShapedProfile::PiecewiseLinear { values, .. })
            | Profile::Shaped(ShapedProfile::PiecewiseCubic { values, .. }) => {
                values.windows(2).all(|w| w[0] == w[1])
            }
            Profile::Shaped(ShapedProfile::Smoothstep { from, to, .. }) => from == to,
            Profile::Shaped(ShapedProfile::SCurve(c)) => c.distance == 0.0,
            Profile::Shaped(ShapedProfile::Shaped(s)) => s.base.is_constant(),
            Profile::Shaped(ShapedProfile::PositionSchedule(s)) => {
                s.values.windows(2).all(|w| w[0] == w[1]) && s.stretch[0] == s.stretch[1]
            }
        }
    }

    /// True when the profile has a continuous first derivative everywhere (needed for a
    /// prescribed motion, whose acceleration must exist).
    pub fn has_continuous_rate(&self) -> bool {
        match self {
            Profile::Constant(_) => true,
            Profile::Shaped(
                ShapedProfile::Constant { .. }
                | ShapedProfile::Smoothstep { .. }
                | ShapedProfile::PiecewiseCubic { .. }
                | ShapedProfile::SCurve(_),
            ) => true,
            Profile::Shaped(ShapedProfile::PositionSchedule(s)) => s.position.has_continuous_rate(),
            Profile::Shaped(ShapedProfile::Shaped(s)) => {
                s.base.has_continuous_rate() && s.period.has_continuous_rate()
                    || s.base.is_constant()
            }
            Profile::Shaped(_) => self.is_constant(),
        }
    }

    /// Times (s) where the profile or one of its first two derivatives jumps: integrators
    /// stop and restart there.
    pub fn breakpoints(&self) -> Vec<f64> {
        match self {
            Profile::Constant(_) | Profile::Shaped(ShapedProfile::Constant { .. }) => Vec::new(),
            Profile::Shaped(ShapedProfile::PiecewiseConstant { times, .. })
            | Profile::Shaped(ShapedProfile::PiecewiseLinear { times, .. })
            | Profile::Shaped(ShapedProfile::PiecewiseCubic { times, .. }) => times.clone(),
            Profile::Shaped(ShapedProfile::Smoothstep { start, end, .. }) => vec![*start, *end],
            Profile::Shaped(ShapedProfile::SCurve(c)) => c.switches(),
            Profile::Shaped(ShapedProfile::Shaped(s)) => s.breakpoints(),
            Profile::Shaped(ShapedProfile::PositionSchedule(s)) => s.breakpoints(),
        }
    }

    /// Smallest and largest value over `[t0, t1]` (every profile here is monotone between
    /// its breakpoints, so the extremes are at `t0`, `t1` or a breakpoint inside).
    pub fn range(&self, t0: f64, t1: f64) -> (f64, f64) {
        let mut lo = self.value(t0).min(self.value(t1));
        let mut hi = self.value(t0).max(self.value(t1));
        for t in self.breakpoints().into_iter().filter(|&t| t > t0 && t < t1) {
            // the value at t and just before t (piecewise-constant jumps)
            for v in [self.value(t), self.value_before(t)] {
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
        (lo, hi)
    }

    /// Limit of the value from the left at `t`.
    fn value_before(&self, t: f64) -> f64 {
        match self {
            Profile::Shaped(ShapedProfile::PiecewiseConstant { times, values }) => {
                let i = times.partition_point(|&ti| ti < t);
                values[i.saturating_sub(1)]
            }
            _ => self.value(t),
        }
    }

    /// All numbers the profile holds, with their field names (for validation).
    pub(crate) fn numbers(&self) -> Vec<(&'static str, f64)> {
        match self {
            Profile::Constant(v) | Profile::Shaped(ShapedProfile::Constant { value: v }) => {
                vec![("", *v)]
            }
            Profile::Shaped(ShapedProfile::PiecewiseConstant { times, values })
            | Profile::Shaped(ShapedProfile::PiecewiseLinear { times, values })
            | Profile::Shaped(ShapedProfile::PiecewiseCubic { times, values }) => times
                .iter()
                .map(|&t| ("times", t))
                .chain(values.iter().map(|&v| ("values", v)))
                .collect(),
            Profile::Shaped(ShapedProfile::Smoothstep {
                start,
                end,
                from,
                to,
            }) => {
                vec![
                    ("start", *start),
                    ("end", *end),
                    ("from", *from),
                    ("to", *to),
                ]
            }
            Profile::Shaped(ShapedProfile::SCurve(c)) => vec![
                ("start", c.start),
                ("from", c.from),
                ("distance", c.distance),
                ("v_max", c.v_max),
                ("a_max", c.a_max),
                ("j_max", c.j_max),
            ],
            Profile::Shaped(ShapedProfile::Shaped(s)) => s
                .base
                .numbers()
                .into_iter()
                .map(|(_, v)| ("base", v))
                .chain(s.impulses.iter().flatten().map(|&v| ("impulses", v)))
                .chain(s.period.numbers().into_iter().map(|(_, v)| ("period", v)))
                .collect(),
            Profile::Shaped(ShapedProfile::PositionSchedule(s)) => s.numbers(),
        }
    }

    /// `(value, rate, acceleration)` at `t`.
    fn eval(&self, t: f64) -> (f64, f64, f64) {
        match self {
            Profile::Shaped(ShapedProfile::SCurve(c)) => c.state(t),
            Profile::Shaped(ShapedProfile::Shaped(s)) => s.state(t),
            Profile::Shaped(ShapedProfile::PositionSchedule(s)) => s.state(t),
            Profile::Shaped(ShapedProfile::PiecewiseCubic { times, values }) => {
                monotone_cubic(times, values, t)
            }
            Profile::Constant(v) | Profile::Shaped(ShapedProfile::Constant { value: v }) => {
                (*v, 0.0, 0.0)
            }
            Profile::Shaped(ShapedProfile::PiecewiseConstant { times, values }) => {
                let i = times.partition_point(|&ti| ti <= t);
                (values[i.saturating_sub(1)], 0.0, 0.0)
            }
            Profile::Shaped(ShapedProfile::PiecewiseLinear { times, values }) => {
                let i = times.partition_point(|&ti| ti <= t);
                if i == 0 {
                    (values[0], 0.0, 0.0)
                } else if i == times.len() {
                    (values[i - 1], 0.0, 0.0)
                } else {
                    let slope = (values[i] - values[i - 1]) / (times[i] - times[i - 1]);
                    (values[i - 1] + slope * (t - times[i - 1]), slope, 0.0)
                }
            }
            Profile::Shaped(ShapedProfile::Smoothstep {
                start,
                end,
                from,
                to,
            }) => smoothstep((*from, *to), (*start, *end), t),
        }
    }
}

/// `(value, rate, acceleration)` at `t` of the quintic smoothstep from `from` at `start` to
/// `to` at `end` (s): `from + (to - from)(10u^3 - 15u^4 + 6u^5)`, constant outside.
pub(crate) fn smoothstep(
    (from, to): (f64, f64),
    (start, end): (f64, f64),
    t: f64,
) -> (f64, f64, f64) {
    let span = end - start;
    if t <= start {
        (from, 0.0, 0.0)
    } else if t >= end {
        (to, 0.0, 0.0)
    } else {
        let u = (t - start) / span;
        let jump = to - from;
        let s = u * u * u * (10.0 + u * (-15.0 + 6.0 * u));
        let ds = 30.0 * u * u * (1.0 - u) * (1.0 - u);
        let dds = 60.0 * u * (1.0 - u) * (1.0 - 2.0 * u);
        (
            from + jump * s,
            jump * ds / span,
            jump * dds / (span * span),
        )
    }
}

/// `(value, rate, acceleration)` at `t` of the monotone cubic through `(times, values)`
/// ([`ShapedProfile::PiecewiseCubic`]).
pub(crate) fn monotone_cubic(times: &[f64], values: &[f64], t: f64) -> (f64, f64, f64) {
    let n = times.len();
    let i = times.partition_point(|&ti| ti <= t);
    if i == 0 {
        return (values[0], 0.0, 0.0);
    }
    if i == n {
        return (values[n - 1], 0.0, 0.0);
    }
    let secant = |k: usize| (values[k + 1] - values[k]) / (times[k + 1] - times[k]);
    // Fritsch-Butland slope at knot k: zero at the ends and at an extremum
    let slope = |k: usize| {
        if k == 0 || k == n - 1 {
            return 0.0;
        }
        let (a, b) = (secant(k - 1), secant(k));
        if a * b <= 0.0 {
            0.0
        } else {
            2.0 * a * b / (a + b)
        }
    };
    let (t0, h) = (times[i - 1], times[i] - times[i - 1]);
    let (y0, y1, m0, m1) = (values[i - 1], values[i], slope(i - 1), slope(i));
    let u = (t - t0) / h;
    // Hermite basis and its derivatives in u
    let (h00, h10, h01, h11) = (
        (1.0 + 2.0 * u) * (1.0 - u) * (1.0 - u),
        u * (1.0 - u) * (1.0 - u),
        u * u * (3.0 - 2.0 * u),
        u * u * (u - 1.0),
    );
    let (d00, d10, d01, d11) = (
        6.0 * u * u - 6.0 * u,
        3.0 * u * u - 4.0 * u + 1.0,
        6.0 * u - 6.0 * u * u,
        3.0 * u * u - 2.0 * u,
    );
    let (s00, s10, s01, s11) = (12.0 * u - 6.0, 6.0 * u - 4.0, 6.0 - 12.0 * u, 6.0 * u - 2.0);
    (
        h00 * y0 + h10 * h * m0 + h01 * y1 + h11 * h * m1,
        (d00 * y0 + d10 * h * m0 + d01 * y1 + d11 * h * m1) / h,
        (s00 * y0 + s10 * h * m0 + s01 * y1 + s11 * h * m1) / (h * h),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn smoothstep() -> Profile {
        Profile::Shaped(ShapedProfile::Smoothstep {
            start: 0.0,
            end: 12.0,
            from: 0.35,
            to: 1.15,
        })
    }

    #[test]
    fn smoothstep_derivatives_agree_with_finite_differences() {
        let p = smoothstep();
        for t in [0.5, 3.0, 6.0, 11.0] {
            let h = 1e-5;
            assert_relative_eq!(
                p.rate(t),
                (p.value(t + h) - p.value(t - h)) / (2.0 * h),
                max_relative = 1e-7
            );
            assert_relative_eq!(
                p.acceleration(t),
                (p.rate(t + h) - p.rate(t - h)) / (2.0 * h),
                epsilon = 1e-9,
                max_relative = 1e-6
            );
        }
        assert_eq!(p.value(-1.0), 0.35);
        assert_eq!(p.value(6.0), 0.75);
        assert_eq!(p.value(20.0), 1.15);
    }

    #[test]
    fn the_monotone_cubic_passes_its_points_with_a_continuous_rate_and_no_overshoot() {
        let p = Profile::Shaped(ShapedProfile::PiecewiseCubic {
            times: vec![0.0, 1.0, 2.0, 4.0],
            values: vec![1.0, 1.5, 3.0, 3.0],
        });
        for (t, v) in [(0.0, 1.0), (1.0, 1.5), (2.0, 3.0), (4.0, 3.0), (9.0, 3.0)] {
            assert!((p.value(t) - v).abs() < 1e-15, "{t}");
        }
        let h = 1e-7;
        for t in [0.0, 1.0, 2.0, 4.0] {
            assert!(
                (p.rate(t - h) - p.rate(t + h)).abs() < 1e-5,
                "rate jumps at {t}"
            );
        }
        for k in 0..=400 {
            let t = f64::from(k) / 100.0;
            let v = p.value(t);
            assert!((1.0 - 1e-12..=3.0 + 1e-12).contains(&v), "{t}: {v}");
            assert!(p.rate(t) >= 0.0);
            let fd = (p.value(t + h) - p.value(t - h)) / (2.0 * h);
            assert!((fd - p.rate(t)).abs() < 1e-6, "{t}");
        }
    }

    #[test]
    fn piecewise_profiles_step_and_interpolate() {
        let f = Profile::Shaped(ShapedProfile::PiecewiseConstant {
            times: vec![0.0, 4.0, 8.0, 12.0],
            values: vec![100.0, 0.0, -100.0, 0.0],
        });
        assert_eq!(f.value(3.999), 100.0);
        assert_eq!(f.value(4.0), 0.0);
        assert_eq!(f.value(9.0), -100.0);
        assert_eq!(f.value(15.0), 0.0);
        assert_eq!(f.range(0.0, 16.0), (-100.0, 100.0));
        let g = Profile::Shaped(ShapedProfile::PiecewiseLinear {
            times: vec![1.0, 3.0],
            values: vec![0.0, 10.0],
        });
        assert_eq!(g.value(0.0), 0.0);
        assert_eq!(g.value(2.0), 5.0);
        assert_eq!(g.rate(2.0), 5.0);
        assert_eq!(g.value(4.0), 10.0);
    }
}
