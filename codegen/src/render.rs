//! Human-readable renderings of a derivation, produced at build time and embedded in the
//! `generated` crate for `telescopic equations`: plain text, a standalone LaTeX document and
//! JSON (for controller-design tools).

use crate::config::ModelConfig;
use crate::derive::Derivation;
use crate::expr::Expr;
use std::fmt::Write as _;

/// What every rendering states before the equations: coordinates, normalisation, symbols.
fn preamble(c: &ModelConfig) -> Vec<String> {
    let mut lines = vec![
        "Coordinates z (computing coordinates: an exact linear change of the model's q, docs/model.md):".to_string(),
        "  z_0 = u = w_1(0,t), the vehicle position; basis function: the unit translation of every section".to_string(),
    ];
    for k in 1..=c.sections() {
        for i in 1..=c.modes[k - 1] {
            let j = c.offset(k) + i - 1;
            let what = match (k, i) {
                (1, 1) => continue,
                (1, _) => format!(
                    "section 1, mode {i}: psi = phi_1,{i}(x) - phi_1,{i}(0) (zero at the vehicle)"
                ),
                (_, 1) => {
                    format!("section {k}, mode 1: psi = 1 (rigid offset of section {k} from u)")
                }
                (_, 2) => format!("section {k}, mode 2: psi = x (rigid rotation)"),
                _ => format!("section {k}, mode {i}: psi = phi_{k},{i}(x)"),
            };
            lines.push(format!("  z_{j}: {what}"));
        }
    }
    lines.extend([
        "Shape functions: the paper's printed normalisation (section 1: cos(b xi) + cos(b)/cosh(b) cosh(b xi);".to_string(),
        "  sections k >= 2: cosh + cos - sigma (sinh + sin), int phi^2 = l), written in xi = x/l_k with every".to_string(),
        "  exponential of non-positive argument (cancellation-free); psi_k,i(x) = l_k^p psi_k,i(xi).".to_string(),
        "Parameters: rho_a_k [kg/m], ei_k [N m^2], l_k [m], m_t, m_l [kg], g [m/s^2]; positions a_k(t) [m];".to_string(),
        "  contact law: c [N/m], d [N s/m], l_S [m]; drive force f_drive = F(t) [N].".to_string(),
        "Equations: M z'' = q,  q = b F(t) - K z - sum_c f_c g_c(t),  b = e_0;".to_string(),
        "  xi_c = g_c . z,  xi_dot_c = g_c . z' + gdot_c . z;".to_string(),
        if c.clearance {
            "  f_c = c (xi_c - l_S/2) + d xi_dot_c above the band, c (xi_c + l_S/2) + d xi_dot_c below, 0 for |xi_c| <= l_S/2;"
        } else {
            "  f_c = c xi_c + d xi_dot_c (l_S = 0: the linear law);"
        }
        .to_string(),
        "  in the Jacobian, kc_c = df_c/dxi_c and dc_c = df_c/dxi_dot_c in the contact's branch (c, d or 0, 0).".to_string(),
        "Contact c = (overlap k, point j), s_j = j/(n_c - 1): g_c = +psi_k(xi_in) on section k, -psi_(k-1)(xi_out) on".to_string(),
        "  section k-1, xi_in = s_j (l_(k-1) - a_k)/l_k, xi_out = (a_k + s_j (l_(k-1) - a_k))/l_(k-1);".to_string(),
        "  gdot_c from dpsi/dxi with dxi_in/dt = -s_j a_k'/l_k, dxi_out/dt = (1 - s_j) a_k'/l_(k-1).".to_string(),
    ]);
    lines
}

/// Each section's static correction shapes as lines of text: the knots, and each shape as
/// its combination of the section's mode functions (`psi_k,i` of the basis functions above)
/// and cubic B-splines `B_k,s` (empty for the paper's modes).
fn correction_lines(d: &Derivation) -> Vec<String> {
    let mut lines = Vec::new();
    for (k0, c) in d.corrections.iter().enumerate() {
        let (Some(c), k) = (c, k0 + 1) else { continue };
        let modes: Vec<usize> = d.bases[k0].iter().map(|b| b.index).collect();
        lines.push(format!(
            "section {k}: B_{k},s (s = 1..{}) the clamped cubic B-splines on xi = 0, 0, 0, 0, \
             {:?}, 1, 1, 1, 1 without the first two",
            c.combination.len(),
            c.knots
        ));
        for (e, row) in c.combination.iter().enumerate() {
            let terms: Vec<String> = row
                .iter()
                .enumerate()
                .filter(|(_, v)| **v != 0.0)
                .map(|(j, v)| match modes.get(j) {
                    Some(i) => format!("{v:e} psi_{i}"),
                    None => format!("{v:e} B_{k},{}", j - modes.len() + 1),
                })
                .collect();
            lines.push(format!(
                "  z_{} on section {k}: l_{k}^0 * ({})",
                c.first_index + e,
                terms.join(" + ")
            ));
        }
    }
    lines
}

/// The plain-text rendering.
pub fn text(d: &Derivation) -> String {
    let c = &d.config;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Model {} (telescopic-codegen {})",
        c.key(),
        crate::GENERATOR_VERSION
    );
    let _ = writeln!(s, "Configuration: {c}\n");
    for l in preamble(c) {
        let _ = writeln!(s, "{l}");
    }
    let _ = writeln!(
        s,
        "\nMass matrix M (symmetric; nonzero entries of the upper triangle):"
    );
    for ((i, j), e) in &d.mass {
        let _ = writeln!(s, "  M[{i}][{j}] = {}", e.to_text());
    }
    let _ = writeln!(
        s,
        "\nStiffness matrix K (elastic minus prestress; symmetric; nonzero entries of the upper triangle):"
    );
    for ((i, j), e) in &d.stiffness {
        let _ = writeln!(s, "  K[{i}][{j}] = {}", e.to_text());
    }
    let _ = writeln!(
        s,
        "\nDrive vector: b = e_0 (F acts on the vehicle coordinate only)."
    );
    let _ = writeln!(s, "\nBasis functions (dimensionless, in xi = x/l_k):");
    for (k0, basis) in d.bases.iter().enumerate() {
        for b in basis {
            let _ = writeln!(
                s,
                "  z_{} on section {}: l_{}^{} * ({})",
                b.index,
                k0 + 1,
                k0 + 1,
                b.length_power,
                b.value.to_text()
            );
        }
    }
    let corrections = correction_lines(d);
    if !corrections.is_empty() {
        let _ = writeln!(
            s,
            "\nStatic correction shapes (orthogonal to the modes, orthonormal in int_0^1 psi psi dxi):"
        );
        for l in corrections {
            let _ = writeln!(s, "  {l}");
        }
    }
    let _ = writeln!(s, "\nContact vectors: nonzero entries of g_c (and gdot_c):");
    for (ci, pat) in d.contact_pattern.iter().enumerate() {
        let idx: Vec<String> = pat.iter().map(|j| j.to_string()).collect();
        let _ = writeln!(s, "  contact {ci}: coordinates {}", idx.join(", "));
    }
    let _ = writeln!(
        s,
        "\nGeneralized forces q (f_c contact forces, k_i_j entries of K, g_c_j of g_c):"
    );
    for (i, e) in d.forces.iter().enumerate() {
        let _ = writeln!(s, "  q[{i}] = {}", e.to_text());
    }
    let _ = writeln!(
        s,
        "\nJacobian of q by symbolic differentiation (nonzero entries):"
    );
    for ((i, j), e) in &d.jacobian_z {
        let _ = writeln!(s, "  dq[{i}]/dz[{j}] = {}", e.to_text());
    }
    for ((i, j), e) in &d.jacobian_zd {
        let _ = writeln!(s, "  dq[{i}]/dz'[{j}] = {}", e.to_text());
    }
    let _ = writeln!(s, "\nConstants (each the f64 nearest its 512-bit value):");
    for k in &d.constants {
        let _ = writeln!(s, "  {} = {:?}  ({})", k.name, k.value, k.doc);
    }
    s
}

/// LaTeX for an expression.
fn latex(e: &Expr) -> String {
    fn sym(s: &str) -> String {
        // rho_a_1 -> \rho A_{1}, ei_2 -> EI_{2}, K_M_1_0_2 -> K^{M}_{1,0,2}, z_3 -> z_{3}
        if let Some(rest) = s.strip_prefix("K_") {
            let mut parts = rest.split('_');
            let kind = parts.next().unwrap_or("");
            let idx: Vec<&str> = parts.collect();
            return format!("K^{{\\mathrm{{{kind}}}}}_{{{}}}", idx.join(","));
        }
        let (base, idx) = match s.rfind('_') {
            Some(p) if s[p + 1..].chars().all(|c| c.is_ascii_digit()) => {
                (&s[..p], Some(&s[p + 1..]))
            }
            _ => (s, None),
        };
        let base = match base {
            "rho_a" => "\\rho A".to_string(),
            "ei" => "EI".to_string(),
            "m_t" => "m_T".to_string(),
            "m_l" => "m_L".to_string(),
            "xi" => "\\xi".to_string(),
            b => b.replace('_', "\\_"),
        };
        match idx {
            Some(i) => format!("{base}_{{{i}}}"),
            None => base,
        }
    }
    match e {
        Expr::Rational(n, 1) => n.to_string(),
        Expr::Rational(n, d) => format!("\\frac{{{n}}}{{{d}}}"),
        Expr::Symbol(s) | Expr::Constant(s) => sym(s),
        Expr::Temp(i) => format!("t_{{{i}}}"),
        Expr::Add(v) => {
            let mut out = String::new();
            for (i, t) in v.iter().enumerate() {
                let p = latex(t);
                if i > 0 && !p.starts_with('-') {
                    out.push_str(" + ");
                } else if i > 0 {
                    out.push(' ');
                }
                out.push_str(&p);
            }
            out
        }
        Expr::Mul(v) => {
            let parts: Vec<String> = v
                .iter()
                .map(|t| {
                    if matches!(t, Expr::Add(_)) {
                        format!("\\left({}\\right)", latex(t))
                    } else {
                        latex(t)
                    }
                })
                .collect();
            let joined = parts.join(" \\, ");
            joined.replacen("-1 \\, ", "-", 1)
        }
        Expr::Pow(b, n) => format!(
            "{{{}}}^{{{n}}}",
            if matches!(**b, Expr::Add(_) | Expr::Mul(_)) {
                format!("\\left({}\\right)", latex(b))
            } else {
                latex(b)
            }
        ),
        Expr::Exp(b) => format!("e^{{{}}}", latex(b)),
        Expr::Cos(b) => format!("\\cos\\left({}\\right)", latex(b)),
        Expr::Sin(b) => format!("\\sin\\left({}\\right)", latex(b)),
    }
}

/// A standalone LaTeX document (compiles with plain `pdflatex`; `amsmath` only).
pub fn latex_document(d: &Derivation) -> String {
    let c = &d.config;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "\\documentclass[10pt]{{article}}\n\\usepackage{{amsmath}}\n\\usepackage[margin=1.5cm]{{geometry}}\n\\allowdisplaybreaks"
    );
    let _ = writeln!(s, "\\begin{{document}}");
    let _ = writeln!(
        s,
        "\\section*{{Model \\texttt{{{}}}}}",
        c.key().replace('_', "\\_")
    );
    let _ = writeln!(
        s,
        "Generated by telescopic-codegen {}. Configuration: {}.\n",
        crate::GENERATOR_VERSION,
        c.to_string().replace('_', "\\_")
    );
    let _ = writeln!(s, "\\begin{{verbatim}}");
    for l in preamble(c) {
        let _ = writeln!(s, "{l}");
    }
    let _ = writeln!(s, "\\end{{verbatim}}");
    let block = |s: &mut String, title: &str, rows: Vec<(String, String)>| {
        let _ = writeln!(s, "\\subsection*{{{title}}}\n\\begin{{align*}}");
        let n = rows.len();
        for (i, (lhs, rhs)) in rows.into_iter().enumerate() {
            let end = if i + 1 < n { " \\\\" } else { "" };
            let _ = writeln!(s, "{lhs} &= {rhs}{end}");
        }
        let _ = writeln!(s, "\\end{{align*}}");
    };
    block(
        &mut s,
        "Mass matrix $M$",
        d.mass
            .iter()
            .map(|((i, j), e)| (format!("M_{{{i},{j}}}"), latex(e)))
            .collect(),
    );
    block(
        &mut s,
        "Stiffness matrix $K$",
        d.stiffness
            .iter()
            .map(|((i, j), e)| (format!("K_{{{i},{j}}}"), latex(e)))
            .collect(),
    );
    block(
        &mut s,
        "Basis functions",
        d.bases
            .iter()
            .enumerate()
            .flat_map(|(k0, b)| {
                b.iter().map(move |f| {
                    (
                        format!(
                            "\\psi_{{{}}}(\\xi)\\ \\text{{on section {}}}",
                            f.index,
                            k0 + 1
                        ),
                        latex(&f.value),
                    )
                })
            })
            .collect(),
    );
    let corrections = correction_lines(d);
    if !corrections.is_empty() {
        let _ = writeln!(
            s,
            "\\subsection*{{Static correction shapes}}\n\\begin{{verbatim}}\n{}\n\\end{{verbatim}}",
            corrections.join("\n")
        );
    }
    block(
        &mut s,
        "Generalized forces $q$",
        d.forces
            .iter()
            .enumerate()
            .map(|(i, e)| (format!("q_{{{i}}}"), latex(e)))
            .collect(),
    );
    let _ = writeln!(s, "\\subsection*{{Constants}}\n\\begin{{verbatim}}");
    for k in &d.constants {
        let _ = writeln!(s, "{} = {:?}", k.name, k.value);
    }
    let _ = writeln!(s, "\\end{{verbatim}}\n\\end{{document}}");
    s
}

/// JSON: the configuration, constants and every entry as text.
pub fn json(d: &Derivation) -> String {
    fn q(s: &str) -> String {
        let mut out = String::from("\"");
        for ch in s.chars() {
            match ch {
                '"' => out.push_str("\\\""),
                '\\' => out.push_str("\\\\"),
                '\n' => out.push_str("\\n"),
                c => out.push(c),
            }
        }
        out.push('"');
        out
    }
    let entries = |v: &[((usize, usize), Expr)]| -> String {
        let items: Vec<String> = v
            .iter()
            .map(|((i, j), e)| format!("{{\"i\": {i}, \"j\": {j}, \"expr\": {}}}", q(&e.to_text())))
            .collect();
        format!("[{}]", items.join(", "))
    };
    let c = &d.config;
    let constants: Vec<String> = d
        .constants
        .iter()
        .map(|k| format!("{}: {:?}", q(&k.name), k.value))
        .collect();
    let forces: Vec<String> = d.forces.iter().map(|e| q(&e.to_text())).collect();
    let bases: Vec<String> = d
        .bases
        .iter()
        .enumerate()
        .flat_map(|(k0, b)| {
            b.iter().map(move |f| {
                format!(
                    "{{\"index\": {}, \"section\": {}, \"length_power\": {}, \"psi\": {}, \"dpsi_dxi\": {}}}",
                    f.index,
                    k0 + 1,
                    f.length_power,
                    q(&f.value.to_text()),
                    q(&f.slope.to_text())
                )
            })
        })
        .collect();
    let corrections: Vec<String> = d
        .corrections
        .iter()
        .enumerate()
        .filter_map(|(k0, c)| c.as_ref().map(|c| (k0 + 1, c)))
        .map(|(k, c)| {
            format!(
                "{{\"section\": {k}, \"first_index\": {}, \"knots\": {:?}, \"combination\": {:?}}}",
                c.first_index, c.knots, c.combination
            )
        })
        .collect();
    format!(
        "{{\"key\": {}, \"generator\": {}, \"modes\": {:?}, \"contacts\": {}, \"dof\": {}, \"drive_vector\": \"e_0\", \
         \"coordinates\": {}, \"constants\": {{{}}}, \"mass\": {}, \"stiffness\": {}, \"basis\": [{}], \"static_corrections\": [{}], \"forces\": [{}], \
         \"jacobian_z\": {}, \"jacobian_zd\": {}}}\n",
        q(&c.key()),
        q(crate::GENERATOR_VERSION),
        c.modes,
        c.contacts,
        c.dof(),
        q(&preamble(c).join("\n")),
        constants.join(", "),
        entries(&d.mass),
        entries(&d.stiffness),
        bases.join(", "),
        corrections.join(", "),
        forces.join(", "),
        entries(&d.jacobian_z),
        entries(&d.jacobian_zd),
    )
}
