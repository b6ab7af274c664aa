//! A run's view as an animated GIF, for slides and issue trackers: the telescope of every
//! track side by side (drawn with plotters as the page draws it) over a strip with
//! `tip_rel` against time and a cursor, one GIF frame per movie frame.
//!
//! Colours are those of a fixed palette, a 216-colour cube (6 levels a channel) and a ramp of
//! 40 greys (text's anti-aliasing), so a frame is indexed by rounding: no per-frame
//! quantizer pass, and the load's colour is exact.

use super::options::AnimationOptions;
use super::run_movie::RunMovie;
use crate::plot::{plot_error, register_font};
use crate::report::Reporter;
use crate::{Error, Result};
use plotters::prelude::*;

/// Colour of the load's square (in the palette exactly, so tests can find its pixels).
pub const LOAD_COLOR: RGBColor = RGBColor(204, 0, 204);
const SECTION_COLORS: [RGBColor; 4] = [
    RGBColor(51, 102, 153),
    RGBColor(102, 153, 51),
    RGBColor(204, 102, 51),
    RGBColor(153, 102, 153),
];
const OPEN_COLOR: RGBColor = RGBColor(51, 153, 51);
const CLOSED_COLOR: RGBColor = RGBColor(204, 51, 51);
const GREY: RGBColor = RGBColor(137, 137, 137);
const DARK: RGBColor = RGBColor(65, 65, 65);

/// Levels of each channel in the palette's cube.
const LEVELS: usize = 6;
/// Greys in the palette's ramp (after the cube).
const GREYS: usize = 40;

/// Where a GIF draws: each track's vehicle centre, the rail's top, pixels per metre, the
/// deflection's exaggeration, and the chart strip.
#[derive(Debug, Clone, PartialEq)]
pub struct GifLayout {
    /// Horizontal centre of each track's vehicle (pixels).
    pub cx: Vec<f64>,
    /// Height of the rail's top (pixels from the top).
    pub ground_y: f64,
    /// Pixels per metre along the telescope and the rail.
    pub ppm: f64,
    /// Exaggeration of the transverse deflection.
    pub scale: f64,
    /// Top and bottom of the `tip_rel` strip (pixels).
    pub strip: (f64, f64),
}

impl GifLayout {
    /// The layout of `movie` on a `size` picture.
    pub fn of(movie: &RunMovie, (width, height): (u32, u32)) -> Self {
        let (w, h) = (f64::from(width), f64::from(height));
        let strip_top = (0.75 * h).round();
        let ground_y = strip_top - 34.0;
        let top = 30.0;
        let n = movie.tracks.len().max(1) as f64;
        GifLayout {
            cx: (0..movie.tracks.len())
                .map(|k| ((k as f64 + 0.5) * w / n).round())
                .collect(),
            ground_y,
            ppm: (ground_y - top) / (1.06 * movie.height_m),
            scale: movie.scale,
            strip: (strip_top + 6.0, h - 18.0),
        }
    }

    /// Pixel of a point `w_rel` (m, relative to the vehicle) at height `y_m` (m) of track `k`.
    pub fn point(&self, k: usize, w_rel: f64, y_m: f64) -> (f64, f64) {
        (
            self.cx[k] + self.ppm * self.scale * w_rel,
            self.ground_y - self.ppm * y_m,
        )
    }
}

/// GIF frame delay (centiseconds) for `fps` frames per second of simulation at `speed`:
/// at least 2 (browsers slow shorter delays down to 10).
pub fn frame_delay_cs(fps: f64, speed: f64) -> u16 {
    (100.0 / (fps * speed)).round().clamp(2.0, 65535.0) as u16
}

/// Writes the GIF of `movie` with `options`' size and speed to `out`, frame by frame, with
/// `reporter`'s progress; stops when `reporter` asks.
///
/// # Errors
/// [`Error::Plot`] when drawing or encoding fails; [`Error::Stopped`] when asked to stop.
pub fn write_gif(
    movie: &RunMovie,
    options: &AnimationOptions,
    out: &mut dyn std::io::Write,
    reporter: &dyn Reporter,
) -> Result<()> {
    register_font()?;
    let (width, height) = options.size;
    let layout = GifLayout::of(movie, options.size);
    let palette = palette();
    let mut encoder =
        gif::Encoder::new(out, width as u16, height as u16, &palette).map_err(gif_error)?;
    encoder
        .set_repeat(gif::Repeat::Infinite)
        .map_err(gif_error)?;
    let mut rgb = vec![0u8; 3 * (width * height) as usize];
    let mut indices = vec![0u8; (width * height) as usize];
    let delay = frame_delay_cs(movie.fps, options.speed);
    let frames = movie.frame_count();
    reporter.start("writing the GIF");
    for i in 0..frames {
        if reporter.stop_requested() {
            return Err(Error::Stopped {
                what: format!("writing the GIF at frame {i} of {frames}"),
            });
        }
        {
            let root = BitMapBackend::with_buffer(&mut rgb, (width, height)).into_drawing_area();
            draw_frame(&root, movie, &layout, i)?;
            root.present().map_err(plot_error)?;
        }
        for (index, px) in indices.iter_mut().zip(rgb.chunks_exact(3)) {
            *index = palette_index(px[0], px[1], px[2]);
        }
        let mut frame =
            gif::Frame::from_indexed_pixels(width as u16, height as u16, indices.clone(), None);
        frame.delay = delay;
        encoder.write_frame(&frame).map_err(gif_error)?;
        reporter.progress((i + 1) as f64 / frames as f64);
    }
    reporter.finish();
    Ok(())
}

fn gif_error(e: impl std::fmt::Display) -> Error {
    Error::Plot(format!("encoding GIF: {e}"))
}

/// The palette as RGB bytes: the cube (red slowest), then the greys.
fn palette() -> Vec<u8> {
    let level = |i: usize, n: usize| ((i * 255 + (n - 1) / 2) / (n - 1)) as u8;
    let mut p = Vec::with_capacity(3 * 256);
    for r in 0..LEVELS {
        for g in 0..LEVELS {
            for b in 0..LEVELS {
                p.extend([level(r, LEVELS), level(g, LEVELS), level(b, LEVELS)]);
            }
        }
    }
    for i in 0..GREYS {
        p.extend([level(i, GREYS); 3]);
    }
    p
}

/// The palette entry for a colour: a grey of the ramp when the channels are within 10 of
/// each other, else the cube's entry nearest channel by channel.
fn palette_index(r: u8, g: u8, b: u8) -> u8 {
    let q = |v: u8, n: usize| (usize::from(v) * (n - 1) + 127) / 255;
    let (lo, hi) = (r.min(g).min(b), r.max(g).max(b));
    if hi - lo <= 10 {
        let mean = ((u16::from(r) + u16::from(g) + u16::from(b)) / 3) as u8;
        return (LEVELS.pow(3) + q(mean, GREYS)) as u8;
    }
    (q(r, LEVELS) * LEVELS * LEVELS + q(g, LEVELS) * LEVELS + q(b, LEVELS)) as u8
}

type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

/// Draws frame `i` of every track and the strip.
fn draw_frame(root: &Area, movie: &RunMovie, layout: &GifLayout, i: usize) -> Result<()> {
    root.fill(&WHITE).map_err(plot_error)?;
    let font = ("sans-serif", 13).into_font();
    let mut now = 0.0;
    for (k, track) in movie.tracks.iter().enumerate() {
        let f = i.min(track.t.len() - 1);
        now = track.t[f];
        draw_rail(root, layout, k, track.vehicle[f])?;
        draw_telescope(root, layout, k, track, f)?;
        let left = (layout.cx[k] - layout.cx[0]) as i32 + 6;
        root.draw_text(&track.label, &font.color(&BLACK), (left, 6))
            .map_err(plot_error)?;
    }
    let (w, _) = root.dim_in_pixel();
    let note = format!("t = {now:.2} s   deflection x {}", movie.scale);
    root.draw_text(&note, &font.color(&BLACK), (w as i32 - 230, 6))
        .map_err(plot_error)?;
    draw_strip(root, movie, layout, now)
}

/// The rail under track `k` with a tick every metre, moving as the vehicle does.
fn draw_rail(root: &Area, layout: &GifLayout, k: usize, vehicle: f64) -> Result<()> {
    let y = (layout.ground_y + 20.0) as i32;
    let half = layout.cx[0];
    let (left, right) = (layout.cx[k] - half, layout.cx[k] + half);
    root.draw(&PathElement::new(
        [(left as i32, y), (right as i32, y)],
        GREY.stroke_width(2),
    ))
    .map_err(plot_error)?;
    for m in metre_marks(vehicle, half / layout.ppm) {
        let x = (layout.cx[k] + layout.ppm * (m - vehicle)) as i32;
        root.draw(&PathElement::new([(x, y), (x, y + 5)], GREY))
            .map_err(plot_error)?;
    }
    let (cx, gy) = (layout.cx[k] as i32, layout.ground_y as i32);
    root.draw(&Rectangle::new(
        [(cx - 28, gy), (cx + 28, gy + 12)],
        DARK.filled(),
    ))
    .map_err(plot_error)
}

/// Most metre marks a rail draws.
const MAX_MARKS: usize = 1000;

/// The whole metres within `span` (m) of `vehicle` (m), at most [`MAX_MARKS`]; none where a
/// metre is below the position's resolution (a vehicle 1e17 m out), where counting up by
/// one would never advance.
fn metre_marks(vehicle: f64, span: f64) -> impl Iterator<Item = f64> {
    let first = (vehicle - span).ceil();
    let count = if first + 1.0 > first && (vehicle + span).is_finite() {
        ((vehicle + span - first).floor() + 1.0).clamp(0.0, MAX_MARKS as f64) as usize
    } else {
        0
    };
    (0..count).map(move |i| first + i as f64)
}

/// The sections, guides, contacts and load of frame `f` of track `k`.
fn draw_telescope(
    root: &Area,
    layout: &GifLayout,
    k: usize,
    track: &super::RunTrack,
    f: usize,
) -> Result<()> {
    let tel = &track.telescope;
    let (z, feet) = (&track.z[f], &track.feet[f]);
    let pixel = |w: f64, y: f64| {
        let (x, y) = layout.point(k, w, y);
        (x.round() as i32, y.round() as i32)
    };
    for (s, xs) in tel.points_m.iter().enumerate() {
        let points: Vec<(i32, i32)> = xs
            .iter()
            .enumerate()
            .map(|(p, &x)| pixel(tel.relative_deflection(s, p, z), f64::from(feet[s]) + x))
            .collect();
        let width = 8u32.saturating_sub(2 * s as u32).max(2);
        root.draw(&PathElement::new(
            points,
            SECTION_COLORS[s % SECTION_COLORS.len()].stroke_width(width),
        ))
        .map_err(plot_error)?;
    }
    for (c, site) in tel.contacts.iter().enumerate() {
        let (inner, outer) = (site.overlap - 1, site.overlap - 2);
        let a = f64::from(feet[inner] - feet[outer]);
        let x_in = site.fraction * (tel.lengths_m[outer] - a);
        let p = nearest_point(&tel.points_m[inner], x_in);
        let (x, y) = pixel(
            tel.relative_deflection(inner, p, z),
            f64::from(feet[inner]) + x_in,
        );
        let closed =
            telescopic_runtime::contact::gap_closed(f64::from(track.gaps[f][c]), tel.half_band_m);
        let color = if closed { CLOSED_COLOR } else { OPEN_COLOR };
        root.draw(&Circle::new((x, y), 4, color.filled()))
            .map_err(plot_error)?;
    }
    let last = tel.points_m.len() - 1;
    let top = tel.points_m[last].len() - 1;
    let (x, y) = pixel(
        tel.relative_deflection(last, top, z),
        f64::from(feet[last]) + tel.lengths_m[last],
    );
    root.draw(&Rectangle::new(
        [(x - 6, y - 12), (x + 6, y)],
        LOAD_COLOR.filled(),
    ))
    .map_err(plot_error)
}

/// Index of the drawing point nearest to `x`.
fn nearest_point(xs: &[f64], x: f64) -> usize {
    (0..xs.len())
        .min_by(|&a, &b| (xs[a] - x).abs().total_cmp(&(xs[b] - x).abs()))
        .unwrap_or(0)
}

/// The `tip_rel` strip: every track's series and a cursor at `now`.
fn draw_strip(root: &Area, movie: &RunMovie, layout: &GifLayout, now: f64) -> Result<()> {
    let (w, _) = root.dim_in_pixel();
    let (top, bottom) = layout.strip;
    let (left, right) = (60.0, f64::from(w) - 10.0);
    let all = || {
        movie
            .tracks
            .iter()
            .flat_map(|t| t.charts[0].t.iter().zip(&t.charts[0].v))
    };
    let (t0, t1) = all().fold((f64::MAX, f64::MIN), |(a, b), (&t, _)| (a.min(t), b.max(t)));
    let (lo, hi) = all().fold((f32::MAX, f32::MIN), |(a, b), (_, &v)| (a.min(v), b.max(v)));
    let (lo, hi) = if hi > lo {
        (f64::from(lo), f64::from(hi))
    } else {
        (-1.0, 1.0)
    };
    let x = |t: f64| (left + (right - left) * (t - t0) / (t1 - t0).max(1e-12)) as i32;
    let y = |v: f64| (bottom - (bottom - top) * (v - lo) / (hi - lo)) as i32;
    root.draw(&Rectangle::new(
        [(left as i32, top as i32), (right as i32, bottom as i32)],
        GREY,
    ))
    .map_err(plot_error)?;
    for track in &movie.tracks {
        let s = &track.charts[0];
        let color = hex_color(&track.color);
        let points: Vec<(i32, i32)> =
            s.t.iter()
                .zip(&s.v)
                .map(|(&t, &v)| (x(t), y(f64::from(v))))
                .collect();
        root.draw(&PathElement::new(points, color))
            .map_err(plot_error)?;
    }
    root.draw(&PathElement::new(
        [(x(now), top as i32), (x(now), bottom as i32)],
        BLACK,
    ))
    .map_err(plot_error)?;
    let font = ("sans-serif", 11).into_font().color(&BLACK);
    root.draw_text("tip_rel", &font, (4, top as i32))
        .map_err(plot_error)?;
    root.draw_text(&format!("{hi:.3} m"), &font, (4, top as i32 + 14))
        .map_err(plot_error)?;
    root.draw_text(&format!("{lo:.3} m"), &font, (4, bottom as i32 - 12))
        .map_err(plot_error)
}

/// `#rrggbb` as a colour (black when malformed).
fn hex_color(hex: &str) -> RGBColor {
    let channel = |i: usize| {
        hex.get(i..i + 2)
            .and_then(|c| u8::from_str_radix(c, 16).ok())
            .unwrap_or(0)
    };
    RGBColor(channel(1), channel(3), channel(5))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A caller that asks to stop after `after` progress reports, and counts them.
    struct StopAfter {
        after: usize,
        reports: std::sync::atomic::AtomicUsize,
    }

    impl Reporter for StopAfter {
        fn progress(&self, _: f64) {
            self.reports
                .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        }
        fn stop_requested(&self) -> bool {
            self.reports.load(std::sync::atomic::Ordering::Relaxed) >= self.after
        }
    }

    #[test]
    fn a_gif_stopped_between_frames_leaves_no_file() {
        use crate::animate::{RunRequest, animate_run, save_run};
        let scene = telescopic_runtime::Scene::load(
            "scenes/adams-clearance.toml".as_ref(),
            &["time.end=1".to_string()],
        )
        .unwrap();
        let options = AnimationOptions {
            size: (160, 120),
            ..AnimationOptions::default()
        };
        let request = RunRequest::new(&scene, crate::run::SimulationOptions::default());
        let movie = animate_run(&request, &options, &crate::Silent).unwrap();
        let path = std::env::temp_dir().join(format!("stopped-{}.gif", std::process::id()));
        let caller = StopAfter {
            after: 3,
            reports: Default::default(),
        };
        let error = save_run(&movie, &options, &path, &caller).unwrap_err();
        assert!(
            matches!(&error, Error::Stopped { what } if what.contains("frame 3 of 51")),
            "{error}"
        );
        assert!(!path.exists());
        let written = save_run(&movie, &options, &path, &crate::Silent).unwrap();
        assert_eq!(std::fs::metadata(&path).unwrap().len(), written);
        std::fs::remove_file(&path).unwrap();
    }

    #[test]
    fn a_rail_has_its_metre_marks_and_none_where_a_metre_is_below_resolution() {
        let marks: Vec<f64> = metre_marks(10.3, 2.0).collect();
        assert_eq!(marks, vec![9.0, 10.0, 11.0, 12.0]);
        assert_eq!(metre_marks(1e17, 5.0).count(), 0);
        assert_eq!(metre_marks(0.0, 1e9).count(), 1000);
        assert_eq!(metre_marks(f64::NAN, 1.0).count(), 0);
    }

    #[test]
    fn the_palette_holds_the_drawing_colours_exactly() {
        let p = palette();
        for c in [
            LOAD_COLOR,
            OPEN_COLOR,
            CLOSED_COLOR,
            GREY,
            DARK,
            WHITE,
            BLACK,
        ] {
            let i = usize::from(palette_index(c.0, c.1, c.2));
            assert_eq!(&p[3 * i..3 * i + 3], &[c.0, c.1, c.2], "{c:?}");
        }
        assert_eq!(p.len(), 3 * 256);
    }

    #[test]
    fn delays_follow_rate_and_speed() {
        assert_eq!(frame_delay_cs(25.0, 1.0), 4);
        assert_eq!(frame_delay_cs(50.0, 0.1), 20);
        assert_eq!(frame_delay_cs(50.0, 10.0), 2);
    }
}
