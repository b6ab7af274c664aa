//! A finished run's summary as data: what ran (scene, model, method and why), what the run
//! did (steps, evaluations, switches, wall time) and its error budget. One struct serves the
//! command's `simulate --json`, the Python package's `summary` and any library user; its
//! field names are the JSON keys.

use super::error_budget::{ErrorBudget, WindowEnd};
use super::simulation::Simulation;
use serde::Serialize;
use std::collections::BTreeMap;

/// The summary of a [`Simulation`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunSummary {
    /// The scene's name.
    pub scene: String,
    /// Which model ran it.
    pub model: String,
    /// The method that started the run.
    pub method: String,
    /// For `auto` or an accuracy: why this method, model size and tolerance.
    pub how: String,
    /// Relative tolerance (1).
    pub rtol: f64,
    /// Absolute tolerance (m, m/s).
    pub atol: f64,
    /// Accepted steps.
    pub steps: u64,
    /// Rejected steps.
    pub rejected: u64,
    /// Right-hand-side evaluations.
    pub rhs_evaluations: u64,
    /// Jacobian evaluations.
    pub jacobian_evaluations: u64,
    /// LU factorizations.
    pub factorizations: u64,
    /// Matrix exponentials of exact stepping.
    pub matrix_exponentials: u64,
    /// Exact stepping's long steps over the closed contacts' modes.
    pub long_steps: u64,
    /// Contact switches.
    pub switches: u64,
    /// Wall time of the integration (s).
    pub wall_s: f64,
    /// Output samples.
    pub samples: usize,
    /// The specializations that applied, one phrase each.
    pub specializations: Vec<String>,
    /// Modes per section of the model that ran.
    pub modes: Vec<usize>,
    /// Its basis (`modes` or `modes+static`).
    pub basis: String,
    /// The error budget; `None` when not estimated.
    pub error: Option<ErrorSummary>,
    /// The summary as the command prints it.
    pub text: String,
}

/// The error budget of a run ([`ErrorBudget`]) as data.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ErrorSummary {
    /// End of the pointwise window (s).
    pub window_end_s: f64,
    /// Why it ends there: `span-end` or `first-switch`.
    pub window_end: String,
    /// Integration error of `tip_rel` in the window (m): the run's stored figure, or with
    /// `integration_included` the companion's own.
    pub integration_m: Option<f64>,
    /// Relative integration error of the statistics beyond the window.
    pub integration_statistics: Option<f64>,
    /// Truncation error of `tip_rel` in the window (m).
    pub truncation_m: Option<f64>,
    /// Whether `truncation_m` and `outputs` also hold the run's interpolation error (its
    /// steps crossed the output samples, its companion's ended on them).
    pub interpolation_included: bool,
    /// Whether `truncation_m` and `outputs` also hold the run's integration error (its
    /// companion was integrated finer); `integration_m` is then the companion's own.
    pub integration_included: bool,
    /// Their sum (m).
    pub total_m: Option<f64>,
    /// Modes per section of the companion run.
    pub refined_modes: Option<Vec<usize>>,
    /// Truncation error of each station's moment, relative to its peak, by column.
    pub moments: BTreeMap<String, f64>,
    /// Truncation error of every other output in the window, by column (its SI unit).
    pub outputs: BTreeMap<String, f64>,
    /// Each statistic beyond the window: its value and its relative truncation error.
    pub statistics: BTreeMap<String, (f64, f64)>,
    /// Why the truncation part is missing.
    pub missing: Option<String>,
    /// The record the budget was reused from ([`crate::run::reuse`]); `None`: this run's own.
    pub reused_from: Option<String>,
}

impl Simulation {
    /// The run's summary as data.
    pub fn run_summary(&self) -> RunSummary {
        let s = &self.trajectory.stats;
        RunSummary {
            scene: self.scene.clone(),
            model: self.model.clone(),
            method: self.plan.method.name(),
            how: self.plan.reason.to_string(),
            rtol: self.plan.settings.rtol,
            atol: self.plan.settings.atol,
            steps: s.steps,
            rejected: s.rejected,
            rhs_evaluations: s.rhs_evals,
            jacobian_evaluations: s.jacobian_evals,
            factorizations: s.factorizations,
            matrix_exponentials: s.exponentials,
            long_steps: s.long_steps,
            switches: s.switches,
            wall_s: s.wall.as_secs_f64(),
            samples: self.trajectory.rows.len(),
            specializations: self
                .specializations
                .iter()
                .map(ToString::to_string)
                .collect(),
            modes: self.modes.clone(),
            basis: self.basis.word().to_string(),
            error: self.error.as_ref().map(ErrorSummary::of),
            text: self.summary(),
        }
    }
}

impl ErrorSummary {
    /// The summary of `budget`.
    pub fn of(budget: &ErrorBudget) -> Self {
        let truncation = budget.truncation.as_ref();
        ErrorSummary {
            window_end_s: budget.window.end,
            window_end: match budget.window.reason {
                WindowEnd::SpanEnd => "span-end",
                WindowEnd::FirstSwitch => "first-switch",
            }
            .to_string(),
            integration_m: budget.integration_m,
            integration_statistics: budget.integration_statistics,
            truncation_m: truncation.map(|t| t.tip_m),
            interpolation_included: truncation.is_some_and(|t| t.interpolation),
            integration_included: truncation.is_some_and(|t| t.integration),
            total_m: budget.total_m(),
            refined_modes: truncation.map(|t| t.refined_modes.clone()),
            moments: truncation
                .map(|t| {
                    t.moments
                        .iter()
                        .map(|m| (m.column.clone(), m.relative))
                        .collect()
                })
                .unwrap_or_default(),
            outputs: truncation
                .map(|t| t.outputs.iter().cloned().collect())
                .unwrap_or_default(),
            statistics: truncation
                .map(|t| {
                    t.statistics
                        .iter()
                        .map(|s| (s.statistic.name().to_string(), (s.value, s.relative)))
                        .collect()
                })
                .unwrap_or_default(),
            missing: budget.missing.clone(),
            reused_from: budget.reused.as_ref().map(|p| p.display().to_string()),
        }
    }
}

impl RunSummary {
    /// The summary as JSON (pretty, keys as the fields are named; a non-finite number, which a
    /// finished run does not have, would be `null`).
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).expect("plain data") + "\n"
    }
}
