//! Analyses built on the model and its runs: natural frequencies and mode shapes
//! ([`modes`]), stable steps ([`stability`]), the derived equations ([`equations`]), metrics of
//! a run ([`metrics`]), speed against accuracy ([`work_precision`], [`model_size`]), the
//! smallest model a scene needs ([`converge`]), the independent beam model that checks the
//! error budget ([`beam_reference`]) and the shape functions' evaluation error
//! ([`shape_errors`]).

pub mod beam_reference;
pub mod converge;
pub mod equations;
pub mod metrics;
pub mod model_size;
pub mod modes;
pub mod shape_errors;
pub mod stability;
pub mod work_precision;
