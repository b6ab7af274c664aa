//! Explicit Runge-Kutta methods from their Butcher tableaus: Dormand-Prince 5(4) (adaptive,
//! embedded error estimate, first-same-as-last) and classical RK4 (fixed step).
//!
//! Hand-written rather than taken from a crate: the driver must redo a step with any length
//! from the same start (event location with full order) and restart at every contact
//! switch, thousands of times per run; the crates we looked at (diffsol, ode_solvers) own
//! the time loop instead.

use super::{Settings, StepFailure, Stepper, System, error_norm};

/// An explicit Runge-Kutta method with optional embedded error estimate.
pub struct ExplicitRk {
    /// Nodes `c_i`.
    c: &'static [f64],
    /// Lower-triangular `a_ij`, row by row (row `i` has `i` entries).
    a: &'static [&'static [f64]],
    /// Weights `b_i` of the propagated solution.
    b: &'static [f64],
    /// `b_i - bhat_i` of the embedded pair, if any.
    e: Option<&'static [f64]>,
    /// True when the last stage is evaluated at `(t + h, y1)` (FSAL).
    fsal: bool,
    order: u32,
    rtol: f64,
    atol: f64,
    stages: Vec<Vec<f64>>,
    scratch: Vec<f64>,
    err: Vec<f64>,
}

const DOPRI5_C: [f64; 7] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0];
const DOPRI5_A: [&[f64]; 7] = [
    &[],
    &[1.0 / 5.0],
    &[3.0 / 40.0, 9.0 / 40.0],
    &[44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0],
    &[19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0],
    &[9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0],
    &[35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0],
];
const DOPRI5_B: [f64; 7] = [
    35.0 / 384.0,
    0.0,
    500.0 / 1113.0,
    125.0 / 192.0,
    -2187.0 / 6784.0,
    11.0 / 84.0,
    0.0,
];
const DOPRI5_E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];

const RK4_C: [f64; 4] = [0.0, 0.5, 0.5, 1.0];
const RK4_A: [&[f64]; 4] = [&[], &[0.5], &[0.0, 0.5], &[0.0, 0.0, 1.0]];
const RK4_B: [f64; 4] = [1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0];

impl ExplicitRk {
    fn new(
        n: usize,
        c: &'static [f64],
        a: &'static [&'static [f64]],
        b: &'static [f64],
        e: Option<&'static [f64]>,
        fsal: bool,
        order: u32,
        settings: Option<&Settings>,
    ) -> Self {
        ExplicitRk {
            c,
            a,
            b,
            e,
            fsal,
            order,
            rtol: settings.map_or(0.0, |s| s.rtol),
            atol: settings.map_or(0.0, |s| s.atol),
            stages: vec![vec![0.0; n]; c.len()],
            scratch: vec![0.0; n],
            err: vec![0.0; n],
        }
    }

    /// Dormand-Prince 5(4) for a state of length `n`.
    pub fn dopri5(n: usize, settings: &Settings) -> Self {
        Self::new(
            n,
            &DOPRI5_C,
            &DOPRI5_A,
            &DOPRI5_B,
            Some(&DOPRI5_E),
            true,
            4,
            Some(settings),
        )
    }

    /// Classical RK4 for a state of length `n`.
    pub fn rk4(n: usize) -> Self {
        Self::new(n, &RK4_C, &RK4_A, &RK4_B, None, false, 4, None)
    }
}

impl Stepper for ExplicitRk {
    fn order(&self) -> u32 {
        self.order
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
        let s = self.c.len();
        self.stages[0].copy_from_slice(f0);
        let last = if self.fsal { s - 1 } else { s };
        for i in 1..last {
            for (j, yj) in self.scratch.iter_mut().enumerate() {
                let mut acc = 0.0;
                for (aij, k) in self.a[i].iter().zip(&self.stages) {
                    acc += aij * k[j];
                }
                *yj = y[j] + h * acc;
            }
            let (done, rest) = self.stages.split_at_mut(i);
            let _ = done;
            sys.rhs(t + self.c[i] * h, &self.scratch, &mut rest[0]);
        }
        for (j, out) in y1.iter_mut().enumerate() {
            let mut acc = 0.0;
            for (bi, k) in self.b.iter().zip(&self.stages) {
                acc += bi * k[j];
            }
            *out = y[j] + h * acc;
        }
        if self.fsal {
            let (_, rest) = self.stages.split_at_mut(s - 1);
            sys.rhs(t + h, y1, &mut rest[0]);
        }
        match self.e {
            None => Ok(0.0),
            Some(e) => {
                for (j, ej) in self.err.iter_mut().enumerate() {
                    let mut acc = 0.0;
                    for (ei, k) in e.iter().zip(&self.stages) {
                        acc += ei * k[j];
                    }
                    *ej = h * acc;
                }
                Ok(error_norm(&self.err, y, y1, self.rtol, self.atol))
            }
        }
    }

    fn end_derivative(&self) -> Option<&[f64]> {
        if self.fsal {
            self.stages.last().map(|v| v.as_slice())
        } else {
            None
        }
    }
}
