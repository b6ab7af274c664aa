//! What an animation is asked for: frame rate, deflection scale, drawing points, and a
//! GIF's size and speed.

use crate::{Error, OptionName, Result};

/// Options of an animation; the defaults are `telescopic animate`'s.
#[derive(Debug, Clone, PartialEq)]
pub struct AnimationOptions {
    /// Frames per second of simulation time (default 50 for a page, 25 for a GIF): frames
    /// are the run's samples nearest to that grid, never interpolated.
    pub fps: f64,
    /// Exaggeration of the transverse deflection (default: a round number that draws the
    /// largest deflection at a fifth of the telescope's height); lengths along the
    /// telescope are true.
    pub scale: Option<f64>,
    /// Drawing points per section (default [`super::geometry::DEFAULT_POINTS`]).
    pub points: usize,
    /// A GIF's width and height (pixels; default 720 x 480).
    pub size: (u32, u32),
    /// A GIF's speed: simulation seconds per second of playback (default 1).
    pub speed: f64,
}

impl Default for AnimationOptions {
    fn default() -> Self {
        AnimationOptions {
            fps: DEFAULT_PAGE_FPS,
            scale: None,
            points: super::geometry::DEFAULT_POINTS,
            size: (720, 480),
            speed: 1.0,
        }
    }
}

/// Frames per second of simulation time of a page.
pub const DEFAULT_PAGE_FPS: f64 = 50.0;
/// Frames per second of simulation time of a GIF.
pub const DEFAULT_GIF_FPS: f64 = 25.0;
/// The largest exaggeration.
pub const MAX_SCALE: f64 = 1e6;

impl AnimationOptions {
    /// Checks every field against its rule.
    ///
    /// # Errors
    /// [`Error::Option`] naming the field.
    pub fn check(&self) -> Result<()> {
        if !(self.fps.is_finite() && self.fps > 0.0 && self.fps <= 1000.0) {
            return Err(Error::option(
                OptionName::Fps,
                format!(
                    "{}: must be above 0 and at most 1000 frames per second",
                    self.fps
                ),
            ));
        }
        if let Some(s) = self.scale
            && !(s.is_finite() && s > 0.0 && s <= MAX_SCALE)
        {
            return Err(Error::option(
                OptionName::DeflectionScale,
                format!("{s}: must be above 0 and at most {MAX_SCALE:e}"),
            ));
        }
        if !(2..=1000).contains(&self.points) {
            return Err(Error::option(
                OptionName::Shapes,
                format!(
                    "{} drawing points per section: must be 2 to 1000",
                    self.points
                ),
            ));
        }
        let (w, h) = self.size;
        if !((160..=4096).contains(&w) && (120..=4096).contains(&h)) {
            return Err(Error::option(
                OptionName::AnimationSize,
                format!("{w}x{h}: width 160 to 4096 and height 120 to 4096 pixels"),
            ));
        }
        if !(self.speed.is_finite() && self.speed >= 0.01 && self.speed <= 100.0) {
            return Err(Error::option(
                OptionName::AnimationSpeed,
                format!(
                    "{}: must be 0.01 to 100 simulation seconds per second",
                    self.speed
                ),
            ));
        }
        Ok(())
    }
}
