//! The scene values a fit frees (`--free KEY,KEY=LOW:HIGH`), their bounds, and the
//! coordinate the optimizer moves in: the logarithm of a positive value (a stiffness and a
//! load differ by nine decades), mapped into the bounds by a sine (MINUIT's transformation
//! of a bounded parameter), so that every step stays inside them and none is stranded: a
//! step past a bound comes back, where a logistic map's flat ends held a value that an early
//! step had thrown there.

use crate::key_range::{RangeRule, parse_key_ranges};
use crate::{Error, OptionName, Result};
use telescopic_runtime::Scene;
use telescopic_runtime::scene::SceneKey;

/// Without bounds a positive value may move this factor either way.
pub const DEFAULT_RANGE_FACTOR: f64 = 10.0;

/// Most free values in one fit.
pub const MAX_FREE: usize = 8;

/// A scene value to fit, as asked: its key and, optionally, its bounds.
#[derive(Debug, Clone, PartialEq)]
pub struct FreeValue {
    /// The scene key ([`telescopic_runtime::scene::KEYS`], a physical parameter).
    pub key: String,
    /// `(low, high)`; `None`: the scene's value divided and multiplied by
    /// [`DEFAULT_RANGE_FACTOR`].
    pub bounds: Option<(f64, f64)>,
}

/// The error of a `--free` entry breaking `rule`.
fn bad(entry: &str, rule: &str) -> Error {
    Error::option(OptionName::Free, format!("{entry}: {rule}"))
}

impl FreeValue {
    /// Parses `KEY,KEY=LOW:HIGH,...`.
    ///
    /// # Errors
    /// [`Error::Option`] naming the entry and the rule.
    pub fn parse_list(text: &str) -> Result<Vec<FreeValue>> {
        let entries = parse_key_ranges(text, OptionName::Free, RangeRule::Optional)?;
        Ok(entries
            .into_iter()
            .map(|e| FreeValue {
                key: e.key,
                bounds: e.range,
            })
            .collect())
    }

    /// Checks `values` against `scene` and gives each its start, bounds and scale.
    ///
    /// # Errors
    /// [`Error::Option`] naming the entry: not a physical scene key of this scene, given
    /// twice, bounds not ordered or not holding the scene's value, a value of zero without
    /// bounds, more than [`MAX_FREE`] or none.
    pub fn resolve(values: &[FreeValue], scene: &Scene) -> Result<Vec<Free>> {
        if values.is_empty() {
            return Err(Error::option(
                OptionName::Free,
                "name at least one scene value to fit, e.g. sections.youngs_modulus",
            ));
        }
        if values.len() > MAX_FREE {
            return Err(Error::option(
                OptionName::Free,
                format!("{} values; at most {MAX_FREE} in one fit", values.len()),
            ));
        }
        let mut out: Vec<Free> = Vec::new();
        for value in values {
            let entry = &value.key;
            let key = SceneKey::parse(entry).map_err(|rule| bad(entry, &rule))?;
            if !key.field.parameter {
                return Err(bad(
                    entry,
                    "is not a physical parameter (the time grid is the record's)",
                ));
            }
            if out.iter().any(|f| f.key == *entry) {
                return Err(bad(entry, "is given twice"));
            }
            let start = scene.value(entry).map_err(|rule| bad(entry, &rule))?;
            let (low, high) = match value.bounds {
                Some(b) => b,
                None if start > 0.0 => (start / DEFAULT_RANGE_FACTOR, start * DEFAULT_RANGE_FACTOR),
                None => {
                    return Err(bad(
                        entry,
                        &format!("its value in the scene is {start}: give bounds, KEY=LOW:HIGH"),
                    ));
                }
            };
            if low >= high {
                return Err(bad(entry, "LOW must be below HIGH"));
            }
            if !(low..=high).contains(&start) {
                return Err(bad(
                    entry,
                    &format!(
                        "the scene's value {start} is outside {low}:{high}: the fit starts there"
                    ),
                ));
            }
            out.push(Free {
                key: entry.clone(),
                unit: key.field.unit,
                start,
                low,
                high,
                logarithmic: low > 0.0,
            });
        }
        check_products(&out)?;
        Ok(out)
    }
}

/// Scene values the beams see only as a product (docs/model.md: `EI` of a section): no
/// record determines both factors.
const PRODUCTS: [(&str, &str); 1] = [("sections.youngs_modulus", "sections.inertia")];

/// Refuses two free values that enter the model only as a product.
fn check_products(free: &[Free]) -> Result<()> {
    let is_free = |key: &str| free.iter().any(|f| f.key == key);
    match PRODUCTS.iter().find(|(a, b)| is_free(a) && is_free(b)) {
        Some((first, second)) => Err(bad(
            second,
            &format!(
                "a record does not determine {second} beside {first}: the beams see only \
                 their product E I; free one of them"
            ),
        )),
        None => Ok(()),
    }
}

/// A free value, resolved: where the fit starts and the box it stays in.
#[derive(Debug, Clone, PartialEq)]
pub struct Free {
    /// The scene key.
    pub key: String,
    /// Its SI unit.
    pub unit: &'static str,
    /// The scene's value, where the fit starts.
    pub start: f64,
    /// Lower bound.
    pub low: f64,
    /// Upper bound.
    pub high: f64,
    /// Whether the fit moves its logarithm (bounds both positive) or the value itself.
    pub logarithmic: bool,
}

/// Share of the box a start on a bound moves in by (on the bound the sine is flat).
const EDGE: f64 = 1e-6;

impl Free {
    /// The scale coordinate `theta` of `value`: its logarithm, or itself.
    pub fn theta(&self, value: f64) -> f64 {
        if self.logarithmic { value.ln() } else { value }
    }

    /// The value of scale coordinate `theta`.
    pub fn value_of_theta(&self, theta: f64) -> f64 {
        if self.logarithmic { theta.exp() } else { theta }
    }

    /// The bounds in the scale coordinate.
    pub fn theta_bounds(&self) -> (f64, f64) {
        (self.theta(self.low), self.theta(self.high))
    }

    /// The optimizer's coordinate `u` of `value`, in `[-pi/2, pi/2]`: `theta`'s share `s` of
    /// the bounds is `(1 + sin u) / 2`.
    pub fn u_of(&self, value: f64) -> f64 {
        let (a, b) = self.theta_bounds();
        let s = ((self.theta(value) - a) / (b - a)).clamp(EDGE, 1.0 - EDGE);
        (2.0 * s - 1.0).asin()
    }

    /// The scale coordinate of `u` (any real: the sine folds it into the bounds).
    pub fn theta_of_u(&self, u: f64) -> f64 {
        let (a, b) = self.theta_bounds();
        a + (b - a) * 0.5 * (1.0 + u.sin())
    }

    /// The value of `u`, inside the bounds.
    pub fn value_of_u(&self, u: f64) -> f64 {
        self.value_of_theta(self.theta_of_u(u))
            .clamp(self.low, self.high)
    }

    /// `d theta / d u` at `u`.
    pub fn dtheta_du(&self, u: f64) -> f64 {
        let (a, b) = self.theta_bounds();
        (b - a) * 0.5 * u.cos()
    }

    /// Whether `value` sits on a bound (within 0.1 % of the box in the scale coordinate): the
    /// fit then did not determine it.
    pub fn at_bound(&self, value: f64) -> bool {
        let (a, b) = self.theta_bounds();
        let s = (self.theta(value) - a) / (b - a);
        !(1e-3..=1.0 - 1e-3).contains(&s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene() -> Scene {
        Scene::load("scenes/adams-linear.toml".as_ref(), &[]).unwrap()
    }

    #[test]
    fn the_coordinates_map_back_and_stay_inside_the_bounds() {
        let free = FreeValue::resolve(
            &FreeValue::parse_list("masses.load, contact.damping=0:5000").unwrap(),
            &scene(),
        )
        .unwrap();
        assert!(free[0].logarithmic && !free[1].logarithmic);
        assert!((free[0].low - 1.7897).abs() < 1e-12 && (free[0].high - 178.97).abs() < 1e-9);
        for f in &free {
            let u = f.u_of(f.start);
            assert!((f.value_of_u(u) - f.start).abs() < 1e-9 * f.start.abs().max(1.0));
            for u in [-1e3, -30.0, 0.0, 30.0, 1e3] {
                let v = f.value_of_u(u);
                assert!((f.low..=f.high).contains(&v), "{} at u {u}: {v}", f.key);
            }
            // the derivative is the sine's
            let h = 1e-6;
            let numeric = (f.theta_of_u(0.3 + h) - f.theta_of_u(0.3 - h)) / (2.0 * h);
            assert!((numeric - f.dtheta_du(0.3)).abs() < 1e-6 * numeric.abs());
        }
    }

    #[test]
    fn bad_free_values_are_refused_naming_the_entry() {
        let refused = |text: &str| {
            FreeValue::parse_list(text)
                .and_then(|v| FreeValue::resolve(&v, &scene()))
                .unwrap_err()
                .to_string()
        };
        assert!(refused("masses.lod").contains("masses.lod"));
        assert!(refused("time.end").contains("not a physical parameter"));
        assert!(refused("masses.load,masses.load").contains("given twice"));
        assert!(refused("masses.load=30:10").contains("LOW must be below HIGH"));
        assert!(refused("masses.load=30:40").contains("outside 30:40"));
        assert!(refused("contact.clearance").contains("give bounds"));
        assert!(refused("masses.load=a:b").contains("finite numbers"));
        assert!(refused("").contains("at least one"));
        let product = refused("sections.youngs_modulus,masses.load,sections.inertia");
        assert!(
            product.contains("does not determine sections.inertia beside sections.youngs_modulus"),
            "{product}"
        );
    }
}
