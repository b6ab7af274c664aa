//! The laws as they run: the continuous law wrapped around the plant ([`controlled`]), the
//! sampled laws and their discrete Kalman filter ([`sampled`]), the extended filter and the
//! model it predicts with ([`ekf`], [`estimator_model`], [`small_dense`]), the strain-rate
//! law ([`strain`]), the velocity feedback and the servo plant it corrects ([`velocity`],
//! [`servo`]), and the gain schedule every law interpolates ([`schedule`]).

pub mod controlled;
pub mod ekf;
pub mod estimator_model;
pub mod sampled;
pub mod schedule;
pub mod servo;
pub mod small_dense;
pub mod strain;
pub mod velocity;
