//! The velocity-feedback law, stepped tick by tick.

use super::file::VelocityFeedback;
use crate::control::sampled::SampledController;
use telescopic_runtime::Profile;

/// The law of a velocity-feedback file, ready to step: allocation-free per tick.
pub struct VelocityController {
    file: VelocityFeedback,
    /// The scheduled positions of the points.
    positions: Vec<f64>,
    /// The setpoint `s(t)` (m): the scene's prescribed motion.
    setpoint: Profile,
    period: f64,
    /// The washout's weight per tick.
    washout: f64,
    /// The previous tick's departure from the quasi-static curvature (1/m), once there is
    /// one, and the washed-out departure.
    curvature: (Option<f64>, f64),
    /// The previous command (m/s).
    last: f64,
}

impl VelocityController {
    /// The law of `file` around the setpoint `setpoint`.
    pub fn new(file: &VelocityFeedback, setpoint: Profile) -> Self {
        let positions = match file.scheduled_index() {
            Some(i) => file.points.iter().map(|p| p.positions[i]).collect(),
            None => vec![0.0; file.points.len()],
        };
        let period = 1.0 / file.rate_hz;
        VelocityController {
            positions,
            setpoint,
            period,
            washout: file.washout_time_constant_s / (file.washout_time_constant_s + period),
            curvature: (None, 0.0),
            last: 0.0,
            file: file.clone(),
        }
    }
}

impl SampledController for VelocityController {
    fn step(&mut self, t: f64, y: &[f64], a: f64) -> f64 {
        let (u, kappa) = (y[0], y[1]);
        let f = &self.file;
        let (i, j, w) = crate::control::schedule::bracket(&self.positions, a);
        let between = |x: f64, y: f64| x + w * (y - x);
        let gain = between(f.points[i].gain_m2_per_s, f.points[j].gain_m2_per_s);
        let c = between(
            f.points[i].curvature_per_acceleration,
            f.points[j].curvature_per_acceleration,
        );
        let (s, _, s_acceleration) = self.setpoint.state(t);
        // the departure from the quasi-static bending of the setpoint's acceleration
        let departure = kappa - c * s_acceleration;
        let (previous, washed) = self.curvature;
        let washed = previous.map_or(0.0, |p| self.washout * (washed + departure - p));
        let wanted = gain * washed - f.position_gain_per_s * (u - s);
        if !wanted.is_finite() {
            // a non-finite measurement (a failed sensor) holds the last command and leaves
            // the filter's state as it was: NaN must reach neither the drive nor the state
            return self.last;
        }
        self.curvature = (Some(departure), washed);
        let step = f.acceleration_limit_m_per_s2 * self.period;
        // the bounds are finite and ordered (the file's limits are checked, `last` is a
        // past command), so `clamp` cannot panic
        let v = wanted
            .clamp(-f.velocity_limit_m_per_s, f.velocity_limit_m_per_s)
            .clamp(self.last - step, self.last + step);
        self.last = v;
        v
    }
}
