//! What `linearize` gives: the linear models of a scene with the names, units and operating
//! points needed to read them elsewhere, and their discrete-time forms.

use telescopic_runtime::nalgebra::DMatrix;
use telescopic_runtime::{ContactMode, LinearModel, Signal};

/// The zero-order-hold discrete-time models of a [`LinearExport`]:
/// `x[k+1] = Ad x[k] + Bd u[k]`, `y[k] = C x[k] + D u[k]` with the continuous `C`, `D`.
#[derive(Debug, Clone, PartialEq)]
pub struct DiscreteModels {
    /// Sample period (s).
    pub dt: f64,
    /// `(Ad, Bd)` per operating point.
    pub points: Vec<(DMatrix<f64>, DMatrix<f64>)>,
}

/// A linear model, or a grid of them, with everything needed to read it elsewhere.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearExport {
    /// The scene's name.
    pub scene: String,
    /// The scene's file, as given (empty when the caller did not say).
    pub scene_file: String,
    /// Its `--set` overrides (empty when the caller did not say).
    pub overrides: Vec<String>,
    /// The configuration key.
    pub configuration: String,
    /// Which model (`generated model <key>` or `quadrature-assembled model`).
    pub model: String,
    /// How the contacts enter.
    pub contacts: ContactMode,
    /// States, in the order of the matrices.
    pub states: Vec<Signal>,
    /// Inputs.
    pub inputs: Vec<Signal>,
    /// Outputs.
    pub outputs: Vec<Signal>,
    /// The gridded position (`a_k`) and its values, when a grid was asked for.
    pub grid: Option<(String, Vec<f64>)>,
    /// How the operating point was chosen, e.g. `positions of the scene at t = 0 s`.
    pub operating_point: String,
    /// One linear model per operating point (one without a grid).
    pub points: Vec<LinearModel>,
    /// The discrete-time models, when asked for.
    pub discrete: Option<DiscreteModels>,
}
