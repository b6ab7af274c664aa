//! What a run is asked for: the method (or `auto`), tolerances, the accuracy in metres, the
//! model and the outputs at stations.

use super::models::{ModelChoice, ModelRegistry};
use std::fmt;
use std::str::FromStr;
use telescopic_runtime::Method;

/// The method of a run: `auto` (chosen on the scene) or one named method.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum MethodChoice {
    /// `exact` for a scene linear and time-invariant between contact switches, else
    /// `dopri5`, handing over to `exact` once the telescopic positions rest.
    #[default]
    Auto,
    /// This method throughout.
    Method(Method),
}

impl FromStr for MethodChoice {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "auto" => Ok(MethodChoice::Auto),
            name => Method::from_name(name).map(MethodChoice::Method),
        }
    }
}

impl fmt::Display for MethodChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MethodChoice::Auto => f.write_str("auto"),
            MethodChoice::Method(m) => write!(f, "{m}"),
        }
    }
}

/// Options of a simulation; the defaults are `simulate`'s.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulationOptions {
    /// The method (default `auto`).
    pub method: MethodChoice,
    /// Relative tolerance of adaptive methods (default 1e-6).
    pub rtol: Option<f64>,
    /// Absolute tolerance of adaptive methods (m, m/s; default 1e-9).
    pub atol: Option<f64>,
    /// Step (s) of fixed-step methods; first trial step of adaptive ones.
    pub dt: Option<f64>,
    /// Cap dop853's step below its stable step while a contact is closed (default true).
    pub step_cap: bool,
    /// Let method `exact` step over closed contacts' fast modes where certified (default
    /// true; false: its short steps throughout, for comparison).
    pub long_steps: bool,
    /// Which model computes the right-hand side (default `auto`).
    pub model: ModelChoice,
    /// Where generated models come from (default: the committed ones).
    pub models: ModelRegistry,
    /// The error asked for in `tip_rel` inside the predictability horizon (m): `auto` then
    /// picks the method and tolerance that reach it cheapest from the measured table
    /// ([`telescopic_runtime::analysis::accuracy`]); `None`: the default accuracy, 1e-6 m, unless a
    /// method or tolerance is given.
    pub accuracy: Option<f64>,
    /// Stations whose bending moment (and stress) become output columns (default none).
    pub stations: Vec<crate::run::stress::Station>,
    /// Keep the scene's modes and basis under [`SimulationOptions::accuracy`], which then
    /// bounds the integration error only (default false: the accuracy is the whole error
    /// against the beams, and the run picks the modes too).
    pub modes_as_given: bool,
    /// Estimate the run's truncation error from a companion run with more modes (default
    /// true; [`crate::run::error_budget`]).
    pub error_estimate: bool,
    /// Largest truncation error of a station's moment, relative to its peak, that
    /// [`SimulationOptions::accuracy`] accepts (default 0.02).
    pub moment_tolerance: f64,
    /// Largest relative truncation error of the statistics beyond the pointwise window
    /// (RMS and peak of `tip_rel`, peak moment) that [`SimulationOptions::accuracy`] accepts
    /// (default 0.05).
    pub statistics_tolerance: f64,
    /// The memory the run's outputs may take (bytes; default
    /// [`super::memory::DEFAULT_MEMORY_BUDGET`]): a longer run is refused before it starts.
    pub memory_budget: u64,
    /// Also output the generalized coordinates (the computing coordinates of
    /// [`telescopic_runtime::model`], m and dimensionless) as columns `z_0 ..` after the
    /// others: what an animation draws from (default false).
    pub coordinates: bool,
    /// Let the accuracy's method step across output samples where its measured row does
    /// (default true; false: steps end on every sample, as a companion run that measures a
    /// run's error needs: its own interpolation error would otherwise hide the run's).
    pub steps_across_samples: bool,
    /// Where a run keeps its error budget, and its accuracy search's pick, for a repeated run
    /// of the same scene and options to reuse ([`crate::run::reuse`]); `None`: every run
    /// estimates afresh. The faces set [`crate::run::reuse::default_dir`].
    pub reuse: Option<std::path::PathBuf>,
}

impl Default for SimulationOptions {
    fn default() -> Self {
        SimulationOptions {
            method: MethodChoice::Auto,
            rtol: None,
            atol: None,
            dt: None,
            step_cap: true,
            long_steps: true,
            model: ModelChoice::Auto,
            models: ModelRegistry::default(),
            accuracy: None,
            stations: Vec::new(),
            modes_as_given: false,
            error_estimate: true,
            moment_tolerance: 0.02,
            statistics_tolerance: 0.05,
            memory_budget: super::memory::DEFAULT_MEMORY_BUDGET,
            coordinates: false,
            steps_across_samples: true,
            reuse: None,
        }
    }
}

impl SimulationOptions {
    /// These options for a run of `scene`: when they ask for no accuracy, method, tolerance,
    /// step or model of their own, keep the error estimate and do not keep the modes as
    /// given, the scene's `accuracy` (m) becomes [`SimulationOptions::accuracy`], so that
    /// the run picks the model size that meets it.
    ///
    /// ```
    /// use telescopic::Scene;
    /// use telescopic::run::SimulationOptions;
    /// let path = std::path::Path::new("scenes/case-study.toml");
    /// let scene = Scene::load(path, &["accuracy=1e-3".to_string()])?;
    /// assert_eq!(SimulationOptions::default().for_scene(&scene).accuracy, Some(1e-3));
    /// let given = SimulationOptions { modes_as_given: true, ..SimulationOptions::default() };
    /// assert_eq!(given.for_scene(&scene).accuracy, None);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn for_scene(&self, scene: &telescopic_runtime::Scene) -> SimulationOptions {
        let own_choice = self.accuracy.is_some()
            || self.modes_as_given
            || !self.error_estimate
            || self.method != MethodChoice::Auto
            || self.rtol.is_some()
            || self.atol.is_some()
            || self.dt.is_some()
            || self.model != ModelChoice::Auto;
        SimulationOptions {
            accuracy: if own_choice {
                self.accuracy
            } else {
                scene.accuracy
            },
            ..self.clone()
        }
    }
}
