//! Shortcuts a scene allows, picked by the runtime without being asked and named in the run
//! summary: constant contact vectors, the linear law without events, no prestress, exact
//! stepping.

use crate::accuracy::{DEFAULT_ACCURACY_M, Resolve, SceneKind, cheapest, plan_for_accuracy};
use crate::integrate::Method;
use crate::integrate::exact::{exact_tail_start, lti_obstacle};
use crate::model::Model;
use crate::params::{ForceFlow, ModelParams};
use crate::scene::TimeSpan;

/// The specializations that apply to `model` over `span` in a run of `method` (with exact
/// stepping from `exact_from`, if set), one phrase each; a shortcut the scene allows but the
/// run does not take is named as available, not as used.
pub fn specializations(
    model: &dyn Model,
    span: &TimeSpan,
    method: Method,
    exact_from: Option<f64>,
) -> Vec<String> {
    let params = model.params();
    let mut found = Vec::new();
    if params.positions.iter().all(|p| p.is_constant()) {
        found.push("fixed positions: contact vectors are constants, computed once".to_string());
    }
    if let Some(table) = model.contact_table() {
        let (start, end) = table.span();
        let (error_g, error_gd) = table.checked_errors();
        found.push(format!(
            "moving positions: contact vectors tabulated on [{start}, {end}] s ({} intervals \
             of {:.3} ms, {} of {} entries moving; checked error {error_g:.1e} of g, \
             {error_gd:.1e} of its rate)",
            table.intervals(),
            1e3 * table.step(),
            table.varying_columns(),
            table.full_width()
        ));
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
        let how = if method == Method::Exact {
            "exact stepping (method exact)".to_string()
        } else {
            format!("exact stepping would apply (method exact or auto; this run: {method})")
        };
        found.push(format!(
            "linear time-invariant between contact switches with a piecewise-constant force: \
             {how}"
        ));
    }
    if let Some(t) = exact_tail_start(params, span) {
        let how = if exact_from.is_some() {
            "exact stepping of the rest (method auto)".to_string()
        } else {
            format!("exact stepping of the rest would apply (this run: {method} throughout)")
        };
        found.push(format!(
            "positions at rest from t = {t} s: linear time-invariant from there, {how}"
        ));
    }
    found
}

/// What method `auto` runs on `span`: the method, the time from which exact stepping takes
/// over when the positions come to rest inside the span (`None`: one method throughout), and
/// why; the plan of [`crate::accuracy::plan_for_accuracy`] at the default accuracy (1e-6 m),
/// whose tolerance is the default one (rtol 1e-6).
pub fn auto_plan(params: &ModelParams, span: &TimeSpan) -> (Method, Option<f64>, String) {
    let plan = plan_for_accuracy(params, span, DEFAULT_ACCURACY_M, Resolve::Displacements)
        .expect("every kind of scene has a measured run within the default accuracy");
    (plan.method, plan.exact_from, plan.why)
}

/// The method `auto` stands for on the scene of `params` (at the default accuracy), with the
/// reason.
pub fn auto_method(params: &ModelParams) -> (Method, String) {
    let kind = SceneKind::of(params);
    let row = cheapest(kind, DEFAULT_ACCURACY_M, Resolve::Displacements)
        .expect("every kind of scene has a measured run within the default accuracy");
    (
        Method::from_name(row.method).expect("the table names known methods"),
        format!("{} (for scenes {})", row.method, kind.describe()),
    )
}
