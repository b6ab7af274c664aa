//! End-to-end tests of the structural engineer's results: `simulate --stations` (moments,
//! stresses, the envelope), `modes --plot` (the mode-shape picture, damping and kinds),
//! `bode` (CSV and plot) and `linearize --disturbance --discrete`, with their refusals.

mod common;

use common::{fails_with, scratch, succeeds};

#[test]
fn simulate_with_stations_writes_moments_stresses_and_the_envelope() {
    let dir = scratch("cli-stations");
    let csv = dir.join("run.csv");
    let out = succeeds(&[
        "simulate",
        "scenes/adams-linear.toml",
        "--set",
        "time.end=0.3",
        "--set",
        "sections.height=0.04",
        "--stations",
        "1:0,2:0.675",
        "--out",
        csv.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("stress envelope: max |stress|"), "{err}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let header = text.lines().find(|l| !l.starts_with('#')).unwrap();
    assert!(
        header.ends_with("moment_1_0,moment_2_0.675,stress_1_0,stress_2_0.675"),
        "{header}"
    );
    // without a section modulus: moments only, and the summary says why
    let out = succeeds(&[
        "simulate",
        "scenes/adams-linear.toml",
        "--set",
        "time.end=0.1",
        "--stations",
        "1:0",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("sections.section_modulus"));
    assert!(!std::fs::read_to_string(&csv).unwrap().contains("stress_"));
    std::fs::remove_file(&csv).unwrap();
    for (stations, needle) in [
        ("3:0", "section 3 does not exist"),
        ("1:9", "outside section 1"),
        ("x", "SECTION:X"),
    ] {
        fails_with(
            &[
                "simulate",
                "scenes/adams-linear.toml",
                "--stations",
                stations,
                "--out",
                csv.to_str().unwrap(),
            ],
            &["--stations", needle],
        );
        assert!(!csv.exists(), "no file after a refused run");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn modes_lists_damping_and_kinds_and_draws_the_shapes() {
    let dir = scratch("cli-mode-plot");
    let svg = dir.join("modes.svg");
    let out = succeeds(&[
        "modes",
        "scenes/test-rig.toml",
        "--set",
        "sections.damping_ratio=0.02",
        "--plot",
        svg.to_str().unwrap(),
    ]);
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(
        table.contains("structural damping: modal, zeta = 0.02"),
        "{table}"
    );
    let f1 = table
        .lines()
        .find(|l| l.trim_start().starts_with("f1 "))
        .unwrap();
    assert!(f1.contains("2.000e-2") && f1.contains("structural"), "{f1}");
    let f8 = table
        .lines()
        .find(|l| l.trim_start().starts_with("f8 "))
        .unwrap();
    assert!(f8.contains("contact"), "{f8}");
    let picture = std::fs::read_to_string(&svg).unwrap();
    assert!(picture.starts_with("<svg") && picture.contains("f1 = 0.4983 Hz"));
    fails_with(
        &[
            "modes",
            "scenes/test-rig.toml",
            "--plot",
            dir.join("modes.pdf").to_str().unwrap(),
        ],
        &["--plot", ".svg or .png"],
    );
    fails_with(
        &[
            "modes",
            "scenes/test-rig.toml",
            "--set",
            "sections.damping_ratio=1.2",
        ],
        &["sections.damping_ratio", "[0, 1)"],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bode_writes_the_csv_and_the_plot_and_refuses_unknown_signals() {
    let dir = scratch("cli-bode");
    let (csv, svg) = (dir.join("fr.csv"), dir.join("fr.svg"));
    let out = succeeds(&[
        "bode",
        "scenes/case-study.toml",
        "--positions",
        "a2=0.8",
        "--inputs",
        "F,F_load",
        "--outputs",
        "tip_rel,kappa_1_0",
        "--points",
        "300",
        "--out",
        csv.to_str().unwrap(),
        "--plot",
        svg.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("natural frequencies [Hz]: 0.7418"), "{err}");
    let text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(
        text.lines().next().unwrap(),
        "f_hz,tip_rel_mag,tip_rel_phase_deg,kappa_1_0_mag,kappa_1_0_phase_deg,\
         tip_rel_from_F_load_mag,tip_rel_from_F_load_phase_deg,kappa_1_0_from_F_load_mag,\
         kappa_1_0_from_F_load_phase_deg"
    );
    assert_eq!(text.lines().count(), 301);
    assert!(
        std::fs::read_to_string(&svg)
            .unwrap()
            .contains("magnitude from F_load")
    );
    std::fs::remove_file(&csv).unwrap();
    fails_with(
        &[
            "bode",
            "scenes/case-study.toml",
            "--outputs",
            "nonsense",
            "--out",
            csv.to_str().unwrap(),
        ],
        &["--outputs", "nonsense", "tip_rel"],
    );
    fails_with(
        &[
            "bode",
            "scenes/case-study.toml",
            "--from",
            "10",
            "--to",
            "1",
            "--out",
            csv.to_str().unwrap(),
        ],
        &["--to"],
    );
    assert!(!csv.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn linearize_adds_the_disturbance_input_and_the_discrete_model() {
    let out = succeeds(&[
        "linearize",
        "scenes/test-rig.toml",
        "--disturbance",
        "--discrete",
        "0.001",
    ]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["inputs"][1]["name"], "F_load");
    assert_eq!(v["discrete"]["dt"], 0.001);
    let (a, ad) = (&v["points"][0]["A"], &v["points"][0]["Ad"]);
    assert_eq!(ad.as_array().unwrap().len(), a.as_array().unwrap().len());
    assert_eq!(v["points"][0]["Bd"][0].as_array().unwrap().len(), 2);
    fails_with(
        &["linearize", "scenes/test-rig.toml", "--discrete=-1"],
        &["--discrete", "> 0"],
    );
    fails_with(
        &[
            "linearize",
            "scenes/test-rig.toml",
            "--discrete",
            "0.001",
            "--format",
            "latex",
        ],
        &["--format latex", "continuous-time model only"],
    );
}

#[test]
fn fmu_refuses_bad_names_and_libraries_and_takes_a_prescribed_motion() {
    let dir = scratch("cli-fmu");
    let out = dir.join("x.fmu");
    let o = out.to_str().unwrap();
    fails_with(
        &[
            "fmu",
            "scenes/adams-linear.toml",
            "--out",
            dir.join("x.zip").to_str().unwrap(),
        ],
        &["--out", ".fmu"],
    );
    fails_with(
        &[
            "fmu",
            "scenes/adams-linear.toml",
            "--out",
            o,
            "--library",
            "/nonexistent/lib.so",
        ],
        &[
            "--library",
            "/nonexistent/lib.so",
            "cargo build --release --manifest-path fmu/Cargo.toml",
        ],
    );
    // a file that is not the FMU's library is not packed
    for (library, why) in [
        (
            "scenes/adams-linear.toml",
            "not a 64-bit ELF shared library",
        ),
        ("/dev/zero", "not a 64-bit ELF shared library"),
        (
            env!("CARGO_BIN_EXE_telescopic"),
            "an executable, not a shared library",
        ),
    ] {
        fails_with(
            &[
                "fmu",
                "scenes/adams-linear.toml",
                "--out",
                o,
                "--library",
                library,
            ],
            &["--library", why],
        );
    }
    // a prescribed motion: the FMU's input is the vehicle's acceleration
    let motion = dir.join("motion.toml");
    let text = std::fs::read_to_string("scenes/adams-linear.toml")
        .unwrap()
        .replace("force = 100.0            # N from t = 0", "motion = 0.0");
    std::fs::write(&motion, text).unwrap();
    let moved = dir.join("moved.fmu");
    let done = succeeds(&[
        "fmu",
        motion.to_str().unwrap(),
        "--out",
        moved.to_str().unwrap(),
    ]);
    assert!(String::from_utf8_lossy(&done.stderr).contains("input a_vehicle"));
    assert!(!out.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
