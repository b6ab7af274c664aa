//! A run's error in metres, in two parts: the integration error of the Ritz model it
//! integrates, and the truncation error of that model's size against the beams it
//! discretizes.
//!
//! * **Truncation**: a companion run of the same scene with more modes per section
//!   ([`refined_modes`]), same basis, its steps ending on every output sample. Its
//!   difference from the run, times [`TRUNCATION_FACTOR`], is the estimate: in `tip_rel`
//!   pointwise inside the [`Window`], relative to their peaks for the moments at stations,
//!   and relative for the statistics beyond the window. Where the run's steps cross the
//!   samples, the difference also holds the run's interpolation error, measured on the run
//!   ([`Truncation::interpolation`]).
//! * **Integration**: where `auto` or `--accuracy` picked the run's method from the table of
//!   measured runs ([`telescopic_runtime::analysis::accuracy`]), the companion is integrated
//!   at most a tenth as coarsely as that row's measured error
//!   ([`telescopic_runtime::analysis::accuracy::COMPANION_RATIO`]): the difference then holds
//!   the run's own integration error, measured on this run ([`Truncation::integration`]), and
//!   the companion's own row's figure is added. Where no row is that much finer (exact
//!   stepping, whose error is rounding) the run's row's figure stands: a stored figure, said
//!   so. Not estimated when the method or a tolerance was given.
//!
//! The window is the whole span without clearance. With clearance it ends at the run's first
//! contact switch: after an impact, two models that differ by a truncation error part like
//! any two runs of a chaotic system, and only statistics compare.
//!
//! The estimate is checked against an independent finite-element model of the beams
//! ([`telescopic_runtime::ElementModel`]) on every shipped scene with fixed positions
//! (`tests/error_budget.rs`; docs/numerics.md has the figures).

use crate::named::named_enum;
use crate::run::Trajectory;
use serde::{Deserialize, Serialize};
use telescopic_runtime::Output;
use telescopic_runtime::{MAX_MODES, ModelParams};

/// The estimate is the difference from the refined model times this factor: when the
/// refined model's own error is at most a third of the run's (the convergence rates measured
/// in docs/numerics.md give that for [`refined_modes`]), the run's error is at most 1.5 times
/// the difference.
pub const TRUNCATION_FACTOR: f64 = 1.5;

/// The refined model's modes for a section with `n`: `n + max(2, ceil(n / 2))`, at most
/// [`MAX_MODES`].
pub fn refined_modes(n: usize) -> usize {
    (n + 2.max(n.div_ceil(2))).min(MAX_MODES)
}

/// The refined model's parameters: every section's modes refined; `None` when every section
/// has [`MAX_MODES`] already.
pub fn refined(params: &ModelParams) -> Option<ModelParams> {
    let mut p = params.clone();
    for s in &mut p.sections {
        s.modes = refined_modes(s.modes);
    }
    (p.modes() != params.modes()).then_some(p)
}

/// Why the pointwise window ends where it does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum WindowEnd {
    /// The span's end (no clearance: no impacts).
    SpanEnd,
    /// The run's first contact switch.
    FirstSwitch,
}

/// Where `tip_rel` is compared pointwise.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Window {
    /// End of the window (s); it starts at the span's start.
    pub end: f64,
    /// Why it ends there.
    pub reason: WindowEnd,
}

/// A statistic of a run beyond its window.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Statistic {
    /// RMS of `tip_rel` (m).
    #[serde(rename = "rms-tip-rel")]
    TipRms,
    /// Largest `|tip_rel|` (m).
    #[serde(rename = "peak-tip-rel")]
    TipPeak,
    /// Contact switches over the whole run.
    #[serde(rename = "contact-switches")]
    Switches,
    /// Largest contact force magnitude (N).
    #[serde(rename = "peak-contact-force")]
    ContactForcePeak,
    /// Largest moment magnitude over the stations (N m).
    #[serde(rename = "peak-moment")]
    MomentPeak,
}

named_enum!(Statistic, "a statistic", {
    TipRms => "rms-tip-rel",
    TipPeak => "peak-tip-rel",
    Switches => "contact-switches",
    ContactForcePeak => "peak-contact-force",
    MomentPeak => "peak-moment",
});

/// One statistic with its relative truncation estimate.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StatisticError {
    /// Which.
    pub statistic: Statistic,
    /// Its value in the run (SI units; a count for switches).
    pub value: f64,
    /// Relative truncation error estimate (1).
    pub relative: f64,
}

/// A station's moment error estimate inside the window, relative to its peak over the run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MomentError {
    /// The column, `moment_k_x`.
    pub column: String,
    /// Largest `|moment|` over the run (N m).
    pub peak: f64,
    /// Truncation estimate relative to `peak` (1).
    pub relative: f64,
}

/// The truncation part of a run's error, from its companion run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Truncation {
    /// Modes per section of the companion run.
    pub refined_modes: Vec<usize>,
    /// Estimate of the error in `tip_rel` inside the window (m).
    pub tip_m: f64,
    /// Per station.
    pub moments: Vec<MomentError>,
    /// Every other output the run prints (`top1_rel`, gaps, contact forces, drive force,
    /// sensors), by column: the estimate of its truncation error inside the window, in the
    /// column's own unit.
    pub outputs: Vec<(String, f64)>,
    /// Beyond the window (clearance scenes only).
    pub statistics: Vec<StatisticError>,
    /// The run's steps crossed its output samples while the companion's ended on every
    /// sample: the estimates also hold the run's interpolation error, measured on this run.
    pub interpolation: bool,
    /// The companion was integrated finer than the run (at most a tenth of its measured
    /// error): the estimates also hold the run's integration error, measured on this run.
    pub integration: bool,
}

/// A run's error budget.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ErrorBudget {
    /// The pointwise window.
    pub window: Window,
    /// Integration error in `tip_rel` inside the horizon (m), from the measured run that
    /// chose the method; `None` when a method was given.
    pub integration_m: Option<f64>,
    /// The integration part of the statistics' relative error beyond the window: that
    /// measured run's, or with clearance the spread of correct runs of a chaotic scene.
    pub integration_statistics: Option<f64>,
    /// The truncation part; `None` when it was not estimated.
    pub truncation: Option<Truncation>,
    /// Why the truncation part is missing, when it is.
    pub missing: Option<String>,
    /// The record this budget was read from ([`crate::run::reuse`]): a run of the same scene
    /// and options whose outputs this run reproduced to the bit. `None`: this run's own.
    pub reused: Option<std::path::PathBuf>,
}

impl ErrorBudget {
    /// The estimate of the whole error in `tip_rel` inside the window (m), when both parts
    /// are known.
    pub fn total_m(&self) -> Option<f64> {
        Some(self.integration_m? + self.truncation.as_ref()?.tip_m)
    }

    /// The largest relative truncation estimate of the moments, if any station.
    pub fn worst_moment(&self) -> Option<f64> {
        let t = self.truncation.as_ref()?;
        t.moments.iter().map(|m| m.relative).reduce(f64::max)
    }

    /// The largest relative truncation estimate among the `statistics`, if any.
    pub fn worst_statistic(&self, statistics: &[Statistic]) -> Option<f64> {
        let t = self.truncation.as_ref()?;
        t.statistics
            .iter()
            .filter(|s| statistics.contains(&s.statistic))
            .map(|s| s.relative)
            .reduce(f64::max)
    }

    /// Lines for the run summary (also the CSV's `#` header). With clearance the statistics
    /// beyond the window lead: beyond the first impact they are what a run is good for.
    pub fn describe(&self, modes: &[usize]) -> Vec<String> {
        let mut lines = vec![self.describe_tip(modes)];
        if let Some(t) = &self.truncation {
            if !t.moments.is_empty() {
                let parts: Vec<String> = t
                    .moments
                    .iter()
                    .map(|m| format!("{} {:.1} %", m.column, 100.0 * m.relative))
                    .collect();
                lines.push(format!(
                    "moment truncation error in the window, of each station's peak: {}",
                    parts.join(", ")
                ));
            }
            if !t.outputs.is_empty() {
                lines.push(describe_outputs(&t.outputs, t));
            }
            if !t.statistics.is_empty() {
                lines.insert(0, self.describe_statistics(t));
            }
        }
        if let Some(path) = &self.reused {
            lines.push(format!(
                "error budget reused from {}: written by a run of the same scene and options, \
                 whose outputs this run reproduced to the bit",
                path.display()
            ));
        }
        lines
    }

    /// The stated error as a figure's legend says it: `tip_rel` in the window, and with
    /// clearance the worst bounded statistic beyond it; `None` when not estimated.
    pub fn legend(&self) -> Option<String> {
        let total = self
            .total_m()
            .or(self.truncation.as_ref().map(|t| t.tip_m))?;
        let tip = match self.window.reason {
            WindowEnd::SpanEnd => format!("error: tip_rel {total:.1e} m"),
            WindowEnd::FirstSwitch => {
                format!("error: tip_rel {total:.1e} m to {} s", self.window.end)
            }
        };
        let statistics = self
            .worst_statistic(&[Statistic::TipRms, Statistic::TipPeak])
            .map(|s| s + self.integration_statistics.unwrap_or(0.0));
        Some(match statistics {
            Some(s) => format!("{tip}, RMS/peak {:.0} %", 100.0 * s),
            None => tip,
        })
    }

    /// The line of the pointwise error of `tip_rel` in the window.
    fn describe_tip(&self, modes: &[usize]) -> String {
        let window = match self.window.reason {
            WindowEnd::SpanEnd => format!("on [start, {}] s", self.window.end),
            WindowEnd::FirstSwitch => format!(
                "up to the first contact switch at t = {} s (beyond it, statistics)",
                self.window.end
            ),
        };
        let measured = self.truncation.as_ref().is_some_and(|t| t.integration);
        let integration = match self.integration_m {
            Some(e) if measured => format!(
                "the companion's own integration {e:.1e} m (a stored figure: the measured \
                 reference run its method was picked from)"
            ),
            Some(e) => format!(
                "integration {e:.1e} m (a stored figure: the measured reference run the \
                 method was picked from, not this run)"
            ),
            None => "integration not estimated (a method was given: `telescopic \
                     work-precision` measures it)"
                .to_string(),
        };
        let truncation = match (&self.truncation, &self.missing) {
            (Some(t), _) => format!(
                "{} {:.1e} m ({} modes per section against {}{})",
                measured_parts(t),
                t.tip_m,
                join(modes),
                join(&t.refined_modes),
                match (t.integration, t.interpolation) {
                    (true, _) => " stepped on every sample and integrated finer",
                    (false, true) => " stepped on every sample",
                    (false, false) => "",
                }
            ),
            (None, Some(why)) => format!("truncation not estimated ({why})"),
            (None, None) => "truncation not estimated".to_string(),
        };
        // what the companion measured leads; the stored figure follows
        if measured {
            return format!("error of tip_rel {window}: {truncation}; {integration}");
        }
        format!("error of tip_rel {window}: {integration}; {truncation}")
    }

    /// The line of the statistics' relative errors beyond the window.
    fn describe_statistics(&self, t: &Truncation) -> String {
        let parts: Vec<String> = t
            .statistics
            .iter()
            .map(|s| format!("{} {:.1} %", s.statistic, 100.0 * s.relative))
            .collect();
        let integration = match self.integration_statistics {
            Some(e) => format!(
                "integration {:.1} % (per-second peak and RMS of tip_rel: a stored figure of \
                 the reference run, or correct runs' spread); ",
                100.0 * e
            ),
            None => String::new(),
        };
        // a companion integrated finer parts from the run beyond an impact as two correct
        // runs do: its difference holds that spread too
        let measured = match t.integration {
            true => "truncation and this run's integration spread",
            false => "truncation",
        };
        format!(
            "error of the statistics beyond t = {} s, relative: {integration}{measured} {}",
            self.window.end,
            parts.join(", ")
        )
    }
}

/// What a companion's difference holds beyond the truncation, as the summary names it.
fn measured_parts(t: &Truncation) -> &'static str {
    match (t.integration, t.interpolation) {
        (true, true) => "truncation and this run's integration and interpolation",
        (true, false) => "truncation and this run's integration",
        (false, true) => "truncation and this run's interpolation",
        (false, false) => "truncation",
    }
}

/// The line of the other outputs' estimates from the companion `t` (with the run's
/// integration and interpolation errors where its difference holds them): the largest of
/// each kind of column (the relative positions, the gaps, the contact forces), the rest by
/// name.
fn describe_outputs(outputs: &[(String, f64)], t: &Truncation) -> String {
    let kinds = [
        ("xi_", "gaps", "m"),
        ("f_", "contact forces", "N"),
        ("stress_", "stresses", "Pa"),
    ];
    let mut parts = Vec::new();
    for (prefix, label, unit) in kinds {
        let worst = outputs
            .iter()
            .filter(|(c, _)| c.starts_with(prefix))
            .map(|(_, e)| *e)
            .reduce(f64::max);
        if let Some(e) = worst {
            parts.push(format!("{label} {e:.1e} {unit}"));
        }
    }
    for (column, e) in outputs {
        if !kinds.iter().any(|(p, _, _)| column.starts_with(p)) {
            parts.push(format!("{column} {e:.1e}"));
        }
    }
    format!(
        "{} error of the other outputs in the window (largest, SI units): {}",
        measured_parts(t),
        parts.join(", ")
    )
}

fn join(modes: &[usize]) -> String {
    modes
        .iter()
        .map(usize::to_string)
        .collect::<Vec<_>>()
        .join("x")
}

/// The pointwise window of `run` on the scene of `params`: the whole span without
/// clearance, else up to the first sample whose contact state (open or closed, from the
/// gaps) differs from the start's.
pub fn window(params: &ModelParams, run: &Trajectory) -> Window {
    let end = run.rows.last().map_or(0.0, |r| r[0]);
    let law = &params.contact;
    let gaps = run.gap_columns();
    if law.is_linear() || gaps.is_empty() {
        return Window {
            end,
            reason: WindowEnd::SpanEnd,
        };
    }
    let closed =
        |row: &[f64]| -> Vec<bool> { gaps.iter().map(|&g| law.is_closed(row[g])).collect() };
    let first = closed(&run.rows[0]);
    match run.rows.iter().find(|r| closed(r) != first) {
        Some(r) => Window {
            end: r[0],
            reason: WindowEnd::FirstSwitch,
        },
        None => Window {
            end,
            reason: WindowEnd::SpanEnd,
        },
    }
}

/// The truncation estimate of `run` from its `companion` (the refined model's run of the
/// same scene with the same method and settings) inside `window`, and beyond it.
pub fn truncation(
    run: &Trajectory,
    companion: &Trajectory,
    refined_modes: Vec<usize>,
    window: Window,
) -> Truncation {
    let tip = run
        .index_of(Output::TipRel)
        .expect("every model has tip_rel");
    // the largest difference of a column up to the window's end; for the outputs other than
    // the tip and the moments strictly before it: the sample at a first switch has a contact
    // force in one run and not in the other, a jump that says when, not how far off
    let largest_before = |column: usize, strictly: bool| {
        let inside = |t: f64| match window.reason {
            WindowEnd::FirstSwitch if strictly => t < window.end,
            _ => t <= window.end,
        };
        run.rows
            .iter()
            .zip(&companion.rows)
            .take_while(|(a, _)| inside(a[0]))
            .map(|(a, b)| (a[column] - b[column]).abs())
            .fold(0.0, f64::max)
    };
    let largest_difference = |column: usize| largest_before(column, false);
    let moments = run
        .columns_where(|o| matches!(o, Output::Moment { .. }))
        .into_iter()
        .map(|c| c - 1)
        .map(|i| {
            let peak = peak_of(companion, i + 1, |_| true);
            MomentError {
                column: run.columns[i].to_string(),
                peak,
                relative: TRUNCATION_FACTOR * largest_difference(i + 1)
                    / peak.max(f64::MIN_POSITIVE),
            }
        })
        .collect();
    let statistics = if window.reason == WindowEnd::FirstSwitch {
        statistics(run, companion, window.end)
    } else {
        Vec::new()
    };
    // every output but the tip and the moments (above), in both runs' same column
    let outputs = run
        .outputs()
        .filter(|&(column, output)| column != tip && !matches!(output, Output::Moment { .. }))
        .filter(|&(column, output)| companion.outputs().any(|c| c == (column, output)))
        .map(|(column, output)| {
            (
                output.to_string(),
                TRUNCATION_FACTOR * largest_before(column, true),
            )
        })
        .collect();
    Truncation {
        refined_modes,
        tip_m: TRUNCATION_FACTOR * largest_difference(tip),
        moments,
        outputs,
        statistics,
        interpolation: false,
        integration: false,
    }
}

/// Largest `|value|` of a column over the rows whose time passes `keep`.
fn peak_of(run: &Trajectory, column: usize, keep: impl Fn(f64) -> bool) -> f64 {
    run.rows
        .iter()
        .filter(|r| keep(r[0]))
        .map(|r| r[column].abs())
        .fold(0.0, f64::max)
}

/// The statistics of `run` after `from` (s) with their relative differences from
/// `companion`'s, times [`TRUNCATION_FACTOR`].
fn statistics(run: &Trajectory, companion: &Trajectory, from: f64) -> Vec<StatisticError> {
    let after = |t: f64| t > from;
    let tip = run
        .index_of(Output::TipRel)
        .expect("every model has tip_rel");
    let rms = |traj: &Trajectory| {
        let (sum, count) = traj
            .rows
            .iter()
            .filter(|r| after(r[0]))
            .fold((0.0, 0usize), |(s, n), r| (s + r[tip] * r[tip], n + 1));
        (sum / count.max(1) as f64).sqrt()
    };
    let is_moment = |o: &Output| matches!(o, Output::Moment { .. });
    let peak_over = |traj: &Trajectory, which: &dyn Fn(&Output) -> bool| {
        traj.columns_where(which)
            .into_iter()
            .map(|c| peak_of(traj, c, after))
            .fold(0.0, f64::max)
    };
    let mut pairs = vec![
        (Statistic::TipRms, rms(run), rms(companion)),
        (
            Statistic::TipPeak,
            peak_of(run, tip, after),
            peak_of(companion, tip, after),
        ),
        (
            Statistic::Switches,
            run.stats.switches as f64,
            companion.stats.switches as f64,
        ),
        (
            Statistic::ContactForcePeak,
            peak_over(run, &Output::is_contact_force),
            peak_over(companion, &Output::is_contact_force),
        ),
    ];
    if !run.columns_where(is_moment).is_empty() {
        pairs.push((
            Statistic::MomentPeak,
            peak_over(run, &is_moment),
            peak_over(companion, &is_moment),
        ));
    }
    pairs
        .into_iter()
        .map(|(statistic, value, reference)| StatisticError {
            statistic,
            value,
            relative: TRUNCATION_FACTOR * (value - reference).abs()
                / reference.abs().max(f64::MIN_POSITIVE),
        })
        .collect()
}
