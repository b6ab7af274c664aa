//! The stiff modes of a model's beams that [`super::imex`] treats implicitly beside the
//! contacts.
//!
//! The static correction shapes ([`crate::params::Basis::ModesAndStatic`]) hold a section's
//! static deflection under point forces, which the paper's modes miss; their own
//! frequencies are far above the modes' (6.8 kHz on case-study-no-clearance with 2 modes
//! per section, against about 0.2 kHz for the paper's 4), and in an explicit part they set
//! the step: 119,000 steps where the paper's basis takes 16,000. Each correction shape adds
//! one coordinate and, in the spectrum of the sections' `(K, M)`, one stiff mode; the top
//! `r` modes, `r` the number of correction coordinates, go to the implicit part, whose
//! L-stable stages give them their quasi-static response. With few modes per section some
//! of them are low (adams-linear with 2 modes per section: the lowest of its 8 is at 23 Hz);
//! treating a slow mode implicitly costs no accuracy, since the step control bounds the
//! error of every coordinate. The paper's basis has none, and its runs are unchanged.
//!
//! `M` and `K` are constant (block diagonal in the sections), so the modes are computed once
//! per run: with `Phi_h` (`n x r`, mass-normalized) and their `Lambda_h = omega^2`, the stiff
//! part of `M^-1 K z` is `W (S z)`, `W = Phi_h`, `S = Lambda_h Phi_h' M`, and `S W = Lambda_h`.

use crate::model::Model;
use crate::params::{Basis, Drive};
use nalgebra::DMatrix;

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
    /// The stiff modes of `model`: `None` for the paper's basis, or when its matrices do
    /// not give a symmetric positive definite mass matrix (the integration then treats every
    /// mode explicitly, as for the paper's basis).
    pub fn of(model: &dyn Model) -> Option<Self> {
        let params = model.params();
        if params.basis != Basis::ModesAndStatic {
            return None;
        }
        let corrections: usize = params.coordinates().iter().sum::<usize>()
            - params.sections.iter().map(|s| s.modes).sum::<usize>();
        let n = model.dof();
        // a prescribed vehicle's coordinate is not free: the modes of the others
        let first = usize::from(matches!(params.drive, Drive::Motion(_)));
        let free = n - first;
        let r = corrections.min(free.saturating_sub(1));
        if r == 0 {
            return None;
        }
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
    use crate::assembled::AssembledModel;
    use crate::scene::Scene;

    /// The modes solve `K Phi = M Phi Lambda` with `Phi' M Phi = I`, so `S W = Lambda`; and
    /// the paper's basis has none.
    #[test]
    fn the_stiff_modes_are_mass_normalized_eigenvectors_of_the_sections() {
        let mut scene = Scene::load("../scenes/adams-linear.toml".as_ref(), &[]).unwrap();
        assert!(StiffModes::of(&AssembledModel::new(&scene.params).unwrap()).is_none());
        scene.params.basis = Basis::ModesAndStatic;
        for s in &mut scene.params.sections {
            s.modes = 2;
        }
        let model = AssembledModel::new(&scene.params).unwrap();
        let stiff = StiffModes::of(&model).unwrap();
        let corrections = scene.params.coordinates().iter().sum::<usize>() - 4;
        assert_eq!(stiff.len(), corrections);
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
