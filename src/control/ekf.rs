//! An estimator that knows the clearance: an extended Kalman filter whose prediction runs
//! the nonlinear model itself (contact law included) over each controller period, and whose
//! covariance follows the exact Jacobian of the contact state the estimate is in. The
//! measurements it takes are linear in the coordinates (`vehicle`, `tip_rel`, `top1_rel`,
//! `kappa_1_0`).

use super::design::Controller;
use super::sampled::SampledController;
use crate::rows::from_rows;
use crate::{Error, Result};
use telescopic_runtime::Model;
use telescopic_runtime::nalgebra::{DMatrix, DVector};

/// Substeps of the prediction's RK4 per controller period: with 20 at 1 kHz the step is
/// 50 us, `h omega` = 1.1 for the 3.6 kHz contact mode, inside RK4's stability limit of 2.8.
const SUBSTEPS: usize = 20;

/// The extended Kalman filter with the controller's LQR law on its estimate.
pub struct ExtendedKalman {
    model: Box<dyn Model>,
    /// Where the drive force enters the accelerations.
    drive: super::controlled::DriveResponse,
    c: DMatrix<f64>,
    r: DMatrix<f64>,
    /// Process noise per period.
    q: DMatrix<f64>,
    x: DVector<f64>,
    p: DMatrix<f64>,
    law: super::sampled::DiscreteController,
    period: f64,
    u: f64,
    jac: DMatrix<f64>,
    scratch: [Vec<f64>; 5],
    tmp: Vec<f64>,
}

impl ExtendedKalman {
    /// The filter of `file`'s sampled part on `model` (the scene's own model, a fresh
    /// instance), over `[start, end]` s.
    ///
    /// # Errors
    /// [`Error::Option`] for sensors that are not linear in the coordinates, [`Error::Model`]
    /// when the mass matrix cannot be factored.
    pub fn new(file: &Controller, model: Box<dyn Model>, start: f64, end: f64) -> Result<Self> {
        let sampled = file.sampled.as_ref().ok_or_else(|| {
            Error::option("controller", "has no sampled part (design it with sensors)")
        })?;
        if let Some(s) = sampled.sensors.iter().find(|s| s.as_str() == "acc_load") {
            return Err(Error::option(
                "controller `sampled.sensors`",
                format!("the extended filter takes outputs linear in the coordinates, not `{s}`"),
            ));
        }
        let n = model.dof();
        let drive = super::controlled::DriveResponse::of(model.as_ref())?;
        let response = drive.entries();
        let c = from_rows(&sampled.points[0].c, None)
            .map_err(|e| Error::option("controller `sampled.points[0].C`", e))?;
        let r = DMatrix::from_diagonal(&DVector::from_iterator(
            sampled.noise.len(),
            sampled.noise.iter().map(|s| s * s),
        ));
        let period = 1.0 / sampled.rate_hz;
        // the force disturbance through the accelerations over one period, plus a floor
        let mut bd = DVector::zeros(2 * n);
        for i in 0..n {
            bd[i] = 0.5 * period * period * response[i];
            bd[n + i] = period * response[i];
        }
        // the floor keeps the filter from growing certain of the motion it cannot see (the
        // upper section inside its band): without it the loop diverges with clearance
        let q = &bd * bd.transpose() * sampled.force_noise.powi(2)
            + DMatrix::identity(2 * n, 2 * n)
                * sampled
                    .process_noise_floor
                    .unwrap_or(super::sampled::FORMER_PROCESS_NOISE_FLOOR);
        Ok(ExtendedKalman {
            drive,
            c,
            r,
            q,
            x: DVector::zeros(2 * n),
            p: DMatrix::identity(2 * n, 2 * n) * 1e-8,
            law: super::sampled::DiscreteController::new(file, start, end)?,
            period,
            u: 0.0,
            jac: DMatrix::zeros(2 * n, 2 * n),
            scratch: std::array::from_fn(|_| vec![0.0; 2 * n]),
            tmp: vec![0.0; 2 * n],
            model,
        })
    }

    /// The current estimate `x_hat = [z, z']` (predicted to the next tick).
    pub fn estimate(&self) -> &[f64] {
        self.x.as_slice()
    }

    /// `ydot` of the model with the drive force `u` at `t`.
    fn rhs(&self, t: f64, y: &[f64], u: f64, ydot: &mut [f64]) {
        self.drive
            .rhs_with(self.model.as_ref(), t, y, None, u, ydot);
    }

    /// Integrates the estimate over one period with the force held (classic RK4).
    fn predict_state(&mut self, t: f64) {
        let h = self.period / SUBSTEPS as f64;
        // the buffers, taken out of self while self.rhs borrows it
        let [mut y, mut k1, mut k2, mut k3, mut k4] = std::mem::take(&mut self.scratch);
        let mut tmp = std::mem::take(&mut self.tmp);
        y.copy_from_slice(self.x.as_slice());
        for s in 0..SUBSTEPS {
            let ts = t + s as f64 * h;
            self.rhs(ts, &y, self.u, &mut k1);
            for i in 0..y.len() {
                tmp[i] = y[i] + 0.5 * h * k1[i];
            }
            self.rhs(ts + 0.5 * h, &tmp, self.u, &mut k2);
            for i in 0..y.len() {
                tmp[i] = y[i] + 0.5 * h * k2[i];
            }
            self.rhs(ts + 0.5 * h, &tmp, self.u, &mut k3);
            for i in 0..y.len() {
                tmp[i] = y[i] + h * k3[i];
            }
            self.rhs(ts + h, &tmp, self.u, &mut k4);
            for i in 0..y.len() {
                y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
        self.x.copy_from_slice(&y);
        self.scratch = [y, k1, k2, k3, k4];
        self.tmp = tmp;
    }
}

impl SampledController for ExtendedKalman {
    fn step(&mut self, t: f64, y: &[f64], a: f64) -> f64 {
        // update with the measurements at t
        let innovation = DVector::from_column_slice(y) - &self.c * &self.x;
        let s = &self.c * &self.p * self.c.transpose() + &self.r;
        if let Some(s_inv) = s.try_inverse() {
            let gain = &self.p * self.c.transpose() * s_inv;
            self.x += &gain * innovation;
            let n = self.x.len();
            // Joseph's form: the covariance stays symmetric positive semi-definite
            let keep = DMatrix::identity(n, n) - &gain * &self.c;
            self.p = &keep * &self.p * keep.transpose() + &gain * &self.r * gain.transpose();
        }
        // the covariance through the exact Jacobian of the estimate's contact state
        self.model
            .jacobian(t, self.x.as_slice(), None, &mut self.jac);
        let f = (&self.jac * self.period).exp();
        self.p = &f * &self.p * f.transpose() + &self.q;
        self.p = (&self.p + self.p.transpose()) * 0.5;
        // the estimate through the nonlinear model to the next tick, with the force now held
        self.predict_state(t);
        // the law on the predicted state
        self.u = self.law.force_at(t, self.x.as_slice(), a);
        self.u
    }
}
