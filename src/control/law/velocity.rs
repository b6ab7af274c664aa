//! The velocity-feedback law, stepped tick by tick: feedback through a velocity servo: the drive follows the scene's setpoint `s(t)` (its
//! prescribed motion) plus a velocity correction the law commands at every tick, from the
//! drive's encoder and a strain gauge at the foot of section 1.
//!
//! At tick `k` the law reads `u_k` (`vehicle`, m) and `kappa_k` (`kappa_1_0`, 1/m) and commands
//!
//! ```text
//! v_{k+1} = sat( g(a) h_k - k_p (u_k - s(t_k)) )
//! g(a)    = 2 zeta_d omega_1(a) r(a)
//! e_k     = kappa_k - c(a) s''(t_k)
//! h_k     = w (h_{k-1} + e_k - e_{k-1}),  w = tau_w / (tau_w + T)
//! ```
//!
//! bounded to `+-v_max` and changed by at most `a_max T` a tick. The drive interpolates its
//! velocity setpoint linearly over a tick (as drives in cyclic velocity mode do), so the
//! correction's acceleration `(v_{k+1} - v_k) / T` holds over the tick after the command:
//! one tick of computation delay, one of interpolation. `r(a)` is `tip_rel` per `kappa_1_0` in
//! the first elastic mode with the vehicle held, `omega_1(a)` that mode's angular frequency:
//! the correction's acceleration is then `2 zeta_d omega_1` times the tip's rate in that mode,
//! the base excitation that adds the damping ratio `zeta_d` to a tip mass on a spring (the
//! force-driven strain-rate law of [`super::strain`] is the same idea one derivative up). The
//! proportional loop `k_p` (a third of the lowest first mode's angular frequency) brings the
//! vehicle back to the setpoint. `c(a)` is the curvature the held structure takes at rest
//! under a unit vehicle acceleration: the law acts on the curvature's departure from the
//! quasi-static bending the setpoint's own acceleration `s''` causes, so that a move that
//! excites no vibration draws no correction (and no offset to win back after it). `h` is that
//! departure through a washout (a first-order
//! high-pass of time constant `tau_w`, the longest first-mode period: 9 degrees of
//! phase at the first mode): a telescope at rest may stay bent (an upper section leaning in
//! its guide under gravity), and a law on the curvature itself would hold the vehicle off
//! its target by `g kappa_rest / k_p`.

use crate::control::file::velocity::VelocityFeedback;
use crate::control::law::sampled::SampledController;
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
        let positions = file.scheduled_positions();
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
        let (i, j, w) = crate::control::law::schedule::bracket(&self.positions, a);
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
