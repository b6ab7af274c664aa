//! What is computed from a model rather than run: modal analysis and damped modes, the
//! structural damping matrix, the linear parameter-varying model, the independent element
//! model of the beams, what `auto` and `--accuracy` pick, the modal surrogate that predicts a
//! model's size, and a Jacobian check.

pub mod accuracy;
pub mod check;
pub mod damped_modes;
pub mod damping;
pub mod eigen;
pub mod elements;
pub mod linear;
pub mod modal_surrogate;
pub mod specialize;
