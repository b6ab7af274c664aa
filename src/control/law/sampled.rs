//! The controller as a machine runs it: sampled at a fixed rate, from the outputs its sensors
//! measure (with noise), through a discrete Kalman filter, with a zero-order hold on the force,
//! one sample of computation delay and saturation at the force limit.
//!
//! At tick `k` (time `t_k = t_0 + k T`) the controller reads the measurements `y_k` and the
//! scheduled position `a_k`, and computes the force applied from `t_{k+1}` on:
//!
//! ```text
//! x_hat_{k+1} = Ad x_hat_k + Bd u_k + L (y_k - C x_hat_k)          (predictor form)
//! u_{k+1}     = sat( F_ff(t_{k+1}) - K (x_hat_{k+1} - x_ref(t_{k+1})), +-F_max )
//! ```
//!
//! `Ad`, `Bd` are the zero-order-hold discretization of the closed-contact linear model at
//! each design point, `L` the steady Kalman gain of the filter's discrete Riccati equation
//! (solved by the structured doubling algorithm), `K` the design point's LQR gain; all are
//! interpolated linearly in the scheduled position between design points, as the continuous
//! law's gains are.

use crate::OptionName;
use crate::control::file::schema::{Controller, DiscretePoint, SampledDesign};
use crate::io::rows::{from_rows, to_rows};
use crate::{Error, Result};
use telescopic_runtime::nalgebra::{DMatrix, DVector};
use telescopic_runtime::{ContactMode, Lpv, Model, Output, Sensor};

/// Default controller rate (Hz).
pub const DEFAULT_RATE_HZ: f64 = 1000.0;

/// Default measurement noise (standard deviation, in the output's unit) of a sensor reading
/// the output `sensor` (an output's name).
pub fn default_noise(sensor: &str) -> f64 {
    match Output::parse(sensor) {
        // 1/m: 1 microstrain on a 0.2 m section
        Some(Output::Sensor(Sensor::FootCurvature)) => 1e-5,
        // m/s^2: an industrial accelerometer
        Some(Output::Sensor(Sensor::LoadAcceleration)) => 0.01,
        // m: an incremental encoder, a laser distance sensor
        _ => 1e-4,
    }
}

/// The extended filter's default process-noise floor (per period, state units squared): below
/// some 3e-11 the filter grows overconfident in the motion it cannot see and the loop chatters
/// or diverges on case-study (docs/control.md).
pub const DEFAULT_PROCESS_NOISE_FLOOR: f64 = 1e-10;

/// The steady predictor-form Kalman gain `L = Ad P C' (C P C' + R)^-1` with `P` the
/// stabilizing solution of the filter's discrete Riccati equation, by the structured doubling
/// algorithm (quadratic convergence; hand-written: nalgebra has no discrete Riccati solver).
///
/// # Errors
/// [`Error::Analysis`] when a step cannot be solved or it does not converge.
pub fn kalman_gain(
    ad: &DMatrix<f64>,
    c: &DMatrix<f64>,
    q: &DMatrix<f64>,
    r: &DMatrix<f64>,
) -> Result<DMatrix<f64>> {
    let n = ad.nrows();
    let fail = |why: &str| Error::Analysis(format!("discrete Kalman filter: {why}"));
    let r_inv = r
        .clone()
        .try_inverse()
        .ok_or_else(|| fail("R is singular"))?;
    // the filter's equation is the control one of (Ad', C')
    let mut a_k = ad.transpose();
    let mut g = c.transpose() * &r_inv * c;
    let mut h = q.clone();
    let identity = DMatrix::<f64>::identity(n, n);
    for _ in 0..100 {
        let w = (&identity + &g * &h)
            .lu()
            .try_inverse()
            .ok_or_else(|| fail("I + G H is singular"))?;
        let a_next = &a_k * &w * &a_k;
        let g_next = &g + &a_k * &w * &g * a_k.transpose();
        let h_next = &h + a_k.transpose() * &h * &w * &a_k;
        let change = (&h_next - &h).norm() / h_next.norm().max(f64::MIN_POSITIVE);
        (a_k, g, h) = (a_next, g_next, h_next);
        if change < 1e-13 {
            let p = (&h + h.transpose()) * 0.5;
            let s = c * &p * c.transpose() + r;
            let s_inv = s
                .try_inverse()
                .ok_or_else(|| fail("C P C' + R is singular"))?;
            return Ok(ad * &p * c.transpose() * s_inv);
        }
        if !change.is_finite() {
            break;
        }
    }
    Err(fail(
        "the doubling iteration did not converge (is the model detectable from these sensors?)",
    ))
}

/// Designs the sampled output-feedback part of `controller` on `model` (closed contacts at
/// each design point): the discrete model, the measurement rows of `sensors` and the Kalman
/// gain with measurement noise `noise` and a force disturbance `force_noise` (N).
///
/// # Errors
/// [`Error::Option`] for unknown sensors or a bad rate; [`Error::Analysis`] for a filter that
/// cannot be designed.
pub fn design_sampled(
    controller: &Controller,
    model: &dyn Model,
    sensors: &[String],
    noise: &[f64],
    force_noise: f64,
    rate_hz: f64,
) -> Result<SampledDesign> {
    check_rate(rate_hz)?;
    let lpv = Lpv::new(model, ContactMode::Closed).map_err(Error::from)?;
    let rows: Vec<usize> = sensors
        .iter()
        .map(|s| {
            lpv.outputs()
                .iter()
                .position(|o| &o.name == s)
                .ok_or_else(|| {
                    let known: Vec<&str> = lpv.outputs().iter().map(|o| o.name.as_str()).collect();
                    Error::option(
                        OptionName::Sensors,
                        format!(
                            "`{s}` is not an output of the scene; its outputs: {}",
                            known.join(", ")
                        ),
                    )
                })
        })
        .collect::<Result<_>>()?;
    let period = 1.0 / rate_hz;
    let r = DMatrix::from_diagonal(&DVector::from_iterator(
        noise.len(),
        noise.iter().map(|s| s * s),
    ));
    let npos = model.params().positions.len();
    let mut points = Vec::with_capacity(controller.schedule.len());
    for point in &controller.schedule {
        let linear = lpv
            .at(&point.positions, &vec![0.0; npos])
            .map_err(Error::from)?;
        let (ad, bd) = crate::linear::zero_order_hold(&linear.a, &linear.b, period);
        let c = DMatrix::from_fn(rows.len(), linear.a.ncols(), |i, j| linear.c[(rows[i], j)]);
        // a measured output that feeds through the input (acc_load) is measured before the
        // new force acts: its D term is part of the one-sample delay
        let q = &bd * bd.transpose() * (force_noise * force_noise)
            + DMatrix::identity(ad.nrows(), ad.nrows()) * 1e-18;
        let l = kalman_gain(&ad, &c, &q, &r)?;
        points.push(DiscretePoint {
            ad: to_rows(&ad),
            bd: to_rows(&bd),
            c: to_rows(&c),
            l: to_rows(&l),
        });
    }
    Ok(SampledDesign {
        rate_hz,
        sensors: sensors.to_vec(),
        noise: noise.to_vec(),
        force_noise,
        seed: 1,
        estimator: crate::control::file::schema::Estimator::Linear,
        process_noise_floor: None,
        points,
        strain_rate: None,
        model: None,
    })
}

/// Checks a controller rate (Hz): 1 to 1e6.
///
/// # Errors
/// [`Error::Option`] naming `DesignOptions::rate_hz`.
pub fn check_rate(rate_hz: f64) -> Result<()> {
    if !(rate_hz.is_finite() && (1.0..=1e6).contains(&rate_hz)) {
        return Err(Error::option(
            OptionName::RateHz,
            format!("must be 1 to 1e6 Hz (got {rate_hz})"),
        ));
    }
    Ok(())
}

/// A sampled controller, stepped by the caller at every tick: the in-library one
/// ([`DiscreteController`]) or another implementation of the same law (the emitted C).
pub trait SampledController {
    /// One tick at `t` (s): the measurements `y` (in the order of the sensors) and the
    /// scheduled position `a` (m); returns the force (N) to apply from the next tick on.
    fn step(&mut self, t: f64, y: &[f64], a: f64) -> f64;
}

/// One design point's matrices, ready to use.
struct PointMatrices {
    ad: DMatrix<f64>,
    bd: DMatrix<f64>,
    c: DMatrix<f64>,
    l: DMatrix<f64>,
    /// The LQR gain on the full state.
    k: DVector<f64>,
}

/// The sampled law of a controller file, ready to step: allocation-free per tick.
pub struct DiscreteController {
    points: Vec<PointMatrices>,
    positions: Vec<f64>,
    reference: crate::control::law::schedule::Reference,
    feedforward: telescopic_runtime::Profile,
    period: f64,
    limit: f64,
    x_hat: DVector<f64>,
    scratch: DVector<f64>,
    innovation: Vec<f64>,
    u: f64,
}

impl DiscreteController {
    /// The controller of `file` (which must have a sampled part and an LQR) over `[start,
    /// end]` s.
    ///
    /// # Errors
    /// [`Error::Option`] naming what the file lacks.
    pub fn new(file: &Controller, start: f64, end: f64) -> Result<Self> {
        let sampled = file.sampled_part()?;
        if !file.kind.has_lqr() || sampled.points.len() != file.schedule.len() {
            return Err(Error::input(
                "controller `sampled.points`",
                "needs one discrete point per design point and an LQR gain",
            ));
        }
        let mut points = Vec::with_capacity(sampled.points.len());
        for (p, s) in sampled.points.iter().zip(&file.schedule) {
            let m = |rows: &[Vec<f64>], name: &str| {
                from_rows(rows, None)
                    .map_err(|e| Error::input(format!("controller `sampled.{name}`"), e))
            };
            let k = DVector::from_column_slice(&s.k[0]);
            points.push(PointMatrices {
                ad: m(&p.ad, "Ad")?,
                bd: m(&p.bd, "Bd")?,
                c: m(&p.c, "C")?,
                l: m(&p.l, "L")?,
                k,
            });
        }
        let n = points[0].ad.nrows();
        Ok(DiscreteController {
            positions: file.schedule_positions(),
            points,
            reference: crate::control::law::schedule::reference(file, start, end),
            feedforward: file.feedforward.clone(),
            period: 1.0 / sampled.rate_hz,
            limit: file.force_limit_n,
            x_hat: DVector::zeros(n),
            scratch: DVector::zeros(n),
            innovation: vec![0.0; sampled.sensors.len()],
            u: 0.0,
        })
    }

    /// The two design points around `a` and the weight of the second.
    fn weights(&self, a: f64) -> (usize, usize, f64) {
        crate::control::law::schedule::bracket(&self.positions, a)
    }
}

impl SampledController for DiscreteController {
    fn step(&mut self, t: f64, y: &[f64], a: f64) -> f64 {
        let (i, j, w) = self.weights(a);
        let n = self.x_hat.len();
        let (pi, pj) = (&self.points[i], &self.points[j]);
        // the filter runs on the nearest design point's discrete model: the entries of
        // exp(A T) of the contact modes (far above the Nyquist rate) vary too fast with the
        // position to interpolate; the state is physical, so switching points keeps it
        let near = if w < 0.5 { pi } else { pj };
        // x_hat <- Ad x_hat + Bd u + L (y - C x_hat), each matrix interpolated entrywise
        for (s, &ys) in y.iter().enumerate() {
            let mut predicted = 0.0;
            for c in 0..n {
                predicted += near.c[(s, c)] * self.x_hat[c];
            }
            self.innovation[s] = ys - predicted;
        }
        for r in 0..n {
            let mut v = 0.0;
            for c in 0..n {
                v += near.ad[(r, c)] * self.x_hat[c];
            }
            v += near.bd[(r, 0)] * self.u;
            for (s, e) in self.innovation.iter().enumerate() {
                v += near.l[(r, s)] * e;
            }
            self.scratch[r] = v;
        }
        std::mem::swap(&mut self.x_hat, &mut self.scratch);
        self.u = self.law(t, a);
        self.u
    }
}

impl DiscreteController {
    /// The saturated LQR force for the next tick after `t` on the estimate `x_hat`.
    fn law(&self, t: f64, a: f64) -> f64 {
        let (i, j, w) = self.weights(a);
        let lerp = |x: f64, z: f64| x + w * (z - x);
        let (pi, pj) = (&self.points[i], &self.points[j]);
        let n = self.x_hat.len();
        let next = t + self.period;
        let (u_ref, v_ref) = self.reference.at(next);
        let mut feedback = 0.0;
        for m in 0..n {
            let e = match m {
                0 => self.x_hat[0] - u_ref,
                _ if m == n / 2 => self.x_hat[m] - v_ref,
                _ => self.x_hat[m],
            };
            feedback += lerp(pi.k[m], pj.k[m]) * e;
        }
        let f = self.feedforward.value(next) - feedback;
        f.clamp(-self.limit, self.limit)
    }

    /// The law of [`DiscreteController::step`] on another estimator's state `x` (the
    /// extended filter's), for the next tick after `t` at scheduled position `a`.
    pub fn force_at(&mut self, t: f64, x: &[f64], a: f64) -> f64 {
        self.x_hat.copy_from_slice(x);
        self.law(t, a)
    }
}
