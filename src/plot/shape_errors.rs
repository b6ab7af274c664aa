//! The chart of [`crate::analysis::shape_errors`] (SVG or PNG with plotters).

use super::{Figure, LogSeries, YAxis, log_panel, plot_error};
use crate::Result;
use crate::analysis::shape_errors::*;
use plotters::prelude::*;
use telescopic_runtime::shape::SectionKind;

impl ShapeErrors {
    /// The chart (for [`crate::plot::save`]).
    pub fn chart(&self) -> impl Figure + '_ {
        ShapeErrorChart { rows: &self.rows }
    }
}

struct ShapeErrorChart<'a> {
    rows: &'a [Row],
}

impl Figure for ShapeErrorChart<'_> {
    fn size(&self) -> (u32, u32) {
        (900, 520)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, plotters::coord::Shift>,
    ) -> Result<()> {
        root.fill(&WHITE).map_err(plot_error)?;
        let mut series = Vec::new();
        for kind in [SectionKind::GuidedFree, SectionKind::FreeFree] {
            for (form, pick) in [
                ("printed", (|r: &Row| r.3) as fn(&Row) -> f64),
                ("cancellation-free", |r: &Row| r.2),
            ] {
                series.push(LogSeries {
                    label: format!("{} {form}", kind_name(kind)),
                    points: self
                        .rows
                        .iter()
                        .filter(|r| r.0 == kind)
                        // an exact evaluation shows at the floor of the axis
                        .map(|r| (r.1 as f64, pick(r).max(1e-17)))
                        .collect(),
                    marks: Vec::new(),
                });
            }
        }
        log_panel(
            &root,
            (
                "shape functions in f64: worst error vs 512-bit printed form (derivatives 0-3)",
                "mode i (log scale)",
                "scaled error",
            ),
            &series,
            YAxis::Log,
            Some((1e-12, "1e-12")),
        )?;
        root.present().map_err(plot_error)
    }
}
