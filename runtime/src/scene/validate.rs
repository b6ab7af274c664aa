//! The rules a scene must satisfy, and its conversion into [`ModelParams`].

use super::error::{FieldError, SceneError};
use super::limits::{
    MAX_CONTACT_POINTS, MAX_OUTPUT_VALUES, MAX_SECTIONS, output_columns, sample_count,
};
use super::schema::{ContactSpec, DriveSpec, PerSection, SceneFile, SectionsSpec, TimeSpec};
use super::validated::{Figures, Scene, TimeSpan};
use crate::contact::ContactLaw;
use crate::model::output::Output;
use crate::model::params::StructuralDamping;
use crate::model::params::{Drive, ForceFlow, ModelParams, SectionParams};
use crate::profile::{Profile, ShapedProfile, ShapedSetpoint};
use crate::shape::MAX_MODES;

/// The broken rules of a profile read from elsewhere (a controller file's feedforward):
/// finite numbers, as many values as times, strictly increasing times; `field` prefixes the
/// names.
pub fn profile_errors(field: &str, profile: &Profile) -> Vec<FieldError> {
    let mut rules = Rules::default();
    rules.profile(field, profile);
    rules.errors
}

/// Collects broken rules.
#[derive(Default)]
struct Rules {
    errors: Vec<FieldError>,
}

impl Rules {
    fn fail(&mut self, field: impl Into<String>, rule: impl Into<String>) {
        self.errors.push(FieldError {
            field: field.into(),
            rule: rule.into(),
        });
    }

    fn positive(&mut self, field: &str, v: f64) {
        if !v.is_finite() || v <= 0.0 {
            self.fail(field, format!("must be a finite number > 0 (got {v})"));
        }
    }

    fn non_negative(&mut self, field: &str, v: f64) {
        if !v.is_finite() || v < 0.0 {
            self.fail(field, format!("must be a finite number >= 0 (got {v})"));
        }
    }

    fn finite(&mut self, field: &str, v: f64) {
        if !v.is_finite() {
            self.fail(field, format!("must be a finite number (got {v})"));
        }
    }

    /// A per-section value: list length, and `check` on every value. Returns one value per
    /// section when the count fits.
    fn per_section<T: Copy>(
        &mut self,
        field: &str,
        spec: &PerSection<T>,
        count: usize,
        mut check: impl FnMut(&mut Self, &str, T),
    ) -> Option<Vec<T>> {
        if let Some(given) = spec.given()
            && given != count
        {
            self.fail(field, format!("has {given} values but sections.count is {count} (give one per section, or one number)"));
            return None;
        }
        let values: Vec<T> = (1..=count)
            .map(|k| spec.get(k).expect("count checked"))
            .collect();
        match spec {
            PerSection::Shared(v) => check(self, field, *v),
            PerSection::Each(list) => {
                for (i, &v) in list.iter().enumerate() {
                    check(self, &format!("{field}[{i}]"), v);
                }
            }
        }
        Some(values)
    }

    fn profile(&mut self, field: &str, p: &Profile) {
        for (part, v) in p.numbers() {
            let name = if part.is_empty() {
                field.to_string()
            } else {
                format!("{field}.{part}")
            };
            self.finite(&name, v);
        }
        match p {
            Profile::Shaped(ShapedProfile::PiecewiseConstant { times, values })
            | Profile::Shaped(ShapedProfile::PiecewiseLinear { times, values })
            | Profile::Shaped(ShapedProfile::PiecewiseCubic { times, values }) => {
                if times.is_empty() {
                    self.fail(format!("{field}.times"), "must not be empty");
                }
                if times.len() != values.len() {
                    self.fail(
                        format!("{field}.values"),
                        format!(
                            "must have one value per time ({} times, {} values)",
                            times.len(),
                            values.len()
                        ),
                    );
                }
                if let Some(i) = times.windows(2).position(|w| w[1] <= w[0]) {
                    self.fail(
                        format!("{field}.times"),
                        format!(
                            "must be strictly increasing (times[{}] = {} follows {})",
                            i + 1,
                            times[i + 1],
                            times[i]
                        ),
                    );
                }
            }
            Profile::Shaped(ShapedProfile::Smoothstep { start, end, .. }) if end <= start => {
                self.fail(
                    format!("{field}.end"),
                    format!("must be after start (start {start}, end {end})"),
                );
            }
            Profile::Shaped(ShapedProfile::SCurve(c)) => {
                self.positive(&format!("{field}.v_max"), c.v_max);
                self.positive(&format!("{field}.a_max"), c.a_max);
                self.positive(&format!("{field}.j_max"), c.j_max);
            }
            Profile::Shaped(ShapedProfile::JerkSegments(m)) => self.jerk_segments(field, m),
            Profile::Shaped(ShapedProfile::Shaped(s)) => self.shaped(field, s),
            Profile::Shaped(ShapedProfile::PositionSchedule(s)) => {
                self.position_schedule(field, s);
            }
            _ => {}
        }
    }

    /// Jerk segments: at least one, none of negative duration, ending at rest (velocity and
    /// acceleration zero to rounding, else the motion would jump at the end).
    fn jerk_segments(&mut self, field: &str, m: &crate::JerkSegments) {
        let segments = format!("{field}.segments");
        if m.segments.is_empty() {
            self.fail(segments.clone(), "must have at least one [duration, jerk]");
        }
        if let Some(i) = m.segments.iter().position(|s| s[0] < 0.0) {
            self.fail(
                segments.clone(),
                format!("durations must be >= 0 (segment {i}: {})", m.segments[i][0]),
            );
            return;
        }
        let (travel, v, a) = m.end();
        let scale = m.segments.iter().map(|s| s[1].abs()).fold(0.0, f64::max) * m.duration();
        if v.abs() > 1e-9 * scale * m.duration() || a.abs() > 1e-9 * scale {
            self.fail(
                segments,
                format!(
                    "must end at rest: they end at {v:.3e} m/s and {a:.3e} m/s^2 after \
                     {travel:.6} m"
                ),
            );
        }
    }

    /// A position schedule: its position profile, knots strictly increasing with one value
    /// each, a positive stretch over an ordered span.
    fn position_schedule(&mut self, field: &str, s: &crate::PositionSchedule) {
        self.profile(&format!("{field}.position"), &s.position);
        if s.positions.is_empty() || s.positions.len() != s.values.len() {
            self.fail(
                format!("{field}.values"),
                format!(
                    "must have one value per position, at least one ({} positions, {} values)",
                    s.positions.len(),
                    s.values.len()
                ),
            );
        }
        if let Some(i) = s.positions.windows(2).position(|w| w[1] <= w[0]) {
            self.fail(
                format!("{field}.positions"),
                format!(
                    "must be strictly increasing (positions[{}] = {} follows {})",
                    i + 1,
                    s.positions[i + 1],
                    s.positions[i]
                ),
            );
        }
        if !s.stretch.iter().all(|&f| f > 0.0) {
            self.fail(format!("{field}.stretch"), "both factors must be > 0");
        }
        if s.over[1] < s.over[0] {
            self.fail(
                format!("{field}.over"),
                "must be [start, end] with end >= start",
            );
        }
    }

    /// A shaped setpoint: its base, impulses of positive amplitude summing to 1 at multiples
    /// >= 0, and a positive period.
    fn shaped(&mut self, field: &str, s: &ShapedSetpoint) {
        self.profile(&format!("{field}.base"), &s.base);
        self.profile(&format!("{field}.period"), &s.period);
        let impulses = format!("{field}.impulses");
        if s.impulses.is_empty() || s.impulses.len() > 16 {
            self.fail(&impulses, "must hold 1 to 16 [amplitude, multiple] pairs");
        }
        if s.impulses
            .iter()
            .any(|&[a, m]| !(a > 0.0 && (0.0..=16.0).contains(&m)))
        {
            self.fail(
                &impulses,
                "each amplitude must be > 0 and each multiple 0 to 16",
            );
        }
        let sum: f64 = s.impulses.iter().map(|i| i[0]).sum();
        if (sum - 1.0).abs() > 1e-9 {
            self.fail(
                &impulses,
                format!("the amplitudes must sum to 1 (they sum to {sum})"),
            );
        }
        let (lo, _) = s.period.range(-1e9, 1e9);
        if lo.is_nan() || lo <= 0.0 {
            self.fail(
                format!("{field}.period"),
                format!("must be > 0 s (its least is {lo})"),
            );
        }
    }
}

/// Checks every rule and builds the validated [`Scene`].
pub(super) fn build(file: SceneFile, origin: &str) -> Result<Scene, SceneError> {
    let mut r = Rules::default();
    // the name and the description go into titles, file headers and comments of emitted
    // code: one line each, so that neither can end a comment or start a line of its own
    for (field, text) in [("name", &file.name), ("description", &file.description)] {
        if let Some(c) = text.chars().find(|c| c.is_control()) {
            r.fail(
                field,
                format!("must be one line of text without control characters (holds {c:?})"),
            );
        }
    }
    let s = &file.sections;
    let n = s.count;
    let SectionChecks {
        n_fits,
        lengths,
        areas,
        inertias,
        densities,
        moduli,
        modes,
    } = section_rules(&mut r, s);
    let damping = damping_rules(&mut r, s);
    if n_fits {
        section_modulus_rules(&mut r, s, n);
    }
    r.non_negative("masses.vehicle", file.masses.vehicle);
    r.non_negative("masses.load", file.masses.load);
    r.non_negative("gravity.g", file.gravity.g);

    let t = &file.time;
    time_rules(&mut r, t);

    // contacts and telescopic positions
    let contact = contact_rules(&mut r, &file, n);
    let positions = position_rules(&mut r, &file, n_fits.then_some(n), lengths.as_deref());

    // drive
    let drive = drive_rules(&mut r, &file.drive);

    if let (Some(a), Some(rho), Some(i), Some(e)) = (&areas, &densities, &inertias, &moduli) {
        product_rules(&mut r, a, rho, i, e);
    }

    if r.errors.is_empty() {
        output_size_rules(&mut r, &file, n);
    }

    reference_rules(&mut r, &file);
    let figures = figure_rules(&mut r, &file);
    accuracy_rule(&mut r, file.accuracy);

    if !r.errors.is_empty() {
        return Err(SceneError::Invalid {
            origin: origin.to_string(),
            errors: r.errors,
        });
    }
    let sections = SectionParams::from_validated(
        lengths.expect("checked"),
        areas.expect("checked"),
        inertias.expect("checked"),
        densities.expect("checked"),
        moduli.expect("checked"),
        modes.expect("checked"),
    );
    let mut params = model_params(&file, sections, contact, positions, drive.expect("checked"));
    params.damping = match damping {
        // the modes of modal damping are those at the scene's start
        StructuralDamping::Modal { ratios, .. } => StructuralDamping::Modal {
            ratios,
            positions: params.positions.iter().map(|p| p.value(t.start)).collect(),
        },
        other => other,
    };
    let mut implausible = super::plausibility::check(&params);
    implausible.extend(basis_rules(&params));
    if !implausible.is_empty() {
        return Err(SceneError::Invalid {
            origin: origin.to_string(),
            errors: implausible,
        });
    }
    Ok(Scene {
        name: file.name.clone(),
        description: file.description.clone(),
        params,
        time: TimeSpan {
            start: t.start,
            end: t.end,
            sample: t.sample,
        },
        references: file.reference.clone(),
        figures,
        accuracy: file.accuracy,
        file,
    })
}

/// `accuracy`, when given, is a whole error that can be asked for.
fn accuracy_rule(r: &mut Rules, accuracy: Option<f64>) {
    let (low, high) = crate::analysis::accuracy::WHOLE_ACCURACY_RANGE;
    if let Some(a) = accuracy
        && !(a.is_finite() && (low..=high).contains(&a))
    {
        r.fail(
            "accuracy",
            format!("must be {low:e} to {high:e} m of tip_rel in all (holds {a:e})"),
        );
    }
}

/// `[figures]` names outputs ([`Output`]), each once, and one-line figure labels.
fn figure_rules(r: &mut Rules, file: &SceneFile) -> Figures {
    let Some(spec) = &file.figures else {
        return Figures::default();
    };
    let mut output = |field: String, name: &str| match Output::parse(name) {
        Some(o) => Some(o),
        None => {
            r.fail(
                &field,
                format!("`{name}` is no output of a run (docs/scenes.md)"),
            );
            None
        }
    };
    let panels = spec.panels.as_ref().map(|names| {
        names
            .iter()
            .enumerate()
            .filter_map(|(i, name)| output(format!("figures.panels[{i}]"), name))
            .collect::<Vec<_>>()
    });
    let paper: Vec<(Output, String)> = spec
        .paper
        .iter()
        .filter_map(|(name, label)| {
            output(format!("figures.paper.{name}"), name).map(|o| (o, label.clone()))
        })
        .collect();
    if let Some(panels) = &panels
        && let Some(i) = (1..panels.len()).find(|&i| panels[..i].contains(&panels[i]))
    {
        r.fail(
            format!("figures.panels[{i}]"),
            "names an output twice".to_string(),
        );
    }
    for (name, label) in &spec.paper {
        if label.chars().any(char::is_control) {
            r.fail(
                format!("figures.paper.{name}"),
                "must be one line of text without control characters".to_string(),
            );
        }
    }
    Figures { panels, paper }
}

/// A scene's per-section values, each checked (`None` where a rule failed).
struct SectionChecks {
    /// Whether the section count is within its limit (nothing is sized by it otherwise).
    n_fits: bool,
    lengths: Option<Vec<f64>>,
    areas: Option<Vec<f64>>,
    inertias: Option<Vec<f64>>,
    densities: Option<Vec<f64>>,
    moduli: Option<Vec<f64>>,
    modes: Option<Vec<usize>>,
}

/// The section count and every per-section value.
fn section_rules(r: &mut Rules, s: &SectionsSpec) -> SectionChecks {
    let n = s.count;
    // checked before anything is sized by it
    let n_fits = (1..=MAX_SECTIONS).contains(&n);
    if !n_fits {
        r.fail(
            "sections.count",
            format!(
                "must be in 1..={MAX_SECTIONS} (got {n}); the limit keeps the model's dense \
                 matrices and eigen analysis small (see docs/scenes.md)"
            ),
        );
    }
    let per_section = |r: &mut Rules, field: &str, spec: &PerSection<f64>| {
        if n_fits {
            r.per_section(field, spec, n, |r, f, v| r.positive(f, v))
        } else {
            None
        }
    };
    let lengths = per_section(r, "sections.length", &s.length);
    let areas = per_section(r, "sections.area", &s.area);
    let inertias = per_section(r, "sections.inertia", &s.inertia);
    let densities = per_section(r, "sections.density", &s.density);
    let moduli = per_section(r, "sections.youngs_modulus", &s.youngs_modulus);
    let modes = if n_fits {
        r.per_section("sections.modes", &s.modes, n, |r, f, v| {
            if !(1..=MAX_MODES).contains(&v) {
                r.fail(f, format!("must be in 1..={MAX_MODES} (got {v})"));
            }
        })
    } else {
        None
    };
    SectionChecks {
        n_fits,
        lengths,
        areas,
        inertias,
        densities,
        moduli,
        modes,
    }
}

/// The reference frequencies the scene records (Hz) are positive.
fn reference_rules(r: &mut Rules, file: &SceneFile) {
    for (i, col) in file.reference.iter().enumerate() {
        for (j, &f) in col.frequencies_hz.iter().enumerate() {
            r.positive(&format!("reference[{i}].frequencies_hz[{j}]"), f);
        }
    }
}

/// Structural damping: modal ratios in `[0, 1)` or Rayleigh coefficients >= 0, not both.
fn damping_rules(r: &mut Rules, s: &SectionsSpec) -> StructuralDamping {
    let rayleigh = s.rayleigh_alpha.is_some() || s.rayleigh_beta.is_some();
    let ratio_rule = |r: &mut Rules, field: &str, v: f64| {
        if !(v.is_finite() && (0.0..1.0).contains(&v)) {
            r.fail(
                field,
                format!("must be a damping ratio in [0, 1) (got {v})"),
            );
        }
    };
    match (&s.damping_ratio, rayleigh) {
        (Some(_), true) => {
            r.fail(
                "sections.damping_ratio",
                "give either modal damping (damping_ratio) or Rayleigh damping (rayleigh_alpha, \
                 rayleigh_beta), not both",
            );
            StructuralDamping::None
        }
        (Some(PerSection::Shared(v)), false) => {
            ratio_rule(r, "sections.damping_ratio", *v);
            StructuralDamping::Modal {
                ratios: vec![*v],
                positions: Vec::new(),
            }
        }
        (Some(PerSection::Each(list)), false) => {
            if list.is_empty() {
                r.fail("sections.damping_ratio", "must not be an empty list");
            }
            for (i, &v) in list.iter().enumerate() {
                ratio_rule(r, &format!("sections.damping_ratio[{i}]"), v);
            }
            StructuralDamping::Modal {
                ratios: list.clone(),
                positions: Vec::new(),
            }
        }
        (None, true) => {
            let alpha = s.rayleigh_alpha.unwrap_or(0.0);
            let beta = s.rayleigh_beta.unwrap_or(0.0);
            r.non_negative("sections.rayleigh_alpha", alpha);
            r.non_negative("sections.rayleigh_beta", beta);
            StructuralDamping::Rayleigh { alpha, beta }
        }
        (None, false) => StructuralDamping::None,
    }
}

/// Section moduli or heights (for stresses): positive, one per section, not both.
fn section_modulus_rules(r: &mut Rules, s: &SectionsSpec, n: usize) {
    if s.section_modulus.is_some() && s.height.is_some() {
        r.fail(
            "sections.height",
            "give either section_modulus or height (W = 2 I / h), not both",
        );
    }
    if let Some(w) = &s.section_modulus {
        r.per_section("sections.section_modulus", w, n, |r, f, v| r.positive(f, v));
    }
    if let Some(h) = &s.height {
        r.per_section("sections.height", h, n, |r, f, v| r.positive(f, v));
    }
}

/// The time span's rules.
fn time_rules(r: &mut Rules, t: &TimeSpec) {
    r.finite("time.start", t.start);
    r.finite("time.end", t.end);
    if t.start.is_finite() && t.end.is_finite() && t.end <= t.start {
        r.fail(
            "time.end",
            format!(
                "the time span is empty: end ({}) must be after start ({})",
                t.end, t.start
            ),
        );
    }
    r.positive("time.sample", t.sample);
    if t.sample > t.end - t.start && t.end > t.start {
        r.fail(
            "time.sample",
            format!(
                "must not exceed the time span ({} s, got {})",
                t.end - t.start,
                t.sample
            ),
        );
    }
}

/// The contact law's rules; `None` for a single section without one.
fn contact_rules(r: &mut Rules, file: &SceneFile, n: usize) -> Option<ContactSpec> {
    match (&file.contact, n) {
        (Some(c), _) => {
            if !(2..=MAX_CONTACT_POINTS).contains(&c.points) {
                r.fail(
                    "contact.points",
                    format!(
                        "must be in 2..={MAX_CONTACT_POINTS} (got {}); more points only stiffen \
                         the coupling (see docs/scenes.md)",
                        c.points
                    ),
                );
            }
            r.positive("contact.stiffness", c.stiffness);
            r.non_negative("contact.damping", c.damping);
            r.non_negative("contact.clearance", c.clearance);
            Some(c.clone())
        }
        (None, 1) => None,
        (None, _) => {
            r.fail("contact", "is required when there is more than one section");
            None
        }
    }
}

/// The telescopic positions' rules: one profile per overlap, each keeping its overlap in
/// range over the span (`n`: the section count when it fits its limit).
fn position_rules(
    r: &mut Rules,
    file: &SceneFile,
    n: Option<usize>,
    lengths: Option<&[f64]>,
) -> Vec<Profile> {
    let t = &file.time;
    let positions = file
        .telescope
        .as_ref()
        .map(|t| t.positions.clone())
        .unwrap_or_default();
    if let Some(n) = n
        && positions.len() != n - 1
    {
        r.fail(
            "telescope.positions",
            format!(
                "must hold one profile per overlap, a_2..a_n: {} expected, {} given",
                n - 1,
                positions.len()
            ),
        );
    }
    for (i, p) in positions.iter().enumerate() {
        let field = format!("telescope.positions[{i}]");
        let before = r.errors.len();
        r.profile(&field, p);
        // overlap o_k = l_{k-1} - a_k must stay in (0, min(l_{k-1}, l_k)] at every time
        if let (Some(l), Some(n)) = (lengths, n)
            && r.errors.len() == before
            && t.end > t.start
            && i + 1 < n
        {
            let (l_out, l_in) = (l[i], l[i + 1]);
            let (a_lo, a_hi) = p.range(t.start, t.end);
            let (o_lo, o_hi) = (l_out - a_hi, l_out - a_lo);
            let o_max = l_out.min(l_in);
            if o_lo <= 0.0 || o_hi > o_max {
                r.fail(
                    field,
                    format!(
                        "overlap l_{k1} - a_{k} must stay in (0, min(l_{k1}, l_{k})] = (0, {o_max}] over the time span, \
                         i.e. a_{k} in [{:.6}, {l_out}); the profile ranges over [{a_lo}, {a_hi}]",
                        l_out - o_max,
                        k = i + 2,
                        k1 = i + 1,
                    ),
                );
            }
        }
    }

    positions
}

/// The drive's rules: a force or a motion with a continuous velocity.
fn drive_rules(r: &mut Rules, d: &DriveSpec) -> Option<Drive> {
    match (&d.force, &d.motion) {
        (Some(f), None) => {
            r.profile("drive.force", f);
            Some(Drive::Force(f.clone()))
        }
        (None, Some(m)) => {
            r.profile("drive.motion", m);
            if !m.has_continuous_rate() {
                r.fail(
                    "drive.motion",
                    "a prescribed motion needs a continuous velocity: use a number or kind = \"smoothstep\", \"s-curve\", \"jerk-segments\" or \"shaped\"",
                );
            }
            Some(Drive::Motion(m.clone()))
        }
        (Some(_), Some(_)) => {
            r.fail("drive", "give either `force` or `motion`, not both");
            None
        }
        (None, None) => {
            r.fail("drive", "needs `force` (N) or `motion` (m)");
            None
        }
    }
}

/// The products the model uses (mass per length, bending stiffness) must exist in double
/// precision too.
fn product_rules(r: &mut Rules, a: &[f64], rho: &[f64], i: &[f64], e: &[f64]) {
    for k in 0..a.len() {
        let per_length = rho[k] * a[k];
        if !(per_length.is_finite() && per_length > 0.0) {
            r.fail(
                format!("sections.area[{k}] and sections.density[{k}]"),
                format!(
                    "their product, the mass per length, must be a finite number > 0 in \
                         double precision (got {} x {} = {per_length})",
                    a[k], rho[k]
                ),
            );
        }
        let bending = e[k] * i[k];
        if !(bending.is_finite() && bending > 0.0) {
            r.fail(
                format!("sections.youngs_modulus[{k}] and sections.inertia[{k}]"),
                format!(
                    "their product, the bending stiffness, must be a finite number > 0 in \
                         double precision (got {} x {} = {bending})",
                    e[k], i[k]
                ),
            );
        }
    }
}

/// The output's size, before a run allocates it.
fn output_size_rules(r: &mut Rules, file: &SceneFile, n: usize) {
    let (t, d) = (&file.time, &file.drive);
    let points = file.contact.as_ref().map_or(0, |c| c.points);
    let columns = output_columns(n, points, d.motion.is_some());
    let samples = sample_count(t.start, t.end, t.sample);
    let values = samples.saturating_mul(columns);
    if values > MAX_OUTPUT_VALUES {
        r.fail(
            "time.sample",
            format!(
                "{} s over a span of {} s gives {} samples of {columns} columns, more than \
                     the limit of {MAX_OUTPUT_VALUES} output values (800 MB in memory); raise \
                     time.sample to at least {:.3e} s or shorten the span",
                t.sample,
                t.end - t.start,
                if samples == u64::MAX {
                    "about 1e18 or more".to_string()
                } else {
                    samples.to_string()
                },
                (t.end - t.start) * columns as f64 / MAX_OUTPUT_VALUES as f64
            ),
        );
    }
}

/// The static correction shapes' count per section stays within what a section holds.
fn basis_rules(params: &ModelParams) -> Vec<FieldError> {
    use crate::shape::section_basis::MAX_SECTION_COORDINATES;
    let coordinates = params.coordinates();
    match coordinates
        .iter()
        .position(|&c| c > MAX_SECTION_COORDINATES)
    {
        Some(k) => vec![FieldError {
            field: "sections.basis".into(),
            rule: format!(
                "\"modes+static\" gives section {} {} coordinates ({} modes and {} static \
                 correction shapes, from its contact stations); at most \
                 {MAX_SECTION_COORDINATES}: fewer modes or contact points",
                k + 1,
                coordinates[k],
                params.sections[k].modes,
                coordinates[k] - params.sections[k].modes
            ),
        }],
        None => Vec::new(),
    }
}

impl SectionParams {
    /// The sections from their validated per-section values.
    fn from_validated(
        lengths: Vec<f64>,
        areas: Vec<f64>,
        inertias: Vec<f64>,
        densities: Vec<f64>,
        moduli: Vec<f64>,
        modes: Vec<usize>,
    ) -> Vec<SectionParams> {
        (0..lengths.len())
            .map(|k| SectionParams {
                length: lengths[k],
                mass_per_length: densities[k] * areas[k],
                bending_stiffness: moduli[k] * inertias[k],
                modes: modes[k],
            })
            .collect()
    }
}

/// The model's parameters from the validated parts.
fn model_params(
    file: &SceneFile,
    sections: Vec<SectionParams>,
    contact: Option<ContactSpec>,
    positions: Vec<Profile>,
    drive: Drive,
) -> ModelParams {
    let contact = contact.unwrap_or(super::schema::ContactSpec {
        points: 2,
        stiffness: 1.0,
        damping: 0.0,
        clearance: 0.0,
    });
    ModelParams {
        sections,
        vehicle_mass: file.masses.vehicle,
        load_mass: file.masses.load,
        gravity: file.gravity.g,
        // gravity off: every prestress term is zero, so the model without them is exact
        force_flow: if file.gravity.g == 0.0 {
            ForceFlow::None
        } else {
            file.gravity.force_flow
        },
        contact_points: contact.points,
        contact: ContactLaw {
            stiffness: contact.stiffness,
            damping: contact.damping,
            clearance: contact.clearance,
        },
        positions,
        drive,
        damping: StructuralDamping::None,
        basis: file.sections.basis,
    }
}
