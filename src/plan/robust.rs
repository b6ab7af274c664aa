//! The plants a plan must work on: the scene as given, and a box of scene values
//! (`masses.load=10:30,contact.clearance=0.005:0.02`): its corners and centre, which the
//! planner evaluates, and interior points it does not, which check it. Without a box, the
//! scene's neighbours check it: a plan that settles only on the plant it was tuned on says
//! so.

use crate::key_range::{RangeRule, parse_key_ranges};
use crate::{Error, OptionName, Result};
use telescopic_runtime::Scene;

/// One uncertain scene value and its range.
#[derive(Debug, Clone, PartialEq)]
pub struct RobustRange {
    /// The scene key, a continuous scene value (`masses.load`;
    /// [`telescopic_runtime::scene::KEYS`]).
    pub key: String,
    /// Smallest value.
    pub low: f64,
    /// Largest value.
    pub high: f64,
}

/// The error of a `--robust` entry breaking `rule`.
fn bad(entry: &str, rule: &str) -> Error {
    Error::option(OptionName::Robust, format!("{entry}: {rule}"))
}

/// Most ranges: the corners double with each.
pub const MAX_RANGES: usize = 6;

impl RobustRange {
    /// Parses `KEY=LOW:HIGH,KEY=LOW:HIGH,...`.
    ///
    /// # Errors
    /// [`Error::Option`] naming the entry and the rule.
    pub fn parse_list(text: &str) -> Result<Vec<RobustRange>> {
        let entries: Vec<(String, f64, f64)> =
            parse_key_ranges(text, OptionName::Robust, RangeRule::Required)?
                .into_iter()
                .filter_map(|e| e.range.map(|(low, high)| (e.key, low, high)))
                .collect();
        Self::list(&entries)
    }

    /// The ranges `(key, low, high)`, each checked: a continuous scene key
    /// ([`telescopic_runtime::scene::KEYS`]) given once, finite bounds with `low < high`, at
    /// most [`MAX_RANGES`].
    ///
    /// # Errors
    /// [`Error::Option`] naming the entry and the rule.
    pub fn list(entries: &[(String, f64, f64)]) -> Result<Vec<RobustRange>> {
        let mut out: Vec<RobustRange> = Vec::new();
        for (key, low, high) in entries {
            let (key, low, high) = (key.trim(), *low, *high);
            // shortest round-trip form: 1e300, not a 301-digit integer
            let entry = format!("{key}={low:?}:{high:?}");
            if !(low.is_finite() && high.is_finite()) {
                return Err(bad(&entry, "LOW and HIGH must be finite numbers"));
            }
            if low >= high {
                return Err(bad(&entry, "LOW must be below HIGH"));
            }
            telescopic_runtime::scene::SceneKey::parse(key).map_err(|rule| bad(&entry, &rule))?;
            if out.iter().any(|r| r.key == key) {
                return Err(bad(&entry, "the key is given twice"));
            }
            out.push(RobustRange {
                key: key.to_string(),
                low,
                high,
            });
        }
        if out.len() > MAX_RANGES {
            return Err(Error::option(
                OptionName::Robust,
                format!(
                    "{} ranges; at most {MAX_RANGES} (their {} corners are all run)",
                    out.len(),
                    1usize << out.len()
                ),
            ));
        }
        Ok(out)
    }
}

/// A plant: a name and the scene values that make it from the scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Plant {
    /// `nominal`, `corner 1` .., `centre`, `check 1` ..
    pub name: String,
    /// `(key, value)` of each uncertain scene value.
    pub values: Vec<(String, f64)>,
}

/// The plants the planner evaluates: the nominal scene, then the corners and the centre of
/// the box (none without ranges).
pub fn evaluated_plants(ranges: &[RobustRange]) -> Vec<Plant> {
    let mut plants = vec![Plant {
        name: "nominal".into(),
        values: Vec::new(),
    }];
    if ranges.is_empty() {
        return plants;
    }
    for corner in 0..(1usize << ranges.len()) {
        let fractions: Vec<f64> = (0..ranges.len())
            .map(|i| f64::from(u8::from(corner >> i & 1 == 1)))
            .collect();
        plants.push(plant(format!("corner {}", corner + 1), ranges, &fractions));
    }
    plants.push(plant("centre".into(), ranges, &vec![0.5; ranges.len()]));
    plants
}

/// How many plants [`evaluated_plants`] gives for `ranges` ranges: the nominal one, then
/// the corners and the centre of the box.
pub fn evaluated_plant_count(ranges: usize) -> usize {
    if ranges == 0 {
        1
    } else {
        2 + (1usize << ranges.min(MAX_RANGES))
    }
}

/// Plants inside the box the planner did not evaluate: points of a fixed low-discrepancy
/// (Halton) sequence, away from the corners and the centre; none without a box.
pub fn check_plants(ranges: &[RobustRange], count: usize) -> Vec<Plant> {
    const BASES: [u32; MAX_RANGES] = [2, 3, 5, 7, 11, 13];
    if ranges.is_empty() {
        return Vec::new();
    }
    (1..=count)
        .map(|n| {
            let fractions: Vec<f64> = (0..ranges.len())
                .map(|i| 0.1 + 0.8 * halton(n as u32, BASES[i]))
                .collect();
            plant(format!("check {n}"), ranges, &fractions)
        })
        .collect()
}

/// How far a neighbour moves its value (a share of the scene's): 1 %.
pub const NEIGHBOUR_SHARE: f64 = 0.01;

/// The values a neighbour moves, their names in the table and in a sentence: the load, the
/// beams' Young's modulus and the clearance.
pub const NEIGHBOUR_KEYS: [(&str, &str, &str); 3] = [
    ("masses.load", "load", "load"),
    ("sections.youngs_modulus", "E", "E"),
    ("contact.clearance", "clear", "clearance"),
];

/// Which plants check a plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CheckPlants {
    /// Points inside the robust box that the planner did not evaluate ([`check_plants`]).
    InsideTheBox,
    /// The scene's neighbours ([`neighbours`]): a plan without a robust box.
    Neighbours,
}

/// The plants that check a plan of `scene` with the robust box `ranges`: `count` plants
/// inside the box; without a box, the scene's [`neighbours`] (none when `count` is 0).
pub fn checking_plants(
    scene: &Scene,
    ranges: &[RobustRange],
    count: usize,
) -> (CheckPlants, Vec<Plant>) {
    if ranges.is_empty() {
        let plants = if count == 0 {
            Vec::new()
        } else {
            neighbours(scene)
        };
        (CheckPlants::Neighbours, plants)
    } else {
        (CheckPlants::InsideTheBox, check_plants(ranges, count))
    }
}

/// The values of [`NEIGHBOUR_KEYS`] that `scene` sets above zero: the entries and the value.
pub fn neighbour_values(scene: &Scene) -> Vec<((&'static str, &'static str, &'static str), f64)> {
    NEIGHBOUR_KEYS
        .into_iter()
        .filter_map(|entry| {
            let value = scene.value(entry.0).ok().filter(|v| *v > 0.0)?;
            Some((entry, value))
        })
        .collect()
}

/// The scene's neighbours: each of its [`neighbour_values`] moved alone by
/// -[`NEIGHBOUR_SHARE`] and +[`NEIGHBOUR_SHARE`].
pub fn neighbours(scene: &Scene) -> Vec<Plant> {
    let mut plants = Vec::new();
    for ((key, short, _), value) in neighbour_values(scene) {
        for sign in [-1.0, 1.0] {
            plants.push(Plant {
                name: format!("{short} {:+.0}%", 100.0 * sign * NEIGHBOUR_SHARE),
                values: vec![(key.to_string(), value * (1.0 + sign * NEIGHBOUR_SHARE))],
            });
        }
    }
    plants
}

/// The `n`-th element of the van der Corput sequence in `base`, in (0, 1).
fn halton(mut n: u32, base: u32) -> f64 {
    let (mut value, mut scale) = (0.0, 1.0);
    while n > 0 {
        scale /= f64::from(base);
        value += scale * f64::from(n % base);
        n /= base;
    }
    value
}

/// The plant at `fractions` of each range.
fn plant(name: String, ranges: &[RobustRange], fractions: &[f64]) -> Plant {
    Plant {
        name,
        values: ranges
            .iter()
            .zip(fractions)
            .map(|(r, &u)| (r.key.clone(), r.low + u * (r.high - r.low)))
            .collect(),
    }
}

/// `scene` as `plant`: its values set by key ([`Scene::with_values`]).
///
/// # Errors
/// [`Error::Scene`] naming the key when a value is refused.
pub fn plant_scene(scene: &Scene, plant: &Plant) -> Result<Scene> {
    let values: Vec<(&str, f64)> = plant.values.iter().map(|(k, v)| (k.as_str(), *v)).collect();
    Ok(scene.with_values(&values)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plan_without_a_box_is_checked_on_the_scenes_neighbours() {
        let scene = Scene::load(std::path::Path::new("scenes/case-study.toml"), &[]).unwrap();
        let (kind, plants) = checking_plants(&scene, &[], 4);
        assert_eq!(kind, CheckPlants::Neighbours);
        let names: Vec<&str> = plants.iter().map(|p| p.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "load -1%",
                "load +1%",
                "E -1%",
                "E +1%",
                "clear -1%",
                "clear +1%"
            ]
        );
        // each moves one value by 1 % of the scene's, and makes a valid scene
        for p in &plants {
            assert_eq!(p.values.len(), 1);
            let (key, value) = &p.values[0];
            let given = scene.value(key).unwrap();
            assert!(
                ((value / given - 1.0).abs() - NEIGHBOUR_SHARE).abs() < 1e-12,
                "{p:?}"
            );
            assert_eq!(plant_scene(&scene, p).unwrap().value(key).unwrap(), *value);
        }
        // without clearance no clearance neighbour; with no checks asked, none
        let linear = Scene::load(
            std::path::Path::new("scenes/case-study-no-clearance.toml"),
            &[],
        )
        .unwrap();
        assert_eq!(checking_plants(&linear, &[], 4).1.len(), 4);
        assert!(checking_plants(&scene, &[], 0).1.is_empty());
    }

    /// Typed entries (Python's) and the option's text give the same ranges, and the same
    /// rules refuse them, naming the entry.
    #[test]
    fn typed_ranges_are_the_texts_and_refused_by_the_same_rules() {
        let text =
            RobustRange::parse_list("masses.load=10:30, contact.clearance=0.005:0.02").unwrap();
        let typed = RobustRange::list(&[
            ("masses.load".into(), 10.0, 30.0),
            ("contact.clearance".into(), 0.005, 0.02),
        ])
        .unwrap();
        assert_eq!(text, typed);
        let refused =
            |entries: &[(String, f64, f64)]| RobustRange::list(entries).unwrap_err().to_string();
        assert!(refused(&[("masses.lod".into(), 1.0, 2.0)]).contains("masses.lod"));
        assert!(refused(&[("masses.load".into(), f64::NAN, 2.0)]).contains("finite"));
        assert!(refused(&[("masses.load".into(), 3.0, 2.0)]).contains("below"));
        let huge = refused(&[("masses.lod".into(), 1e300, 2e300)]);
        assert!(huge.contains("masses.lod=1e300:2e300"), "{huge}");
        let twice = [
            ("masses.load".to_string(), 1.0, 2.0),
            ("masses.load".into(), 1.0, 3.0),
        ];
        assert!(refused(&twice).contains("twice"));
        assert!(
            RobustRange::parse_list("masses.load=1:nan")
                .unwrap_err()
                .to_string()
                .contains("finite")
        );
    }
}
