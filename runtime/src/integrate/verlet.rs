//! Stormer-Verlet in velocity form for `z'' = a(t, z, z')`: half kick, drift, half kick.
//! Second order, explicit, one right-hand side per step; stable for undamped oscillation
//! while `h omega_max <= 2`. With velocity-dependent forces (contact damping) the second
//! half kick uses the half-step velocity, which keeps the method explicit.

use super::{StepFailure, Stepper, System};

/// Stormer-Verlet stepper.
pub struct StormerVerlet {
    dof: usize,
    scratch: Vec<f64>,
    accel: Vec<f64>,
}

impl StormerVerlet {
    /// For a model with `dof` coordinates.
    pub fn new(dof: usize) -> Self {
        StormerVerlet {
            dof,
            scratch: vec![0.0; 2 * dof],
            accel: vec![0.0; 2 * dof],
        }
    }
}

impl Stepper for StormerVerlet {
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
        // half kick and drift
        for i in 0..n {
            let v_half = y[n + i] + 0.5 * h * f0[n + i];
            self.scratch[n + i] = v_half;
            self.scratch[i] = y[i] + h * v_half;
        }
        // second half kick with the force at the new position
        sys.rhs(t + h, &self.scratch, &mut self.accel);
        for i in 0..n {
            y1[i] = self.scratch[i];
            y1[n + i] = self.scratch[n + i] + 0.5 * h * self.accel[n + i];
        }
        Ok(0.0)
    }
}
