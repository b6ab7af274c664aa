//! Explicit Runge-Kutta methods from their Butcher tableaus: Dormand-Prince 5(4) (adaptive,
//! embedded error estimate, first-same-as-last) and classical RK4 (fixed step).
//!
//! Hand-written rather than taken from a crate: the driver must redo a step with any length
//! from the same start (event location with full order) and restart at every contact
//! switch, thousands of times per run; the crates we looked at (diffsol, ode_solvers) own
//! the time loop instead.

use super::{Settings, StepFailure, Stepper, System, error_norm};

/// A Butcher tableau, with the embedded error weights of an adaptive pair.
pub struct Tableau {
    /// Nodes `c_i`.
    pub c: &'static [f64],
    /// Lower-triangular `a_ij`, row by row (row `i` has `i` entries).
    pub a: &'static [&'static [f64]],
    /// Weights `b_i` of the propagated solution.
    pub b: &'static [f64],
    /// `b_i - bhat_i` of the embedded pair, if any.
    pub e: Option<&'static [f64]>,
    /// True when the last stage is evaluated at `(t + h, y1)` (first same as last).
    pub fsal: bool,
    /// Order for step-size control.
    pub order: u32,
}

/// Dormand & Prince (1980), the 5(4) pair with 5th-order propagation.
pub const DOPRI5: Tableau = Tableau {
    c: &[0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0],
    a: &[
        &[],
        &[1.0 / 5.0],
        &[3.0 / 40.0, 9.0 / 40.0],
        &[44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0],
        &[
            19372.0 / 6561.0,
            -25360.0 / 2187.0,
            64448.0 / 6561.0,
            -212.0 / 729.0,
        ],
        &[
            9017.0 / 3168.0,
            -355.0 / 33.0,
            46732.0 / 5247.0,
            49.0 / 176.0,
            -5103.0 / 18656.0,
        ],
        &[
            35.0 / 384.0,
            0.0,
            500.0 / 1113.0,
            125.0 / 192.0,
            -2187.0 / 6784.0,
            11.0 / 84.0,
        ],
    ],
    b: &[
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
        0.0,
    ],
    e: Some(&[
        71.0 / 57600.0,
        0.0,
        -71.0 / 16695.0,
        71.0 / 1920.0,
        -17253.0 / 339200.0,
        22.0 / 525.0,
        -1.0 / 40.0,
    ]),
    fsal: true,
    order: 4,
};

/// The classical fourth-order Runge-Kutta method.
pub const RK4: Tableau = Tableau {
    c: &[0.0, 0.5, 0.5, 1.0],
    a: &[&[], &[0.5], &[0.0, 0.5], &[0.0, 0.0, 1.0]],
    b: &[1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0],
    e: None,
    fsal: false,
    order: 4,
};

/// An explicit Runge-Kutta method with its stage storage.
pub struct ExplicitRk {
    tableau: &'static Tableau,
    rtol: f64,
    atol: f64,
    stages: Vec<Vec<f64>>,
    scratch: Vec<f64>,
    err: Vec<f64>,
}

/// `out = base + h sum_i w_i k_i` (`base` zero when `None`).
fn combine(out: &mut [f64], base: Option<&[f64]>, h: f64, weights: &[f64], stages: &[Vec<f64>]) {
    for (j, o) in out.iter_mut().enumerate() {
        let mut acc = 0.0;
        for (w, k) in weights.iter().zip(stages) {
            acc += w * k[j];
        }
        *o = base.map_or(0.0, |b| b[j]) + h * acc;
    }
}

impl ExplicitRk {
    /// The method of `tableau` for a state of length `n`; `settings` give the tolerances
    /// of an embedded pair.
    pub fn new(tableau: &'static Tableau, n: usize, settings: &Settings) -> Self {
        ExplicitRk {
            tableau,
            rtol: settings.rtol,
            atol: settings.atol,
            stages: vec![vec![0.0; n]; tableau.c.len()],
            scratch: vec![0.0; n],
            err: vec![0.0; n],
        }
    }
}

impl Stepper for ExplicitRk {
    fn order(&self) -> u32 {
        self.tableau.order
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
        let tab = self.tableau;
        let s = tab.c.len();
        self.stages[0].copy_from_slice(f0);
        let last = if tab.fsal { s - 1 } else { s };
        for i in 1..last {
            combine(&mut self.scratch, Some(y), h, tab.a[i], &self.stages);
            sys.rhs(t + tab.c[i] * h, &self.scratch, &mut self.stages[i]);
        }
        combine(y1, Some(y), h, tab.b, &self.stages);
        if tab.fsal {
            sys.rhs(t + h, y1, &mut self.stages[s - 1]);
        }
        match tab.e {
            None => Ok(0.0),
            Some(e) => {
                combine(&mut self.err, None, h, e, &self.stages);
                Ok(error_norm(&self.err, y, y1, self.rtol, self.atol))
            }
        }
    }

    fn end_derivative(&self) -> Option<&[f64]> {
        if self.tableau.fsal {
            self.stages.last().map(|v| v.as_slice())
        } else {
            None
        }
    }
}
