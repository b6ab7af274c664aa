//! An estimator that knows the clearance: an extended Kalman filter whose prediction runs
//! the nonlinear model itself (contact law included) over each controller period, and whose
//! covariance follows the exact Jacobian of the contact state the estimate is in. The model
//! is the design scene's, recorded in the controller file
//! ([`crate::control::law::estimator_model::EstimatorModel`]), not the plant's. The measurements it takes
//! are linear in the coordinates (`vehicle`, `tip_rel`, `top1_rel`, `kappa_1_0`).
//!
//! Every step is a fixed sequence of plain loops ([`crate::control::law::small_dense`]) that the emitted C
//! ([`crate::control::emit::emit_c`]) repeats operation for operation.

use crate::control::file::schema::Controller;
use crate::control::law::estimator_model::PreparedEstimatorModel;
use crate::control::law::sampled::SampledController;
use crate::control::law::small_dense::{exponential, invert_spd, multiply, multiply_transposed};
use crate::{Error, Result};
use telescopic_runtime::{Output, Sensor};

/// Substeps of the prediction's RK4 per controller period: with 20 at 1 kHz the step is
/// 50 us, `h omega` = 1.1 for the 3.6 kHz contact mode, inside RK4's stability limit of 2.8.
pub const SUBSTEPS: usize = 20;

/// The filter's initial covariance: this times the identity (the plant starts at rest).
pub const INITIAL_COVARIANCE: f64 = 1e-8;

/// The extended Kalman filter with the controller's LQR law on its estimate.
pub struct ExtendedKalman {
    model: PreparedEstimatorModel,
    /// Measurement rows (`sensors x 2 dof`), row-major.
    c: Vec<f64>,
    /// Measurement noise covariance (`sensors x sensors`).
    r: Vec<f64>,
    /// Process noise per period (`2 dof x 2 dof`).
    q: Vec<f64>,
    x: Vec<f64>,
    p: Vec<f64>,
    law: crate::control::law::sampled::DiscreteController,
    period: f64,
    u: f64,
    scratch: Scratch,
}

/// The per-tick work arrays, allocated once.
struct Scratch {
    innovation: Vec<f64>,
    pc: Vec<f64>,
    s: Vec<f64>,
    s_inv: Vec<f64>,
    factor: Vec<f64>,
    gain: Vec<f64>,
    gain_r: Vec<f64>,
    keep: Vec<f64>,
    m1: Vec<f64>,
    m2: Vec<f64>,
    m3: Vec<f64>,
    rk: [Vec<f64>; 6],
}

/// The sampled part's checks shared by the filter and its C emission: the part itself and
/// sensors linear in the coordinates.
pub(crate) fn sampled_of(
    file: &Controller,
) -> Result<&crate::control::file::schema::SampledDesign> {
    let sampled = file.sampled_part()?;
    let load_acceleration = Output::Sensor(Sensor::LoadAcceleration);
    if let Some(s) = sampled
        .sensors
        .iter()
        .find(|s| Output::parse(s) == Some(load_acceleration))
    {
        return Err(Error::input(
            "controller `sampled.sensors`",
            format!("the extended filter takes outputs linear in the coordinates, not `{s}`"),
        ));
    }
    Ok(sampled)
}

/// The measurement rows (`sensors x w`, row-major) of the first design point: the filter's
/// `C`, checked against the `w` states of its model.
pub(crate) fn measurement_rows(
    sampled: &crate::control::file::schema::SampledDesign,
    w: usize,
) -> Result<Vec<f64>> {
    let m = sampled.sensors.len();
    match sampled.points.first() {
        Some(p) if p.c.len() == m && p.c.iter().all(|r| r.len() == w) => {
            Ok(p.c.iter().flatten().copied().collect())
        }
        _ => Err(Error::input(
            "controller `sampled.points[0].C`",
            format!("must be {m} x {w} (sensors x the recorded model's states)"),
        )),
    }
}

/// The measurement noise covariance (`sensors x sensors`, row-major): the noise levels
/// squared on the diagonal.
pub(crate) fn measurement_noise(sampled: &crate::control::file::schema::SampledDesign) -> Vec<f64> {
    let m = sampled.noise.len();
    let mut r = vec![0.0; m * m];
    for (i, s) in sampled.noise.iter().enumerate() {
        r[i * m + i] = s * s;
    }
    r
}

/// The process noise per period (`2 dof x 2 dof`, row-major): the force disturbance through
/// the accelerations over one period, plus the floor on every state.
pub(crate) fn process_noise(
    sampled: &crate::control::file::schema::SampledDesign,
    response: &[f64],
) -> Vec<f64> {
    let n = response.len();
    let period = 1.0 / sampled.rate_hz;
    let mut bd = vec![0.0; 2 * n];
    for i in 0..n {
        bd[i] = 0.5 * period * period * response[i];
        bd[n + i] = period * response[i];
    }
    // the floor keeps the filter from growing certain of the motion it cannot see (the
    // upper section inside its band): without it the loop diverges with clearance
    let floor = sampled
        .process_noise_floor
        .unwrap_or(crate::control::law::sampled::DEFAULT_PROCESS_NOISE_FLOOR);
    let variance = sampled.force_noise * sampled.force_noise;
    let mut q = vec![0.0; 4 * n * n];
    for i in 0..2 * n {
        for j in 0..2 * n {
            q[i * 2 * n + j] = bd[i] * bd[j] * variance + if i == j { floor } else { 0.0 };
        }
    }
    q
}

impl ExtendedKalman {
    /// The filter of `file`'s sampled part over `[start, end]` s, on the model the file
    /// records.
    ///
    /// # Errors
    /// [`Error::Input`] for sensors that are not linear in the coordinates, or a recorded
    /// model that is missing or does not fit.
    pub fn new(file: &Controller, start: f64, end: f64) -> Result<Self> {
        let sampled = sampled_of(file)?;
        let record = sampled.model.as_ref().ok_or_else(|| {
            Error::input(
                "controller `sampled.model`",
                "is missing: the extended filter predicts with the model its file records",
            )
        })?;
        let model = PreparedEstimatorModel::new(record)?;
        let w = 2 * model.dof();
        let m = sampled.sensors.len();
        let mut p = vec![0.0; w * w];
        for i in 0..w {
            p[i * w + i] = INITIAL_COVARIANCE;
        }
        let matrix = || vec![0.0; w * w];
        Ok(ExtendedKalman {
            c: measurement_rows(sampled, w)?,
            r: measurement_noise(sampled),
            q: process_noise(sampled, model.drive_response()),
            x: vec![0.0; w],
            p,
            law: crate::control::law::sampled::DiscreteController::new(file, start, end)?,
            period: 1.0 / sampled.rate_hz,
            u: 0.0,
            scratch: Scratch {
                innovation: vec![0.0; m],
                pc: vec![0.0; w * m],
                s: vec![0.0; m * m],
                s_inv: vec![0.0; m * m],
                factor: vec![0.0; m * m],
                gain: vec![0.0; w * m],
                gain_r: vec![0.0; w * m],
                keep: matrix(),
                m1: matrix(),
                m2: matrix(),
                m3: matrix(),
                rk: std::array::from_fn(|_| vec![0.0; w]),
            },
            model,
        })
    }

    /// The current estimate `x_hat = [z, z']` (predicted to the next tick).
    pub fn estimate(&self) -> &[f64] {
        &self.x
    }

    /// The measurement update with `y`: the Kalman gain from `S = C P C^T + R` and Joseph's
    /// form of the covariance (it stays symmetric positive semi-definite). Skipped when `S`
    /// is not positive definite.
    // indexed loops, as in the emitted C this code is mirrored in
    #[allow(clippy::needless_range_loop)]
    fn update(&mut self, y: &[f64]) {
        let (w, m) = (self.x.len(), y.len());
        let sc = &mut self.scratch;
        for s in 0..m {
            let mut predicted = 0.0;
            for col in 0..w {
                predicted += self.c[s * w + col] * self.x[col];
            }
            sc.innovation[s] = y[s] - predicted;
        }
        multiply_transposed(&self.p, &self.c, &mut sc.pc, w, w, m);
        multiply(&self.c, &sc.pc, &mut sc.s, m, w, m);
        for i in 0..m * m {
            sc.s[i] += self.r[i];
        }
        if !invert_spd(&sc.s, m, &mut sc.factor, &mut sc.s_inv) {
            return;
        }
        multiply(&sc.pc, &sc.s_inv, &mut sc.gain, w, m, m);
        for row in 0..w {
            let mut dx = 0.0;
            for s in 0..m {
                dx += sc.gain[row * m + s] * sc.innovation[s];
            }
            self.x[row] += dx;
        }
        // keep = I - G C; P = keep P keep^T + G R G^T
        multiply(&sc.gain, &self.c, &mut sc.keep, w, m, w);
        for row in 0..w {
            for col in 0..w {
                let identity = if row == col { 1.0 } else { 0.0 };
                sc.keep[row * w + col] = identity - sc.keep[row * w + col];
            }
        }
        multiply(&sc.keep, &self.p, &mut sc.m1, w, w, w);
        multiply_transposed(&sc.m1, &sc.keep, &mut self.p, w, w, w);
        multiply(&sc.gain, &self.r, &mut sc.gain_r, w, m, m);
        multiply_transposed(&sc.gain_r, &sc.gain, &mut sc.m1, w, m, w);
        for i in 0..w * w {
            self.p[i] += sc.m1[i];
        }
    }

    /// The covariance through one period: `F = exp(J T)` of the Jacobian at the estimate,
    /// `P = F P F^T + Q`, symmetrized.
    fn predict_covariance(&mut self, t: f64) {
        let w = self.x.len();
        let sc = &mut self.scratch;
        self.model.jacobian(t, &self.x, &mut sc.m1);
        for v in sc.m1.iter_mut() {
            *v *= self.period;
        }
        // m2 = F (a non-finite Jacobian leaves the covariance as it is)
        if !exponential(&sc.m1, w, &mut sc.m2, &mut sc.m3, &mut sc.keep) {
            return;
        }
        multiply(&sc.m2, &self.p, &mut sc.m1, w, w, w);
        multiply_transposed(&sc.m1, &sc.m2, &mut sc.m3, w, w, w);
        for row in 0..w {
            for col in 0..w {
                self.p[row * w + col] = 0.5
                    * ((sc.m3[row * w + col] + self.q[row * w + col])
                        + (sc.m3[col * w + row] + self.q[col * w + row]));
            }
        }
    }

    /// Integrates the estimate over one period with the force held (classic RK4).
    fn predict_state(&mut self, t: f64) {
        let h = self.period / SUBSTEPS as f64;
        let w = self.x.len();
        let [y, k1, k2, k3, k4, tmp] = &mut self.scratch.rk;
        y.copy_from_slice(&self.x);
        for s in 0..SUBSTEPS {
            let ts = t + s as f64 * h;
            self.model.rhs(ts, y, self.u, k1);
            for i in 0..w {
                tmp[i] = y[i] + 0.5 * h * k1[i];
            }
            self.model.rhs(ts + 0.5 * h, tmp, self.u, k2);
            for i in 0..w {
                tmp[i] = y[i] + 0.5 * h * k2[i];
            }
            self.model.rhs(ts + 0.5 * h, tmp, self.u, k3);
            for i in 0..w {
                tmp[i] = y[i] + h * k3[i];
            }
            self.model.rhs(ts + h, tmp, self.u, k4);
            for i in 0..w {
                y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
        self.x.copy_from_slice(y);
    }
}

impl SampledController for ExtendedKalman {
    fn step(&mut self, t: f64, y: &[f64], a: f64) -> f64 {
        // update with the measurements at t, then the covariance through the exact Jacobian
        // of the estimate's contact state, then the estimate through the nonlinear model to
        // the next tick with the force now held
        self.update(y);
        self.predict_covariance(t);
        self.predict_state(t);
        // the law on the predicted state
        self.u = self.law.force_at(t, &self.x, a);
        self.u
    }
}
