//! ESDIRK4(3)6L\[2\]SA of Kennedy & Carpenter (NASA/TM-2016-219173, Table 16): a six-stage,
//! L-stable, stiffly accurate singly diagonally implicit Runge-Kutta method of order 4 with
//! an embedded order-3 solution, explicit first stage. Each implicit stage solves
//! `Y_i = y + h sum_{j<i} a_ij k_j + h gamma f(t + c_i h, Y_i)` by Newton on the analytic
//! Jacobian; the diagonal `gamma` is the same for every stage, so one factorization serves
//! the whole step.
//!
//! Hand-written (diffsol has SDIRK tableaus, but owns the time loop; the event driver must
//! redo steps of any length from the same start).

use super::newton::NewtonSolver;
use super::{Settings, StepFailure, Stepper, System, error_norm};
use std::f64::consts::SQRT_2;

/// Diagonal coefficient `gamma` (every implicit stage).
pub const GAMMA: f64 = 0.25;
const C3: f64 = (2.0 - SQRT_2) / 4.0;
const C4: f64 = 5.0 / 8.0;
const C5: f64 = 26.0 / 25.0;
const A32: f64 = (1.0 - SQRT_2) / 8.0;
const A42: f64 = (5.0 - 7.0 * SQRT_2) / 64.0;
const A43: f64 = 7.0 * (1.0 + SQRT_2) / 32.0;
const A52: f64 = (-13796.0 - 54539.0 * SQRT_2) / 125000.0;
const A53: f64 = (506605.0 + 132109.0 * SQRT_2) / 437500.0;
const A54: f64 = 166.0 * (-97.0 + 376.0 * SQRT_2) / 109375.0;
const B2: f64 = (1181.0 - 987.0 * SQRT_2) / 13782.0;
const B3: f64 = 47.0 * (-267.0 + 1783.0 * SQRT_2) / 273343.0;
const B4: f64 = -16.0 * (-22922.0 + 3525.0 * SQRT_2) / 571953.0;
const B5: f64 = -15625.0 * (97.0 + 376.0 * SQRT_2) / 90749876.0;
const B1: f64 = 1.0 - B2 - B3 - B4 - B5 - GAMMA;
const BH2: f64 = -480923228411.0 / 4982971448372.0;
const BH3: f64 = 6709447293961.0 / 12833189095359.0;
const BH4: f64 = 3513175791894.0 / 6748737351361.0;
const BH5: f64 = -498863281070.0 / 6042575550617.0;
const BH6: f64 = 2077005547802.0 / 8945017530137.0;

/// Nodes `c_i`.
pub const C: [f64; 6] = [0.0, 2.0 * GAMMA, C3, C4, C5, 1.0];
/// Strictly lower part of `A` (the diagonal is [`GAMMA`] from the second stage on); the
/// first column follows from the row sums `c_i`.
pub const A: [[f64; 5]; 6] = [
    [0.0; 5],
    [GAMMA, 0.0, 0.0, 0.0, 0.0],
    [C3 - A32 - GAMMA, A32, 0.0, 0.0, 0.0],
    [C4 - A42 - A43 - GAMMA, A42, A43, 0.0, 0.0],
    [C5 - A52 - A53 - A54 - GAMMA, A52, A53, A54, 0.0],
    [B1, B2, B3, B4, B5],
];
/// Weights `b_i` (the last row of `A` with `gamma`: stiffly accurate).
pub const B: [f64; 6] = [B1, B2, B3, B4, B5, GAMMA];
/// Embedded third-order weights `bhat_i`.
pub const BHAT: [f64; 6] = [1.0 - BH2 - BH3 - BH4 - BH5 - BH6, BH2, BH3, BH4, BH5, BH6];

/// The ESDIRK stepper with its stage storage.
pub struct Esdirk {
    newton: NewtonSolver,
    rtol: f64,
    atol: f64,
    /// Stage derivatives `k_i`.
    stages: Vec<Vec<f64>>,
    base: Vec<f64>,
    err: Vec<f64>,
}

impl Esdirk {
    /// For `dof` coordinates with the run's tolerances.
    pub fn new(dof: usize, settings: &Settings) -> Self {
        Esdirk {
            newton: NewtonSolver::new(dof, settings.rtol, settings.atol),
            rtol: settings.rtol,
            atol: settings.atol,
            stages: vec![vec![0.0; 2 * dof]; 6],
            base: vec![0.0; 2 * dof],
            err: vec![0.0; 2 * dof],
        }
    }
}

impl Stepper for Esdirk {
    fn order(&self) -> u32 {
        3
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
        self.newton.prepare_step(sys, t, y);
        self.stages[0].copy_from_slice(f0);
        let hg = h * GAMMA;
        for i in 1..6 {
            for (j, b) in self.base.iter_mut().enumerate() {
                let mut acc = 0.0;
                for (a, k) in A[i][..i].iter().zip(&self.stages) {
                    acc += a * k[j];
                }
                *b = y[j] + h * acc;
            }
            // guess: the previous stage's slope continued over the diagonal part
            for (j, yj) in y1.iter_mut().enumerate() {
                *yj = self.base[j] + hg * self.stages[i - 1][j];
            }
            self.newton.solve(sys, t + C[i] * h, &self.base, hg, y1)?;
            // the stage slope from the solved equation (no extra evaluation, and free of
            // the Newton residual amplified by a stiff Jacobian)
            for (j, k) in self.stages[i].iter_mut().enumerate() {
                *k = (y1[j] - self.base[j]) / hg;
            }
        }
        // stiffly accurate: y1 is the last stage value
        for (j, e) in self.err.iter_mut().enumerate() {
            let mut acc = 0.0;
            for ((b, bh), k) in B.iter().zip(&BHAT).zip(&self.stages) {
                acc += (b - bh) * k[j];
            }
            *e = h * acc;
        }
        Ok(error_norm(&self.err, y, y1, self.rtol, self.atol))
    }

    fn accepted(&mut self) {
        self.newton.forget_jacobian();
    }

    fn restart(&mut self) {
        self.newton.forget_jacobian();
    }
}

#[cfg(test)]
mod tests {
    use super::super::tableau::{dot, full, mul};
    use super::*;
    use approx::assert_relative_eq;

    /// The transcribed coefficients satisfy the order conditions: 4 for `b`, 3 for `bhat`,
    /// and the row sums are the nodes.
    #[test]
    fn order_conditions_hold() {
        let a = full(&A, GAMMA);
        let ones = [1.0; 6];
        for (i, row) in a.iter().enumerate() {
            assert_relative_eq!(row.iter().sum::<f64>(), C[i], epsilon = 1e-14);
        }
        let c2: [f64; 6] = std::array::from_fn(|i| C[i] * C[i]);
        let c3: [f64; 6] = std::array::from_fn(|i| C[i] * C[i] * C[i]);
        let ac = mul(&a, &C);
        let ac2 = mul(&a, &c2);
        let aac = mul(&a, &ac);
        let cac: [f64; 6] = std::array::from_fn(|i| C[i] * ac[i]);
        for (w, order) in [(&B, 4), (&BHAT, 3)] {
            let mut conditions = vec![
                (dot(w, &ones), 1.0),
                (dot(w, &C), 0.5),
                (dot(w, &c2), 1.0 / 3.0),
                (dot(w, &ac), 1.0 / 6.0),
            ];
            if order == 4 {
                conditions.extend([
                    (dot(w, &c3), 0.25),
                    (dot(w, &cac), 0.125),
                    (dot(w, &ac2), 1.0 / 12.0),
                    (dot(w, &aac), 1.0 / 24.0),
                ]);
            }
            for (value, exact) in conditions {
                assert_relative_eq!(value, exact, epsilon = 1e-13);
            }
        }
        // not of order 4: the embedded solution differs from the propagated one
        assert!((dot(&BHAT, &c3) - 0.25).abs() > 1e-4);
    }
}
