//! `linearize`, `design` and `simulate --controller` end to end.

mod common;

use common::{fails_with, scratch, telescopic};

#[test]
fn linearize_writes_each_format() {
    let out = telescopic(&["linearize", "scenes/adams-linear.toml"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(doc["format"], "telescopic linear model");
    assert_eq!(doc["states"][0]["name"], "u");
    assert_eq!(doc["points"][0]["A"].as_array().unwrap().len(), 20);
    let dir = scratch("cli-control-formats");
    for (format, starts) in [
        ("matlab", "% Linear model"),
        ("python", "# Linear model"),
        ("latex", "% Linear model"),
        ("npz", "PK"),
    ] {
        let file = dir.join(format!("model.{format}"));
        let out = telescopic(&[
            "linearize",
            "scenes/case-study.toml",
            "--grid",
            "a2=0.35:1.15:3",
            "--format",
            format,
            "--out",
            file.to_str().unwrap(),
        ]);
        assert!(
            out.status.success(),
            "{format}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let bytes = std::fs::read(&file).unwrap();
        assert!(bytes.starts_with(starts.as_bytes()), "{format}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn linearize_refuses_bad_operating_points() {
    fails_with(
        &[
            "linearize",
            "scenes/case-study.toml",
            "--positions",
            "a2=2.0",
        ],
        &["a2 = 2 m is outside the valid overlap"],
    );
    fails_with(
        &[
            "linearize",
            "scenes/case-study.toml",
            "--grid",
            "a2=0.35:1.15",
        ],
        &["--grid", "a<k>=FROM:TO:COUNT"],
    );
    fails_with(
        &[
            "linearize",
            "scenes/case-study.toml",
            "--positions",
            "a2=0.5",
            "--grid",
            "a2=0.35:1.15:5",
        ],
        &["--positions", "a2", "one or the other", "--grid"],
    );
    fails_with(
        &[
            "linearize",
            "scenes/three-section.toml",
            "--set",
            "sections.modes=6",
            "--format",
            "latex",
        ],
        &["at most 24 states"],
    );
    fails_with(
        &["linearize", "scenes/case-study.toml", "--at-time", "99"],
        &["--at-time", "time span"],
    );
}

#[test]
fn design_then_simulate_with_the_controller() {
    let dir = scratch("cli-control-design");
    let controller = dir.join("controller.json");
    let out = telescopic(&[
        "design",
        "scenes/case-study.toml",
        "--controller",
        "lqr",
        "--no-table",
        "--out",
        controller.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = dir.join("run.csv");
    let svg = dir.join("run.svg");
    let out = telescopic(&[
        "simulate",
        "scenes/case-study.toml",
        "--controller",
        controller.to_str().unwrap(),
        "--out",
        csv.to_str().unwrap(),
        "--plot",
        svg.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    // the figure says what differs, shows the force limit and marks the residual window
    let picture = std::fs::read_to_string(&svg).unwrap();
    for needle in [
        "case-study with lqr",
        "case-study without control",
        "force limit ±300 N",
        "residual window",
        "xi_2_0 [mm]",
    ] {
        assert!(picture.contains(needle), "the figure lacks `{needle}`");
    }
    assert!(
        err.contains("controller lqr: residual tip vibration") && err.contains("without"),
        "{err}"
    );
    let header = std::fs::read_to_string(&csv)
        .unwrap()
        .lines()
        .find(|l| !l.starts_with('#'))
        .unwrap()
        .to_string();
    assert!(
        header.ends_with(",drive_force,kappa_1_0,acc_load"),
        "{header}"
    );
    // a controller for another configuration is refused before the run
    fails_with(
        &[
            "simulate",
            "scenes/adams-clearance.toml",
            "--controller",
            controller.to_str().unwrap(),
        ],
        &["--controller", "designed for configuration"],
    );
    // the design's settings are refused by their flags, and nothing is written
    let bad = dir.join("bad.json");
    fails_with(
        &[
            "design",
            "scenes/case-study.toml",
            "--sensors",
            "vehicle,kappa_1_0",
            "--estimator",
            "extended",
            "--process-noise-floor",
            "0",
            "--no-table",
            "--out",
            bad.to_str().unwrap(),
        ],
        &["--process-noise-floor: must be"],
    );
    fails_with(
        &[
            "design",
            "scenes/case-study.toml",
            "--shaper-timing",
            "early",
            "--out",
            bad.to_str().unwrap(),
        ],
        &["--shaper-timing", "delayed or within"],
    );
    assert!(!bad.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn malformed_controller_files_are_refused_before_the_run() {
    // each used to panic (index out of range) inside the run instead of failing cleanly
    let good: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string("docs/case-study-controller.json").unwrap())
            .unwrap();
    let dir = scratch("cli-control-malformed");
    let empty_filter = serde_json::json!({
        "C_modal": [], "Q_noise": [], "R_noise": [], "L_modal": [], "L": [],
        "A_full": [], "B_full": [], "C_meas": []
    });
    type Edit = Box<dyn Fn(&mut serde_json::Value)>;
    let cases: Vec<(&str, Edit, &[&str])> = vec![
        (
            "positions",
            Box::new(|c| {
                for p in c["schedule"].as_array_mut().unwrap() {
                    p["positions"] = serde_json::json!([]);
                }
            }),
            &[
                "--controller",
                "`schedule[0].positions`: has 0 position(s), the scene has 1",
            ],
        ),
        (
            "order",
            Box::new(|c| c["schedule"].as_array_mut().unwrap().reverse()),
            &["--controller", "not in ascending order of a_2"],
        ),
        (
            "gain",
            Box::new(|c| {
                c["schedule"][0]["K"][0].as_array_mut().unwrap().pop();
            }),
            &[
                "--controller",
                "`schedule[0].K`: must be one row of 16 gains",
            ],
        ),
        (
            "filter",
            Box::new(move |c| {
                c["kind"] = "lqr+shaper+kalman".into();
                for p in c["schedule"].as_array_mut().unwrap() {
                    p["observer"] = empty_filter.clone();
                }
            }),
            &[
                "--controller",
                "Kalman filter: A_full is 0 x 0, expected 16 x 16",
            ],
        ),
    ];
    for (name, edit, needles) in cases {
        let mut c = good.clone();
        edit(&mut c);
        let path = dir.join(format!("{name}.json"));
        std::fs::write(&path, c.to_string()).unwrap();
        fails_with(
            &[
                "simulate",
                "scenes/case-study.toml",
                "--controller",
                path.to_str().unwrap(),
            ],
            needles,
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
