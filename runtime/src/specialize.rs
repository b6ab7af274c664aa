//! Shortcuts a scene allows, picked by the runtime without being asked and named in the run
//! summary: constant contact vectors, the linear law without events, no prestress, exact
//! stepping.

use crate::integrate::Method;
use crate::integrate::exact::lti_obstacle;
use crate::params::{ForceFlow, ModelParams};

/// The specializations that apply to `params`, one phrase each.
pub fn specializations(params: &ModelParams) -> Vec<String> {
    let mut found = Vec::new();
    if params.positions.iter().all(|p| p.is_constant()) {
        found.push("fixed positions: contact vectors are constants, computed once".to_string());
    }
    if params.contact.is_linear() {
        found.push("l_S = 0: linear contact law, no switch events".to_string());
    }
    if params.force_flow == ForceFlow::None {
        let why = if params.gravity == 0.0 {
            "gravity off"
        } else {
            "force flow none"
        };
        found.push(format!("{why}: no prestress terms"));
    }
    if lti_obstacle(params).is_none() {
        found.push(
            "linear time-invariant between contact switches with a piecewise-constant force: \
             exact stepping (method exact)"
                .to_string(),
        );
    }
    found
}

/// The method `auto` stands for: `exact` for a scene that is linear and time-invariant
/// between contact switches, else `dopri5`; with the reason.
pub fn auto_method(params: &ModelParams) -> (Method, String) {
    match lti_obstacle(params) {
        None => (
            Method::Exact,
            "the scene is linear and time-invariant between contact switches".to_string(),
        ),
        Some(why) => (Method::Dopri5, format!("not exact: {why}")),
    }
}
