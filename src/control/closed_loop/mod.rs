//! Laws in the loop with the full nonlinear model: a controlled run beside its open loop and
//! the design's variants ([`comparison`]), the tick loop of the sampled laws ([`sampled`]),
//! the velocity feedback's run ([`velocity`]), and a controller file of either kind as
//! `simulate --controller` reads it ([`controller_file`]).

pub mod comparison;
pub mod controller_file;
pub mod sampled;
pub mod velocity;
