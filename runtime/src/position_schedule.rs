//! A value scheduled on a telescopic position: the monotone cubic of
//! [`crate::ShapedProfile::PiecewiseCubic`] over positions instead of times, evaluated at the
//! position `a_k(t)`, times a factor that changes from `stretch[0]` to `stretch[1]` over the
//! span `over` along a quintic smoothstep. A shaper's period scheduled this way follows the
//! first mode as the telescope extends, and a machine computes it from the measured
//! position (the emitted setpoint filter does).

use crate::profile::{Profile, monotone_cubic, smoothstep};
use serde::{Deserialize, Serialize};

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

/// `(f, f', f'')` of the factor going from `early` to `late` over `[start, end]` (s): `early`
/// throughout for an empty span.
pub fn stretch_factor([early, late]: [f64; 2], [start, end]: [f64; 2], t: f64) -> (f64, f64, f64) {
    if end <= start {
        return (early, 0.0, 0.0);
    }
    smoothstep((early, late), (start, end), t)
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
    use crate::ShapedProfile;

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
