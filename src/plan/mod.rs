//! Planning a move: the shortest cycle that brings the load to rest within a tolerance,
//! robust over the plants it carries. The vehicle follows a setpoint (the scene's prescribed
//! motion, a position-controlled servo); the candidates are the time-optimal jerk-limited
//! move ([`telescopic_runtime::SCurve`]), that move filtered by each shaper of the ZV/ZVD/EI
//! family ([`shapers`]) designed on the first mode at the target, the same shapers with
//! their spacing following the first mode as the telescopic positions move (scheduled),
//! an optimized scheduled shaper ([`optimize`]), and the matched S-curve whose acceleration
//! and braking each span whole periods of the first mode ([`candidates::matched`]), also
//! optimized. Every candidate runs on the nonlinear
//! model with clearance on every plant of the robust set ([`robust`]); [`metrics`] reads
//! its cycle time.
//!
//! ```no_run
//! use telescopic::plan::{MoveLimits, PlanOptions, plan_move};
//! use telescopic::{Scene, Silent};
//!
//! let scene = Scene::load("scenes/case-study.toml".as_ref(), &[])?;
//! let options = PlanOptions::new(MoveLimits { distance: 23.0, v_max: 2.5, a_max: 0.7, j_max: 2.0 });
//! let plan = plan_move(&scene, &options, &Silent)?;
//! println!("{}", plan.table());
//! # Ok::<(), telescopic::Error>(())
//! ```

pub mod candidates;
pub mod emit;
pub mod metrics;
mod moving;
pub mod optimize;
mod options;
mod outcome;
mod planner;
pub mod price;
pub mod robust;
pub mod shapers;

pub use moving::moving_scene;
pub use options::{
    DEFAULT_A_MAX, DEFAULT_CHECKS, DEFAULT_J_MAX, DEFAULT_MARGIN, DEFAULT_SETTLE_S,
    DEFAULT_TOLERANCE_M, DEFAULT_V_MAX, MAX_CHECKS, MoveLimits, PlanOptions,
};
pub use outcome::{MovePlan, PlanRow};
pub use planner::{first_period, plan as plan_move};
pub use price::PlanPrice;
pub use robust::RobustRange;
