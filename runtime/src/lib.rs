//! Runtime of `telescopic`: everything a simulation of a telescopic multi-section beam with
//! clearance needs at run time (docs/model.md describes the model).
//!
//! * [`scene`]: TOML scene files, `--set` overrides and validation;
//! * [`shape`]: the paper's shape functions and their roots, evaluated without cancellation;
//! * [`Model`]: the interface of a discretized telescope, in computing coordinates
//!   (see [`model`] for the exact change of variables);
//! * [`AssembledModel`]: the Galerkin model of docs/model.md section 4 by Gauss-Legendre
//!   quadrature, for any number of sections and modes: the generic model and the reference;
//! * [`contact`]: the clearance contact law;
//! * [`eigen`]: natural frequencies and mode shapes with closed contacts.
//!
//! ```no_run
//! use telescopic_runtime::{AssembledModel, Scene, modal_analysis};
//! let scene = Scene::load("scenes/test-rig.toml".as_ref(), &[]).unwrap();
//! let model = AssembledModel::new(&scene.params).unwrap();
//! let modes = modal_analysis(&model, scene.time.start).unwrap();
//! println!("{:?}", modes.frequencies_hz);
//! ```

#![warn(missing_docs)]

pub mod accuracy;
pub mod assembled;
pub mod check;
pub mod configuration;
pub mod contact;
pub mod contact_table;
pub mod damped_modes;
pub mod damping;
pub mod eigen;
pub mod elements;
pub mod input;
pub mod integrate;
pub mod layout;
pub mod linear;
mod mass_solve;
pub mod model;
pub mod output;
pub mod params;
pub mod profile;
pub mod quadrature;
pub mod scene;
pub(crate) mod section_basis;
pub mod sensors;
pub mod shape;
#[cfg(feature = "reference")]
pub mod shape_reference;
pub mod specialize;
pub mod spline;

pub use accuracy::{AccuracyPlan, DEFAULT_ACCURACY_M, plan_for_accuracy};
pub use assembled::{AssembledModel, ModelError, paper_section_matrices};
pub use configuration::{DriveKind, ModelConfig, Positions, configuration_key, models_toml_entry};
pub use contact::{ContactForce, ContactLaw, ContactState};
pub use contact_table::{ContactTable, ContactTableParts};
pub use damped_modes::{DampedMode, damped_modes};
pub use damping::{
    CONTACT_MODE_SHARE, StructuralDamping, contact_energy_shares, structural_damping,
};
pub use eigen::{
    EigenError, FastestRates, ModalAnalysis, closed_contact_damping, closed_contact_eigenvalues,
    eigenvalues, fastest_rates, modal_analysis, modal_analysis_with, sample_shape,
};
pub use elements::{ElementError, ElementModel};
pub use integrate::{Method, RunStats, Settings, SimError, simulate};
pub use layout::{ContactPoint, Layout};
pub use linear::{ContactMode, LinearError, LinearModel, Lpv, Signal};
pub use model::{Model, mechanical_energy, rest_state};
/// The linear-algebra crate of the [`Model`] interface, re-exported so that generated modules
/// and downstream crates use the same version.
pub use nalgebra;
pub use output::{LinearInput, Output, Sensor};
pub use params::{Basis, Drive, ForceFlow, ModelParams, SectionParams};
pub use profile::{
    Phases, PositionSchedule, Profile, ReachedLimits, SCurve, ShapedProfile, ShapedSetpoint,
};
pub use scene::{FieldError, Scene, SceneError, SceneFile, TimeSpan};
pub use shape::{MAX_MODES, SectionKind, SectionShapes, ShapeFunction, mode_root};
pub use specialize::{Specialization, auto_method, auto_plan, specializations};
