//! A finished simulation: what ran (scene, model, method, specializations), every sample,
//! the error budget, and the run summary and CSV.

use super::error_budget::ErrorBudget;
use super::method::Plan;
use super::trajectory::Trajectory;
use crate::Result;
use std::io::Write;
use std::path::Path;
use telescopic_runtime::Output;
use telescopic_runtime::integrate::StepControl;

/// A finished simulation: what ran and every sample.
#[derive(Debug, Clone, PartialEq)]
pub struct Simulation {
    /// The scene's name.
    pub scene: String,
    /// The scene's time span `(start, end)` (s).
    pub span: (f64, f64),
    /// Which model ran it (`generated model <key>` or `quadrature-assembled model`).
    pub model: String,
    /// The method and settings.
    pub plan: Plan,
    /// The specializations that applied, one phrase each.
    pub specializations: Vec<telescopic_runtime::Specialization>,
    /// The samples and the run's statistics.
    pub trajectory: Trajectory,
    /// Modes per section of the model that ran.
    pub modes: Vec<usize>,
    /// Its basis.
    pub basis: telescopic_runtime::Basis,
    /// The run's error in two parts ([`crate::run::error_budget`]); `None` when not asked for.
    pub error: Option<ErrorBudget>,
}

impl Simulation {
    /// This run's error budget from a `companion` run of `modes` per section on `scene`:
    /// the truncation from the companion's difference, whether that difference holds this
    /// run's interpolation (steps across the samples), and whether it holds this run's
    /// integration error (`companion_integration`: the companion's own stored figure, when
    /// it was integrated finer; else the integration part is this run's stored figure).
    pub(crate) fn budget_against(
        &self,
        scene: &telescopic_runtime::Scene,
        companion: &Trajectory,
        modes: Vec<usize>,
        companion_integration: Option<f64>,
    ) -> ErrorBudget {
        let window = super::error_budget::window(&scene.params, &self.trajectory);
        ErrorBudget {
            window,
            // integrated finer, the companion's difference holds this run's integration
            // error: what remains to add is the companion's own
            integration_m: companion_integration.or(self.plan.integration_error_m),
            integration_statistics: self.plan.integration_statistics_rel,
            truncation: Some(super::error_budget::Truncation {
                interpolation: self.plan.settings.longest_step.is_some(),
                integration: companion_integration.is_some(),
                ..super::error_budget::truncation(&self.trajectory, companion, modes, window)
            }),
            missing: None,
            reused: None,
        }
    }

    /// The run summary: scene, model, method (and why, for `auto`), specializations, and
    /// what the run did.
    pub fn summary(&self) -> String {
        let s = &self.trajectory.stats;
        let settings = &self.plan.settings;
        let cap = s.step_cap.map_or(String::new(), |c| {
            format!("; step capped at {c:.3e} s while a contact is closed (its stable step)")
        });
        let long = if s.long_steps > 0 {
            format!(", {} steps over the closed contacts' modes", s.long_steps)
        } else {
            String::new()
        };
        // 1e-3 x rtol prints 1.0000000000000001e-7: twelve digits say the same shorter
        let tidy = |x: f64| format!("{x:.12e}").parse::<f64>().unwrap_or(x);
        let (rtol, atol) = (tidy(settings.rtol), tidy(settings.atol));
        let tol = match self.plan.method.step_control() {
            StepControl::Adaptive if s.exponentials > 0 => format!(
                "rtol {rtol:e}, atol {atol:e}{cap}; {} matrix exponentials{long}",
                s.exponentials
            ),
            StepControl::Adaptive => {
                format!("rtol {rtol:e}, atol {atol:e}{cap}")
            }
            StepControl::Fixed => format!("dt {:e} s", settings.dt.unwrap_or(f64::NAN)),
            StepControl::Exact => format!("{} matrix exponentials{long}", s.exponentials),
        };
        let special = if self.specializations.is_empty() {
            "none".to_string()
        } else {
            self.specializations
                .iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join("; ")
        };
        let stress = match crate::run::stress::StressEnvelope::of(&self.trajectory) {
            Some(envelope) => format!("\n{}", envelope.describe()),
            None if self
                .trajectory
                .outputs()
                .any(|(_, o)| matches!(o, Output::Moment { .. })) =>
            {
                "\nstresses: none (the scene gives neither sections.section_modulus nor \
                 sections.height)"
                    .to_string()
            }
            None => String::new(),
        };
        format!(
            "{} on the {}: method {} ({}{tol}), t = {} .. {} s, {} samples\n\
             specializations: {special}\n\
             steps {} (rejected {}), rhs evaluations {}, Jacobian evaluations {}, \
             factorizations {}, contact switches {}, wall time {:.3} s",
            self.scene,
            self.model,
            self.plan.method,
            self.plan.reason,
            self.span.0,
            self.span.1,
            self.trajectory.rows.len(),
            s.steps,
            s.rejected,
            s.rhs_evals,
            s.jacobian_evals,
            s.factorizations,
            s.switches,
            s.wall.as_secs_f64()
        ) + &stress
            + &self
                .error_lines()
                .map(|l| format!("\n{l}"))
                .collect::<String>()
    }

    /// The error budget's lines, empty when it was not estimated.
    fn error_lines(&self) -> impl Iterator<Item = String> {
        self.error
            .as_ref()
            .map(|e| e.describe(&self.modes))
            .unwrap_or_default()
            .into_iter()
    }

    /// Writes the CSV: the error budget as `#` lines, then the samples
    /// ([`Trajectory::write_csv`]).
    ///
    /// # Errors
    /// The writer's error.
    pub fn write_csv(&self, w: &mut dyn Write) -> std::io::Result<()> {
        for line in self.error_lines() {
            writeln!(w, "# {line}")?;
        }
        self.trajectory.write_csv(w)
    }
}

/// Writes the CSV of `simulation` to `path` (atomically) or to standard output.
///
/// # Errors
/// [`crate::Error::Write`] or [`crate::Error::Stdout`].
pub fn write_csv(simulation: &Simulation, path: Option<&Path>) -> Result<()> {
    crate::io::output::write_to(path, |w| simulation.write_csv(w))
}
