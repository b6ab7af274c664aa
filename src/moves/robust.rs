//! The plants a plan must work on: the scene as given, and a box of scene values
//! (`masses.load=10:30,contact.clearance=0.005:0.02`): its corners and centre, which the
//! planner evaluates, and interior points it does not, which check it.

use crate::{Error, OptionName, Result};
use telescopic_runtime::Scene;

/// One uncertain scene value and its range.
#[derive(Debug, Clone, PartialEq)]
pub struct RobustRange {
    /// The scene key, as `--set` takes it (`masses.load`).
    pub key: String,
    /// Smallest value.
    pub low: f64,
    /// Largest value.
    pub high: f64,
}

/// Most ranges: the corners double with each.
pub const MAX_RANGES: usize = 6;

impl RobustRange {
    /// Parses `KEY=LOW:HIGH,KEY=LOW:HIGH,...`.
    ///
    /// # Errors
    /// [`Error::Option`] naming the entry and the rule.
    pub fn parse_list(text: &str) -> Result<Vec<RobustRange>> {
        let bad =
            |entry: &str, rule: &str| Error::option(OptionName::Robust, format!("{entry}: {rule}"));
        let mut out: Vec<RobustRange> = Vec::new();
        for entry in text.split(',').map(str::trim).filter(|e| !e.is_empty()) {
            let (key, range) = entry
                .split_once('=')
                .ok_or_else(|| bad(entry, "give KEY=LOW:HIGH, e.g. masses.load=10:30"))?;
            let (low, high) = range
                .split_once(':')
                .ok_or_else(|| bad(entry, "give the range as LOW:HIGH"))?;
            let number = |s: &str| {
                s.trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| bad(entry, "LOW and HIGH must be finite numbers"))
            };
            let (low, high) = (number(low)?, number(high)?);
            if low >= high {
                return Err(bad(entry, "LOW must be below HIGH"));
            }
            if out.iter().any(|r| r.key == key.trim()) {
                return Err(bad(entry, "the key is given twice"));
            }
            out.push(RobustRange {
                key: key.trim().to_string(),
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

/// A plant: a name and its overrides (`KEY=VALUE`).
#[derive(Debug, Clone, PartialEq)]
pub struct Plant {
    /// `nominal`, `corner 1` .., `centre`, `check 1` ..
    pub name: String,
    /// The overrides that make it from the scene.
    pub overrides: Vec<String>,
}

/// The plants the planner evaluates: the nominal scene, then the corners and the centre of
/// the box (none without ranges).
pub fn evaluated_plants(ranges: &[RobustRange]) -> Vec<Plant> {
    let mut plants = vec![Plant {
        name: "nominal".into(),
        overrides: Vec::new(),
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
        overrides: ranges
            .iter()
            .zip(fractions)
            .map(|(r, &u)| format!("{}={}", r.key, r.low + u * (r.high - r.low)))
            .collect(),
    }
}

/// The scene of the file `text` (TOML) named `name` with a plant's `overrides` (checked as
/// `--set` is).
///
/// # Errors
/// [`Error::Scene`] naming the key when an override is refused.
pub fn plant_scene(text: &str, name: &str, overrides: &[String]) -> Result<Scene> {
    Ok(Scene::from_toml_str(
        text,
        std::path::Path::new(name),
        overrides,
    )?)
}
