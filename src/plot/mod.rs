//! Charts: the paper's figures of a simulation as SVG or PNG with plotters. Case-study-like scenes get
//! the vehicle (Fig. 8), `tip_rel` (Fig. 9), `top1_rel` (Fig. 10) and, for two sections, the
//! gaps at the lower and upper contact (Figs. 11, 12) with the band edges `+-l_S/2`; with
//! more sections a panel of gaps and one of contact forces per overlap. The adams scenes get
//! `tip_rel` (Figs. 14, 15). Titles name the paper's figures only for the paper's scenes. A
//! second scene (`--compare`) is overlaid.

pub(crate) mod bode;
mod converge;
mod model_size;
pub mod modes;
mod shape_errors;
mod work_precision;

use crate::run::Trajectory;
use crate::{Error, Result};
use plotters::prelude::*;
use std::path::Path;
use telescopic_runtime::Output;
use telescopic_runtime::scene::Figures;

/// What a run is in a figure; each role has one colour in every figure.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// The scene as given, without control (blue).
    Scene,
    /// A second scene compared with it, e.g. without clearance (red).
    Compared,
    /// The scene with a controller (green).
    Controlled,
}

impl Role {
    /// The role's colour.
    pub fn color(self) -> RGBColor {
        match self {
            Role::Scene => COLORS[0],
            Role::Compared => COLORS[1],
            Role::Controlled => COLORS[2],
        }
    }
}

/// One scene's run, as plotted.
pub struct Curve<'a> {
    /// Legend label: what differs between the curves (`l_S = 10 mm`, `without control`).
    pub label: String,
    /// The run.
    pub traj: &'a Trajectory,
    /// Half the clearance `l_S/2` (m), for the band edges in gap panels.
    pub half_band: f64,
    /// What the run is (sets its colour).
    pub role: Role,
}

/// Marks drawn over the panels: the drive's force limit and the residual-vibration window.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Marks {
    /// `|F| <= limit` (N), drawn on the drive-force panel.
    pub force_limit: Option<f64>,
    /// `[start, end]` (s) over which the residual vibration is measured.
    pub residual_window: Option<(f64, f64)>,
}

/// `label` with the run's stated error ([`crate::run::error_budget::ErrorBudget::legend`]),
/// when it was estimated: every figure of a run says how far its curves are from the beams.
pub fn with_stated_error(label: String, run: &crate::run::Simulation) -> String {
    match run.error.as_ref().and_then(|e| e.legend()) {
        Some(error) => format!("{label} ({error})"),
        None => label,
    }
}

/// The label of a run by its clearance, e.g. `case-study, l_S = 10 mm`.
pub fn clearance_label(scene: &telescopic_runtime::Scene) -> String {
    let mm = 2000.0 * scene.params.contact.half_band();
    format!(
        "{}, l_S = {} mm",
        scene.name,
        crate::io::output::csv_number(mm)
    )
}

/// A panel: output columns (the first drawn solid, the next dashed), axis label, title, and
/// the factor from SI to the axis's unit.
struct Panel {
    columns: Vec<String>,
    axis: String,
    title: String,
    scale: f64,
}

/// A panel's title for `output`; `lower_and_upper`: a gap is the first or the last of its
/// overlap and its title says which.
fn panel_title(output: Output, lower_and_upper: bool) -> String {
    match output {
        Output::Vehicle => "vehicle position".into(),
        Output::TipRel => "load relative to the foot".into(),
        Output::TopRel(k) => format!("top of section {k} relative to the foot"),
        Output::DriveForce => "force of the drive on the vehicle".into(),
        Output::Gap { point: 0, .. } if lower_and_upper => "gap at the lower contact".into(),
        Output::Gap { .. } if lower_and_upper => "gap at the upper contact".into(),
        other => other.description(),
    }
}

/// One output's panel, titled with the paper's figure the scene says it reproduces; gaps in
/// millimetres.
fn output_panel(figures: &Figures, output: Output, lower_and_upper: bool) -> Panel {
    let title = panel_title(output, lower_and_upper);
    let scale = if output.is_gap() { 1e3 } else { 1.0 };
    let unit = if output.is_gap() { "mm" } else { output.unit() };
    Panel {
        columns: vec![output.to_string()],
        axis: format!("{output} [{unit}]"),
        title: match figures.paper_figure(output) {
            Some(figure) => format!("{title} ({figure})"),
            None => title,
        },
        scale,
    }
}

/// The panels of a run with `outputs`: the scene's explicit set (`[figures] panels`,
/// the outputs the run has), or the standard set: the vehicle, `tip_rel`, `top1_rel`, the
/// drive force when there is one, and the gaps: for two sections at the lower and the upper
/// contact, for more a panel of gaps and one of contact forces per overlap. A title names
/// the paper's figure the scene says its panel reproduces (`[figures] paper`).
fn panels(figures: &Figures, outputs: &[Output]) -> Vec<Panel> {
    let overlaps: Vec<usize> = (2..)
        .take_while(|&k| {
            outputs
                .iter()
                .any(|o| matches!(o, Output::Gap { overlap, .. } if *overlap == k))
        })
        .collect();
    let two_sections = overlaps.len() == 1;
    if let Some(chosen) = &figures.panels {
        // a chosen gap is titled by its contact's number, which says where it is
        return chosen
            .iter()
            .filter(|o| outputs.contains(o))
            .map(|&o| output_panel(figures, o, false))
            .collect();
    }
    let mut out: Vec<Panel> = [
        Output::Vehicle,
        Output::TipRel,
        Output::TopRel(1),
        Output::DriveForce,
    ]
    .into_iter()
    .filter(|o| outputs.contains(o))
    .map(|o| output_panel(figures, o, false))
    .collect();
    if two_sections {
        // two sections: a gap panel at the lower and at the upper contact
        let gaps = first_and_last(outputs, Output::is_gap, 2);
        out.extend(gaps.iter().map(|&g| output_panel(figures, g, true)));
        return out;
    }
    for k in overlaps {
        out.extend(overlap_panels(outputs, k));
    }
    out
}

/// The first and last of overlap `k`'s outputs that `which` picks (one if there is one).
fn first_and_last(outputs: &[Output], which: fn(&Output) -> bool, k: usize) -> Vec<Output> {
    let all: Vec<Output> = outputs
        .iter()
        .filter(|o| {
            which(o)
                && matches!(o, Output::Gap { overlap, .. } | Output::ContactForce { overlap, .. }
                    if *overlap == k)
        })
        .copied()
        .collect();
    match (all.first(), all.last()) {
        (Some(a), Some(b)) if a != b => vec![*a, *b],
        _ => all,
    }
}

/// Overlap `k`'s two panels: the gaps, and the contact forces, at its lower (solid) and upper
/// (dashed) contact.
fn overlap_panels(outputs: &[Output], k: usize) -> [Panel; 2] {
    let gaps = first_and_last(outputs, Output::is_gap, k);
    let forces = first_and_last(outputs, Output::is_contact_force, k);
    let listed = |c: &[Output]| {
        c.iter()
            .map(Output::to_string)
            .collect::<Vec<_>>()
            .join(" (solid), ")
    };
    let panel = |columns: &[Output], axis: &str, title: String, scale: f64| Panel {
        columns: columns.iter().map(Output::to_string).collect(),
        axis: axis.into(),
        title,
        scale,
    };
    [
        panel(
            &gaps,
            "gap [mm]",
            format!(
                "overlap {k}: gaps at the lower and upper contact, {} (dashed)",
                listed(&gaps)
            ),
            1e3,
        ),
        panel(
            &forces,
            "contact force [N]",
            format!("overlap {k}: contact forces, {} (dashed)", listed(&forces)),
            1.0,
        ),
    ]
}

/// Output formats of [`save`], by file extension.
const PLOT_EXTENSIONS: [&str; 2] = ["svg", "png"];

/// Checks before any work that a picture file ends in .svg or .png and can be written.
///
/// # Errors
/// [`Error::Destination`] naming the path and the rule.
pub fn check_picture_path(path: &Path) -> Result<()> {
    let ext = path.extension().and_then(|e| e.to_str());
    if !ext.is_some_and(|e| PLOT_EXTENSIONS.contains(&e)) {
        return Err(Error::Destination {
            path: path.to_path_buf(),
            rule: "the file name must end in .svg or .png (the format follows it)".into(),
        });
    }
    crate::io::output::check_writable(path)
}

/// Width of a plot (pixels).
const WIDTH: u32 = 1000;

/// A picture that can be drawn on any plotters backend.
pub trait Figure {
    /// Size in pixels.
    fn size(&self) -> (u32, u32);
    /// Draws the picture on `root`.
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, plotters::coord::Shift>)
    -> Result<()>;
}

/// Saves `figure` as SVG or PNG by the extension of `path` (written completely or not at
/// all).
pub fn save<F: Figure>(figure: &F, path: &Path) -> Result<()> {
    // both backends measure text with the font
    register_font()?;
    let size = figure.size();
    let bytes = match path.extension().and_then(|e| e.to_str()) {
        Some("png") => {
            let mut rgb = vec![0u8; 3 * (size.0 * size.1) as usize];
            figure.draw(BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area())?;
            encode_png(&rgb, size)?
        }
        _ => {
            let mut svg = String::new();
            figure.draw(SVGBackend::with_string(&mut svg, size).into_drawing_area())?;
            xml_chars(&svg).into_bytes()
        }
    };
    crate::io::output::write_atomically(path, |w| w.write_all(&bytes))
}

/// `text` with the characters XML 1.0 forbids (control characters but tab, newline and
/// carriage return; U+FFFE and U+FFFF) replaced by U+FFFD: a label the user gave (a scene's
/// name) may hold them, and escaping cannot make them valid.
pub fn xml_chars(text: &str) -> String {
    text.chars()
        .map(|c| match c {
            '\t' | '\n' | '\r' => c,
            c if c < ' ' || c == '\u{fffe}' || c == '\u{ffff}' => '\u{fffd}',
            c => c,
        })
        .collect()
}

/// The paper's figures for one scene, with overlaid runs.
struct PaperFigure<'a> {
    panels: Vec<Panel>,
    curves: &'a [Curve<'a>],
    marks: Marks,
}

impl Figure for PaperFigure<'_> {
    fn size(&self) -> (u32, u32) {
        (WIDTH, 320 * self.panels.len() as u32)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: DrawingArea<DB, plotters::coord::Shift>,
    ) -> Result<()> {
        root.fill(&WHITE).map_err(plot_error)?;
        let areas = root.split_evenly((self.panels.len(), 1));
        for (panel, area) in self.panels.iter().zip(&areas) {
            draw_panel(area, panel, self.curves, &self.marks)?;
        }
        root.present().map_err(plot_error)
    }
}

/// Draws the panels `figures` chooses (a scene's `[figures]`) of `curves[0]`'s outputs to an
/// SVG or PNG file at `path` (by extension; written completely or not at all).
pub fn plot(figures: &Figures, curves: &[Curve], marks: &Marks, path: &Path) -> Result<()> {
    let figure = PaperFigure {
        panels: panels(
            figures,
            &curves[0].traj.outputs().map(|(_, o)| o).collect::<Vec<_>>(),
        ),
        curves,
        marks: *marks,
    };
    save(&figure, path)
}

/// Text needs a font: DejaVu Sans, compiled in, so plots look the same on any machine.
pub(crate) fn register_font() -> Result<()> {
    plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular())
        .map_err(|_| Error::Plot("the built-in DejaVu Sans font could not be loaded".into()))
}

/// An RGB buffer as PNG bytes.
fn encode_png(rgb: &[u8], (width, height): (u32, u32)) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let png_error = |e: png::EncodingError| Error::Plot(format!("encoding PNG: {e}"));
    let mut writer = encoder.write_header().map_err(png_error)?;
    writer.write_image_data(rgb).map_err(png_error)?;
    writer.finish().map_err(png_error)?;
    Ok(out)
}

/// A plotters error as the library's [`Error::Plot`].
pub fn plot_error<E: std::fmt::Debug>(e: E) -> Error {
    Error::Plot(format!("{e:?}"))
}

/// A tick label with as many decimals as the axis span needs (exponent form below 1e-3).
pub fn tick_label(v: f64, span: f64) -> String {
    if span <= 0.0 || !span.is_finite() {
        return format!("{v}");
    }
    // a rounding residue of zero would print as "-0.000"
    let v = if v.abs() < 1e-9 * span { 0.0 } else { v };
    if span < 1e-3 {
        return format!("{v:.2e}");
    }
    let decimals = (2.0 - span.log10().floor()).max(0.0) as usize;
    format!("{v:.decimals$}")
}

/// At most `2 buckets` points: the smallest and largest value of each of `buckets` runs of
/// consecutive points, in time order, so peaks and chatter stay visible in a small file.
pub(crate) fn decimate(points: Vec<(f64, f64)>, buckets: usize) -> Vec<(f64, f64)> {
    if points.len() <= 2 * buckets {
        return points;
    }
    let size = points.len().div_ceil(buckets);
    let mut out = Vec::with_capacity(2 * buckets);
    for chunk in points.chunks(size) {
        let lo = chunk
            .iter()
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .expect("non-empty");
        let hi = chunk
            .iter()
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .expect("non-empty");
        if lo.0 <= hi.0 {
            out.extend([*lo, *hi]);
        } else {
            out.extend([*hi, *lo]);
        }
    }
    out
}

/// Line colors, one per overlaid run or method.
pub const COLORS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

/// The legend of a chart's labelled series, in its upper left corner on a light box.
pub fn upper_left_legend<'a, DB: DrawingBackend + 'a, CT: plotters::coord::CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
) -> Result<()> {
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(plot_error)
}

/// A white page with `title` on top (22 px); returns the area below the title.
pub fn titled_page<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
) -> Result<DrawingArea<DB, plotters::coord::Shift>> {
    root.fill(&WHITE).map_err(plot_error)?;
    root.titled(title, ("sans-serif", 22)).map_err(plot_error)
}

/// One line of a log-log panel: a label, points `(x, y)` and optional text at each point.
pub struct LogSeries {
    /// Legend entry.
    pub label: String,
    /// Points in data units (non-positive or non-finite ones are left out).
    pub points: Vec<(f64, f64)>,
    /// Text next to each point (empty: none).
    pub marks: Vec<String>,
}

/// The y axis of a [`log_panel`].
pub enum YAxis {
    /// log10 of the values (labels show the powers).
    Log,
    /// The values themselves, on this range.
    Linear(f64, f64),
}

/// A panel with a log10 x axis, one colored line with dots per series, an optional
/// horizontal line `(y, label)` and a legend. Log axes are drawn as linear axes of log10
/// values, labelled with the powers.
pub fn log_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    (title, x_desc, y_desc): (&str, &str, &str),
    series: &[LogSeries],
    y_axis: YAxis,
    level: Option<(f64, &str)>,
) -> Result<()> {
    let log_y = matches!(y_axis, YAxis::Log);
    let transformed: Vec<Vec<(f64, f64, &str)>> = series
        .iter()
        .map(|s| {
            s.points
                .iter()
                .enumerate()
                .filter(|(_, (x, y))| x.is_finite() && *x > 0.0 && y.is_finite())
                .filter(|(_, (_, y))| !log_y || *y > 0.0)
                .map(|(i, &(x, y))| {
                    let mark = s.marks.get(i).map_or("", String::as_str);
                    (x.log10(), if log_y { y.log10() } else { y }, mark)
                })
                .collect()
        })
        .collect();
    let all = || transformed.iter().flatten();
    if all().next().is_none() {
        return Ok(());
    }
    let bounds = |v: &mut dyn Iterator<Item = f64>| {
        v.fold((f64::MAX, f64::MIN), |(a, b), x| (a.min(x), b.max(x)))
    };
    let (x0, x1) = bounds(&mut all().map(|p| p.0));
    let (y0, y1) = match y_axis {
        YAxis::Log => {
            let (mut y0, mut y1) = bounds(&mut all().map(|p| p.1));
            if let Some((v, _)) = level.filter(|(v, _)| *v > 0.0) {
                (y0, y1) = (y0.min(v.log10()), y1.max(v.log10()));
            }
            (y0 - 0.2, y1 + 0.2)
        }
        YAxis::Linear(a, b) => (a, b),
    };
    let (x0, x1) = (x0 - 0.1, x1 + 0.1);
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 16))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(plot_error)?;
    let power = |v: &f64| format!("{:.1e}", 10f64.powf(*v));
    let plain = |v: &f64| format!("{v:.1}");
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_label_formatter(&power)
        .y_label_formatter(if log_y { &power } else { &plain })
        .draw()
        .map_err(plot_error)?;
    for (i, (s, line)) in series.iter().zip(&transformed).enumerate() {
        let color = COLORS[i % COLORS.len()];
        let xy: Vec<(f64, f64)> = line.iter().map(|p| (p.0, p.1)).collect();
        chart
            .draw_series(LineSeries::new(xy.clone(), color.stroke_width(2)))
            .map_err(plot_error)?
            .label(s.label.as_str())
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], color.stroke_width(2)));
        chart
            .draw_series(xy.iter().map(|&p| Circle::new(p, 3, color.filled())))
            .map_err(plot_error)?;
        chart
            .draw_series(
                line.iter()
                    .filter(|p| !p.2.is_empty())
                    .map(|p| Text::new(p.2.to_string(), (p.0, p.1), ("sans-serif", 11))),
            )
            .map_err(plot_error)?;
    }
    if let Some((v, label)) = level {
        let y = if log_y { v.log10() } else { v };
        chart
            .draw_series(LineSeries::new([(x0, y), (x1, y)], BLACK.stroke_width(1)))
            .map_err(plot_error)?
            .label(label)
            .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], BLACK));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", 11))
        .draw()
        .map_err(plot_error)
}

/// Height of the legend strip above each panel (pixels).
const LEGEND_STRIP: u32 = 26;

/// How a legend entry is drawn.
#[derive(Clone, Copy)]
enum Swatch {
    Line(RGBColor),
    Dashed(RGBColor),
    Band(RGBColor),
}

/// A legend drawn in its own strip above the plot, so that it never covers data.
fn legend_strip<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    entries: &[(String, Swatch)],
) -> Result<()> {
    let font: TextStyle = ("sans-serif", 13).into_font().into();
    let (mut x, y) = (90i32, (LEGEND_STRIP / 2) as i32);
    for (label, swatch) in entries {
        match *swatch {
            Swatch::Line(c) => {
                area.draw(&PathElement::new([(x, y), (x + 22, y)], c.stroke_width(2)))
            }
            Swatch::Dashed(c) => area
                .draw(&PathElement::new([(x, y), (x + 6, y)], c.stroke_width(2)))
                .and_then(|_| {
                    area.draw(&PathElement::new(
                        [(x + 10, y), (x + 16, y)],
                        c.stroke_width(2),
                    ))
                })
                .and_then(|_| {
                    area.draw(&PathElement::new(
                        [(x + 20, y), (x + 22, y)],
                        c.stroke_width(2),
                    ))
                }),
            Swatch::Band(c) => area.draw(&Rectangle::new(
                [(x, y - 6), (x + 22, y + 6)],
                c.mix(0.25).filled(),
            )),
        }
        .map_err(plot_error)?;
        area.draw_text(label, &font, (x + 28, y - 7))
            .map_err(plot_error)?;
        let (w, _) = area.estimate_text_size(label, &font).map_err(plot_error)?;
        x += 28 + w as i32 + 24;
    }
    Ok(())
}

/// Colour of the band edges `+-l_S/2` (dashed; distinct from the grey grid).
const BAND_EDGE: RGBColor = RGBColor(230, 120, 0);
/// Colour of the force limit (dashed).
const LIMIT: RGBColor = RGBColor(120, 0, 120);
/// Colour of the residual window's shading.
const WINDOW: RGBColor = RGBColor(120, 120, 120);

/// A dashed horizontal line at `y` from `t0` to `t1`.
fn dashed(
    t0: f64,
    t1: f64,
    y: f64,
    color: RGBColor,
) -> DashedLineSeries<std::vec::IntoIter<(f64, f64)>, u32> {
    DashedLineSeries::new(vec![(t0, y), (t1, y)], 8u32, 5u32, color.stroke_width(1))
}

/// One drawn series of a panel: `(curve, column, points)`.
type Series = (usize, usize, Vec<(f64, f64)>);

/// The panel's columns of every curve that has them, scaled and decimated.
fn panel_series(panel: &Panel, curves: &[Curve]) -> Vec<Series> {
    let mut out = Vec::new();
    for (i, c) in curves.iter().enumerate() {
        for (j, column) in panel.columns.iter().enumerate() {
            let Some(col) = c.traj.index(column) else {
                continue;
            };
            let points: Vec<(f64, f64)> = c
                .traj
                .rows
                .iter()
                .map(|r| (r[0], panel.scale * r[col]))
                .collect();
            out.push((i, j, decimate(points, 2000)));
        }
    }
    out
}

/// The smallest and largest time and value of the series, `(t0, t1, y0, y1)`.
fn bounds(series: &[Series]) -> (f64, f64, f64, f64) {
    let (mut t0, mut t1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for (_, _, s) in series {
        for &(t, y) in s {
            t0 = t0.min(t);
            t1 = t1.max(t);
            y0 = y0.min(y);
            y1 = y1.max(y);
        }
    }
    (t0, t1, y0, y1)
}

/// The panel's legend: its curves (a column after the first dashed, named), then the band
/// edges (`band_edge`, the panel's unit), the force limit (N) and the residual window where
/// they are drawn.
fn panel_legend(
    (panel, series): (&Panel, &[Series]),
    curves: &[Curve],
    band_edge: Option<f64>,
    limit: Option<f64>,
    marks: &Marks,
) -> Vec<(String, Swatch)> {
    let mut legend: Vec<(String, Swatch)> = series
        .iter()
        .map(|(i, j, _)| {
            let color = curves[*i].role.color();
            match (panel.columns.len(), j) {
                (1, _) => (curves[*i].label.clone(), Swatch::Line(color)),
                (_, 0) => (
                    format!("{}, {}", curves[*i].label, panel.columns[0]),
                    Swatch::Line(color),
                ),
                (_, j) => (
                    format!("{}, {}", curves[*i].label, panel.columns[*j]),
                    Swatch::Dashed(color),
                ),
            }
        })
        .collect();
    if let Some(band) = band_edge {
        let edge = tick_label(band, band);
        legend.push((
            format!("band edges ±l_S/2 = ±{edge} mm"),
            Swatch::Dashed(BAND_EDGE),
        ));
    }
    if let Some(l) = limit {
        legend.push((format!("force limit ±{l} N"), Swatch::Dashed(LIMIT)));
    }
    if marks.residual_window.is_some() {
        legend.push(("residual window".into(), Swatch::Band(WINDOW)));
    }
    legend
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    panel: &Panel,
    curves: &[Curve],
    marks: &Marks,
) -> Result<()> {
    let series = panel_series(panel, curves);
    let (t0, t1, mut y0, mut y1) = bounds(&series);
    let first = Output::parse(&panel.columns[0]);
    let is_gap = first.is_some_and(|o| o.is_gap());
    let band = panel.scale * curves[0].half_band;
    if is_gap {
        y0 = y0.min(-band);
        y1 = y1.max(band);
    }
    let limit = marks
        .force_limit
        .filter(|_| first == Some(Output::DriveForce));
    if let Some(l) = limit {
        y0 = y0.min(-l);
        y1 = y1.max(l);
    }
    let band_edge = if is_gap && band > 0.0 {
        Some(band)
    } else {
        None
    };
    let legend = panel_legend((panel, &series), curves, band_edge, limit, marks);
    let (strip, plot_area) = area.split_vertically(LEGEND_STRIP + 24);
    let pad = 0.05 * (y1 - y0).max(1e-12);
    let mut chart = ChartBuilder::on(&plot_area)
        .margin(10)
        .margin_top(0)
        .x_label_area_size(40)
        .y_label_area_size(80)
        .build_cartesian_2d(t0..t1, (y0 - pad)..(y1 + pad))
        .map_err(plot_error)?;
    let legend_area = strip
        .titled(&panel.title, ("sans-serif", 18))
        .map_err(plot_error)?;
    legend_strip(&legend_area, &legend)?;
    chart
        .configure_mesh()
        .x_desc("t [s]")
        .y_desc(panel.axis.as_str())
        .y_label_formatter(&|v| tick_label(*v, y1 - y0))
        .draw()
        .map_err(plot_error)?;
    if let Some((w0, w1)) = marks.residual_window {
        chart
            .draw_series([Rectangle::new(
                [(w0.max(t0), y0 - pad), (w1.min(t1), y1 + pad)],
                WINDOW.mix(0.12).filled(),
            )])
            .map_err(plot_error)?;
    }
    if is_gap && band > 0.0 {
        for edge in [-band, band] {
            chart
                .draw_series(dashed(t0, t1, edge, BAND_EDGE))
                .map_err(plot_error)?;
        }
    }
    if let Some(l) = limit {
        for edge in [-l, l] {
            chart
                .draw_series(dashed(t0, t1, edge, LIMIT))
                .map_err(plot_error)?;
        }
    }
    for (i, j, points) in series {
        let style = curves[i].role.color().stroke_width(1);
        if j == 0 {
            chart.draw_series(LineSeries::new(points, style))
        } else {
            chart.draw_series(DashedLineSeries::new(points, 6u32, 4u32, style))
        }
        .map_err(plot_error)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The outputs of a two-section run with three contact points.
    fn outputs() -> Vec<Output> {
        [
            "vehicle", "tip_rel", "top1_rel", "xi_2_0", "xi_2_1", "xi_2_2",
        ]
        .into_iter()
        .chain(["f_2_0", "f_2_1", "f_2_2", "kappa_1_0"])
        .map(|name| Output::parse(name).unwrap())
        .collect()
    }

    #[test]
    fn the_standard_panels_draw_the_lower_and_upper_gap_and_name_the_papers_figures() {
        let figures = Figures {
            panels: None,
            paper: vec![(Output::TipRel, "Fig. 9".into())],
        };
        let panels = panels(&figures, &outputs());
        let titles: Vec<&str> = panels.iter().map(|p| p.title.as_str()).collect();
        assert_eq!(
            titles,
            [
                "vehicle position",
                "load relative to the foot (Fig. 9)",
                "top of section 1 relative to the foot",
                "gap at the lower contact",
                "gap at the upper contact",
            ]
        );
        assert_eq!(panels[4].columns, ["xi_2_2"]);
        assert_eq!(
            (panels[4].scale, panels[4].axis.as_str()),
            (1e3, "xi_2_2 [mm]")
        );
    }

    #[test]
    fn a_chosen_set_draws_only_its_outputs_the_run_has_in_its_order() {
        let figures = Figures {
            panels: Some(vec![
                Output::Gap {
                    overlap: 2,
                    point: 1,
                },
                Output::DriveForce,
                Output::Sensor(telescopic_runtime::Sensor::FootCurvature),
            ]),
            paper: Vec::new(),
        };
        let panels = panels(&figures, &outputs());
        let columns: Vec<&str> = panels.iter().map(|p| p.columns[0].as_str()).collect();
        // no drive force in a force-driven run
        assert_eq!(columns, ["xi_2_1", "kappa_1_0"]);
        assert_eq!(panels[0].title, "gap at contact 1 of overlap 2");
        assert_eq!(panels[1].axis, "kappa_1_0 [1/m]");
    }
}
