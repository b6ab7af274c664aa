//! `telescopic plan` end to end: the scene it writes reproduces its table's row (cycle time
//! and peak foot stress) when `simulate` runs it, by this file's own reading of the CSV; bad
//! options are refused naming the flag.

mod common;

use common::{Csv, failed_cleanly, fails_with, scratch, succeeds, telescopic};

/// The nominal row of candidate `name` in `table`: its cells after the name.
fn nominal_row(table: &str, name: &str) -> Vec<String> {
    let row = table
        .lines()
        .find(|l| l.starts_with(&format!("{name:<52} nominal")))
        .unwrap_or_else(|| panic!("no nominal row for {name}:\n{table}"));
    row[52..].split_whitespace().map(str::to_string).collect()
}

/// This file's own reading of a run's cycle time (s): from the start until the setpoint has
/// arrived (`move_time`, s), `tip_rel` stays within `tolerance` of its mean over the last
/// second and the vehicle within 1 mm of `target`.
fn cycle_time(run: &Csv, (target, move_time): (f64, f64), tolerance: f64) -> f64 {
    let rows = &run.rows;
    let (tip, vehicle) = (run.column("tip_rel"), run.column("vehicle"));
    let end = rows.last().unwrap()[0];
    let window: Vec<f64> = rows
        .iter()
        .filter(|r| r[0] >= end - 1.0)
        .map(|r| r[tip])
        .collect();
    let rest = window.iter().sum::<f64>() / window.len() as f64;
    let last_outside = rows
        .iter()
        .rposition(|r| (r[tip] - rest).abs() > tolerance || (r[vehicle] - target).abs() > 1e-3)
        .unwrap();
    rows[last_outside + 1][0].max(move_time)
}

/// The flags of a 2 m move of adams-linear (rigid limit 3.2 s) planned without the optimizer.
const SHORT_MOVE: [&str; 14] = [
    "plan",
    "scenes/adams-linear.toml",
    "--distance",
    "2",
    "--v-max",
    "1",
    "--a-max",
    "1",
    "--j-max",
    "5",
    "--tolerance",
    "0.002",
    "--no-optimize",
    "--settle",
];

#[test]
fn the_written_plan_reproduces_its_cycle_time_under_simulate() {
    let dir = scratch("plan-reproduce");
    let plan = dir.join("plan.toml");
    let csv = dir.join("plan.csv");
    let flags = [
        "4",
        "--set",
        "sections.height=0.04",
        "--stations",
        "1:0",
        "--out",
        plan.to_str().unwrap(),
    ];
    let out = succeeds(&[&SHORT_MOVE[..], &flags].concat());
    let table = String::from_utf8_lossy(&out.stdout);
    // the rigid limit: 2 m at 1 m/s, 1 m/s^2, 5 m/s^3 takes 2/1 + 1/1 + 1/5 = 3.2 s
    assert!(table.contains("3.20 s"), "{table}");
    let best = table
        .lines()
        .find(|l| l.starts_with("best: "))
        .expect("the table names the best");
    let name = &best["best: ".len()..best.find(" (worst").unwrap()];
    let cells = nominal_row(&table, name);
    let move_time: f64 = cells[1].parse().expect("the move time");
    let reported: f64 = cells[3].parse().expect("the best settles");
    let settle: f64 = cells[2].parse().expect("the best settles");
    assert!(
        settle >= 0.0 && (reported - move_time - settle).abs() < 0.011,
        "cycle {reported} s, move {move_time} s, settle {settle} s"
    );
    let reported_stress: f64 = cells[9].parse().expect("the stress at the foot (MPa)");
    // the best line states what the best was ranked on: its pick, never before its cycle
    let pick: f64 = cells[4].parse().expect("the best gets within the margin");
    let stated = best
        .split("worst pick ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .expect("the best line names the worst pick");
    assert_eq!(stated, format!("{pick:.2}"), "{best}");
    assert!(pick >= reported, "{best}");
    succeeds(&[
        "simulate",
        plan.to_str().unwrap(),
        "--stations",
        "1:0",
        "--no-error-estimate",
        "--out",
        csv.to_str().unwrap(),
    ]);
    let run = Csv::read(&csv);
    let measured = cycle_time(&run, (2.0, move_time), 0.002);
    let stress = run.column("stress_1_0");
    let peak = run.rows.iter().map(|r| r[stress].abs()).fold(0.0, f64::max) / 1e6;
    assert!(
        (peak - reported_stress).abs() < 0.051,
        "the plan says {reported_stress} MPa at the foot, simulate gives {peak} MPa"
    );
    assert!(
        (measured - reported).abs() < 0.006,
        "the plan says {reported} s, simulate gives {measured} s"
    );
    assert!(
        measured >= 3.2 - 1e-3,
        "faster than the rigid limit: {measured}"
    );
}

/// The row of candidate `name` on `plant` in `table`: its cells after the name and plant.
fn row_on(table: &str, name: &str, plant: &str) -> Vec<String> {
    let row = table
        .lines()
        .find(|l| l.starts_with(&format!("{name:<52} {plant:<10}")))
        .unwrap_or_else(|| panic!("no {plant} row for {name}:\n{table}"));
    row[63..].split_whitespace().map(str::to_string).collect()
}

/// The table's `plants:` block: each plant's name and the scene values it sets, as written.
fn plant_legend(table: &str) -> std::collections::BTreeMap<String, String> {
    table
        .lines()
        .skip_while(|l| *l != "plants:")
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .map(|l| (l[2..12].trim().to_string(), l[13..].to_string()))
        .collect()
}

/// The value `key=...` that a plant's legend entry sets.
fn legend_value(entry: &str, key: &str) -> f64 {
    entry
        .split(", ")
        .find_map(|kv| kv.strip_prefix(key)?.strip_prefix('='))
        .unwrap_or_else(|| panic!("{key} in {entry}"))
        .parse()
        .unwrap()
}

#[test]
fn a_plan_without_a_robust_set_is_checked_on_its_neighbours_as_simulate_reproduces() {
    let dir = scratch("plan-neighbours");
    let (plan, csv) = (dir.join("plan.toml"), dir.join("neighbour.csv"));
    let out = succeeds(&[&SHORT_MOVE[..], &["4", "--out", plan.to_str().unwrap()]].concat());
    let table = String::from_utf8_lossy(&out.stdout);
    let best = table.lines().find(|l| l.starts_with("best: ")).unwrap();
    let name = &best["best: ".len()..best.find(" (").unwrap()];
    // adams-linear has no clearance: its load and E, each 1 % down and up
    let plants = ["load -1%", "load +1%", "E -1%", "E +1%"];
    let settled = plants
        .iter()
        .filter(|p| row_on(&table, name, p)[2] != "never")
        .count();
    let checks = table
        .lines()
        .find(|l| l.starts_with("checks: "))
        .expect("the table says how the best did on its checks");
    assert!(checks.contains("its 4 neighbours"), "{checks}");
    let count = if settled == 4 {
        "settles on all".to_string()
    } else {
        format!("settles on {settled}")
    };
    assert!(checks.contains(&count), "{checks}\n{table}");
    // it names the neighbour where the best is in position last, with that row's cycle
    let worst = plants
        .iter()
        .filter_map(|p| row_on(&table, name, p)[2].parse::<f64>().ok())
        .fold(f64::NEG_INFINITY, f64::max);
    if settled > 0 {
        let (cycle, rest) = checks["checks: ".len()..]
            .split_once("the worst cycle ")
            .and_then(|(_, rest)| rest.split_once(" s on "))
            .expect("the worst cycle and its plant");
        let plant = rest.split([')', ':']).next().unwrap();
        assert_eq!(row_on(&table, name, plant)[2], cycle, "{checks}");
        assert_eq!(format!("{worst:.2}"), cycle, "{checks}");
    }
    // the load 1 % up, by this file's own reading of the scene and of the run
    let text = std::fs::read_to_string("scenes/adams-linear.toml").unwrap();
    let scene: toml::Value = toml::from_str(&text).unwrap();
    let load = scene["masses"]["load"].as_float().unwrap() * 1.01;
    // the table says what each plant is, to four digits
    let legend = plant_legend(&table);
    assert_eq!(legend.len(), 5, "{table}");
    assert_eq!(legend["nominal"], "the scene as given");
    let written = legend_value(&legend["load +1%"], "masses.load");
    assert!((written / load - 1.0).abs() < 5e-4, "{written} for {load}");
    let modulus = scene["sections"]["youngs_modulus"].as_float().unwrap();
    let written = legend_value(&legend["E -1%"], "sections.youngs_modulus");
    assert!((written / (0.99 * modulus) - 1.0).abs() < 5e-4, "{written}");
    let cells = row_on(&table, name, "load +1%");
    let (move_time, reported): (f64, f64) = (cells[0].parse().unwrap(), cells[2].parse().unwrap());
    succeeds(&[
        "simulate",
        plan.to_str().unwrap(),
        "--set",
        &format!("masses.load={load:?}"),
        "--no-error-estimate",
        "--out",
        csv.to_str().unwrap(),
    ]);
    let measured = cycle_time(&Csv::read(&csv), (2.0, move_time), 0.002);
    assert!(
        (measured - reported).abs() < 0.006,
        "the table says {reported} s with the load 1 % up, simulate gives {measured} s"
    );
}

#[test]
fn the_matched_move_is_written_as_jerk_segments_that_simulate_reproduces() {
    let dir = scratch("plan-matched");
    let plan = dir.join("plan.toml");
    let csv = dir.join("plan.csv");
    let name = "matched s-curve";
    let flags = ["4", "--pick", name, "--out", plan.to_str().unwrap()];
    let out = succeeds(&[&SHORT_MOVE[..], &flags].concat());
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(
        said.contains("the matched s-curve accelerates at"),
        "{said}"
    );
    let table = String::from_utf8_lossy(&out.stdout);
    let cells = nominal_row(&table, name);
    let move_time: f64 = cells[1].parse().expect("the move time");
    let residual_mm: f64 = cells[6].parse().expect("the residual");
    let text = std::fs::read_to_string(&plan).unwrap();
    assert!(text.contains("kind = \"jerk-segments\""), "{text}");
    succeeds(&[
        "simulate",
        plan.to_str().unwrap(),
        "--no-error-estimate",
        "--out",
        csv.to_str().unwrap(),
    ]);
    let run = Csv::read(&csv);
    let (tip, vehicle) = (run.column("tip_rel"), run.column("vehicle"));
    // the setpoint arrives at the target when the table says, and not before
    let arrived = run
        .rows
        .iter()
        .find(|r| (r[vehicle] - 2.0).abs() < 1e-9)
        .map(|r| r[0])
        .expect("the vehicle reaches the target");
    assert!(
        (arrived - move_time).abs() < 0.011 && move_time >= 3.2 - 1e-9,
        "arrives at {arrived} s, the table says {move_time} s"
    );
    let rest = run.rows.last().unwrap()[tip];
    let measured = run
        .rows
        .iter()
        .filter(|r| r[0] >= move_time)
        .map(|r| (r[tip] - rest).abs())
        .fold(0.0, f64::max);
    assert!(
        (1e3 * measured - residual_mm).abs() < 0.051 + 0.02 * residual_mm,
        "the plan says {residual_mm} mm, simulate gives {} mm",
        1e3 * measured
    );
}

#[test]
fn a_plan_with_feedback_writes_its_file_and_simulate_reproduces_its_row() {
    let dir = scratch("plan-feedback");
    let plan = dir.join("plan.toml");
    let feedback = dir.join("plan.json");
    let csv = dir.join("plan.csv");
    let name = "s-curve + feedback";
    let flags = ["6", "--feedback", "0.2", "--pick", name, "--emit-c"];
    let emitted = [dir.to_str().unwrap(), "--out", plan.to_str().unwrap()];
    let out = succeeds(&[&SHORT_MOVE[..], &flags, &emitted].concat());
    // the S-curve has no shaper: the C is its feedback law alone
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(said.contains("its velocity feedback law at"), "{said}");
    let law = std::fs::read_to_string(dir.join("telescopic_feedback.c")).unwrap();
    assert!(law.contains("double tvf_step("), "{law}");
    assert!(!dir.join("telescopic_setpoint.c").exists(), "{said}");
    let table = String::from_utf8_lossy(&out.stdout);
    let cells = nominal_row(&table, name);
    let move_time: f64 = cells[1].parse().expect("the move time");
    let reported: f64 = cells[3].parse().expect("the plan with feedback settles");
    let text = std::fs::read_to_string(&feedback).expect("the feedback file beside the plan");
    assert!(text.contains("\"telescopic velocity feedback\""), "{text}");
    let out = succeeds(&[
        "simulate",
        plan.to_str().unwrap(),
        "--controller",
        feedback.to_str().unwrap(),
        "--no-error-estimate",
        "--out",
        csv.to_str().unwrap(),
    ]);
    let summary = String::from_utf8_lossy(&out.stderr);
    assert!(
        summary.contains("velocity feedback (zeta 0.20)"),
        "{summary}"
    );
    let measured = cycle_time(&Csv::read(&csv), (2.0, move_time), 0.002);
    assert!(
        (measured - reported).abs() < 0.006,
        "the plan says {reported} s, simulate --controller gives {measured} s"
    );
    // the animation reads the same file: the run with the feedback beside the one without
    let page = dir.join("plan.html");
    let out = succeeds(&[
        "animate",
        plan.to_str().unwrap(),
        "--controller",
        feedback.to_str().unwrap(),
        "--out",
        page.to_str().unwrap(),
    ]);
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(said.contains("wrote") && page.is_file(), "{said}");
    // planned again without feedback: the old feedback file does not stay beside the plan
    let out = succeeds(
        &[
            &SHORT_MOVE[..],
            &["6", "--pick", "zvd", "--out", plan.to_str().unwrap()],
        ]
        .concat(),
    );
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(said.contains("removed") && !feedback.exists(), "{said}");
}

#[test]
fn emit_c_writes_the_chosen_shaper_and_refuses_a_move_without_one() {
    let dir = scratch("plan-emit-c");
    let flags = ["4", "--pick", "zvd", "--emit-c", dir.to_str().unwrap()];
    succeeds(&[&SHORT_MOVE[..], &flags].concat());
    let source = std::fs::read_to_string(dir.join("telescopic_setpoint.c")).unwrap();
    assert!(source.contains("candidate `zvd`, 3 impulses"), "{source}");
    assert!(dir.join("telescopic_setpoint.h").is_file());
    let flags = ["4", "--pick", "s-curve", "--emit-c", dir.to_str().unwrap()];
    fails_with(
        &[&SHORT_MOVE[..], &flags].concat(),
        &["--emit-c", "\"s-curve\" has no shaper to emit"],
    );
}

/// Plan options refused before any work, and what the refusal names.
static REFUSED_PLAN_OPTIONS: &[(&[&str], &[&str])] = &[
    (
        &["--distance", "2", "--stations", "1:0"],
        &["--stations", "sections.section_modulus nor sections.height"],
    ),
    (
        &["--distance", "2", "--pick", "zw scheduled"],
        &[
            "--pick",
            "no candidate of this plan can be named \"zw scheduled\"",
            "zvd",
            "matched s-curve",
        ],
    ),
    (
        &["--distance", "2", "--pick", "zv + feedback"],
        &["--pick", "+ feedback"],
    ),
    (
        &["--distance", "2", "--pick", "s-curve", "--emit-c", "."],
        &["--emit-c", "no shaper to emit"],
    ),
    (
        &[
            "--distance",
            "2",
            "--pick",
            "matched s-curve",
            "--emit-c",
            ".",
        ],
        &["--emit-c", "\"matched s-curve\" has no shaper to emit"],
    ),
    (
        &[
            "--distance",
            "2",
            "--feedback",
            "0.2",
            "--correction-v-max",
            "1e9",
        ],
        &["--correction-v-max", "at most 1000"],
    ),
    (
        &["--distance", "2", "--robust", "masses.load=-10:30"],
        &["--robust", "plant", "masses.load"],
    ),
    (
        &[
            "--distance",
            "2",
            "--robust",
            "masses.load=10:30",
            "--checks",
            "1000000000",
        ],
        &["--checks", "at most 256"],
    ),
    (
        &["--distance", "23", "--v-max", "0.003"],
        &[
            "--v-max/--a-max/--j-max",
            "eigen analyses",
            "shorten the distance",
        ],
    ),
    (
        &[
            "--distance",
            "2",
            "--settle",
            "1000",
            "--robust",
            "masses.load=10:30,contact.clearance=0.005:0.02,gravity.g=9:10,\
             contact.stiffness=1e7:1e8,contact.damping=100:1000,masses.vehicle=10:20",
        ],
        &["--robust", "samples", "fewer robust ranges"],
    ),
    (
        &[
            "--distance",
            "2",
            "--feedback",
            "0.2",
            "--correction-v-max",
            "-1",
        ],
        &["--correction-v-max", "velocity bound must be > 0"],
    ),
    (
        &["--distance", "2", "--emit-c", "/nonexistent/dir"],
        &["--emit-c", "not an existing directory"],
    ),
    (
        &["--distance", "2", "--feedback", "0"],
        &["--feedback", "(0, 2]"],
    ),
    (
        &["--distance", "2", "--feedback", "0.2", "--out", "plan.json"],
        &["--out", "another extension"],
    ),
    (&["--distance", "0"], &["--distance", "not 0"]),
    (&["--distance", "2", "--v-max", "-1"], &["--v-max", "> 0"]),
    (&["--distance", "2", "--tolerance", "0"], &["--tolerance"]),
    (
        &["--distance", "2", "--margin", "0.95"],
        &["--margin", "share of the tolerance, 0 to 0.9"],
    ),
    (
        &["--distance", "2", "--robust", "masses.load=30:10"],
        &["--robust", "LOW must be below HIGH"],
    ),
    (
        &["--distance", "2", "--robust", "masses.load"],
        &["--robust", "KEY=LOW:HIGH"],
    ),
    (
        &["--distance", "2", "--robust", "nonsense.key=1:2"],
        &["nonsense"],
    ),
];

#[test]
fn bad_plan_options_are_refused_naming_the_flag() {
    for &(flags, needles) in REFUSED_PLAN_OPTIONS {
        let args = [&["plan", "scenes/adams-linear.toml"][..], flags].concat();
        let out = telescopic(&args);
        failed_cleanly(&args, &out, needles);
        // before any work: no candidate was evaluated
        let said = String::from_utf8_lossy(&out.stderr);
        assert!(
            !said.contains("evaluating"),
            "{args:?} refused only after work:\n{said}"
        );
    }
}

#[test]
fn emitted_c_never_overwrites_an_input_in_its_directory() {
    let dir = scratch("plan-emit-input");
    let scene = dir.join("telescopic_setpoint.c");
    std::fs::copy("scenes/adams-linear.toml", &scene).unwrap();
    let before = std::fs::read(&scene).unwrap();
    fails_with(
        &[
            "plan",
            scene.to_str().unwrap(),
            "--distance",
            "2",
            "--emit-c",
            dir.to_str().unwrap(),
        ],
        &["--emit-c", "is the input", "telescopic_setpoint.c"],
    );
    let controller = dir.join("telescopic_controller.h");
    std::fs::copy("scenes/case-study.toml", &controller).unwrap();
    fails_with(
        &[
            "design",
            controller.to_str().unwrap(),
            "--out",
            dir.join("c.json").to_str().unwrap(),
            "--sensors",
            "vehicle,kappa_1_0",
            "--emit-c",
            dir.to_str().unwrap(),
        ],
        &["--emit-c", "is the input"],
    );
    assert_eq!(std::fs::read(&scene).unwrap(), before);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A robust plan over a load range writes a law scheduled on the load; `simulate
/// --controller` tells it the scene's load, `--weighed-load` another: the scene's own load
/// given gives the same samples as none, another load other corrections, and a bad load or
/// a designed controller is refused naming the flag.
#[test]
fn simulate_tells_a_load_scheduled_feedback_the_weighed_load() {
    let dir = scratch("plan-weighed");
    let plan = dir.join("plan.toml");
    let feedback = dir.join("plan.json");
    let flags = [
        "4",
        "--robust",
        "masses.load=12:24",
        "--checks",
        "0",
        "--feedback",
        "0.2",
        "--pick",
        "s-curve + feedback",
        "--out",
        plan.to_str().unwrap(),
    ];
    let planned = succeeds(&[&SHORT_MOVE[..], &flags].concat());
    let text = std::fs::read_to_string(&feedback).unwrap();
    let file = telescopic::control::file::velocity::VelocityFeedback::from_json(&text).unwrap();
    assert_eq!(file.loads(), [12.0, 15.0, 18.0, 21.0, 24.0]);
    // the table names the plants the robust set was evaluated on: its ends and its middle
    let legend = plant_legend(&String::from_utf8_lossy(&planned.stdout));
    let loads: Vec<(&str, f64)> = ["corner 1", "corner 2", "centre"]
        .map(|p| (p, legend_value(&legend[p], "masses.load")))
        .to_vec();
    assert_eq!(
        loads,
        [("corner 1", 12.0), ("corner 2", 24.0), ("centre", 18.0)]
    );
    assert_eq!(legend.len(), 4, "{legend:?}");
    let run = |name: &str, extra: &[&str]| {
        let csv = dir.join(name);
        let (p, f, c) = (
            plan.to_str().unwrap(),
            feedback.to_str().unwrap(),
            csv.to_str().unwrap(),
        );
        let args = [
            &[
                "simulate",
                p,
                "--controller",
                f,
                "--no-error-estimate",
                "--out",
                c,
            ][..],
            extra,
        ];
        let out = succeeds(&args.concat());
        (
            std::fs::read(&csv).unwrap(),
            String::from_utf8_lossy(&out.stderr).to_string(),
        )
    };
    let (carried, said) = run("carried.csv", &[]);
    assert!(said.contains("scheduled on the load 12 to 24 kg"), "{said}");
    let (told_same, _) = run("same.csv", &["--weighed-load", "17.897"]);
    assert_eq!(
        carried, told_same,
        "the scene's load told: the same samples"
    );
    let (told_other, said) = run("other.csv", &["--weighed-load", "24"]);
    assert!(said.contains("told a load of 24 kg"), "{said}");
    assert_ne!(carried, told_other, "another load: other corrections");
    let p = plan.to_str().unwrap();
    let f = feedback.to_str().unwrap();
    fails_with(
        &["simulate", p, "--controller", f, "--weighed-load", "nan"],
        &["--weighed-load", "finite"],
    );
    fails_with(&["simulate", p, "--weighed-load", "20"], &["--controller"]);
    let designed = [
        "simulate",
        "scenes/case-study.toml",
        "--controller",
        "docs/case-study-controller.json",
        "--weighed-load",
        "20",
    ];
    fails_with(&designed, &["--weighed-load", "designed controller"]);
}

#[test]
fn a_best_that_does_not_settle_everywhere_names_the_plants_it_misses() {
    let dir = scratch("plan-misses");
    let plan = dir.join("plan.toml");
    let flags = [
        "4",
        "--robust",
        "masses.load=12:24,sections.youngs_modulus=1.9e11:2.3e11",
        "--checks",
        "0",
        "--out",
        plan.to_str().unwrap(),
    ];
    let out = succeeds(&[&SHORT_MOVE[..], &flags].concat());
    let table = String::from_utf8_lossy(&out.stdout);
    let best = table.lines().find(|l| l.starts_with("best: ")).unwrap();
    let name = &best["best: ".len()..best.find(" (").unwrap()];
    let plants = [
        "nominal", "corner 1", "corner 2", "corner 3", "corner 4", "centre",
    ];
    // the pick column of the best's rows: `never` where it does not get within
    let missed: Vec<&str> = plants
        .iter()
        .copied()
        .filter(|p| row_on(&table, name, p)[3] == "never")
        .collect();
    assert!(
        !missed.is_empty() && missed.len() < plants.len(),
        "this box is meant to have a best that settles on some plants only:\n{table}"
    );
    let listed = format!("(not on {})", missed.join(", "));
    assert!(best.contains(&listed), "{best}\nexpected {listed}");
    let settled = format!("settles on {} of the 6", plants.len() - missed.len());
    assert!(best.contains(&settled), "{best}");
}
