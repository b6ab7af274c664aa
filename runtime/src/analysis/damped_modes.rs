//! Damped natural frequencies and damping ratios of the closed-contact modes: the eigenvalues
//! `lambda = -zeta omega +- i omega sqrt(1 - zeta^2)` of the first-order system
//! `x' = [[0, I], [-M^-1 K_eff, -M^-1 D]] x` with `D = D_s + d sum_c g_c g_c'` (structural and
//! contact damping), each matched to the undamped mode of [`crate::modal_analysis`] nearest
//! in `|lambda| = omega`.

use crate::analysis::eigen::{
    EigenError, ModalAnalysis, closed_contact_damping, closed_contact_stiffness, eigenvalues,
};
use crate::model::Model;
use crate::model::params::Drive;
use nalgebra::DMatrix;
use std::f64::consts::PI;

/// One mode's damping.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DampedMode {
    /// Undamped natural frequency (Hz), as in [`ModalAnalysis::frequencies_hz`].
    pub undamped_hz: f64,
    /// Damped natural frequency `omega sqrt(1 - zeta^2) / 2 pi` (Hz); 0 when overdamped.
    pub damped_hz: f64,
    /// Damping ratio (1).
    pub ratio: f64,
    /// True when the ratio comes from the first-order eigenvalues; false when no complex pair
    /// matched (an overdamped mode) and it is the modal estimate `v' D v / (2 omega)`.
    pub from_eigenvalues: bool,
}

/// Largest relative mismatch of `|lambda|` and `omega` at which an eigenvalue pair counts as
/// the undamped mode's.
const MATCH_TOLERANCE: f64 = 0.2;

/// The damping of every mode of `analysis` (computed by [`crate::modal_analysis`] of `model`
/// at `analysis.time`).
///
/// # Errors
/// [`EigenError`] when the mass matrix cannot be factored or the eigenvalues do not converge.
pub fn damped_modes(
    model: &dyn Model,
    analysis: &ModalAnalysis,
) -> Result<Vec<DampedMode>, EigenError> {
    let t = analysis.time;
    let k = closed_contact_stiffness(model, t);
    let d = closed_contact_damping(model, t);
    let m = model.mass_matrix().clone();
    // a prescribed motion holds the vehicle: the system of the other coordinates
    let skip = usize::from(matches!(model.params().drive, Drive::Motion(_)));
    let r = model.dof() - skip;
    let sub = |x: &DMatrix<f64>| x.view((skip, skip), (r, r)).into_owned();
    let minv = sub(&m)
        .cholesky()
        .ok_or(EigenError::MassNotPositiveDefinite)?
        .inverse();
    let mut a = DMatrix::zeros(2 * r, 2 * r);
    a.view_mut((0, r), (r, r)).fill_with_identity();
    a.view_mut((r, 0), (r, r)).copy_from(&(-(&minv * sub(&k))));
    a.view_mut((r, r), (r, r)).copy_from(&(-(&minv * sub(&d))));
    let lambdas = eigenvalues(
        a,
        "damped eigenvalues of the closed-contact first-order system",
    )?;
    let mut used = vec![false; lambdas.len()];
    let modes = analysis
        .frequencies_hz
        .iter()
        .zip(&analysis.shapes)
        .map(|(&f, shape)| {
            let omega = 2.0 * PI * f;
            let best = lambdas
                .iter()
                .enumerate()
                .filter(|(i, l)| !used[*i] && l.im > 0.0)
                .map(|(i, l)| (i, (l.norm() - omega).abs() / omega))
                .min_by(|a, b| a.1.total_cmp(&b.1));
            match best {
                Some((i, mismatch)) if mismatch <= MATCH_TOLERANCE => {
                    used[i] = true;
                    let l = lambdas[i];
                    DampedMode {
                        undamped_hz: f,
                        damped_hz: l.im / (2.0 * PI),
                        ratio: -l.re / l.norm(),
                        from_eigenvalues: true,
                    }
                }
                _ => {
                    let ratio = shape.dot(&(&d * shape)) / (2.0 * omega);
                    DampedMode {
                        undamped_hz: f,
                        damped_hz: omega * (1.0 - ratio * ratio).max(0.0).sqrt() / (2.0 * PI),
                        ratio,
                        from_eigenvalues: false,
                    }
                }
            }
        })
        .collect();
    Ok(modes)
}
