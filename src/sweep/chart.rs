//! Charts of a sweep's results: a metric against an override key, one line per value of a
//! second key, or a heat map over both.

use super::table::{SweepTable, split_csv};
use crate::OptionName;
use crate::plot::{COLORS, Figure, plot_error, tick_label, titled_page, upper_left_legend};
use crate::{Error, Result};
use plotters::prelude::*;

/// The chart of [`chart`].
#[derive(Debug, Clone)]
pub struct SweepChart {
    title: String,
    x: String,
    y: String,
    color: Option<String>,
    /// `(series label, points (x, y))`, points sorted by x.
    series: Vec<(String, Vec<(f64, f64)>)>,
    heatmap: bool,
}

/// Most lines of a line chart (distinct values of the color column).
pub const MAX_LINES: usize = 64;

/// A chart of column `y` against column `x` of `table`, a line per value of `color` (or a
/// heat map over `x` and `color`); failed runs and empty cells are left out.
///
/// # Errors
/// [`Error::Option`] naming a column that is missing or not numeric, or a table without a
/// successful run.
pub fn chart(
    table: &SweepTable,
    x: &str,
    y: &str,
    color: Option<&str>,
    heatmap: bool,
) -> Result<SweepChart> {
    let columns = split_csv(&table.columns);
    let find = |name: &str, option: OptionName| {
        columns.iter().position(|c| c == name).ok_or_else(|| {
            Error::option(
                option,
                format!(
                    "`{name}` is not a column; the columns are {}",
                    columns.join(", ")
                ),
            )
        })
    };
    let (ix, iy) = (find(x, OptionName::ChartX)?, find(y, OptionName::ChartY)?);
    let ic = color.map(|c| find(c, OptionName::ChartColor)).transpose()?;
    let status = find("status", OptionName::ChartY)?;
    let mut groups: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    // the group of each label: linear in the rows however many labels there are
    let mut group_of: std::collections::HashMap<String, usize> = Default::default();
    for (_, line) in &table.rows {
        let cells = split_csv(line);
        if cells.get(status).map(String::as_str) != Some("ok") {
            continue;
        }
        let number = |i: usize| {
            cells
                .get(i)
                .and_then(|v| v.parse::<f64>().ok())
                .filter(|v| v.is_finite())
        };
        let (Some(xv), Some(yv)) = (number(ix), number(iy)) else {
            continue;
        };
        let label = ic
            .map(|i| cells.get(i).cloned().unwrap_or_default())
            .unwrap_or_default();
        match group_of.get(&label) {
            Some(&g) => groups[g].1.push((xv, yv)),
            None => {
                group_of.insert(label.clone(), groups.len());
                groups.push((label, vec![(xv, yv)]));
            }
        }
    }
    if !heatmap && groups.len() > MAX_LINES {
        return Err(Error::option(
            OptionName::ChartColor,
            format!(
                "`{}` has {} distinct values; a line chart shows at most {MAX_LINES} lines: \
                 draw a heat map, or color by a column with fewer values",
                color.unwrap_or(""),
                groups.len()
            ),
        ));
    }
    if groups.is_empty() {
        return Err(Error::option(
            OptionName::ChartY,
            format!("no successful run has numbers in both `{x}` and `{y}`"),
        ));
    }
    if heatmap && groups.iter().any(|(l, _)| l.parse::<f64>().is_err()) {
        return Err(Error::option(
            OptionName::ChartHeatmap,
            format!("the color column `{}` is not numeric", color.unwrap_or("")),
        ));
    }
    for (_, points) in &mut groups {
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    groups.sort_by(|a, b| match (a.0.parse::<f64>(), b.0.parse::<f64>()) {
        (Ok(p), Ok(q)) => p.total_cmp(&q),
        _ => a.0.cmp(&b.0),
    });
    let sweep = table.header_field("file").unwrap_or("sweep").to_string();
    Ok(SweepChart {
        title: format!("{y} against {x} ({sweep})"),
        x: x.into(),
        y: y.into(),
        color: color.map(str::to_string),
        series: groups,
        heatmap,
    })
}

/// The unit of a column, where it is known: the metrics and every continuous scene key
/// ([`telescopic_runtime::scene::KEYS`]).
pub fn unit_of(column: &str) -> Option<&'static str> {
    let unit = match column {
        "tip_rel_max" | "tip_rel_rms" | "residual_std" => "m",
        "contact_force_max" => "N",
        "f1_hz" => "Hz",
        "wall_s" => "s",
        key => return telescopic_runtime::scene::keys::unit_of(key),
    };
    Some(unit)
}

/// A column's name with its unit, for an axis.
fn axis_label(column: &str) -> String {
    match unit_of(column) {
        Some(unit) => format!("{column} [{unit}]"),
        None => column.to_string(),
    }
}

/// A sequential colour from light (0) to dark (1), for a metric that is never negative
/// (viridis' stops, reversed: small values pale, large ones dark).
fn sequential(v: f64) -> RGBColor {
    const STOPS: [(f64, f64, f64); 5] = [
        (253.0, 231.0, 37.0),
        (94.0, 201.0, 98.0),
        (33.0, 145.0, 140.0),
        (59.0, 82.0, 139.0),
        (68.0, 1.0, 84.0),
    ];
    let x = v.clamp(0.0, 1.0) * (STOPS.len() - 1) as f64;
    let i = (x.floor() as usize).min(STOPS.len() - 2);
    let t = x - i as f64;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    let mix = |p: f64, q: f64| (p + (q - p) * t).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// The padded axis range of `[lo, hi]`, kept on the data's side of zero: a positive
/// quantity's axis does not run into negative values.
fn padded(lo: f64, hi: f64) -> (f64, f64) {
    let pad = 0.05 * (hi - lo).max(1e-12 * hi.abs().max(1e-300));
    let below = if lo >= 0.0 {
        (lo - pad).max(0.0)
    } else {
        lo - pad
    };
    let above = if hi <= 0.0 {
        (hi + pad).min(0.0)
    } else {
        hi + pad
    };
    (below, above)
}

/// A colour from blue (0) to red (1) through white, for a metric of either sign.
fn ramp(v: f64) -> RGBColor {
    let v = v.clamp(0.0, 1.0);
    let mix = |a: f64, b: f64, t: f64| (a + (b - a) * t).round() as u8;
    if v < 0.5 {
        let t = v / 0.5;
        RGBColor(
            mix(49.0, 247.0, t),
            mix(54.0, 247.0, t),
            mix(149.0, 247.0, t),
        )
    } else {
        let t = (v - 0.5) / 0.5;
        RGBColor(
            mix(247.0, 165.0, t),
            mix(247.0, 0.0, t),
            mix(247.0, 38.0, t),
        )
    }
}

/// The sorted distinct values of `v`, and for each the cell `[low, high]` around it (halfway
/// to its neighbours).
fn cells(mut v: Vec<f64>) -> (Vec<f64>, Vec<(f64, f64)>) {
    v.sort_by(f64::total_cmp);
    v.dedup();
    let n = v.len();
    let bounds = (0..n)
        .map(|i| {
            let below = if i > 0 {
                0.5 * (v[i] - v[i - 1])
            } else if n > 1 {
                0.5 * (v[1] - v[0])
            } else {
                0.5
            };
            let above = if i + 1 < n {
                0.5 * (v[i + 1] - v[i])
            } else {
                below
            };
            (v[i] - below, v[i] + above)
        })
        .collect();
    (v, bounds)
}

impl SweepChart {
    /// The heat map: cells over x and the colour key, coloured by y, and a colour bar.
    fn draw_heatmap<DB: DrawingBackend>(
        &self,
        page: DrawingArea<DB, plotters::coord::Shift>,
    ) -> Result<()> {
        let all = || self.series.iter().flat_map(|(_, p)| p.iter());
        let (y0, y1) = all().fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.1), b.max(p.1)));
        let (xs, xcells) = cells(all().map(|p| p.0).collect());
        let keys: Vec<f64> = self
            .series
            .iter()
            .map(|(l, _)| l.parse::<f64>().unwrap_or(0.0))
            .collect();
        let (ks, kcells) = cells(keys.clone());
        let (left, bar) = page.split_horizontally(page.dim_in_pixel().0.saturating_sub(150));
        let (xa, xb) = (xcells[0].0, xcells[xcells.len() - 1].1);
        let (ka, kb) = (kcells[0].0, kcells[kcells.len() - 1].1);
        let mut chart = ChartBuilder::on(&left)
            .margin(20)
            .x_label_area_size(45)
            .y_label_area_size(90)
            .build_cartesian_2d(xa..xb, ka..kb)
            .map_err(plot_error)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(axis_label(&self.x))
            .y_desc(axis_label(self.color.as_deref().unwrap_or("")))
            .x_label_formatter(&|v| tick_label(*v, xb - xa))
            .y_label_formatter(&|v| tick_label(*v, kb - ka))
            .draw()
            .map_err(plot_error)?;
        // a positive metric on a sequential scale; one of either sign on a diverging one
        let scale: fn(f64) -> RGBColor = if y0 >= 0.0 { sequential } else { ramp };
        let shade = |y: f64| scale((y - y0) / (y1 - y0).max(1e-300));
        // values in the cells only where there is room for them
        let cell_px = left.dim_in_pixel().0 as usize / xs.len().max(1);
        let label_cells = cell_px >= 70 && ks.len() <= 20;
        for ((_, points), k) in self.series.iter().zip(&keys) {
            let (k_lo, k_hi) = kcells[ks.iter().position(|v| v == k).unwrap_or(0)];
            for &(x, y) in points {
                let (x_lo, x_hi) = xcells[xs.iter().position(|&v| v == x).unwrap_or(0)];
                chart
                    .draw_series([Rectangle::new(
                        [(x_lo, k_lo), (x_hi, k_hi)],
                        shade(y).filled(),
                    )])
                    .map_err(plot_error)?;
                if label_cells {
                    chart
                        .draw_series([Text::new(
                            format!("{y:.3e}"),
                            (x_lo + 0.1 * (x_hi - x_lo), 0.5 * (k_lo + k_hi)),
                            ("sans-serif", 12),
                        )])
                        .map_err(plot_error)?;
                }
            }
        }
        // the colour bar: y from bottom to top
        let (_, height) = bar.dim_in_pixel();
        let (top, bottom) = (40i32, height as i32 - 65);
        let steps = 100;
        for i in 0..steps {
            let a = bottom - (bottom - top) * i / steps;
            let b = bottom - (bottom - top) * (i + 1) / steps;
            bar.draw(&Rectangle::new(
                [(20, b), (50, a)],
                scale((i as f64 + 0.5) / steps as f64).filled(),
            ))
            .map_err(plot_error)?;
        }
        bar.draw(&Rectangle::new(
            [(20, top), (50, bottom)],
            BLACK.stroke_width(1),
        ))
        .map_err(plot_error)?;
        for (frac, value) in [(0.0, y0), (0.5, 0.5 * (y0 + y1)), (1.0, y1)] {
            let py = bottom - ((bottom - top) as f64 * frac) as i32;
            bar.draw(&Text::new(
                format!("{value:.3e}"),
                (56, py - 6),
                ("sans-serif", 13),
            ))
            .map_err(plot_error)?;
        }
        bar.draw(&Text::new(
            axis_label(&self.y),
            (10, top - 25),
            ("sans-serif", 14),
        ))
        .map_err(plot_error)?;
        page.present().map_err(plot_error)
    }
}

impl Figure for SweepChart {
    fn size(&self) -> (u32, u32) {
        (1000, 600)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, plotters::coord::Shift>,
    ) -> Result<()> {
        let root = titled_page(root, &self.title)?;
        if self.heatmap {
            return self.draw_heatmap(root);
        }
        let all = || self.series.iter().flat_map(|(_, p)| p.iter());
        let (x0, x1) = all().fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
        let (y0, y1) = all().fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.1), b.max(p.1)));
        let ((xa, xb), (ya, yb)) = (padded(x0, x1), padded(y0, y1));
        let mut chart = ChartBuilder::on(&root)
            .margin(20)
            .x_label_area_size(45)
            .y_label_area_size(90)
            .build_cartesian_2d(xa..xb, ya..yb)
            .map_err(plot_error)?;
        chart
            .configure_mesh()
            .x_desc(axis_label(&self.x))
            .y_desc(axis_label(&self.y))
            .x_label_formatter(&|v| tick_label(*v, x1 - x0))
            .y_label_formatter(&|v| tick_label(*v, y1 - y0))
            .draw()
            .map_err(plot_error)?;
        for (i, (label, points)) in self.series.iter().enumerate() {
            let color = COLORS[i % COLORS.len()];
            let legend = match &self.color {
                Some(key) => format!("{key} = {label}"),
                None => self.y.clone(),
            };
            chart
                .draw_series(LineSeries::new(points.clone(), color.stroke_width(2)))
                .map_err(plot_error)?
                .label(legend)
                .legend(move |(x, y)| {
                    PathElement::new([(x, y), (x + 20, y)], color.stroke_width(2))
                });
            chart
                .draw_series(points.iter().map(|&p| Circle::new(p, 4, color.filled())))
                .map_err(plot_error)?;
        }
        upper_left_legend(&mut chart)?;
        root.present().map_err(plot_error)
    }
}
