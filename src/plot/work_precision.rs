//! The chart of [`crate::analysis::work_precision`] (SVG or PNG with plotters).

use super::{Figure, LogSeries, YAxis, log_panel, plot_error, titled_page};
use crate::Result;
use crate::analysis::work_precision::*;
use plotters::prelude::*;

impl WorkPrecision {
    /// The six-panel chart (for [`crate::plot::save`]).
    pub fn chart(&self) -> impl Figure + '_ {
        WorkPrecisionChart {
            scene: &self.scene,
            horizon: self.horizon,
            end: self.end,
            points: &self.points,
        }
    }
}

/// Six log-log panels: three errors against wall time, two against rhs evaluations, and how
/// long each run agrees with the reference.
struct WorkPrecisionChart<'a> {
    scene: &'a str,
    horizon: f64,
    end: f64,
    points: &'a [Point],
}

type Pick = fn(&Point) -> f64;

/// How a panel's y axis reads.
#[derive(Clone, Copy, PartialEq)]
enum Scale {
    /// Errors, on a log axis.
    Error,
    /// Seconds of agreement, linear from 0 to the run's end, with the horizon marked.
    AgreementTime,
}

impl Figure for WorkPrecisionChart<'_> {
    fn size(&self) -> (u32, u32) {
        (1500, 900)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, plotters::coord::Shift>,
    ) -> Result<()> {
        let title = format!(
            "work-precision, {} (T_h = {:.3} s of {} s)",
            self.scene, self.horizon, self.end
        );
        let root = titled_page(root, &title)?;
        let panels: [(&str, &str, Pick, &str, Pick, Scale); 6] = [
            (
                "tip_rel error on [0, T_h]",
                "wall time [s]",
                |p| p.wall,
                "max |error| [m]",
                |p| p.tip_error,
                Scale::Error,
            ),
            (
                "gap error on [0, T_h]",
                "wall time [s]",
                |p| p.wall,
                "max |error| [m]",
                |p| p.gap_error,
                Scale::Error,
            ),
            (
                "statistics error (whole span)",
                "wall time [s]",
                |p| p.wall,
                "per-second peak/RMS, relative",
                |p| p.statistics_error,
                Scale::Error,
            ),
            (
                "tip_rel error on [0, T_h]",
                "rhs evaluations",
                |p| p.rhs_evals as f64,
                "max |error| [m]",
                |p| p.tip_error,
                Scale::Error,
            ),
            (
                "gap error on [0, T_h]",
                "rhs evaluations",
                |p| p.rhs_evals as f64,
                "max |error| [m]",
                |p| p.gap_error,
                Scale::Error,
            ),
            (
                "agreement with the reference (1e-6 m)",
                "wall time [s]",
                |p| p.wall,
                "agrees until [s]",
                |p| p.agrees_until,
                Scale::AgreementTime,
            ),
        ];
        let areas = root.split_evenly((2, 3));
        let methods: Vec<&str> = {
            let mut m: Vec<&str> = self.points.iter().map(|p| p.method.as_str()).collect();
            m.dedup();
            m
        };
        for ((title, xd, fx, yd, fy, scale), area) in panels.iter().zip(&areas) {
            let series: Vec<LogSeries> = methods
                .iter()
                .map(|m| LogSeries {
                    label: m.to_string(),
                    points: self
                        .points
                        .iter()
                        .filter(|p| p.method == *m && p.failure.is_empty())
                        // an exact zero error shows at the floor of the axis
                        .map(|p| (fx(p), fy(p).max(1e-16)))
                        .collect(),
                    marks: Vec::new(),
                })
                .collect();
            if *scale == Scale::AgreementTime {
                let axis = YAxis::Linear(0.0, self.end);
                log_panel(
                    area,
                    (title, xd, yd),
                    &series,
                    axis,
                    Some((self.horizon, "T_h")),
                )?;
            } else {
                log_panel(area, (title, xd, yd), &series, YAxis::Log, None)?;
            }
        }
        root.present().map_err(plot_error)
    }
}
