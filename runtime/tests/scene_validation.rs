//! Every validation rule of a scene, each broken once: the error must name the field and the
//! rule. Overrides go through the same validation.

use std::path::Path;
use telescopic_runtime::{Drive, Profile, Scene, SceneError};

const BASE: &str = r#"
name = "base"
[sections]
count = 2
length = [1.35, 1.35]
area = 0.001
inertia = 0.83e-8
density = 7850.0
youngs_modulus = 2.1e11
modes = 4
[masses]
vehicle = 100.0
load = 17.897
[gravity]
g = 9.81
force_flow = "cable"
[contact]
points = 2
stiffness = 0.2375e9
damping = 1000.0
clearance = 0.01
[telescope]
positions = [{ kind = "smoothstep", start = 0, end = 12, from = 0.35, to = 1.15 }]
[drive]
force = { kind = "piecewise-constant", times = [0, 4, 8, 12], values = [100, 0, -100, 0] }
[time]
start = 0.0
end = 16.0
sample = 0.01
"#;

fn load(overrides: &[&str]) -> Result<Scene, SceneError> {
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    Scene::from_toml_str(BASE, Path::new("base.toml"), &o)
}

/// Loading with the overrides fails, and the message names `field` and contains `rule`.
fn rejects(overrides: &[&str], field: &str, rule: &str) {
    let err = load(overrides).expect_err("the scene should be rejected");
    let msg = err.to_string();
    assert!(
        msg.contains(field),
        "{overrides:?}: message does not name `{field}`:\n{msg}"
    );
    assert!(
        msg.contains(rule),
        "{overrides:?}: message does not state `{rule}`:\n{msg}"
    );
}

#[test]
fn the_base_scene_is_valid_and_converts() {
    let s = load(&[]).unwrap();
    assert_eq!(s.params.sections.len(), 2);
    assert!((s.params.sections[0].mass_per_length - 7.85).abs() < 1e-12);
    assert!((s.params.sections[1].bending_stiffness - 1743.0).abs() < 1e-9);
    assert!(matches!(s.params.drive, Drive::Force(_)));
    assert_eq!(s.params.positions[0].value(6.0), 0.75);
}

#[test]
fn unknown_keys_are_rejected_everywhere() {
    rejects(&["colour=1"], "colour", "unknown field");
    rejects(
        &["contact.friction=0.1"],
        "contact.friction",
        "unknown field",
    );
    rejects(&["telescope.positions.0.speed=1"], "speed", "unknown field");
}

#[test]
fn missing_required_fields_are_named() {
    let text = BASE.replace("stiffness = 0.2375e9\n", "");
    let err = Scene::from_toml_str(&text, Path::new("x.toml"), &[])
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("contact") && err.contains("missing field `stiffness`"),
        "{err}"
    );
    let text = BASE.replace("[time]\nstart = 0.0\nend = 16.0\nsample = 0.01\n", "");
    let err = Scene::from_toml_str(&text, Path::new("x.toml"), &[])
        .unwrap_err()
        .to_string();
    assert!(err.contains("missing field `time`"), "{err}");
}

#[test]
fn wrong_types_name_the_field() {
    rejects(
        &["sections.area=\"big\""],
        "sections.area",
        "a number (shared by all sections) or a list",
    );
    rejects(
        &["drive.force=[1, 2]"],
        "drive.force",
        "a number, or a table with kind",
    );
    rejects(
        &["gravity.force_flow=sideways"],
        "gravity.force_flow",
        "unknown variant",
    );
}

#[test]
fn physical_values_must_be_finite_and_positive() {
    rejects(
        &["sections.length=[1.35, 0.0]"],
        "sections.length[1]",
        "finite number > 0",
    );
    rejects(
        &["sections.area=-0.001"],
        "sections.area",
        "finite number > 0",
    );
    rejects(
        &["sections.inertia=nan"],
        "sections.inertia",
        "finite number > 0",
    );
    rejects(
        &["sections.density=inf"],
        "sections.density",
        "finite number > 0",
    );
    rejects(
        &["sections.youngs_modulus=0"],
        "sections.youngs_modulus",
        "finite number > 0",
    );
    rejects(
        &["contact.stiffness=0"],
        "contact.stiffness",
        "finite number > 0",
    );
    rejects(
        &["masses.vehicle=-1"],
        "masses.vehicle",
        "finite number >= 0",
    );
    rejects(&["masses.load=nan"], "masses.load", "finite number >= 0");
    rejects(&["gravity.g=-9.81"], "gravity.g", "finite number >= 0");
    rejects(
        &["contact.damping=-1"],
        "contact.damping",
        "finite number >= 0",
    );
    rejects(
        &["contact.clearance=-0.01"],
        "contact.clearance",
        "finite number >= 0",
    );
    rejects(&["drive.force=nan"], "drive.force", "finite number");
    // zero point masses and gravity are allowed
    assert!(load(&["masses.vehicle=0", "masses.load=0", "gravity.g=0"]).is_ok());
}

#[test]
fn per_section_lists_need_one_value_per_section() {
    rejects(
        &["sections.length=[1.35]"],
        "sections.length",
        "has 1 values but sections.count is 2",
    );
    rejects(
        &["sections.modes=[4, 4, 4]"],
        "sections.modes",
        "has 3 values but sections.count is 2",
    );
    rejects(
        &["sections.count=0"],
        "sections.count",
        "must be in 1..=16 (got 0)",
    );
}

#[test]
fn modes_are_limited_to_1_through_30() {
    rejects(
        &["sections.modes=0"],
        "sections.modes",
        "must be in 1..=30 (got 0)",
    );
    rejects(
        &["sections.modes=[4, 31]"],
        "sections.modes[1]",
        "must be in 1..=30 (got 31)",
    );
    assert!(load(&["sections.modes=[1, 30]"]).is_ok());
}

#[test]
fn contacts_need_two_points() {
    rejects(
        &["contact.points=1"],
        "contact.points",
        "must be in 2..=32 (got 1)",
    );
    let text = BASE.replace(
        "[contact]\npoints = 2\nstiffness = 0.2375e9\ndamping = 1000.0\nclearance = 0.01\n",
        "",
    );
    let err = Scene::from_toml_str(&text, Path::new("x.toml"), &[])
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("`contact`") && err.contains("required when there is more than one section"),
        "{err}"
    );
}

#[test]
fn overlap_must_stay_inside_its_range_at_every_time() {
    // o = l_1 - a_2 must lie in (0, min(l_1, l_2)]
    rejects(
        &["telescope.positions=[1.35]"],
        "telescope.positions[0]",
        "overlap l_1 - a_2 must stay in (0, min(l_1, l_2)]",
    );
    rejects(
        &["telescope.positions=[-0.1]"],
        "telescope.positions[0]",
        "overlap",
    );
    // a ramp that leaves the range only in the middle of the profile
    rejects(
        &[
            "telescope.positions=[{kind=\"piecewise-linear\", times=[0, 5, 10], values=[0.5, 1.4, 0.5]}]",
        ],
        "telescope.positions[0]",
        "the profile ranges over [0.5, 1.4]",
    );
    // a step that leaves it after the time span is fine; inside the span it is not
    assert!(
        load(&[
            "telescope.positions=[{kind=\"piecewise-constant\", times=[0, 20], values=[1.0, 2.0]}]"
        ])
        .is_ok()
    );
    rejects(
        &["telescope.positions=[{kind=\"piecewise-constant\", times=[0, 10], values=[1.0, 2.0]}]"],
        "telescope.positions[0]",
        "overlap",
    );
    // a longer inner section: the overlap is bounded by the shorter outer one
    assert!(load(&["sections.length=[1.0, 2.0]", "telescope.positions=[0.0001]"]).is_ok());
    rejects(
        &["sections.length=[2.0, 1.0]", "telescope.positions=[0.5]"],
        "telescope.positions[0]",
        "(0, 1]",
    );
    rejects(
        &["telescope.positions=[]"],
        "telescope.positions",
        "one profile per overlap",
    );
}

#[test]
fn profile_times_must_increase() {
    rejects(
        &["drive.force={kind=\"piecewise-constant\", times=[0, 4, 4], values=[1, 2, 3]}"],
        "drive.force.times",
        "strictly increasing (times[2] = 4 follows 4)",
    );
    rejects(
        &["drive.force={kind=\"piecewise-linear\", times=[0, 1], values=[1]}"],
        "drive.force.values",
        "one value per time",
    );
    rejects(
        &["drive.force={kind=\"piecewise-linear\", times=[], values=[]}"],
        "drive.force.times",
        "must not be empty",
    );
    rejects(
        &["telescope.positions=[{kind=\"smoothstep\", start=5, end=5, from=0.5, to=1}]"],
        "telescope.positions[0].end",
        "must be after start",
    );
}

#[test]
fn the_time_span_must_not_be_empty() {
    rejects(&["time.end=0"], "time.end", "the time span is empty");
    rejects(&["time.start=20"], "time.end", "the time span is empty");
    rejects(&["time.sample=0"], "time.sample", "finite number > 0");
    rejects(
        &["time.sample=100"],
        "time.sample",
        "must not exceed the time span",
    );
}

#[test]
fn the_drive_is_a_force_or_a_motion() {
    rejects(
        &["drive.motion=0.0"],
        "drive",
        "either `force` or `motion`, not both",
    );
    let text = BASE.replace("force = { kind = \"piecewise-constant\", times = [0, 4, 8, 12], values = [100, 0, -100, 0] }\n", "");
    let err = Scene::from_toml_str(&text, Path::new("x.toml"), &[])
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("`drive`") && err.contains("needs `force`"),
        "{err}"
    );
    let motion = Scene::from_toml_str(
        &text,
        Path::new("x.toml"),
        &["drive.motion={kind=\"smoothstep\", start=0, end=8, from=0, to=10}".into()],
    )
    .unwrap();
    assert!(matches!(
        motion.params.drive,
        Drive::Motion(Profile::Shaped(_))
    ));
    let err = Scene::from_toml_str(
        &text,
        Path::new("x.toml"),
        &["drive.motion={kind=\"piecewise-linear\", times=[0, 1], values=[0, 1]}".into()],
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("drive.motion") && err.contains("continuous velocity"),
        "{err}"
    );
}

#[test]
fn all_broken_rules_are_reported_at_once() {
    let err = load(&["contact.points=1", "sections.modes=40", "time.end=-1"]).unwrap_err();
    let fields: Vec<&str> = err
        .field_errors()
        .iter()
        .map(|e| e.field.as_str())
        .collect();
    assert_eq!(fields, ["sections.modes", "time.end", "contact.points"]);
    assert!(
        err.to_string().contains("with overrides contact.points=1"),
        "the message says the values came from overrides"
    );
}

#[test]
fn overrides_set_values_and_report_malformed_keys() {
    let s = load(&[
        "contact.clearance=0.02",
        "sections.length.1=1.2",
        "gravity.force_flow=none",
    ])
    .unwrap();
    assert_eq!(s.params.contact.clearance, 0.02);
    assert_eq!(s.params.sections[1].length, 1.2);
    assert_eq!(s.params.force_flow, telescopic_runtime::ForceFlow::None);
    let cases = [
        ("contact.clearance", "expected KEY=VALUE"),
        ("=3", "the key is empty"),
        (
            "sections.length.5=1",
            "index 5 is past the end of a list of 2",
        ),
        ("sections.length.x=1", "a list takes a numeric index"),
        ("masses.vehicle.kg=1", "is a float, not a table or list"),
    ];
    for (arg, rule) in cases {
        let err = load(&[arg]).unwrap_err();
        assert!(matches!(err, SceneError::Override { .. }), "{arg}: {err}");
        assert!(err.to_string().contains(rule), "{arg}: {err}");
    }
}

#[test]
fn syntax_errors_give_the_line() {
    let err = Scene::from_toml_str(
        "name = \"x\"\n[sections\ncount = 2\n",
        Path::new("bad.toml"),
        &[],
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("bad.toml") && err.contains("line 2"), "{err}");
}

#[test]
fn shipped_scenes_are_valid() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
    let mut count = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            Scene::load(&path, &[]).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            count += 1;
        }
    }
    assert!(count >= 1);
}

#[test]
fn sizes_are_bounded_before_anything_is_allocated() {
    // a count that would ask for terabytes is refused at once, by its bound
    let start = std::time::Instant::now();
    rejects(
        &["sections.count=1000000000000"],
        "sections.count",
        "must be in 1..=16 (got 1000000000000)",
    );
    assert!(
        start.elapsed().as_secs_f64() < 1.0,
        "validation must not allocate by the count"
    );
    rejects(
        &["contact.points=33"],
        "contact.points",
        "must be in 2..=32 (got 33)",
    );
    // 16 s every picosecond: 1.6e13 samples
    rejects(
        &["time.sample=1e-12"],
        "time.sample",
        "more than the limit of 100000000 output values",
    );
    rejects(
        &["time.sample=1e-300"],
        "time.sample",
        "raise time.sample to at least",
    );
    // at the limit: 2 sections, 2 contacts: 8 columns; 1e8 / 8 samples over 16 s is fine
    assert!(load(&["time.sample=2e-6"]).is_ok());
    assert!(load(&["sections.count=16", "telescope.positions=[1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0]", "sections.length=1.35"]).is_ok());
}

#[test]
fn derived_section_properties_must_exist_in_double_precision() {
    // each value is finite and positive, their product is not
    rejects(
        &["sections.area=[1e305, 0.001]"],
        "sections.area[0] and sections.density[0]",
        "the mass per length, must be a finite number > 0",
    );
    rejects(
        &["sections.inertia=1e-200", "sections.youngs_modulus=1e-200"],
        "sections.youngs_modulus[1] and sections.inertia[1]",
        "= 0)",
    );
}

#[test]
fn figures_name_outputs_each_once() {
    let s = load(&[
        "figures.panels=[\"tip_rel\", \"xi_2_1\"]",
        "figures.paper={ tip_rel = \"Fig. 9\" }",
    ])
    .unwrap();
    let panels = s.figures.panels.as_deref().unwrap();
    assert_eq!(
        panels,
        [
            telescopic_runtime::Output::TipRel,
            telescopic_runtime::Output::Gap {
                overlap: 2,
                point: 1
            }
        ]
    );
    assert_eq!(
        s.figures.paper_figure(telescopic_runtime::Output::TipRel),
        Some("Fig. 9")
    );
    rejects(
        &["figures.panels=[\"tip\"]"],
        "figures.panels[0]",
        "no output of a run",
    );
    rejects(
        &["figures.panels=[\"vehicle\", \"vehicle\"]"],
        "figures.panels[1]",
        "names an output twice",
    );
    rejects(
        &["figures.paper={ top9 = \"Fig. 1\" }"],
        "figures.paper.top9",
        "no output",
    );
    rejects(&["figures.colour=1"], "colour", "unknown field");
}
