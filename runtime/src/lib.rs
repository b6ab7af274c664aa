//! Runtime of `telescopic`: everything a simulation of a telescopic multi-section beam with
//! clearance needs at run time (docs/model.md describes the model).
//!
//! * [`scene`]: TOML scene files, `--set` overrides and validation;
//! * [`profile`]: time profiles of positions, forces and motions;
//! * [`shape`]: the paper's shape functions and their roots, evaluated without cancellation;
//! * [`model`]: the [`Model`] interface of a discretized telescope, in computing coordinates
//!   (the exact change of variables), its parameters, layout and outputs, and the
//!   [`AssembledModel`]: the Galerkin model of docs/model.md section 4 by Gauss-Legendre
//!   quadrature, for any number of sections and modes: the generic model and the reference;
//! * [`contact`]: the clearance contact law;
//! * [`integrate`]: the methods, the driver and the [`integrate::Integrator`] a caller
//!   advances;
//! * [`analysis`]: natural frequencies and mode shapes with closed contacts, linear models,
//!   the element model of the beams and what `auto` and `--accuracy` pick.
//!
//! ```no_run
//! use telescopic_runtime::{AssembledModel, Scene, modal_analysis};
//! let scene = Scene::load("scenes/test-rig.toml".as_ref(), &[]).unwrap();
//! let model = AssembledModel::new(&scene.params).unwrap();
//! let modes = modal_analysis(&model, scene.time.start).unwrap();
//! println!("{:?}", modes.frequencies_hz);
//! ```

#![warn(missing_docs)]

pub mod analysis;
pub mod contact;
pub mod input;
pub mod integrate;
pub mod model;
pub mod profile;
pub mod scene;
pub mod shape;

pub use analysis::accuracy::{AccuracyPlan, DEFAULT_ACCURACY_M, plan_for_accuracy, setting_label};
pub use analysis::damped_modes::{DampedMode, damped_modes};
pub use analysis::damping::{
    CONTACT_MODE_SHARE, StructuralDamping, contact_energy_shares, structural_damping,
};
pub use analysis::eigen::{
    EigenError, FastestRates, ModalAnalysis, closed_contact_damping, closed_contact_eigenvalues,
    eigenvalues, fastest_rates, modal_analysis, modal_analysis_with, sample_shape,
};
pub use analysis::elements::{ElementError, ElementModel};
pub use analysis::linear::{ContactMode, LinearError, LinearModel, Lpv, Signal};
pub use analysis::specialize::{Specialization, auto_method, auto_plan, specializations};
pub use contact::table::{ContactTable, ContactTableParts};
pub use contact::{ContactForce, ContactLaw, ContactState};
pub use integrate::{Method, RunStats, Settings, SimError, simulate};
pub use model::assembled::{AssembledModel, ModelError, paper_section_matrices};
pub use model::configuration::{
    DriveKind, ModelConfig, Positions, StaticKnots, config_of, configuration_key, models_toml_entry,
};
pub use model::layout::{ContactPoint, Layout};
pub use model::output::{LinearInput, Output, Sensor};
pub use model::params::{Basis, Drive, ForceFlow, ModelParams, SectionParams};
pub use model::{Model, mechanical_energy, rest_state};
/// The linear-algebra crate of the [`Model`] interface, re-exported so that generated modules
/// and downstream crates use the same version.
pub use nalgebra;
pub use profile::{
    JerkSegments, Phases, PositionSchedule, Profile, ReachedLimits, SCurve, ShapedProfile,
    ShapedSetpoint,
};
pub use scene::{FieldError, Scene, SceneError, SceneFile, TimeSpan};
pub use shape::{MAX_MODES, SectionKind, SectionShapes, ShapeFunction, mode_root};
