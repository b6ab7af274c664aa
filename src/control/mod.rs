//! Controller design on the linear models and its test on the full nonlinear model with
//! clearance: the Riccati solver ([`riccati`]), input shapers ([`shaper`]), the gain-scheduled
//! LQR and its controller file ([`design`](mod@design)), the controlled model ([`controlled`]), and the
//! figures a design is judged by ([`crate::analysis::metrics`]).
//!
//! ```no_run
//! use telescopic::control::{DesignOptions, compare_variants};
//! use telescopic::{Scene, Silent};
//!
//! let scene = Scene::load("scenes/case-study.toml".as_ref(), &[])?;
//! for row in compare_variants(&scene, &DesignOptions::default(), &Silent)? {
//!     println!("{}: residual {:.4} m", row.variant, row.metrics.residual_std);
//! }
//! # Ok::<(), telescopic::Error>(())
//! ```

pub mod comparison;
pub mod controlled;
pub mod controller_file;
pub mod design;
pub mod ekf;
pub mod emit;
pub mod estimator_model;
pub mod file;
pub mod riccati;
pub mod sampled;
pub mod sampled_run;
pub mod schedule;
pub mod schema;
pub mod shaper;
pub mod small_dense;
pub mod strain;
pub mod velocity;

pub use comparison::{
    ControlComparison, VariantRow, compare_variants, compare_with_open_loop, comparison_options,
    simulate_controlled, variants_table,
};
pub use controlled::{ControlLaw, Controlled, Observed};
pub use controller_file::{ControllerFile, compare_file_with_open_loop};
pub use design::{DesignOptions, design};
pub use schema::{
    CONTROLLER_FILE_VERSION, Controller, ControllerKind, Estimator, SampledLaw, SchedulePoint,
};
pub use shaper::{ShaperKind, ShaperTiming};
