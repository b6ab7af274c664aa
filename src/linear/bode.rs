//! Frequency response of the linear model (`telescopic bode`): `H(i w) = C (i w I - A)^-1 B +
//! D` from the drive input (and the disturbance force at the load, `F_load`) to chosen
//! outputs, over a logarithmic frequency grid, with the natural frequencies (`|lambda| / 2 pi`
//! of `A`'s eigenvalues) to mark on the plot.
//!
//! ```
//! use telescopic::linear::bode::{BodeOptions, frequency_response};
//! use telescopic::linear::LinearizeOptions;
//! use telescopic::Scene;
//!
//! let scene = Scene::load("scenes/test-rig.toml".as_ref(), &[])?;
//! let options = BodeOptions {
//!     linear: LinearizeOptions { positions: vec![(2, 0.8)], ..LinearizeOptions::default() },
//!     ..BodeOptions::default()
//! };
//! let response = frequency_response(&scene, &options)?;
//! assert_eq!(response.f_hz.len(), 400);
//! assert_eq!(response.curves[0].column, "tip_rel");
//! # Ok::<(), telescopic::Error>(())
//! ```

use crate::OptionName;
use crate::linear::export::LinearExport;
use crate::linear::{LinearizeOptions, linearize};
use crate::{Error, Result};
use std::io::Write;
use telescopic_runtime::nalgebra::{Complex, DMatrix};
use telescopic_runtime::{LinearInput, eigenvalues};

/// Default number of frequencies.
pub const DEFAULT_POINTS: usize = 400;

/// Most frequencies of a grid.
pub const MAX_POINTS: usize = 100_000;

/// Options of [`frequency_response`].
#[derive(Debug, Clone, PartialEq)]
pub struct BodeOptions {
    /// The operating point, contacts and model (`disturbance` is set when an input needs it;
    /// `discrete` and `grid` must be unset).
    pub linear: LinearizeOptions,
    /// Outputs (names of the linear model's outputs); default `tip_rel`.
    pub outputs: Vec<String>,
    /// Inputs: the drive (`F`, or `a_vehicle` for a prescribed motion) and/or `F_load`;
    /// default the drive.
    pub inputs: Vec<LinearInput>,
    /// Lowest frequency (Hz); default a tenth of the lowest natural frequency.
    pub from_hz: Option<f64>,
    /// Highest frequency (Hz); default 1.5 times the highest natural frequency.
    pub to_hz: Option<f64>,
    /// Number of frequencies, log-spaced.
    pub points: usize,
}

impl Default for BodeOptions {
    fn default() -> Self {
        BodeOptions {
            linear: LinearizeOptions::default(),
            outputs: vec!["tip_rel".into()],
            inputs: Vec::new(),
            from_hz: None,
            to_hz: None,
            points: DEFAULT_POINTS,
        }
    }
}

/// One input-output pair's response.
#[derive(Debug, Clone, PartialEq)]
pub struct ResponseCurve {
    /// The input's name.
    pub input: String,
    /// The output's name.
    pub output: String,
    /// The CSV columns' stem: `<output>` for the drive, `<output>_from_<input>` otherwise.
    pub column: String,
    /// Unit of the magnitude (output unit per input unit).
    pub unit: String,
    /// `|H|` at each frequency.
    pub magnitude: Vec<f64>,
    /// `arg H` (degrees), unwrapped along the frequencies.
    pub phase_deg: Vec<f64>,
}

/// The frequency response of one operating point.
#[derive(Debug, Clone, PartialEq)]
pub struct FrequencyResponse {
    /// The scene's name.
    pub scene: String,
    /// The operating point, in words.
    pub operating_point: String,
    /// Frequencies (Hz), ascending.
    pub f_hz: Vec<f64>,
    /// One curve per input and output.
    pub curves: Vec<ResponseCurve>,
    /// Natural frequencies of the linear model (Hz), ascending.
    pub natural_hz: Vec<f64>,
    /// The linear model it was computed from.
    pub model: LinearExport,
}

/// The frequency response of `scene`'s linear model.
///
/// # Errors
/// [`Error::Option`] for unknown inputs or outputs, a bad grid, or a bad operating point;
/// [`Error::Analysis`] when `i w` hits an eigenvalue of `A` exactly.
pub fn frequency_response(
    scene: &telescopic_runtime::Scene,
    options: &BodeOptions,
) -> Result<FrequencyResponse> {
    if options.linear.grid.is_some() || options.linear.discrete.is_some() {
        return Err(Error::option(
            OptionName::BodeLinear,
            "a frequency response is of one continuous-time model: no grid, no discrete",
        ));
    }
    let mut linear = options.linear.clone();
    linear.disturbance = options.inputs.contains(&LinearInput::LoadForce);
    let model = linearize(scene, &linear)?;
    let point = &model.points[0];
    let input_names: Vec<String> = options.inputs.iter().map(LinearInput::to_string).collect();
    let inputs = pick(&model.inputs, &input_names, OptionName::BodeInputs, true)?;
    let outputs = pick(
        &model.outputs,
        &options.outputs,
        OptionName::BodeOutputs,
        false,
    )?;
    let natural_hz = natural_frequencies(&point.a)?;
    let f_hz = grid(options, &natural_hz)?;
    let responses = f_hz
        .iter()
        .map(|&f| {
            response(
                &point.a,
                &point.b,
                &point.c,
                &point.d,
                2.0 * std::f64::consts::PI * f,
            )
        })
        .collect::<Result<Vec<_>>>()?;
    let mut curves = Vec::new();
    for &i in &inputs {
        for &o in &outputs {
            let (input, output) = (&model.inputs[i], &model.outputs[o]);
            let column = if i == 0 {
                output.name.clone()
            } else {
                format!("{}_from_{}", output.name, input.name)
            };
            let values: Vec<Complex<f64>> = responses.iter().map(|h| h[(o, i)]).collect();
            if let Some(k) = values
                .iter()
                .position(|h| !(h.re.is_finite() && h.im.is_finite()))
            {
                return Err(Error::Analysis(format!(
                    "the response {column} at {} Hz is not finite (the model is singular there); \
                     move the frequency grid",
                    f_hz[k]
                )));
            }
            curves.push(ResponseCurve {
                input: input.name.clone(),
                output: output.name.clone(),
                column,
                unit: format!("{}/{}", output.unit, input.unit),
                magnitude: values.iter().map(|h| h.norm()).collect(),
                phase_deg: unwrapped_phase(&values),
            });
        }
    }
    Ok(FrequencyResponse {
        scene: scene.name.clone(),
        operating_point: model.operating_point.clone(),
        f_hz,
        curves,
        natural_hz,
        model,
    })
}

/// The indices of `wanted` among `signals` (the first signal when `wanted` is empty and
/// `default_first`).
fn pick(
    signals: &[telescopic_runtime::Signal],
    wanted: &[String],
    flag: OptionName,
    default_first: bool,
) -> Result<Vec<usize>> {
    if wanted.is_empty() && default_first {
        return Ok(vec![0]);
    }
    if wanted.is_empty() {
        return Err(Error::option(flag, "name at least one"));
    }
    if let Some((k, name)) = wanted
        .iter()
        .enumerate()
        .find(|(k, n)| wanted[..*k].contains(n))
    {
        return Err(Error::option(
            flag,
            format!("`{name}` is named twice (again as entry {})", k + 1),
        ));
    }
    wanted
        .iter()
        .map(|name| {
            signals.iter().position(|s| &s.name == name).ok_or_else(|| {
                let known: Vec<&str> = signals.iter().map(|s| s.name.as_str()).collect();
                Error::option(
                    flag,
                    format!(
                        "`{name}` is not one of the linear model's: {}",
                        known.join(", ")
                    ),
                )
            })
        })
        .collect()
}

/// `|lambda| / 2 pi` of the eigenvalues of `a` with positive imaginary part (Hz), ascending.
fn natural_frequencies(a: &DMatrix<f64>) -> Result<Vec<f64>> {
    let lambdas = eigenvalues(a.clone(), "eigenvalues of the linear model's A")?;
    let mut f: Vec<f64> = lambdas
        .iter()
        .filter(|l| l.im > 0.0)
        .map(|l| l.norm() / (2.0 * std::f64::consts::PI))
        .collect();
    f.sort_by(f64::total_cmp);
    Ok(f)
}

/// The frequencies a response is computed at (Hz): `2 pi f` and `(2 pi f)^2` stay far from
/// underflow and overflow, and the band covers any structure's modes.
pub const FREQUENCY_RANGE_HZ: (f64, f64) = (1e-9, 1e12);

/// The log-spaced frequencies of `options` (defaults from the natural frequencies).
fn grid(options: &BodeOptions, natural_hz: &[f64]) -> Result<Vec<f64>> {
    let lowest = natural_hz.first().copied().unwrap_or(1.0);
    let highest = natural_hz.last().copied().unwrap_or(100.0);
    let from = options.from_hz.unwrap_or(lowest / 10.0);
    let to = options.to_hz.unwrap_or(1.5 * highest);
    let (low, high) = FREQUENCY_RANGE_HZ;
    if !(from.is_finite() && (low..high).contains(&from)) {
        return Err(Error::option(
            OptionName::FromHz,
            format!("must be a frequency of {low:e} to {high:e} Hz (got {from})"),
        ));
    }
    if !(to.is_finite() && to > from && to <= high) {
        return Err(Error::option(
            OptionName::ToHz,
            format!(
                "must be a frequency above the lower end of the band, {from} Hz, and at most \
                 {high:e} Hz (got {to})"
            ),
        ));
    }
    if !(2..=MAX_POINTS).contains(&options.points) {
        return Err(Error::option(
            OptionName::BodePoints,
            format!("must be 2 to {MAX_POINTS} (got {})", options.points),
        ));
    }
    let (l0, l1) = (from.log10(), to.log10());
    let n = options.points;
    Ok((0..n)
        .map(|i| 10f64.powf(l0 + (l1 - l0) * i as f64 / (n - 1) as f64))
        .collect())
}

/// `C (i w I - A)^-1 B + D` (outputs x inputs).
fn response(
    a: &DMatrix<f64>,
    b: &DMatrix<f64>,
    c: &DMatrix<f64>,
    d: &DMatrix<f64>,
    w: f64,
) -> Result<DMatrix<Complex<f64>>> {
    let n = a.nrows();
    let shifted = DMatrix::from_fn(n, n, |i, j| {
        Complex::new(-a[(i, j)], if i == j { w } else { 0.0 })
    });
    let x = shifted
        .lu()
        .solve(&b.map(|v| Complex::new(v, 0.0)))
        .ok_or_else(|| {
            Error::Analysis(format!(
                "the frequency {} Hz is an eigenvalue of the linear model (an undamped mode): \
                 move the frequency grid (its ends or its number of points)",
                w / (2.0 * std::f64::consts::PI)
            ))
        })?;
    Ok(c.map(|v| Complex::new(v, 0.0)) * x + d.map(|v| Complex::new(v, 0.0)))
}

/// `arg h` in degrees, made continuous by whole turns.
fn unwrapped_phase(values: &[Complex<f64>]) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::with_capacity(values.len());
    for h in values {
        let mut p = h.arg().to_degrees();
        if let Some(&prev) = out.last() {
            p += 360.0 * ((prev - p) / 360.0).round();
        }
        out.push(p);
    }
    out
}

impl FrequencyResponse {
    /// The CSV: `f_hz`, then `<column>_mag` and `<column>_phase_deg` per curve.
    ///
    /// # Errors
    /// The writer's error.
    pub fn write_csv(&self, w: &mut dyn Write) -> std::io::Result<()> {
        let mut header = vec!["f_hz".to_string()];
        for c in &self.curves {
            header.push(format!("{}_mag", c.column));
            header.push(format!("{}_phase_deg", c.column));
        }
        writeln!(w, "{}", header.join(","))?;
        for (i, f) in self.f_hz.iter().enumerate() {
            let mut line = crate::io::output::csv_number(*f);
            for c in &self.curves {
                line.push(',');
                line.push_str(&crate::io::output::csv_number(c.magnitude[i]));
                line.push(',');
                line.push_str(&crate::io::output::csv_number(c.phase_deg[i]));
            }
            writeln!(w, "{line}")?;
        }
        Ok(())
    }

    /// A summary for the terminal: operating point, natural frequencies, peaks.
    pub fn summary(&self) -> String {
        let listed: Vec<String> = self
            .natural_hz
            .iter()
            .take(8)
            .map(|f| format!("{f:.4}"))
            .collect();
        let mut s = format!(
            "{}: frequency response at {} over {:.4e} .. {:.4e} Hz ({} frequencies)\nnatural \
             frequencies [Hz]: {}{}",
            self.scene,
            self.operating_point,
            self.f_hz[0],
            self.f_hz[self.f_hz.len() - 1],
            self.f_hz.len(),
            listed.join(", "),
            if self.natural_hz.len() > 8 {
                ", ..."
            } else {
                ""
            }
        );
        for c in &self.curves {
            let (i, peak) = c
                .magnitude
                .iter()
                .enumerate()
                .fold((0, 0.0), |b, (i, &m)| if m > b.1 { (i, m) } else { b });
            s += &format!(
                "\n{} from {}: largest |H| {peak:.4e} {} at {:.4} Hz",
                c.output, c.input, c.unit, self.f_hz[i]
            );
        }
        s
    }
}
