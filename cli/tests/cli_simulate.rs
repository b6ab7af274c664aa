//! End-to-end tests of `telescopic simulate`: CSV columns and rows, the run summary, and
//! failures that leave no file behind.

mod common;

use common::{fails_with, scratch, succeeds, telescopic};

/// A fresh directory for one test's files.

#[test]
fn csv_has_the_model_md_columns_and_one_row_per_sample() {
    let dir = scratch("csv");
    let csv = dir.join("run.csv");
    let out = telescopic(&[
        "simulate",
        "scenes/adams-clearance.toml",
        "--set",
        "time.end=0.5",
        "--out",
        csv.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        out.stdout.is_empty(),
        "CSV went to a file; stdout stays empty"
    );
    for needle in [
        // gravity off, fixed positions, a constant force: auto takes the exact method
        "method exact (auto: exact, the cheapest measured run within 1e-6 m / 3 for scenes \
         linear and time-invariant between contact switches",
        "specializations: fixed positions: contact vectors are constants",
        "gravity off: no prestress terms",
        "steps ",
        "rejected ",
        "rhs evaluations ",
        "Jacobian evaluations ",
        "factorizations ",
        "contact switches ",
        "wall time ",
    ] {
        assert!(err.contains(needle), "summary lacks `{needle}`: {err}");
    }
    let text = std::fs::read_to_string(&csv).unwrap();
    // the error budget leads as `#` lines, as the summary says it
    let budget: Vec<&str> = text.lines().take_while(|l| l.starts_with('#')).collect();
    // with clearance the statistics beyond the window lead, then tip_rel inside it, then
    // every other output's truncation
    assert!(
        budget[0].starts_with("# error of the statistics beyond t = ")
            && budget[1].starts_with("# error of tip_rel")
            && budget[1].contains("truncation")
            && budget[2].contains("gaps")
            && budget[2].contains("contact forces"),
        "{budget:?}"
    );
    for line in &budget {
        assert!(err.contains(&line[2..]), "{err}");
    }
    let mut lines = text.lines().skip(budget.len());
    assert_eq!(
        lines.next().unwrap(),
        "t,vehicle,tip_rel,top1_rel,xi_2_0,xi_2_1,xi_2_2,f_2_0,f_2_1,f_2_2,kappa_1_0,acc_load"
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse::<f64>().unwrap()).collect())
        .collect();
    // 0 .. 0.5 s every millisecond
    assert_eq!(rows.len(), 501);
    for (k, r) in rows.iter().enumerate() {
        assert_eq!(r.len(), 12);
        assert!(
            (r[0] - k as f64 * 1e-3).abs() < 1e-12,
            "row {k} at t = {}",
            r[0]
        );
        assert!(r.iter().all(|v| v.is_finite()));
    }
    // gravity off, F = 100 N on ~118 kg: the vehicle moves forward
    assert!(rows[500][1] > 0.05);
    // a contact inside the band carries no force
    for r in &rows {
        for j in 0..3 {
            if r[4 + j].abs() < 0.005 {
                assert_eq!(r[7 + j], 0.0, "force inside the clearance at t = {}", r[0]);
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn auto_takes_dop853_imex_where_positions_move_with_clearance_and_says_why() {
    let out = telescopic(&[
        "simulate",
        "scenes/case-study.toml",
        "--modes-as-given",
        "--set",
        "time.end=0.05",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains(
            "method dop853-imex (auto: dop853-imex at rtol 1e-6, the cheapest measured run"
        ) && err.contains("for scenes with impacts"),
        "{err}"
    );
    assert!(
        err.contains("specializations: moving positions: contact vectors tabulated on [0, 12] s"),
        "{err}"
    );
    assert!(
        !err.contains("exact from"),
        "the positions move beyond the span: {err}"
    );
    // positions at rest from 0.02 s: auto hands the rest to exact stepping, on one sample grid
    let dir = scratch("auto-tail");
    let csv = dir.join("tail.csv");
    let out = telescopic(&[
        "simulate",
        "scenes/case-study.toml",
        "--modes-as-given",
        "--set",
        "time.end=0.05",
        "--set",
        "telescope.positions=[{ kind = \"smoothstep\", start = 0.0, end = 0.02, from = 0.35, to = 0.36 }]",
        "--out",
        csv.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("method dop853-imex (auto: dop853-imex at rtol 1e-6")
            && err.contains("exact stepping from t = 0.02 s on (positions at rest)"),
        "{err}"
    );
    assert!(err.contains("1 matrix exponentials"), "{err}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let times: Vec<f64> = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .skip(1)
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(
        times.len(),
        51,
        "one row per sample, the one at 0.02 s once"
    );
    for (k, t) in times.iter().enumerate() {
        assert!((t - 1e-3 * k as f64).abs() < 1e-12, "row {k}: t = {t}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
    // asked for explicitly, exact refuses the scene with the reason
    fails_with(
        &["simulate", "scenes/case-study.toml", "--method", "exact"],
        &[
            "method exact needs a scene that is linear and time-invariant",
            "a_2 moves",
        ],
    );
}

#[test]
fn divergence_is_an_error_and_leaves_no_file() {
    let dir = scratch("diverge");
    let csv = dir.join("run.csv");
    fails_with(
        &[
            "simulate",
            "scenes/adams-linear.toml",
            "--method",
            "rk4",
            "--dt",
            "1e-3",
            "--out",
            csv.to_str().unwrap(),
        ],
        &[
            "diverged at t = ",
            "method rk4",
            "stability limit",
            "largest stable step",
        ],
    );
    let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert!(left.is_empty(), "files left behind: {left:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_method_settings_are_named() {
    fails_with(
        &["simulate", "scenes/adams-linear.toml", "--method", "euler"],
        &[
            "unknown method `euler`",
            "dopri5",
            "rk4",
            "verlet",
            "galpha",
        ],
    );
    fails_with(
        &["simulate", "scenes/adams-linear.toml", "--method", "verlet"],
        &["fixed step", "--dt"],
    );
    fails_with(
        &["simulate", "scenes/adams-linear.toml", "--rtol=-1"],
        &["tolerances must be positive"],
    );
}

#[test]
fn plot_draws_the_papers_figures_with_labelled_axes() {
    let dir = scratch("plot");
    let svg = dir.join("cs.svg");
    let out = telescopic(&[
        "simulate",
        "scenes/case-study.toml",
        "--set",
        "time.end=0.3",
        "--compare",
        "scenes/case-study-no-clearance.toml",
        "--plot",
        svg.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&svg).unwrap();
    for needle in [
        "Fig. 8",
        "Fig. 9",
        "Fig. 10",
        "Fig. 11",
        "Fig. 12",
        "t [s]",
        "tip_rel [m]",
        "xi_2_1 [mm]",
        "case-study, l_S = 10 mm",
        "case-study-no-clearance, l_S = 0 mm",
        "band edges ±l_S/2 = ±5.00 mm",
    ] {
        assert!(text.contains(needle), "plot lacks `{needle}`");
    }
    fails_with(
        &["simulate", "scenes/adams-linear.toml", "--plot", "run.jpg"],
        &["--plot: run.jpg", ".svg or .png"],
    );
    fails_with(
        &[
            "work-precision",
            "scenes/adams-linear.toml",
            "--out",
            "chart.pdf",
        ],
        &["--out: chart.pdf", ".svg or .png"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn plot_as_png_has_curves_and_text() {
    let dir = scratch("png");
    let path = dir.join("adams.png");
    let out = telescopic(&[
        "simulate",
        "scenes/adams-clearance.toml",
        "--set",
        "time.end=0.5",
        "--plot",
        path.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut rgb = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut rgb).unwrap();
    // one panel (tip_rel) for the adams scenes
    assert_eq!((info.width, info.height), (1000, 320));
    let pixels: Vec<&[u8]> = rgb.chunks(3).collect();
    let colored = pixels
        .iter()
        .filter(|p| p.iter().max().unwrap() - p.iter().min().unwrap() > 80)
        .count();
    // the axis labels: dark pixels left of the plot area (text needs the built-in font)
    let label_ink = (0..320)
        .flat_map(|y| (0..30).map(move |x| y * 1000 + x))
        .filter(|&i| pixels[i].iter().all(|&c| c < 100))
        .count();
    assert!(
        colored > 500,
        "the curve is missing: {colored} colored pixels"
    );
    assert!(
        label_ink > 20,
        "the y-axis label is missing: {label_ink} dark pixels"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn stability_prints_omega_max_and_the_limits() {
    let out = telescopic(&["stability", "scenes/adams-linear.toml"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    let line = |m: &str| {
        text.lines()
            .find(|l| l.starts_with(m))
            .unwrap_or_else(|| panic!("no {m} line in\n{text}"))
            .to_string()
    };
    // the last number of each method's line is h omega_max at the model's limit
    for (m, lo, hi) in [("rk4", 2.7, 3.1), ("verlet", 1.8, 2.0)] {
        let l = line(m);
        let last: f64 = l.split_whitespace().last().unwrap().parse().unwrap();
        assert!((lo..=hi).contains(&last), "{l}");
    }
    // the adaptive explicit methods' caps: dop853's stability region reaches further along
    // the imaginary axis than dopri5's (which leaves it near 0 and needs the damping)
    let cap = |m: &str| -> f64 {
        let at = text
            .find(&format!("{m} "))
            .and_then(|i| text[i..].find("h omega_max ").map(|j| i + j + 12))
            .unwrap_or_else(|| panic!("no {m} cap in\n{text}"));
        text[at..].split(')').next().unwrap().parse().unwrap()
    };
    let (dopri5, dop853) = (cap("dopri5"), cap("dop853"));
    assert!(0.0 < dopri5 && dopri5 < dop853, "{text}");
}

#[test]
fn work_precision_writes_a_converging_table_and_a_chart() {
    let dir = scratch("wp");
    let (csv, svg) = (dir.join("wp.csv"), dir.join("wp.svg"));
    let out = telescopic(&[
        "work-precision",
        "scenes/adams-linear.toml",
        "--set",
        "time.end=0.2",
        "--methods",
        "dopri5,rk4",
        "--repeat",
        "1",
        "--csv",
        csv.to_str().unwrap(),
        "--out",
        svg.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    // no clearance: the references agree over the whole span
    assert!(stderr.contains("T_h = 0.2000 s"), "{stderr}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<Vec<&str>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), 6 + 5, "{text}");
    let error = |r: &Vec<&str>| r[5].parse::<f64>().unwrap();
    let dopri5: Vec<f64> = rows
        .iter()
        .filter(|r| r[0] == "dopri5")
        .map(error)
        .collect();
    let rk4: Vec<f64> = rows.iter().filter(|r| r[0] == "rk4").map(error).collect();
    // tighter settings are more accurate: the last (tightest) far below the first
    assert!(dopri5[5] < 1e-3 * dopri5[0], "{dopri5:?}");
    assert!(rk4[4] < 1e-2 * rk4[0], "{rk4:?}");
    assert!(
        std::fs::read_to_string(&svg)
            .unwrap()
            .contains("work-precision, adams-linear")
    );
    // tolerances between the decades, as asked, for the adaptive method only
    let out = telescopic(&[
        "work-precision",
        "scenes/adams-linear.toml",
        "--set",
        "time.end=0.2",
        "--methods",
        "dopri5,rk4",
        "--rtols",
        "3e-5,2.5e-6",
        "--repeat",
        "1",
    ]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    let settings: Vec<&str> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).unwrap())
        .collect();
    assert_eq!(&settings[..2], ["rtol=3e-5", "rtol=2.5e-6"], "{text}");
    assert_eq!(settings.len(), 2 + 5, "{text}");
    fails_with(
        &[
            "work-precision",
            "scenes/adams-linear.toml",
            "--methods",
            "euler",
        ],
        &["unknown method `euler`"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn work_precision_runs_auto_on_a_moving_scene_on_the_reference() {
    let dir = scratch("wp-auto");
    let csv = dir.join("wp.csv");
    // `auto` on a scene whose position moves (no clearance: imex, which steps once per
    // sample): its own rows, not skipped as plain exact, and on the reference over the whole
    // span at every tolerance (measured 3.2e-10 to 3.7e-9 m)
    let out = telescopic(&[
        "work-precision",
        "scenes/adams-linear.toml",
        "--set",
        "time.end=0.2",
        "--set",
        "telescope.positions=[{ kind = \"smoothstep\", start = 0.0, end = 0.05, from = 1.1, to = 1.15 }]",
        "--methods",
        "exact,auto",
        "--repeat",
        "1",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("exact: skipped (the telescopic position a_2 moves"),
        "{stderr}"
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let auto: Vec<f64> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|r| r[0] == "auto")
        .map(|r| r[5].parse::<f64>().unwrap())
        .collect();
    assert_eq!(auto.len(), 6, "{text}");
    assert!(auto.iter().all(|e| *e < 1e-8), "{auto:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn exact_reports_its_long_steps_and_no_long_steps_turns_them_off() {
    let dir = scratch("long-steps");
    let run = |extra: &[&str], name: &str| {
        let csv = dir.join(name);
        let mut args = vec![
            "simulate",
            "scenes/adams-clearance.toml",
            "--set",
            "time.end=1.2",
            "--method",
            "exact",
            "--out",
            csv.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let out = telescopic(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let summary = String::from_utf8_lossy(&out.stderr).to_string();
        let text = std::fs::read_to_string(&csv).unwrap();
        let tip: Vec<f64> = text
            .lines()
            .filter(|l| !l.starts_with('#'))
            .skip(1)
            .map(|l| l.split(',').nth(2).unwrap().parse().unwrap())
            .collect();
        (summary, tip)
    };
    let (long, tip_long) = run(&[], "long.csv");
    let (short, tip_short) = run(&["--no-long-steps"], "short.csv");
    assert!(
        long.contains("steps over the closed contacts' modes"),
        "{long}"
    );
    assert!(!short.contains("steps over"), "{short}");
    // the same motion to rounding, amplified by the scene's rattling (library test: 8e-10 m)
    let worst = tip_long
        .iter()
        .zip(&tip_short)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(tip_long.len() == 1201 && worst < 1e-8, "{worst:e}");
    let out = telescopic(&["stability", "scenes/adams-clearance.toml"]);
    let text = String::from_utf8_lossy(&out.stdout);
    let line = text
        .lines()
        .find(|l| l.starts_with("exact"))
        .unwrap_or_else(|| panic!("no exact line in\n{text}"));
    assert!(line.contains("steps over them with 1.0000e-3 s"), "{line}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The `accuracy search` lines of `stderr` as (which size, the verdict's first words).
fn search_verdicts(stderr: &str) -> Vec<(String, String)> {
    stderr
        .lines()
        .filter_map(|l| l.strip_prefix("accuracy search, "))
        .map(|l| {
            let (size, rest) = l.split_once(" (").expect("a size, then its figures");
            let verdict = rest.rsplit_once("; ").expect("a verdict").1;
            let verdict = verdict.split(" m x ").next().unwrap().trim_end_matches(')');
            let verdict = match verdict.split_once(" estimate") {
                Some((head, _)) => format!("{head} estimate"),
                None => verdict.to_string(),
            };
            (size.to_string(), verdict)
        })
        .collect()
}

#[test]
fn accuracy_picks_the_model_size_and_no_error_estimate_leaves_the_header_out() {
    let csv = scratch("accuracy-size").join("run.csv");
    let at_a_millimetre = || {
        telescopic(&[
            "simulate",
            "scenes/adams-linear.toml",
            "--accuracy",
            "1e-3",
            "--out",
            csv.to_str().unwrap(),
        ])
    };
    let out = at_a_millimetre();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("accuracy 1e-3 m in all")
            && err.contains("basis modes+static, 2 modes per section")
            && err.contains("accuracy search: predicted modes+static 2 (its modal surrogate")
            && err.contains("confirmed by its companion"),
        "{err}"
    );
    // without clearance the predicted size and its companion are the only runs
    assert_eq!(
        search_verdicts(&err),
        [(
            "size 1 of at most 17: modes+static 2".to_string(),
            "passes".to_string()
        )],
        "{err}"
    );
    assert!(err.contains("the search: 2 runs, "), "{err}");
    assert!(
        std::fs::read_to_string(&csv)
            .unwrap()
            .starts_with("# error of tip_rel")
    );
    // the integration accuracy alone, the scene's own modes
    let out = telescopic(&[
        "simulate",
        "scenes/adams-linear.toml",
        "--accuracy",
        "1e-8",
        "--modes-as-given",
        "--no-error-estimate",
        "--out",
        csv.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("generated model s2_m5x5"), "{err}");
    assert!(!err.contains("truncation"), "{err}");
    assert!(
        std::fs::read_to_string(&csv)
            .unwrap()
            .starts_with("t,vehicle")
    );
    // a whole accuracy below what is certified
    fails_with(
        &[
            "simulate",
            "scenes/adams-linear.toml",
            "--accuracy",
            "1e-7",
            "--out",
            "/dev/null",
        ],
        &["--accuracy", "1e-5 to 1e-1 m", "--modes-as-given"],
    );
}

#[test]
fn with_clearance_nothing_is_predicted_and_the_search_is_best_first_by_counted_work() {
    // a line per size checked, the paper's first size
    // first, then best-first by counted work: the paper's 4 modes are rejected by their
    // estimate, 6 pass, and 2 with the static shapes (costlier than a passing size) get no
    // companion run
    let with_clearance = || {
        telescopic(&[
            "simulate",
            "scenes/adams-clearance.toml",
            "--accuracy",
            "1e-4",
            "--out",
            "/dev/null",
        ])
    };
    let out = with_clearance();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("no size predicted (clearance: impacts set the error)"),
        "{err}"
    );
    let search = search_verdicts(&err);
    assert_eq!(
        search,
        [
            (
                "size 1 of at most 11: modes 4",
                "rejected: tip_rel estimate"
            ),
            ("size 2 of at most 11: modes 6", "passes"),
            (
                "size 3 of at most 11: modes+static 2",
                "rejected: costs more than a passing size, not checked"
            ),
        ]
        .map(|(a, b)| (a.to_string(), b.to_string())),
        "{err}"
    );
    // 4 runs and the static shapes' first size run ahead beside the 4 modes' companion,
    // capped by their cost; with the 4 modes rejected, that cap was not the one its turn
    // had, so it ran again in its turn
    assert!(err.contains("the search: 5 runs, "), "{err}");
    // the pick ranks by counted work, not time: a second run checks the same sizes in the
    // same order with the same verdicts
    assert_eq!(
        search_verdicts(&String::from_utf8_lossy(&with_clearance().stderr)),
        search
    );
}

#[test]
fn a_size_costlier_than_a_passing_one_is_stopped_past_that_cost() {
    // case-study states 1e-3 m: the paper's 4 modes pass first, so the static shapes' first
    // run is stopped as soon as its counted work passes theirs
    let out = telescopic(&[
        "simulate",
        "scenes/case-study.toml",
        "--set",
        "time.end=0.3",
        "--out",
        "/dev/null",
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let verdicts = search_verdicts(&err);
    assert_eq!(
        verdicts,
        [
            ("size 1 of at most 11: modes 4", "passes"),
            (
                "size 2 of at most 11: modes+static 2",
                "rejected: stopped once it cost more than a passing size (its operations so far), not checked"
            ),
        ]
        .map(|(a, b)| (a.to_string(), b.to_string())),
        "{err}"
    );
    // the stopped run's count is past the passing size's (the printed figures, 2 digits)
    let operations = |line: &str| -> f64 {
        let figures = line
            .split_once(" m, ")
            .or(line.split_once("estimated, "))
            .unwrap()
            .1;
        figures
            .split_once(" operations")
            .unwrap()
            .0
            .parse()
            .unwrap()
    };
    let lines: Vec<&str> = err
        .lines()
        .filter(|l| l.starts_with("accuracy search, "))
        .collect();
    assert!(operations(lines[1]) >= operations(lines[0]), "{err}");
    assert!(err.contains("generated model s2_m4x4"), "{err}");
}

#[test]
fn a_scene_that_states_an_accuracy_is_run_to_it_unless_its_modes_are_kept() {
    let stated = |extra: &[&str]| {
        let mut args = vec![
            "simulate",
            "scenes/adams-linear.toml",
            "--set",
            "accuracy=1e-3",
            "--out",
            "/dev/null",
        ];
        args.extend_from_slice(extra);
        let out = telescopic(&args);
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(out.status.success(), "{err}");
        err
    };
    // by default the run picks the size that meets the scene's accuracy, as --accuracy does
    let err = stated(&[]);
    assert!(
        err.contains("the scene states accuracy = 1e-3 m")
            && err.contains("accuracy 1e-3 m in all")
            && err.contains("basis modes+static, 2 modes per section"),
        "{err}"
    );
    // the paper's N on request, and a method of the user's own keeps the scene's modes too
    for extra in [&["--modes-as-given"][..], &["--method", "dop853"]] {
        let err = stated(extra);
        assert!(
            err.contains("generated model s2_m5x5") && !err.contains("accuracy search"),
            "{extra:?}: {err}"
        );
    }
    // the key is checked like the flag, naming the field
    fails_with(
        &[
            "simulate",
            "scenes/adams-linear.toml",
            "--set",
            "accuracy=1e-7",
        ],
        &["`accuracy`", "1e-5 to 1e-1 m"],
    );
}

#[test]
fn the_json_summary_is_the_runs_and_agrees_with_the_text_summary_and_the_csv() {
    let dir = scratch("json-summary");
    let csv = dir.join("run.csv");
    let out = telescopic(&[
        "simulate",
        "scenes/adams-clearance.toml",
        "--set",
        "time.end=1",
        "--json",
        "--out",
        csv.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    // the same run as the text summary on stderr and the CSV
    let text = v["text"].as_str().unwrap();
    assert!(err.contains(text), "{err}\nagainst\n{text}");
    let steps = v["steps"].as_u64().unwrap();
    let switches = v["switches"].as_u64().unwrap();
    assert!(
        text.contains(&format!("steps {steps} "))
            && text.contains(&format!("contact switches {switches},")),
        "{text}"
    );
    let rows = std::fs::read_to_string(&csv)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .count()
        - 1;
    assert_eq!(v["samples"].as_u64().unwrap() as usize, rows);
    assert_eq!(v["method"], "exact");
    assert_eq!(v["modes"], serde_json::json!([5, 5]));
    // the error budget: its total is its two parts
    let e = &v["error"];
    let (integration, truncation) = (
        e["integration_m"].as_f64().unwrap(),
        e["truncation_m"].as_f64().unwrap(),
    );
    let total = e["total_m"].as_f64().unwrap();
    assert!(
        (total - (integration + truncation)).abs() <= 1e-12 * total,
        "{e}"
    );
    assert_eq!(e["window_end"], "first-switch");
    assert!(
        e["statistics"]["rms-tip-rel"].as_array().unwrap().len() == 2,
        "{e}"
    );
    // the CSV needs a file of its own
    fails_with(
        &["simulate", "scenes/adams-clearance.toml", "--json"],
        &["--out"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_documented_top_accuracy_is_taken() {
    // 0.1 m in all: its integration share (a tenth) rounds above the integration's top
    let out = succeeds(&[
        "simulate",
        "scenes/adams-linear.toml",
        "--accuracy",
        "0.1",
        "--out",
        "/dev/null",
    ]);
    let said = String::from_utf8_lossy(&out.stderr);
    assert!(said.contains("wrote /dev/null"), "{said}");
}

/// Runs `simulate` on adams-clearance's first half second with records kept in `dir`.
fn simulate_keeping_records(
    dir: &std::path::Path,
    out: &std::path::Path,
    extra: &[&str],
) -> String {
    let mut args = vec![
        "simulate",
        "scenes/adams-clearance.toml",
        "--set",
        "time.end=0.5",
        "--json",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_telescopic"))
        .args(&args)
        .env("TELESCOPIC_CACHE_DIR", dir)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    String::from_utf8(output.stdout).unwrap()
}

#[test]
fn a_repeated_simulate_reuses_the_error_budget_its_first_run_kept() {
    let dir = scratch("reuse");
    let records = dir.join("records");
    let (first, second, fresh) = (dir.join("a.csv"), dir.join("b.csv"), dir.join("c.csv"));
    let json = |text: &str| serde_json::from_str::<serde_json::Value>(text).unwrap();
    let kept = json(&simulate_keeping_records(&records, &first, &[]));
    assert!(kept["error"]["reused_from"].is_null());
    assert_eq!(std::fs::read_dir(&records).unwrap().count(), 1);
    let reused = json(&simulate_keeping_records(&records, &second, &[]));
    let record = reused["error"]["reused_from"]
        .as_str()
        .expect("the second run reuses");
    assert!(record.starts_with(records.to_str().unwrap()));
    assert!(
        reused["text"]
            .as_str()
            .unwrap()
            .contains("error budget reused from")
    );
    // the same samples and, apart from where it came from, the same budget
    let samples = |path: &std::path::Path| -> Vec<String> {
        let text = std::fs::read_to_string(path).unwrap();
        text.lines()
            .filter(|l| !l.starts_with('#'))
            .map(String::from)
            .collect()
    };
    assert!(
        samples(&first) == samples(&second),
        "the reused run's samples differ"
    );
    let without_source = |mut v: serde_json::Value| {
        v["error"]["reused_from"] = serde_json::Value::Null;
        v["error"].clone()
    };
    assert_eq!(without_source(kept.clone()), without_source(reused));
    // --no-reuse estimates afresh and keeps nothing
    let afresh = json(&simulate_keeping_records(&records, &fresh, &["--no-reuse"]));
    assert!(afresh["error"]["reused_from"].is_null());
    assert_eq!(afresh["error"], kept["error"]);
    assert_eq!(std::fs::read_dir(&records).unwrap().count(), 1);
    std::fs::remove_dir_all(&dir).unwrap();
}
