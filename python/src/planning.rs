//! Planning a move for Python: `telescopic.plan` gets the table as rows of plain values and
//! the best plan as scene text, which `telescopic/__init__.py` turns into a DataFrame and a
//! `Scene`.

use crate::background::run_showing;
use crate::errors::to_python;
use crate::scene::PyScene;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use telescopic::control::design::velocity::VelocityDesign;
use telescopic::plan::{
    DEFAULT_A_MAX, DEFAULT_CHECKS, DEFAULT_J_MAX, DEFAULT_MARGIN, DEFAULT_SETTLE_S,
    DEFAULT_TOLERANCE_M, DEFAULT_V_MAX,
};
use telescopic::plan::{MoveLimits, MovePlan, PlanOptions, RobustRange, plan_move};

/// The plan's table as one dict per row (candidate, plant and the figures).
fn rows<'py>(py: Python<'py>, plan: &MovePlan) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let evaluated = plan.rows.iter().map(|r| (r, true));
    let checks = plan.checks.iter().map(|r| (r, false));
    evaluated
        .chain(checks)
        .map(|(r, was_evaluated)| {
            let m = &r.metrics;
            let row = PyDict::new(py);
            row.set_item("candidate", &plan.candidates[r.candidate].name)?;
            row.set_item("plant", &r.plant)?;
            row.set_item("evaluated", was_evaluated)?;
            row.set_item("move_time_s", m.move_time_s)?;
            row.set_item("settling_time_s", m.settling_time_s)?;
            row.set_item("cycle_time_s", m.cycle_time_s)?;
            row.set_item("pick_cycle_time_s", m.pick_cycle_time_s)?;
            row.set_item("peak_tip_move_m", m.peak_tip_move_m)?;
            row.set_item("residual_m", m.residual_m)?;
            row.set_item("peak_drive_force_n", m.peak_drive_force_n)?;
            row.set_item("peak_contact_force_n", m.peak_contact_force_n)?;
            row.set_item("peak_foot_stress_pa", m.peak_foot_stress_pa)?;
            row.set_item("switches_after_arrival", m.switches_after_arrival)?;
            Ok(row)
        })
        .collect()
}

/// The shortest move that brings the load to rest (see `telescopic.plan`): `(rows, plan
/// scene TOML, summary)`.
#[pyfunction]
#[pyo3(signature = (scene, distance, v_max = DEFAULT_V_MAX, a_max = DEFAULT_A_MAX,
    j_max = DEFAULT_J_MAX, tolerance = DEFAULT_TOLERANCE_M, margin = DEFAULT_MARGIN, robust = None,
    settle = DEFAULT_SETTLE_S, optimize = true, checks = None, force_limit = None,
    feedback = None,
    options = None, progress = None, notes = true))]
#[allow(clippy::too_many_arguments)]
pub fn plan<'py>(
    py: Python<'py>,
    scene: &PyScene,
    distance: f64,
    v_max: f64,
    a_max: f64,
    j_max: f64,
    tolerance: f64,
    margin: f64,
    robust: Option<Vec<(String, f64, f64)>>,
    settle: f64,
    optimize: bool,
    checks: Option<Bound<'py, PyAny>>,
    force_limit: Option<f64>,
    feedback: Option<f64>,
    options: Option<crate::calls::RunArguments>,
    progress: Option<&Bound<'py, PyAny>>,
    notes: bool,
) -> PyResult<(Vec<Bound<'py, PyDict>>, String, Bound<'py, PyDict>)> {
    let simulation = match options {
        Some(o) => o.into_options()?,
        None => telescopic::run::SimulationOptions {
            memory_budget: crate::calls::memory_budget()?,
            ..Default::default()
        },
    };
    let options = PlanOptions {
        tolerance,
        margin,
        robust: match &robust {
            Some(entries) => RobustRange::list(entries).map_err(to_python)?,
            None => Vec::new(),
        },
        settle_s: settle,
        optimize,
        checks: match &checks {
            Some(c) => crate::calls::whole("checks", c)?,
            None => DEFAULT_CHECKS,
        },
        force_limit,
        feedback: feedback.map(|zeta| VelocityDesign {
            added_damping: zeta,
            ..VelocityDesign::default()
        }),
        simulation,
        ..PlanOptions::new(MoveLimits {
            distance,
            v_max,
            a_max,
            j_max,
        })
    };
    let scene = &scene.scene;
    let plan = run_showing(py, progress, notes, |reporter| {
        plan_move(scene, &options, reporter)
    })?;
    let summary = PyDict::new(py);
    summary.set_item("rigid_limit_s", plan.rigid_limit_s)?;
    summary.set_item("first_mode_hz", 1.0 / plan.first_period_s)?;
    summary.set_item("best", &plan.candidates[plan.best].name)?;
    summary.set_item(
        "worst_cycle_s",
        MovePlan::worst_cycle(&plan.rows, plan.best),
    )?;
    summary.set_item("worst_pick_s", MovePlan::worst_pick(&plan.rows, plan.best))?;
    summary.set_item("table", plan.table())?;
    let plants = PyDict::new(py);
    for plant in &plan.plants {
        let values = PyDict::new(py);
        for (key, value) in &plant.values {
            values.set_item(key, value)?;
        }
        plants.set_item(&plant.name, values)?;
    }
    summary.set_item("plants", plants)?;
    summary.set_item("feedback", plan.feedback_json())?;
    Ok((rows(py, &plan)?, plan.scene_toml(), summary))
}
