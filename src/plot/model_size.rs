//! The chart of [`crate::analysis::model_size`] (SVG or PNG with plotters).

use super::{Figure, LogSeries, YAxis, log_panel, plot_error, titled_page};
use crate::Result;
use crate::analysis::model_size::*;
use plotters::prelude::*;
use telescopic_runtime::Basis;

impl ModelSizeStudy {
    /// The chart: error against counted work, one curve per size, the front marked.
    pub fn chart(&self) -> impl Figure + '_ {
        SizeChart { study: self }
    }
}

struct SizeChart<'a> {
    study: &'a ModelSizeStudy,
}

impl Figure for SizeChart<'_> {
    fn size(&self) -> (u32, u32) {
        (900, 650)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, plotters::coord::Shift>,
    ) -> Result<()> {
        let s = self.study;
        let title = format!(
            "whole error against cost, {} (against the beams: {}; pointwise to {} s)",
            s.scene, s.reference, s.window.end
        );
        let root = titled_page(root, &title)?;
        let mut sizes: Vec<ModelSize> = Vec::new();
        for p in &s.points {
            if !sizes.contains(&p.size) {
                sizes.push(p.size);
            }
        }
        let mut series: Vec<LogSeries> = sizes
            .iter()
            .map(|size| LogSeries {
                label: match size.basis {
                    Basis::Modes => format!("{} modes", size.modes),
                    Basis::ModesAndStatic => format!("{} modes + static", size.modes),
                },
                points: s
                    .points
                    .iter()
                    .filter(|p| p.size == *size)
                    .map(|p| (p.operations, p.tip_error.max(1e-16)))
                    .collect(),
                marks: Vec::new(),
            })
            .collect();
        let mut front: Vec<&SizePoint> = s.points.iter().filter(|p| p.pareto).collect();
        front.sort_by(|a, b| a.operations.total_cmp(&b.operations));
        series.push(LogSeries {
            label: "Pareto front".into(),
            points: front
                .iter()
                .map(|p| (p.operations, p.tip_error.max(1e-16)))
                .collect(),
            marks: front.iter().map(|p| p.size.to_string()).collect(),
        });
        log_panel(
            &root,
            (
                "tip_rel error against the beams",
                "counted work [operations]",
                "max |error| [m]",
            ),
            &series,
            YAxis::Log,
            None,
        )?;
        root.present().map_err(plot_error)
    }
}
