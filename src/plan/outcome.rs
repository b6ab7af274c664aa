//! A finished plan: every candidate on every plant, the best, and its table and files.

use super::candidates;
use super::metrics::CycleMetrics;
use super::moving;
use super::options::PlanOptions;
use super::robust::{CheckPlants, NEIGHBOUR_SHARE, Plant, neighbour_values};
use super::shapers::Shaper;
use crate::control::file::velocity::VelocityFeedback;
use crate::{Error, OptionName, Result};
use std::fmt::Write as _;
use telescopic_runtime::Scene;

/// One candidate on one plant.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanRow {
    /// Index into [`MovePlan::candidates`].
    pub candidate: usize,
    /// The plant's name.
    pub plant: String,
    /// What the move achieved there.
    pub metrics: CycleMetrics,
}

/// A finished plan: every candidate on every plant, and the best.
#[derive(Debug, Clone, PartialEq)]
pub struct MovePlan {
    /// The scene planned for.
    pub scene: Scene,
    /// The time-optimal move of a rigid telescope (s): the S-curve's duration.
    pub rigid_limit_s: f64,
    /// The first mode's period at the target (s), vehicle held.
    pub first_period_s: f64,
    /// The end of every run (s).
    pub end_s: f64,
    /// The tolerance on `tip_rel` (m) and the share of it the pick keeps in reserve.
    pub tolerance: (f64, f64),
    /// The candidates, in the table's order.
    pub candidates: Vec<candidates::Candidate>,
    /// Each candidate on each evaluated plant.
    pub rows: Vec<PlanRow>,
    /// The best candidate on the plants it was not chosen on.
    pub checks: Vec<PlanRow>,
    /// What those plants are.
    pub checked_on: CheckPlants,
    /// Every plant of the table, the evaluated ones then the checks: its name and the scene
    /// values it sets (the nominal plant sets none).
    pub plants: Vec<Plant>,
    /// Index of the best candidate: within the force limit, the one that settles on the most
    /// plants, then the shortest worst penalized cycle.
    pub best: usize,
    /// The velocity feedback the candidates marked `feedback` run with, designed on the
    /// nominal plant.
    pub feedback: Option<VelocityFeedback>,
}

impl MovePlan {
    /// The worst cycle time (s) of candidate `i` over `rows`; `None` if a plant never settles.
    pub fn worst_cycle(rows: &[PlanRow], i: usize) -> Option<f64> {
        Self::worst_of(rows, i, |m| m.cycle_time_s)
    }

    /// The worst pick cycle time (s, [`CycleMetrics::pick_cycle_time_s`]) of candidate `i`
    /// over `rows`: what the best is ranked on; `None` if a plant never gets within.
    pub fn worst_pick(rows: &[PlanRow], i: usize) -> Option<f64> {
        Self::worst_of(rows, i, |m| m.pick_cycle_time_s)
    }

    /// The longest cycle (s) of candidate `i` over the plants of `rows` where it settles, and
    /// that plant (the first of equals); `None` where it settles on none.
    pub fn worst_settled(rows: &[PlanRow], i: usize) -> Option<(f64, &str)> {
        rows.iter()
            .filter(|r| r.candidate == i)
            .filter_map(|r| Some((r.metrics.cycle_time_s?, r.plant.as_str())))
            .fold(None, |worst, (cycle, plant)| match worst {
                Some((last, _)) if last >= cycle => worst,
                _ => Some((cycle, plant)),
            })
    }

    /// The metrics of candidate `i` in `rows`, plant by plant.
    pub fn metrics(rows: &[PlanRow], i: usize) -> Vec<CycleMetrics> {
        rows.iter()
            .filter(|r| r.candidate == i)
            .map(|r| r.metrics.clone())
            .collect()
    }

    /// The largest `time` (s) of candidate `i` over `rows`; `None` if one is `None`.
    fn worst_of(
        rows: &[PlanRow],
        i: usize,
        time: impl Fn(&CycleMetrics) -> Option<f64>,
    ) -> Option<f64> {
        rows.iter()
            .filter(|r| r.candidate == i)
            .map(|r| time(&r.metrics))
            .try_fold(0.0_f64, |w, c| c.map(|c| w.max(c)))
    }

    /// The best plan as a scene file (TOML): the scene with the setpoint as `drive.motion`
    /// and the span of the runs.
    pub fn scene_toml(&self) -> String {
        self.scene_toml_of(self.best)
    }

    /// Candidate `i`'s plan as a scene file (TOML).
    pub fn scene_toml_of(&self, i: usize) -> String {
        let chosen = &self.candidates[i];
        let mut file = moving::moving_file(&self.scene, &chosen.profile, self.end_s);
        file.description = format!("{}: planned move ({})", self.scene.name, chosen.name);
        file.to_toml()
    }

    /// The best plan's feedback file (JSON), when the best plan uses feedback: what
    /// `simulate PLAN.toml --controller PLAN.json` reads.
    pub fn feedback_json(&self) -> Option<String> {
        self.feedback_json_of(self.best)
    }

    /// Candidate `i`'s feedback file (JSON), when it uses feedback.
    pub fn feedback_json_of(&self, i: usize) -> Option<String> {
        self.candidates[i]
            .feedback
            .then_some(self.feedback.as_ref())
            .flatten()
            .map(VelocityFeedback::to_json)
    }

    /// The index of the candidate named `name`.
    ///
    /// # Errors
    /// [`Error::Option`] listing the names.
    pub fn candidate_named(&self, name: &str) -> Result<usize> {
        self.candidates
            .iter()
            .position(|c| c.name == name)
            .ok_or_else(|| {
                let names: Vec<&str> = self.candidates.iter().map(|c| c.name.as_str()).collect();
                Error::option(
                    OptionName::Pick,
                    format!(
                        "no candidate is named {name:?}; the candidates: {}",
                        names.join(", ")
                    ),
                )
            })
    }

    /// Checks, before planning, that `name` can name a candidate of a plan with `options`
    /// (the S-curve, a shaper, a scheduled shaper, an optimized one when the optimizer
    /// runs, each `+ feedback` when the feedback is evaluated), and, when `emit_c`, that it
    /// has a shaper or a feedback law to emit.
    ///
    /// # Errors
    /// [`Error::Option`] naming the pick (or `--emit-c`) and the names it may take.
    pub fn check_pick(name: &str, options: &PlanOptions, emit_c: bool) -> Result<()> {
        let (base, with_feedback) = match name.strip_suffix(" + feedback") {
            Some(base) => (base, true),
            None => (name, false),
        };
        let shaper_named = |n: &str| n.parse::<Shaper>().is_ok();
        let unshaped = base == "s-curve"
            || base == candidates::MATCHED_NAME
            || base.starts_with(&format!("optimized {}", candidates::MATCHED_NAME));
        let known = unshaped
            || shaper_named(base)
            || base.strip_suffix(" scheduled").is_some_and(shaper_named)
            || (options.optimize && base.starts_with("optimized "));
        if !known || (with_feedback && options.feedback.is_none()) {
            let mut forms = vec![
                "s-curve".to_string(),
                candidates::MATCHED_NAME.into(),
                "SHAPER".into(),
                "SHAPER scheduled".into(),
            ];
            if options.optimize {
                forms.push("optimized ... (as the table names it)".into());
            }
            if options.feedback.is_some() {
                forms.push("any of these + feedback".into());
            }
            return Err(Error::option(
                OptionName::Pick,
                format!(
                    "no candidate of this plan can be named {name:?}: the names are {}, with \
                     SHAPER one of {}",
                    forms.join(", "),
                    Shaper::ALL.map(|s| s.to_string()).join(", ")
                ),
            ));
        }
        if emit_c && unshaped && !with_feedback {
            return Err(Error::option(
                OptionName::EmitC,
                format!(
                    "the candidate {name:?} has no shaper to emit as a setpoint filter: it is \
                     the setpoint a drive makes from its limits (the written scene's \
                     drive.motion)"
                ),
            ));
        }
        Ok(())
    }

    /// The table: every candidate on every plant, the rigid limit, the best and its checks,
    /// and a legend that defines each column.
    pub fn table(&self) -> String {
        let mut out = String::new();
        let (tolerance, margin) = self.tolerance;
        let _ = writeln!(
            out,
            "rigid limit (time-optimal move of a rigid telescope): {:.2} s; first mode at the \
             target {:.3} Hz (vehicle held)",
            self.rigid_limit_s,
            1.0 / self.first_period_s
        );
        let _ = writeln!(
            out,
            "{:<52} {:<10} {:>7} {:>8} {:>7} {:>7} {:>8} {:>8} {:>8} {:>9} {:>10} {:>8}",
            "candidate",
            "plant",
            "move s",
            "settle s",
            "cycle s",
            "pick s",
            "tip mm",
            "resid mm",
            "drive N",
            "contact N",
            "stress MPa",
            "switches"
        );
        let cell = |v: Option<f64>, digits: usize| {
            v.map_or("never".to_string(), |v| format!("{v:.digits$}"))
        };
        for r in self.rows.iter().chain(&self.checks) {
            let m = &r.metrics;
            let _ = writeln!(
                out,
                "{:<52} {:<10} {:>7.2} {:>8} {:>7} {:>7} {:>8.1} {:>8.1} {:>8.0} {:>9.0} {:>10} \
                 {:>8}",
                self.candidates[r.candidate].name,
                r.plant,
                m.move_time_s,
                cell(m.settling_time_s, 2),
                cell(m.cycle_time_s, 2),
                cell(m.pick_cycle_time_s, 2),
                1e3 * m.peak_tip_move_m,
                1e3 * m.residual_m,
                m.peak_drive_force_n,
                m.peak_contact_force_n,
                m.peak_foot_stress_pa
                    .map_or("-".into(), |s| format!("{:.1}", s / 1e6)),
                m.switches_after_arrival
            );
        }
        out.push_str(&legend(tolerance, margin, self.end_s));
        out.push_str(&plant_legend(&self.plants));
        out.push_str(&self.best_line());
        if let Some(line) = self.checks_line() {
            let _ = writeln!(out, "{line}");
        }
        out
    }

    /// The `best:` line: the best candidate and its worst cycle over the evaluated plants
    /// (naming the plant), or on how many plants it settles and which it misses.
    fn best_line(&self) -> String {
        let (best, margin) = (&self.candidates[self.best], self.tolerance.1);
        let percent = |w: f64| 100.0 * (w / self.rigid_limit_s - 1.0);
        let worst = Self::worst_cycle(&self.rows, self.best);
        let pick = Self::worst_pick(&self.rows, self.best).map_or("never".into(), |p| {
            format!("{p:.2} s, {:+.1} %", percent(p))
        });
        let verdict = match worst {
            // every plant settles: the worst settled cycle is the worst cycle
            Some(w) => format!(
                "worst cycle over the evaluated plants {w:.2} s on {}, {:+.1} % of the rigid \
                 limit; worst pick {pick}",
                Self::worst_settled(&self.rows, self.best).map_or("-", |(_, plant)| plant),
                percent(w)
            ),
            None => {
                // the plants not within the pick's tolerance, as `metrics::settled` counts
                let rows: Vec<&PlanRow> = self
                    .rows
                    .iter()
                    .filter(|r| r.candidate == self.best)
                    .collect();
                let outside: Vec<&str> = rows
                    .iter()
                    .filter(|r| r.metrics.pick_cycle_time_s.is_none())
                    .map(|r| r.plant.as_str())
                    .collect();
                let (all, end) = (rows.len(), self.end_s);
                let settled = all - outside.len();
                if settled == 0 {
                    format!(
                        "the load settles on none of the {all} evaluated plants within \
                         {end:.1} s; the smallest worst residual"
                    )
                } else {
                    format!(
                        "the load settles on {settled} of the {all} evaluated plants within \
                         {end:.1} s (not on {}), the most of any candidate; of those that settle \
                         as many, the smallest worst residual",
                        outside.join(", ")
                    )
                }
            }
        };
        format!(
            "best: {} ({verdict}; picked on the pick column: the tolerance less its {:.0} % \
             margin)\n",
            best.name,
            100.0 * margin
        )
    }

    /// What the best did on the plants that check it: on how many it settles within the
    /// tolerance, and its worst cycle there; `None` without checks.
    fn checks_line(&self) -> Option<String> {
        if self.checks.is_empty() {
            return None;
        }
        let all = self.checks.len();
        let settled = self
            .checks
            .iter()
            .filter(|r| r.metrics.cycle_time_s.is_some())
            .count();
        let neighbours = self.checked_on == CheckPlants::Neighbours;
        let what = if neighbours {
            let words: Vec<&str> = neighbour_values(&self.scene)
                .into_iter()
                .map(|((_, _, word), _)| word)
                .collect();
            let moved = match words.split_last() {
                Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
                _ => words.concat(),
            };
            format!(
                "its {all} neighbours ({moved} each moved by {:.0} % alone)",
                100.0 * NEIGHBOUR_SHARE
            )
        } else {
            format!("the {all} check plants inside the box, not evaluated")
        };
        let verdict = match Self::worst_settled(&self.checks, self.best) {
            None => "it settles on none".to_string(),
            Some((worst, on)) if settled == all => {
                format!("it settles on all, the worst cycle {worst:.2} s on {on}")
            }
            Some((worst, on)) => {
                format!("it settles on {settled} (the worst cycle {worst:.2} s on {on})")
            }
        };
        let advice = if neighbours && settled < all {
            ": a plan that holds off its plant needs --robust"
        } else {
            ""
        };
        Some(format!("checks: on {what} {verdict}{advice}"))
    }
}

/// What each plant of [`MovePlan::table`] is: the scene values it sets, one line each.
fn plant_legend(plants: &[Plant]) -> String {
    let mut out = String::from("plants:\n");
    for plant in plants {
        let values: Vec<String> = plant
            .values
            .iter()
            .map(|(key, v)| format!("{key}={}", short_number(*v)))
            .collect();
        let set = if values.is_empty() {
            "the scene as given".to_string()
        } else {
            values.join(", ")
        };
        let _ = writeln!(out, "  {:<10} {set}", plant.name);
    }
    out
}

/// `v` to four significant digits, in exponent form when large or small (1.89e11, 0.0125).
fn short_number(v: f64) -> String {
    if v != 0.0 && !(1e-3..1e5).contains(&v.abs()) {
        let text = format!("{v:.3e}");
        let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, "0"));
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        format!("{mantissa}e{exponent}")
    } else {
        let digits = (3 - v.abs().log10().floor().max(-3.0) as i32).max(0) as usize;
        let text = format!("{v:.digits$}");
        if text.contains('.') {
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            text
        }
    }
}

/// What each column of [`MovePlan::table`] means, one line each, with the plan's
/// `tolerance` (m), its `margin` and the runs' `end` (s).
fn legend(tolerance: f64, margin: f64, end: f64) -> String {
    let vehicle_mm = 1e3 * super::metrics::VEHICLE_TOLERANCE_M;
    let lines = [
        ("move s", "when the setpoint reaches the target".to_string()),
        (
            "cycle s",
            format!(
                "from the start until the setpoint has arrived, tip_rel stays within {:.1} mm \
                 of its final rest and the vehicle within {vehicle_mm:.0} mm of its target (in \
                 position)",
                1e3 * tolerance
            ),
        ),
        ("settle s", "cycle - move".into()),
        (
            "pick s",
            format!(
                "the cycle within {:.1} mm, the tolerance less the {:.0} % margin: the best \
                 has the shortest worst pick",
                1e3 * super::options::pick_tolerance(tolerance, margin),
                100.0 * margin
            ),
        ),
        ("never", format!("not within the run ({end:.1} s)")),
        ("tip mm", "the peak |tip_rel| before arrival".into()),
        (
            "resid mm",
            "the largest |tip_rel - rest| after arrival".into(),
        ),
        (
            "drive N",
            "the peak drive reaction (correction included)".into(),
        ),
        ("contact N", "the peak contact force".into()),
        (
            "stress MPa",
            "the peak bending stress at the stations".into(),
        ),
        (
            "switches",
            "contact openings and closings after arrival: the rattling in the clearance".into(),
        ),
    ];
    let mut out = String::from("columns:\n");
    for (name, meaning) in lines {
        let _ = writeln!(out, "  {name:<10} {meaning}");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::short_number;

    #[test]
    fn plant_values_are_written_to_four_digits_in_the_form_a_key_takes() {
        let cases = [
            (1.89e11, "1.89e11"),
            (2.0466e11, "2.047e11"),
            (0.0125, "0.0125"),
            (0.005, "0.005"),
            (17.897, "17.9"),
            (10.0, "10"),
            (12345.6, "12346"),
            (-0.5, "-0.5"),
            (1e-4, "1e-4"),
            (0.0, "0"),
        ];
        for (value, written) in cases {
            assert_eq!(short_number(value), written, "{value}");
            // what is written reads back as a scene value within four digits
            let back: f64 = written.parse().unwrap();
            assert!((back - value).abs() <= 5e-4 * value.abs(), "{value}");
        }
    }
}
