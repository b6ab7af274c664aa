//! Linear models of a scene with stable names, at one operating point or over a grid of
//! telescopic positions, and their export to the tools controls engineers use (JSON,
//! MATLAB/Octave, NumPy, python-control, LaTeX). The states, inputs and outputs are those of
//! [`telescopic_runtime::analysis::linear`]; docs/linear.md describes the formats.
//!
//! ```
//! use telescopic::linear::{LinearizeOptions, linearize};
//!
//! let scene = telescopic::Scene::load("scenes/test-rig.toml".as_ref(), &[])?;
//! let export = linearize(&scene, &LinearizeOptions::default())?;
//! let point = &export.points[0];
//! assert_eq!(point.a.nrows(), 20); // 10 coordinates and their rates
//! assert_eq!(export.states[0].name, "u");
//! assert_eq!(export.inputs[0].name, "F");
//! # Ok::<(), telescopic::Error>(())
//! ```

pub mod bode;
mod export;
mod formats;
mod npy;

pub use export::{DiscreteModels, LinearExport};
pub use formats::{Format, MAX_LATEX_STATES};

use crate::OptionName;
use crate::run::models::{ModelChoice, ModelRegistry};
use crate::{Error, Result};
use std::str::FromStr;
use telescopic_runtime::nalgebra::DMatrix;
use telescopic_runtime::{ContactMode, LinearModel, Lpv, Scene, configuration_key};

/// Bytes a linear model's number takes in memory and in its written text, together
/// (measured: 152 MB for 100 models of 15,367 numbers, written as JSON).
const BYTES_PER_NUMBER: u64 = 100;

/// Most points of a grid.
pub const MAX_GRID_POINTS: usize = 10_000;

/// A grid over one telescopic position: `a<k>=FROM:TO:COUNT` (m).
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    /// Section `k` of `a_k` (2..=n).
    pub section: usize,
    /// First value (m).
    pub from: f64,
    /// Last value (m).
    pub to: f64,
    /// Number of points (2 or more), evenly spaced.
    pub count: usize,
}

impl Grid {
    /// `count` evenly spaced values of the position `name` (`a2`, `a3`, ...) from `from` to
    /// `to` (m).
    ///
    /// # Errors
    /// A message naming the bad part: a name that is no position, a bound that is not
    /// finite, a count outside 2 to [`MAX_GRID_POINTS`].
    pub fn new(name: &str, from: f64, to: f64, count: usize) -> std::result::Result<Self, String> {
        let section = position_name(name)?;
        for bound in [from, to] {
            if !bound.is_finite() {
                return Err(format!("`{bound}` is not a finite number of metres"));
            }
        }
        if !(2..=MAX_GRID_POINTS).contains(&count) {
            return Err(format!(
                "COUNT must be 2 to {MAX_GRID_POINTS} (got `{count}`)"
            ));
        }
        Ok(Grid {
            section,
            from,
            to,
            count,
        })
    }

    /// The grid's values (m).
    pub fn values(&self) -> Vec<f64> {
        (0..self.count)
            .map(|i| self.from + (self.to - self.from) * i as f64 / (self.count - 1) as f64)
            .collect()
    }
}

/// Parses `a<k>` into `k`.
fn position_name(name: &str) -> std::result::Result<usize, String> {
    name.trim()
        .strip_prefix('a')
        .map(|k| k.trim_start_matches('_'))
        .and_then(|k| k.parse::<usize>().ok())
        .filter(|&k| k >= 2)
        .ok_or_else(|| format!("`{name}` is not a telescopic position; use a2, a3, ..."))
}

impl FromStr for Grid {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let usage = "expected a<k>=FROM:TO:COUNT, e.g. a2=0.35:1.15:9";
        let (name, range) = s.split_once('=').ok_or(usage)?;
        let parts: Vec<&str> = range.split(':').collect();
        let [from, to, count] = parts.as_slice() else {
            return Err(usage.to_string());
        };
        let number = |v: &str| {
            v.trim()
                .parse::<f64>()
                .map_err(|_| format!("`{v}` is not a finite number of metres"))
        };
        let count = count
            .trim()
            .parse::<usize>()
            .map_err(|_| format!("COUNT must be 2 to {MAX_GRID_POINTS} (got `{count}`)"))?;
        Grid::new(name, number(from)?, number(to)?, count)
    }
}

/// Parses `a2=V,a3=W` into `(k, value)` pairs.
///
/// # Errors
/// A message naming the bad part.
pub fn parse_positions(s: &str) -> std::result::Result<Vec<(usize, f64)>, String> {
    s.split(',')
        .map(|part| {
            let (name, value) = part
                .split_once('=')
                .ok_or_else(|| format!("`{part}`: expected a<k>=VALUE, e.g. a2=1.15"))?;
            let v = value
                .trim()
                .parse::<f64>()
                .map_err(|_| format!("`{value}` is not a finite number of metres"))?;
            position_value(name, v)
        })
        .collect()
}

/// One position `a<k>` (`a2`, ...) at `value` (m) as `(k, value)`.
///
/// # Errors
/// A message naming the position or the value when either breaks its rule.
pub fn position_value(name: &str, value: f64) -> std::result::Result<(usize, f64), String> {
    if !value.is_finite() {
        return Err(format!("`{value}` is not a finite number of metres"));
    }
    Ok((position_name(name)?, value))
}

/// Options of [`linearize`].
#[derive(Debug, Clone, PartialEq)]
pub struct LinearizeOptions {
    /// Telescopic positions to use, `(k, a_k)` (m); the others come from the scene.
    pub positions: Vec<(usize, f64)>,
    /// Take the positions and their speeds of the scene at this time (s); default: the
    /// scene's start.
    pub at_time: Option<f64>,
    /// Closed (linear law) or open contacts.
    pub contacts: ContactMode,
    /// Sample the LPV model over a grid of one position (speeds zero).
    pub grid: Option<Grid>,
    /// Which model's matrices.
    pub model: ModelChoice,
    /// Where generated models come from (default: the committed ones).
    pub models: ModelRegistry,
    /// Add the disturbance input `F_load` (N), a horizontal force on the load.
    pub disturbance: bool,
    /// Also give the zero-order-hold discrete-time model at this sample period (s).
    pub discrete: Option<f64>,
    /// The memory the grid's linear models may take (bytes; default
    /// [`crate::run::memory::DEFAULT_MEMORY_BUDGET`]).
    pub memory_budget: u64,
}

impl Default for LinearizeOptions {
    fn default() -> Self {
        LinearizeOptions {
            positions: Vec::new(),
            at_time: None,
            contacts: ContactMode::default(),
            grid: None,
            model: ModelChoice::default(),
            models: ModelRegistry::default(),
            disturbance: false,
            discrete: None,
            memory_budget: crate::run::memory::DEFAULT_MEMORY_BUDGET,
        }
    }
}

/// The linear model of `scene` at the operating point or grid of `options`.
///
/// # Errors
/// [`Error::Option`] for positions, times or grids outside the scene or the valid overlap;
/// [`Error::Model`] when no model can be had.
pub fn linearize(scene: &Scene, options: &LinearizeOptions) -> Result<LinearExport> {
    let chosen = options.models.build(&scene.params, options.model)?;
    let model = chosen.model.as_ref();
    let mut lpv = Lpv::new(model, options.contacts).map_err(Error::from)?;
    if options.disturbance {
        lpv = lpv.with_disturbance();
    }
    if let Some(dt) = options.discrete
        && !(dt.is_finite() && dt > 0.0)
    {
        return Err(Error::option(
            OptionName::Discrete,
            format!("the sample period must be a finite number of seconds > 0 (got {dt})"),
        ));
    }
    let npos = scene.params.sections.len() - 1;
    let OperatingPoint {
        positions,
        rates,
        mut operating_point,
    } = operating_point(scene, options)?;
    let (grid, points) = match &options.grid {
        None => (
            None,
            vec![at(&lpv, &positions, &rates, OptionName::Positions)?],
        ),
        Some(g) => {
            check_position(OptionName::Grid, g.section, npos)?;
            let (grid, points) = grid_points(&lpv, g, &positions, &rates, options.memory_budget)?;
            let others = if npos > 1 {
                format!("; the other positions: {operating_point}")
            } else {
                String::new()
            };
            operating_point = format!(
                "a grid of a_{} over [{}, {}] m ({} points), at rest{others}",
                g.section, g.from, g.to, g.count
            );
            (Some(grid), points)
        }
    };
    let discrete = options
        .discrete
        .map(|dt| -> Result<DiscreteModels> {
            let points = points
                .iter()
                .map(|p| finite_hold(p, dt))
                .collect::<Result<_>>()?;
            Ok(DiscreteModels { dt, points })
        })
        .transpose()?;
    Ok(LinearExport {
        scene: scene.name.clone(),
        scene_file: String::new(),
        overrides: Vec::new(),
        configuration: configuration_key(&scene.params),
        model: chosen.description,
        contacts: options.contacts,
        states: lpv.states().to_vec(),
        inputs: lpv.inputs().to_vec(),
        outputs: lpv.outputs().to_vec(),
        grid,
        operating_point,
        points,
        discrete,
    })
}

/// The positions (m), their rates (m/s) and a description of the point a linear model is
/// taken at.
struct OperatingPoint {
    positions: Vec<f64>,
    rates: Vec<f64>,
    operating_point: String,
}

/// Refuses a position index `k` (a_k) the scene with `npos` moving positions lacks.
fn check_position(option: OptionName, k: usize, npos: usize) -> Result<()> {
    if !(2..=npos + 1).contains(&k) {
        return Err(Error::option(
            option,
            format!(
                "a{k}: the scene has {} section(s), so its positions are a2..a{}",
                npos + 1,
                npos + 1
            ),
        ));
    }
    Ok(())
}

/// The scene's positions and rates at `options.at_time`, or the positions given at rest.
fn operating_point(scene: &Scene, options: &LinearizeOptions) -> Result<OperatingPoint> {
    let npos = scene.params.sections.len() - 1;
    let t = options.at_time.unwrap_or(scene.time.start);
    if !(t.is_finite() && t >= scene.time.start && t <= scene.time.end) {
        return Err(Error::option(
            OptionName::AtTime,
            format!(
                "{t}: must lie in the scene's time span [{}, {}] s",
                scene.time.start, scene.time.end
            ),
        ));
    }
    let mut positions: Vec<f64> = scene.params.positions.iter().map(|p| p.value(t)).collect();
    let mut rates: Vec<f64> = scene.params.positions.iter().map(|p| p.rate(t)).collect();
    let mut operating_point = format!("positions and speeds of the scene at t = {t} s");
    if !options.positions.is_empty() {
        for (i, &(k, v)) in options.positions.iter().enumerate() {
            check_position(OptionName::Positions, k, npos)?;
            if options.positions[..i].iter().any(|&(other, _)| other == k) {
                return Err(Error::option(
                    OptionName::Positions,
                    format!("a{k} is given twice"),
                ));
            }
            positions[k - 2] = v;
            rates[k - 2] = 0.0;
        }
        operating_point = "positions given, at rest".to_string();
    }
    if let Some(g) = &options.grid
        && options.positions.iter().any(|&(k, _)| k == g.section)
    {
        return Err(Error::option_see(
            OptionName::Positions,
            format!(
                "a{} is given a value and is the grid's position: give it one or the other",
                g.section
            ),
            OptionName::Grid,
        ));
    }
    Ok(OperatingPoint {
        positions,
        rates,
        operating_point,
    })
}

/// A grid's name and its values.
type NamedGrid = (String, Vec<f64>);

/// The linear models over the grid `g` of one position (the others at `positions`, every
/// rate zero), within `memory_budget` (bytes): the grid's name and values, and the models.
fn grid_points(
    lpv: &Lpv,
    g: &Grid,
    positions: &[f64],
    rates: &[f64],
    memory_budget: u64,
) -> Result<(NamedGrid, Vec<LinearModel>)> {
    // the other positions must be valid too, whatever the grid's values
    lpv.check_point(positions, rates)
        .map_err(|e| Error::option(OptionName::Positions, e.to_string()))?;
    let values = g.values();
    let (ns, ni, no) = (lpv.states().len(), lpv.inputs().len(), lpv.outputs().len());
    let numbers = (ns * ns + ns * ni + no * ns + no * ni) as u64;
    crate::run::memory::check(
        numbers * BYTES_PER_NUMBER * values.len() as u64,
        memory_budget,
        (
            Some(OptionName::Grid),
            "the grid of operating points".into(),
        ),
        format!(
            "{} linear models of {ns} states ({numbers} numbers each, held and written \
             together)",
            values.len()
        ),
        "the grid (fewer points) or sections.modes",
    )?;
    let mut points = Vec::with_capacity(values.len());
    for &v in &values {
        let mut p = positions.to_vec();
        p[g.section - 2] = v;
        points.push(at(lpv, &p, &vec![0.0; positions.len()], OptionName::Grid)?);
    }
    Ok(((format!("a_{}", g.section), values), points))
}

/// The linear model at one operating point; a bad point is an error of `option`.
fn at(lpv: &Lpv, positions: &[f64], rates: &[f64], option: OptionName) -> Result<LinearModel> {
    lpv.at(positions, rates)
        .map_err(|e| Error::option(option, e.to_string()))
}

/// The zero-order hold of `point` at `dt` (s), refused when a number of it is not finite (a
/// period so long that the exponential of an unstable or undamped model's matrix overflows).
fn finite_hold(point: &LinearModel, dt: f64) -> Result<(DMatrix<f64>, DMatrix<f64>)> {
    let (ad, bd) = zero_order_hold(&point.a, &point.b, dt);
    if ad.iter().chain(bd.iter()).all(|v| v.is_finite()) {
        return Ok((ad, bd));
    }
    let rate = point.a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    Err(Error::option(
        OptionName::Discrete,
        format!(
            "the sample period {dt} s gives a discrete model that is not finite: it is too long \
             against the model's fastest rate (|A| up to {rate:.3e} 1/s); take a period of the \
             controller's, well below 1 s"
        ),
    ))
}

/// `(Ad, Bd)`: the zero-order-hold discretization of `(A, B)` with period `period` (s), from
/// the exponential of the augmented matrix `[A B; 0 0] T`.
pub fn zero_order_hold(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    period: f64,
) -> (DMatrix<f64>, DMatrix<f64>) {
    let (n, m) = (a.nrows(), b.ncols());
    let mut aug = DMatrix::zeros(n + m, n + m);
    aug.view_mut((0, 0), (n, n)).copy_from(&(a * period));
    aug.view_mut((0, n), (n, m)).copy_from(&(b * period));
    let e = aug.exp();
    (
        e.view((0, 0), (n, n)).into_owned(),
        e.view((0, n), (n, m)).into_owned(),
    )
}
