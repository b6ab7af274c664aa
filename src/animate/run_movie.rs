//! The animation of a run: frames picked from its samples (never interpolated, so never
//! across a contact switch), each with the generalized coordinates, the telescopic
//! positions, the vehicle and the contact forces; the time series beside the view.

use super::geometry::{self, Telescope};
use super::options::AnimationOptions;
use crate::run::Simulation;
use crate::{Error, OptionName, Result};
use serde::Serialize;
use telescopic_runtime::Output;
use telescopic_runtime::model::params::Drive;
use telescopic_runtime::{Model, Scene};

/// A time series beside the view: `(t, value)` pairs, at most a few thousand (the smallest
/// and largest value of each run of samples, so peaks stay visible).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Series {
    /// Times (s).
    pub t: Vec<f64>,
    /// Values (SI units of the quantity).
    pub v: Vec<f32>,
}

/// One run as the view plays it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunTrack {
    /// What the run is (`case-study, l_S = 10 mm`, `with control`).
    pub label: String,
    /// Its colour in the charts, `#rrggbb`.
    pub color: String,
    /// The telescope it draws.
    pub telescope: Telescope,
    /// Frame times (s): samples of the run.
    pub t: Vec<f64>,
    /// Generalized coordinates per frame (the computing coordinates; index 0 the vehicle).
    pub z: Vec<Vec<f32>>,
    /// Height of each section's foot per frame (m).
    pub feet: Vec<Vec<f32>>,
    /// Vehicle position per frame (m).
    pub vehicle: Vec<f64>,
    /// Gap `xi` per frame and contact (m).
    pub gaps: Vec<Vec<f32>>,
    /// Contact force per frame and contact (N).
    pub forces: Vec<Vec<f32>>,
    /// `tip_rel` (m), the vehicle (m) and the drive force (N) against time.
    pub charts: [Series; 3],
}

/// The animation of one or more runs of a scene, side by side.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunMovie {
    /// Always `run` (the page tells its two kinds apart by it).
    pub kind: &'static str,
    /// Page title.
    pub title: String,
    /// Transverse deflection's exaggeration.
    pub scale: f64,
    /// Frames per second of simulation time.
    pub fps: f64,
    /// The highest the telescope gets in any frame (m).
    pub height_m: f64,
    /// The runs.
    pub tracks: Vec<RunTrack>,
}

/// A run to animate: its label, scene, finished simulation (with its coordinates) and the
/// model it ran on.
pub struct Take<'a> {
    /// Label.
    pub label: String,
    /// The scene.
    pub scene: &'a Scene,
    /// The run, with its coordinates ([`crate::run::SimulationOptions::coordinates`]).
    pub run: &'a Simulation,
    /// The model it ran on (its shape functions draw it).
    pub model: &'a dyn Model,
    /// Its colour, `#rrggbb`.
    pub color: String,
}

/// Samples per chart series at most (twice the buckets of the min/max decimation).
pub(crate) const CHART_BUCKETS: usize = 1500;

/// Share of the height the largest deflection is drawn at by the default scale.
const DEFLECTION_SHARE: f64 = 0.2;

impl RunMovie {
    /// The movie of `takes` (side by side) with `options`.
    ///
    /// # Errors
    /// [`Error::Option`] for a frame rate above the runs' sample rate or a bad scale;
    /// [`Error::Input`] when a run has no coordinates.
    pub fn new(title: String, takes: &[Take], options: &AnimationOptions) -> Result<Self> {
        options.check()?;
        let tracks = takes
            .iter()
            .map(|take| track(take, options))
            .collect::<Result<Vec<_>>>()?;
        let height_m = takes
            .iter()
            .zip(&tracks)
            .flat_map(|(take, tr)| {
                tr.t.iter()
                    .map(|&t| geometry::height(&take.scene.params, t))
            })
            .fold(0.0, f64::max);
        let scale = match options.scale {
            Some(s) => s,
            None => {
                let largest = tracks
                    .iter()
                    .map(|tr| {
                        tr.telescope
                            .largest_deflection(tr.z.iter().map(Vec::as_slice))
                    })
                    .fold(0.0, f64::max);
                geometry::readable_scale(largest, height_m, DEFLECTION_SHARE)
            }
        };
        Ok(RunMovie {
            kind: "run",
            title,
            scale,
            fps: options.fps,
            height_m,
            tracks,
        })
    }

    /// Number of frames of the longest track.
    pub fn frame_count(&self) -> usize {
        self.tracks.iter().map(|t| t.t.len()).max().unwrap_or(0)
    }

    /// The movie at `fps` frames a second, at most its own rate: every `k`-th frame, `k` the
    /// ratio of the rates rounded (a page's 50 to a GIF's 25: every other frame).
    pub fn at_rate(&self, fps: f64) -> RunMovie {
        let k = (self.fps / fps).round().max(1.0) as usize;
        let every = |v: &[f64]| v.iter().step_by(k).copied().collect::<Vec<_>>();
        let every_row = |v: &[Vec<f32>]| v.iter().step_by(k).cloned().collect::<Vec<_>>();
        let tracks = self
            .tracks
            .iter()
            .map(|t| RunTrack {
                t: every(&t.t),
                z: every_row(&t.z),
                feet: every_row(&t.feet),
                vehicle: every(&t.vehicle),
                gaps: every_row(&t.gaps),
                forces: every_row(&t.forces),
                ..t.clone()
            })
            .collect();
        RunMovie {
            fps: self.fps / k as f64,
            tracks,
            ..self.clone()
        }
    }
}

/// Indices of the samples nearest to the frame times `t0 + j / fps`.
fn frame_rows(times: &[f64], fps: f64) -> Vec<usize> {
    let (Some(&t0), Some(&t1)) = (times.first(), times.last()) else {
        return Vec::new();
    };
    let count = ((t1 - t0) * fps + 1e-9).floor() as usize + 1;
    let mut rows: Vec<usize> = (0..count)
        .map(|j| {
            let target = t0 + j as f64 / fps;
            let i = times.partition_point(|&t| t < target).min(times.len() - 1);
            if i > 0 && (target - times[i - 1]) < (times[i] - target) {
                i - 1
            } else {
                i
            }
        })
        .collect();
    rows.dedup();
    rows
}

/// The track of one take: its frames and charts.
fn track(take: &Take, options: &AnimationOptions) -> Result<RunTrack> {
    let traj = &take.run.trajectory;
    let dof = take.model.layout().dof();
    let Some(first) = traj.index("z_0") else {
        return Err(Error::input(
            format!("the run of {}", take.scene.name),
            "has no coordinate columns z_0.. (simulate it with coordinates)",
        ));
    };
    let sample = take.scene.time.sample;
    if options.fps * sample > 1.0 + 1e-9 {
        return Err(Error::option(
            OptionName::Fps,
            format!(
                "{} frames per second is more than the run's {} samples per second (time.sample = {sample} s); frames are samples, never interpolated",
                options.fps,
                1.0 / sample
            ),
        ));
    }
    let times: Vec<f64> = traj.rows.iter().map(|r| r[0]).collect();
    let rows = frame_rows(&times, options.fps);
    let column = |name: &str| traj.index(name);
    let telescope = Telescope::of(take.model, options.points);
    let columns_of = |prefix: &str| -> Vec<usize> {
        telescope
            .contacts
            .iter()
            .filter_map(|c| column(&format!("{prefix}_{}_{}", c.overlap, c.point)))
            .collect()
    };
    let (gap_cols, force_cols) = (columns_of("xi"), columns_of("f"));
    let vehicle = column("vehicle").expect("every run has the vehicle");
    let params = &take.scene.params;
    let mut out = empty_track(take, telescope, rows.len());
    for &i in &rows {
        let row = &traj.rows[i];
        out.t.push(row[0]);
        out.z
            .push(row[first..first + dof].iter().map(|&v| v as f32).collect());
        out.feet.push(
            geometry::feet(params, row[0])
                .iter()
                .map(|&v| v as f32)
                .collect(),
        );
        out.vehicle.push(row[vehicle]);
        out.gaps
            .push(gap_cols.iter().map(|&c| row[c] as f32).collect());
        out.forces
            .push(force_cols.iter().map(|&c| row[c] as f32).collect());
    }
    out.charts = charts(take);
    Ok(out)
}

/// A track with its telescope and no frames yet.
fn empty_track(take: &Take, telescope: Telescope, frames: usize) -> RunTrack {
    let empty = || Series {
        t: Vec::new(),
        v: Vec::new(),
    };
    RunTrack {
        label: take.label.clone(),
        color: take.color.clone(),
        telescope,
        t: Vec::with_capacity(frames),
        z: Vec::with_capacity(frames),
        feet: Vec::with_capacity(frames),
        vehicle: Vec::with_capacity(frames),
        gaps: Vec::with_capacity(frames),
        forces: Vec::with_capacity(frames),
        charts: [empty(), empty(), empty()],
    }
}

/// `tip_rel`, the vehicle and the drive force of a take against time, decimated.
fn charts(take: &Take) -> [Series; 3] {
    let traj = &take.run.trajectory;
    let series = |values: Vec<(f64, f64)>| {
        let points = crate::plot::decimate(values, CHART_BUCKETS);
        Series {
            t: points.iter().map(|p| p.0).collect(),
            v: points.iter().map(|p| p.1 as f32).collect(),
        }
    };
    let of_column = |name: &str| {
        let i = traj
            .index(name)
            .expect("every run has tip_rel and the vehicle");
        traj.rows.iter().map(|r| (r[0], r[i])).collect::<Vec<_>>()
    };
    let force = match (traj.index_of(Output::DriveForce), &take.scene.params.drive) {
        (Some(i), _) => traj.rows.iter().map(|r| (r[0], r[i])).collect(),
        (None, Drive::Force(p)) => traj.rows.iter().map(|r| (r[0], p.value(r[0]))).collect(),
        // a prescribed motion always has its reaction as a column
        (None, Drive::Motion(_)) => Vec::new(),
    };
    [
        series(of_column("tip_rel")),
        series(of_column("vehicle")),
        series(force),
    ]
}

#[cfg(test)]
mod tests {
    use super::frame_rows;

    #[test]
    fn frames_are_the_nearest_samples_at_the_rate() {
        let times: Vec<f64> = (0..=1000).map(|i| i as f64 * 1e-3).collect();
        let rows = frame_rows(&times, 50.0);
        assert_eq!(rows.len(), 51);
        assert_eq!(rows[1], 20);
        assert_eq!(*rows.last().unwrap(), 1000);
        let rows = frame_rows(&times, 30.0);
        assert_eq!(rows.len(), 31);
        assert_eq!(rows[1], 33); // 0.0333.. s
    }
}
