//! The smallest model a scene needs.
//!
//! Raises the modes per section (the same number on every section) from 1 to `--max-modes`,
//! simulating the scene and computing the first three frequencies with closed contacts for
//! each. The quantities compared between models: the frequencies, and the peak and RMS of
//! `tip_rel` over the whole scene (with clearance the pointwise motion of two different
//! models parts after the first impacts, like two runs of one model beyond the
//! predictability horizon, so the pointwise difference cannot converge; for `l_S = 0` the
//! largest pointwise difference relative to the peak is compared too). The smallest model is
//! the first whose change to the next one is below `--tol` in every quantity. Then the
//! contacts per overlap are raised from 2 the same way, at that number of modes.
//!
//! Every model is the quadrature-assembled one, so costs compare like with like (a generated
//! model exists only for the configurations in generated/models.toml).

use crate::OptionName;
use crate::analysis::metrics::peak_and_rms;
use crate::report::Reporter;
use crate::run::PreparedRun;
use crate::run::models::ChosenModel;
use crate::{Error, Result};
use std::io::Write;
use telescopic_runtime::Output;
use telescopic_runtime::scene::limits::MAX_CONTACT_POINTS;
use telescopic_runtime::{MAX_MODES, Scene, Settings, auto_method, modal_analysis};

/// Options of [`converge`].
#[derive(Debug, Clone, PartialEq)]
pub struct ConvergeOptions {
    /// Largest relative change between consecutive models that counts as converged, in
    /// (0, 1).
    pub tol: f64,
    /// Most modes per section tried, 2 to 30 (default 12).
    pub max_modes: usize,
    /// Most contact points per overlap tried from 2, 3 to 32 (default 5).
    pub max_contacts: usize,
    /// The memory a run's outputs may take (bytes,
    /// [`crate::run::memory::DEFAULT_MEMORY_BUDGET`] by default): a longer run is refused
    /// before it starts.
    pub memory_budget: u64,
}

impl Default for ConvergeOptions {
    fn default() -> Self {
        ConvergeOptions {
            tol: 1e-2,
            max_modes: 12,
            max_contacts: 5,
            memory_budget: crate::run::memory::DEFAULT_MEMORY_BUDGET,
        }
    }
}

/// One model of the sweep and what it gave.
#[derive(Debug, Clone, PartialEq)]
pub struct Trial {
    /// Modes per section.
    pub modes: usize,
    /// Contact points per overlap.
    pub contacts: usize,
    /// Generalized coordinates.
    pub dof: usize,
    /// Wall time of the scene (s).
    pub wall: f64,
    /// First three frequencies with closed contacts (Hz).
    pub frequencies: Vec<f64>,
    /// Peak of `|tip_rel|` over the scene (m).
    pub tip_peak: f64,
    /// RMS of `tip_rel` over the scene (m).
    pub tip_rms: f64,
    /// `tip_rel` at every sample (m).
    pub tip: Vec<f64>,
}

/// The result of [`converge`].
#[derive(Debug, Clone, PartialEq)]
pub struct Convergence {
    /// The scene's name.
    pub scene: String,
    /// The tolerance asked for.
    pub tol: f64,
    /// Contact points per overlap of the scene.
    pub contacts: usize,
    /// Whether pointwise `tip_rel` differences were compared (`l_S = 0`).
    pub pointwise: bool,
    /// One trial per modes per section, 1 to `max_modes`, at the scene's contacts.
    pub by_modes: Vec<Trial>,
    /// Index into `by_modes` of the smallest converged model.
    pub chosen: usize,
    /// One trial per contact count, 2 to `max_contacts`, at the chosen modes.
    pub by_contacts: Vec<Trial>,
    /// The smallest converged contact count, if any.
    pub contacts_needed: Option<usize>,
}

impl Trial {
    /// Wall time, frequencies and `tip_rel` statistics, for the progress lines.
    fn describe(&self) -> String {
        let frequencies: Vec<String> = self.frequencies.iter().map(|f| format!("{f:.4}")).collect();
        format!(
            "wall {:.4} s, f1..f3 {frequencies:?} Hz, tip_rel peak {:.5e} m, RMS {:.5e} m",
            self.wall, self.tip_peak, self.tip_rms
        )
    }
}

impl Trial {
    /// Largest relative difference to `other` over the compared quantities.
    pub fn change(&self, other: &Trial, pointwise: bool) -> f64 {
        let rel = |a: f64, b: f64| (a - b).abs() / b.abs().max(1e-300);
        let mut change = rel(self.tip_peak, other.tip_peak).max(rel(self.tip_rms, other.tip_rms));
        for (a, b) in self.frequencies.iter().zip(&other.frequencies) {
            change = change.max(rel(*a, *b));
        }
        if pointwise {
            let worst = self
                .tip
                .iter()
                .zip(&other.tip)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            change = change.max(worst / other.tip_peak.max(1e-300));
        }
        change
    }
}

/// Simulates `scene` with `modes` per section and `contacts` per overlap.
fn trial(
    scene: &Scene,
    (modes, contacts): (usize, usize),
    memory_budget: u64,
    reporter: &dyn Reporter,
) -> Result<Trial> {
    let mut scene = scene.clone();
    for s in &mut scene.params.sections {
        s.modes = modes;
    }
    scene.params.contact_points = contacts;
    let what = format!("{modes} modes per section, {contacts} contacts per overlap");
    let in_trial = |error: Error| Error::Trial {
        what: what.clone(),
        error: Box::new(error),
    };
    let chosen = ChosenModel::assembled(&scene.params).map_err(in_trial)?;
    let (method, _) = auto_method(&scene.params);
    let run = PreparedRun::with_model(&scene, chosen, (method, Settings::default()), memory_budget);
    let model = run.model();
    let modal = modal_analysis(model, scene.time.start).map_err(|error| {
        in_trial(Error::Eigen {
            scene: scene.name.clone(),
            error,
        })
    })?;
    let traj = run.integrate(reporter).map_err(in_trial)?;
    let tip = traj
        .column_of(Output::TipRel)
        .expect("every model has tip_rel");
    let (tip_peak, tip_rms) = peak_and_rms(&tip);
    Ok(Trial {
        modes,
        contacts,
        dof: model.dof(),
        wall: traj.stats.wall.as_secs_f64(),
        frequencies: modal.frequencies_hz.iter().take(3).copied().collect(),
        tip_peak,
        tip_rms,
        tip,
    })
}

/// The first trial whose change to the next is below `tol` (index), if any.
fn first_converged(trials: &[Trial], tol: f64, pointwise: bool) -> Option<usize> {
    trials
        .windows(2)
        .position(|w| w[0].change(&w[1], pointwise) < tol)
}

/// The smallest model `scene` needs: modes per section raised from 1, then contacts per
/// overlap from 2, until the change to the next model is below `options.tol`. Progress
/// lines go to `reporter`.
///
/// # Errors
/// [`Error::Option`] for options out of range; [`Error::Analysis`] when no model up to
/// `max_modes` converges; [`Error::Trial`] when a model fails.
pub fn converge(
    scene: &Scene,
    options: &ConvergeOptions,
    reporter: &dyn Reporter,
) -> Result<Convergence> {
    if !(options.tol > 0.0 && options.tol < 1.0) {
        return Err(Error::option(
            OptionName::ConvergeTol,
            format!("must be a relative change in (0, 1) (got {})", options.tol),
        ));
    }
    if !(2..=MAX_MODES).contains(&options.max_modes) {
        return Err(Error::option(
            OptionName::MaxModes,
            format!(
                "must be 2 to {MAX_MODES} (got {}); the shape functions are checked up to mode \
                 {MAX_MODES}",
                options.max_modes
            ),
        ));
    }
    if !(3..=MAX_CONTACT_POINTS).contains(&options.max_contacts) {
        return Err(Error::option(
            OptionName::MaxContacts,
            format!(
                "must be 3 to {MAX_CONTACT_POINTS} (got {}): contacts are raised from 2 to at \
                 most the scene limit",
                options.max_contacts
            ),
        ));
    }
    let contacts = scene.params.contact_points;
    let pointwise = scene.params.contact.is_linear();
    let (method, _) = auto_method(&scene.params);
    reporter.note(&format!(
        "{}: modes per section 1..{} with {contacts} contacts per overlap, method {method}, \
         assembled models",
        scene.name, options.max_modes
    ));
    let mut by_modes = Vec::new();
    for n in 1..=options.max_modes {
        let t = trial(scene, (n, contacts), options.memory_budget, reporter)?;
        reporter.note(&format!("  N = {n:2}: dof {:3}, {}", t.dof, t.describe()));
        by_modes.push(t);
    }
    let Some(chosen) = first_converged(&by_modes, options.tol, pointwise) else {
        return Err(Error::Analysis(format!(
            "no model up to {} modes per section changes by less than {} to the next; raise \
             the largest number of modes or the tolerance",
            options.max_modes, options.tol
        )));
    };
    let modes = by_modes[chosen].modes;
    reporter.note(&format!(
        "contacts per overlap 2..{} at {modes} modes per section",
        options.max_contacts
    ));
    let mut by_contacts = Vec::new();
    for c in 2..=options.max_contacts {
        let t = trial(scene, (modes, c), options.memory_budget, reporter)?;
        reporter.note(&format!("  n_c = {c}: {}", t.describe()));
        by_contacts.push(t);
    }
    let contacts_needed =
        first_converged(&by_contacts, options.tol, pointwise).map(|i| by_contacts[i].contacts);
    Ok(Convergence {
        scene: scene.name.clone(),
        tol: options.tol,
        contacts,
        pointwise,
        by_modes,
        chosen,
        by_contacts,
        contacts_needed,
    })
}

impl Convergence {
    /// The answer as text: the smallest model, its change and speed-up, the contacts.
    pub fn render(&self) -> String {
        let chosen = &self.by_modes[self.chosen];
        let largest = self.by_modes.last().expect("at least two models");
        let contacts = self.contacts;
        let mut s = format!(
            "smallest model for tol {}: {} modes per section ({} dof) with {contacts} contacts \
             per overlap\n",
            self.tol, chosen.modes, chosen.dof
        );
        s += &format!(
            "  its change to {} modes: {:.3e}; its difference to the largest model tried ({} \
             modes): {:.3e}\n",
            chosen.modes + 1,
            chosen.change(&self.by_modes[self.chosen + 1], self.pointwise),
            largest.modes,
            chosen.change(largest, self.pointwise)
        );
        s += &format!(
            "  wall time {:.4} s against {:.4} s: {:.1}x faster than the largest model\n",
            chosen.wall,
            largest.wall,
            largest.wall / chosen.wall
        );
        s += &match self.contacts_needed {
            Some(c) if c == contacts => {
                format!("  contacts per overlap: {c} (the scene's) already converged to tol\n")
            }
            Some(c) => format!(
                "  contacts per overlap: {c} would do (the scene has {contacts}; the paper's \
                 contacts are physical points, so this is for information)\n"
            ),
            None => format!(
                "  contacts per overlap: no count up to {} changes by less than tol to the \
                 next\n",
                self.by_contacts.last().map_or(0, |t| t.contacts)
            ),
        };
        s
    }

    /// The CSV table: one row per model tried, with its error against the largest model of
    /// its series.
    ///
    /// # Errors
    /// The writer's error.
    pub fn write_table(&self, w: &mut dyn Write) -> std::io::Result<()> {
        let largest = self.by_modes.last().expect("at least two models");
        writeln!(
            w,
            "modes,contacts,dof,wall_s,f1_hz,f2_hz,f3_hz,tip_peak_m,tip_rms_m,error_vs_largest"
        )?;
        for t in self.by_modes.iter().chain(&self.by_contacts) {
            let reference = if t.contacts == self.contacts {
                largest
            } else {
                self.by_contacts.last().expect("contacts tried")
            };
            let f = |i: usize| t.frequencies.get(i).copied().unwrap_or(f64::NAN);
            writeln!(
                w,
                "{},{},{},{:e},{},{},{},{:e},{:e},{:e}",
                t.modes,
                t.contacts,
                t.dof,
                t.wall,
                f(0),
                f(1),
                f(2),
                t.tip_peak,
                t.tip_rms,
                t.change(reference, self.pointwise)
            )?;
        }
        Ok(())
    }
}
