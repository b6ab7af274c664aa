//! A plan's shaper as a C99 setpoint filter for a machine's controller: raw setpoint in,
//! shaped setpoint out, the period scheduled on the measured telescopic position. One header
//! and one source, fixed-size arrays (a ring of the raw setpoint's recent ticks), no
//! allocation, nothing beyond `math.h`.
//!
//! The filter computes `sum_i A_i raw(t - m_i P)` as the library's `kind = "shaped"` profile
//! does. A delayed time falls between ticks, so the raw setpoint there is rebuilt from the
//! ticks around it: each tick brings the raw setpoint's position, velocity, acceleration and
//! jerk, and between two ticks a jerk-limited setpoint is the cubic of its constant jerk, from
//! the tick before or, past a jerk switch inside the tick (found from the two accelerations),
//! back from the tick after. That is exact for the S-curve as long as no phase is shorter
//! than a tick: the filter then gives the library's profile to rounding.

use super::candidates::Candidate;
use super::outcome::MovePlan;
use crate::control::emit::common::{list, lit};
use crate::io::comment::comment_text;
use crate::{Error, OptionName, Result};
use std::fmt::Write as _;
use std::path::Path;
use telescopic_runtime::{PositionSchedule, Profile, Scene, ShapedProfile, ShapedSetpoint};

/// The emitted filter's default tick rate (Hz).
pub const DEFAULT_FILTER_RATE_HZ: f64 = 1000.0;

/// The file names written by [`write_filter_c`].
pub const FILTER_FILES: [&str; 2] = ["telescopic_setpoint.h", "telescopic_setpoint.c"];

/// The fixed functions of every filter.
const FILTER_FUNCTIONS: &str = include_str!("c/setpoint_filter.c");

/// The shaped setpoint of `candidate` and its period as a position schedule (a fixed
/// period is one knot); the telescopic position of `scene` it follows (`a_k`; empty for a
/// fixed period).
fn shaped_parts<'c>(
    scene: &Scene,
    candidate: &'c Candidate,
) -> Result<(&'c ShapedSetpoint, PositionSchedule, String)> {
    let Profile::Shaped(ShapedProfile::Shaped(shaped)) = &candidate.profile else {
        return Err(Error::option(
            OptionName::EmitC,
            format!(
                "candidate {} has no shaper to emit: it is the setpoint a drive makes from its \
                 limits (the written scene's drive.motion); --pick a shaper to have a filter",
                candidate.name
            ),
        ));
    };
    let (schedule, section) = match shaped.period.as_ref() {
        Profile::Constant(p) => (
            PositionSchedule {
                position: Box::new(Profile::Constant(0.0)),
                positions: vec![0.0],
                values: vec![*p],
                stretch: [1.0, 1.0],
                over: [0.0, 0.0],
            },
            String::new(),
        ),
        Profile::Shaped(ShapedProfile::PositionSchedule(s)) => {
            let k = scene
                .params
                .positions
                .iter()
                .position(|p| p == s.position.as_ref())
                .map_or("the scheduled position".to_string(), |k| {
                    format!("a_{}", k + 2)
                });
            (s.clone(), k)
        }
        _ => {
            return Err(Error::option(
                OptionName::EmitC,
                "the emitted filter schedules its period on a telescopic position; this \
                 candidate's period is another profile",
            ));
        }
    };
    Ok((shaped, schedule, section))
}

/// The header and the source of `candidate`'s setpoint filter (a move of `scene`), ticking at
/// `rate_hz`.
///
/// ```no_run
/// # use telescopic::plan::{MoveLimits, PlanOptions, plan_move, emit::emit_filter_c};
/// # let scene = telescopic::Scene::load("scenes/case-study.toml".as_ref(), &[])?;
/// # let plan = plan_move(&scene, &PlanOptions::new(MoveLimits { distance: 23.0, v_max: 2.5, a_max: 0.7, j_max: 2.0 }), &telescopic::Silent)?;
/// let (header, source) = emit_filter_c(&plan.scene, &plan.candidates[plan.best], 1000.0)?;
/// # Ok::<(), telescopic::Error>(())
/// ```
///
/// # Errors
/// [`Error::Option`] for a candidate without a shaper, a rate outside 1 Hz to 1 MHz, or a
/// state above [`MAX_FILTER_STATE_BYTES`].
pub fn emit_filter_c(
    scene: &Scene,
    candidate: &Candidate,
    rate_hz: f64,
) -> Result<(String, String)> {
    check_filter_rate(rate_hz)?;
    let (shaped, schedule, section) = shaped_parts(scene, candidate)?;
    let period = 1.0 / rate_hz;
    let longest_multiple = shaped.impulses.iter().map(|p| p[1]).fold(0.0, f64::max);
    let longest_period = schedule.values.iter().copied().fold(0.0, f64::max)
        * schedule.stretch[0].max(schedule.stretch[1]);
    // the ring covers the longest delay and two ticks around it
    let delay_s = longest_multiple * longest_period;
    let history = (delay_s / period).ceil().min(1e12) as usize + 3;
    if state_bytes(history) > MAX_FILTER_STATE_BYTES {
        let top = (MAX_FILTER_STATE_BYTES / SAMPLE_BYTES - 4) as f64 / delay_s;
        return Err(Error::option(
            OptionName::FilterRate,
            format!(
                "at {rate_hz} Hz the filter keeps {history} ticks of its {delay_s:.2} s delay, \
                 {} bytes, at most {MAX_FILTER_STATE_BYTES}: give a rate of at most {top:.0} Hz",
                state_bytes(history)
            ),
        ));
    }
    let spacing = if section.is_empty() {
        "a fixed period".to_string()
    } else {
        format!("the period scheduled on {section}")
    };
    let banner = format!(
        "/* Generated by telescopic {} from the plan of scene `{}`: the setpoint filter of\n \
         * candidate `{}`, {} impulses, {spacing}, at {rate_hz} Hz.\n \
         * Do not edit: plan again and emit it anew. */\n",
        env!("CARGO_PKG_VERSION"),
        comment_text(&scene.name),
        comment_text(&candidate.name),
        shaped.impulses.len()
    );
    let header = header(&banner, history, &section);
    let mut s = banner.clone();
    s.push_str("#include \"telescopic_setpoint.h\"\n#include <math.h>\n\n");
    let _ = writeln!(s, "#define TS_IMPULSES {}", shaped.impulses.len());
    let _ = writeln!(s, "#define TS_KNOTS {}\n", schedule.positions.len());
    append_tables(&mut s, shaped, &schedule, period);
    s.push_str(FILTER_FUNCTIONS);
    Ok((header, s))
}

/// The filter's constants: the tick, the impulses, the period's knots and its stretch.
fn append_tables(
    s: &mut String,
    shaped: &ShapedSetpoint,
    schedule: &PositionSchedule,
    period: f64,
) {
    let tables = [
        ("TS_PERIOD", "the tick (s)", vec![period], false),
        (
            "TS_AMPLITUDES",
            "each impulse's amplitude",
            shaped.impulses.iter().map(|p| p[0]).collect(),
            true,
        ),
        (
            "TS_MULTIPLES",
            "each impulse's time, in periods",
            shaped.impulses.iter().map(|p| p[1]).collect(),
            true,
        ),
        (
            "TS_KNOT_POSITIONS",
            "the period's knots: telescopic positions (m)",
            schedule.positions.clone(),
            true,
        ),
        (
            "TS_KNOT_PERIODS",
            "and the first mode's period there (s)",
            schedule.values.clone(),
            true,
        ),
        (
            "TS_STRETCH",
            "the period's factor before and after the span TS_OVER",
            schedule.stretch.to_vec(),
            true,
        ),
        (
            "TS_OVER",
            "the span (s) over which the factor changes",
            schedule.over.to_vec(),
            true,
        ),
    ];
    for (name, what, values, array) in tables {
        let _ = writeln!(s, "/* {what} */");
        if array {
            let _ = writeln!(
                s,
                "static const double {name}[] = {};",
                list(values, "    ")
            );
        } else {
            let _ = writeln!(s, "static const double {name} = {};", lit(values[0]));
        }
    }
}

/// The filter's header: its memory and its two entry points; `section` names the scheduled
/// position (empty for a fixed period).
fn header(banner: &str, history: usize, section: &str) -> String {
    let bytes = state_bytes(history);
    let position = if section.is_empty() {
        "unused: the period is fixed".to_string()
    } else {
        format!("the measured telescopic position {section} (m)")
    };
    format!(
        "{banner}#ifndef TELESCOPIC_SETPOINT_H\n#define TELESCOPIC_SETPOINT_H\n\n\
         #define TS_HISTORY {history} /* ticks of raw setpoint kept: the longest delay and two */\n\n\
         /* One tick of the raw setpoint: time (s), position (m), velocity (m/s), acceleration\n \
         * (m/s^2) and the jerk (m/s^3) it holds from this tick on. */\n\
         typedef struct {{\n    double t, p, v, a, j;\n}} ts_sample;\n\n\
         /* The filter's memory: the recent raw setpoint and the last output. */\n\
         typedef struct {{\n    ts_sample history[TS_HISTORY];\n    long count;\n    long newest;\n\
         \x20   double shaped;          /* m */\n\
         \x20   unsigned long rejected; /* ticks refused: inputs not finite, or too early */\n\
         }} ts_state;\n\n\
         /* A ts_state takes about {bytes} bytes: declare it static (or allocate it once), not\n \
         * as a local variable of a task whose stack is small. */\n\n\
         /* Starts the filter with no history: start it at the latest when the move starts. */\n\
         void ts_init(ts_state *s);\n\n\
         /* One tick at time t (s): raw = the raw setpoint's position, velocity, acceleration\n \
         * and jerk at t; position = {position}.\n \
         * Returns the shaped setpoint (m). A tick is rejected when an input is not finite or\n \
         * when t is less than half a tick after the last accepted tick's (a repeated tick, a\n \
         * clock that went back): the last output is returned again and s->rejected counts\n \
         * it. After a rejection keep calling on every tick as before: the next tick with\n \
         * finite inputs at least half a tick on is taken, so skipped, late and jittered\n \
         * ticks cost nothing but the samples they miss. A clock that restarts from an earlier\n \
         * time is refused until it passes the last accepted one: call ts_init after a\n \
         * restart, with the machine at rest. */\n\
         double ts_step(ts_state *s, double t, const double raw[4], double position);\n\n\
         #endif\n"
    )
}

/// Bytes of one raw-setpoint sample in the filter's memory (five doubles).
const SAMPLE_BYTES: usize = 40;

/// Most memory a filter's state may take (bytes): a controller's RAM is small.
pub const MAX_FILTER_STATE_BYTES: usize = 16 << 20;

/// The size of a `ts_state` holding `history` samples (bytes).
fn state_bytes(history: usize) -> usize {
    history * SAMPLE_BYTES + 32
}

/// Checks a filter's rate (Hz) before any work: 1 Hz to 1 MHz.
///
/// # Errors
/// [`Error::Option`] naming the rate.
pub fn check_filter_rate(rate_hz: f64) -> Result<()> {
    if rate_hz.is_finite() && (1.0..=1e6).contains(&rate_hz) {
        return Ok(());
    }
    Err(Error::option(
        OptionName::FilterRate,
        format!("the filter's rate must be 1 to 1e6 Hz (got {rate_hz})"),
    ))
}

/// Writes `candidate`'s filter into the directory `dir` (each file whole or not at all).
///
/// # Errors
/// As [`emit_filter_c`]; [`Error::Write`] naming a file that cannot be written.
pub fn write_filter_c(
    scene: &Scene,
    candidate: &Candidate,
    rate_hz: f64,
    dir: &Path,
) -> Result<()> {
    let (header, source) = emit_filter_c(scene, candidate, rate_hz)?;
    crate::io::output::write_files_atomically(dir, &FILTER_FILES, [header, source])
}

/// Writes what a machine runs of candidate `i` of `plan` into `dir`: its shaper as the
/// setpoint filter at `rate_hz` ([`write_filter_c`]) and, when it uses the plan's velocity
/// feedback, the feedback law
/// ([`crate::control::emit::velocity::write_velocity_c`]). Returns a line per pair of files
/// written.
///
/// # Errors
/// [`Error::Option`] for a candidate with neither (the S-curve, the matched S-curve: a
/// drive makes those from its limits), or as [`write_filter_c`].
pub fn write_plan_c(plan: &MovePlan, i: usize, rate_hz: f64, dir: &Path) -> Result<Vec<String>> {
    let candidate = &plan.candidates[i];
    let shaped = matches!(candidate.profile, Profile::Shaped(ShapedProfile::Shaped(_)));
    let feedback = plan.feedback.as_ref().filter(|_| candidate.feedback);
    let mut written = Vec::new();
    if shaped || feedback.is_none() {
        write_filter_c(&plan.scene, candidate, rate_hz, dir)?;
        written.push(format!(
            "{}: {}'s setpoint filter at {rate_hz} Hz",
            FILTER_FILES.join(", "),
            candidate.name
        ));
    }
    if let Some(law) = feedback {
        crate::control::emit::velocity::write_velocity_c(law, dir)?;
        written.push(format!(
            "{}: its velocity feedback law at {} Hz",
            crate::control::emit::velocity::FEEDBACK_FILES.join(", "),
            law.rate_hz
        ));
    }
    Ok(written)
}
