//! Why a run failed, diagnosed from the model rather than guessed: the causes the error
//! messages of the driver and of exact stepping name.

use crate::analysis::eigen::modal_analysis;
use crate::model::Model;
use crate::scene::TimeSpan;

/// Why the state grew beyond any physical size when no step-size limit explains it: modes
/// that buckle under gravity (negative stiffness), or else the drive.
pub fn growth_cause(model: &dyn Model, t: f64, span: &TimeSpan) -> String {
    let params = model.params();
    match modal_analysis(model, t) {
        Ok(m) if !m.unstable_growth_rates.is_empty() => format!(
            "the model is unstable: {} mode(s) buckle under the axial load of gravity (growth \
             rates up to {:.3e} 1/s); check gravity.g, gravity.force_flow and the masses against \
             the bending stiffness.{}",
            m.unstable_growth_rates.len(),
            m.unstable_growth_rates.last().copied().unwrap_or(0.0),
            crate::scene::plausibility::unit_note(params)
        ),
        Ok(_) => {
            let (lo, hi) = params.drive_profile().range(span.start, span.end);
            format!(
                "the model is stable (no buckled mode), so the drive moved it there: the drive \
                 profile ranges over [{lo:e}, {hi:e}] (N for a force, m for a motion) on a \
                 telescope of {:.4e} kg; check drive",
                params.total_mass()
            )
        }
        Err(e) => format!("the eigen analysis of the model fails too: {e}"),
    }
}
