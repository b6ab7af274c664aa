//! The setpoint a servo drive makes for a point-to-point move: the time-optimal jerk-limited
//! move (the S-curve: seven phases of constant jerk `+j, 0, -j, 0, -j, 0, +j`), in closed
//! form. [`crate::profile::ShapedSetpoint`] filters it through an input shaper.

use serde::{Deserialize, Serialize};

/// The time-optimal rest-to-rest move over `distance` (m, either sign) within `v_max`
/// (m/s), `a_max` (m/s^2) and `j_max` (m/s^3), starting at `start` (s) from `from` (m).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SCurve {
    /// Start time (s).
    pub start: f64,
    /// Position before the move (m).
    #[serde(default)]
    pub from: f64,
    /// Travel (m); negative moves backwards.
    pub distance: f64,
    /// Velocity limit (m/s, > 0).
    pub v_max: f64,
    /// Acceleration limit (m/s^2, > 0).
    pub a_max: f64,
    /// Jerk limit (m/s^3, > 0).
    pub j_max: f64,
}

/// Which limits a time-optimal move reaches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReachedLimits {
    /// Velocity and acceleration: seven phases, a cruise among them.
    VelocityAndAcceleration,
    /// Velocity only: the jerk phases meet, no constant acceleration.
    Velocity,
    /// Acceleration only: no cruise.
    Acceleration,
    /// Neither: four jerk phases.
    Neither,
}

/// The phases of an S-curve: durations of jerk, constant acceleration and cruise.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Phases {
    /// Each jerk phase (s).
    pub jerk: f64,
    /// Each constant-acceleration phase (s).
    pub constant_acceleration: f64,
    /// The cruise (s).
    pub cruise: f64,
    /// Peak acceleration reached (m/s^2).
    pub peak_acceleration: f64,
    /// Peak velocity reached (m/s).
    pub peak_velocity: f64,
    /// Which limits are reached.
    pub reached: ReachedLimits,
}

impl Phases {
    /// The move's duration (s).
    pub fn duration(&self) -> f64 {
        4.0 * self.jerk + 2.0 * self.constant_acceleration + self.cruise
    }
}

impl SCurve {
    /// The phases of the time-optimal move (closed form).
    pub fn phases(&self) -> Phases {
        let (d, v, a, j) = (self.distance.abs(), self.v_max, self.a_max, self.j_max);
        // accelerating to a velocity w takes w/a + a/j when the acceleration limit is met on
        // the way (w j >= a^2), else 2 sqrt(w/j); its distance is w times that, by symmetry
        let ramp = |w: f64| {
            if w * j >= a * a {
                (a / j, w / a - a / j, a)
            } else {
                ((w / j).sqrt(), 0.0, (w * j).sqrt())
            }
        };
        let (tj, ta, ap) = ramp(v);
        let ramp_time = 2.0 * tj + ta;
        if d >= v * ramp_time {
            let reached = if ta > 0.0 {
                ReachedLimits::VelocityAndAcceleration
            } else {
                ReachedLimits::Velocity
            };
            return Phases {
                jerk: tj,
                constant_acceleration: ta,
                cruise: (d - v * ramp_time) / v,
                peak_acceleration: ap,
                peak_velocity: v,
                reached,
            };
        }
        // no cruise: the peak velocity w with d = w (w/a + a/j), if it meets the acceleration
        // limit, else d = 2 w sqrt(w/j)
        let w = 0.5 * a * (-a / j + (a * a / (j * j) + 4.0 * d / a).sqrt());
        let (w, reached) = if w * j >= a * a {
            (w, ReachedLimits::Acceleration)
        } else {
            ((0.5 * d * j.sqrt()).powf(2.0 / 3.0), ReachedLimits::Neither)
        };
        let (tj, ta, ap) = ramp(w);
        Phases {
            jerk: tj,
            constant_acceleration: ta,
            cruise: 0.0,
            peak_acceleration: ap,
            peak_velocity: w,
            reached,
        }
    }

    /// The seven phases as `(duration, jerk)` for a forward move (s, m/s^3).
    fn jerk_phases(&self) -> [(f64, f64); 7] {
        let p = self.phases();
        let j = self.j_max;
        [
            (p.jerk, j),
            (p.constant_acceleration, 0.0),
            (p.jerk, -j),
            (p.cruise, 0.0),
            (p.jerk, -j),
            (p.constant_acceleration, 0.0),
            (p.jerk, j),
        ]
    }

    /// `(position, velocity, acceleration)` at `t` (s).
    pub fn state(&self, t: f64) -> (f64, f64, f64) {
        let sign = self.distance.signum();
        match segments_state(self.jerk_phases(), t - self.start) {
            Some((x, v, a)) => (self.from + sign * x, sign * v, sign * a),
            // at rest after the move: exactly the target
            None => (self.from + self.distance, 0.0, 0.0),
        }
    }

    /// The jerk (m/s^3) on `[t, t + dt)` for small `dt`: the phase `t` starts or lies in
    /// (zero before and after the move).
    pub fn jerk(&self, t: f64) -> f64 {
        let mut left = t - self.start;
        if left < 0.0 {
            return 0.0;
        }
        for (duration, jerk) in self.jerk_phases() {
            if left < duration {
                return jerk * self.distance.signum();
            }
            left -= duration;
        }
        0.0
    }

    /// Times (s) where the jerk switches.
    pub fn switches(&self) -> Vec<f64> {
        let mut t = self.start;
        let mut out = vec![t];
        for (d, _) in self.jerk_phases() {
            if d > 0.0 {
                t += d;
                out.push(t);
            }
        }
        out
    }
}

/// `(position, velocity, acceleration)` from rest at the origin after `elapsed` (s) of
/// `segments` of `(duration, jerk)` (s, m/s^3); `None` once they are all over.
fn segments_state(
    segments: impl IntoIterator<Item = (f64, f64)>,
    elapsed: f64,
) -> Option<(f64, f64, f64)> {
    let (mut x, mut v, mut a) = (0.0, 0.0, 0.0);
    let mut left = elapsed;
    if left <= 0.0 {
        return Some((0.0, 0.0, 0.0));
    }
    for (duration, jerk) in segments {
        let tau = left.min(duration);
        x += v * tau + a * tau * tau / 2.0 + jerk * tau * tau * tau / 6.0;
        v += a * tau + jerk * tau * tau / 2.0;
        a += jerk * tau;
        left -= tau;
        if left <= 0.0 {
            return Some((x, v, a));
        }
    }
    None
}

/// A rest-to-rest move of segments of constant jerk, as a drive's setpoint generator runs
/// them: `{ kind = "jerk-segments", start = 0, from = 0, segments = [[duration, jerk], ..] }`
/// (s, m/s^3). The S-curve is the time-optimal seven of them; a planned move may have
/// others (an acceleration and a deceleration of their own lengths). It must end at rest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JerkSegments {
    /// Start time (s).
    pub start: f64,
    /// Position before the move (m).
    #[serde(default)]
    pub from: f64,
    /// `[duration (s), jerk (m/s^3)]` per segment, in order.
    pub segments: Vec<[f64; 2]>,
}

impl JerkSegments {
    /// The seven segments `+j, 0, -j, cruise, -j, 0, +j` of a move at the cruise velocity
    /// `v` (m/s) over `distance` (m, either sign) from `from` at `start`, that accelerates
    /// and then brakes each with its own `(acceleration (m/s^2), jerk (m/s^3))`. `None` when
    /// they leave no cruise (the ramps alone overshoot `distance`) or a jerk ramp is longer
    /// than its acceleration phase (`a^2 > v j`).
    pub fn trapezoidal(
        (start, from, distance): (f64, f64, f64),
        v: f64,
        halves: [(f64, f64); 2],
    ) -> Option<JerkSegments> {
        if halves
            .iter()
            .any(|&(a, j)| !(a > 0.0 && j > 0.0 && a * a <= v * j))
        {
            return None;
        }
        // each ramp from 0 to v lasts v/a + a/j; at mean velocity v/2 it covers v/2 of that
        let covered: f64 = halves.iter().map(|&(a, j)| 0.5 * v * (v / a + a / j)).sum();
        let cruise = (distance.abs() - covered) / v;
        // a NaN cruise (a limit of NaN) is no cruise either
        if cruise.is_nan() || cruise < 0.0 {
            return None;
        }
        let sign = distance.signum();
        let ramp = |(a, j): (f64, f64), first: f64| {
            [
                [a / j, first * sign * j],
                [v / a - a / j, 0.0],
                [a / j, -first * sign * j],
            ]
        };
        let mut segments = ramp(halves[0], 1.0).to_vec();
        segments.push([cruise, 0.0]);
        segments.extend(ramp(halves[1], -1.0));
        Some(JerkSegments {
            start,
            from,
            segments,
        })
    }

    /// The move's duration (s).
    pub fn duration(&self) -> f64 {
        self.segments.iter().map(|s| s[0]).sum()
    }

    /// `(position, velocity, acceleration)` at `t` (s); after the last segment, where it
    /// ended.
    pub fn state(&self, t: f64) -> (f64, f64, f64) {
        let segments = self.segments.iter().map(|s| (s[0], s[1]));
        let (x, v, a) = segments_state(segments, t - self.start).unwrap_or_else(|| {
            let (x, _, _) = self.end();
            (x, 0.0, 0.0)
        });
        (self.from + x, v, a)
    }

    /// Travel, velocity and acceleration at the end of the last segment (m, m/s, m/s^2).
    pub fn end(&self) -> (f64, f64, f64) {
        // a last segment without end, so that rounding in the sum of durations never leaves
        // the end past every segment
        let segments = self.segments.iter().map(|s| (s[0], s[1]));
        segments_state(segments.chain([(f64::INFINITY, 0.0)]), self.duration())
            .unwrap_or((0.0, 0.0, 0.0))
    }

    /// Times (s) where the jerk switches.
    pub fn switches(&self) -> Vec<f64> {
        let mut t = self.start;
        let mut out = vec![t];
        for s in &self.segments {
            if s[0] > 0.0 {
                t += s[0];
                out.push(t);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve(distance: f64, v_max: f64, a_max: f64, j_max: f64) -> SCurve {
        SCurve {
            start: 1.0,
            from: 2.0,
            distance,
            v_max,
            a_max,
            j_max,
        }
    }

    /// Checks the closed form against its own finite differences: velocity, acceleration and
    /// jerk are the derivatives of the position and of each other, the jerk is 0 or the limit, the limits hold, and
    /// the move ends at rest at the target.
    fn check_derivatives_and_limits(c: &SCurve) {
        let p = c.phases();
        let h = 1e-4;
        let switches = c.switches();
        for k in 1..2000 {
            let t = c.start + p.duration() * f64::from(k) / 2000.0;
            if switches.iter().any(|s| (s - t).abs() < 2.0 * h) {
                continue; // the differences straddle a switch of the jerk
            }
            let ((x0, v0, a0), (x1, v1, a1), (_, v, a)) =
                (c.state(t - h), c.state(t + h), c.state(t));
            assert!((v - (x1 - x0) / (2.0 * h)).abs() < 1e-6, "t {t}: v");
            assert!(
                (a - (v1 - v0) / (2.0 * h)).abs() < 1e-6,
                "t {t}: a {a} against {}",
                (v1 - v0) / (2.0 * h)
            );
            assert!(
                (c.jerk(t) - (a1 - a0) / (2.0 * h)).abs() < 1e-6,
                "t {t}: jerk {}",
                c.jerk(t)
            );
            let jerk = ((a1 - a0) / (2.0 * h)).abs();
            assert!(
                jerk < 1e-6
                    || (jerk - c.j_max).abs() < 1e-6
                    || (a1 - a0).abs() < 2.0 * h * c.j_max + 1e-9,
                "t {t}: jerk {jerk}"
            );
            assert!(
                v.abs() <= c.v_max + 1e-12 && a.abs() <= c.a_max + 1e-12,
                "t {t}: v {v}, a {a}"
            );
        }
        let (xe, ve, ae) = c.state(c.start + p.duration());
        assert!(
            (xe - c.from - c.distance).abs() < 1e-9 * c.distance.abs().max(1.0),
            "{xe}"
        );
        assert!(ve.abs() < 1e-9 && ae.abs() < 1e-9, "{ve} {ae}");
        let (xm, vm, _) = c.state(c.start + 0.5 * p.duration());
        assert!((xm - c.from - 0.5 * c.distance).abs() < 1e-9 * c.distance.abs().max(1.0));
        assert!((vm.abs() - p.peak_velocity).abs() < 1e-9);
    }

    #[test]
    fn the_duration_is_the_closed_form_time_optimal_move_in_every_case() {
        // velocity and acceleration reached: the case study's move, 13.12 s
        let c = curve(23.0, 2.5, 0.7, 2.0);
        let p = c.phases();
        assert_eq!(p.reached, ReachedLimits::VelocityAndAcceleration);
        let expected = 23.0 / 2.5 + 2.5 / 0.7 + 0.7 / 2.0;
        assert!((p.duration() - expected).abs() < 1e-12, "{}", p.duration());
        assert!((p.duration() - 13.12).abs() < 5e-3);
        check_derivatives_and_limits(&c);
        // velocity only (the jerk phases meet): T = d/v + 2 sqrt(v/j)
        let c = curve(10.0, 1.0, 5.0, 2.0);
        assert_eq!(c.phases().reached, ReachedLimits::Velocity);
        assert!((c.phases().duration() - (10.0 + 2.0 * 0.5_f64.sqrt())).abs() < 1e-12);
        check_derivatives_and_limits(&c);
        // acceleration only: T = 2 (a/j + w/a) with w the peak velocity of d = w (w/a + a/j)
        let c = curve(-3.0, 5.0, 0.7, 2.0);
        let p = c.phases();
        assert_eq!(p.reached, ReachedLimits::Acceleration);
        let w = p.peak_velocity;
        assert!((w * (w / 0.7 + 0.7 / 2.0) - 3.0).abs() < 1e-12);
        assert!((p.duration() - 2.0 * (0.7 / 2.0 + w / 0.7)).abs() < 1e-12);
        check_derivatives_and_limits(&c);
        // neither: T = 4 (d / 2j)^(1/3)
        let c = curve(0.1, 5.0, 5.0, 2.0);
        assert_eq!(c.phases().reached, ReachedLimits::Neither);
        assert!((c.phases().duration() - 4.0 * (0.1_f64 / 4.0).cbrt()).abs() < 1e-12);
        check_derivatives_and_limits(&c);
    }

    #[test]
    fn jerk_segments_of_equal_ramps_are_the_s_curve_and_unequal_ones_end_at_rest_on_target() {
        let c = curve(23.0, 2.5, 0.7, 2.0);
        let same = JerkSegments::trapezoidal((1.0, 2.0, 23.0), 2.5, [(0.7, 2.0); 2]).unwrap();
        assert!((same.duration() - c.phases().duration()).abs() < 1e-12);
        for k in 0..=1500 {
            let t = 0.5 + 15.0 * f64::from(k) / 1500.0;
            let ((x, v, a), (y, w, b)) = (c.state(t), same.state(t));
            assert!(
                (x - y).abs() < 1e-9 && (v - w).abs() < 1e-12 && (a - b).abs() < 1e-12,
                "t {t}: ({x}, {v}, {a}) against ({y}, {w}, {b})"
            );
        }
        // backwards, accelerating at 0.6 m/s^2 with jerk 1 and braking at 0.4 with jerk 0.5
        let halves = [(0.6, 1.0), (0.4, 0.5)];
        let m = JerkSegments::trapezoidal((0.0, 5.0, -20.0), 2.0, halves).unwrap();
        // each ramp covers v/2 (v/a + a/j); the cruise the rest at v
        let ramps = 0.5 * 2.0 * (2.0 / 0.6 + 0.6) + 0.5 * 2.0 * (2.0 / 0.4 + 0.8);
        let expected = (2.0 / 0.6 + 0.6) + (2.0 / 0.4 + 0.8) + (20.0 - ramps) / 2.0;
        assert!((m.duration() - expected).abs() < 1e-12, "{}", m.duration());
        let (x, v, a) = m.state(m.duration());
        assert!((x + 15.0).abs() < 1e-9 && v.abs() < 1e-12 && a.abs() < 1e-12);
        assert_eq!(m.state(m.duration() + 3.0), (x, 0.0, 0.0));
        let h = 1e-5;
        let mut peak = (0.0f64, 0.0f64, 0.0f64);
        for k in 1..4000 {
            let t = m.duration() * f64::from(k) / 4000.0;
            let ((x0, v0, _), (x1, v1, _), (_, v, a)) =
                (m.state(t - h), m.state(t + h), m.state(t));
            assert!((v - (x1 - x0) / (2.0 * h)).abs() < 1e-8, "t {t}: v");
            assert!((a - (v1 - v0) / (2.0 * h)).abs() < 1e-6, "t {t}: a");
            let half = if t < 0.5 * m.duration() { 1 } else { 2 };
            peak.0 = peak.0.max(v.abs());
            if half == 1 {
                peak.1 = peak.1.max(a.abs());
            } else {
                peak.2 = peak.2.max(a.abs());
            }
        }
        assert!((peak.0 - 2.0).abs() < 1e-12, "{peak:?}");
        assert!(
            (peak.1 - 0.6).abs() < 1e-12 && (peak.2 - 0.4).abs() < 1e-12,
            "{peak:?}"
        );
        // no cruise left, or a ramp longer than its acceleration phase
        assert_eq!(
            JerkSegments::trapezoidal((0.0, 0.0, 3.0), 2.5, [(0.7, 2.0); 2]),
            None
        );
        assert_eq!(
            JerkSegments::trapezoidal((0.0, 0.0, 30.0), 1.0, [(2.0, 2.0), (0.7, 2.0)]),
            None
        );
    }
}
