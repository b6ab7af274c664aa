//! Parameters that are valid one by one but together make a model that double precision
//! cannot resolve: refused with the fields that cause it, before any solve.
//!
//! The eigen solvers resolve eigenvalues `w^2` to about `eps` times the largest, and an
//! explicit integrator's step is set by the fastest rate while the motion lives at the
//! slowest. Masses or stiffnesses that differ by more than 10^12 (frequencies by 10^6) leave
//! the slow part with fewer than four digits, so such scenes are refused here. What passes
//! is still checked where it is computed: the modal analysis refuses a spectrum that lost
//! its digits, and a run whose predicted step count is absurd is refused before it starts.

use super::error::FieldError;
use crate::model::params::ModelParams;

/// Largest ratio of two masses of the model (sections, vehicle, load).
pub const MAX_MASS_RATIO: f64 = 1e12;

/// Largest ratio of a contact spring to a section's bending stiffness `3 EI / l^3`, either
/// way.
pub const MAX_STIFFNESS_RATIO: f64 = 1e12;

/// Largest damping ratio `d / (2 sqrt(c m))` of a contact (with `m` the lighter of the two
/// sections it joins): beyond it the contact's damping rate outruns every frequency by more
/// than double precision keeps.
pub const MAX_DAMPING_RATIO: f64 = 1e6;

/// Largest clearance against the shortest section's length: a clearance is a small play in
/// a guide, not a gap of the section's own size.
pub const MAX_CLEARANCE_FRACTION: f64 = 0.05;

fn fail(errors: &mut Vec<FieldError>, field: String, rule: String) {
    errors.push(FieldError { field, rule });
}

/// Longest plausible section (m): a longer one was likely given in millimetres.
pub const MAX_SECTION_LENGTH: f64 = 100.0;

/// A section whose cantilever sag under its own weight exceeds this many times its length
/// has a bending stiffness no structure has: real sections sag 1e-4 to 1e-2 of their length,
/// and a modulus given in MPa makes it 1e6 times more.
pub const SAG_FACTOR: f64 = 100.0;

/// Fields whose values point to a wrong unit, with a hint: `(field, hint)`. A section
/// longer than [`MAX_SECTION_LENGTH`]; a section that would sag more than [`SAG_FACTOR`]
/// times its own length as a cantilever under its own weight at standard gravity
/// (`q l^4 / (8 EI)`), which no steel or aluminium section does with its modulus in N/m^2
/// but every one does in MPa.
pub fn unit_suspects(params: &ModelParams) -> Vec<(String, String)> {
    const STANDARD_GRAVITY: f64 = 9.80665;
    let mut suspects = Vec::new();
    for (k, s) in params.sections.iter().enumerate() {
        if s.length > MAX_SECTION_LENGTH {
            suspects.push((
                format!("sections.length[{k}]"),
                format!(
                    "{} m is longer than any telescope section; was it given in millimetres?",
                    s.length
                ),
            ));
        }
        let sag =
            s.mass_per_length * STANDARD_GRAVITY * s.length.powi(4) / (8.0 * s.bending_stiffness);
        if s.length <= MAX_SECTION_LENGTH && sag > SAG_FACTOR * s.length {
            suspects.push((
                format!("sections.youngs_modulus[{k}]"),
                format!(
                    "with sections.inertia[{k}], a bending stiffness EI = {:e} N m^2 under which \
                     the section would sag {sag:.3e} m under its own weight, over {SAG_FACTOR} \
                     times its length {} m; was the modulus given in MPa or GPa (SI: N/m^2 = \
                     Pa)?",
                    s.bending_stiffness, s.length
                ),
            ));
        }
    }
    suspects
}

/// The unit hints of `params` as a sentence to append to a message ("" without any).
pub fn unit_note(params: &ModelParams) -> String {
    let suspects = unit_suspects(params);
    if suspects.is_empty() {
        return String::new();
    }
    let list: Vec<String> = suspects
        .iter()
        .map(|(field, hint)| format!("`{field}`: {hint}"))
        .collect();
    format!(" Values are SI: {}", list.join("; "))
}

/// The broken plausibility rules of `params` (empty when it is resolvable).
pub fn check(params: &ModelParams) -> Vec<FieldError> {
    let mut errors = Vec::new();
    check_clearance(params, &mut errors);
    check_masses(params, &mut errors);
    check_contact_law(params, &mut errors);
    let structural = errors.len();
    check_rayleigh(params, &mut errors);
    // name the field most likely at fault first, and say that values are SI (not for the
    // structural damping, whose fields are the cause)
    let suspects = unit_suspects(params);
    for e in &mut errors[..structural] {
        if e.field == "contact.clearance" {
            continue;
        }
        let index = |f: &str| f.rsplit_once('[').map(|(_, i)| i.to_string());
        if let Some((field, hint)) = suspects
            .iter()
            .find(|(f, _)| index(f).is_some_and(|i| e.field.contains(&format!("[{i}"))))
            .or(suspects.first())
        {
            e.field = format!("{field} (or {})", e.field);
            e.rule = format!(
                "{}. Values are SI: `{field}` = {hint}",
                e.rule.trim_end_matches('.')
            );
        }
    }
    // a value in a wrong unit is refused on its own too, whatever else the scene has
    for (field, hint) in suspects {
        if !errors.iter().any(|e| e.field.starts_with(&field)) {
            fail(&mut errors, field, format!("values are SI: {hint}"));
        }
    }
    errors
}

/// A section's mass (kg).
fn section_mass(params: &ModelParams, k: usize) -> f64 {
    params.sections[k].mass_per_length * params.sections[k].length
}

/// The masses of the model are within [`MAX_MASS_RATIO`] of each other.
fn check_masses(params: &ModelParams, errors: &mut Vec<FieldError>) {
    // masses: the lightest section against the heaviest mass of the model
    let mut masses: Vec<(String, f64)> = (0..params.sections.len())
        .map(|k| {
            (
                format!("sections.area[{k}] and sections.density[{k}]"),
                section_mass(params, k),
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
            errors,
            format!("{} against {}", heaviest.0, lightest.0),
            format!(
                "a mass of {:.3e} kg against a section of {:.3e} kg: masses that differ by more \
                 than {MAX_MASS_RATIO:e} leave the light part without digits in double \
                 precision (its modes are lost in the rounding of the heavy part)",
                heaviest.1, lightest.1
            ),
        );
    }
}

/// The contact spring against the bending stiffness of the sections it joins, and the
/// contacts' damping ratio.
fn check_contact_law(params: &ModelParams, errors: &mut Vec<FieldError>) {
    // contacts: spring against the bending stiffness of the sections they join, damping
    let law = &params.contact;
    for k in 1..params.sections.len() {
        for j in [k - 1, k] {
            let s = &params.sections[j];
            let bending = 3.0 * s.bending_stiffness / s.length.powi(3);
            let ratio = law.stiffness / bending;
            if !(1.0 / MAX_STIFFNESS_RATIO..=MAX_STIFFNESS_RATIO).contains(&ratio) {
                fail(
                    errors,
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
        let m = section_mass(params, k - 1).min(section_mass(params, k));
        let zeta = law.damping / (2.0 * (law.stiffness * m).sqrt());
        if zeta.is_nan() || zeta > MAX_DAMPING_RATIO {
            fail(
                errors,
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
}

/// Rayleigh damping's ratios at each section's first cantilever frequency
/// `3.516 sqrt(EI / (m' l^4))` are within [`MAX_DAMPING_RATIO`]: beyond it the damping
/// rates outrun the model's frequencies by more than double precision keeps (and the eigen
/// analyses cannot resolve them).
fn check_rayleigh(params: &ModelParams, errors: &mut Vec<FieldError>) {
    let crate::model::params::StructuralDamping::Rayleigh { alpha, beta } = params.damping else {
        return;
    };
    let frequencies = params
        .sections
        .iter()
        .map(|s| 3.516 * (s.bending_stiffness / (s.mass_per_length * s.length.powi(4))).sqrt());
    let (lowest, highest) = frequencies.fold((f64::INFINITY, 0.0f64), |(lo, hi), w| {
        (lo.min(w), hi.max(w))
    });
    for (field, ratio, omega, law) in [
        (
            "sections.rayleigh_beta",
            beta * highest / 2.0,
            highest,
            "beta omega / 2",
        ),
        (
            "sections.rayleigh_alpha",
            alpha / (2.0 * lowest),
            lowest,
            "alpha / (2 omega)",
        ),
    ] {
        if ratio.is_nan() || ratio > MAX_DAMPING_RATIO {
            fail(
                errors,
                field.into(),
                format!(
                    "its damping ratio {law} = {ratio:.3e} at a section's first bending \
                     frequency {omega:.3e} rad/s is beyond {MAX_DAMPING_RATIO:e}: damping \
                     rates that far beyond the frequencies are not resolved in double precision"
                ),
            );
        }
    }
}

/// A clearance is small against the sections' lengths (a value in millimetres is not).
fn check_clearance(params: &ModelParams, errors: &mut Vec<FieldError>) {
    let clearance = params.contact.clearance;
    let (shortest, k) = params
        .sections
        .iter()
        .enumerate()
        .map(|(k, s)| (s.length, k))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .expect("at least one section");
    if params.sections.len() > 1 && clearance > MAX_CLEARANCE_FRACTION * shortest {
        fail(
            errors,
            "contact.clearance".into(),
            format!(
                "{clearance} m is {:.1} % of section {}'s length {shortest} m; a clearance is a \
                 small play, at most {:.0} % of the shortest section's length. Values are SI \
                 (metres): {clearance} mm would be {:e} m",
                100.0 * clearance / shortest,
                k + 1,
                100.0 * MAX_CLEARANCE_FRACTION,
                clearance / 1000.0
            ),
        );
    }
}
