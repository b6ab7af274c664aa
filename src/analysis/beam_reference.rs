//! The beams' own response, the truth a Ritz model's whole error is measured against: the
//! finite-element model of the same sections and contacts
//! ([`telescopic_runtime::ElementModel`]) for a scene with fixed telescopic positions, run
//! with method `exact`; with moving positions, the most refined Ritz model
//! ([`REFERENCE_BASIS`] with [`REFERENCE_MODES`] per section, at tight tolerances), whose
//! agreement with the finite elements on the fixed-position scenes and with the elements'
//! sliding stations over case-study-no-clearance's first 4 s is what justifies it
//! (docs/numerics.md): the elements with sliding stations ([`element_response`]) take some
//! ten times longer.
//!
//! ```
//! use telescopic::analysis::beam_reference::{BeamReference, beam_response};
//! use telescopic::{Scene, Silent};
//! let scene = Scene::load("scenes/adams-linear.toml".as_ref(), &["time.end=0.2".into()])?;
//! let beams = beam_response(&scene, &[], &Silent)?;
//! assert_eq!(beams.reference, BeamReference::Elements(REFERENCE_ELEMENTS));
//! # use telescopic::analysis::beam_reference::REFERENCE_ELEMENTS;
//! # Ok::<(), telescopic::Error>(())
//! ```

use crate::report::Reporter;
use crate::run::PreparedRun;
use crate::run::models::ModelChoice;
use crate::run::stress::Station;
use crate::run::{Column, SimulationOptions, Trajectory};
use crate::{Error, Result};
use telescopic_runtime::{
    Basis, ElementModel, Method, Model, Profile, Scene, Settings, model::rest_state, simulate,
};

/// Elements per section of the finite-element reference: 32 and 64 agree to 2e-7 m in
/// `tip_rel` on adams-linear over 5 s (Hermite elements converge as `h^4`).
pub const REFERENCE_ELEMENTS: usize = 32;

/// Tolerance of the finite-element reference with moving positions (`atol = 1e-3 rtol`).
pub const ELEMENT_SLIDING_RTOL: f64 = 1e-8;

/// The basis and modes per section of the Ritz reference for moving positions.
pub const REFERENCE_BASIS: Basis = Basis::ModesAndStatic;
/// See [`REFERENCE_BASIS`].
pub const REFERENCE_MODES: usize = 10;
/// Tolerance of the Ritz reference (`atol = 1e-3 rtol`).
pub const REFERENCE_RTOL: f64 = 1e-8;

/// Which model gave a reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BeamReference {
    /// The finite elements, with this many elements per section (about).
    Elements(usize),
    /// The most refined Ritz model.
    Ritz {
        /// Its basis.
        basis: Basis,
        /// Its modes per section.
        modes: usize,
    },
}

impl std::fmt::Display for BeamReference {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BeamReference::Elements(n) => write!(f, "finite elements, about {n} per section"),
            BeamReference::Ritz { basis, modes } => {
                write!(
                    f,
                    "the Ritz model with {modes} modes per section, basis {}",
                    basis.word()
                )
            }
        }
    }
}

/// The beams' response to a scene.
#[derive(Debug, Clone, PartialEq)]
pub struct BeamResponse {
    /// Which model.
    pub reference: BeamReference,
    /// Its samples: the model's outputs, then one `moment_k_x` column per station.
    pub trajectory: Trajectory,
}

/// The beams' response to `scene` with the moments at `stations` (see the module
/// documentation).
///
/// # Errors
/// [`Error::Model`] when the reference model cannot be built, [`Error::Simulation`] for a
/// failed run.
pub fn beam_response(
    scene: &Scene,
    stations: &[Station],
    reporter: &dyn Reporter,
) -> Result<BeamResponse> {
    if scene.params.positions.iter().all(Profile::is_constant) {
        element_response(scene, REFERENCE_ELEMENTS, stations, reporter)
    } else {
        ritz_response(scene, stations, reporter)
    }
}

/// The finite-element model's response with `elements` per section: with fixed positions by
/// method `exact`, with moving ones (the contacts sliding across the elements) by `imex` at
/// [`ELEMENT_SLIDING_RTOL`], its steps on every sample (16 elements per section take about
/// 4 s for case-study-no-clearance's first 4 s on the 2-core machine, 32 about 15 s).
///
/// # Errors
/// As [`beam_response`].
pub fn element_response(
    scene: &Scene,
    elements: usize,
    stations: &[Station],
    reporter: &dyn Reporter,
) -> Result<BeamResponse> {
    let model = ElementModel::new(&scene.params, elements).map_err(Error::from)?;
    let outputs = model.output_quantities();
    let mut out = vec![0.0; outputs.len()];
    let moments = stations.iter().map(Station::moment);
    let columns: Vec<Column> = outputs
        .into_iter()
        .chain(moments)
        .map(Column::Output)
        .collect();
    let mut rows = Vec::new();
    let dof = model.dof();
    let mut observe = |t: f64, y: &[f64], ydot: &[f64]| {
        model.outputs(t, y, ydot, &mut out);
        let mut row = Vec::with_capacity(columns.len() + 1);
        row.push(t);
        row.extend_from_slice(&out);
        row.extend(
            stations
                .iter()
                .map(|s| model.moment(s.section, s.x, &y[..dof])),
        );
        rows.push(row);
    };
    reporter.start(&format!("finite-element reference of {}", scene.name));
    let y0 = rest_state(&model, scene.time.start);
    let (method, settings) = if scene.params.positions.iter().all(Profile::is_constant) {
        (Method::Exact, Settings::default())
    } else {
        let settings = Settings {
            rtol: ELEMENT_SLIDING_RTOL,
            atol: 1e-3 * ELEMENT_SLIDING_RTOL,
            ..Settings::default()
        };
        (Method::Imex, settings)
    };
    let stats = simulate(
        &model,
        &y0,
        &scene.time,
        method,
        &settings,
        &mut observe,
        None,
    )
    .map_err(|error| Error::Simulation {
        scene: scene.name.clone(),
        error,
    })?;
    reporter.finish();
    Ok(BeamResponse {
        reference: BeamReference::Elements(elements),
        trajectory: Trajectory::new(columns, rows, stats),
    })
}

/// The most refined Ritz model's response.
fn ritz_response(
    scene: &Scene,
    stations: &[Station],
    reporter: &dyn Reporter,
) -> Result<BeamResponse> {
    let mut refined = scene.clone();
    refined.params.basis = REFERENCE_BASIS;
    for s in &mut refined.params.sections {
        s.modes = REFERENCE_MODES;
    }
    let options = SimulationOptions {
        method: crate::run::MethodChoice::Method(Method::Dop853),
        rtol: Some(REFERENCE_RTOL),
        atol: Some(1e-3 * REFERENCE_RTOL),
        model: ModelChoice::Assembled,
        stations: stations.to_vec(),
        error_estimate: false,
        ..SimulationOptions::default()
    };
    let run = PreparedRun::new(&refined, &options, reporter)?;
    let trajectory = run.integrate(reporter)?;
    Ok(BeamResponse {
        reference: BeamReference::Ritz {
            basis: REFERENCE_BASIS,
            modes: REFERENCE_MODES,
        },
        trajectory,
    })
}
