//! The evaluation error of the shape functions for modes 1..30,
//! the paper's printed forms in `f64` against the cancellation-free forms, both measured
//! against the printed forms in 512-bit arithmetic. Shows the failure of the naive form
//! instead of only avoiding it.

use crate::OptionName;
use crate::{Error, Result};
use std::io::Write;
use telescopic_runtime::shape::reference::{Hp, evaluation_errors};
use telescopic_runtime::shape::{MAX_MODES, SectionKind};

/// Most evaluation points along a section: each point costs 512-bit evaluations of four
/// derivatives of 57 shape functions (1000 points took 48 s on the project's machine, the
/// default 41 about 2 s).
pub const MAX_POINTS: usize = 1000;

/// Options of [`shape_errors`].
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeErrorsOptions {
    /// Section length (m); the errors barely depend on it (default 1.35).
    pub length: f64,
    /// Evaluation points along the section, 2 to [`MAX_POINTS`] (default 41).
    pub points: usize,
}

impl Default for ShapeErrorsOptions {
    fn default() -> Self {
        ShapeErrorsOptions {
            length: 1.35,
            points: 41,
        }
    }
}

/// Worst errors of one mode: `(kind, mode, cancellation-free, printed)`.
pub type Row = (SectionKind, usize, f64, f64);

/// The result of [`shape_errors`]: one row per elastic mode of each section kind.
#[derive(Debug, Clone, PartialEq)]
pub struct ShapeErrors {
    /// `(kind, mode, error of the cancellation-free form, error of the printed form)`.
    pub rows: Vec<Row>,
}

/// The evaluation error of the shape functions for modes 1..30 in `f64`: the printed forms
/// and the cancellation-free ones, both against the printed forms in 512-bit arithmetic.
///
/// # Errors
/// [`Error::Option`] for a length or point count out of range.
pub fn shape_errors(options: &ShapeErrorsOptions) -> Result<ShapeErrors> {
    if !(options.length > 0.0 && options.length.is_finite()) {
        return Err(Error::option(
            OptionName::ShapeLength,
            format!(
                "must be a positive number of metres (got {})",
                options.length
            ),
        ));
    }
    if !(2..=MAX_POINTS).contains(&options.points) {
        return Err(Error::option(
            OptionName::ShapePoints,
            format!(
                "must be 2 to {MAX_POINTS} (got {}); each point costs 512-bit evaluations of \
                 57 shape functions (1000 take about 50 s)",
                options.points
            ),
        ));
    }
    let mut hp = Hp::new();
    let mut rows: Vec<Row> = Vec::new();
    for kind in [SectionKind::GuidedFree, SectionKind::FreeFree] {
        // rigid modes (beta = 0) are exact constants or lines in both forms
        let first_elastic = if kind == SectionKind::GuidedFree {
            2
        } else {
            3
        };
        for i in first_elastic..=MAX_MODES {
            let (free, printed) =
                evaluation_errors(&mut hp, kind, i, options.length, options.points);
            rows.push((kind, i, free, printed));
        }
    }
    Ok(ShapeErrors { rows })
}

impl ShapeErrors {
    /// The CSV table: kind, mode, worst scaled error of each form.
    ///
    /// # Errors
    /// The writer's error.
    pub fn write_table(&self, w: &mut dyn Write) -> std::io::Result<()> {
        writeln!(w, "kind,mode,cancellation_free_error,printed_error")?;
        for (kind, i, free, printed) in &self.rows {
            writeln!(w, "{},{i},{free:e},{printed:e}", kind_name(*kind))?;
        }
        Ok(())
    }
}

/// The section kind as the table names it.
pub(crate) fn kind_name(kind: SectionKind) -> &'static str {
    match kind {
        SectionKind::GuidedFree => "guided-free",
        SectionKind::FreeFree => "free-free",
    }
}
