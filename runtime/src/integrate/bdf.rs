//! Backward differentiation formulas of orders 1 to 5 in variable-coefficient form (the
//! formula is rebuilt from the actual past step points, so any step sequence is exact), with
//! Newton on the analytic Jacobian and a simple order selection.
//!
//! Step to `x0 = t + h` at order `k`: the polynomial through `(x0, y1)` and the `k` points
//! `x1 = t, x2, ...` has slope `f(x0, y1)` at `x0`, i.e. `sum_j alpha_j y_j = f(x0, y1)` with
//! `alpha_j` the derivatives at `x0` of the Lagrange basis. Predictor: the polynomial through
//! `x1..x(k+1)` extrapolated to `x0` (after a restart, an Euler step). Local error estimate
//! (Shampine): `h / (x0 - x(k+1)) (y1 - predictor)`. After `k + 1` steps at one order the
//! estimates for `k - 1` and `k + 1` are compared with the one for `k`, and the order with
//! the largest next step wins (with a bias against changing).
//!
//! Every contact switch and drive discontinuity restarts the formula at order 1: the past
//! points lie on the other side of a kink of the contact law. Hand-written for the same
//! reason as the other methods (the event driver needs steps from a given start).

use super::newton::NewtonSolver;
use super::{Settings, StepFailure, Stepper, System, error_norm};

/// Most past points kept: order 5 with the order-6 estimate needs `x1..x7`, `x1` being the
/// current point passed to every step.
const KEPT: usize = 6;

/// Highest order.
pub const MAX_ORDER: usize = 5;

/// The BDF stepper with its history.
pub struct Bdf {
    max_order: usize,
    order: usize,
    /// Accepted steps since the order last changed.
    steps_at_order: usize,
    newton: NewtonSolver,
    rtol: f64,
    atol: f64,
    /// Times of the past points `x2, x3, ...` (most recent first).
    past_t: [f64; KEPT],
    past_y: Vec<Vec<f64>>,
    past_count: usize,
    /// Start `(t, y)` of the last step tried: becomes a past point when accepted.
    start_t: f64,
    start_y: Vec<f64>,
    /// Scaled error estimates of the last step for orders `k - 1`, `k`, `k + 1`
    /// (infinite when not available).
    estimates: [f64; 3],
    /// The estimate belonging to the order chosen for the next step.
    control: f64,
    predictor: Vec<f64>,
    base: Vec<f64>,
    err: Vec<f64>,
}

impl Bdf {
    /// For `dof` coordinates, orders up to `max_order` (1..=5).
    pub fn new(dof: usize, max_order: usize, settings: &Settings) -> Self {
        Bdf {
            max_order: max_order.clamp(1, MAX_ORDER),
            order: 1,
            steps_at_order: 0,
            newton: NewtonSolver::new(dof, settings.rtol, settings.atol),
            rtol: settings.rtol,
            atol: settings.atol,
            past_t: [0.0; KEPT],
            past_y: vec![vec![0.0; 2 * dof]; KEPT],
            past_count: 0,
            start_t: 0.0,
            start_y: vec![0.0; 2 * dof],
            estimates: [f64::INFINITY; 3],
            control: 0.0,
            predictor: vec![0.0; 2 * dof],
            base: vec![0.0; 2 * dof],
            err: vec![0.0; 2 * dof],
        }
    }

    /// The value at node `j >= 1` (`x1` is the current point `y`).
    fn value<'a>(&'a self, y: &'a [f64], j: usize) -> &'a [f64] {
        if j == 1 { y } else { &self.past_y[j - 2] }
    }

    /// Lagrange extrapolation to `x` through nodes `x1..=x(m)` into `out`.
    fn extrapolate(&self, nodes: &[f64], m: usize, x: f64, y: &[f64], out: &mut [f64]) {
        out.fill(0.0);
        for j in 1..=m {
            let mut w = 1.0;
            for i in 1..=m {
                if i != j {
                    w *= (x - nodes[i]) / (nodes[j] - nodes[i]);
                }
            }
            for (o, v) in out.iter_mut().zip(self.value(y, j)) {
                *o += w * v;
            }
        }
    }

    /// Scaled estimate `h / (x0 - x(m)) |y1 - p|` for the predictor `p` through `x1..=x(m)`.
    fn estimate(&mut self, nodes: &[f64], m: usize, y: &[f64], y1: &[f64]) -> f64 {
        let mut p = std::mem::take(&mut self.predictor);
        self.extrapolate(nodes, m, nodes[0], y, &mut p);
        let scale = (nodes[0] - nodes[1]) / (nodes[0] - nodes[m]);
        for ((e, a), b) in self.err.iter_mut().zip(y1).zip(&p) {
            *e = scale * (a - b);
        }
        self.predictor = p;
        error_norm(&self.err, y, y1, self.rtol, self.atol)
    }
}

impl Stepper for Bdf {
    fn order(&self) -> u32 {
        self.order as u32
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
        self.start_t = t;
        self.start_y.copy_from_slice(y);
        self.newton.prepare_step(sys, t, y);
        let k = self.order;
        let mut nodes = [0.0; KEPT + 2];
        nodes[0] = t + h;
        nodes[1] = t;
        nodes[2..2 + self.past_count].copy_from_slice(&self.past_t[..self.past_count]);
        // alpha_j: slopes at x0 of the Lagrange basis over x0..=xk
        let x0 = nodes[0];
        let alpha0: f64 = (1..=k).map(|m| 1.0 / (x0 - nodes[m])).sum();
        let hg = 1.0 / alpha0;
        self.base.fill(0.0);
        for j in 1..=k {
            let mut num = 1.0;
            let mut den = 1.0;
            for m in 0..=k {
                if m != j {
                    den *= nodes[j] - nodes[m];
                    if m != 0 {
                        num *= x0 - nodes[m];
                    }
                }
            }
            let alpha_j = num / den;
            let v = if j == 1 { y } else { &self.past_y[j - 2] };
            for (b, v) in self.base.iter_mut().zip(v) {
                *b -= hg * alpha_j * v;
            }
        }
        // predictor and Newton
        let startup = self.past_count < k;
        if startup {
            for ((p, a), d) in self.predictor.iter_mut().zip(y).zip(f0) {
                *p = a + h * d;
            }
        } else {
            let mut p = std::mem::take(&mut self.predictor);
            self.extrapolate(&nodes, k + 1, x0, y, &mut p);
            self.predictor = p;
        }
        y1.copy_from_slice(&self.predictor);
        self.newton.solve(sys, x0, &self.base, hg, y1)?;
        let err = if startup {
            // Euler predictor: y1 - p ~ h^2 y''; BDF1's error is half of it
            for ((e, a), p) in self.err.iter_mut().zip(y1.iter()).zip(&self.predictor) {
                *e = 0.5 * (a - p);
            }
            error_norm(&self.err, y, y1, self.rtol, self.atol)
        } else {
            self.estimate(&nodes, k + 1, y, y1)
        };
        self.estimates = [f64::INFINITY, err, f64::INFINITY];
        if k >= 2 {
            self.estimates[0] = self.estimate(&nodes, k, y, y1);
        }
        if k < self.max_order && self.past_count > k {
            self.estimates[2] = self.estimate(&nodes, k + 2, y, y1);
        }
        Ok(err)
    }

    fn accepted(&mut self) {
        self.past_y.rotate_right(1);
        self.past_t.rotate_right(1);
        self.past_t[0] = self.start_t;
        self.past_y[0].copy_from_slice(&self.start_y);
        self.past_count = (self.past_count + 1).min(KEPT);
        self.newton.forget_jacobian();
        self.steps_at_order += 1;
        let k = self.order;
        self.control = self.estimates[1];
        if self.steps_at_order > k {
            // the next step's size factor per candidate order, biased toward staying
            let gain = |e: f64, q: usize| {
                if e == 0.0 {
                    f64::INFINITY
                } else {
                    e.powf(-1.0 / (q as f64 + 1.0))
                }
            };
            let same = gain(self.estimates[1], k);
            let lower = if k >= 2 {
                gain(self.estimates[0], k - 1) / 1.3
            } else {
                0.0
            };
            let higher = gain(self.estimates[2], k + 1) / 1.4;
            if lower > same && lower >= higher {
                self.order = k - 1;
                self.control = self.estimates[0];
                self.steps_at_order = 0;
            } else if higher > same && self.estimates[2].is_finite() {
                self.order = k + 1;
                self.control = self.estimates[2];
                self.steps_at_order = 0;
            }
        }
    }

    fn restart(&mut self) {
        self.past_count = 0;
        self.order = 1;
        self.steps_at_order = 0;
        self.newton.forget_jacobian();
    }

    fn control_error(&self, err: f64) -> f64 {
        if self.control.is_finite() {
            self.control
        } else {
            err
        }
    }

    fn growth_limit(&self) -> f64 {
        // variable-step BDF of higher order loses zero-stability with large step ratios
        2.0
    }
}
