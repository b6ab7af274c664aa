//! What a movie costs, predicted before its runs: a page's memory (its data is every
//! frame's coordinates as JSON, held several times while the document is built) against the
//! memory budget, and a GIF's frames against a cap (a GIF is streamed frame by frame, so its
//! memory is a few frames; its file grows with the frames).

use super::run_movie::CHART_BUCKETS;
use crate::run::memory::check;
use crate::{Error, OptionName, Result};
use telescopic_runtime::{Scene, config_of};

/// Bytes of a page's JSON per number: an `f32` printed shortest with its comma (measured
/// 10.8 in case-study's frames, 9.2 in its charts).
const PAGE_BYTES_PER_NUMBER: u64 = 11;

/// Peak memory while a page is built, over its size: the movie, its JSON, the JSON made
/// safe inside `<script>`, and the document (measured 5x).
const PAGE_PEAK_FACTOR: u64 = 5;

/// Most frames of a GIF: 4 minutes at 25 frames a second (a GIF of 720 x 480 takes up to
/// about 100 kB a frame).
pub const MAX_GIF_FRAMES: u64 = 6000;

/// Frames of a run of `scene` at `fps` frames per second of simulation.
pub fn frames(scene: &Scene, fps: f64) -> u64 {
    let span = scene.time.end - scene.time.start;
    let by_rate = (span * fps).floor().min(1e15) as u64 + 1;
    by_rate.min(crate::run::budget::sample_count(&scene.time) as u64)
}

/// The size of the page's data (bytes) of runs of `scenes` side by side at `fps`: per frame
/// each track's coordinates, feet, vehicle, time, gaps and contact forces, and per track its
/// three charts (time and value of at most two points per bucket).
pub fn page_bytes(scenes: &[&Scene], fps: f64) -> u64 {
    scenes
        .iter()
        .map(|scene| {
            let config = config_of(&scene.params);
            let per_frame =
                (config.dof() + config.sections() + 2 + 2 * config.contact_count()) as u64;
            let samples = crate::run::budget::sample_count(&scene.time) as u64;
            let charts = 6 * samples.min(2 * CHART_BUCKETS as u64);
            frames(scene, fps)
                .saturating_mul(per_frame)
                .saturating_add(charts)
                .saturating_mul(PAGE_BYTES_PER_NUMBER)
        })
        .fold(0, u64::saturating_add)
}

/// Refuses a page of runs of `scenes` at `fps` whose building would pass `budget` (bytes).
///
/// # Errors
/// [`Error::OverMemoryBudget`] naming the frame rate, time.sample and time.end.
pub fn check_page(scenes: &[&Scene], fps: f64, budget: u64) -> Result<()> {
    let page = page_bytes(scenes, fps);
    check(
        page.saturating_mul(PAGE_PEAK_FACTOR),
        budget,
        (
            Some(OptionName::Fps),
            format!("scene {}", scenes.first().map_or("", |s| s.name.as_str())),
        ),
        format!("building a page of about {page} bytes"),
        "the frame rate (fewer frames) or time.end",
    )
}

/// Refuses a GIF of `frames` frames (at `fps` a second of simulation) above
/// [`MAX_GIF_FRAMES`].
///
/// # Errors
/// [`Error::Option`] naming the frame rate.
pub fn check_gif_frames(frames: u64, fps: f64) -> Result<()> {
    if frames > MAX_GIF_FRAMES {
        return Err(Error::option(
            OptionName::Fps,
            format!(
                "a GIF of {frames} frames ({fps} a second of simulation); at most \
                 {MAX_GIF_FRAMES}: lower the frame rate or shorten time.end"
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::animate::{AnimationOptions, RunRequest, animate_run};
    use crate::run::SimulationOptions;

    /// The prediction against the page a run of `name` makes (its data: the page less an
    /// empty movie's).
    fn predicted_over_made(name: &str) -> f64 {
        let scene = Scene::load(format!("scenes/{name}.toml").as_ref(), &[]).unwrap();
        let options = AnimationOptions::default();
        let request = RunRequest::new(&scene, SimulationOptions::default());
        let movie = animate_run(&request, &options, &crate::Silent).unwrap();
        let fixed = crate::animate::page::document("", &()).len();
        let made = movie.html().len() - fixed;
        page_bytes(&[&scene], options.fps) as f64 / made as f64
    }

    #[test]
    fn a_page_is_predicted_from_three_quarters_to_one_and_a_half_of_its_size() {
        for name in ["case-study", "adams-clearance", "three-section"] {
            let ratio = predicted_over_made(name);
            eprintln!("{name}: predicted / made {ratio:.3}");
            assert!((0.75..=1.5).contains(&ratio), "{name}: {ratio}");
        }
    }
}
