//! The mass matrix's part of a right-hand side and a Jacobian, shared by the models that hold
//! `M` as a dense matrix (the quadrature-assembled and the finite-element one): the solve
//! with `M` for a force drive, and for a prescribed motion the solve on the relative
//! coordinates with the vehicle's acceleration given and its reaction dropped.

use crate::model::params::Drive;
use nalgebra::{Cholesky, DMatrix, DVectorViewMut, Dyn};

/// The factors of `M` a model's right-hand side and Jacobian solve with.
#[derive(Debug, Clone)]
pub(crate) struct MassSolve {
    /// Cholesky factor of `M`.
    full: Cholesky<f64, Dyn>,
    /// For a prescribed motion: the factor of `M` without row and column 0, and `M`'s column
    /// 0 (what the given vehicle acceleration pushes the other rows with).
    relative: Option<(Cholesky<f64, Dyn>, Vec<f64>)>,
}

impl MassSolve {
    /// The factors of `mass` for `drive`; `None` when `M` (or its relative part) is not
    /// positive definite.
    pub(crate) fn new(mass: &DMatrix<f64>, drive: &Drive) -> Option<Self> {
        let n = mass.nrows();
        let full = mass.clone().cholesky()?;
        let relative = match drive {
            Drive::Motion(_) if n > 1 => Some((
                mass.view((1, 1), (n - 1, n - 1)).into_owned().cholesky()?,
                mass.column(0).iter().copied().collect(),
            )),
            _ => None,
        };
        Some(MassSolve { full, relative })
    }

    /// Turns `acc`, the generalized forces without the drive, into accelerations: adds the
    /// drive force `input` on the vehicle and solves with `M`, or, for a prescribed motion,
    /// sets the vehicle's acceleration to `input` and solves the other rows with it given.
    pub(crate) fn accelerations(&self, input: f64, mut acc: DVectorViewMut<f64>) {
        let n = acc.len();
        match &self.relative {
            None => {
                acc[0] += input;
                self.full.solve_mut(&mut acc);
            }
            Some((factor, column)) => {
                // u'' = s''(t) is given; the other rows carry -M_p0 s'' and drop the reaction
                for j in 1..n {
                    acc[j] -= column[j] * input;
                }
                factor.solve_mut(&mut acc.rows_mut(1, n - 1));
                acc[0] = input;
            }
        }
    }

    /// Turns the lower half of a Jacobian `jac` (`2n x 2n`), holding the derivatives of the
    /// generalized forces' negatives `[K + .. | D + ..]`, into `-M^-1` times them (for a
    /// prescribed motion the vehicle's row is zero and the others use the relative factor).
    pub(crate) fn jacobian_rows(&self, jac: &mut DMatrix<f64>) {
        let n = jac.nrows() / 2;
        match &self.relative {
            None => self.full.solve_mut(&mut jac.view_mut((n, 0), (n, 2 * n))),
            Some((factor, _)) => {
                jac.row_mut(n).fill(0.0);
                factor.solve_mut(&mut jac.view_mut((n + 1, 0), (n - 1, 2 * n)));
            }
        }
        jac.view_mut((n, 0), (n, 2 * n)).neg_mut();
    }
}
