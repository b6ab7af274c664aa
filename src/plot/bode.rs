//! The Bode plot of a [`FrequencyResponse`] (`telescopic bode --plot`): per input a magnitude
//! panel (log-log) and a phase panel, one line per output, the natural frequencies marked by
//! thin vertical lines.

use crate::Result;
use crate::linear::bode::{FrequencyResponse, ResponseCurve};
use crate::plot::{Figure, plot_error, titled_page};
use plotters::prelude::*;

/// Most natural frequencies labelled on a panel (all are marked).
const LABELLED: usize = 8;

impl Figure for FrequencyResponse {
    fn size(&self) -> (u32, u32) {
        (1000, 40 + 330 * 2 * self.inputs().len() as u32)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, plotters::coord::Shift>,
    ) -> Result<()> {
        let title = format!(
            "{}: frequency response at {}",
            self.scene, self.operating_point
        );
        let page = titled_page(root, &title)?;
        let inputs = self.inputs();
        let areas = page.split_evenly((2 * inputs.len(), 1));
        for (k, input) in inputs.iter().enumerate() {
            let curves: Vec<&ResponseCurve> =
                self.curves.iter().filter(|c| &c.input == input).collect();
            let unit = format!("per {}", input);
            self.panel(
                &areas[2 * k],
                &curves,
                &format!("magnitude from {input}"),
                &unit,
                true,
            )?;
            self.panel(
                &areas[2 * k + 1],
                &curves,
                &format!("phase from {input}"),
                "phase [deg]",
                false,
            )?;
        }
        page.present().map_err(plot_error)
    }
}

impl FrequencyResponse {
    /// The inputs in order of first appearance.
    fn inputs(&self) -> Vec<String> {
        let mut out: Vec<String> = Vec::new();
        for c in &self.curves {
            if !out.contains(&c.input) {
                out.push(c.input.clone());
            }
        }
        out
    }

    /// One panel over log10 frequency: log10 magnitudes or phases, with the marks.
    fn panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, plotters::coord::Shift>,
        curves: &[&ResponseCurve],
        title: &str,
        y_desc: &str,
        magnitude: bool,
    ) -> Result<()> {
        let x: Vec<f64> = self.f_hz.iter().map(|f| f.log10()).collect();
        let values = |c: &ResponseCurve| -> Vec<f64> {
            if magnitude {
                c.magnitude.iter().map(|m| m.max(1e-300).log10()).collect()
            } else {
                c.phase_deg.clone()
            }
        };
        let all: Vec<f64> = curves
            .iter()
            .flat_map(|c| values(c))
            .filter(|v| v.is_finite())
            .collect();
        let (lo, hi) = all
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), &v| (a.min(v), b.max(v)));
        let pad = 0.05 * (hi - lo).max(1e-9);
        let (x0, x1) = (x[0], x[x.len() - 1]);
        let mut chart = ChartBuilder::on(area)
            .caption(title, ("sans-serif", 16))
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(70)
            .build_cartesian_2d(x0..x1, lo - pad..hi + pad)
            .map_err(plot_error)?;
        let power = |v: &f64| format!("{:.1e}", 10f64.powf(*v));
        let plain = |v: &f64| format!("{v:.0}");
        chart
            .configure_mesh()
            .x_desc("frequency [Hz]")
            .y_desc(y_desc)
            .x_label_formatter(&power)
            .y_label_formatter(if magnitude { &power } else { &plain })
            .draw()
            .map_err(plot_error)?;
        for (i, f) in self.natural_hz.iter().enumerate() {
            let lf = f.log10();
            if lf < x0 || lf > x1 {
                continue;
            }
            chart
                .draw_series(LineSeries::new(
                    [(lf, lo - pad), (lf, hi + pad)],
                    BLACK.mix(0.25),
                ))
                .map_err(plot_error)?;
            if i < LABELLED {
                chart
                    .draw_series([Text::new(
                        crate::plot::tick_label(*f, *f),
                        (lf, hi + pad),
                        ("sans-serif", 10),
                    )])
                    .map_err(plot_error)?;
            }
        }
        for (i, c) in curves.iter().enumerate() {
            let color = Palette99::pick(i).to_rgba();
            let unit = if magnitude {
                format!(" [{}]", c.unit)
            } else {
                String::new()
            };
            chart
                .draw_series(LineSeries::new(
                    x.iter().copied().zip(values(c)),
                    color.stroke_width(2),
                ))
                .map_err(plot_error)?
                .label(format!("{}{unit}", c.output))
                .legend(move |(x, y)| {
                    PathElement::new([(x, y), (x + 20, y)], color.stroke_width(2))
                });
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerLeft)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .label_font(("sans-serif", 11))
            .draw()
            .map_err(plot_error)
    }
}
