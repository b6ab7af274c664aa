//! # telescopic
//!
//! Equations of motion, eigenfrequencies and simulation of telescopic multi-section beams
//! with clearance (mobile cranes, rack feeders), after Barthelis & Wauer (2005). This crate
//! is the library behind the `telescopic` command: everything the command does is a function
//! here with typed options and a typed result, and the command only parses and prints.
//!
//! The path of a scene: a TOML scene file ([`Scene`], see `docs/scenes.md`) gives the
//! parameters; they select a model, the generated one of their configuration when
//! `telescopic-generated` or a registered downstream set has it ([`run::models`]); one
//! prepared-run path integrates it with the clearance contact law and estimates its error
//! ([`run`]); the analyses ([`analysis`]: modes, stability, work-precision, model sizes,
//! convergence, the beams' finite-element reference), linear models and controllers
//! ([`linear`], [`control`]), parameter studies ([`sweep`]), the FMU ([`fmu`]) and outputs
//! ([`io`], [`plot`]) build on that.
//!
//! Simulate a scene file and write its CSV:
//!
//! ```
//! use telescopic::run::{SimulationOptions, simulate_scene};
//! use telescopic::{Scene, Silent};
//!
//! let scene = Scene::load("scenes/adams-clearance.toml".as_ref(), &["time.end=0.3".into()])?;
//! let run = simulate_scene(&scene, &SimulationOptions::default(), &Silent)?;
//! assert_eq!(run.plan.method.name(), "exact"); // auto: linear and time-invariant between switches
//! let mut csv = Vec::new();
//! run.trajectory.write_csv(&mut csv)?;
//! assert!(csv.starts_with(b"t,vehicle,tip_rel,top1_rel,xi_2_0"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Compute eigenfrequencies:
//!
//! ```
//! use telescopic::analysis::modes::{ModesOptions, compute_modes};
//!
//! let scene = telescopic::Scene::load("scenes/test-rig.toml".as_ref(), &[])?;
//! let report = compute_modes(&scene, &ModesOptions::default())?;
//! println!("{}", report.to_table());
//! # Ok::<(), telescopic::Error>(())
//! ```
//!
//! Generating a model for a new configuration is `telescopic_codegen::Builder`'s job, at
//! build time (see `docs/generator.md`); this crate never runs Symbolica.

#![warn(missing_docs)]

pub mod analysis;
#[cfg(feature = "plot")]
pub mod animate;
mod cancel;
pub mod control;
mod error;
pub mod fmu;
pub mod identify;
pub mod io;
mod key_range;
pub mod linear;
mod named;
mod option_name;
pub mod plan;
#[cfg(feature = "plot")]
pub mod plot;
pub mod report;
pub mod run;
pub mod sweep;
mod wrapped;

pub use cancel::Cancel;
pub use error::{Error, Result};
pub use option_name::OptionName;
pub use report::{Reporter, Silent};
pub use telescopic_runtime as runtime;
pub use telescopic_runtime::Scene;
