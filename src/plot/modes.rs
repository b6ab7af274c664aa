//! The mode shapes of a telescope as a picture (`telescopic modes --plot FILE.svg`): one
//! panel per mode, the telescope upright, each section along its own axis (section `k`'s
//! axis drawn a little to the right of section `k-1`'s, so that the overlaps stay apart),
//! its deflection scaled so that the largest is a fixed share of the height; the frequency,
//! damping ratio and kind of each mode in its title.
//!
//! ```
//! use telescopic::Scene;
//! use telescopic::plot::modes::ModeShapeFigure;
//! use telescopic::analysis::modes::{ModesOptions, compute_modes};
//!
//! let scene = Scene::load("scenes/test-rig.toml".as_ref(), &[])?;
//! let options = ModesOptions { shapes: Some(21), count: Some(4), ..ModesOptions::default() };
//! let figure = ModeShapeFigure::new(&scene, &compute_modes(&scene, &options)?)?;
//! assert_eq!(figure.modes.len(), 4);
//! assert_eq!(figure.modes[0].sections[1].heights[0], 1.15); // section 2's foot at a_2
//! # Ok::<(), telescopic::Error>(())
//! ```

use crate::OptionName;
use crate::analysis::modes::{ModeKind, ModesReport};
use crate::plot::{Figure, plot_error, titled_page, upper_left_legend};
use crate::{Error, Result};
use plotters::prelude::*;
use telescopic_runtime::Scene;

/// Most modes drawn (two columns of panels).
pub const MAX_PLOTTED_MODES: usize = 8;

/// Largest deflection drawn, as a share of the telescope's height.
const DEFLECTION_SHARE: f64 = 0.12;

/// Horizontal distance between neighbouring sections' axes, as a share of the height.
const AXIS_OFFSET_SHARE: f64 = 0.06;

/// One section's curve in a mode.
#[derive(Debug, Clone, PartialEq)]
pub struct SectionCurve {
    /// Section `k` (1-based).
    pub section: usize,
    /// Height of each point above the foot of section 1 (m).
    pub heights: Vec<f64>,
    /// Deflection at each point, scaled so that the mode's largest `|w|` is 1.
    pub deflections: Vec<f64>,
}

/// One mode's panel.
#[derive(Debug, Clone, PartialEq)]
pub struct PlottedMode {
    /// Panel title: number, frequency, damping ratio and kind.
    pub title: String,
    /// One curve per section, bottom up.
    pub sections: Vec<SectionCurve>,
}

/// The mode-shape picture of a [`ModesReport`] with sampled shapes.
#[derive(Debug, Clone, PartialEq)]
pub struct ModeShapeFigure {
    /// Page title.
    pub title: String,
    /// Height of the telescope's top above the foot of section 1 (m).
    pub height: f64,
    /// The panels, at most [`MAX_PLOTTED_MODES`].
    pub modes: Vec<PlottedMode>,
}

impl ModeShapeFigure {
    /// The figure of `report` (computed for `scene` with `shapes` sampled).
    ///
    /// # Errors
    /// [`Error::Option`] when the report has no sampled shapes.
    pub fn new(scene: &Scene, report: &ModesReport) -> Result<Self> {
        let shapes = report.mode_shapes.as_ref().ok_or_else(|| {
            Error::option(
                OptionName::Shapes,
                "a mode-shape plot needs the shapes sampled (2 or more points per section)",
            )
        })?;
        let params = &scene.params;
        let feet = crate::animate::geometry::feet(params, report.time_s);
        let height = crate::animate::geometry::height(params, report.time_s);
        let modes = shapes
            .iter()
            .take(MAX_PLOTTED_MODES)
            .enumerate()
            .map(|(i, shape)| PlottedMode {
                title: format!(
                    "f{} = {:.4} Hz, zeta {:.2e}{}",
                    i + 1,
                    shape.frequency_hz,
                    report.damping_ratios[i],
                    if report.kinds[i] == ModeKind::Contact {
                        " (contact mode)"
                    } else {
                        ""
                    }
                ),
                sections: shape
                    .sections
                    .iter()
                    .enumerate()
                    .map(|(k, w)| {
                        let l = params.sections[k].length;
                        let step = l / (w.len() - 1) as f64;
                        SectionCurve {
                            section: k + 1,
                            heights: (0..w.len()).map(|j| feet[k] + j as f64 * step).collect(),
                            deflections: w.clone(),
                        }
                    })
                    .collect(),
            })
            .collect();
        Ok(ModeShapeFigure {
            title: format!(
                "{}: mode shapes at t = {} s (contacts closed; deflection scaled)",
                report.scene, report.time_s
            ),
            height,
            modes,
        })
    }

    /// Draws the figure to an SVG or PNG file (by extension), completely or not at all.
    ///
    /// # Errors
    /// [`Error::Plot`] or [`Error::Write`].
    pub fn save(&self, path: &std::path::Path) -> Result<()> {
        crate::plot::save(self, path)
    }
}

impl Figure for ModeShapeFigure {
    fn size(&self) -> (u32, u32) {
        let rows = self.modes.len().div_ceil(2).max(1) as u32;
        (1000, 40 + 420 * rows)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, plotters::coord::Shift>,
    ) -> Result<()> {
        let page = titled_page(root, &self.title)?;
        let rows = self.modes.len().div_ceil(2).max(1);
        let areas = page.split_evenly((rows, 2));
        for (mode, area) in self.modes.iter().zip(&areas) {
            self.draw_mode(mode, area)?;
        }
        page.present().map_err(plot_error)
    }
}

impl ModeShapeFigure {
    /// One panel: the sections' axes (thin, grey) and deflected shapes (coloured).
    fn draw_mode<DB: DrawingBackend>(
        &self,
        mode: &PlottedMode,
        area: &DrawingArea<DB, plotters::coord::Shift>,
    ) -> Result<()> {
        let h = self.height;
        let (scale, offset) = (DEFLECTION_SHARE * h, AXIS_OFFSET_SHARE * h);
        let sections = mode.sections.len() as f64;
        let x_range = -1.6 * scale..(sections - 1.0) * offset + 1.6 * scale;
        let mut chart = ChartBuilder::on(area)
            .caption(&mode.title, ("sans-serif", 15))
            .margin(8)
            .x_label_area_size(30)
            .y_label_area_size(50)
            .build_cartesian_2d(x_range, 0.0..h * 1.04)
            .map_err(plot_error)?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_desc("deflection (scaled), axes offset per section")
            .y_desc("height [m]")
            .x_label_formatter(&|_| String::new())
            .draw()
            .map_err(plot_error)?;
        for curve in &mode.sections {
            let axis = (curve.section - 1) as f64 * offset;
            let (bottom, top) = (curve.heights[0], *curve.heights.last().unwrap_or(&0.0));
            chart
                .draw_series(LineSeries::new(
                    [(axis, bottom), (axis, top)],
                    BLACK.mix(0.3).stroke_width(1),
                ))
                .map_err(plot_error)?;
            let color = Palette99::pick(curve.section - 1).to_rgba();
            let points: Vec<(f64, f64)> = curve
                .deflections
                .iter()
                .zip(&curve.heights)
                .map(|(w, y)| (axis + scale * w, *y))
                .collect();
            chart
                .draw_series(LineSeries::new(points, color.stroke_width(3)))
                .map_err(plot_error)?
                .label(format!("section {}", curve.section))
                .legend(move |(x, y)| {
                    PathElement::new([(x, y), (x + 20, y)], color.stroke_width(3))
                });
        }
        upper_left_legend(&mut chart)
    }
}
