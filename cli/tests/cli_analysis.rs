//! End-to-end tests of `converge` (the smallest model a scene needs) and `shape-errors`
//! (printed vs cancellation-free shape functions).

mod common;

use common::{fails_with, telescopic};

/// Rows of a CSV with a header, as strings.
fn rows(text: &str) -> Vec<Vec<String>> {
    text.lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

#[test]
fn converge_finds_a_model_whose_next_refinement_changes_less_than_tol() {
    let dir = std::env::temp_dir().join(format!("telescopic-converge-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("converge.csv");
    let tol = 1e-2;
    let out = telescopic(&[
        "converge",
        "scenes/adams-clearance.toml",
        "--set",
        "time.end=2",
        "--tol",
        &tol.to_string(),
        "--max-modes",
        "9",
        "--max-contacts",
        "3",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let chosen: usize = stdout
        .split("modes per section")
        .next()
        .and_then(|s| s.split_whitespace().last())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no model in: {stdout}"));
    assert!(stdout.contains("faster than the largest model"), "{stdout}");
    let table = rows(&std::fs::read_to_string(&csv).unwrap());
    let by_modes: Vec<&Vec<String>> = table.iter().filter(|r| r[1] == "3").take(9).collect();
    assert_eq!(by_modes.len(), 9);
    let num = |r: &Vec<String>, i: usize| r[i].parse::<f64>().unwrap();
    // Ritz: adding shape functions never raises a frequency (from 2 modes on, where there
    // are three)
    for w in by_modes[1..].windows(2) {
        for i in 4..7 {
            assert!(
                num(w[1], i) <= num(w[0], i) * (1.0 + 1e-9),
                "{:?} -> {:?}",
                w[0],
                w[1]
            );
        }
    }
    // the chosen model changes by less than tol to the next one, the one before by more
    let change = |a: &Vec<String>, b: &Vec<String>| {
        (4..9)
            .map(|i| (num(a, i) - num(b, i)).abs() / num(b, i).abs())
            .fold(0.0, f64::max)
    };
    let at = |n: usize| by_modes[n - 1];
    assert!(change(at(chosen), at(chosen + 1)) < tol);
    assert!(change(at(chosen - 1), at(chosen)) >= tol);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn converge_rejects_a_bad_tolerance() {
    fails_with(
        &["converge", "scenes/adams-linear.toml", "--tol", "2"],
        &["--tol: must be a relative change in (0, 1)"],
    );
}

#[test]
fn printed_free_free_shape_functions_fail_where_the_cancellation_free_ones_do_not() {
    let out = telescopic(&["shape-errors", "--points", "11"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let table = rows(&String::from_utf8_lossy(&out.stdout));
    assert_eq!(table.len(), 29 + 28, "modes 2..30 and 3..30");
    for r in &table {
        let mode: usize = r[1].parse().unwrap();
        let (free, printed) = (r[2].parse::<f64>().unwrap(), r[3].parse::<f64>().unwrap());
        assert!(free <= 1e-12, "{r:?}");
        if r[0] == "free-free" && mode >= 20 {
            // sigma rounds to 1 and the e^beta terms cancel to nothing
            assert!(printed > 1e-2, "{r:?}");
        }
        if r[0] == "guided-free" {
            // cos(beta)/cosh(beta) cosh(lam x) never exceeds 1: nothing cancels
            assert!(printed <= 1e-12, "{r:?}");
        }
    }
}

#[test]
fn work_precision_over_model_sizes_marks_the_front_and_names_the_cheapest() {
    let dir = std::env::temp_dir().join(format!("telescopic-sizes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("sizes.csv");
    let out = telescopic(&[
        "work-precision",
        "scenes/adams-linear.toml",
        "--set",
        "time.end=1",
        "--modes",
        "4,8,static:2",
        "--repeat",
        "1",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(
        text.starts_with(
            "basis,modes,method,setting,wall_s,tip_error_window_m,statistics_error_rel,pareto"
        ),
        "{text}"
    );
    let table = rows(&text);
    assert_eq!(table.len(), 3, "exact: one run per size");
    let error = |basis: &str, modes: &str| -> f64 {
        table
            .iter()
            .find(|r| r[0] == basis && r[1] == modes)
            .unwrap()[5]
            .parse()
            .unwrap()
    };
    // against the beams over [0, 1] s: the paper's 4 modes 6.8 mm, 8 modes 0.28 mm, 2 modes
    // with the static shapes 0.02 mm (docs/numerics.md)
    assert!((3e-3..1.2e-2).contains(&error("modes", "4")), "{text}");
    assert!((1e-4..5e-4).contains(&error("modes", "8")), "{text}");
    assert!(error("modes+static", "2") < 5e-5, "{text}");
    // the static shapes' run is on the front: nothing both cheaper and more accurate
    assert!(
        table
            .iter()
            .any(|r| r[0] == "modes+static" && r[7] == "true"),
        "{text}"
    );
    assert!(
        stderr.contains("cheapest within 1e-3 m: modes static:2"),
        "{stderr}"
    );
    fails_with(
        &[
            "work-precision",
            "scenes/adams-linear.toml",
            "--modes",
            "static:0",
        ],
        &["--modes", "1 to 30"],
    );
}
