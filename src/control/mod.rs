//! Controller design on the linear models and its test on the full nonlinear model with
//! clearance, a room per role: the designs ([`design`](mod@design): the gain-scheduled LQR,
//! the Riccati solver, input shapers, the velocity feedback), the laws as they run
//! ([`law`]), the files a design writes ([`file`](mod@file)), the laws in the loop with the plant
//! ([`closed_loop`]) and the laws as C99 ([`emit`]). The figures a design is judged by are
//! [`crate::analysis::metrics`].
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

pub mod closed_loop;
pub mod design;
pub mod emit;
pub mod file;
pub mod law;

pub use closed_loop::comparison::{
    ControlComparison, VariantRow, compare_variants, compare_with_open_loop, comparison_options,
    controlled_options, simulate_controlled, variants_table,
};
pub use closed_loop::controller_file::{ControllerFile, compare_file_with_open_loop};
pub use design::shaper::{ShaperKind, ShaperTiming};
pub use design::{DesignOptions, design};
pub use file::schema::{
    CONTROLLER_FILE_VERSION, Controller, ControllerKind, Estimator, SampledLaw, SchedulePoint,
};
pub use law::controlled::{ControlLaw, Controlled, Observed};
