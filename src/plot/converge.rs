//! The chart of [`crate::analysis::converge`] (SVG or PNG with plotters).

use super::{Figure, LogSeries, YAxis, log_panel, plot_error, titled_page};
use crate::Result;
use crate::analysis::converge::*;
use plotters::prelude::*;

impl Convergence {
    /// The error-against-cost chart (for [`crate::plot::save`]).
    pub fn chart(&self) -> impl Figure + '_ {
        ConvergenceChart {
            scene: &self.scene,
            tol: self.tol,
            trials: &self.by_modes,
            pointwise: self.pointwise,
        }
    }
}

/// Model error against the largest model versus cost, one point per number of modes.
struct ConvergenceChart<'a> {
    scene: &'a str,
    tol: f64,
    trials: &'a [Trial],
    pointwise: bool,
}

impl Figure for ConvergenceChart<'_> {
    fn size(&self) -> (u32, u32) {
        (1200, 500)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, plotters::coord::Shift>,
    ) -> Result<()> {
        let title = format!(
            "model error vs cost, {} (modes per section 1..{})",
            self.scene,
            self.trials.len()
        );
        let root = titled_page(root, &title)?;
        let largest = self.trials.last().expect("trials");
        let rest = &self.trials[..self.trials.len() - 1];
        let marks: Vec<String> = rest.iter().map(|t| format!("N={}", t.modes)).collect();
        let error = |t: &Trial| t.change(largest, self.pointwise).max(1e-16);
        let areas = root.split_evenly((1, 2));
        let by_wall = [LogSeries {
            label: "error vs largest model".into(),
            points: rest.iter().map(|t| (t.wall, error(t))).collect(),
            marks: marks.clone(),
        }];
        log_panel(
            &areas[0],
            (
                "error vs wall time",
                "wall time of the scene [s]",
                "relative error",
            ),
            &by_wall,
            YAxis::Log,
            Some((self.tol, "tol")),
        )?;
        let by_dof = [LogSeries {
            label: "error vs largest model".into(),
            points: rest.iter().map(|t| (t.dof as f64, error(t))).collect(),
            marks,
        }];
        log_panel(
            &areas[1],
            (
                "error vs model size",
                "degrees of freedom",
                "relative error",
            ),
            &by_dof,
            YAxis::Log,
            Some((self.tol, "tol")),
        )?;
        root.present().map_err(plot_error)
    }
}
