//! `telescopic plan` end to end: the scene it writes reproduces its table's row (cycle time
//! and peak foot stress) when `simulate` runs it, by this file's own reading of the CSV; bad
//! options are refused naming the flag.

mod common;

use common::{Csv, fails_with, scratch, succeeds};

#[test]
fn the_written_plan_reproduces_its_cycle_time_under_simulate() {
    let dir = scratch("plan-reproduce");
    let plan = dir.join("plan.toml");
    let csv = dir.join("plan.csv");
    let out = succeeds(&[
        "plan",
        "scenes/adams-linear.toml",
        "--set",
        "sections.height=0.04",
        "--stations",
        "1:0",
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
        "4",
        "--out",
        plan.to_str().unwrap(),
    ]);
    let table = String::from_utf8_lossy(&out.stdout);
    // the rigid limit: 2 m at 1 m/s, 1 m/s^2, 5 m/s^3 takes 2/1 + 1/1 + 1/5 = 3.2 s
    assert!(table.contains("3.20 s"), "{table}");
    let best = table
        .lines()
        .find(|l| l.starts_with("best: "))
        .expect("the table names the best");
    let name = best["best: ".len()..best.find(" (worst").unwrap()].to_string();
    let row = table
        .lines()
        .find(|l| l.starts_with(&format!("{name:<44} nominal")))
        .unwrap_or_else(|| panic!("no nominal row for {name}:\n{table}"));
    let cells: Vec<&str> = row[44..].split_whitespace().collect();
    let reported: f64 = cells[3].parse().expect("the best settles");
    let reported_stress: f64 = cells[8].parse().expect("the stress at the foot (MPa)");
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
        .rposition(|r| (r[tip] - rest).abs() > 0.002 || (r[vehicle] - 2.0).abs() > 1e-3)
        .unwrap();
    let measured = rows[last_outside + 1][0];
    let stress = run.column("stress_1_0");
    let peak = rows.iter().map(|r| r[stress].abs()).fold(0.0, f64::max) / 1e6;
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

#[test]
fn bad_plan_options_are_refused_naming_the_flag() {
    let refused: [(&[&str], &[&str]); 6] = [
        (&["--distance", "0"], &["--distance", "not 0"]),
        (&["--distance", "2", "--v-max", "-1"], &["--v-max", "> 0"]),
        (&["--distance", "2", "--tolerance", "0"], &["--tolerance"]),
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
    for (flags, needles) in refused {
        let args = [&["plan", "scenes/adams-linear.toml"][..], flags].concat();
        fails_with(&args, needles);
    }
}
