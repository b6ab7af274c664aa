//! Structural damping of the sections: the damping matrix `D_s` of
//! `M z'' + D_s z' + K z = ...` (docs/model.md section 4, "Structural damping").
//!
//! * **Modal** (`sections.damping_ratio`): `D_s = M Phi diag(2 zeta_i omega_i) Phi' M` over the
//!   structural modes `Phi` (mass-normalized) of the telescope with its contacts closed, at
//!   the telescopic positions of the scene's start: each of those modes decays at exactly its
//!   ratio `zeta_i` there (what a modal test of the structure would measure). Contact modes
//!   (most strain energy in the contact springs, see [`contact_energy_shares`]) get none:
//!   their damping is the contacts' own `d`. The vehicle's travel is not damped. Where the
//!   telescope moves away from the start geometry or a contact opens, the same `D_s` stays:
//!   the ratios there are close to, not exactly, `zeta` (`telescopic modes --at T` shows them).
//! * **Rayleigh** (`sections.rayleigh_alpha`, `sections.rayleigh_beta`): `D_s = alpha M +
//!   beta K` with the sections' own stiffness `K`; a mode of the sections alone (one section,
//!   or contacts open) gets `zeta = alpha / (2 omega) + beta omega / 2`. `alpha M` damps the
//!   rigid travel too (a drag on the whole telescope).
//!
//! The default is no structural damping, the paper's worst case for control; the contacts'
//! own damping `d` is separate and always present.

use crate::analysis::eigen::{EigenError, ModalAnalysis, modal_analysis_with};
use crate::model::Model;
pub use crate::model::params::StructuralDamping;
use nalgebra::DMatrix;

/// Share of a mode's strain energy in the contact springs above which it is a contact mode.
pub const CONTACT_MODE_SHARE: f64 = 0.5;

/// The share of each mode's strain energy stored in the contact springs,
/// `c sum_c (g_c . v)^2 / omega^2` for mass-normalized shapes `v` (contact vectors `g`, one
/// column per contact, at the modes' geometry; contact stiffness `c` in N/m).
pub fn contact_energy_shares(modal: &ModalAnalysis, g: &DMatrix<f64>, c: f64) -> Vec<f64> {
    modal
        .shapes
        .iter()
        .zip(&modal.frequencies_hz)
        .map(|(v, f)| {
            let omega2 = (2.0 * std::f64::consts::PI * f).powi(2);
            let springs: f64 = g.column_iter().map(|gc| gc.dot(v).powi(2)).sum();
            c * springs / omega2
        })
        .collect()
}

/// The structural damping matrix `D_s` (N s/m in computing coordinates) of `model`'s
/// `params().damping`, from its mass and stiffness matrices (and, for modal damping, its
/// closed-contact modes); `None` without structural damping. The model's own damping matrix
/// is not used.
///
/// # Errors
/// [`EigenError`] when the modes cannot be had (modal damping).
pub fn structural_damping(model: &dyn Model) -> Result<Option<DMatrix<f64>>, EigenError> {
    let damping = &model.params().damping;
    if damping.is_none() {
        return Ok(None);
    }
    let (m, k) = (model.mass_matrix(), model.stiffness_matrix());
    let StructuralDamping::Modal { positions, .. } = damping else {
        let StructuralDamping::Rayleigh { alpha, beta } = damping else {
            unreachable!("not none")
        };
        return Ok(Some(*alpha * m + *beta * k));
    };
    let (n, nc) = (model.dof(), model.layout().contact_count());
    let mut g = DMatrix::zeros(n, nc);
    let mut gdot = DMatrix::zeros(n, nc);
    let mut k_closed = k.clone();
    let c = model.params().contact.stiffness;
    if nc > 0 {
        model.contact_vectors_at(positions, &vec![0.0; positions.len()], &mut g, &mut gdot);
        k_closed += c * &g * g.transpose();
    }
    let modal = modal_analysis_with(model, &k_closed)?;
    let shares = contact_energy_shares(&modal, &g, c);
    let mut d = DMatrix::zeros(n, n);
    for (i, (v, f)) in modal.shapes.iter().zip(&modal.frequencies_hz).enumerate() {
        if shares[i] > CONTACT_MODE_SHARE {
            continue;
        }
        let mv = m * v;
        let weight = 2.0 * damping.modal_ratio(i) * 2.0 * std::f64::consts::PI * f;
        d += weight * &mv * mv.transpose();
    }
    Ok(Some(0.5 * (&d + d.transpose())))
}
