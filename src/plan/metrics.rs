//! What a move achieved on one plant: when it arrived, when the load came to rest, and the
//! peaks on the way, read from the run's samples.

use crate::run::Trajectory;
use serde::Serialize;
use telescopic_runtime::{ContactLaw, Output};

/// How long the rest is judged over at the end of a run (s): the load's final rest is its
/// mean `tip_rel` there.
pub const REST_WINDOW_S: f64 = 1.0;

/// The vehicle's tolerance around its target (m).
pub const VEHICLE_TOLERANCE_M: f64 = 1e-3;

/// One candidate's figures on one plant.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CycleMetrics {
    /// When the setpoint reaches the target (s from the start).
    pub move_time_s: f64,
    /// Cycle time minus move time (s); `None` when the load does not settle in the run.
    pub settling_time_s: Option<f64>,
    /// From the start until `tip_rel` stays within the tolerance of its final rest and the
    /// vehicle within 1 mm of its target (s); `None` when that does not happen in the run.
    pub cycle_time_s: Option<f64>,
    /// Largest `|tip_rel|` before arrival (m).
    pub peak_tip_move_m: f64,
    /// Largest `|drive_force|`, the prescribed motion's reaction (N).
    pub peak_drive_force_n: f64,
    /// Largest `|f_k_j|` (N).
    pub peak_contact_force_n: f64,
    /// Largest `|stress_K_X|` over the stations (Pa), when the run has stresses: the foot
    /// of section 1 when the stations are `1:0`.
    pub peak_foot_stress_pa: Option<f64>,
    /// Contact openings and closings after arrival.
    pub switches_after_arrival: usize,
    /// Largest `|tip_rel - rest|` after arrival (m): the residual vibration.
    pub residual_m: f64,
}

/// The figures of `traj`, a run of a move to `target` (m) that arrives at `move_time` (s),
/// with `tolerance` (m) on `tip_rel` and the contact `law` of its scene.
pub fn cycle_metrics(
    traj: &Trajectory,
    (target, move_time): (f64, f64),
    tolerance: f64,
    law: &ContactLaw,
) -> CycleMetrics {
    let (tip, vehicle) = (
        traj.index_of(Output::TipRel).expect("tip_rel"),
        traj.index_of(Output::Vehicle).expect("vehicle"),
    );
    let end = traj.rows.last().map_or(0.0, |r| r[0]);
    let window: Vec<f64> = traj
        .rows
        .iter()
        .filter(|r| r[0] >= end - REST_WINDOW_S)
        .map(|r| r[tip])
        .collect();
    let rest = window.iter().sum::<f64>() / window.len().max(1) as f64;
    let outside = |r: &Vec<f64>| {
        (r[tip] - rest).abs() > tolerance || (r[vehicle] - target).abs() > VEHICLE_TOLERANCE_M
    };
    let last_outside = traj.rows.iter().rposition(outside);
    let cycle = match last_outside {
        None => Some(traj.rows.first().map_or(0.0, |r| r[0])),
        // still outside in the rest window: the run never settles
        Some(i) if traj.rows[i][0] >= end - REST_WINDOW_S => None,
        Some(i) => traj.rows.get(i + 1).map(|r| r[0]),
    };
    let max_abs = |cols: &[usize], during: &dyn Fn(f64) -> bool| {
        traj.rows
            .iter()
            .filter(|r| during(r[0]))
            .flat_map(|r| cols.iter().map(move |&c| r[c].abs()))
            .fold(0.0, f64::max)
    };
    let all = |_: f64| true;
    let forces = traj.columns_where(Output::is_contact_force);
    let switches = traj.sampled_switches(law, move_time);
    CycleMetrics {
        move_time_s: move_time,
        settling_time_s: cycle.map(|c| (c - move_time).max(0.0)),
        cycle_time_s: cycle,
        peak_tip_move_m: max_abs(&[tip], &|t| t <= move_time),
        peak_drive_force_n: traj
            .index_of(Output::DriveForce)
            .map_or(0.0, |c| max_abs(&[c], &all)),
        peak_contact_force_n: max_abs(&forces, &all),
        peak_foot_stress_pa: Some(traj.columns_where(|o| matches!(o, Output::Stress { .. })))
            .filter(|c| !c.is_empty())
            .map(|c| max_abs(&c, &all)),
        switches_after_arrival: switches,
        residual_m: traj
            .rows
            .iter()
            .filter(|r| r[0] >= move_time)
            .map(|r| (r[tip] - rest).abs())
            .fold(0.0, f64::max),
    }
}
