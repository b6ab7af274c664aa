//! The stiff modes of a model's beams that [`super::imex`] treats implicitly beside the
//! contacts.
//!
//! A mode of the sections' `(K, M)` that turns more than [`STIFF_TURN`] radians over the
//! run's longest step (its output sample interval where adaptive steps end on samples, else
//! `Settings::longest_step`) goes to
//! the implicit part, whose L-stable stages give it its quasi-static response; the step
//! control bounds every coordinate's error whichever part holds it. In an explicit part such
//! modes set the step although the drive and the sliding contacts hardly excite them:
//! measured on case-study-no-clearance (1 ms samples), the paper's basis with 14 modes per
//! section took 331,000 steps explicitly and its contact forces were 2.6 kN off a tight
//! reference; with its modes above 0.6 rad per sample implicit it takes the sample grid's
//! 16,000 steps and the forces are within 0.8 N. The static correction shapes' own modes
//! (6.8 kHz with 2 modes per section there) fall under the same rule. Thresholds from 0.3 to
//! 0.7 rad gave the same step count there; 1.0 rad left modes at 0.87 rad explicit and took
//! 26,000 steps with forces 30 N off (docs/numerics.md). The paper's 4 modes per section
//! on the shipped moving scenes stay below it (0.52 rad), so their runs are the explicit
//! split of the paper.
//!
//! `M` and `K` are constant (block diagonal in the sections), so the modes are computed once
//! per run: with `Phi_h` (`n x r`, mass-normalized) and their `Lambda_h = omega^2`, the stiff
//! part of `M^-1 K z` is `W (S z)`, `W = Phi_h`, `S = Lambda_h Phi_h' M`, and `S W = Lambda_h`.

use crate::model::Model;
use crate::model::params::Drive;
use nalgebra::DMatrix;

/// A mode that turns more than this (rad) over the run's longest step is treated implicitly.
pub const STIFF_TURN: f64 = 0.6;

/// The stiff modes of a model's sections, in the form the implicit stages use.
#[derive(Debug, Clone)]
pub struct StiffModes {
    /// `Phi_h`, `n x r`, column-major (zero in a prescribed vehicle's row).
    pub w: DMatrix<f64>,
    /// `S' = M Phi_h Lambda_h`, `n x r`, column-major: row `j` of `S` is column `j` here
    /// (zero in a prescribed vehicle's row).
    pub st: DMatrix<f64>,
    /// `Lambda_h` (rad^2/s^2), ascending.
    pub lambda: Vec<f64>,
}

impl StiffModes {
    /// The modes of `model` that turn more than [`STIFF_TURN`] radians in `longest_step`
    /// (s): `None` when there are none, or when its matrices do not give a symmetric
    /// positive definite mass matrix (the integration then treats every mode explicitly).
    pub fn of(model: &dyn Model, longest_step: f64) -> Option<Self> {
        let n = model.dof();
        // a prescribed vehicle's coordinate is not free: the modes of the others
        let first = usize::from(matches!(model.params().drive, Drive::Motion(_)));
        let free = n - first;
        if free < 2 || longest_step.is_nan() || longest_step <= 0.0 {
            return None;
        }
        let stiff_above = (STIFF_TURN / longest_step).powi(2);
        let m = model
            .mass_matrix()
            .view((first, first), (free, free))
            .into_owned();
        let k = model
            .stiffness_matrix()
            .view((first, first), (free, free))
            .into_owned();
        let l = m.clone().cholesky()?.l();
        // A = L^-1 K L^-T, symmetric; K Phi = M Phi Lambda with Phi = L^-T Q
        let a = l.solve_lower_triangular(&k)?;
        let a = l.solve_lower_triangular(&a.transpose())?;
        let a = 0.5 * (&a + a.transpose());
        if !a.iter().all(|v| v.is_finite()) {
            return None;
        }
        let eigen = a.symmetric_eigen();
        let mut order: Vec<usize> = (0..free).collect();
        order.sort_by(|&i, &j| eigen.eigenvalues[i].total_cmp(&eigen.eigenvalues[j]));
        // the lowest mode stays explicit: the implicit part never holds the whole structure
        let r = order
            .iter()
            .filter(|&&i| eigen.eigenvalues[i] > stiff_above)
            .count()
            .min(free - 1);
        if r == 0 {
            return None;
        }
        let top = &order[free - r..];
        let q = DMatrix::from_fn(free, r, |i, j| eigen.eigenvectors[(i, top[j])]);
        let phi = l.transpose().solve_upper_triangular(&q)?;
        let lambda: Vec<f64> = top.iter().map(|&i| eigen.eigenvalues[i]).collect();
        let st_free =
            (&m * &phi) * DMatrix::from_diagonal(&nalgebra::DVector::from_vec(lambda.clone()));
        let mut w = DMatrix::zeros(n, r);
        w.view_mut((first, 0), (free, r)).copy_from(&phi);
        let mut st = DMatrix::zeros(n, r);
        st.view_mut((first, 0), (free, r)).copy_from(&st_free);
        Some(StiffModes { w, st, lambda })
    }

    /// Number of stiff modes.
    pub fn len(&self) -> usize {
        self.lambda.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.lambda.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::assembled::AssembledModel;
    use crate::scene::Scene;

    /// The modes solve `K Phi = M Phi Lambda` with `Phi' M Phi = I`, so `S W = Lambda`; they
    /// are the eigenvalues of `M^-1 K` (computed apart, unsymmetric) above the turn; a short
    /// enough step has none.
    #[test]
    fn the_stiff_modes_are_mass_normalized_eigenvectors_of_the_sections() {
        let mut scene = Scene::load("../scenes/adams-linear.toml".as_ref(), &[]).unwrap();
        let paper = AssembledModel::new(&scene.params).unwrap();
        assert!(StiffModes::of(&paper, 1e-7).is_none());
        scene.params.basis = crate::model::params::Basis::ModesAndStatic;
        for s in &mut scene.params.sections {
            s.modes = 2;
        }
        let model = AssembledModel::new(&scene.params).unwrap();
        let step = 1e-3;
        let stiff = StiffModes::of(&model, step).unwrap();
        let mk = model.mass_matrix().clone().try_inverse().unwrap() * model.stiffness_matrix();
        let above = mk
            .complex_eigenvalues()
            .iter()
            .filter(|l| l.re.max(0.0).sqrt() * step > STIFF_TURN)
            .count();
        assert_eq!(stiff.len(), above);
        assert!(above > 0 && above < model.dof());
        let (m, k) = (model.mass_matrix(), model.stiffness_matrix());
        let sw = stiff.st.transpose() * &stiff.w;
        for i in 0..stiff.len() {
            for j in 0..stiff.len() {
                let want = if i == j { stiff.lambda[i] } else { 0.0 };
                assert!((sw[(i, j)] - want).abs() <= 1e-8 * stiff.lambda[i], "{sw}");
            }
            let phi = stiff.w.column(i);
            let residual = k * phi - m * phi * stiff.lambda[i];
            assert!(residual.amax() <= 1e-8 * (k * phi).amax(), "mode {i}");
        }
        // ascending, the last the model's stiffest
        assert!(
            stiff.lambda.windows(2).all(|w| w[0] <= w[1]),
            "{:?}",
            stiff.lambda
        );
    }
}
