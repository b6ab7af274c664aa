//! The scene file format (TOML). Every table rejects unknown keys. See the README for a
//! complete, commented example.

use crate::model::params::ForceFlow;
use crate::profile::Profile;
use serde::de::{self, Deserializer, SeqAccess, Visitor};
use serde::{Deserialize, Serialize};
use std::fmt;
use std::marker::PhantomData;

/// A scene file as written.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Short name, used in titles and file names.
    pub name: String,
    /// One line on what the scene is.
    #[serde(default)]
    pub description: String,
    /// The whole error in `tip_rel` against the beams that runs of this scene meet by
    /// default (m); `None`: the scene's modes, integrated to 1e-6 m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub accuracy: Option<f64>,
    /// Geometry, materials and modes of the sections.
    pub sections: SectionsSpec,
    /// Vehicle and load masses.
    pub masses: MassesSpec,
    /// Gravity and how it loads the sections.
    pub gravity: GravitySpec,
    /// Contacts between neighbouring sections.
    #[serde(default)]
    pub contact: Option<ContactSpec>,
    /// Telescopic positions `a_k(t)`.
    #[serde(default)]
    pub telescope: Option<TelescopeSpec>,
    /// What drives the vehicle.
    pub drive: DriveSpec,
    /// Time span and output sampling.
    pub time: TimeSpec,
    /// Published values to compare with (printed beside ours by `telescopic modes`).
    #[serde(default)]
    pub reference: Vec<ReferenceSpec>,
    /// What a run's figure draws.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub figures: Option<FiguresSpec>,
}

impl SceneFile {
    /// The scene file as TOML text, readable by [`crate::Scene::from_toml_str`].
    pub fn to_toml(&self) -> String {
        // the serializer refuses shapes (a map with keys that are not strings, a value
        // after a table), never values; this schema has none of those shapes
        toml::to_string(self).expect("the scene schema serializes as TOML")
    }
}

/// `[figures]`: the panels of a run's figure and the paper's figures they reproduce.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FiguresSpec {
    /// The outputs drawn, one panel each, in order (default: the vehicle, `tip_rel`,
    /// `top1_rel`, the drive force and the gaps and contact forces).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub panels: Option<Vec<String>>,
    /// The paper's figure each output's panel reproduces (`tip_rel = "Fig. 9"`), named in
    /// the panel's title.
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub paper: std::collections::BTreeMap<String, String>,
}

/// `[sections]`: per-section values are one number (shared) or a list (one per section,
/// from the bottom up).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SectionsSpec {
    /// Number of sections `n >= 1`.
    pub count: usize,
    /// Lengths `l_k` (m).
    pub length: PerSection<f64>,
    /// Cross-section areas `A_k` (m^2).
    pub area: PerSection<f64>,
    /// Second moments of area `I_k` (m^4).
    pub inertia: PerSection<f64>,
    /// Densities `rho` (kg/m^3).
    pub density: PerSection<f64>,
    /// Young's moduli `E` (N/m^2).
    pub youngs_modulus: PerSection<f64>,
    /// Shape functions per section `N_k`, 1..=30.
    pub modes: PerSection<usize>,
    /// `"modes"` (default: the paper's shape functions) or `"modes+static"` (with each
    /// section's static correction shapes).
    #[serde(default, skip_serializing_if = "is_default_basis")]
    pub basis: crate::model::params::Basis,
    /// Modal structural damping ratio (1), in `[0, 1)`: one number for every elastic mode of the
    /// open-contact structure, or a list by mode in ascending frequency (modes beyond the
    /// list take its last value). Default: no structural damping.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping_ratio: Option<PerSection<f64>>,
    /// Rayleigh damping's mass coefficient `alpha` (1/s), >= 0; not with `damping_ratio`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rayleigh_alpha: Option<f64>,
    /// Rayleigh damping's stiffness coefficient `beta` (s), >= 0; not with `damping_ratio`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rayleigh_beta: Option<f64>,
    /// Section moduli `W_k` (m^3) for bending stresses `M / W`; or give `height`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub section_modulus: Option<PerSection<f64>>,
    /// Section heights `h_k` (m) in the bending plane, for a section symmetric about its
    /// bending axis: `W = 2 I / h`. Not with `section_modulus`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<PerSection<f64>>,
}

fn is_default_basis(b: &crate::model::params::Basis) -> bool {
    *b == crate::model::params::Basis::Modes
}

/// `[masses]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MassesSpec {
    /// Vehicle mass `m_T` (kg), >= 0.
    pub vehicle: f64,
    /// Load mass `m_L` at the top of the last section (kg), >= 0.
    pub load: f64,
}

/// `[gravity]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GravitySpec {
    /// Gravitational acceleration `g` (m/s^2), >= 0.
    pub g: f64,
    /// `"cable"` (default), `"external"` or `"none"`.
    #[serde(default)]
    pub force_flow: ForceFlow,
}

/// `[contact]`: required when there is more than one section.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// Contact points per overlap `n_c >= 2`.
    pub points: usize,
    /// Contact stiffness `c` (N/m), > 0.
    pub stiffness: f64,
    /// Contact damping `d` (N s/m), >= 0.
    pub damping: f64,
    /// Total clearance `l_S` (m), >= 0.
    pub clearance: f64,
}

/// `[telescope]`: required when there is more than one section.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TelescopeSpec {
    /// `a_k(t)` for `k = 2..n` (m): where the foot of section `k` sits along section `k-1`.
    pub positions: Vec<Profile>,
}

/// `[drive]`: exactly one of `force` and `motion`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DriveSpec {
    /// Force on the vehicle `F(t)` (N).
    #[serde(default)]
    pub force: Option<Profile>,
    /// Prescribed vehicle position `s(t)` (m); needs a continuous rate.
    #[serde(default)]
    pub motion: Option<Profile>,
}

/// `[time]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeSpec {
    /// Start time (s); default 0.
    #[serde(default)]
    pub start: f64,
    /// End time (s), after `start`.
    pub end: f64,
    /// Output sample interval (s), > 0 and at most the span.
    pub sample: f64,
}

/// `[[reference]]`: one column of published frequencies.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceSpec {
    /// Column heading, e.g. "test rig (Table I)".
    pub label: String,
    /// Frequencies (Hz), ascending, rigid modes excluded.
    pub frequencies_hz: Vec<f64>,
}

/// One value shared by all sections, or one per section.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum PerSection<T> {
    /// The same value for every section.
    Shared(T),
    /// One value per section, from the bottom up.
    Each(Vec<T>),
}

impl<T: Copy> PerSection<T> {
    /// The value for section `k` (1-based), if there is one.
    pub fn get(&self, k: usize) -> Option<T> {
        match self {
            PerSection::Shared(v) => Some(*v),
            PerSection::Each(v) => v.get(k - 1).copied(),
        }
    }

    /// Number of values given (`None` for a shared value).
    pub fn given(&self) -> Option<usize> {
        match self {
            PerSection::Shared(_) => None,
            PerSection::Each(v) => Some(v.len()),
        }
    }
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for PerSection<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct PerSectionVisitor<T>(PhantomData<T>);
        impl<'de, T: Deserialize<'de>> Visitor<'de> for PerSectionVisitor<T> {
            type Value = PerSection<T>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(
                    "a number (shared by all sections) or a list with one number per section",
                )
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Self::Value, E> {
                T::deserialize(de::value::F64Deserializer::new(v)).map(PerSection::Shared)
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Self::Value, E> {
                T::deserialize(de::value::I64Deserializer::new(v)).map(PerSection::Shared)
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Self::Value, E> {
                T::deserialize(de::value::U64Deserializer::new(v)).map(PerSection::Shared)
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Self::Value, A::Error> {
                Vec::<T>::deserialize(de::value::SeqAccessDeserializer::new(seq))
                    .map(PerSection::Each)
            }
        }
        deserializer.deserialize_any(PerSectionVisitor(PhantomData))
    }
}
