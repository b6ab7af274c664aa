//! End-to-end tests of `telescopic modes`: the binary, its output formats and its errors.

mod common;

use common::{fails_with, telescopic};

fn json(args: &[&str]) -> serde_json::Value {
    let out = telescopic(args);
    assert!(
        out.status.success(),
        "{args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("stdout is one JSON document")
}

#[test]
fn json_has_the_documented_keys_and_physical_values() {
    let v = json(&["modes", "scenes/test-rig.toml", "--json"]);
    assert_eq!(v["rigid_modes"], 1);
    assert_eq!(v["modes_per_section"], serde_json::json!([5, 5]));
    let f: Vec<f64> = v["frequencies_hz"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    // 10 coordinates, one rigid translation: 9 frequencies, ascending and positive
    assert_eq!(f.len(), 9);
    assert!(f.windows(2).all(|w| w[0] < w[1]) && f[0] > 0.0);
    // within 10 % of the test rig's measured fundamental (the README discusses the gap)
    assert!((f[0] - 0.533).abs() / 0.533 < 0.1, "f1 = {}", f[0]);
}

#[test]
fn overrides_change_the_model() {
    let v = json(&[
        "modes",
        "scenes/test-rig.toml",
        "--json",
        "--set",
        "sections.modes=[3,4]",
        "--count",
        "2",
    ]);
    assert_eq!(v["modes_per_section"], serde_json::json!([3, 4]));
    assert_eq!(v["frequencies_hz"].as_array().unwrap().len(), 2);
    // gravity off stiffens the mast: no prestress softening
    let on = json(&["modes", "scenes/test-rig.toml", "--json"])["frequencies_hz"][0]
        .as_f64()
        .unwrap();
    let off = json(&[
        "modes",
        "scenes/test-rig.toml",
        "--json",
        "--set",
        "gravity.force_flow=none",
    ])["frequencies_hz"][0]
        .as_f64()
        .unwrap();
    assert!(off > on * 1.1, "gravity off {off} vs on {on}");
}

#[test]
fn table_shows_the_reference_columns() {
    let out = telescopic(&["modes", "scenes/test-rig.toml"]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("test rig [Hz]") && text.contains("paper Galerkin [Hz]"),
        "{text}"
    );
    assert!(text.contains("rigid-body modes: 1"), "{text}");
    let f1 = text
        .lines()
        .find(|l| l.trim_start().starts_with("f1 "))
        .expect("a row for f1");
    assert_eq!(f1.matches('%').count(), 2, "{f1}");
}

#[test]
fn mode_shapes_are_sampled_and_normalized() {
    let v = json(&[
        "modes",
        "scenes/test-rig.toml",
        "--json",
        "--count",
        "3",
        "--shapes",
        "11",
    ]);
    let shapes = v["mode_shapes"].as_array().unwrap();
    assert_eq!(shapes.len(), 3);
    for s in shapes {
        let sections = s["sections"].as_array().unwrap();
        assert_eq!(sections.len(), 2);
        let values: Vec<f64> = sections
            .iter()
            .flat_map(|w| w.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
            .collect();
        assert_eq!(values.len(), 22);
        let peak = values.iter().fold(0.0_f64, |m, w| m.max(w.abs()));
        assert!((peak - 1.0).abs() < 1e-12);
    }
    // the fundamental bends the mast one way: the top of section 2 moves most
    let first: Vec<f64> = shapes[0]["sections"][1]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    assert!((first[10].abs() - 1.0).abs() < 1e-12, "{first:?}");
}

#[test]
fn bad_input_fails_cleanly_and_names_the_field() {
    fails_with(
        &["modes", "scenes/test-rig.toml", "--set", "contact.points=1"],
        &["contact.points", "must be in 2..=32"],
    );
    fails_with(
        &[
            "modes",
            "scenes/test-rig.toml",
            "--set",
            "sections.modes=31",
        ],
        &["sections.modes", "1..=30"],
    );
    fails_with(
        &[
            "modes",
            "scenes/test-rig.toml",
            "--set",
            "telescope.positions=[1.4]",
        ],
        &["telescope.positions[0]", "overlap"],
    );
    fails_with(
        &["modes", "scenes/test-rig.toml", "--set", "nonsense"],
        &["--set nonsense", "KEY=VALUE"],
    );
    fails_with(
        &["modes", "scenes/no-such-scene.toml"],
        &["cannot read scene file", "no-such-scene.toml"],
    );
    fails_with(
        &["modes", "scenes/test-rig.toml", "--at", "5"],
        &["--at", "time span"],
    );
    fails_with(
        &["modes", "scenes/test-rig.toml", "--shapes", "1"],
        &["--shapes"],
    );
}

#[test]
fn generated_and_assembled_models_give_the_same_frequencies() {
    let freqs = |model: &str| -> Vec<f64> {
        let v = json(&["modes", "scenes/test-rig.toml", "--json", "--model", model]);
        assert!(
            v["model"]
                .as_str()
                .unwrap()
                .contains(if model == "generated" {
                    "generated"
                } else {
                    "assembled"
                })
        );
        v["frequencies_hz"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    let (g, a) = (freqs("generated"), freqs("assembled"));
    assert_eq!(g.len(), a.len());
    for (fg, fa) in g.iter().zip(&a) {
        assert!((fg - fa).abs() <= 1e-9 * fa, "{fg} vs {fa}");
    }
}

#[test]
fn a_scene_without_a_generated_model_falls_back_and_says_what_to_add() {
    let out = telescopic(&[
        "modes",
        "scenes/test-rig.toml",
        "--json",
        "--set",
        "sections.modes=[6,7]",
    ]);
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("no generated model for configuration s2_m6x7_c3_cable_linear_fixed_force"),
        "{err}"
    );
    assert!(
        err.contains("[[model]]\nmodes = [6, 7]\ncontacts = 3"),
        "{err}"
    );
    let v: serde_json::Value =
        serde_json::from_slice(&out.stdout).expect("stdout is still clean JSON");
    assert_eq!(v["model"], "quadrature-assembled model");
    fails_with(
        &[
            "modes",
            "scenes/test-rig.toml",
            "--model",
            "generated",
            "--set",
            "sections.modes=[6,7]",
        ],
        &[
            "--model: `generated`: no generated model",
            "s2_m6x7_c3_cable_linear_fixed_force",
            "models.toml",
        ],
    );
}

#[test]
fn equations_are_printed_in_every_format_without_a_banner() {
    for (format, marker) in [
        ("text", "Mass matrix M"),
        ("latex", "\\documentclass"),
        ("rust", "impl Model for GeneratedModel"),
        ("json", "\"key\": \"s2_m5x5_c3_cable_linear_fixed_force\""),
    ] {
        let out = telescopic(&["equations", "scenes/test-rig.toml", "--format", format]);
        assert!(
            out.status.success(),
            "{format}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = String::from_utf8(out.stdout).unwrap();
        assert!(text.contains(marker), "{format} lacks {marker}");
        assert!(
            !text.contains("Symbolica instance"),
            "{format}: the banner leaked"
        );
        let key = if format == "latex" {
            r"s2\_m5x5\_c3\_cable\_linear\_fixed\_force"
        } else {
            "s2_m5x5_c3_cable_linear_fixed_force"
        };
        assert!(text.contains(key), "{format} names the configuration");
    }
    let json: serde_json::Value = serde_json::from_slice(
        &telescopic(&["equations", "scenes/test-rig.toml", "--format", "json"]).stdout,
    )
    .unwrap();
    assert_eq!(json["dof"], 10);
    assert!(
        json["mass"]
            .as_array()
            .unwrap()
            .iter()
            .any(|e| e["i"] == 0 && e["j"] == 0)
    );
    fails_with(
        &[
            "equations",
            "scenes/test-rig.toml",
            "--set",
            "sections.modes=[6,7]",
        ],
        &["no generated model for configuration s2_m6x7", "[[model]]"],
    );
}
