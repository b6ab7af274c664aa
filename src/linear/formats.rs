//! The export formats of a [`LinearExport`]: JSON (with a reader, for round trips and for
//! tools), a MATLAB/Octave script, NumPy's `.npz`, a python-control script and LaTeX.

use super::export::{DiscreteModels, LinearExport};
use super::npy::{self, Array};
use crate::OptionName;
use crate::io::rows::{from_rows, to_rows};
use crate::{Error, Result};
use serde_json::{Value, json};
use std::io::Write;
use telescopic_runtime::nalgebra::DMatrix;
use telescopic_runtime::{ContactMode, LinearModel, Signal};

/// Most states the LaTeX export writes out entry by entry.
pub const MAX_LATEX_STATES: usize = 24;

/// The version of the JSON document's layout (docs/linear.md).
const JSON_VERSION: u64 = 1;

/// An export format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Format {
    /// A JSON document with names, units, the operating point or grid, scene and generator.
    #[default]
    Json,
    /// A MATLAB/Octave script defining `sys` (`ss` with names).
    Matlab,
    /// NumPy's `.npz`: the arrays and the names.
    Npz,
    /// A Python script defining `sys`, a `control.StateSpace` (python-control).
    Python,
    /// A LaTeX document with the matrices' entries (small models).
    Latex,
}

crate::named::named_enum!(Format, "a format", {
    Json => "json",
    Matlab => "matlab",
    Npz => "npz",
    Python => "python",
    Latex => "latex",
});

/// A number with every digit needed to read it back exactly.
fn num(v: f64) -> String {
    if v == 0.0 {
        "0".to_string()
    } else {
        format!("{v:e}")
    }
}

fn names(signals: &[Signal]) -> Vec<String> {
    signals.iter().map(|s| s.name.clone()).collect()
}

fn signals_json(signals: &[Signal]) -> Value {
    Value::Array(
        signals
            .iter()
            .map(|s| json!({"name": s.name, "unit": s.unit, "description": s.description}))
            .collect(),
    )
}

impl LinearExport {
    /// The names of the positions `a_2..a_n`.
    fn position_names(&self) -> Vec<String> {
        let n = self.points.first().map_or(0, |p| p.positions.len());
        (0..n).map(|i| format!("a_{}", i + 2)).collect()
    }

    /// Checks that the export can be written in `format`.
    ///
    /// # Errors
    /// [`Error::Option`] for LaTeX of a model too large to write out.
    pub fn check_format(&self, format: Format) -> Result<()> {
        if format == Format::Latex && self.discrete.is_some() {
            return Err(Error::option(
                OptionName::LatexFormat,
                "writes the continuous-time model only; the discrete-time model is in json, \
                 matlab, npz and python",
            ));
        }
        if format == Format::Latex && self.states.len() > MAX_LATEX_STATES {
            return Err(Error::option(
                OptionName::LatexFormat,
                format!(
                    "is for small models: at most {MAX_LATEX_STATES} states, this one has {}; \
                     use json, matlab, npz or python",
                    self.states.len()
                ),
            ));
        }
        Ok(())
    }

    /// Writes the export in `format` (check it first with [`LinearExport::check_format`]).
    ///
    /// # Errors
    /// The writer's error.
    pub fn write(&self, format: Format, w: &mut dyn Write) -> std::io::Result<()> {
        let text = match format {
            Format::Json => {
                serde_json::to_string_pretty(&self.to_json()).expect("plain data") + "\n"
            }
            Format::Matlab => self.to_matlab(),
            Format::Python => self.to_python(),
            Format::Latex => self.to_latex(),
            Format::Npz => return w.write_all(&self.to_npz()?),
        };
        w.write_all(text.as_bytes())
    }

    /// The JSON document (docs/linear.md).
    pub fn to_json(&self) -> Value {
        let pos_names = self.position_names();
        let points: Vec<Value> = self
            .points
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let named = |v: &[f64]| {
                    Value::Object(
                        pos_names
                            .iter()
                            .zip(v)
                            .map(|(n, x)| (n.clone(), json!(x)))
                            .collect(),
                    )
                };
                let mut point = json!({
                    "positions": named(&p.positions),
                    "rates": named(&p.rates),
                    "A": to_rows(&p.a), "B": to_rows(&p.b), "C": to_rows(&p.c), "D": to_rows(&p.d),
                });
                if let Some(d) = &self.discrete {
                    point["Ad"] = json!(to_rows(&d.points[k].0));
                    point["Bd"] = json!(to_rows(&d.points[k].1));
                }
                point
            })
            .collect();
        json!({
            "format": "telescopic linear model",
            "version": JSON_VERSION,
            "generator": format!("telescopic {}", env!("CARGO_PKG_VERSION")),
            "equations": "x' = A x + B u, y = C x + D u",
            "scene": {"name": self.scene, "file": self.scene_file, "overrides": self.overrides},
            "configuration": self.configuration,
            "model": self.model,
            "contacts": self.contacts.name(),
            "operating_point": self.operating_point,
            "states": signals_json(&self.states),
            "inputs": signals_json(&self.inputs),
            "outputs": signals_json(&self.outputs),
            "grid": self.grid.as_ref().map(|(n, v)| json!({"parameter": n, "values": v})),
            "points": points,
            "discrete": self.discrete.as_ref().map(|d| json!({
                "dt": d.dt,
                "equations": "x[k+1] = Ad x[k] + Bd u[k], y[k] = C x[k] + D u[k] (zero-order hold; \
                              Ad, Bd in each point)",
            })),
        })
    }

    /// Reads a JSON document written by [`LinearExport::to_json`].
    ///
    /// # Errors
    /// [`Error::Input`] naming what is missing or malformed.
    pub fn from_json(text: &str) -> Result<Self> {
        let bad = |what: &str| Error::input("linear model JSON", what);
        let v: Value = serde_json::from_str(text).map_err(|e| bad(&e.to_string()))?;
        if v["format"] != "telescopic linear model" {
            return Err(bad("`format` is not \"telescopic linear model\""));
        }
        if v["version"].as_u64() != Some(JSON_VERSION) {
            return Err(bad(&format!("`version` is not {JSON_VERSION}")));
        }
        let text_of = |x: &Value, what: &str| {
            x.as_str()
                .map(str::to_string)
                .ok_or_else(|| bad(&format!("`{what}` is not a string")))
        };
        let signals = |key: &str| -> Result<Vec<Signal>> {
            v[key]
                .as_array()
                .ok_or_else(|| bad(&format!("`{key}` is not a list")))?
                .iter()
                .map(|s| {
                    Ok(Signal {
                        name: text_of(&s["name"], key)?,
                        unit: text_of(&s["unit"], key)?,
                        description: text_of(&s["description"], key)?,
                    })
                })
                .collect()
        };
        let matrix = |x: &Value, what: &str| -> Result<DMatrix<f64>> {
            let rows: Vec<Vec<f64>> =
                serde_json::from_value(x.clone()).map_err(|e| bad(&format!("`{what}`: {e}")))?;
            from_rows(&rows, None).map_err(|e| bad(&format!("`{what}` {e}")))
        };
        // by name: a JSON object's keys need not keep their order (a_10 sorts before a_2)
        let values = |x: &Value| -> Result<Vec<f64>> {
            let count = x.as_object().map_or(0, |o| o.len());
            (0..count)
                .map(|i| {
                    x[format!("a_{}", i + 2)]
                        .as_f64()
                        .ok_or_else(|| bad(&format!("position a_{} missing", i + 2)))
                })
                .collect()
        };
        let points = v["points"]
            .as_array()
            .ok_or_else(|| bad("`points` is not a list"))?
            .iter()
            .map(|p| {
                Ok(LinearModel {
                    positions: values(&p["positions"])?,
                    rates: values(&p["rates"])?,
                    a: matrix(&p["A"], "A")?,
                    b: matrix(&p["B"], "B")?,
                    c: matrix(&p["C"], "C")?,
                    d: matrix(&p["D"], "D")?,
                })
            })
            .collect::<Result<Vec<_>>>()?;
        let discrete = match &v["discrete"] {
            Value::Null => None,
            d => Some(DiscreteModels {
                dt: d["dt"]
                    .as_f64()
                    .ok_or_else(|| bad("`discrete.dt` is not a number"))?,
                points: v["points"]
                    .as_array()
                    .ok_or_else(|| bad("`points` is not a list"))?
                    .iter()
                    .map(|p| Ok((matrix(&p["Ad"], "Ad")?, matrix(&p["Bd"], "Bd")?)))
                    .collect::<Result<Vec<_>>>()?,
            }),
        };
        let grid = match &v["grid"] {
            Value::Null => None,
            g => Some((
                text_of(&g["parameter"], "grid.parameter")?,
                serde_json::from_value(g["values"].clone()).map_err(|e| bad(&e.to_string()))?,
            )),
        };
        Ok(LinearExport {
            scene: text_of(&v["scene"]["name"], "scene.name")?,
            scene_file: text_of(&v["scene"]["file"], "scene.file")?,
            overrides: serde_json::from_value(v["scene"]["overrides"].clone())
                .map_err(|e| bad(&e.to_string()))?,
            configuration: text_of(&v["configuration"], "configuration")?,
            model: text_of(&v["model"], "model")?,
            contacts: text_of(&v["contacts"], "contacts")?
                .parse::<ContactMode>()
                .map_err(|e| bad(&format!("`contacts`: {e}")))?,
            states: signals("states")?,
            inputs: signals("inputs")?,
            outputs: signals("outputs")?,
            grid,
            operating_point: text_of(&v["operating_point"], "operating_point")?,
            points,
            discrete,
        })
    }

    fn banner(&self, comment: &str) -> String {
        let scene = if self.overrides.is_empty() {
            self.scene_file.clone()
        } else {
            format!(
                "{} with overrides {}",
                self.scene_file,
                self.overrides.join(", ")
            )
        };
        [
            format!(
                "Linear model x' = A x + B u, y = C x + D u of scene {} ({scene}),",
                self.scene
            ),
            format!(
                "configuration {}, {}, contacts {}; {}.",
                self.configuration,
                self.model,
                self.contacts.name(),
                self.operating_point
            ),
            format!(
                "Generated by telescopic {}; states, inputs and outputs: docs/linear.md.",
                env!("CARGO_PKG_VERSION")
            ),
        ]
        .iter()
        .map(|l| format!("{comment} {}\n", crate::io::comment::comment_text(l)))
        .collect()
    }

    /// A MATLAB/Octave script: `A`, `B`, `C`, `D` and `sys = ss(...)` with names; for a grid,
    /// 3-D arrays and an `ss` array with its `SamplingGrid` in MATLAB, a cell array of `ss`
    /// models in Octave (whose control package has no model arrays).
    pub fn to_matlab(&self) -> String {
        let mut s = self.banner("%");
        s += "if exist('OCTAVE_VERSION', 'builtin')\n  pkg load control\nend\n";
        let cell = |signals: &[Signal]| {
            let q: Vec<String> = signals.iter().map(|x| format!("'{}'", x.name)).collect();
            format!("{{{}}}", q.join(", "))
        };
        let units = |signals: &[Signal]| {
            let q: Vec<String> = signals.iter().map(|x| format!("'{}'", x.unit)).collect();
            format!("{{{}}}", q.join(", "))
        };
        let mat = |m: &DMatrix<f64>| {
            let r: Vec<String> = to_rows(m)
                .iter()
                .map(|row| row.iter().map(|v| num(*v)).collect::<Vec<_>>().join(" "))
                .collect();
            format!("[{}]", r.join(";\n  "))
        };
        s += &format!(
            "StateName = {};\nStateUnit = {};\nInputName = {};\nInputUnit = {};\nOutputName = \
             {};\nOutputUnit = {};\n",
            cell(&self.states),
            units(&self.states),
            cell(&self.inputs),
            units(&self.inputs),
            cell(&self.outputs),
            units(&self.outputs)
        );
        let names = "'StateName', StateName, 'InputName', InputName, 'OutputName', OutputName";
        match &self.grid {
            None => {
                let p = &self.points[0];
                for (name, m) in [("A", &p.a), ("B", &p.b), ("C", &p.c), ("D", &p.d)] {
                    s += &format!("{name} = {};\n", mat(m));
                }
                s += &format!("sys = ss(A, B, C, D, {names});\n");
                if let Some(d) = &self.discrete {
                    s += &format!(
                        "% zero-order-hold discrete-time model, sample period dt (s)\ndt = {};\n\
                         Ad = {};\nBd = {};\nsysd = ss(Ad, Bd, C, D, dt, {names});\n",
                        num(d.dt),
                        mat(&d.points[0].0),
                        mat(&d.points[0].1)
                    );
                }
            }
            Some((param, values)) => {
                let grid: Vec<String> = values.iter().map(|v| num(*v)).collect();
                s += &format!("{param} = [{}];\n", grid.join(" "));
                for (k, p) in self.points.iter().enumerate() {
                    for (name, m) in [("A", &p.a), ("B", &p.b), ("C", &p.c), ("D", &p.d)] {
                        s += &format!("{name}(:, :, {}) = {};\n", k + 1, mat(m));
                    }
                    if let Some(d) = &self.discrete {
                        let (ad, bd) = &d.points[k];
                        s += &format!(
                            "Ad(:, :, {0}) = {1};\nBd(:, :, {0}) = {2};\n",
                            k + 1,
                            mat(ad),
                            mat(bd)
                        );
                    }
                }
                if let Some(d) = &self.discrete {
                    s += &format!(
                        "% zero-order-hold discrete-time models Ad, Bd (with C, D), sample period dt (s)\ndt = {};\n",
                        num(d.dt)
                    );
                }
                s += &format!(
                    "if exist('OCTAVE_VERSION', 'builtin')\n  sys = cell(1, numel({param}));\n  \
                     for k = 1:numel({param})\n    sys{{k}} = ss(A(:, :, k), B(:, :, k), C(:, :, \
                     k), D(:, :, k), {names});\n  end\nelse\n  sys = ss(A, B, C, D, {names});\n  \
                     sys.SamplingGrid = struct('{param}', {param});\nend\n"
                );
            }
        }
        s
    }

    /// A Python script defining `sys` (a `control.StateSpace` with names; for a grid, a list
    /// of them and `grid`) and the arrays.
    pub fn to_python(&self) -> String {
        let mut s = self.banner("#");
        s += "import numpy as np\nimport control\n\n";
        let list = |v: &[String]| {
            let q: Vec<String> = v.iter().map(|x| format!("{x:?}")).collect();
            format!("[{}]", q.join(", "))
        };
        let arr = |m: &DMatrix<f64>| {
            let r: Vec<String> = to_rows(m)
                .iter()
                .map(|row| {
                    format!(
                        "[{}]",
                        row.iter().map(|v| num(*v)).collect::<Vec<_>>().join(", ")
                    )
                })
                .collect();
            format!("np.array([\n    {},\n])", r.join(",\n    "))
        };
        s += &format!(
            "states = {}\ninputs = {}\noutputs = {}\n",
            list(&names(&self.states)),
            list(&names(&self.inputs)),
            list(&names(&self.outputs))
        );
        let ss = "control.ss(A, B, C, D, states=states, inputs=inputs, outputs=outputs)";
        let ssd = "control.ss(Ad, Bd, C, D, dt, states=states, inputs=inputs, outputs=outputs)";
        match &self.grid {
            None => {
                let p = &self.points[0];
                for (name, m) in [("A", &p.a), ("B", &p.b), ("C", &p.c), ("D", &p.d)] {
                    s += &format!("{name} = {}\n", arr(m));
                }
                s += &format!("sys = {ss}\n");
                if let Some(d) = &self.discrete {
                    s += &format!(
                        "# zero-order-hold discrete-time model, sample period dt (s)\ndt = {}\n\
                         Ad = {}\nBd = {}\nsysd = {ssd}\n",
                        num(d.dt),
                        arr(&d.points[0].0),
                        arr(&d.points[0].1)
                    );
                }
            }
            Some((param, values)) => {
                let grid: Vec<String> = values.iter().map(|v| num(*v)).collect();
                s += &format!(
                    "grid_parameter = {param:?}\ngrid = np.array([{}])\nsys = []\n",
                    grid.join(", ")
                );
                if let Some(d) = &self.discrete {
                    s += &format!(
                        "# zero-order-hold discrete-time models, sample period dt (s)\ndt = {}\nsysd = []\n",
                        num(d.dt)
                    );
                }
                for (k, p) in self.points.iter().enumerate() {
                    for (name, m) in [("A", &p.a), ("B", &p.b), ("C", &p.c), ("D", &p.d)] {
                        s += &format!("{name} = {}\n", arr(m));
                    }
                    s += &format!("sys.append({ss})\n");
                    if let Some(d) = &self.discrete {
                        let (ad, bd) = &d.points[k];
                        s += &format!("Ad = {}\nBd = {}\nsysd.append({ssd})\n", arr(ad), arr(bd));
                    }
                }
            }
        }
        s
    }

    /// NumPy's `.npz`: `A`, `B`, `C`, `D` (stacked along a first axis over a grid),
    /// `positions`, `rates` (points x positions), the names and units of states, inputs and
    /// outputs, and `grid` with `grid_parameter` for a grid.
    ///
    /// # Errors
    /// The zip writer's error.
    pub fn to_npz(&self) -> std::io::Result<Vec<u8>> {
        let mut npz = Npz::new();
        let grid = self.grid.is_some();
        for (name, pick) in [
            (
                "A",
                (|p: &LinearModel| &p.a) as fn(&LinearModel) -> &DMatrix<f64>,
            ),
            ("B", |p| &p.b),
            ("C", |p| &p.c),
            ("D", |p| &p.d),
        ] {
            npz.add_stacked(name, &self.points, pick, grid)?;
        }
        if let Some(d) = &self.discrete {
            npz.add_stacked("Ad", &d.points, |p| &p.0, grid)?;
            npz.add_stacked("Bd", &d.points, |p| &p.1, grid)?;
            npz.add_floats("dt", vec![], &[d.dt])?;
        }
        let npos = self.points[0].positions.len();
        let positions: Vec<f64> = self
            .points
            .iter()
            .flat_map(|p| p.positions.clone())
            .collect();
        npz.add_floats("positions", vec![self.points.len(), npos], &positions)?;
        let rates: Vec<f64> = self.points.iter().flat_map(|p| p.rates.clone()).collect();
        npz.add_floats("rates", vec![self.points.len(), npos], &rates)?;
        npz.add_texts("position_names", &self.position_names())?;
        for (name, signals) in [
            ("states", &self.states),
            ("inputs", &self.inputs),
            ("outputs", &self.outputs),
        ] {
            npz.add_texts(name, &names(signals))?;
            let units: Vec<String> = signals.iter().map(|s| s.unit.clone()).collect();
            npz.add_texts(&format!("{}_units", name.trim_end_matches('s')), &units)?;
        }
        if let Some((param, values)) = &self.grid {
            npz.add_floats("grid", vec![values.len()], values)?;
            npz.add(
                "grid_parameter",
                Array::Text {
                    shape: vec![],
                    data: std::slice::from_ref(param),
                },
            )?;
        }
        npz.finish()
    }

    /// A LaTeX document with the names, units and the entries of `A`, `B`, `C` and `D` (six
    /// significant digits; the first operating point of a grid).
    pub fn to_latex(&self) -> String {
        // LaTeX's special characters as text (a scene's name may hold any); `^` is a unit's
        // power: `m/s^2` is typeset as `m/s$^{2}$`
        let esc = |t: &str| {
            let t: String = t
                .chars()
                .map(|c| match c {
                    '\\' => "\\textbackslash{}".to_string(),
                    '~' => "\\textasciitilde{}".to_string(),
                    '&' | '%' | '$' | '#' | '_' | '{' | '}' => format!("\\{c}"),
                    c if c.is_control() => "\u{fffd}".to_string(),
                    c => c.to_string(),
                })
                .collect();
            match t.split_once('^') {
                Some((base, power)) => format!("{base}$^{{{power}}}$"),
                None => t,
            }
        };
        let entry = |v: f64| {
            if v == 0.0 {
                "0".to_string()
            } else {
                let e = v.abs().log10().floor() as i32;
                let m = v / 10f64.powi(e);
                // 9.9999995 rounds up to 10.00000
                let (m, e) = if format!("{:.5}", m.abs()).starts_with("10") {
                    (m / 10.0, e + 1)
                } else {
                    (m, e)
                };
                if e == 0 {
                    format!("{m:.5}")
                } else {
                    format!("{m:.5}\\cdot 10^{{{e}}}")
                }
            }
        };
        let matrix = |m: &DMatrix<f64>| {
            let r: Vec<String> = to_rows(m)
                .iter()
                .map(|row| {
                    row.iter()
                        .map(|v| entry(*v))
                        .collect::<Vec<_>>()
                        .join(" & ")
                })
                .collect();
            format!(
                "\\begin{{bmatrix}}\n{}\n\\end{{bmatrix}}",
                r.join(" \\\\\n")
            )
        };
        let table = |title: &str, signals: &[Signal]| {
            let r: Vec<String> = signals
                .iter()
                .enumerate()
                .map(|(i, s)| {
                    format!(
                        "{} & \\texttt{{{}}} & {} \\\\",
                        i + 1,
                        esc(&s.name),
                        esc(&s.unit)
                    )
                })
                .collect();
            format!(
                "\\paragraph{{{title}}}\n\\begin{{tabular}}{{rll}}\n{}\n\\end{{tabular}}\n",
                r.join("\n")
            )
        };
        let p = &self.points[0];
        let mut s = self.banner("%");
        s += "\\documentclass[landscape]{article}\n\\usepackage[margin=1cm]{geometry}\n\
              \\usepackage{amsmath}\n\\setcounter{MaxMatrixCols}{64}\n\\begin{document}\n\\tiny\n";
        s += &format!(
            "\\section*{{Linear model of {}}}\n{}, contacts {}; {}.\n\\[ \\dot x = A x + B u, \\quad y = C x + D u \\]\n",
            esc(&self.scene),
            esc(&self.configuration),
            self.contacts.name(),
            esc(&self.operating_point)
        );
        s += &table("States x", &self.states);
        s += &table("Inputs u", &self.inputs);
        s += &table("Outputs y", &self.outputs);
        for (name, m) in [("A", &p.a), ("B", &p.b), ("C", &p.c), ("D", &p.d)] {
            s += &format!("\\[ {name} = {} \\]\n", matrix(m));
        }
        s += "\\end{document}\n";
        s
    }
}

/// An `.npz` archive being written: `.npy` arrays stored uncompressed.
struct Npz {
    zip: zip::ZipWriter<std::io::Cursor<Vec<u8>>>,
}

impl Npz {
    fn new() -> Self {
        Npz {
            zip: zip::ZipWriter::new(std::io::Cursor::new(Vec::new())),
        }
    }

    /// Adds `array` as `name.npy`.
    fn add(&mut self, name: &str, array: Array) -> std::io::Result<()> {
        let options = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Stored);
        self.zip
            .start_file(format!("{name}.npy"), options)
            .map_err(std::io::Error::other)?;
        npy::write(&mut self.zip, &array)
    }

    /// Adds numbers of `shape`.
    fn add_floats(&mut self, name: &str, shape: Vec<usize>, data: &[f64]) -> std::io::Result<()> {
        self.add(name, Array::Float { shape, data })
    }

    /// Adds a list of strings.
    fn add_texts(&mut self, name: &str, data: &[String]) -> std::io::Result<()> {
        self.add(
            name,
            Array::Text {
                shape: vec![data.len()],
                data,
            },
        )
    }

    /// Adds the matrix `pick` gives of every point, stacked along a first axis over a grid
    /// (`grid`), else the one point's.
    fn add_stacked<P>(
        &mut self,
        name: &str,
        points: &[P],
        pick: fn(&P) -> &DMatrix<f64>,
        grid: bool,
    ) -> std::io::Result<()> {
        let first = pick(&points[0]);
        let mut shape = vec![first.nrows(), first.ncols()];
        if grid {
            shape.insert(0, points.len());
        }
        let data: Vec<f64> = points
            .iter()
            .flat_map(|p| to_rows(pick(p)).into_iter().flatten())
            .collect();
        self.add_floats(name, shape, &data)
    }

    /// The archive's bytes.
    fn finish(self) -> std::io::Result<Vec<u8>> {
        let cursor = self.zip.finish().map_err(std::io::Error::other)?;
        Ok(cursor.into_inner())
    }
}
