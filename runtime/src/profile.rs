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
//! ```
//!
//! Piecewise profiles hold their first value before the first time and their last value
//! after the last one; piecewise-constant takes `values[i]` on `[times[i], times[i+1])`.
//! The smoothstep is the quintic `from + (to - from)(10u^3 - 15u^4 + 6u^5)`,
//! `u = (t - start)/(end - start)`, constant outside `[start, end]`.

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
}

impl<'de> Deserialize<'de> for Profile {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ProfileVisitor;
        impl<'de> Visitor<'de> for ProfileVisitor {
            type Value = Profile;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(
                    "a number, or a table with kind = \"constant\", \"piecewise-constant\", \
                     \"piecewise-linear\" or \"smoothstep\"",
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
            | Profile::Shaped(ShapedProfile::PiecewiseLinear { values, .. }) => {
                values.windows(2).all(|w| w[0] == w[1])
            }
            Profile::Shaped(ShapedProfile::Smoothstep { from, to, .. }) => from == to,
        }
    }

    /// True when the profile has a continuous first derivative everywhere (needed for a
    /// prescribed motion, whose acceleration must exist).
    pub fn has_continuous_rate(&self) -> bool {
        match self {
            Profile::Constant(_) => true,
            Profile::Shaped(ShapedProfile::Constant { .. } | ShapedProfile::Smoothstep { .. }) => {
                true
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
            | Profile::Shaped(ShapedProfile::PiecewiseLinear { times, .. }) => times.clone(),
            Profile::Shaped(ShapedProfile::Smoothstep { start, end, .. }) => vec![*start, *end],
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
            | Profile::Shaped(ShapedProfile::PiecewiseLinear { times, values }) => times
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
        }
    }

    /// `(value, rate, acceleration)` at `t`.
    fn eval(&self, t: f64) -> (f64, f64, f64) {
        match self {
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
            }) => {
                let span = end - start;
                if t <= *start {
                    (*from, 0.0, 0.0)
                } else if t >= *end {
                    (*to, 0.0, 0.0)
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
        }
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
