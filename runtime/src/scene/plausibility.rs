//! Parameters that are valid one by one but together make a model that double precision
//! cannot resolve: refused with the fields that cause it, before any solve.
//!
//! The eigen solvers resolve eigenvalues `w^2` to about `eps` times the largest, and an
//! explicit integrator's step is set by the fastest rate while the motion lives at the
//! slowest. Masses or stiffnesses that differ by more than 10^12 (frequencies by 10^6) leave
//! the slow part with fewer than four digits, so such scenes are refused here. What passes
//! is still checked where it is computed: the modal analysis refuses a spectrum that lost
//! its digits, and a run whose predicted step count is absurd is refused before it starts.

use super::FieldError;
use crate::params::ModelParams;

/// Largest ratio of two masses of the model (sections, vehicle, load).
pub const MAX_MASS_RATIO: f64 = 1e12;

/// Largest ratio of a contact spring to a section's bending stiffness `3 EI / l^3`, either
/// way.
pub const MAX_STIFFNESS_RATIO: f64 = 1e12;

/// Largest damping ratio `d / (2 sqrt(c m))` of a contact (with `m` the lighter of the two
/// sections it joins): beyond it the contact's damping rate outruns every frequency by more
/// than double precision keeps.
pub const MAX_DAMPING_RATIO: f64 = 1e6;

fn fail(errors: &mut Vec<FieldError>, field: String, rule: String) {
    errors.push(FieldError { field, rule });
}

/// The broken plausibility rules of `params` (empty when it is resolvable).
pub fn check(params: &ModelParams) -> Vec<FieldError> {
    let mut errors = Vec::new();
    let section_mass = |k: usize| params.sections[k].mass_per_length * params.sections[k].length;
    // masses: the lightest section against the heaviest mass of the model
    let mut masses: Vec<(String, f64)> = (0..params.sections.len())
        .map(|k| {
            (
                format!("sections.area[{k}] and sections.density[{k}]"),
                section_mass(k),
            )
        })
        .collect();
    let lightest = masses
        .iter()
        .cloned()
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .expect("at least one section");
    if params.vehicle_mass > 0.0 {
        masses.push(("masses.vehicle".into(), params.vehicle_mass));
    }
    if params.load_mass > 0.0 {
        masses.push(("masses.load".into(), params.load_mass));
    }
    let heaviest = masses
        .iter()
        .cloned()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .expect("at least one section");
    if heaviest.1 > MAX_MASS_RATIO * lightest.1 {
        fail(
            &mut errors,
            format!("{} against {}", heaviest.0, lightest.0),
            format!(
                "a mass of {:.3e} kg against a section of {:.3e} kg: masses that differ by more \
                 than {MAX_MASS_RATIO:e} leave the light part without digits in double \
                 precision (its modes are lost in the rounding of the heavy part)",
                heaviest.1, lightest.1
            ),
        );
    }
    // contacts: spring against the bending stiffness of the sections they join, damping
    let law = &params.contact;
    for k in 1..params.sections.len() {
        for j in [k - 1, k] {
            let s = &params.sections[j];
            let bending = 3.0 * s.bending_stiffness / s.length.powi(3);
            let ratio = law.stiffness / bending;
            if !(ratio <= MAX_STIFFNESS_RATIO && ratio >= 1.0 / MAX_STIFFNESS_RATIO) {
                fail(
                    &mut errors,
                    format!(
                        "contact.stiffness against sections.youngs_modulus[{j}] and sections.inertia[{j}]"
                    ),
                    format!(
                        "the contact spring c = {:.3e} N/m is {ratio:.3e} times section {}'s \
                         bending stiffness 3 EI / l^3 = {bending:.3e} N/m; beyond a ratio of \
                         {MAX_STIFFNESS_RATIO:e} either way, double precision cannot resolve \
                         the softer part",
                        law.stiffness,
                        j + 1
                    ),
                );
            }
        }
        let m = section_mass(k - 1).min(section_mass(k));
        let zeta = law.damping / (2.0 * (law.stiffness * m).sqrt());
        if !(zeta <= MAX_DAMPING_RATIO) {
            fail(
                &mut errors,
                "contact.damping".into(),
                format!(
                    "the contacts' damping ratio d / (2 sqrt(c m)) = {zeta:.3e} (d = {:.3e} N s/m \
                     against c = {:.3e} N/m and a section of {m:.3e} kg) is beyond \
                     {MAX_DAMPING_RATIO:e}: its damping rate outruns every frequency of the \
                     model by more than double precision keeps",
                    law.damping, law.stiffness
                ),
            );
        }
    }
    errors
}
