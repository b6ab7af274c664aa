//! Checks shared by the tests of every model implementation.

use crate::contact::ContactState;
use crate::model::Model;
use nalgebra::DMatrix;

/// Compares the analytic Jacobian at `(t, y)` with central differences of the right-hand
/// side, both with the contact branches fixed to `states` (within fixed branches the
/// right-hand side is linear in `y`, so a large step has no truncation error and only
/// round-off, `eps |f| / h`, is allowed for).
///
/// # Errors
/// The first entry that differs, with both values.
pub fn jacobian_against_differences(
    model: &dyn Model,
    t: f64,
    y: &[f64],
    states: &[ContactState],
) -> Result<(), String> {
    let n2 = y.len();
    let mut jac = DMatrix::zeros(n2, n2);
    model.jacobian(t, y, Some(states), &mut jac);
    let mut base = vec![0.0; n2];
    model.rhs(t, y, Some(states), &mut base);
    let size = base.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let (mut plus, mut minus) = (vec![0.0; n2], vec![0.0; n2]);
    for j in 0..n2 {
        let h = 1e-3 * y[j].abs().max(1e-3);
        let (mut yp, mut ym) = (y.to_vec(), y.to_vec());
        yp[j] += h;
        ym[j] -= h;
        model.rhs(t, &yp, Some(states), &mut plus);
        model.rhs(t, &ym, Some(states), &mut minus);
        let scale = jac.column(j).abs().max().max(1.0);
        for i in 0..n2 {
            let fd = (plus[i] - minus[i]) / (2.0 * h);
            if (fd - jac[(i, j)]).abs() > 1e-8 * scale + 64.0 * f64::EPSILON * size / h {
                return Err(format!(
                    "d f_{i} / d y_{j}: analytic {} vs differences {fd}",
                    jac[(i, j)]
                ));
            }
        }
    }
    Ok(())
}
