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
    /// Cycle time minus move time (s, never negative); `None` when the load does not settle
    /// in the run.
    pub settling_time_s: Option<f64>,
    /// From the start until the setpoint has arrived, `tip_rel` stays within the tolerance
    /// of its final rest and the vehicle within 1 mm of its target (s): a drive's "in
    /// position"; `None` when that does not happen in the run.
    pub cycle_time_s: Option<f64>,
    /// The same with the tolerance less the plan's margin (s): what the pick ranks on.
    pub pick_cycle_time_s: Option<f64>,
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
/// with the `tolerance` and the pick's tolerance (m) on `tip_rel`
/// ([`super::PlanOptions::pick_tolerance`]) and the contact `law` of its scene.
pub fn cycle_metrics(
    traj: &Trajectory,
    (target, move_time): (f64, f64),
    (tolerance, pick_tolerance): (f64, f64),
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
    let cycle_within = |tolerance: f64| {
        let outside = |r: &Vec<f64>| {
            (r[tip] - rest).abs() > tolerance || (r[vehicle] - target).abs() > VEHICLE_TOLERANCE_M
        };
        let inside_from = match traj.rows.iter().rposition(outside) {
            None => traj.rows.first().map(|r| r[0]),
            // still outside in the rest window: the run never settles
            Some(i) if traj.rows[i][0] >= end - REST_WINDOW_S => None,
            Some(i) => traj.rows.get(i + 1).map(|r| r[0]),
        };
        // in position only once the setpoint has arrived
        inside_from.map(|t| t.max(move_time))
    };
    let cycle = cycle_within(tolerance);
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
        settling_time_s: cycle.map(|c| c - move_time),
        cycle_time_s: cycle,
        pick_cycle_time_s: cycle_within(pick_tolerance),
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

/// On how many of the plants of `metrics` the load settles within the pick's tolerance.
pub fn settled(metrics: &[CycleMetrics]) -> usize {
    metrics
        .iter()
        .filter(|m| m.pick_cycle_time_s.is_some())
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run::Column;
    use telescopic_runtime::RunStats;

    /// A run of 5 s at 1 ms: the vehicle at its target 1 m from 0.9 s on, `tip_rel` a 1 Hz
    /// swing of `amplitude` (m) until 3 s, then at rest at 0.
    fn run(amplitude: f64) -> Trajectory {
        run_until(amplitude, 3.0)
    }

    /// As [`run`], the swing lasting until `until` (s; beyond 5 s it never stops).
    fn run_until(amplitude: f64, until: f64) -> Trajectory {
        let rows = (0..=5000)
            .map(|k| {
                let t = k as f64 * 1e-3;
                let vehicle = if t >= 0.9 { 1.0 } else { t / 0.9 };
                let tip = if t < until {
                    amplitude * (2.0 * std::f64::consts::PI * t).sin()
                } else {
                    0.0
                };
                vec![t, vehicle, tip]
            })
            .collect();
        let columns = vec![
            Column::Output(Output::Vehicle),
            Column::Output(Output::TipRel),
        ];
        Trajectory::new(columns, rows, RunStats::default())
    }

    const LAW: ContactLaw = ContactLaw {
        stiffness: 1e6,
        damping: 1e3,
        clearance: 0.0,
    };

    #[test]
    fn the_cycle_waits_for_the_setpoint_and_the_pick_keeps_its_margin() {
        // 4.9 mm of swing against 5 mm: in position when the setpoint arrives at 1 s, not
        // before (the vehicle is there at 0.9 s), and the pick's 4 mm only after the swing
        let close = cycle_metrics(&run(0.0049), (1.0, 1.0), (0.005, 0.004), &LAW);
        assert_eq!(close.cycle_time_s, Some(1.0));
        assert_eq!(close.settling_time_s, Some(0.0));
        let pick = close.pick_cycle_time_s.unwrap();
        assert!((2.75..=3.001).contains(&pick), "{pick}");
        // 2.1 mm: in position at 1 s within either tolerance
        let still = cycle_metrics(&run(0.0021), (1.0, 1.0), (0.005, 0.004), &LAW);
        assert_eq!(still.pick_cycle_time_s, Some(1.0));
        // a swing that arrives late settles after the move: settle is the difference
        let late = cycle_metrics(&run(0.0049), (1.0, 1.0), (0.003, 0.002), &LAW);
        let cycle = late.cycle_time_s.unwrap();
        assert!(cycle > 2.5 && (late.settling_time_s.unwrap() - (cycle - 1.0)).abs() < 1e-12);
    }

    #[test]
    fn the_objective_prefers_the_plan_with_its_margin_to_one_just_inside_the_tolerance() {
        let penalty = (5.0, 0.004);
        let close = [cycle_metrics(
            &run(0.0049),
            (1.0, 1.0),
            (0.005, 0.004),
            &LAW,
        )];
        let still = [cycle_metrics(
            &run(0.0021),
            (1.0, 1.02),
            (0.005, 0.004),
            &LAW,
        )];
        // the close one is in position first at the tolerance, the still one wins the pick
        assert!(close[0].cycle_time_s < still[0].cycle_time_s);
        let (c, s) = (
            super::super::planner::objective(&close, penalty),
            super::super::planner::objective(&still, penalty),
        );
        assert!(s < c, "still {s} against close {c}");
    }

    #[test]
    fn the_best_settles_on_the_most_plants_before_it_has_the_smallest_residual() {
        let penalty = (5.0, 0.004);
        let metrics = |amplitude: f64, until: f64| {
            cycle_metrics(
                &run_until(amplitude, until),
                (1.0, 1.0),
                (0.005, 0.004),
                &LAW,
            )
        };
        // settles on one plant of two and swings 0.5 m on the other
        let half = [metrics(0.0021, 3.0), metrics(0.5, 9.0)];
        // settles on neither, a 10 mm swing on both: the smaller worst penalized cycle
        let neither = [metrics(0.01, 9.0), metrics(0.01, 9.0)];
        assert!(neither[0].pick_cycle_time_s.is_none() && half[0].pick_cycle_time_s.is_some());
        let objective = super::super::planner::objective;
        assert!(objective(&neither, penalty) < objective(&half, penalty));
        let ranking = super::super::planner::ranking;
        assert_eq!(ranking(&half, &neither, penalty), std::cmp::Ordering::Less);
        assert_eq!(
            ranking(&neither, &half, penalty),
            std::cmp::Ordering::Greater
        );
        // as many settled: the smaller worst penalized cycle
        let better = [metrics(0.0021, 3.0), metrics(0.2, 9.0)];
        assert_eq!(ranking(&better, &half, penalty), std::cmp::Ordering::Less);
    }
}
