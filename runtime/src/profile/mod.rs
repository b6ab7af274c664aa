//! Time profiles for telescopic positions `a_k(t)`, the drive force `F(t)` and a prescribed
//! vehicle motion `s(t)`.
//!
//! In a scene file a profile is a number (constant) or a table with a `kind`:
//!
//! ```toml
//! force = 100.0
//! force = { kind = "piecewise-constant", times = [0, 4, 8, 12], values = [100, 0, -100, 0] }
//! force = { kind = "piecewise-linear", times = [0, 1], values = [0, 100] }
//! position = { kind = "smoothstep", start = 0, end = 12, from = 0.35, to = 1.15 }
//! motion = { kind = "s-curve", start = 0, distance = 23, v_max = 2.5, a_max = 0.7, j_max = 2 }
//! motion = { kind = "jerk-segments", start = 0, segments = [[0.5, 2], [3, 0], [0.5, -2], [4, 0], [0.5, -2], [3, 0], [0.5, 2]] }
//! motion = { kind = "shaped", base = { kind = "s-curve", ... }, impulses = [[0.5, 0], [0.5, 0.5]], period = 1.75 }
//! ```
//!
//! Piecewise profiles hold their first value before the first time and their last value
//! after the last one; piecewise-constant takes `values[i]` on `[times[i], times[i+1])`.
//! The smoothstep is the quintic `from + (to - from)(10u^3 - 15u^4 + 6u^5)`,
//! `u = (t - start)/(end - start)`, constant outside `[start, end]`. The S-curve is the
//! time-optimal jerk-limited move ([`SCurve`]); jerk segments are any rest-to-rest move of
//! constant-jerk pieces ([`JerkSegments`]); a shaped setpoint is
//! `sum_i A_i base(t - m_i P(t))`, impulses of amplitude `A_i` at multiples `m_i` of a period
//! `P(t)` that may follow the telescopic positions ([`ShapedSetpoint`]).

pub mod curves;
mod function;
mod parse;
pub mod setpoint;

pub use function::{PositionSchedule, Profile, ShapedProfile, ShapedSetpoint};
pub use setpoint::{JerkSegments, Phases, ReachedLimits, SCurve};
