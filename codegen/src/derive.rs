//! Derivation of a configuration's equations: matrices, shape functions, generalized forces
//! and their Jacobian, as expressions in the named physical parameters.
//!
//! Numbers (mode roots, shape-function coefficients, Galerkin integrals) are computed in high
//! precision here ([`crate::exact`]) and enter the expressions as named constants `K_...`,
//! each later emitted as one correctly rounded `f64`. Symbolica builds and normalizes the
//! expressions and differentiates them (shape-function slopes, the Jacobian of the
//! generalized forces); it runs on its own thread ([`crate::symbolic`]).
//!
//! Symbols: `rho_a_k` (kg/m), `ei_k` (N m^2), `l_k` (m), `m_t`, `m_l` (kg), `g` (m/s^2) are
//! parameters; `xi` is the dimensionless position `x / l_k` on a section; `z_j`, `zd_j` the
//! coordinates and their rates; `f_drive` the drive force; `f_c` the contact forces;
//! `k_i_j` the entries of `K`; `g_c_j`, `gd_c_j` the contact vectors and their rates;
//! `kc_c`, `dc_c`, `off_c` the slope, damping and offset of contact `c`'s law in its branch.

use crate::CodegenError;
use crate::config::{ForceFlow, ModelConfig, StaticKnots};
use crate::exact::{Func, RootTable, SectionIntegrals, Trig};
use crate::expr::Expr;
use crate::precise::{Kind, Real};
use crate::spline::{self, Primitive, correction_splines, orthonormal_corrections};
use crate::symbolic;
use std::collections::BTreeMap;
use symbolica::atom::{Atom, AtomCore};

/// A named numeric constant of the emitted code.
#[derive(Debug, Clone, PartialEq)]
pub struct Constant {
    /// Name, `K_...` (emitted upper case).
    pub name: String,
    /// Value, correctly rounded from 512 bits.
    pub value: f64,
    /// What it is.
    pub doc: String,
}

/// One basis function of a section in computing coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct BasisFunction {
    /// Global coordinate index.
    pub index: usize,
    /// Power of `l_k` in front of the dimensionless form.
    pub length_power: i32,
    /// `psi(xi)` without the length power.
    pub value: Expr,
    /// `d psi / d xi` without the length power.
    pub slope: Expr,
    /// Value at the top of the section, `xi = 1` (without the length power).
    pub top: String,
}

/// Everything the emitter needs, as plain data.
#[derive(Debug, Clone, PartialEq)]
pub struct Derivation {
    /// The configuration.
    pub config: ModelConfig,
    /// Named constants in order of creation.
    pub constants: Vec<Constant>,
    /// Nonzero entries `(i, j), i <= j` of the mass matrix.
    pub mass: Entries,
    /// Nonzero entries `(i, j), i <= j` of the stiffness matrix.
    pub stiffness: Entries,
    /// Per section (index k - 1), its elastic basis functions (the translation excluded).
    pub bases: Vec<Vec<BasisFunction>>,
    /// Per section, its static correction shapes (basis `modes+static`), after its modes.
    pub corrections: Vec<Option<Corrections>>,
    /// Generalized forces `q_i` (right-hand side before `M^-1`).
    pub forces: Vec<Expr>,
    /// Nonzero `d q_i / d z_j`.
    pub jacobian_z: Entries,
    /// Nonzero `d q_i / d zd_j`.
    pub jacobian_zd: Entries,
    /// Nonzero entries `j` of each contact vector (the same pattern for `g` and `gdot`).
    pub contact_pattern: Vec<Vec<usize>>,
}

/// A section's static correction shapes: combinations of its modes (as in
/// [`Derivation::bases`], without `l_k^p`) and its cubic B-splines in `xi`.
#[derive(Debug, Clone, PartialEq)]
pub struct Corrections {
    /// Global index of the first correction (the rest follow).
    pub first_index: usize,
    /// Interior knots of the B-splines, fractions of the section's length.
    pub knots: Vec<f64>,
    /// Row `e`: correction `e`'s coefficients of the modes, then of the B-splines.
    pub combination: Vec<Vec<f64>>,
    /// Each correction's value at the top (`xi = 1`), a constant's name.
    pub tops: Vec<String>,
}

/// Nonzero entries of a matrix: `((i, j), expression)`, upper triangle.
pub type Entries = Vec<((usize, usize), Expr)>;

/// Integrals below this (relative to O(1) entries) are exact zeros that 512-bit round-off
/// left behind (orthogonality): about 1e-150 in practice.
const ZERO: f64 = 1e-60;

struct Constants(Vec<Constant>);

impl Constants {
    fn add(&mut self, name: String, value: &Real, doc: String) -> String {
        self.0.push(Constant {
            name: name.clone(),
            value: value.to_f64(),
            doc,
        });
        name
    }
}

fn is_zero(v: &Real) -> bool {
    v.abs() < Real::from_f64(ZERO)
}

/// A section's local basis in computing coordinates: the translation (index 0) first, then
/// the section's modes (section 1: `phi_i - phi_i(0)`, `i >= 2`).
fn local_basis(config: &ModelConfig, k: usize, roots: &RootTable) -> Vec<(usize, Func, usize)> {
    let kind = if k == 1 {
        Kind::GuidedFree
    } else {
        Kind::FreeFree
    };
    let offset = config.offset(k);
    let mut basis = vec![(0, Func::constant(Real::int(1)), 0)];
    for i in 1..=config.modes[k - 1] {
        if k == 1 && i == 1 {
            continue;
        }
        let f = Func::paper_mode(kind, i, roots);
        let f = if k == 1 {
            let shift = f.value_at_end(roots, false);
            f.minus_constant(shift)
        } else {
            f
        };
        basis.push((offset + i - 1, f, i));
    }
    basis
}

/// `l_k^p` as text.
/// Global index of the first correction shape of section `k` (1-based): after its modes.
fn first_correction(config: &ModelConfig, k: usize) -> usize {
    config.offset(k) + config.modes[k - 1]
}

fn length_pow(k: usize, p: i32) -> String {
    match p {
        0 => "1".into(),
        1 => format!("l_{k}"),
        _ => format!("l_{k}^({p})"),
    }
}

/// The shape function as text in `xi` with named constants; every exponential has a
/// non-positive argument on `[0, 1]` (`e^(b xi) = e^b e^(b (xi - 1))`, `e^b` folded into the
/// coefficient): the cancellation-free form.
fn shape_text(f: &Func, roots: &RootTable, k: usize, i: usize, consts: &mut Constants) -> String {
    let mut parts = Vec::new();
    for (t, term) in f.terms.iter().enumerate() {
        let mut coef = term.coef.clone();
        let mut factors = Vec::new();
        if let Some((sign, m)) = term.exp {
            let beta = format!("K_BETA_{k}_{}", m + 1);
            if sign > 0 {
                coef = &coef * &roots.beta[m].exp();
                factors.push(format!("exp({beta}*(xi-1))"));
            } else {
                factors.push(format!("exp(-{beta}*xi)"));
            }
        }
        if let Some((trig, m)) = term.trig {
            let beta = format!("K_BETA_{k}_{}", m + 1);
            factors.push(match trig {
                Trig::Cos => format!("cos({beta}*xi)"),
                Trig::Sin => format!("sin({beta}*xi)"),
            });
        }
        if term.power > 0 {
            factors.push(format!("xi^{}", term.power));
        }
        if is_zero(&coef) {
            continue;
        }
        let c = if coef == Real::int(1) {
            "1".to_string()
        } else if coef == Real::int(-1) {
            "-1".to_string()
        } else {
            consts.add(
                format!("K_C_{k}_{i}_{t}"),
                &coef,
                format!("coefficient {t} of psi_{k},{i} (xi)"),
            )
        };
        factors.insert(0, c);
        parts.push(factors.join("*"));
    }
    if parts.is_empty() {
        "0".into()
    } else {
        parts.join(" + ")
    }
}

/// Symbolic inputs of one derivation (strings for Symbolica, built outside its thread).
struct Inputs {
    mass: BTreeMap<(usize, usize), Vec<String>>,
    stiffness: BTreeMap<(usize, usize), Vec<String>>,
    shapes: Vec<Vec<(usize, i32, String, String)>>,
    corrections: Vec<Option<Corrections>>,
    forces: Vec<String>,
    contact_pattern: Vec<Vec<usize>>,
    dof: usize,
}

/// Derives the equations of one configuration.
///
/// # Errors
/// [`CodegenError`] for an invalid configuration or a failed Symbolica step.
pub fn derive(config: &ModelConfig) -> Result<Derivation, CodegenError> {
    config.validate().map_err(CodegenError::Config)?;
    let n = config.sections();
    let dof = config.dof();
    let mut consts = Constants(Vec::new());
    let mut mass: BTreeMap<(usize, usize), Vec<String>> = BTreeMap::new();
    let mut stiffness: BTreeMap<(usize, usize), Vec<String>> = BTreeMap::new();
    let (mut shapes, mut corrections) = (Vec::new(), Vec::new());
    mass.entry((0, 0)).or_default().push("m_t".into());
    for k in 1..=n {
        let (section_shapes, section_corrections) =
            section_terms(config, k, &mut consts, &mut mass, &mut stiffness)?;
        shapes.push(section_shapes);
        corrections.push(section_corrections);
    }
    let (forces, contact_pattern) = force_terms(config, &stiffness);
    let inputs = Inputs {
        mass,
        stiffness,
        shapes,
        corrections,
        forces,
        contact_pattern,
        dof,
    };
    let config_owned = config.clone();
    let constants = consts.0;
    symbolic::run(move || symbolic_part(inputs, config_owned, constants))?
}

/// Entries of `M` (and `K`) as sums of terms, by `(row, column)` of the upper triangle.
type TermEntries = BTreeMap<(usize, usize), Vec<String>>;

/// One coordinate function of a section: its global index, the power of `l_k` in front,
/// and its label in constant names (a mode's number, or `s1`, `s2`, ... for corrections).
struct Coordinate {
    index: usize,
    length_power: i32,
    label: String,
}

/// A section's coordinate functions with their four Galerkin tables (see
/// [`SectionIntegrals`]), their values at the top, and their corrections.
struct SectionTables {
    coordinates: Vec<Coordinate>,
    tables: [Vec<Vec<Real>>; 4],
    tops: Vec<Real>,
    corrections: Option<(Vec<f64>, Vec<Vec<Real>>)>,
}

/// Section `k`'s coordinate functions and tables: the translation and the modes, and with
/// static knots the correction shapes orthonormalized against them ([`crate::spline`]).
fn section_tables(
    config: &ModelConfig,
    k: usize,
    basis: &[(usize, Func, usize)],
    roots: &RootTable,
) -> Result<SectionTables, CodegenError> {
    let mut coordinates: Vec<Coordinate> = basis
        .iter()
        .map(|(g, f, i)| Coordinate {
            index: *g,
            length_power: f.length_power,
            label: i.to_string(),
        })
        .collect();
    let mut tops: Vec<Real> = basis
        .iter()
        .map(|(_, f, _)| f.value_at_end(roots, true))
        .collect();
    let Some(StaticKnots(knots)) = &config.static_knots else {
        let funcs: Vec<Func> = basis.iter().map(|(_, f, _)| f.clone()).collect();
        let ints = SectionIntegrals::new(&funcs, roots);
        return Ok(SectionTables {
            coordinates,
            tables: [ints.mass, ints.bending, ints.axial, ints.axial_x],
            tops,
            corrections: None,
        });
    };
    let knots = knots[k - 1].clone();
    let mut primitives: Vec<Primitive> = basis
        .iter()
        .map(|(_, f, _)| Primitive::Sum(f.clone()))
        .collect();
    primitives.extend(
        correction_splines(&knots)
            .into_iter()
            .map(Primitive::Spline),
    );
    let raw = spline::tables(&primitives, roots);
    // the Gram matrix of every function but the translation, the corrections after the modes
    let gram: Vec<Vec<Real>> = raw[0][1..].iter().map(|row| row[1..].to_vec()).collect();
    let combination = orthonormal_corrections(&gram, basis.len() - 1, k)
        .map_err(|e| CodegenError::Config(format!("static_knots: {e}")))?;
    // rows of the change of functions: the translation and modes as they are, then each
    // correction over the functions after the translation
    let mut rows: Vec<Vec<Real>> = (0..basis.len())
        .map(|i| {
            (0..primitives.len())
                .map(|j| Real::int(i64::from(i == j)))
                .collect()
        })
        .collect();
    for (e, c) in combination.iter().enumerate() {
        let mut row = vec![Real::zero()];
        row.extend(c.iter().cloned());
        rows.push(row);
        coordinates.push(Coordinate {
            index: first_correction(config, k) + e,
            length_power: 0,
            label: format!("s{}", e + 1),
        });
        tops.push(
            c.iter()
                .zip(&primitives[1..])
                .fold(Real::zero(), |acc, (a, p)| &acc + &(a * &p.top(roots))),
        );
    }
    let transform = |t: &Vec<Vec<Real>>| -> Vec<Vec<Real>> {
        let n = rows.len();
        let mut out = vec![vec![Real::zero(); n]; n];
        for a in 0..n {
            for b in a..n {
                let mut v = Real::zero();
                for (i, ra) in rows[a].iter().enumerate().filter(|(_, x)| !x.is_zero()) {
                    for (j, rb) in rows[b].iter().enumerate().filter(|(_, x)| !x.is_zero()) {
                        v = &v + &(&(ra * rb) * &t[i][j]);
                    }
                }
                out[b][a] = v.clone();
                out[a][b] = v;
            }
        }
        out
    };
    Ok(SectionTables {
        coordinates,
        tables: raw.each_ref().map(transform),
        tops,
        corrections: Some((knots, combination)),
    })
}

/// Section `k`'s terms of `M` and `K` (closed-form integrals as named constants), the load's
/// mass at the top of the last section, and the section's shapes `(global index, length
/// power, text, top value)` and corrections.
#[allow(clippy::type_complexity)]
fn section_terms(
    config: &ModelConfig,
    k: usize,
    consts: &mut Constants,
    mass: &mut TermEntries,
    stiffness: &mut TermEntries,
) -> Result<(Vec<(usize, i32, String, String)>, Option<Corrections>), CodegenError> {
    let n = config.sections();
    let kind = if k == 1 {
        Kind::GuidedFree
    } else {
        Kind::FreeFree
    };
    let roots = RootTable::new(kind, config.modes[k - 1]);
    for (m, b) in roots.beta.iter().enumerate() {
        if !b.is_zero() {
            consts.add(
                format!("K_BETA_{k}_{}", m + 1),
                b,
                format!("root beta of mode {} of section {k}", m + 1),
            );
        }
    }
    let basis = local_basis(config, k, &roots);
    let section = section_tables(config, k, &basis, &roots)?;
    // prestress P(x) = p0 + p1 x, p0 = g (rho_a_k l_k + above), p1 = -g rho_a_k
    let above = match config.force_flow {
        ForceFlow::Cable => {
            let mut s: Vec<String> = (k + 1..=n).map(|j| format!("rho_a_{j}*l_{j}")).collect();
            s.push("m_l".into());
            Some(s.join(" + "))
        }
        ForceFlow::External if k == n => Some("m_l".into()),
        ForceFlow::External => Some("0".into()),
        ForceFlow::None => None,
    };
    let coords = &section.coordinates;
    for a in 0..coords.len() {
        for b in 0..coords.len() {
            pair_terms(
                k,
                (&coords[a], &coords[b]),
                (a, b),
                &section.tables,
                above.as_deref(),
                consts,
                mass,
                stiffness,
            );
        }
    }
    // every coordinate function's value at the top, registered once (the translation: 1)
    let tops: Vec<String> = coords
        .iter()
        .zip(&section.tops)
        .map(|(c, v)| {
            if c.index == 0 {
                return "1".to_string();
            }
            consts.add(
                format!("K_TOP_{k}_{}", c.label),
                v,
                format!("psi_{k},{} at the top (xi = 1)", c.label),
            )
        })
        .collect();
    // the load at the top of section n: m_L h h'
    if k == n {
        let h: Vec<(usize, String)> = coords
            .iter()
            .zip(&tops)
            .map(|(c, top)| (c.index, format!("{}*{top}", length_pow(k, c.length_power))))
            .collect();
        for (ga, ha) in &h {
            for (gb, hb) in &h {
                if ga <= gb {
                    mass.entry((*ga, *gb))
                        .or_default()
                        .push(format!("m_l*{ha}*{hb}"));
                }
            }
        }
    }
    let mut section_shapes = Vec::new();
    for ((g, f, i), top) in basis.iter().zip(&tops).skip(1) {
        let text = shape_text(f, &roots, k, *i, consts);
        section_shapes.push((*g, f.length_power, text, top.clone()));
    }
    let corrections = section.corrections.map(|(knots, combination)| Corrections {
        first_index: first_correction(config, k),
        knots,
        combination: combination
            .iter()
            .map(|row| row.iter().map(Real::to_f64).collect())
            .collect(),
        tops: tops[basis.len()..].to_vec(),
    });
    Ok((section_shapes, corrections))
}

/// The terms of basis functions `a` and `b` of section `k` (every ordered pair of global
/// indices once) in `M` (mass) and `K` (bending, and with `above` the prestress of the
/// weight above).
#[allow(clippy::too_many_arguments)]
fn pair_terms(
    k: usize,
    (ca, cb): (&Coordinate, &Coordinate),
    (a, b): (usize, usize),
    [mass_table, bending, axial, axial_x]: &[Vec<Vec<Real>>; 4],
    above: Option<&str>,
    consts: &mut Constants,
    mass: &mut TermEntries,
    stiffness: &mut TermEntries,
) {
    let ((ga, ia), (gb, ib)) = ((&ca.index, &ca.label), (&cb.index, &cb.label));
    if ga > gb {
        return;
    }
    let lp = ca.length_power + cb.length_power;
    let key = (*ga, *gb);
    let tag = format!("{k}_{ia}_{ib}");
    if !is_zero(&mass_table[a][b]) {
        let c = consts.add(
            format!("K_M_{tag}"),
            &mass_table[a][b],
            format!("int psi_{k},{ia} psi_{k},{ib} dxi"),
        );
        mass.entry(key)
            .or_default()
            .push(format!("rho_a_{k}*{}*{c}", length_pow(k, lp + 1)));
    }
    if !is_zero(&bending[a][b]) {
        let c = consts.add(
            format!("K_EI_{tag}"),
            &bending[a][b],
            format!("int psi_{k},{ia}'' psi_{k},{ib}'' dxi"),
        );
        stiffness
            .entry(key)
            .or_default()
            .push(format!("ei_{k}*{}*{c}", length_pow(k, lp - 3)));
    }
    if let Some(above) = above {
        if !is_zero(&axial[a][b]) {
            let c = consts.add(
                format!("K_AX_{tag}"),
                &axial[a][b],
                format!("int psi_{k},{ia}' psi_{k},{ib}' dxi"),
            );
            stiffness.entry(key).or_default().push(format!(
                "-g*(rho_a_{k}*l_{k} + {above})*{}*{c}",
                length_pow(k, lp - 1)
            ));
        }
        if !is_zero(&axial_x[a][b]) {
            let c = consts.add(
                format!("K_AXX_{tag}"),
                &axial_x[a][b],
                format!("int xi psi_{k},{ia}' psi_{k},{ib}' dxi"),
            );
            stiffness
                .entry(key)
                .or_default()
                .push(format!("g*rho_a_{k}*{}*{c}", length_pow(k, lp)));
        }
    }
}

/// The generalized forces `q_i = b_i f_drive - sum_j k_i_j z_j - sum_c f_c g_c_i` as text,
/// and the coordinates each contact vector touches.
fn force_terms(config: &ModelConfig, stiffness: &TermEntries) -> (Vec<String>, Vec<Vec<usize>>) {
    let (n, dof) = (config.sections(), config.dof());
    // generalized forces: q_i = b_i f_drive - sum_j k_i_j z_j - sum_c f_c g_c_i
    let mut contact_pattern = Vec::new();
    for k in 2..=n {
        let mut pattern: Vec<usize> =
            (config.offset(k - 1)..config.offset(k) + config.coordinates(k)).collect();
        pattern.retain(|&j| j != 0);
        for _ in 0..config.contacts {
            contact_pattern.push(pattern.clone());
        }
    }
    let mut forces = Vec::new();
    for i in 0..dof {
        let mut terms = Vec::new();
        if i == 0 {
            terms.push("f_drive".to_string());
        }
        for ((a, b), _) in stiffness.iter() {
            if *a == i {
                terms.push(format!("-k_{a}_{b}*z_{b}"));
            } else if *b == i {
                terms.push(format!("-k_{b}_{a}*z_{a}"));
            }
        }
        for (c, pat) in contact_pattern.iter().enumerate() {
            if pat.contains(&i) {
                terms.push(format!("-f_{c}*g_{c}_{i}"));
            }
        }
        forces.push(if terms.is_empty() {
            "0".into()
        } else {
            terms.join(" + ")
        });
    }
    (forces, contact_pattern)
}

/// Everything that needs Symbolica, on its thread.
fn symbolic_part(
    inputs: Inputs,
    config: ModelConfig,
    constants: Vec<Constant>,
) -> Result<Derivation, CodegenError> {
    let parse = |s: &str| -> Result<Atom, CodegenError> {
        symbolica::try_parse!(s)
            .map_err(|e| CodegenError::Symbolica(format!("cannot parse `{s}`: {e}")))
    };
    let convert = |a: &Atom| symbolic::to_expr(a.as_view()).map_err(CodegenError::Symbolica);
    let entries = |m: &BTreeMap<(usize, usize), Vec<String>>| -> Result<Entries, CodegenError> {
        let mut out = Vec::new();
        for (key, terms) in m {
            let a = parse(&terms.join(" + "))?.expand();
            if !a.is_zero() {
                out.push((*key, convert(&a)?));
            }
        }
        Ok(out)
    };
    let mass = entries(&inputs.mass)?;
    let stiffness = entries(&inputs.stiffness)?;
    let xi = symbolica::symbol!("xi");
    let mut bases = Vec::new();
    for section in &inputs.shapes {
        let mut funcs = Vec::new();
        for (index, length_power, text, top) in section {
            let value = parse(text)?;
            let slope = value.derivative(xi);
            funcs.push(BasisFunction {
                index: *index,
                length_power: *length_power,
                value: convert(&value)?,
                slope: convert(&slope)?,
                top: top.clone(),
            });
        }
        bases.push(funcs);
    }
    // q with f_c kept as symbols (emitted as named locals)
    let forces_atoms: Vec<Atom> = inputs
        .forces
        .iter()
        .map(|s| parse(s))
        .collect::<Result<_, _>>()?;
    let forces = forces_atoms
        .iter()
        .map(&convert)
        .collect::<Result<Vec<_>, _>>()?;
    // the Jacobian: substitute the law f_c = kc_c (xi_c - off_c) + dc_c xid_c with
    // xi_c = g_c . z, xid_c = g_c . zd + gd_c . z, and differentiate
    let mut laws = Vec::new();
    for (c, pat) in inputs.contact_pattern.iter().enumerate() {
        let xi_c: Vec<String> = pat.iter().map(|j| format!("g_{c}_{j}*z_{j}")).collect();
        let xid_c: Vec<String> = pat
            .iter()
            .map(|j| format!("g_{c}_{j}*zd_{j} + gd_{c}_{j}*z_{j}"))
            .collect();
        laws.push((
            symbolica::symbol!(&format!("f_{c}")),
            parse(&format!(
                "kc_{c}*({} - off_{c}) + dc_{c}*({})",
                xi_c.join(" + "),
                xid_c.join(" + ")
            ))?,
        ));
    }
    let mut jacobian_z = Vec::new();
    let mut jacobian_zd = Vec::new();
    for (i, q) in forces_atoms.iter().enumerate() {
        let mut full = q.clone();
        for (sym, law) in &laws {
            full = full.replace(Atom::var(*sym)).with(law.to_pattern());
        }
        let full = full.expand();
        for j in 0..inputs.dof {
            for (name, out) in [("z", &mut jacobian_z), ("zd", &mut jacobian_zd)] {
                let d = full
                    .derivative(symbolica::symbol!(&format!("{name}_{j}")))
                    .expand();
                if !d.is_zero() {
                    out.push(((i, j), convert(&d)?));
                }
            }
        }
    }
    Ok(Derivation {
        config,
        constants,
        mass,
        stiffness,
        bases,
        corrections: inputs.corrections,
        forces,
        jacobian_z,
        jacobian_zd,
        contact_pattern: inputs.contact_pattern,
    })
}
