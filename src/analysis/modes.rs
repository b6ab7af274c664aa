//! Natural frequencies and mode shapes of a scene, linearized about the straight state with
//! closed contacts (`f = c xi`: clearance and contact damping ignored, as for the paper's
//! Table I), with published reference columns beside them.
//!
//! ```
//! use telescopic::analysis::modes::{ModesOptions, compute_modes};
//! use telescopic::Scene;
//!
//! let scene = Scene::load("scenes/test-rig.toml".as_ref(), &[])?;
//! let report = compute_modes(&scene, &ModesOptions::default())?;
//! assert_eq!(report.rigid_modes, 1); // the vehicle's translation
//! assert!((report.frequencies_hz[0] - 0.498).abs() < 1e-3); // f1 of the test rig, Hz
//! # Ok::<(), telescopic::Error>(())
//! ```

use crate::OptionName;
use crate::run::models::{ModelChoice, ModelRegistry};
use crate::{Error, Result};
use serde::Serialize;
use std::fmt::Write as _;
use telescopic_runtime::nalgebra::DMatrix;
use telescopic_runtime::{
    CONTACT_MODE_SHARE, ModalAnalysis, Model, Scene, damped_modes, modal_analysis, sample_shape,
};

/// Options of [`compute_modes`].
#[derive(Debug, Clone, PartialEq)]
pub struct ModesOptions {
    /// Time (s) whose telescopic positions are used; default: the scene's start.
    pub at: Option<f64>,
    /// How many frequencies to report (default: all).
    pub count: Option<usize>,
    /// Also sample mode shapes at this many points per section (2 or more).
    pub shapes: Option<usize>,
    /// Which model computes the matrices.
    pub model: ModelChoice,
    /// Where generated models come from (default: the committed ones).
    pub models: ModelRegistry,
    /// The memory the sampled shapes may take (bytes,
    /// [`crate::run::memory::DEFAULT_MEMORY_BUDGET`] by default).
    pub memory_budget: u64,
}

impl Default for ModesOptions {
    fn default() -> Self {
        ModesOptions {
            at: None,
            count: None,
            shapes: None,
            model: ModelChoice::default(),
            models: ModelRegistry::default(),
            memory_budget: crate::run::memory::DEFAULT_MEMORY_BUDGET,
        }
    }
}

/// Most points per section of a sampled mode shape.
pub const MAX_SHAPE_POINTS: usize = 10_000;

/// One mode shape: displacement along each section, normalized to a largest value of 1.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModeShape {
    /// The mode's frequency (Hz).
    pub frequency_hz: f64,
    /// `w_k(x)` at evenly spaced points from the foot to the top of each section.
    pub sections: Vec<Vec<f64>>,
}

/// A reference column printed beside ours.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ReferenceColumn {
    /// Column heading.
    pub label: String,
    /// Frequencies (Hz).
    pub frequencies_hz: Vec<f64>,
}

/// What carries a mode: the beams, or the contact springs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ModeKind {
    /// Most of the mode's strain energy is in the sections' bending.
    Structural,
    /// Most of it (more than [`CONTACT_MODE_SHARE`]) is in the contact springs: a section
    /// rocking in its guide, its frequency set by the contact stiffness `c` (and at the mercy
    /// of the clearance in a run).
    Contact,
}

/// The result of [`compute_modes`]; its JSON form is `telescopic modes --json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModesReport {
    /// The scene's name.
    pub scene: String,
    /// Time of the contact geometry (s).
    pub time_s: f64,
    /// Which model computed the matrices.
    pub model: String,
    /// Natural frequencies (Hz), ascending, rigid modes excluded.
    pub frequencies_hz: Vec<f64>,
    /// Damped natural frequencies (Hz), one per frequency: structural damping and the closed
    /// contacts' damping `d` (see [`telescopic_runtime::damped_modes()`]).
    pub damped_frequencies_hz: Vec<f64>,
    /// Damping ratios (1), one per frequency.
    pub damping_ratios: Vec<f64>,
    /// Share of each mode's strain energy in the contact springs, `c sum (g_c . v)^2 / omega^2`.
    pub contact_energy_shares: Vec<f64>,
    /// Each mode's kind: contact when its contact share exceeds [`CONTACT_MODE_SHARE`].
    pub kinds: Vec<ModeKind>,
    /// The scene's structural damping, in words.
    pub structural_damping: String,
    /// Rigid-body modes (zero frequency), counted, not listed.
    pub rigid_modes: usize,
    /// Growth rates (1/s) of modes buckled by the axial load.
    pub unstable_growth_rates_per_s: Vec<f64>,
    /// Modes per section.
    pub modes_per_section: Vec<usize>,
    /// Generalized coordinates.
    #[serde(skip)]
    pub dof: usize,
    /// Contact stiffness `c` (N/m).
    #[serde(skip)]
    pub contact_stiffness: f64,
    /// Contact damping `d` (N s/m).
    #[serde(skip)]
    pub contact_damping: f64,
    /// Published columns to print beside ours.
    #[serde(skip)]
    pub references: Vec<ReferenceColumn>,
    /// Mode shapes, when asked for.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mode_shapes: Option<Vec<ModeShape>>,
    /// The mode shapes in the model's computing coordinates, mass-normalized, one per
    /// reported frequency (not in the JSON document: `mode_shapes` samples them).
    #[serde(skip)]
    pub vectors: Vec<Vec<f64>>,
    /// Set when the model choice fell back to the assembled model.
    #[serde(skip)]
    pub note: Option<String>,
}

/// Natural frequencies (and optionally mode shapes) of `scene`.
///
/// # Errors
/// [`Error::Option`] for a time outside the span or too few shape points; [`Error::Model`]
/// or [`Error::Eigen`] when the model or its eigen analysis fails.
pub fn compute_modes(scene: &Scene, options: &ModesOptions) -> Result<ModesReport> {
    let t = options.at.unwrap_or(scene.time.start);
    if !(t.is_finite() && t >= scene.time.start && t <= scene.time.end) {
        return Err(Error::option(
            OptionName::ModesAt,
            format!(
                "{t}: must lie in the scene's time span [{}, {}] s",
                scene.time.start, scene.time.end
            ),
        ));
    }
    if let Some(points) = options.shapes
        && !(2..=MAX_SHAPE_POINTS).contains(&points)
    {
        return Err(Error::option(
            OptionName::Shapes,
            format!(
                "must be 2 to {MAX_SHAPE_POINTS} points per section (got {points}); more add \
                 nothing a plot or table can show"
            ),
        ));
    }
    let chosen = options.models.build(&scene.params, options.model)?;
    let model = chosen.model.as_ref();
    let modal = modal_analysis(model, t).map_err(|error| Error::Eigen {
        scene: scene.name.clone(),
        error,
    })?;
    let count = options
        .count
        .unwrap_or(modal.frequencies_hz.len())
        .min(modal.frequencies_hz.len());
    let damped = damped_modes(model, &modal).map_err(|error| Error::Eigen {
        scene: scene.name.clone(),
        error,
    })?;
    let shares = contact_energy_shares(model, &modal);
    check_shape_memory(scene, options, count)?;
    let mode_shapes = options.shapes.map(|points| {
        modal.shapes[..count]
            .iter()
            .zip(&modal.frequencies_hz)
            .map(|(v, &f)| {
                let mut sections = sample_shape(model, v, points);
                let peak = sections
                    .iter()
                    .flatten()
                    .fold(0.0_f64, |m, w| m.max(w.abs()));
                sections.iter_mut().flatten().for_each(|w| *w /= peak);
                ModeShape {
                    frequency_hz: f,
                    sections,
                }
            })
            .collect()
    });
    Ok(ModesReport {
        scene: scene.name.clone(),
        time_s: t,
        model: chosen.description.clone(),
        frequencies_hz: modal.frequencies_hz[..count].to_vec(),
        damped_frequencies_hz: damped[..count].iter().map(|d| d.damped_hz).collect(),
        damping_ratios: damped[..count].iter().map(|d| d.ratio).collect(),
        kinds: shares[..count]
            .iter()
            .map(|&s| ModeKind::of_share(s))
            .collect(),
        contact_energy_shares: shares[..count].to_vec(),
        structural_damping: scene.params.damping.describe(),
        rigid_modes: modal.rigid_modes,
        unstable_growth_rates_per_s: modal.unstable_growth_rates.clone(),
        modes_per_section: scene.params.modes(),
        dof: model.dof(),
        contact_stiffness: scene.params.contact.stiffness,
        contact_damping: scene.params.contact.damping,
        references: scene
            .references
            .iter()
            .map(|r| ReferenceColumn {
                label: r.label.clone(),
                frequencies_hz: r.frequencies_hz.clone(),
            })
            .collect(),
        mode_shapes,
        vectors: modal.shapes[..count]
            .iter()
            .map(|v| v.as_slice().to_vec())
            .collect(),
        note: chosen.note,
    })
}

/// Refuses sampled shapes of `count` modes that would exceed the memory budget.
fn check_shape_memory(scene: &Scene, options: &ModesOptions, count: usize) -> Result<()> {
    let Some(points) = options.shapes else {
        return Ok(());
    };
    // each shape holds its values and positions at every point of every section
    let values = (count * scene.params.sections.len() * points * 2) as u64;
    crate::run::memory::check(
        values.saturating_mul(8),
        options.memory_budget,
        (Some(OptionName::Shapes), format!("scene {}", scene.name)),
        format!("{count} mode shapes of {points} points per section"),
        "the points per section or the count of modes",
    )
}

impl ModeKind {
    /// The kind of a mode whose strain energy is `share` in the contact springs.
    fn of_share(share: f64) -> Self {
        if share > CONTACT_MODE_SHARE {
            ModeKind::Contact
        } else {
            ModeKind::Structural
        }
    }
}

/// The share of each mode's strain energy stored in the contact springs.
fn contact_energy_shares(model: &dyn Model, modal: &ModalAnalysis) -> Vec<f64> {
    let (n, nc) = (model.dof(), model.layout().contact_count());
    let mut g = DMatrix::zeros(n, nc);
    let mut gdot = DMatrix::zeros(n, nc);
    model.contact_vectors(modal.time, &mut g, &mut gdot);
    telescopic_runtime::contact_energy_shares(modal, &g, model.params().contact.stiffness)
}

impl ModesReport {
    /// The JSON document (`telescopic modes --json`).
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("plain data serializes")
    }

    /// The text table: ours, then each reference column with the difference in percent, and
    /// the mode shapes when sampled.
    pub fn to_table(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "{}: {} section(s), modes per section {:?}, {} coordinates; contacts closed (c = {} \
             N/m), geometry at t = {} s",
            self.scene,
            self.modes_per_section.len(),
            self.modes_per_section,
            self.dof,
            self.contact_stiffness,
            self.time_s
        );
        let _ = writeln!(s, "model: {}", self.model);
        let _ = writeln!(s, "rigid-body modes: {} (not listed)", self.rigid_modes);
        if !self.unstable_growth_rates_per_s.is_empty() {
            let _ = writeln!(
                s,
                "UNSTABLE: {} mode(s) with negative stiffness (buckled under the axial load), \
                 growth rates {:?} 1/s",
                self.unstable_growth_rates_per_s.len(),
                self.unstable_growth_rates_per_s
            );
        }
        let _ = writeln!(
            s,
            "structural damping: {}; contact damping d = {} N s/m",
            self.structural_damping, self.contact_damping
        );
        let mut header = format!(
            "{:>5} {:>14} {:>14} {:>10} {:>10}",
            "mode", "ours [Hz]", "damped [Hz]", "zeta", "kind"
        );
        for r in &self.references {
            let _ = write!(header, " {:>16} {:>8}", format!("{} [Hz]", r.label), "diff");
        }
        let _ = writeln!(s, "{header}");
        for (i, f) in self.frequencies_hz.iter().enumerate() {
            let mut line = format!(
                "{:>5} {:>14.6} {:>14.6} {:>10.3e} {:>10}",
                format!("f{}", i + 1),
                f,
                self.damped_frequencies_hz[i],
                self.damping_ratios[i],
                match self.kinds[i] {
                    ModeKind::Structural => "structural",
                    ModeKind::Contact => "contact",
                }
            );
            for r in &self.references {
                match r.frequencies_hz.get(i) {
                    // difference as the paper's Table I states it: (reference - ours) / reference
                    Some(&fr) => {
                        let _ = write!(line, " {:>16} {:>7.2}%", fr, 100.0 * (fr - f) / fr);
                    }
                    None => {
                        let _ = write!(line, " {:>16} {:>8}", "", "");
                    }
                }
            }
            let _ = writeln!(s, "{line}");
        }
        if self.kinds.contains(&ModeKind::Contact) {
            let _ = writeln!(
                s,
                "contact: more than half of the mode's strain energy is in the contact springs (a \
                 section rocking in its guide; with clearance the run never sees it as a steady \
                 mode)"
            );
        }
        if !self.references.is_empty() {
            let _ = writeln!(
                s,
                "diff = (reference - ours) / reference, as in the paper's Table I"
            );
        }
        if let Some(shapes) = &self.mode_shapes {
            s.push_str("\nmode shapes (w along each section, foot to top, largest |w| = 1):\n");
            for (i, m) in shapes.iter().enumerate() {
                let _ = writeln!(s, "f{} = {:.6} Hz", i + 1, m.frequency_hz);
                for (k, w) in m.sections.iter().enumerate() {
                    let vals: Vec<String> = w.iter().map(|v| format!("{v:+.3}")).collect();
                    let _ = writeln!(s, "  section {}: {}", k + 1, vals.join(" "));
                }
            }
        }
        s
    }
}
