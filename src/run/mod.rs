//! One simulation, from the scene to every sample: the options ([`options`]), the resolved
//! method ([`method`]), the model chosen for the scene's configuration ([`models`]), the
//! checks before a run starts ([`budget`], [`memory`]), the prepared run that integrates it
//! ([`prepared`]), the outputs at stations ([`stress`]), the samples ([`trajectory`]), the
//! error budget ([`error_budget`]) and its reuse by a repeated run ([`reuse`]), a model size
//! ([`sized`]), the search for a model size
//! and method that meets a total accuracy ([`total_accuracy`]), the finished run
//! ([`simulation`]) and its summary as data ([`summary`]).
//!
//! ```
//! use telescopic::run::{SimulationOptions, simulate_scene};
//! use telescopic::{Scene, Silent};
//!
//! let scene = Scene::load("scenes/adams-linear.toml".as_ref(), &["time.end=0.5".into()])?;
//! let run = simulate_scene(&scene, &SimulationOptions::default(), &Silent)?;
//! let tip = run.trajectory.column("tip_rel").expect("every model has tip_rel");
//! assert_eq!(tip.len(), 501); // 0 .. 0.5 s every millisecond
//! println!("{}", run.summary());
//! # Ok::<(), telescopic::Error>(())
//! ```

pub mod budget;
pub mod error_budget;
pub mod held;
pub mod memory;
pub mod method;
pub mod models;
pub mod options;
pub mod predicted_size;
pub mod prepared;
pub mod reuse;
pub mod simulate;
pub mod simulation;
pub mod sized;
pub mod stress;
pub mod summary;
pub mod total_accuracy;
pub mod trajectory;

pub use held::HeldInputStepper;
pub use method::{MethodReason, Plan, plan};
pub use options::{MethodChoice, SimulationOptions};
pub use predicted_size::{NoPrediction, SizePrediction, predict_size};
pub use prepared::PreparedRun;
pub use simulate::{estimate_error, simulate_scene};
pub use simulation::{Simulation, write_csv};
pub use sized::ModelSize;
pub use summary::{ErrorSummary, RunSummary};
pub use trajectory::{Column, Trajectory};
