//! The profile types: a scalar function of time (`Profile`), its table forms
//! (`ShapedProfile`), a shaped setpoint and a value scheduled on a telescopic position
//! (one family: a schedule holds the position profile it follows).

use super::curves::{monotone_cubic, smoothstep, stretch_factor};
use super::setpoint::{JerkSegments, SCurve};
use serde::{Deserialize, Serialize};

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
    /// A rest-to-rest move of constant-jerk segments.
    JerkSegments(JerkSegments),
    /// A setpoint filtered by an input shaper.
    Shaped(ShapedSetpoint),
    /// A value scheduled on a telescopic position (a shaper's period).
    PositionSchedule(PositionSchedule),
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
            Profile::Shaped(ShapedProfile::JerkSegments(m)) => {
                m.segments.iter().all(|s| s[0] == 0.0 || s[1] == 0.0)
            }
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
                | ShapedProfile::SCurve(_)
                | ShapedProfile::JerkSegments(_),
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
            Profile::Shaped(ShapedProfile::JerkSegments(m)) => m.switches(),
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
            Profile::Shaped(ShapedProfile::JerkSegments(m)) => {
                [("start", m.start), ("from", m.from)]
                    .into_iter()
                    .chain(m.segments.iter().flatten().map(|&v| ("segments", v)))
                    .collect()
            }
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
            Profile::Shaped(ShapedProfile::JerkSegments(m)) => m.state(t),
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

/// A value scheduled on a telescopic position: the monotone cubic of
/// [`crate::ShapedProfile::PiecewiseCubic`] over positions instead of times, evaluated at the
/// position `a_k(t)`, times a factor that changes from `stretch[0]` to `stretch[1]` over the
/// span `over` along a quintic smoothstep. A shaper's period scheduled this way follows the
/// first mode as the telescope extends, and a machine computes it from the measured
/// position (the emitted setpoint filter does).
///
/// `{ kind = "position-schedule", position = .., positions = [..], values = [..],
/// stretch = [early, late], over = [start, end] }`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PositionSchedule {
    /// The telescopic position `a_k(t)` (m) the schedule follows: a copy of the scene's.
    pub position: Box<Profile>,
    /// Knot positions (m), strictly increasing.
    pub positions: Vec<f64>,
    /// The value at each knot.
    pub values: Vec<f64>,
    /// The factor before `over` and after it.
    pub stretch: [f64; 2],
    /// The span (s) over which the factor changes.
    pub over: [f64; 2],
}

impl PositionSchedule {
    /// The value at the position `a` (m) and time `t` (s): what a machine computes from its
    /// measured position.
    pub fn at_position(&self, a: f64, t: f64) -> f64 {
        monotone_cubic(&self.positions, &self.values, a).0
            * stretch_factor(self.stretch, self.over, t).0
    }

    /// `(value, rate, acceleration)` at `t` (s), by the chain and product rules.
    pub(crate) fn state(&self, t: f64) -> (f64, f64, f64) {
        let (a, da, dda) = self.position_state(t);
        let (c, dc, ddc) = monotone_cubic(&self.positions, &self.values, a);
        let (f, df, ddf) = stretch_factor(self.stretch, self.over, t);
        (
            c * f,
            dc * da * f + c * df,
            (ddc * da * da + dc * dda) * f + 2.0 * dc * da * df + c * ddf,
        )
    }

    fn position_state(&self, t: f64) -> (f64, f64, f64) {
        (
            self.position.value(t),
            self.position.rate(t),
            self.position.acceleration(t),
        )
    }

    /// Where the value's derivatives may jump: the position's breakpoints and the span's
    /// ends (a knot crossed between them only bends the cubic's second derivative).
    pub(crate) fn breakpoints(&self) -> Vec<f64> {
        let mut out = self.position.breakpoints();
        out.extend(self.over);
        out
    }

    /// Every number it holds, with the field names.
    pub(crate) fn numbers(&self) -> Vec<(&'static str, f64)> {
        self.position
            .numbers()
            .into_iter()
            .map(|(_, v)| ("position", v))
            .chain(self.positions.iter().map(|&v| ("positions", v)))
            .chain(self.values.iter().map(|&v| ("values", v)))
            .chain(self.stretch.iter().map(|&v| ("stretch", v)))
            .chain(self.over.iter().map(|&v| ("over", v)))
            .collect()
    }
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

#[cfg(test)]
mod schedule_tests {
    use super::*;

    fn schedule() -> Profile {
        Profile::Shaped(ShapedProfile::PositionSchedule(PositionSchedule {
            position: Box::new(Profile::Shaped(ShapedProfile::Smoothstep {
                start: 0.0,
                end: 12.0,
                from: 0.35,
                to: 1.15,
            })),
            positions: vec![0.35, 0.6, 0.9, 1.15],
            values: vec![1.0, 1.3, 1.7, 2.0],
            stretch: [1.1, 0.9],
            over: [0.0, 13.0],
        }))
    }

    #[test]
    fn derivatives_agree_with_finite_differences() {
        let p = schedule();
        let h = 1e-5;
        for t in [0.5, 3.0, 6.1, 11.0, 12.5] {
            let rate = (p.value(t + h) - p.value(t - h)) / (2.0 * h);
            assert!((rate - p.rate(t)).abs() < 1e-7, "{t}: {rate} {}", p.rate(t));
            let acc = (p.rate(t + h) - p.rate(t - h)) / (2.0 * h);
            assert!((acc - p.acceleration(t)).abs() < 1e-5, "{t}");
        }
    }

    #[test]
    fn it_is_the_cubic_of_the_position_times_the_factor() {
        let Profile::Shaped(ShapedProfile::PositionSchedule(s)) = schedule() else {
            unreachable!()
        };
        // at the start the position is the first knot, the factor the early stretch
        assert_eq!(schedule().value(0.0), 1.1);
        // after both spans: the last knot's value times the late stretch
        assert!((schedule().value(20.0) - 1.8).abs() < 1e-15);
        assert_eq!(s.at_position(0.6, 0.0), 1.3 * 1.1);
    }
}
