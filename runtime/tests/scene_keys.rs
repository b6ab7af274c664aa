//! Typed scene edits: `Scene::with_values` gives the scene that `--set KEY=VALUE` (the text
//! path: TOML written, parsed and validated) gives, for every continuous key of every shipped
//! scene; bad keys and values are refused naming the key.

use telescopic_runtime::Scene;
use telescopic_runtime::scene::KEYS;

const SCENES: [&str; 6] = [
    "adams-linear",
    "adams-clearance",
    "case-study",
    "case-study-no-clearance",
    "test-rig",
    "three-section",
];

fn load(name: &str, overrides: &[String]) -> Scene {
    Scene::load(format!("../scenes/{name}.toml").as_ref(), overrides).unwrap()
}

/// A new value near `v` that keeps the scene valid (a zero becomes a small positive value).
fn changed(key: &str, v: f64) -> f64 {
    match key {
        "time.start" => v - 0.01,
        _ if v == 0.0 => 1e-3,
        _ => v * 1.05,
    }
}

#[test]
fn every_typed_edit_is_the_set_override_of_the_same_value() {
    let mut checked = 0;
    for name in SCENES {
        let scene = load(name, &[]);
        let sections = scene.params.sections.len();
        let mut keys: Vec<String> = Vec::new();
        for f in KEYS {
            keys.push(f.path.to_string());
            if f.per_section {
                keys.extend((0..sections).map(|i| format!("{}.{i}", f.path)));
            }
        }
        for key in keys {
            let key = key.as_str();
            let Ok(value) = scene.value(key) else {
                continue; // not a value of this scene (no contacts, a moving position, ...)
            };
            let new = changed(key, value);
            let Ok(text) = Scene::load(
                format!("../scenes/{name}.toml").as_ref(),
                &[format!("{key}={new:e}")],
            ) else {
                // the text path cannot index a shared value; the typed one can
                assert!(scene.with_values(&[(key, new)]).is_ok(), "{name} {key}");
                continue;
            };
            let typed = scene
                .with_values(&[(key, new)])
                .unwrap_or_else(|e| panic!("{name} {key} = {new}: {e}"));
            assert_eq!(typed.params, text.params, "{name} {key}");
            assert_eq!(typed.time, text.time, "{name} {key}");
            assert_eq!(typed.value(key).unwrap(), new, "{name} {key}");
            checked += 1;
        }
    }
    // every scene has at least the masses, gravity, sections and time
    assert!(checked >= 6 * 10, "{checked} edits checked");
}

#[test]
fn bad_edits_are_refused_naming_the_key_and_the_rule() {
    let scene = load("case-study", &[]);
    let message = |values: &[(&str, f64)]| scene.with_values(values).unwrap_err().to_string();
    let unknown = message(&[("contact.stifness", 1e8)]);
    assert!(unknown.contains("contact.stifness") && unknown.contains("not a continuous scene key"));
    let negative = message(&[("contact.clearance", -0.01)]);
    assert!(negative.contains("contact.clearance"), "{negative}");
    let nan = message(&[("masses.load", f64::NAN)]);
    assert!(
        nan.contains("masses.load") && nan.contains("finite"),
        "{nan}"
    );
    let past = message(&[("sections.length.2", 3.0)]);
    assert!(past.contains("index 2"), "{past}");
    let indexed = message(&[("masses.load.0", 3.0)]);
    assert!(indexed.contains("takes no index"), "{indexed}");
    // case-study's a_2 moves: it is not a held value to read or set
    assert!(scene.value("telescope.positions.0").is_err());
}

#[test]
fn one_section_of_a_shared_value_becomes_a_list() {
    let scene = load("adams-linear", &[]);
    let edited = scene.with_values(&[("sections.length.1", 1.2)]).unwrap();
    let lengths: Vec<f64> = edited.params.sections.iter().map(|s| s.length).collect();
    assert_eq!(lengths, vec![scene.params.sections[0].length, 1.2]);
}

#[test]
fn a_modal_damping_ratio_is_no_value_of_a_rayleigh_damped_scene() {
    let plain = load("case-study", &[]);
    assert_eq!(plain.value("sections.damping_ratio").unwrap(), 0.0);
    let rayleigh = load("case-study", &["sections.rayleigh_beta=1e-4".to_string()]);
    let error = rayleigh.value("sections.damping_ratio").unwrap_err();
    assert!(error.to_string().contains("Rayleigh"), "{error}");
    assert_eq!(rayleigh.value("sections.rayleigh_beta").unwrap(), 1e-4);
}
