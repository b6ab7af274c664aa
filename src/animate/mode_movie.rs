//! The animation of a scene's modes: each mode shape oscillating, with its frequency,
//! damping and kind; the page forms each shape from the eigenvector and the shape functions.

use super::geometry::{self, Telescope};
use crate::analysis::modes::{ModeKind, ModesReport};
use serde::Serialize;
use telescopic_runtime::{Model, Scene};

/// One mode as the view draws it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AnimatedMode {
    /// Natural frequency (Hz).
    pub frequency_hz: f64,
    /// Damping ratio.
    pub damping_ratio: f64,
    /// `structural` or `contact`.
    pub kind: &'static str,
    /// The eigenvector in the model's computing coordinates.
    pub vector: Vec<f64>,
}

/// The modes of a scene at one time, animated.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModeMovie {
    /// Always `modes`.
    pub kind: &'static str,
    /// Page title.
    pub title: String,
    /// Time of the telescopic positions (s).
    pub time_s: f64,
    /// The largest deflection of every mode is drawn as this many metres.
    pub scale: f64,
    /// The telescope's height (m).
    pub height_m: f64,
    /// Height of each section's foot (m).
    pub feet: Vec<f64>,
    /// The telescope it draws.
    pub telescope: Telescope,
    /// The modes, lowest first.
    pub modes: Vec<AnimatedMode>,
}

/// Share of the height a mode's largest deflection is drawn at.
const MODE_SHARE: f64 = 0.2;

impl ModeMovie {
    /// The movie of `report`, computed for `scene` on `model`, drawn with `points` points
    /// per section.
    pub fn new(scene: &Scene, report: &ModesReport, model: &dyn Model, points: usize) -> Self {
        let height_m = geometry::height(&scene.params, report.time_s);
        let modes = report
            .vectors
            .iter()
            .enumerate()
            .map(|(i, v)| AnimatedMode {
                frequency_hz: report.frequencies_hz[i],
                damping_ratio: report.damping_ratios[i],
                kind: match report.kinds[i] {
                    ModeKind::Structural => "structural",
                    ModeKind::Contact => "contact",
                },
                vector: v.clone(),
            })
            .collect();
        ModeMovie {
            kind: "modes",
            title: format!("{}: mode shapes at t = {} s", report.scene, report.time_s),
            time_s: report.time_s,
            scale: MODE_SHARE * height_m,
            height_m,
            feet: geometry::feet(&scene.params, report.time_s),
            telescope: Telescope::of(model, points),
            modes,
        }
    }
}
