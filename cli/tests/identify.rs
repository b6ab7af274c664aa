//! `telescopic identify` end to end: a record the model makes with other values is fitted
//! back, the fitted scene it writes reproduces the record under `simulate`, and bad records
//! are refused naming the column and the line.

mod common;

use common::{Csv, fails_with, scratch, succeeds};
use std::fmt::Write as _;
use std::path::Path;

/// The machine's values the records are made with (the scene has 2.1e11 and 17.897).
const TRUTH: [&str; 2] = [
    "--set=sections.youngs_modulus=1.93e11",
    "--set=masses.load=21.5",
];

/// A record of adams-linear with `TRUTH` (its paper's 5 modes), 1 s, without noise: `t`, `F`
/// and the encoder, the strain gauge and the tip, as a logger writes it.
fn write_record(dir: &Path) -> std::path::PathBuf {
    let truth = dir.join("truth.csv");
    let mut args = vec!["simulate", "scenes/adams-linear.toml", "--set=time.end=1"];
    args.extend(TRUTH);
    args.extend(["--out", truth.to_str().unwrap()]);
    succeeds(&args);
    let run = Csv::read(&truth);
    let mut text = String::from("# logged at 1 kHz\nt,F,vehicle,kappa_1_0,tip_rel\n");
    let columns = ["vehicle", "kappa_1_0", "tip_rel"].map(|c| run.column(c));
    for row in &run.rows {
        let _ = write!(text, "{},100", row[0]);
        for c in columns {
            let _ = write!(text, ",{}", row[c]);
        }
        text.push('\n');
    }
    let record = dir.join("run.csv");
    std::fs::write(&record, text).unwrap();
    record
}

/// A noise-free record of the scene's own model is fitted back to its values, and the
/// fitted scene, run by `simulate`, gives the record's tip.
#[test]
fn a_record_is_fitted_back_and_its_fitted_scene_reproduces_it() {
    let dir = scratch("identify-fit");
    let record = write_record(&dir);
    let (fitted, figure) = (dir.join("fitted.toml"), dir.join("fit.svg"));
    let out = succeeds(&[
        "identify",
        "scenes/adams-linear.toml",
        "--data",
        record.to_str().unwrap(),
        "--free",
        "sections.youngs_modulus,masses.load=5:50",
        "--size",
        "5",
        "--offsets",
        "zero",
        "--out",
        fitted.to_str().unwrap(),
        "--plot",
        figure.to_str().unwrap(),
        "--validate",
        record.to_str().unwrap(),
    ]);
    let report = String::from_utf8(out.stdout).unwrap();
    let value = |key: &str| -> f64 {
        let line = report
            .lines()
            .find(|l| l.trim_start().starts_with(key))
            .unwrap();
        line.split_whitespace().nth(1).unwrap().parse().unwrap()
    };
    assert!(
        (value("sections.youngs_modulus") / 1.93e11 - 1.0).abs() < 1e-6,
        "{report}"
    );
    assert!((value("masses.load") / 21.5 - 1.0).abs() < 1e-6, "{report}");
    assert!(report.contains("validation on"), "{report}");
    let svg = std::fs::read_to_string(&figure).unwrap();
    assert!(svg.contains("measured") && svg.contains("fitted"));
    // the fitted scene under simulate, on the scene's own grid
    let rerun = dir.join("rerun.csv");
    succeeds(&[
        "simulate",
        fitted.to_str().unwrap(),
        "--set=time.end=1",
        "--out",
        rerun.to_str().unwrap(),
    ]);
    let (rerun, truth) = (Csv::read(&rerun), Csv::read(&dir.join("truth.csv")));
    let tip = truth.column("tip_rel");
    let peak = truth.rows.iter().map(|r| r[tip].abs()).fold(0.0, f64::max);
    for (a, b) in rerun.rows.iter().zip(&truth.rows) {
        assert!(
            (a[tip] - b[tip]).abs() < 1e-5 * peak,
            "t {}: {} {}",
            a[0],
            a[tip],
            b[tip]
        );
    }
}

/// Bad records and bad free values are refused before any fit, naming what is wrong.
#[test]
fn bad_records_are_refused_naming_the_column_and_the_line() {
    let dir = scratch("identify-bad");
    let good = std::fs::read_to_string(write_record(&dir)).unwrap();
    let lines: Vec<&str> = good.lines().collect();
    let variant = |name: &str, edit: &dyn Fn(&mut Vec<String>)| {
        let mut l: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
        edit(&mut l);
        let path = dir.join(name);
        std::fs::write(&path, l.join("\n")).unwrap();
        path
    };
    let identify = |record: &Path, free: &str, needles: &[&str]| {
        fails_with(
            &[
                "identify",
                "scenes/adams-linear.toml",
                "--data",
                record.to_str().unwrap(),
                "--free",
                free,
            ],
            needles,
        );
    };
    let free = "masses.load";
    // line 1 is the comment, 2 the header: sample i is on line i + 3
    let nan = variant("nan.csv", &|l| l[12] = l[12].replacen(",100,", ",NaN,", 1));
    identify(&nan, free, &["line 13, column F", "not a finite number"]);
    let back = variant("back.csv", &|l| l[40] = l[40].replacen("0.038", "0.01", 1));
    identify(&back, free, &["line 41, column t", "does not increase"]);
    let gap = variant("gap.csv", &|l| {
        l.remove(300);
    });
    identify(&gap, free, &["line 301, column t", "a gap"]);
    let unknown = variant("unknown.csv", &|l| l[1] = l[1].replace("tip_rel", "tip"));
    identify(&unknown, free, &["column tip", "no output"]);
    let absent = variant("absent.csv", &|l| l[1] = l[1].replace("tip_rel", "xi_3_0"));
    identify(&absent, free, &["column xi_3_0", "cannot produce it"]);
    let record = dir.join("run.csv");
    // the beams' bending sees E and I only as their product
    identify(
        &record,
        "sections.youngs_modulus,sections.inertia",
        &["does not determine sections."],
    );
    identify(&record, "masses.lod", &["--free", "masses.lod"]);
    identify(&record, "contact.clearance", &["--free", "give bounds"]);
}

/// `--start moving`: the record from 0.3 s on (the machine already moving, its time from 0)
/// is fitted back to the machine's values with the free motion of its start, and the
/// report says so; with clearance the flag is refused, naming it and the rule.
#[test]
fn a_record_that_starts_in_motion_is_fitted_with_start_moving() {
    let dir = scratch("identify-moving");
    let whole = std::fs::read_to_string(write_record(&dir)).unwrap();
    let mut text = String::new();
    for (i, line) in whole.lines().enumerate() {
        // line 1 is the comment, 2 the header, sample 300 (0.3 s) on line 303
        if !(2..302).contains(&i) {
            let mut fields: Vec<String> = line.split(',').map(String::from).collect();
            if i >= 302 {
                fields[0] = format!("{}", fields[0].parse::<f64>().unwrap() - 0.3);
            }
            text.push_str(&fields.join(","));
            text.push('\n');
        }
    }
    let record = dir.join("moving.csv");
    std::fs::write(&record, text).unwrap();
    let args = |scene: &'static str| {
        vec![
            "identify".to_string(),
            scene.to_string(),
            "--data".into(),
            record.to_str().unwrap().into(),
            "--free".into(),
            "sections.youngs_modulus,masses.load".into(),
            "--size".into(),
            "5".into(),
            "--start".into(),
            "moving".into(),
        ]
    };
    let fitted = succeeds(
        &args("scenes/adams-linear.toml")
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>(),
    );
    let report = String::from_utf8(fitted.stdout).unwrap();
    assert!(report.contains("start in motion"), "{report}");
    for (key, want) in [("sections.youngs_modulus", 1.93e11), ("masses.load", 21.5)] {
        let line = report
            .lines()
            .find(|l| l.trim_start().starts_with(key))
            .unwrap();
        let value: f64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
        assert!((value / want - 1.0).abs() < 1e-5, "{report}");
    }
    fails_with(
        &args("scenes/adams-clearance.toml")
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>(),
        &["--start", "clearance"],
    );
}
