//! The validated scene: the model parameters, the time span and the file as read.

use super::schema::{ReferenceSpec, SceneFile};
use crate::model::output::Output;
use crate::model::params::ModelParams;

/// Time span and output sampling of a scene (s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeSpan {
    /// Start time (s).
    pub start: f64,
    /// End time (s).
    pub end: f64,
    /// Output sample interval (s).
    pub sample: f64,
}

/// A validated scene: the model parameters, the time span and the reference values.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// Short name.
    pub name: String,
    /// One line on what the scene is.
    pub description: String,
    /// Physical parameters of the model.
    pub params: ModelParams,
    /// Time span and sampling.
    pub time: TimeSpan,
    /// Published frequency columns to compare with.
    pub references: Vec<ReferenceSpec>,
    /// What a run's figure draws.
    pub figures: Figures,
    /// The whole error in `tip_rel` against the beams that runs meet by default (m;
    /// `accuracy`); `None`: the scene's modes, integrated to the default accuracy.
    pub accuracy: Option<f64>,
    /// The file as read, after overrides (for echoing into outputs).
    pub file: SceneFile,
}

/// The panels of a run's figure (`[figures]`).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Figures {
    /// The outputs drawn, one panel each; `None`: the standard set.
    pub panels: Option<Vec<Output>>,
    /// The paper's figure an output's panel reproduces.
    pub paper: Vec<(Output, String)>,
}

impl Figures {
    /// The paper's figure `output`'s panel reproduces, if any.
    pub fn paper_figure(&self, output: Output) -> Option<&str> {
        self.paper
            .iter()
            .find(|(o, _)| *o == output)
            .map(|(_, f)| f.as_str())
    }
}

impl Scene {
    /// The section moduli `W_k` (m^3), bottom up, from `sections.section_modulus` or from
    /// `sections.height` (`W = 2 I / h`); `None` when the scene gives neither.
    pub fn section_moduli(&self) -> Option<Vec<f64>> {
        let s = &self.file.sections;
        let n = self.params.sections.len();
        if let Some(w) = &s.section_modulus {
            return (1..=n).map(|k| w.get(k)).collect();
        }
        let h = s.height.as_ref()?;
        (1..=n)
            .map(|k| Some(2.0 * s.inertia.get(k)? / h.get(k)?))
            .collect()
    }
}
