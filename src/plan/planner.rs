//! The planner: the first mode along the move, the candidates on every evaluated plant, the
//! optimized shaper, the best plan on the plants it did not see, and the plan as a scene.

use super::candidates::{self, Candidate, MATCHED_NAME};
use super::metrics::{CycleMetrics, cycle_metrics, settled};
use super::moving::moving_scene;
use super::optimize::nelder_mead;
use super::options::PlanOptions;
use super::outcome::{MovePlan, PlanRow};
use super::price::{
    MATCHED_BUDGET, OPTIMIZER_BUDGET, PlanPrice, SCHEDULE_PAST_ARRIVAL_S, SCHEDULE_STEP_S,
};
use super::robust::{Plant, RobustRange, checking_plants, evaluated_plants, plant_scene};
use super::shapers::Shaper;
use crate::analysis::modes::{ModesOptions, compute_modes};
use crate::control::{
    closed_loop::velocity::simulate_velocity,
    design::velocity::{VelocityDesign, design_velocity_feedback},
    file::velocity::VelocityFeedback,
};
use crate::report::{Reporter, StopOnly};
use crate::run::simulate_scene;
use crate::{Error, OptionName, Result};
use rayon::prelude::*;
use telescopic_runtime::{PositionSchedule, Profile, SCurve, Scene, ShapedProfile};

/// The range of the stretches of the spacing the optimizer tries (at the start and at the
/// end of the move).
const STRETCH_RANGE: (f64, f64) = (0.7, 1.3);

/// The range of the stretches of the matched move's acceleration and deceleration boxes
/// the optimizer tries.
const MATCHED_STRETCH_RANGE: (f64, f64) = (0.85, 1.15);

/// Points per stretch of the grid the matched move's optimizer starts from.
const MATCHED_GRID: usize = 5;

/// The loads a robust plan's feedback is scheduled on, evenly over the set's `masses.load`:
/// the first mode's frequency goes about as one over the root of the moving mass, and on
/// case-study five tables over 10 to 30 kg, interpolated linearly, miss the design's `f_1`
/// and `c` midway between two tables by at most 0.93 % (against tables designed there).
const LOAD_TABLES: usize = 5;

/// The first mode's period (s) along the move, with the vehicle held, scheduled on the
/// moving telescopic position (a monotone cubic through its values at the positions reached
/// every 0.25 s; a number when no position moves), and its value at `arrival`
/// (s). With one moving position the period is a function of it; with several, the first
/// one's schedule is exact only along the scene's own motion.
pub fn first_period(
    held: &Scene,
    arrival: f64,
    end: f64,
    reporter: &dyn Reporter,
) -> Result<(Profile, f64)> {
    let start = held.time.start;
    let steps = ((end - start) / SCHEDULE_STEP_S).ceil() as usize;
    let period_at = |t: f64| -> Result<f64> {
        stop_point(reporter, "in the first mode's schedule")?;
        let options = ModesOptions {
            at: Some(t.min(held.time.end)),
            count: Some(1),
            ..ModesOptions::default()
        };
        let report = compute_modes(held, &options)?;
        let f = report.frequencies_hz.first().copied().ok_or_else(|| {
            Error::input(
                format!("scene {}", held.name),
                "has no vibration mode to shape",
            )
        })?;
        Ok(1.0 / f)
    };
    let at_arrival = period_at(arrival)?;
    let Some(position) = held.params.positions.iter().find(|p| !p.is_constant()) else {
        return Ok((Profile::Constant(at_arrival), at_arrival));
    };
    let mut knots: Vec<(f64, f64)> = (0..=steps)
        .map(|i| (start + i as f64 * SCHEDULE_STEP_S).min(end))
        .map(|t| Ok((position.value(t), period_at(t)?)))
        .collect::<Result<_>>()?;
    knots.sort_by(|a, b| a.0.total_cmp(&b.0));
    knots.dedup_by(|b, a| b.0 - a.0 <= 1e-9 * a.0.abs().max(1.0));
    let schedule = Profile::Shaped(ShapedProfile::PositionSchedule(PositionSchedule {
        position: Box::new(position.clone()),
        positions: knots.iter().map(|k| k.0).collect(),
        values: knots.iter().map(|k| k.1).collect(),
        stretch: [1.0, 1.0],
        over: [start, start],
    }));
    Ok((schedule, at_arrival))
}

/// The figures of `candidate` on each of `plants` (in parallel), with `feedback` if the
/// candidate uses it.
pub fn evaluate(
    scene: &Scene,
    (candidate, feedback): (&Candidate, Option<&VelocityFeedback>),
    plants: &[Plant],
    options: &PlanOptions,
    end: f64,
    reporter: &dyn Reporter,
) -> Result<Vec<CycleMetrics>> {
    // built once; each plant patches it with its values
    let moving = moving_scene(scene, &candidate.profile, end)?;
    let target = options.limits.distance;
    let simulation = crate::run::SimulationOptions {
        error_estimate: false,
        ..options.simulation.clone()
    };
    plants
        .par_iter()
        .map(|plant| {
            stop_point(reporter, &format!("evaluating {}", candidate.name))?;
            let quiet = StopOnly(reporter);
            let s = plant_scene(&moving, plant)?;
            let trajectory = match (candidate.feedback, feedback) {
                (false, _) => simulate_scene(&s, &simulation, &quiet)?.trajectory,
                (true, Some(f)) => {
                    simulate_velocity(&s, f, &simulation, &quiet)?
                        .simulation
                        .trajectory
                }
                (true, None) => {
                    return Err(Error::Analysis(format!(
                        "candidate {} uses feedback, but the plan designed none",
                        candidate.name
                    )));
                }
            };
            Ok(cycle_metrics(
                &trajectory,
                (target, candidate.arrival_s),
                (options.tolerance, options.pick_tolerance()),
                &s.params.contact,
            ))
        })
        .collect()
}

/// A point where a plan honours its caller's stop request.
///
/// # Errors
/// [`Error::Stopped`] naming where, once the caller asked.
fn stop_point(reporter: &dyn Reporter, at: &str) -> Result<()> {
    if reporter.stop_requested() {
        return Err(Error::Stopped {
            what: format!("the plan, {at},"),
        });
    }
    Ok(())
}

/// What the planner minimizes: the worst cycle time within the pick's tolerance (s) of
/// `metrics`, where a plant that never settles within it counts as `end` (s) plus its
/// residual in pick tolerances, so that the optimizer sees how far it is from settling.
pub fn objective(metrics: &[CycleMetrics], (end, pick_tolerance): (f64, f64)) -> f64 {
    metrics
        .iter()
        .map(|m| {
            m.pick_cycle_time_s
                .unwrap_or(end + m.residual_m / pick_tolerance)
        })
        .fold(0.0, f64::max)
}

/// How two candidates rank for the best, by their `metrics` over the same plants: first the
/// one that settles within the pick's tolerance on more plants, then the smaller
/// [`objective`] (with `penalty`). `Less` when `a` is the better.
pub fn ranking(a: &[CycleMetrics], b: &[CycleMetrics], penalty: (f64, f64)) -> std::cmp::Ordering {
    settled(b)
        .cmp(&settled(a))
        .then(objective(a, penalty).total_cmp(&objective(b, penalty)))
}

/// What every candidate of a plan shares: the curve, the schedule, the plants and the span.
struct Setting<'a> {
    scene: &'a Scene,
    options: &'a PlanOptions,
    curve: SCurve,
    schedule: Profile,
    plants: Vec<Plant>,
    end: f64,
    /// The velocity feedback, designed on the nominal plant, if asked for.
    feedback: Option<VelocityFeedback>,
    /// The caller's: its stop request ends the plan at the next run or eigen analysis.
    reporter: &'a dyn Reporter,
}

impl Setting<'_> {
    /// Runs `candidate` (index `i`) on every evaluated plant: its rows.
    fn rows(&self, i: usize, candidate: &Candidate) -> Result<Vec<PlanRow>> {
        let metrics = evaluate(
            self.scene,
            (candidate, self.feedback.as_ref()),
            &self.plants,
            self.options,
            self.end,
            self.reporter,
        )?;
        Ok(self
            .plants
            .iter()
            .zip(metrics)
            .map(|(p, m)| PlanRow {
                candidate: i,
                plant: p.name.clone(),
                metrics: m,
            })
            .collect())
    }

    /// Runs each of `candidates` (indices from `first`) on every evaluated plant, the
    /// candidates side by side: their rows in the candidates' order (the same whichever
    /// finishes first); `finished` is called as each candidate's runs end.
    fn rows_of(
        &self,
        candidates: &[Candidate],
        first: usize,
        finished: &(dyn Fn() + Sync),
    ) -> Result<Vec<PlanRow>> {
        let per_candidate = candidates
            .par_iter()
            .enumerate()
            .map(|(k, c)| {
                let rows = self.rows(first + k, c);
                finished();
                rows
            })
            .collect::<Result<Vec<_>>>()?;
        Ok(per_candidate.into_iter().flatten().collect())
    }

    /// How a plant that never settles counts in the worst cycle time.
    fn penalty(&self) -> (f64, f64) {
        (self.end, self.options.pick_tolerance())
    }

    /// The worst penalized cycle (s) of `candidate` on the evaluated plants; infinite when
    /// it cannot be run.
    fn cost(&self, candidate: Option<&Candidate>) -> f64 {
        let Some(c) = candidate else {
            return f64::INFINITY;
        };
        evaluate(
            self.scene,
            (c, None),
            &self.plants,
            self.options,
            self.end,
            self.reporter,
        )
        .map(|m| objective(&m, self.penalty()))
        .unwrap_or(f64::INFINITY)
    }

    /// Nelder-Mead over `dims` parameters in `range` from 1 each, of the candidates `build`
    /// makes, within `budget` evaluations; the parameters found.
    fn search(
        &self,
        (dims, range): (usize, (f64, f64)),
        build: &dyn Fn(&[f64]) -> Option<Candidate>,
        budget: usize,
    ) -> Vec<f64> {
        let mut objective = |x: &[f64]| self.cost(build(x).as_ref());
        nelder_mead(&mut objective, &vec![1.0; dims], &vec![range; dims], budget).x
    }

    /// Nelder-Mead over the two stretches of `shaper`'s scheduled period (at the start and
    /// at the end of the move).
    fn optimized(&self, shaper: Shaper) -> Candidate {
        // a fixed period (no position moves) has one stretch
        let scheduled = self.is_scheduled();
        let dims = if scheduled { 2 } else { 1 };
        let stretches = |x: &[f64]| (x[0], x[dims - 1]);
        let build = |x: &[f64]| {
            let (early, late) = stretches(x);
            let period = (&self.schedule, early, late);
            Some(candidates::shaped(
                String::new(),
                &self.curve,
                shaper,
                period,
            ))
        };
        let found = self.search((dims, STRETCH_RANGE), &build, OPTIMIZER_BUDGET);
        let (early, late) = stretches(&found);
        let name = if scheduled {
            format!("optimized {shaper} scheduled x {early:.3}/{late:.3}")
        } else {
            format!("optimized {shaper} x {early:.3}")
        };
        candidates::shaped(name, &self.curve, shaper, (&self.schedule, early, late))
    }

    /// The stretches of the matched move's acceleration and deceleration that leave the
    /// least: a [`MATCHED_GRID`]-square grid over [`MATCHED_STRETCH_RANGE`] first, its runs
    /// side by side, then Nelder-Mead within a grid spacing of its best point for the rest
    /// of [`MATCHED_BUDGET`]. The residual's zero is sharp (a few thousandths of a stretch
    /// wide), so a simplex from the linear design's point finds it or not by the path that
    /// rounding sets; the grid finds its valley first. `None` when the limits leave no
    /// matched move.
    fn optimized_matched(&self) -> Option<Candidate> {
        let period = &self.schedule;
        let build = |x: &[f64]| candidates::matched("", &self.curve, period, (x[0], x[1]));
        build(&[1.0, 1.0])?;
        let cost = |x: &[f64]| self.cost(build(x).map(|m| m.candidate).as_ref());
        let (lo, hi) = MATCHED_STRETCH_RANGE;
        let spacing = (hi - lo) / (MATCHED_GRID - 1) as f64;
        let grid: Vec<[f64; 2]> = (0..MATCHED_GRID * MATCHED_GRID)
            .map(|k| {
                let at = |i: usize| lo + spacing * i as f64;
                [at(k / MATCHED_GRID), at(k % MATCHED_GRID)]
            })
            .collect();
        let values: Vec<f64> = grid.par_iter().map(|x| cost(x)).collect();
        // the first of equal values: the same pick whichever run ends first
        let best = (0..grid.len())
            .min_by(|&a, &b| values[a].total_cmp(&values[b]))
            .expect("the grid has points");
        let bounds = grid[best].map(|v| ((v - spacing).max(lo), (v + spacing).min(hi)));
        let budget = MATCHED_BUDGET - grid.len();
        let found = nelder_mead(&mut |x| cost(x), &grid[best], &bounds, budget);
        let x = if found.value < values[best] {
            found.x
        } else {
            grid[best].to_vec()
        };
        let found = build(&x)?;
        // named by what a drive is set to: its acceleration and braking limits (m/s^2)
        let [accelerate, brake] = found.accelerations;
        Some(Candidate {
            name: format!("optimized {MATCHED_NAME} a {accelerate:.3}/{brake:.3}"),
            ..found.candidate
        })
    }

    /// Whether the period follows a moving position (else it is fixed).
    fn is_scheduled(&self) -> bool {
        !matches!(self.schedule, Profile::Constant(_))
    }
}

/// The S-curve of `options` from the scene's start, its fixed period and schedule, and the
/// span of every run.
fn setting<'a>(
    scene: &'a Scene,
    options: &'a PlanOptions,
    reporter: &'a dyn Reporter,
) -> Result<(Setting<'a>, f64)> {
    let curve = options.limits.curve(scene.time.start);
    let arrival = curve.start + curve.phases().duration();
    // the schedule reaches past the longest shaper at the longest stretch
    let held = moving_scene(scene, &candidates::unshaped(&curve).profile, arrival + 30.0)?;
    let (schedule, period) =
        first_period(&held, arrival, arrival + SCHEDULE_PAST_ARRIVAL_S, reporter)?;
    let longest = arrival + 1.5 * STRETCH_RANGE.1 * period.max(max_value(&schedule));
    let end = longest + options.settle_s;
    let feedback = match &options.feedback {
        Some(design) => {
            let moving = moving_scene(scene, &candidates::unshaped(&curve).profile, end)?;
            let design = scheduled_on_load(design, &options.robust);
            Some(design_velocity_feedback(&moving, &design)?)
        }
        None => None,
    };
    let setting = Setting {
        scene,
        options,
        curve,
        schedule,
        plants: evaluated_plants(&options.robust),
        end,
        feedback,
        reporter,
    };
    Ok((setting, period))
}

/// `design` scheduled on the load over the robust set's range of `masses.load`, at
/// [`LOAD_TABLES`] loads evenly spaced, when the set has one and `design` names no loads.
fn scheduled_on_load(design: &VelocityDesign, robust: &[RobustRange]) -> VelocityDesign {
    let range = robust.iter().find(|r| r.key == "masses.load");
    match range {
        Some(r) if design.loads_kg.is_empty() => VelocityDesign {
            loads_kg: (0..LOAD_TABLES)
                .map(|k| r.low + (r.high - r.low) * k as f64 / (LOAD_TABLES - 1) as f64)
                .collect(),
            ..design.clone()
        },
        _ => design.clone(),
    }
}

/// The unshaped S-curve, then each shaper with the fixed `period` and, when a position
/// moves, scheduled; with, for each shaper, the index of the candidate the optimizer may
/// start from (the scheduled one, else the fixed one).
fn candidate_list(s: &Setting, period: f64) -> (Vec<Candidate>, Vec<(Shaper, usize)>) {
    let mut list = vec![candidates::unshaped(&s.curve)];
    if let Some(matched) = candidates::matched(MATCHED_NAME, &s.curve, &s.schedule, (1.0, 1.0)) {
        let ([k_accelerate, k_brake], [accelerate, brake]) =
            (matched.periods, matched.accelerations);
        s.reporter.note(&format!(
            "the {MATCHED_NAME} accelerates at {accelerate:.3} m/s^2 over {k_accelerate:.0} \
             periods of the first mode and brakes at {brake:.3} m/s^2 over {k_brake:.0}"
        ));
        list.push(matched.candidate);
    }
    let mut starts = Vec::with_capacity(Shaper::ALL.len());
    for shaper in Shaper::ALL {
        let fixed = (&Profile::Constant(period), 1.0, 1.0);
        list.push(candidates::shaped(
            shaper.to_string(),
            &s.curve,
            shaper,
            fixed,
        ));
        if s.is_scheduled() {
            let scheduled = (&s.schedule, 1.0, 1.0);
            let name = format!("{shaper} scheduled");
            list.push(candidates::shaped(name, &s.curve, shaper, scheduled));
        }
        starts.push((shaper, list.len() - 1));
    }
    (list, starts)
}

/// Every plant of the robust set, the checks included, a valid scene: refused before any
/// work, naming the plant and the rule (a load range reaching below zero).
fn check_robust_set(scene: &Scene, options: &PlanOptions) -> Result<()> {
    let (_, checks) = checking_plants(scene, &options.robust, options.checks);
    for plant in evaluated_plants(&options.robust).iter().chain(&checks) {
        plant_scene(scene, plant).map_err(|e| {
            Error::option(OptionName::Robust, format!("the {} plant: {e}", plant.name))
        })?;
    }
    Ok(())
}

/// The whole plan (see the module documentation).
pub fn plan(scene: &Scene, options: &PlanOptions, reporter: &dyn Reporter) -> Result<MovePlan> {
    options.check()?;
    if !options.simulation.stations.is_empty() && scene.section_moduli().is_none() {
        return Err(Error::option(
            OptionName::Stations,
            format!(
                "the table's peak stress needs the sections' moduli: scene {} gives neither \
                 sections.section_modulus nor sections.height",
                scene.name
            ),
        ));
    }
    let price = PlanPrice::of(scene, options);
    price.check()?;
    reporter.note(&format!("planning: {}", price.describe()));
    check_robust_set(scene, options)?;
    let (s, period) = setting(scene, options, reporter)?;
    let (mut list, starts) = candidate_list(&s, period);
    let steps = (list.len() + 2) as f64;
    reporter.note(&format!(
        "evaluating {} candidates on {} plants, side by side",
        list.len(),
        s.plants.len()
    ));
    let done = std::sync::atomic::AtomicUsize::new(0);
    let mut rows = s.rows_of(&list, 0, &|| {
        let finished = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        reporter.progress(finished as f64 / steps);
    })?;
    if options.optimize {
        // from the best scheduled shaper (the best fixed one when no position moves), ranked
        // as the best plan is
        let (shaper, _) = starts
            .iter()
            .copied()
            .min_by(|a, b| {
                ranking(
                    &MovePlan::metrics(&rows, a.1),
                    &MovePlan::metrics(&rows, b.1),
                    s.penalty(),
                )
            })
            .expect("there are shapers");
        reporter.note(&format!(
            "optimizing the shaper's spacing and the {MATCHED_NAME}'s acceleration and \
             braking, side by side"
        ));
        // two sequential searches: side by side they keep both cores busy on one plant
        let (shaped, matched) = rayon::join(|| s.optimized(shaper), || s.optimized_matched());
        for c in std::iter::once(shaped).chain(matched) {
            rows.extend(s.rows(list.len(), &c)?);
            list.push(c);
        }
    }
    if s.feedback.is_some() {
        // on top of the S-curve and of the best open-loop move
        let open = best_within_limit(&s, &rows, list.len())?;
        let mut with: Vec<Candidate> = vec![list[0].with_feedback()];
        if open != 0 {
            with.push(list[open].with_feedback());
        }
        let names: Vec<&str> = with.iter().map(|c| c.name.as_str()).collect();
        reporter.note(&format!("evaluating {}, side by side", names.join(" and ")));
        rows.extend(s.rows_of(&with, list.len(), &|| {})?);
        list.extend(with);
    }
    reporter.progress((steps - 1.0) / steps);
    let best = best_within_limit(&s, &rows, list.len())?;
    let (checked_on, checks) = checking_plants(scene, &options.robust, options.checks);
    let with = (&list[best], s.feedback.as_ref());
    let check_rows = evaluate(scene, with, &checks, options, s.end, reporter)?
        .into_iter()
        .zip(&checks)
        .map(|(m, p)| PlanRow {
            candidate: best,
            plant: p.name.clone(),
            metrics: m,
        })
        .collect();
    reporter.progress(1.0);
    let plants = s.plants.iter().chain(&checks).cloned().collect();
    Ok(MovePlan {
        scene: scene.clone(),
        rigid_limit_s: s.curve.phases().duration(),
        first_period_s: period,
        end_s: s.end,
        tolerance: (options.tolerance, options.margin),
        candidates: list,
        rows,
        checks: check_rows,
        checked_on,
        plants,
        best,
        feedback: s.feedback,
    })
}

/// Among the candidates whose drive reaction stays within the force limit on every plant,
/// the one that brings the load to rest on the most plants, and of those the one with the
/// shortest worst (penalized) cycle time: a plan that settles on 8 plants of 10 wins over one
/// that settles on none with a smaller worst residual.
fn best_within_limit(s: &Setting, rows: &[PlanRow], count: usize) -> Result<usize> {
    let within_limit = |i: usize| {
        s.options.force_limit.is_none_or(|limit| {
            rows.iter()
                .filter(|r| r.candidate == i)
                .all(|r| r.metrics.peak_drive_force_n <= limit)
        })
    };
    (0..count)
        .filter(|&i| within_limit(i))
        .min_by(|&a, &b| {
            ranking(
                &MovePlan::metrics(rows, a),
                &MovePlan::metrics(rows, b),
                s.penalty(),
            )
        })
        .ok_or_else(|| {
            Error::option(
                OptionName::ForceLimit,
                "every candidate's drive reaction exceeds the force limit: lower the \
                 acceleration or jerk limit",
            )
        })
}

/// The largest value of a schedule (its knots, at the larger stretch).
fn max_value(p: &Profile) -> f64 {
    match p {
        Profile::Shaped(ShapedProfile::PositionSchedule(s)) => {
            s.values.iter().copied().fold(0.0, f64::max) * s.stretch[0].max(s.stretch[1])
        }
        other => other.value(0.0),
    }
}
