//! The files a design writes and a run reads: the controller file's layout ([`schema`]) and
//! its checks against its rules and its scene ([`check`]), and the velocity-feedback file
//! ([`velocity`]).

pub mod check;
pub mod schema;
pub mod velocity;
