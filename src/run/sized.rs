//! A model size: the basis and the modes per section, as `work-precision --modes` and
//! `--accuracy` name and apply it.

use std::fmt;
use std::str::FromStr;
use telescopic_runtime::{Basis, MAX_MODES, Scene};

/// One model size: the basis and the modes per section.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(into = "String", try_from = "String")]
pub struct ModelSize {
    /// The basis.
    pub basis: Basis,
    /// Modes per section (every section the same).
    pub modes: usize,
}

impl FromStr for ModelSize {
    type Err = String;

    /// `N` (the paper's modes) or `static:N` (with the static correction shapes).
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let (basis, n) = match s.trim().split_once(':') {
            Some(("static", n)) => (Basis::ModesAndStatic, n),
            None => (Basis::Modes, s.trim()),
            Some(_) => return Err(format!("`{s}` is not N or static:N")),
        };
        match n.parse::<usize>() {
            Ok(modes) if (1..=MAX_MODES).contains(&modes) => Ok(ModelSize { basis, modes }),
            _ => Err(format!(
                "`{s}`: the modes per section must be 1 to {MAX_MODES} (N or static:N)"
            )),
        }
    }
}

impl From<ModelSize> for String {
    fn from(size: ModelSize) -> String {
        size.to_string()
    }
}

impl TryFrom<String> for ModelSize {
    type Error = String;

    fn try_from(text: String) -> std::result::Result<Self, String> {
        text.parse()
    }
}

impl fmt::Display for ModelSize {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.basis {
            Basis::Modes => write!(f, "{}", self.modes),
            Basis::ModesAndStatic => write!(f, "static:{}", self.modes),
        }
    }
}

impl ModelSize {
    /// `scene` with this basis and these modes on every section.
    pub fn apply(&self, scene: &Scene) -> Scene {
        let mut s = scene.clone();
        s.params.basis = self.basis;
        for section in &mut s.params.sections {
            section.modes = self.modes;
        }
        s
    }
}
