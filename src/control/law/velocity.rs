//! The velocity-feedback law, stepped tick by tick: feedback through a velocity servo. The
//! drive follows the scene's setpoint `s(t)` (its prescribed motion) plus a velocity
//! correction the law commands at every tick, from the drive's encoder and a strain gauge at
//! the foot of section 1.
//!
//! The law is a state feedback on the first mode and the vehicle, with an observer of the
//! mode. In the first mode (vehicle held) the tip moves by `y = r kappa` and obeys
//! `y'' + w^2 y = -Gamma a_base`, where `w = 2 pi f_1(a)`, `r(a)` is `tip_rel` per `kappa_1_0`
//! and `Gamma = -r c w^2` follows from `c(a)`, the curvature under a unit vehicle
//! acceleration at rest. At tick `k` the law reads `u_k` (`vehicle`, m) and `kappa_k`
//! (`kappa_1_0`, 1/m):
//!
//! ```text
//! observer (one Euler step of T): m = r kappa_k, e = m - (y^ + b^)
//!   y^' = w^ + l1 e,  w^' = -w^2 y^ - Gamma (s'' + a_c) + l2 e,  b^' = l3 e
//! the mode's departure from the setpoint's quasi-static bending:
//!   y_d = y^ - r c s'',  w_d = w^ - r c s'''
//! a_c = -(k1 (u_k - s) + k2 v_k + k3 y_d + k4 w_d),  v_{k+1} = v_k + T a_c
//! ```
//!
//! with `a_c` bounded to `+-a_max` and `v` to `+-v_max`; `v_k` is the correction commanded
//! last. The gains place the poles at every scheduled position: the closed loop of the
//! vehicle and the mode, `(s^2 + 2 zeta w s + w^2)(s + p_1 w)(s + p_2 w)`, and the observer's,
//! `(s^2 + 2 zeta_o w_o s + w_o^2)(s + p_b w)` with `w_o = q w`. The bias `b^` is the curvature
//! the structure keeps at rest (an upper section leaning in its guide under gravity), so a
//! telescope that rests bent draws no correction and leaves the vehicle on its target. The
//! vehicle's position and velocity are states of the loop, so the vehicle returns at the
//! rate of its own poles once the mode is damped. The drive interpolates its velocity
//! setpoint linearly over a tick (as drives in cyclic velocity mode do): one tick of
//! computation delay, one of interpolation.
//!
//! A file may hold design points at several loads (`tables`): the law is told the load the
//! machine weighs and interpolates `f_1`, `r` and `c` along the position in the two tables
//! around it, then between them; a file of one table is used whatever the load.

use crate::control::file::velocity::{VelocityFeedback, VelocityPoint};
use crate::control::law::sampled::SampledController;
use crate::{Error, Result};
use telescopic_runtime::Profile;

/// The law's gains at one scheduled position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LawGains {
    /// The first mode's angular frequency `w` (rad/s).
    pub omega: f64,
    /// Its participation `Gamma = -r c w^2` (tip per vehicle acceleration times `w^2`).
    pub gamma: f64,
    /// The feedback gains on the vehicle's error (1/s^2), the correction's velocity (1/s),
    /// the mode's departure (1/s^2 per m of tip) and its rate (1/s per m/s of tip).
    pub k: [f64; 4],
    /// The observer's gains on its innovation (1/s, 1/s^2, 1/s).
    pub l: [f64; 3],
}

impl LawGains {
    /// The gains that place the poles of `file` for a first mode of `f1` Hz with tip per
    /// curvature `r` and curvature per acceleration `c`.
    ///
    /// The loop of the vehicle `[X, V]` and the mode `[y, y']` under `a = -k . state` has the
    /// poles placed: the vehicle's two real ones and the mode's pair at `zeta`.
    ///
    /// ```
    /// # use telescopic::control::design::velocity::{VelocityDesign, design_velocity_feedback};
    /// # use telescopic::control::law::velocity::LawGains;
    /// # let scene = telescopic::Scene::load("scenes/case-study-no-clearance.toml".as_ref(), &[])?;
    /// # let curve = telescopic_runtime::SCurve { start: 0.0, from: 0.0, distance: 23.0, v_max: 2.5, a_max: 0.7, j_max: 2.0 };
    /// # let scene = telescopic::plan::moving_scene(&scene, &telescopic::plan::candidates::unshaped(&curve).profile, 20.0)?;
    /// let file = design_velocity_feedback(&scene, &VelocityDesign::default())?;
    /// let p = &file.tables[0].points[0];
    /// let g = LawGains::place(&file, p.first_mode_hz, p.tip_per_curvature_m2, p.curvature_per_acceleration);
    /// let k = nalgebra::RowDVector::from_row_slice(&g.k);
    /// let b = nalgebra::DVector::from_column_slice(&[0.0, 1.0, 0.0, -g.gamma]);
    /// let mut a = nalgebra::DMatrix::<f64>::zeros(4, 4);
    /// (a[(0, 1)], a[(2, 3)], a[(3, 2)]) = (1.0, 1.0, -g.omega * g.omega);
    /// let closed = a - &b * &k;
    /// let poles = closed.complex_eigenvalues();
    /// let real = |p: f64| poles.iter().any(|s| (s.re + p * g.omega).abs() < 1e-6 * g.omega);
    /// assert!(real(file.vehicle_poles_per_mode[0]) && real(file.vehicle_poles_per_mode[1]));
    /// let pair = poles.iter().find(|s| s.im > 0.0).unwrap();
    /// assert!((pair.norm() - g.omega).abs() < 1e-6 * g.omega);
    /// assert!((-pair.re / pair.norm() - file.added_damping).abs() < 1e-6);
    /// # Ok::<(), telescopic::Error>(())
    /// ```
    pub fn place(file: &VelocityFeedback, f1: f64, r: f64, c: f64) -> Self {
        let w = std::f64::consts::TAU * f1;
        let w2 = w * w;
        let gamma = -r * c * w2;
        // (s^2 + a1 s + w^2)(s^2 + b1 s + b0) = s^4 + d3 s^3 + d2 s^2 + d1 s + d0, matched to
        // s^4 + (k2 - Gamma k4) s^3 + (k1 + w^2 - Gamma k3) s^2 + k2 w^2 s + k1 w^2
        let a1 = 2.0 * file.added_damping * w;
        let [p1, p2] = file.vehicle_poles_per_mode.map(|p| p * w);
        let (b1, b0) = (p1 + p2, p1 * p2);
        let (d3, d2, d1, d0) = (a1 + b1, w2 + a1 * b1 + b0, a1 * b0 + w2 * b1, w2 * b0);
        let (k1, k2) = (d0 / w2, d1 / w2);
        let k = [k1, k2, (k1 + w2 - d2) / gamma, (k2 - d3) / gamma];
        // the observer's error: s^3 + (l1 + l3) s^2 + (w^2 + l2) s + l3 w^2
        let wo = file.observer_frequency_per_mode * w;
        let pb = file.observer_bias_pole_per_mode * w;
        let zo = file.observer_damping;
        let (e2, e1, e0) = (
            2.0 * zo * wo + pb,
            wo * wo + 2.0 * zo * wo * pb,
            wo * wo * pb,
        );
        let l3 = e0 / w2;
        let l = [e2 - l3, e1 - w2, l3];
        LawGains {
            omega: w,
            gamma,
            k,
            l,
        }
    }
}

/// The observer's estimate: the tip in the first mode, its rate, and the tip the curvature
/// at rest stands for (m, m/s, m).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Estimate {
    tip: f64,
    rate: f64,
    bias: f64,
}

/// The law of a velocity-feedback file, ready to step: allocation-free per tick.
pub struct VelocityController {
    file: VelocityFeedback,
    /// The scheduled positions of the points.
    positions: Vec<f64>,
    /// The tables around the load the law is told and the weight of the second.
    load: (usize, usize, f64),
    /// The setpoint `s(t)` (m): the scene's prescribed motion.
    setpoint: Profile,
    period: f64,
    /// The observer's estimate, once there is one.
    estimate: Option<Estimate>,
    /// The setpoint's acceleration at the last tick (m/s^2).
    last_setpoint_acceleration: f64,
    /// The correction's acceleration over the last tick (m/s^2).
    last_acceleration: f64,
    /// The previous command (m/s).
    last: f64,
}

impl VelocityController {
    /// The law of `file` around the setpoint `setpoint`, carrying a load of `load_kg` (kg, as
    /// the machine weighs it; clamped to the tables' loads).
    ///
    /// # Errors
    /// [`Error::Input`] for a load that is not a finite number of kilograms or a file
    /// without design points or with tables of different lengths (`check_fits` refuses
    /// those too, with the field's rule).
    pub fn new(file: &VelocityFeedback, setpoint: Profile, load_kg: f64) -> Result<Self> {
        crate::control::file::velocity::check_weighed_load(load_kg)
            .map_err(|rule| Error::input("measured load", rule))?;
        let count = file.tables.first().map_or(0, |t| t.points.len());
        if count == 0 || file.tables.iter().any(|t| t.points.len() != count) {
            return Err(Error::input(
                "velocity feedback `tables`",
                "must be one or more tables of the same number of design points, one or more",
            ));
        }
        let mut points = file.tables.iter().flat_map(|t| &t.points);
        if let Some(i) = file.scheduled_index()
            && points.any(|p| p.positions.len() <= i)
        {
            return Err(Error::input(
                "velocity feedback `schedule_parameter`",
                "must name a telescopic position every design point has",
            ));
        }
        Ok(VelocityController {
            positions: file.scheduled_positions(),
            load: crate::control::law::schedule::bracket(&file.loads(), load_kg),
            setpoint,
            period: 1.0 / file.rate_hz,
            estimate: None,
            last_setpoint_acceleration: 0.0,
            last_acceleration: 0.0,
            last: 0.0,
            file: file.clone(),
        })
    }

    /// The first mode's `(f_1, r, c)` at the scheduled position `a` and the law's load,
    /// interpolated along the position in the two tables around the load, then between them.
    fn scheduled(&self, a: f64) -> (f64, f64, f64) {
        let (i, j, w) = crate::control::law::schedule::bracket(&self.positions, a);
        let (low, high, w_load) = self.load;
        let tables = &self.file.tables;
        let at = |quantity: fn(&VelocityPoint) -> f64| {
            let along = |t: usize| {
                let points = &tables[t].points;
                let (x, y) = (quantity(&points[i]), quantity(&points[j]));
                x + w * (y - x)
            };
            let (x, y) = (along(low), along(high));
            x + w_load * (y - x)
        };
        (
            at(|p| p.first_mode_hz),
            at(|p| p.tip_per_curvature_m2),
            at(|p| p.curvature_per_acceleration),
        )
    }
}

/// The observer's estimate one tick of `period` on from `e`, seeing the tip `measured` (m)
/// with the base accelerated at `base` (m/s^2).
fn observe(e: Estimate, g: &LawGains, measured: f64, base: f64, period: f64) -> Estimate {
    let innovation = measured - (e.tip + e.bias);
    let [l1, l2, l3] = g.l;
    Estimate {
        tip: e.tip + period * (e.rate + l1 * innovation),
        rate: e.rate + period * (-g.omega * g.omega * e.tip - g.gamma * base + l2 * innovation),
        bias: e.bias + period * l3 * innovation,
    }
}

impl SampledController for VelocityController {
    fn step(&mut self, t: f64, y: &[f64], a: f64) -> f64 {
        let (u, kappa) = (y[0], y[1]);
        let (f1, r, c) = self.scheduled(a);
        let gains = LawGains::place(&self.file, f1, r, c);
        let (s, _, s_acceleration) = self.setpoint.state(t);
        let measured = r * kappa;
        // before the first tick the structure rests: what the gauge reads is its bias
        let (estimate, jerk) = match self.estimate {
            None => (
                Estimate {
                    tip: 0.0,
                    rate: 0.0,
                    bias: measured,
                },
                0.0,
            ),
            Some(e) => {
                let base = s_acceleration + self.last_acceleration;
                (
                    observe(e, &gains, measured, base, self.period),
                    (s_acceleration - self.last_setpoint_acceleration) / self.period,
                )
            }
        };
        // the mode's departure from the bending the setpoint's own acceleration causes
        let quasi_static = r * c;
        let (tip, rate) = (
            estimate.tip - quasi_static * s_acceleration,
            estimate.rate - quasi_static * jerk,
        );
        let [k1, k2, k3, k4] = gains.k;
        let wanted = -(k1 * (u - s) + k2 * self.last + k3 * tip + k4 * rate);
        let f = &self.file;
        let finite = [wanted, estimate.tip, estimate.rate, estimate.bias];
        if !finite.iter().all(|v| v.is_finite()) {
            // a non-finite measurement (a failed sensor) holds the last command and leaves
            // the law's state as it was: NaN must reach neither the drive nor the state
            return self.last;
        }
        self.estimate = Some(estimate);
        self.last_setpoint_acceleration = s_acceleration;
        // the bounds are finite and ordered (the file's limits are checked), so `clamp`
        // cannot panic
        let acceleration = wanted.clamp(
            -f.acceleration_limit_m_per_s2,
            f.acceleration_limit_m_per_s2,
        );
        let v = (self.last + acceleration * self.period)
            .clamp(-f.velocity_limit_m_per_s, f.velocity_limit_m_per_s);
        self.last_acceleration = (v - self.last) / self.period;
        self.last = v;
        v
    }
}
