//! Every continuous value of a scene by its dotted key: its unit, what it is, whether it is
//! a physical parameter (what a sweep, a robust range or a fit varies), and how to read and
//! set it on the scene file. [`crate::Scene::with_values`] patches a scene through this
//! table and validates it again, without writing or parsing text.
//!
//! A per-section key names every section (`sections.length`: one value shared by all) or one
//! of them by its 0-based index, as `--set` does (`sections.length.1`, the second from the
//! bottom); `telescope.positions.0` is `a_2`. Setting one section of a shared value makes
//! it a list.

use super::schema::{ContactSpec, PerSection, SceneFile};
use crate::profile::Profile;

/// A continuous scene field.
#[derive(Debug)]
pub struct KeyField {
    /// Dotted key, as in the file and `--set` (`contact.stiffness`).
    pub path: &'static str,
    /// SI unit (`1` for a ratio).
    pub unit: &'static str,
    /// What it is.
    pub description: &'static str,
    /// Whether it is a physical parameter (not the time grid).
    pub parameter: bool,
    /// Whether it takes a section's index (`.k`).
    pub per_section: bool,
    get: fn(&SceneFile, Option<usize>) -> Result<f64, String>,
    set: fn(&mut SceneFile, Option<usize>, f64) -> Result<(), String>,
}

/// A key of [`KEYS`] with its section index, if any.
#[derive(Debug, Clone, Copy)]
pub struct SceneKey {
    /// The field.
    pub field: &'static KeyField,
    /// The 0-based index of a per-section field (`None`: every section).
    pub index: Option<usize>,
}

impl SceneKey {
    /// The key `text` (`contact.clearance`, `sections.length.1`).
    ///
    /// # Errors
    /// A message naming the key and the rule: not a continuous scene key, or an index on a
    /// field that has none.
    pub fn parse(text: &str) -> Result<Self, String> {
        let text = text.trim();
        if let Some(field) = KEYS.iter().find(|f| f.path == text) {
            return Ok(SceneKey { field, index: None });
        }
        if let Some((path, index)) = text.rsplit_once('.')
            && let Some(field) = KEYS.iter().find(|f| f.path == path)
        {
            let index = index
                .parse::<usize>()
                .map_err(|_| format!("`{text}`: `{index}` is not a section index (0, 1, ..)"))?;
            if !field.per_section {
                return Err(format!("`{path}` is one value, it takes no index"));
            }
            return Ok(SceneKey {
                field,
                index: Some(index),
            });
        }
        Err(format!(
            "`{text}` is not a continuous scene key; the keys are {}",
            KEYS.iter().map(|f| f.path).collect::<Vec<_>>().join(", ")
        ))
    }

    /// Its value in `file`.
    ///
    /// # Errors
    /// A message when the file has no such value (no contacts, an index past the end, a
    /// profile that is not a constant).
    pub fn get(&self, file: &SceneFile) -> Result<f64, String> {
        (self.field.get)(file, self.index)
    }

    /// Sets it to `value` in `file` (the scene's rules are checked when it is built).
    ///
    /// # Errors
    /// A message when the file has no such value to set.
    pub fn set(&self, file: &mut SceneFile, value: f64) -> Result<(), String> {
        (self.field.set)(file, self.index, value)
    }
}

/// `section`'s value of `values`, or the shared one.
fn get_per_section(values: &PerSection<f64>, index: Option<usize>) -> Result<f64, String> {
    match (values, index) {
        (PerSection::Shared(v), _) => Ok(*v),
        (PerSection::Each(v), Some(i)) => v
            .get(i)
            .copied()
            .ok_or_else(|| format!("index {i} is past the {} values", v.len())),
        (PerSection::Each(v), None) if v.windows(2).all(|w| w[0] == w[1]) && !v.is_empty() => {
            Ok(v[0])
        }
        (PerSection::Each(_), None) => {
            Err("the sections differ: name one by its index (`.0`, `.1`, ..)".into())
        }
    }
}

/// Sets one section of `values` (of `count` sections), or all of them.
fn set_per_section(
    values: &mut PerSection<f64>,
    count: usize,
    index: Option<usize>,
    value: f64,
) -> Result<(), String> {
    match index {
        None => *values = PerSection::Shared(value),
        Some(i) => {
            let mut each = match values {
                PerSection::Shared(v) => vec![*v; count],
                PerSection::Each(v) => v.clone(),
            };
            let len = each.len();
            *each
                .get_mut(i)
                .ok_or_else(|| format!("index {i} is past the {len} values"))? = value;
            *values = PerSection::Each(each);
        }
    }
    Ok(())
}

fn contact(file: &SceneFile) -> Result<&ContactSpec, String> {
    file.contact
        .as_ref()
        .ok_or_else(|| "the scene has no [contact] table (one section)".into())
}

fn contact_mut(file: &mut SceneFile) -> Result<&mut ContactSpec, String> {
    file.contact
        .as_mut()
        .ok_or_else(|| "the scene has no [contact] table (one section)".into())
}

fn constant(profile: &Profile) -> Result<f64, String> {
    match profile {
        Profile::Constant(v) => Ok(*v),
        Profile::Shaped(_) => Err("the profile is not a constant".into()),
    }
}

/// A per-section field of `[sections]`.
macro_rules! section_field {
    ($path:literal, $field:ident, $unit:literal, $description:literal) => {
        KeyField {
            path: $path,
            unit: $unit,
            description: $description,
            parameter: true,
            per_section: true,
            get: |f, i| get_per_section(&f.sections.$field, i),
            set: |f, i, v| {
                let count = f.sections.count;
                set_per_section(&mut f.sections.$field, count, i, v)
            },
        }
    };
}

/// A key that is one number of the file: how to read it and how to set it.
macro_rules! single_field {
    ($path:literal, $unit:literal, $description:literal, $parameter:literal,
     get |$g:ident| $get:expr, set |$s:ident, $v:ident| $set:expr) => {
        KeyField {
            path: $path,
            unit: $unit,
            description: $description,
            parameter: $parameter,
            per_section: false,
            get: |$g, _| Ok($get),
            set: |$s, _, $v| {
                $set;
                Ok(())
            },
        }
    };
}

/// An optional number of `[sections]`, zero when absent.
macro_rules! optional_section_field {
    ($path:literal, $field:ident, $unit:literal, $description:literal) => {
        single_field!(
            $path,
            $unit,
            $description,
            true,
            get | f | f.sections.$field.unwrap_or(0.0),
            set | f,
            v | f.sections.$field = Some(v)
        )
    };
}

/// A single number of the file, always present.
macro_rules! number_field {
    ($path:literal, $unit:literal, $description:literal, $parameter:literal, |$f:ident| $place:expr) => {
        single_field!(
            $path,
            $unit,
            $description,
            $parameter,
            get | $f | $place,
            set | $f,
            v | $place = v
        )
    };
}

/// A number of `[contact]`.
macro_rules! contact_field {
    ($path:literal, $field:ident, $unit:literal, $description:literal) => {
        single_field!(
            $path,
            $unit,
            $description,
            true,
            get | f | contact(f)?.$field,
            set | f,
            v | contact_mut(f)?.$field = v
        )
    };
}

/// Every continuous scene key.
pub static KEYS: &[KeyField] = &[
    section_field!("sections.length", length, "m", "section length l_k"),
    section_field!("sections.area", area, "m^2", "cross-section area A_k"),
    section_field!(
        "sections.inertia",
        inertia,
        "m^4",
        "second moment of area I_k"
    ),
    section_field!("sections.density", density, "kg/m^3", "density rho"),
    section_field!(
        "sections.youngs_modulus",
        youngs_modulus,
        "N/m^2",
        "Young's modulus E"
    ),
    KeyField {
        path: "sections.damping_ratio",
        unit: "1",
        description: "modal structural damping ratio of every elastic mode",
        parameter: true,
        per_section: false,
        get: |f, _| match &f.sections.damping_ratio {
            _ if f.sections.rayleigh_alpha.is_some() || f.sections.rayleigh_beta.is_some() => {
                Err("the scene's damping is Rayleigh's (sections.rayleigh_alpha, _beta)".into())
            }
            None => Ok(0.0),
            Some(PerSection::Shared(v)) => Ok(*v),
            Some(PerSection::Each(_)) => Err("the ratios differ by mode".into()),
        },
        set: |f, _, v| {
            f.sections.damping_ratio = Some(PerSection::Shared(v));
            Ok(())
        },
    },
    optional_section_field!(
        "sections.rayleigh_alpha",
        rayleigh_alpha,
        "1/s",
        "Rayleigh damping's mass coefficient alpha"
    ),
    optional_section_field!(
        "sections.rayleigh_beta",
        rayleigh_beta,
        "s",
        "Rayleigh damping's stiffness coefficient beta"
    ),
    number_field!("masses.vehicle", "kg", "vehicle mass m_T", true, |f| f
        .masses
        .vehicle),
    number_field!(
        "masses.load",
        "kg",
        "load mass m_L at the top of the last section",
        true,
        |f| f.masses.load
    ),
    number_field!(
        "gravity.g",
        "m/s^2",
        "gravitational acceleration g",
        true,
        |f| f.gravity.g
    ),
    contact_field!("contact.stiffness", stiffness, "N/m", "contact stiffness c"),
    contact_field!("contact.damping", damping, "N s/m", "contact damping d"),
    contact_field!(
        "contact.clearance",
        clearance,
        "m",
        "total clearance l_S of every overlap"
    ),
    KeyField {
        path: "telescope.positions",
        unit: "m",
        description: "telescopic position a_(k+2) of section k+2 along its lower neighbour, held",
        parameter: true,
        per_section: true,
        get: |f, i| {
            let positions = &f
                .telescope
                .as_ref()
                .ok_or("the scene has no [telescope] table (one section)")?
                .positions;
            let i = i.ok_or("name a position by its index (`.0` is a_2)")?;
            constant(
                positions.get(i).ok_or_else(|| {
                    format!("index {i} is past the {} positions", positions.len())
                })?,
            )
        },
        set: |f, i, v| {
            let positions = &mut f
                .telescope
                .as_mut()
                .ok_or("the scene has no [telescope] table (one section)")?
                .positions;
            let i = i.ok_or("name a position by its index (`.0` is a_2)")?;
            let len = positions.len();
            *positions
                .get_mut(i)
                .ok_or_else(|| format!("index {i} is past the {len} positions"))? =
                Profile::Constant(v);
            Ok(())
        },
    },
    KeyField {
        path: "drive.force",
        unit: "N",
        description: "drive force F on the vehicle, held",
        parameter: true,
        per_section: false,
        get: |f, _| constant(f.drive.force.as_ref().ok_or("the drive is a motion")?),
        set: |f, _, v| {
            if f.drive.force.is_none() {
                return Err("the drive is a motion, not a force".into());
            }
            f.drive.force = Some(Profile::Constant(v));
            Ok(())
        },
    },
    number_field!("time.start", "s", "start time", false, |f| f.time.start),
    number_field!("time.end", "s", "end time", false, |f| f.time.end),
    number_field!("time.sample", "s", "output sample interval", false, |f| f
        .time
        .sample),
];

/// The unit of `key` (a continuous scene key, with or without a section index).
pub fn unit_of(key: &str) -> Option<&'static str> {
    SceneKey::parse(key).ok().map(|k| k.field.unit)
}
