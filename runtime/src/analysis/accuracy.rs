//! Accuracy asked for in metres, not a tolerance to guess: the method and tolerance that reach
//! a requested error in `tip_rel` cheapest, from a table of measured runs per kind of scene.
//!
//! Every row of [`MEASURED`] is a run of `telescopic work-precision` on a shipped scene (the
//! committed CSVs `docs/wp-<scene>.csv`; a test checks that each row is there with the error
//! and time written here): the error is the largest `|tip_rel|` difference from two tight
//! reference runs inside the scene's predictability horizon, the time the run's wall time on
//! the machine that measured it. [`plan_for_accuracy`] takes the cheapest row of the scene's
//! kind whose measured error is at most the requested accuracy over [`MARGIN`]: the margin
//! stands for the scenes of the same kind that were not measured.

use crate::integrate::Method;
use crate::integrate::exact::{exact_tail_start, lti_obstacle};
use crate::model::params::{Drive, ModelParams};
use crate::scene::TimeSpan;

/// The whole errors against the beams that can be asked for (m): below, the truncation of
/// the largest models that the shipped scenes afford cannot be certified; above, no longer
/// an accuracy.
pub const WHOLE_ACCURACY_RANGE: (f64, f64) = (1e-5, 1e-1);

/// The accuracy the defaults keep (m, in `tip_rel` inside the predictability horizon).
pub const DEFAULT_ACCURACY_M: f64 = 1e-6;

/// The accuracies that can be asked for (m): below, rounding and the references' own
/// agreement; above a centimetre, no longer an accuracy of this model.
pub const ACCURACY_RANGE: (f64, f64) = (1e-11, 1e-2);

/// How far below the requested accuracy a row's measured error must lie.
pub const MARGIN: f64 = 3.0;

/// The kinds of scene the table distinguishes: what decides which method is cheapest.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SceneKind {
    /// Linear and time-invariant between contact switches: exact stepping applies.
    LinearTimeInvariant,
    /// No clearance (the linear law: the contacts never open) and a drive force, with moving
    /// positions or a force that is not piecewise constant: no impacts, the contact modes
    /// stiff but never excited by a switch.
    ContactsAlwaysClosed,
    /// Everything else: clearance with moving positions or a smooth force, or a prescribed
    /// motion: impacts, each of which must be resolved.
    Impacts,
}

impl SceneKind {
    /// The kind of the scene of `params`.
    pub fn of(params: &ModelParams) -> Self {
        if lti_obstacle(params).is_none() {
            SceneKind::LinearTimeInvariant
        } else if params.contact.is_linear() && matches!(params.drive, Drive::Force(_)) {
            SceneKind::ContactsAlwaysClosed
        } else {
            SceneKind::Impacts
        }
    }

    /// A few words for the summary.
    pub fn describe(self) -> &'static str {
        match self {
            SceneKind::LinearTimeInvariant => "linear and time-invariant between contact switches",
            SceneKind::ContactsAlwaysClosed => "without clearance (contacts always closed)",
            SceneKind::Impacts => "with impacts (clearance, or a prescribed motion)",
        }
    }
}

/// What a run's outputs need the integration to resolve.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Resolve {
    /// Displacements and gaps (`tip_rel`): every row of the table counts.
    Displacements,
    /// Every output at every sample from a step's end, as a companion run that measures
    /// another run's error needs: the rows whose steps cross samples are left out (their
    /// Hermite samples' error in the contact forces is of the size of a truncation
    /// error: 3.6 N against the beams' 400 N peak on case-study-no-clearance where the
    /// truncation estimate said 0.9 N).
    EverySample,
    /// Bending moments too: a moment at a station is an acceleration and a curvature, which
    /// carry the contact modes that `imex` steps over. Its rows are left out (measured on
    /// case-study-no-clearance with 10 modes per section: the foot moment's peak 263 N m with
    /// imex, 181 N m with dop853 at rtol 1e-8 and with the beams' reference).
    Moments,
}

/// One measured run: a method at a tolerance on a shipped scene of a kind.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeasuredRun {
    /// The kind of scene.
    pub kind: SceneKind,
    /// The shipped scene it was measured on.
    pub scene: &'static str,
    /// The method's name.
    pub method: &'static str,
    /// The relative tolerance (the absolute one is 1e-3 of it); 0 for exact stepping.
    pub rtol: f64,
    /// The longest step (s) when steps cross output samples (`Settings::longest_step`);
    /// `None`: steps end on every sample.
    pub longest_step: Option<f64>,
    /// Largest `|tip_rel|` error inside the predictability horizon (m).
    pub error_m: f64,
    /// Wall time of the whole scene (s).
    pub wall_s: f64,
    /// Largest relative error of the per-second peak and RMS of `tip_rel` over the whole
    /// span (the work-precision table's `statistics_error_rel`): with clearance, the floor
    /// two correct runs of a chaotic scene part by.
    pub statistics_rel: f64,
}

/// The measured runs (`telescopic work-precision`, median of 3, on the 2-core machine of
/// docs/benchmarks.md); `docs/wp-<scene>.csv` hold every run they were picked from. The times vary
/// by up to 1.5x between sessions of the same machine; the choices do not depend on that
/// (the rows that compete differ by 1.4x or more, or the finer one costs little more). Errors
/// below about 1e-9 m are at the agreement of the two references (which defines the horizon),
/// so the finest rows say "1e-9 m or better", not their last digit.
pub const MEASURED: [MeasuredRun; 11] = [
    MeasuredRun {
        kind: SceneKind::LinearTimeInvariant,
        scene: "adams-linear",
        method: "exact",
        rtol: 0.0,
        longest_step: None,
        error_m: 2.8e-9,
        wall_s: 0.0011,
        statistics_rel: 1.5e-8,
    },
    MeasuredRun {
        kind: SceneKind::ContactsAlwaysClosed,
        scene: "case-study-no-clearance",
        method: "imex",
        rtol: 1e-6,
        longest_step: None,
        error_m: 1.9e-7,
        wall_s: 0.034,
        statistics_rel: 8.6e-7,
    },
    MeasuredRun {
        kind: SceneKind::ContactsAlwaysClosed,
        scene: "case-study-no-clearance",
        method: "imex",
        rtol: 1e-6,
        longest_step: Some(8e-3),
        error_m: 1.9e-6,
        wall_s: 0.017,
        statistics_rel: 1.4e-5,
    },
    MeasuredRun {
        kind: SceneKind::ContactsAlwaysClosed,
        scene: "case-study-no-clearance",
        method: "imex",
        rtol: 1e-4,
        longest_step: Some(8e-3),
        error_m: 1.3e-5,
        wall_s: 0.0074,
        statistics_rel: 7.0e-5,
    },
    MeasuredRun {
        kind: SceneKind::ContactsAlwaysClosed,
        scene: "case-study-no-clearance",
        method: "dop853",
        rtol: 1e-5,
        longest_step: None,
        error_m: 1.8e-12,
        wall_s: 0.12,
        statistics_rel: 7.8e-12,
    },
    MeasuredRun {
        kind: SceneKind::Impacts,
        scene: "case-study",
        method: "dop853",
        rtol: 1e-5,
        longest_step: None,
        error_m: 1.6e-6,
        wall_s: 0.072,
        statistics_rel: 0.087,
    },
    MeasuredRun {
        kind: SceneKind::Impacts,
        scene: "case-study",
        method: "dop853",
        rtol: 1e-6,
        longest_step: None,
        error_m: 4.6e-8,
        wall_s: 0.088,
        statistics_rel: 0.058,
    },
    MeasuredRun {
        kind: SceneKind::Impacts,
        scene: "case-study",
        method: "dop853",
        rtol: 1e-7,
        longest_step: None,
        error_m: 8.1e-10,
        wall_s: 0.10,
        statistics_rel: 0.037,
    },
    MeasuredRun {
        kind: SceneKind::Impacts,
        scene: "case-study",
        method: "dop853-imex",
        rtol: 1e-5,
        longest_step: None,
        error_m: 1.6e-6,
        wall_s: 0.046,
        statistics_rel: 0.088,
    },
    MeasuredRun {
        kind: SceneKind::Impacts,
        scene: "case-study",
        method: "dop853-imex",
        rtol: 1e-6,
        longest_step: None,
        error_m: 4.6e-8,
        wall_s: 0.067,
        statistics_rel: 0.076,
    },
    MeasuredRun {
        kind: SceneKind::Impacts,
        scene: "case-study",
        method: "dop853-imex",
        rtol: 1e-7,
        longest_step: None,
        error_m: 8.3e-10,
        wall_s: 0.098,
        statistics_rel: 0.14,
    },
];

/// The label of an adaptive run's settings in `telescopic work-precision`'s `setting`
/// column: `rtol=1e-5`, or `rtol=1e-5 longest=8e-3` when steps cross samples up to a
/// longest step (s).
pub fn setting_label(rtol: f64, longest_step: Option<f64>) -> String {
    match longest_step {
        Some(h) => format!("rtol={rtol:e} longest={h:e}"),
        None => format!("rtol={rtol:e}"),
    }
}

impl MeasuredRun {
    /// The row's `setting` in its work-precision CSV ([`setting_label`], or `exact`).
    pub fn setting(&self) -> String {
        if self.method == "exact" {
            "exact".to_string()
        } else {
            setting_label(self.rtol, self.longest_step)
        }
    }
}

/// What runs a scene for an accuracy: the method, its tolerances, exact stepping from a
/// time (positions at rest), and why.
#[derive(Debug, Clone, PartialEq)]
pub struct AccuracyPlan {
    /// The method.
    pub method: Method,
    /// Relative tolerance (the absolute one is 1e-3 of it).
    pub rtol: f64,
    /// Exact stepping from this time on (s), once the positions rest.
    pub exact_from: Option<f64>,
    /// The longest step (s) of steps that cross output samples: the row's, where it is
    /// longer than the scene's sample interval (`Settings::longest_step`).
    pub longest_step: Option<f64>,
    /// The accuracy asked for (m of `tip_rel`).
    pub accuracy_m: f64,
    /// The measured run it follows (its kind is the scene's).
    pub row: MeasuredRun,
    /// The row's measured error in `tip_rel` inside the horizon (m).
    pub error_m: f64,
    /// The relative error of the statistics beyond the horizon to expect of the run (the
    /// row's, or with clearance at least [`CLEARANCE_STATISTICS_FLOOR`]).
    pub statistics_rel: f64,
}

/// Why: the row, the accuracy, the scene's kind and what the row measured.
impl std::fmt::Display for AccuracyPlan {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let row = &self.row;
        write!(f, "{}", row.method)?;
        if self.method != Method::Exact {
            write!(f, " at rtol {:e}", row.rtol)?;
        }
        if let Some(h) = self.longest_step {
            write!(
                f,
                " with steps up to {} ms across the samples (Hermite-interpolated)",
                h * 1e3
            )?;
        }
        write!(
            f,
            ", the cheapest measured run within {:e} m / {MARGIN} for scenes {} ({:.1e} m in \
             {:.3} s on {})",
            self.accuracy_m,
            row.kind.describe(),
            row.error_m,
            row.wall_s,
            row.scene
        )?;
        if let Some(t) = self.exact_from {
            write!(f, "; exact stepping from t = {t} s on (positions at rest)")?;
        }
        Ok(())
    }
}

/// The relative spread of the per-second peak and RMS of `tip_rel` between correct runs of a
/// scene with clearance that is linear and time-invariant between switches: `exact` on
/// adams-clearance (`docs/wp-adams-clearance.csv`: 2.7 %). The table's row for such scenes is
/// measured on adams-linear, which has no impacts and so no such floor.
pub const CLEARANCE_STATISTICS_FLOOR: f64 = 0.027;

/// The cheapest plan that reaches `accuracy` (m) in `tip_rel` on the scene of `params` over
/// `span`, among the rows that resolve what `resolve` says.
///
/// # Errors
/// A message naming the rule when `accuracy` is outside [`ACCURACY_RANGE`] or below what the
/// table's rows for the scene's kind reach.
pub fn plan_for_accuracy(
    params: &ModelParams,
    span: &TimeSpan,
    accuracy: f64,
    resolve: Resolve,
) -> Result<AccuracyPlan, String> {
    let (low, high) = ACCURACY_RANGE;
    if !(accuracy.is_finite() && (low..=high).contains(&accuracy)) {
        return Err(format!(
            "accuracy must be {low:e} to {high:e} m of tip_rel (got {accuracy:e} m)"
        ));
    }
    let kind = SceneKind::of(params);
    let row = cheapest(kind, accuracy, resolve)?;
    let method = Method::from_name(row.method).expect("the table names known methods");
    let exact_from = exact_tail_start(params, span).filter(|_| method != Method::Exact);
    Ok(AccuracyPlan {
        method,
        // exact stepping has no tolerance: the default one stands
        rtol: if row.rtol > 0.0 {
            row.rtol
        } else {
            crate::Settings::default().rtol
        },
        exact_from,
        longest_step: row.longest_step.filter(|&h| h > span.sample),
        accuracy_m: accuracy,
        row: *row,
        error_m: row.error_m,
        statistics_rel: if params.contact.is_linear() {
            row.statistics_rel
        } else {
            row.statistics_rel.max(CLEARANCE_STATISTICS_FLOOR)
        },
    })
}

/// The cheapest row of `kind` whose measured error is within `accuracy` (m) over [`MARGIN`].
///
/// # Errors
/// A message naming the finest row of the kind when none is.
pub fn cheapest(
    kind: SceneKind,
    accuracy: f64,
    resolve: Resolve,
) -> Result<&'static MeasuredRun, String> {
    let rows = rows_of(kind, resolve);
    if let Some(row) = rows
        .clone()
        .filter(|r| r.error_m * MARGIN <= accuracy)
        .min_by(|a, b| a.wall_s.total_cmp(&b.wall_s))
    {
        return Ok(row);
    }
    let finest = rows
        .min_by(|a, b| a.error_m.total_cmp(&b.error_m))
        .expect("every kind has a row");
    Err(format!(
        "accuracy {accuracy:e} m is finer than any measured run reaches for scenes {}: the \
         best, {} at rtol {:e}, measured {:.1e} m on {}; ask for at least {:.1e} m",
        kind.describe(),
        finest.method,
        finest.rtol,
        finest.error_m,
        finest.scene,
        round_up_two_digits(finest.error_m * MARGIN)
    ))
}

/// The rows of `kind` that resolve what `resolve` says.
fn rows_of(
    kind: SceneKind,
    resolve: Resolve,
) -> impl Iterator<Item = &'static MeasuredRun> + Clone {
    MEASURED.iter().filter(move |r| {
        r.kind == kind
            && match resolve {
                Resolve::Displacements => true,
                Resolve::EverySample => r.longest_step.is_none(),
                Resolve::Moments => r.method != "imex",
            }
    })
}

/// How many times finer than its run's measured error a companion run is integrated: the
/// companion's difference from the run then holds the run's own integration error, and the
/// companion's (its row's stored figure) adds at most a tenth of it.
pub const COMPANION_RATIO: f64 = 10.0;

/// The accuracy (m) to ask of the companion of a run planned on `row` of `kind`, among the
/// rows that resolve what `resolve` says: the cheapest row whose measured error is at most
/// `row`'s over [`COMPANION_RATIO`] is the one [`cheapest`] then picks. `None` when no row
/// is that fine (`row` is the finest of its kind: exact stepping, rounding).
///
/// ```
/// use telescopic_runtime::analysis::accuracy::{
///     COMPANION_RATIO, MEASURED, Resolve, cheapest, companion_accuracy,
/// };
/// let run = &MEASURED[5]; // case-study: dop853 at rtol 1e-5
/// let asked = companion_accuracy(run.kind, run, Resolve::EverySample).unwrap();
/// let companion = cheapest(run.kind, asked, Resolve::EverySample).unwrap();
/// assert!(companion.error_m * COMPANION_RATIO <= run.error_m);
/// ```
pub fn companion_accuracy(kind: SceneKind, row: &MeasuredRun, resolve: Resolve) -> Option<f64> {
    rows_of(kind, resolve)
        .filter(|r| r.error_m * COMPANION_RATIO <= row.error_m)
        .min_by(|a, b| a.wall_s.total_cmp(&b.wall_s))
        .map(|r| (r.error_m * MARGIN).max(ACCURACY_RANGE.0))
}

/// `x > 0` rounded up to two significant digits, so that the printed bound is one a request
/// can meet (2.43e-9 -> 2.5e-9, where rounding to nearest printed 2e-9).
fn round_up_two_digits(x: f64) -> f64 {
    let unit = 10f64.powf(x.log10().floor() - 1.0);
    (x / unit).ceil() * unit
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_companion_is_integrated_a_tenth_as_coarsely_wherever_a_finer_row_exists() {
        for resolve in [Resolve::EverySample, Resolve::Moments] {
            for row in &MEASURED {
                let finer =
                    rows_of(row.kind, resolve).any(|r| r.error_m * COMPANION_RATIO <= row.error_m);
                match companion_accuracy(row.kind, row, resolve) {
                    Some(asked) => {
                        let picked = cheapest(row.kind, asked, resolve).unwrap();
                        assert!(
                            picked.error_m * COMPANION_RATIO <= row.error_m,
                            "{row:?}: {picked:?}"
                        );
                    }
                    None => assert!(!finer, "{row:?} has a finer row"),
                }
            }
        }
        // exact stepping is the finest of its kind: its figure stays a stored one
        let exact = MEASURED.iter().find(|r| r.method == "exact").unwrap();
        assert_eq!(
            companion_accuracy(exact.kind, exact, Resolve::EverySample),
            None
        );
    }

    #[test]
    fn every_kind_has_a_row_that_reaches_the_default_accuracy() {
        for kind in [
            SceneKind::LinearTimeInvariant,
            SceneKind::ContactsAlwaysClosed,
            SceneKind::Impacts,
        ] {
            assert!(
                MEASURED
                    .iter()
                    .any(|r| r.kind == kind && r.error_m * MARGIN <= DEFAULT_ACCURACY_M),
                "{kind:?}"
            );
        }
    }
}
