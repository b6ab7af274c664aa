//! Generalized-alpha (Chung & Hulbert 1993) for `z'' = a(t, z, z')`, with Newton's method on
//! the analytic Jacobian of the model. Second order; the spectral radius at infinite
//! frequency `rho_inf` sets the numerical damping of the unresolved stiff (contact) modes.
//!
//! Unknown: the algorithmic acceleration `a1`. With the Newmark updates
//! `z1 = z0 + h v0 + h^2 ((1/2 - beta) a0 + beta a1)`, `v1 = v0 + h ((1 - gamma) a0 + gamma a1)`,
//! the balance `(1 - alpha_m) a1 + alpha_m a0 = a(t + (1 - alpha_f) h, z_alpha, v_alpha)` with
//! `z_alpha = (1 - alpha_f) z1 + alpha_f z0` (same for `v`) is solved by Newton. Within fixed
//! contact branches the system is affine in `(z, v)`, so one iteration usually converges.
//! Local error estimate (adaptive variant): `h^2 (beta - 1/6) (a1 - a0)` on `z`.

use super::{Settings, StepFailure, Stepper, System, error_norm};
use nalgebra::{DMatrix, DVector};

/// Generalized-alpha stepper.
pub struct GeneralizedAlpha {
    dof: usize,
    alpha_m: f64,
    alpha_f: f64,
    beta: f64,
    gamma: f64,
    adaptive: bool,
    rtol: f64,
    atol: f64,
    /// Algorithmic acceleration at the start of the step.
    a0: Vec<f64>,
    /// True after a restart: the step starts from the true acceleration `f0` instead.
    fresh: bool,
    /// Algorithmic acceleration at the end of the last step taken.
    a1: Vec<f64>,
    y_alpha: Vec<f64>,
    f_alpha: Vec<f64>,
    jac: DMatrix<f64>,
    /// Storage of the iteration matrix, lent to the LU factorization during a step.
    iteration: DMatrix<f64>,
    residual: DVector<f64>,
    err: Vec<f64>,
}

/// Newton iterations before a step counts as failed.
const MAX_NEWTON: usize = 8;

impl GeneralizedAlpha {
    /// For `dof` coordinates, spectral radius `rho_inf` in `[0, 1]`.
    pub fn new(dof: usize, rho_inf: f64, adaptive: bool, settings: &Settings) -> Self {
        let alpha_m = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0);
        let alpha_f = rho_inf / (rho_inf + 1.0);
        let gamma = 0.5 - alpha_m + alpha_f;
        let beta = 0.25 * (1.0 - alpha_m + alpha_f).powi(2);
        GeneralizedAlpha {
            dof,
            alpha_m,
            alpha_f,
            beta,
            gamma,
            adaptive,
            rtol: settings.rtol,
            atol: settings.atol,
            a0: vec![0.0; dof],
            fresh: true,
            a1: vec![0.0; dof],
            y_alpha: vec![0.0; 2 * dof],
            f_alpha: vec![0.0; 2 * dof],
            jac: DMatrix::zeros(2 * dof, 2 * dof),
            iteration: DMatrix::zeros(dof, dof),
            residual: DVector::zeros(dof),
            err: vec![0.0; 2 * dof],
        }
    }

    /// `z1`, `v1` from the Newmark updates for the current `a1`.
    fn newmark(&self, y: &[f64], a0: &[f64], h: f64, y1: &mut [f64]) {
        let n = self.dof;
        for i in 0..n {
            y1[i] =
                y[i] + h * y[n + i] + h * h * ((0.5 - self.beta) * a0[i] + self.beta * self.a1[i]);
            y1[n + i] = y[n + i] + h * ((1.0 - self.gamma) * a0[i] + self.gamma * self.a1[i]);
        }
    }
}

impl Stepper for GeneralizedAlpha {
    fn order(&self) -> u32 {
        2
    }

    fn step(
        &mut self,
        sys: &mut System,
        t: f64,
        y: &[f64],
        f0: &[f64],
        h: f64,
        y1: &mut [f64],
    ) -> Result<f64, StepFailure> {
        let n = self.dof;
        if self.fresh {
            self.a0.copy_from_slice(&f0[n..]);
        }
        // lent out for the step so `newmark` can borrow `self` beside it (no allocation)
        let a0 = std::mem::take(&mut self.a0);
        let result = self.solve(sys, t, y, &a0, h, y1);
        self.a0 = a0;
        result
    }

    fn accepted(&mut self) {
        self.a0.copy_from_slice(&self.a1);
        self.fresh = false;
    }

    fn restart(&mut self) {
        self.fresh = true;
    }
}

impl GeneralizedAlpha {
    /// Newton on the balance equation for `a1`; writes `y1` and returns the error estimate.
    // index loops: up to five arrays are read and written at the same index
    #[allow(clippy::needless_range_loop)]
    fn solve(
        &mut self,
        sys: &mut System,
        t: f64,
        y: &[f64],
        a0: &[f64],
        h: f64,
        y1: &mut [f64],
    ) -> Result<f64, StepFailure> {
        let n = self.dof;
        let (am, af) = (self.alpha_m, self.alpha_f);
        let t_alpha = t + (1.0 - af) * h;
        self.a1.copy_from_slice(a0);
        // modified Newton: one Jacobian and factorization per step
        let mut lu = None;
        let outcome = 'newton: {
            for _ in 0..MAX_NEWTON {
                self.newmark(y, a0, h, y1);
                for i in 0..2 * n {
                    self.y_alpha[i] = (1.0 - af) * y1[i] + af * y[i];
                }
                sys.rhs(t_alpha, &self.y_alpha, &mut self.f_alpha);
                for i in 0..n {
                    self.residual[i] = (1.0 - am) * self.a1[i] + am * a0[i] - self.f_alpha[n + i];
                }
                if lu.is_none() {
                    sys.jacobian(t_alpha, &self.y_alpha, &mut self.jac);
                    let mut s = std::mem::replace(&mut self.iteration, DMatrix::zeros(0, 0));
                    for j in 0..n {
                        for i in 0..n {
                            let dz = self.jac[(n + i, j)];
                            let dv = self.jac[(n + i, n + j)];
                            s[(i, j)] =
                                -(1.0 - af) * (self.beta * h * h * dz + self.gamma * h * dv);
                        }
                        s[(j, j)] += 1.0 - am;
                    }
                    sys.stats.factorizations += 1;
                    lu = Some(s.lu());
                }
                let lu_ref = lu.as_ref().expect("factorized above");
                if !lu_ref.solve_mut(&mut self.residual) {
                    break 'newton Err(StepFailure::NewtonDiverged);
                }
                // the correction, measured as the change of z1 and v1 it causes
                let mut size = 0.0f64;
                for i in 0..n {
                    let da = -self.residual[i];
                    self.a1[i] += da;
                    let dz = self.beta * h * h * da / (self.atol + self.rtol * y1[i].abs());
                    let dv = self.gamma * h * da / (self.atol + self.rtol * y1[n + i].abs());
                    size = size.max(dz.abs()).max(dv.abs());
                }
                if !size.is_finite() {
                    break 'newton Err(StepFailure::NewtonDiverged);
                }
                if size <= 1e-3 {
                    self.newmark(y, a0, h, y1);
                    if !self.adaptive {
                        break 'newton Ok(0.0);
                    }
                    let c = h * h * (self.beta - 1.0 / 6.0);
                    for i in 0..n {
                        self.err[i] = c * (self.a1[i] - a0[i]);
                        self.err[n + i] = 0.0;
                    }
                    break 'newton Ok(error_norm(&self.err, y, y1, self.rtol, self.atol));
                }
            }
            Err(StepFailure::NewtonDiverged)
        };
        // take the matrix storage back (a square LU unpacks in place)
        if let Some(lu) = lu {
            self.iteration = lu.l_unpack();
        }
        outcome
    }
}
