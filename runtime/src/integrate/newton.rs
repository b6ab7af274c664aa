//! Newton's method for the implicit equations of the stiff methods (ESDIRK stages, BDF
//! steps), all of the form `y = base + hg f(t, y)`, on the analytic Jacobian.
//!
//! The state is `y = [z, v]` with `z' = v`, so the Jacobian is `[[0, I], [A, B]]` and the
//! iteration matrix `I - hg J` reduces to the `dof x dof` matrix `S = I - hg B - hg^2 A`: for
//! the correction `d = [dz, dv]` of a residual `r = [rz, rv]`, `S dv = -rv - hg A rz` and
//! `dz = hg dv - rz`. Eight times fewer operations than factorizing the full matrix.

use super::{StepFailure, System, error_norm};
use nalgebra::{DMatrix, DVector, Dyn, LU};

/// Newton iterations before an implicit equation counts as unsolved.
const MAX_ITERATIONS: usize = 10;

/// Converged when the predicted remaining error of the iterate is below this fraction of
/// the tolerance.
const CONVERGED: f64 = 0.03;

/// Newton solver with a Jacobian kept per step and one factorization per distinct `hg`.
pub struct NewtonSolver {
    dof: usize,
    rtol: f64,
    atol: f64,
    /// `d ydot / d y` (2 dof x 2 dof), evaluated by [`NewtonSolver::prepare_step`].
    jac: DMatrix<f64>,
    /// Storage of the iteration matrix between factorizations.
    iteration: DMatrix<f64>,
    lu: Option<LU<f64, Dyn, Dyn>>,
    /// `hg` of the current factorization.
    factorized_hg: f64,
    /// Start time of the step the Jacobian belongs to (retries from that start reuse it).
    jacobian_at: Option<f64>,
    f: Vec<f64>,
    correction: Vec<f64>,
    dv: DVector<f64>,
}

impl NewtonSolver {
    /// For `dof` coordinates and the run's tolerances.
    pub fn new(dof: usize, rtol: f64, atol: f64) -> Self {
        NewtonSolver {
            dof,
            rtol,
            atol,
            jac: DMatrix::zeros(2 * dof, 2 * dof),
            iteration: DMatrix::zeros(dof, dof),
            lu: None,
            factorized_hg: f64::NAN,
            jacobian_at: None,
            f: vec![0.0; 2 * dof],
            correction: vec![0.0; 2 * dof],
            dv: DVector::zeros(dof),
        }
    }

    /// Evaluates the Jacobian at the step start `(t, y)` unless it belongs to this start
    /// already (a retried or event-located step), dropping the factorization when it does.
    pub fn prepare_step(&mut self, sys: &mut System, t: f64, y: &[f64]) {
        if self.jacobian_at == Some(t) {
            return;
        }
        sys.jacobian(t, y, &mut self.jac);
        self.jacobian_at = Some(t);
        self.release();
    }

    /// The step start moved on (accepted step or restart): the next step needs a new Jacobian.
    pub fn forget_jacobian(&mut self) {
        self.jacobian_at = None;
    }

    /// Returns the factorization's storage (a square LU unpacks in place: no allocation).
    fn release(&mut self) {
        if let Some(lu) = self.lu.take() {
            self.iteration = lu.l_unpack();
        }
        self.factorized_hg = f64::NAN;
    }

    /// Factorizes `S = I - hg B - hg^2 A` unless it is already factorized for `hg`.
    fn factorize(&mut self, sys: &mut System, hg: f64) {
        if self.factorized_hg == hg && self.lu.is_some() {
            return;
        }
        self.release();
        let n = self.dof;
        let mut s = std::mem::replace(&mut self.iteration, DMatrix::zeros(0, 0));
        for j in 0..n {
            for i in 0..n {
                s[(i, j)] = -hg * self.jac[(n + i, n + j)] - hg * hg * self.jac[(n + i, j)];
            }
            s[(j, j)] += 1.0;
        }
        sys.stats.factorizations += 1;
        self.lu = Some(s.lu());
        self.factorized_hg = hg;
    }

    /// Solves `y = base + hg f(t, y)` for `y`, starting from the guess in `y`.
    ///
    /// # Errors
    /// [`StepFailure::NewtonDiverged`] when the iteration diverges, stalls or the matrix is
    /// singular.
    // index loops: residual, Jacobian blocks and iterate are read at the same index
    #[allow(clippy::needless_range_loop)]
    pub fn solve(
        &mut self,
        sys: &mut System,
        t: f64,
        base: &[f64],
        hg: f64,
        y: &mut [f64],
    ) -> Result<(), StepFailure> {
        self.factorize(sys, hg);
        let n = self.dof;
        let mut previous = f64::INFINITY;
        for _ in 0..MAX_ITERATIONS {
            sys.rhs(t, y, &mut self.f);
            // residual r = y - base - hg f, kept in `correction`
            for i in 0..2 * n {
                self.correction[i] = y[i] - base[i] - hg * self.f[i];
            }
            for i in 0..n {
                let mut a_rz = 0.0;
                for j in 0..n {
                    a_rz += self.jac[(n + i, j)] * self.correction[j];
                }
                self.dv[i] = -self.correction[n + i] - hg * a_rz;
            }
            let lu = self.lu.as_ref().expect("factorized above");
            if !lu.solve_mut(&mut self.dv) {
                return Err(StepFailure::NewtonDiverged);
            }
            for i in 0..n {
                self.correction[i] = hg * self.dv[i] - self.correction[i];
                self.correction[n + i] = self.dv[i];
            }
            for (yi, d) in y.iter_mut().zip(&self.correction) {
                *yi += d;
            }
            let size = error_norm(&self.correction, y, y, self.rtol, self.atol);
            if !size.is_finite() {
                return Err(StepFailure::NewtonDiverged);
            }
            // Hairer & Wanner's test: the rate predicts the distance to the solution
            // (the first correction has no rate: it converges only when already tiny)
            if size <= 1e-3 * CONVERGED {
                return Ok(());
            }
            if previous.is_finite() {
                let rate = size / previous;
                if rate >= 1.0 {
                    return Err(StepFailure::NewtonDiverged);
                }
                if rate / (1.0 - rate) * size <= CONVERGED {
                    return Ok(());
                }
            }
            previous = size;
        }
        Err(StepFailure::NewtonDiverged)
    }
}
