//! Emission of a derived model as a Rust module (quote / proc-macro2, checked by
//! `syn::parse_file`, formatted by `prettyplease`).
//!
//! The module implements `telescopic_runtime::Model` for `GeneratedModel`. Per-scene work
//! (matrices from the parameters, `M^-1`, fixed contact vectors, output vectors) happens in
//! `GeneratedModel::prepare`; the per-call path is straight-line code over fixed-size arrays
//! with the structural zeros of the derivation dropped, and allocates nothing.

use crate::config::{DriveKind, ModelConfig, Positions};
use crate::derive::Derivation;
use crate::expr::{Expr, eliminate_common};
use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};
use std::str::FromStr;

/// An `f64` literal that reads back to the same value (shortest round-trip form), with a
/// leading `-` when negative.
fn float(v: f64) -> TokenStream {
    let lit = Literal::from_str(&format!("{:?}", v.abs())).expect("a float literal");
    if v.is_sign_negative() {
        quote!(-#lit)
    } else {
        quote!(#lit)
    }
}

/// How tightly emitted tokens bind, loosest first: a term of a sum needs at least
/// `Product`, a factor at least `Literal`, a method receiver `Atom`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Binding {
    Sum,
    Negated,
    Product,
    Literal,
    Atom,
}

/// Tokens and how tightly they bind.
struct Emitted {
    tokens: TokenStream,
    binding: Binding,
}

impl Emitted {
    /// The tokens, parenthesized unless they bind at least as tightly as `needed`.
    fn at_least(self, needed: Binding) -> TokenStream {
        let t = self.tokens;
        if self.binding >= needed {
            t
        } else {
            quote!((#t))
        }
    }
}

/// Splits a product's numeric factors from the rest: (negative?, remaining factors, with a
/// coefficient of magnitude 1 dropped).
fn signed_factors(factors: &[Expr]) -> (bool, Vec<Expr>) {
    let mut negative = false;
    let mut rest = Vec::with_capacity(factors.len());
    for f in factors {
        match f {
            Expr::Rational(n, d) => {
                negative ^= (*n < 0) != (*d < 0);
                if n.unsigned_abs() != d.unsigned_abs() {
                    rest.push(Expr::Rational(n.abs(), d.abs()));
                }
            }
            _ => rest.push(f.clone()),
        }
    }
    (negative, rest)
}

/// The magnitude of a sum's term and whether it is subtracted.
fn signed_term(term: &Expr) -> (bool, Expr) {
    match term {
        Expr::Rational(n, d) if (*n < 0) != (*d < 0) => (true, Expr::Rational(n.abs(), d.abs())),
        Expr::Mul(factors) => {
            let (negative, rest) = signed_factors(factors);
            let magnitude = match rest.len() {
                0 => Expr::Rational(1, 1),
                1 => rest.into_iter().next().expect("one factor"),
                _ => Expr::Mul(rest),
            };
            (negative, magnitude)
        }
        _ => (false, term.clone()),
    }
}

/// Rust tokens for an expression, with symbols resolved by `map` (unmapped symbols become
/// identifiers of the same name) and constants by their upper-case names. Parentheses only
/// where precedence needs them or where they fix the evaluation order of the derivation
/// (a nested sum or product keeps its own parentheses: floating-point `+` and `*` are not
/// associative).
fn tokens(e: &Expr, map: &dyn Fn(&str) -> Option<TokenStream>) -> TokenStream {
    emitted(e, map).tokens
}

fn emitted(e: &Expr, map: &dyn Fn(&str) -> Option<TokenStream>) -> Emitted {
    let rec = |x: &Expr| emitted(x, map);
    let atom = |tokens| Emitted {
        tokens,
        binding: Binding::Atom,
    };
    let call = |base: &Expr, method: TokenStream| {
        let b = rec(base).at_least(Binding::Atom);
        atom(quote!(#b.#method))
    };
    match e {
        Expr::Rational(n, d) => {
            let v = *n as f64 / *d as f64;
            Emitted {
                tokens: float(v),
                binding: if v < 0.0 {
                    Binding::Negated
                } else {
                    Binding::Literal
                },
            }
        }
        Expr::Symbol(s) => atom(map(s).unwrap_or_else(|| {
            let id = format_ident!("{}", s);
            quote!(#id)
        })),
        Expr::Add(terms) => {
            let mut out = TokenStream::new();
            for (i, term) in terms.iter().enumerate() {
                let (negative, magnitude) = signed_term(term);
                let t = rec(&magnitude).at_least(Binding::Product);
                out.extend(match (i, negative) {
                    (0, false) => quote!(#t),
                    (0, true) => quote!(-#t),
                    (_, false) => quote!(+ #t),
                    (_, true) => quote!(- #t),
                });
            }
            Emitted {
                tokens: out,
                binding: Binding::Sum,
            }
        }
        Expr::Mul(factors) => {
            let (negative, rest) = signed_factors(factors);
            if !negative && rest.len() == 1 {
                return rec(&rest[0]);
            }
            let mut parts = rest.iter().map(|f| rec(f).at_least(Binding::Literal));
            let first = parts.next().unwrap_or_else(|| quote!(1.0));
            // quote's `#(..)*` cannot take `*` as a separator: join by hand
            let product = parts.fold(first, |acc, p| quote!(#acc * #p));
            if negative {
                // unary minus binds tighter than `*`; negation is exact, so `-a * b` is `-(a b)`
                Emitted {
                    tokens: quote!(-#product),
                    binding: Binding::Negated,
                }
            } else {
                Emitted {
                    tokens: product,
                    binding: Binding::Product,
                }
            }
        }
        Expr::Pow(b, n) => match *n {
            -1 => call(b, quote!(recip())),
            n => {
                let lit = Literal::i32_unsuffixed(n.abs());
                if n < 0 {
                    call(b, quote!(powi(-#lit)))
                } else {
                    call(b, quote!(powi(#lit)))
                }
            }
        },
        Expr::Exp(b) => call(b, quote!(exp())),
        Expr::Cos(b) => call(b, quote!(cos())),
        Expr::Sin(b) => call(b, quote!(sin())),
        Expr::Constant(s) => {
            let id = format_ident!("{}", s.to_uppercase());
            atom(quote!(#id))
        }
        Expr::Temp(i) => {
            let id = format_ident!("t{}", i);
            atom(quote!(#id))
        }
    }
}

/// `[i][j]`-style indices parsed from a symbol such as `k_3_4`.
fn indices(s: &str, prefix: &str) -> Option<Vec<usize>> {
    let rest = s.strip_prefix(prefix)?;
    rest.split('_').map(|p| p.parse().ok()).collect()
}

/// How the per-call code reads the derivation's symbols.
fn call_symbol(s: &str) -> Option<TokenStream> {
    if let Some(v) = indices(s, "zd_") {
        let j = v[0];
        return Some(quote!(zd[#j]));
    }
    if let Some(v) = indices(s, "z_") {
        let j = v[0];
        return Some(quote!(z[#j]));
    }
    if let Some(v) = indices(s, "gd_") {
        let (c, j) = (v[0], v[1]);
        return Some(quote!(geo.gd[#c][#j]));
    }
    if let Some(v) = indices(s, "g_") {
        let (c, j) = (v[0], v[1]);
        return Some(quote!(geo.g[#c][#j]));
    }
    if let Some(v) = indices(s, "k_") {
        let (i, j) = (v[0], v[1]);
        return Some(quote!(self.k[#i][#j]));
    }
    if let Some(v) = indices(s, "kc_") {
        let c = v[0];
        return Some(quote!(law[#c].d_gap));
    }
    if let Some(v) = indices(s, "dc_") {
        let c = v[0];
        return Some(quote!(law[#c].d_rate));
    }
    if let Some(v) = indices(s, "f_") {
        let c = v[0];
        return Some(quote!(f[#c]));
    }
    None
}

/// `let` bindings of the parameters a matrix expression reads, by physical name.
fn parameter_bindings(config: &ModelConfig) -> TokenStream {
    let mut out = TokenStream::new();
    for k in 0..config.sections() {
        let (rho, ei, l) = (
            format_ident!("rho_a_{}", k + 1),
            format_ident!("ei_{}", k + 1),
            format_ident!("l_{}", k + 1),
        );
        out.extend(quote! {
            let #rho = p.sections[#k].mass_per_length;
            let #ei = p.sections[#k].bending_stiffness;
            let #l = p.sections[#k].length;
        });
    }
    out.extend(quote! {
        let m_t = p.vehicle_mass;
        let m_l = p.load_mass;
        let g = p.gravity;
    });
    out
}

/// Marks a doc attribute that [`emit`] turns into a plain `//` comment after formatting
/// (quote cannot carry comments, and a doc comment on a block would be unused).
const LINE_COMMENT: &str = "@line-comment@";

/// A `// text` line comment before the next statement (`text` starts with a space).
fn line_comment(text: &str) -> TokenStream {
    let marked = format!("{LINE_COMMENT}{text}");
    quote!(#[doc = #marked])
}

/// Integer literals without their type suffix (`2` rather than `quote`'s `2usize`): the
/// types follow from the context in every place the module uses them.
fn unsuffixed(tokens: TokenStream) -> TokenStream {
    use proc_macro2::{Group, TokenTree};
    tokens
        .into_iter()
        .map(|tree| match tree {
            TokenTree::Group(g) => {
                let mut inner = Group::new(g.delimiter(), unsuffixed(g.stream()));
                inner.set_span(g.span());
                TokenTree::Group(inner)
            }
            TokenTree::Literal(lit) => {
                let text = lit.to_string();
                let digits = ["usize", "i32"]
                    .iter()
                    .find_map(|suffix| text.strip_suffix(suffix))
                    .filter(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()));
                match digits {
                    Some(d) => TokenTree::Literal(Literal::from_str(d).expect("digits")),
                    None => TokenTree::Literal(lit),
                }
            }
            other => other,
        })
        .collect()
}

/// A symmetric matrix function from its upper-triangle entries, with common subexpressions
/// as temporaries.
fn matrix_fn(
    name: &str,
    doc: &str,
    config: &ModelConfig,
    entries: &[((usize, usize), Expr)],
) -> TokenStream {
    let fname = format_ident!("{}", name);
    let exprs: Vec<Expr> = entries.iter().map(|(_, e)| e.clone()).collect();
    let (temps, exprs) = eliminate_common(&exprs);
    let temp_lets = temps.iter().enumerate().map(|(i, t)| {
        let id = format_ident!("t{}", i);
        let v = tokens(t, &|_| None);
        quote!(let #id = #v;)
    });
    let sets = entries.iter().zip(&exprs).map(|(((i, j), original), e)| {
        let v = tokens(e, &|_| None);
        let comment = format!(" {name}[{i}][{j}] = {}", original.to_text());
        if i == j {
            let note = line_comment(&comment);
            quote! { #note { m[(#i, #j)] = #v; } }
        } else {
            let note = line_comment(&comment);
            quote! { #note { let v = #v; m[(#i, #j)] = v; m[(#j, #i)] = v; } }
        }
    });
    let bindings = parameter_bindings(config);
    quote! {
        #[doc = #doc]
        #[allow(unused_variables)]
        pub fn #fname(p: &ModelParams) -> DMatrix<f64> {
            #bindings
            #(#temp_lets)*
            let mut m = DMatrix::zeros(DOF, DOF);
            #(#sets)*
            m
        }
    }
}

/// The emitted module's source, formatted.
///
/// # Errors
/// A message if the tokens do not parse as a Rust file (a generator bug).
pub fn emit(d: &Derivation, header: &str) -> Result<String, String> {
    let c = &d.config;
    let n = c.sections();
    let dof = c.dof();
    let nc = c.contact_count();
    let constants = d.constants.iter().map(|k| {
        let id = format_ident!("{}", k.name.to_uppercase());
        let v = float(k.value);
        let doc = format!(" {}", k.doc);
        quote!(#[doc = #doc] pub const #id: f64 = #v;)
    });
    let mass_fn = matrix_fn(
        "mass_matrix",
        " Mass matrix `M` in computing coordinates (dof x dof).",
        c,
        &d.mass,
    );
    let stiffness_fn = matrix_fn(
        "stiffness_matrix",
        " Stiffness matrix `K` (elastic minus prestress) in computing coordinates.",
        c,
        &d.stiffness,
    );

    // shape functions per section: values and d/dxi
    let mut shape_fns = Vec::new();
    for (k0, basis) in d.bases.iter().enumerate() {
        let k = k0 + 1;
        let fname = format_ident!("shapes_{}", k);
        let len = basis.len();
        let exprs: Vec<Expr> = basis
            .iter()
            .flat_map(|b| [b.value.clone(), b.slope.clone()])
            .collect();
        let (temps, exprs) = eliminate_common(&exprs);
        let temp_lets = temps.iter().enumerate().map(|(i, t)| {
            let id = format_ident!("t{}", i);
            let v = tokens(t, &|_| None);
            quote!(let #id = #v;)
        });
        let sets = exprs.chunks(2).enumerate().map(|(i, pair)| {
            let (v, s) = (tokens(&pair[0], &|_| None), tokens(&pair[1], &|_| None));
            let doc = format!(" psi_{k},{} = {}", basis[i].index, basis[i].value.to_text());
            let note = line_comment(&doc);
            quote! { #note { value[#i] = #v; slope[#i] = #s; } }
        });
        let doc = format!(
            " Basis functions of section {k} at `xi = x / l_{k}` (cancellation-free forms) and their `d/dxi`, \
             without the factor `l_{k}^p` (see `LENGTH_POWERS_{k}`)."
        );
        shape_fns.push(quote! {
            #[doc = #doc]
            #[inline]
            pub fn #fname(xi: f64) -> ([f64; #len], [f64; #len]) {
                #(#temp_lets)*
                let mut value = [0.0; #len];
                let mut slope = [0.0; #len];
                #(#sets)*
                (value, slope)
            }
        });
        let idx_name = format_ident!("INDICES_{}", k);
        let lp_name = format_ident!("LENGTH_POWERS_{}", k);
        let top_name = format_ident!("TOPS_{}", k);
        let idx: Vec<usize> = basis.iter().map(|b| b.index).collect();
        let lps: Vec<i32> = basis.iter().map(|b| b.length_power).collect();
        let tops: Vec<TokenStream> = basis
            .iter()
            .map(|b| format_ident!("{}", b.top.to_uppercase()))
            .map(|i| quote!(#i))
            .collect();
        let doc_i = format!(" Global indices of section {k}'s basis functions.");
        let doc_l = format!(" Powers of `l_{k}` in front of section {k}'s basis functions.");
        let doc_t =
            format!(" Section {k}'s basis functions at its top (`xi = 1`), without `l_{k}^p`.");
        shape_fns.push(quote! {
            #[doc = #doc_i] pub const #idx_name: [usize; #len] = [#(#idx),*];
            #[doc = #doc_l] pub const #lp_name: [i32; #len] = [#(#lps),*];
            #[doc = #doc_t] pub const #top_name: [f64; #len] = [#(#tops),*];
        });
    }

    // contact geometry: for each overlap and point, the shapes at the moving contact points
    let mut geo_stmts = Vec::new();
    let mut cidx = 0usize;
    for k in 2..=n {
        let (ki, ko) = (k - 1, k - 2);
        let (shapes_in, shapes_out) = (
            format_ident!("shapes_{}", k),
            format_ident!("shapes_{}", k - 1),
        );
        let (idx_in, idx_out) = (
            format_ident!("INDICES_{}", k),
            format_ident!("INDICES_{}", k - 1),
        );
        for j in 0..c.contacts {
            let s = j as f64 / (c.contacts - 1) as f64;
            let s_tok = float(s);
            let one_minus = float(1.0 - s);
            geo_stmts.push(quote! {
                {
                    let l_out = self.lengths[#ko];
                    let l_in = self.lengths[#ki];
                    let (a, a_dot) = (positions[#ko].0, positions[#ko].1);
                    // x_in = s (l_out - a) on section k, x_out = a + s (l_out - a) on section k - 1
                    let xi_in = #s_tok * (l_out - a) / l_in;
                    let xi_out = (a + #s_tok * (l_out - a)) / l_out;
                    let rate_in = -#s_tok * a_dot / l_in;
                    let rate_out = #one_minus * a_dot / l_out;
                    let (v, sl) = #shapes_in(xi_in);
                    for i in 0..v.len() {
                        let f = self.length_factors[#ki][i];
                        geo.g[#cidx][#idx_in[i]] = f * v[i];
                        geo.gd[#cidx][#idx_in[i]] = f * sl[i] * rate_in;
                    }
                    let (v, sl) = #shapes_out(xi_out);
                    for i in 0..v.len() {
                        let f = self.length_factors[#ko][i];
                        geo.g[#cidx][#idx_out[i]] = -f * v[i];
                        geo.gd[#cidx][#idx_out[i]] = -f * sl[i] * rate_out;
                    }
                }
            });
            cidx += 1;
        }
    }

    // generalized forces and Jacobian
    let (ftemps, forces) = eliminate_common(&d.forces);
    let force_temps = ftemps.iter().enumerate().map(|(i, t)| {
        let id = format_ident!("t{}", i);
        let v = tokens(t, &call_symbol);
        quote!(let #id = #v;)
    });
    let force_sets = forces.iter().enumerate().map(|(i, e)| {
        let v = tokens(e, &call_symbol);
        let doc = format!(" q[{i}] = {}", d.forces[i].to_text());
        let note = line_comment(&doc);
        quote!(#note { q[#i] = #v; })
    });
    let jac_all: Vec<Expr> = d
        .jacobian_z
        .iter()
        .chain(&d.jacobian_zd)
        .map(|(_, e)| e.clone())
        .collect();
    let (jtemps, jac_all) = eliminate_common(&jac_all);
    let jac_temps = jtemps.iter().enumerate().map(|(i, t)| {
        let id = format_ident!("t{}", i);
        let v = tokens(t, &call_symbol);
        quote!(let #id = #v;)
    });
    let nz = d.jacobian_z.len();
    let jac_sets = d
        .jacobian_z
        .iter()
        .chain(&d.jacobian_zd)
        .zip(&jac_all)
        .enumerate()
        .map(|(m, (((i, j), _), e))| {
            let col = if m < nz { *j } else { dof + *j };
            let v = tokens(e, &call_symbol);
            quote!(dq[#i][#col] = #v;)
        });
    let gaps = (0..nc).map(|ci| {
        let pat = &d.contact_pattern[ci];
        let xi_terms = pat.iter().map(|&j| quote!(geo.g[#ci][#j] * z[#j]));
        let xid_terms = pat
            .iter()
            .map(|&j| quote!(geo.g[#ci][#j] * zd[#j] + geo.gd[#ci][#j] * z[#j]));
        quote! {
            xi[#ci] = #(#xi_terms)+*;
            xi_dot[#ci] = #(#xid_terms)+*;
        }
    });
    let gaps: Vec<TokenStream> = gaps.collect();

    let key = c.key();
    let fixed = c.positions == Positions::Fixed;
    let motion = c.drive == DriveKind::Motion;
    let n_pos = n - 1;
    let length_factors = (0..n).map(|k| {
        let lp = format_ident!("LENGTH_POWERS_{}", k + 1);
        quote!(#lp.map(|p| p_l[#k].powi(p)).to_vec())
    });
    let tip_sets = {
        let (idx, tops) = (format_ident!("INDICES_{}", n), format_ident!("TOPS_{}", n));
        quote! { for i in 0..#idx.len() { tip[#idx[i]] = length_factors[#n - 1][i] * #tops[i]; } }
    };
    let top1_sets = quote! { for i in 0..INDICES_1.len() { top1[INDICES_1[i]] = length_factors[0][i] * TOPS_1[i]; } };
    let positions_at = if n_pos > 0 {
        quote! {
            let mut positions = [(0.0, 0.0); #n_pos];
            for (k, p) in self.params.positions.iter().enumerate() {
                positions[k] = (p.value(t), p.rate(t));
            }
        }
    } else {
        quote!(let positions: [(f64, f64); 0] = [];)
    };
    // fixed positions: contact vectors once per scene (constant profiles, so any time will do);
    // moving positions: a table in time, built once per scene (runtime::ContactTable)
    let (geometry_field, geometry_init, geometry_finish, geometry_lookup) = if fixed {
        (
            quote!(fixed_geometry: Geometry,),
            quote!(fixed_geometry: Geometry { g: [[0.0; DOF]; CONTACTS], gd: [[0.0; DOF]; CONTACTS] },),
            quote!(let mut model = model; model.fixed_geometry = model.exact_geometry(0.0);),
            quote!(),
        )
    } else {
        (
            quote!(contact_table: Option<telescopic_runtime::ContactTable>,),
            quote!(contact_table: None,),
            quote! {
                let mut model = model;
                model.contact_table = telescopic_runtime::ContactTable::build(&model.params.positions, CONTACTS * DOF, |t, g, gd| {
                    let geo = model.exact_geometry(t);
                    g.copy_from_slice(geo.g.as_flattened());
                    gd.copy_from_slice(geo.gd.as_flattened());
                });
            },
            quote! {
                /// Contact vectors at time `t` (s): interpolated from the table while positions
                /// move, exact without a table.
                #[inline]
                fn geometry(&self, t: f64) -> Geometry {
                    match &self.contact_table {
                        Some(table) => {
                            let mut geo = Geometry { g: [[0.0; DOF]; CONTACTS], gd: [[0.0; DOF]; CONTACTS] };
                            table.interpolate(t, geo.g.as_flattened_mut(), geo.gd.as_flattened_mut());
                            geo
                        }
                        None => self.exact_geometry(t),
                    }
                }
            },
        )
    };
    let table_accessor = if fixed {
        quote!()
    } else {
        quote! {
            fn contact_table(&self) -> Option<&telescopic_runtime::ContactTable> { self.contact_table.as_ref() }
        }
    };
    let geometry_source = if fixed {
        quote!(let geo = &self.fixed_geometry;)
    } else {
        quote!(let geo = &self.geometry(t);)
    };
    let drive_kind_check = if motion {
        quote!(matches!(params.drive, Drive::Motion(_)))
    } else {
        quote!(matches!(params.drive, Drive::Force(_)))
    };
    let clearance_check = if c.clearance {
        quote!(params.contact.clearance > 0.0)
    } else {
        quote!(params.contact.clearance == 0.0)
    };
    let positions_check = if fixed {
        quote!(params.positions.iter().all(|p| p.is_constant()))
    } else {
        quote!(true)
    };
    let flow = match c.force_flow {
        crate::config::ForceFlow::Cable => quote!(ForceFlow::Cable),
        crate::config::ForceFlow::External => quote!(ForceFlow::External),
        crate::config::ForceFlow::None => quote!(ForceFlow::None),
    };
    let modes = &c.modes;
    let contacts = c.contacts;
    let accel = if motion {
        quote! {
            // u'' = s''(t) is given; the other rows carry -M_p0 s'' and drop the reaction
            let s_acc = self.drive_input(t);
            for j in 1..DOF { q[j] -= self.mass_col0[j] * s_acc; }
            let mut acc = [0.0; DOF];
            for i in 1..DOF { let mut s = 0.0; for j in 1..DOF { s += self.minv[i][j] * q[j]; } acc[i] = s; }
            acc[0] = s_acc;
        }
    } else {
        quote! {
            let mut acc = [0.0; DOF];
            for i in 0..DOF { let mut s = 0.0; for j in 0..DOF { s += self.minv[i][j] * q[j]; } acc[i] = s; }
        }
    };
    let minv_build = if motion {
        quote! {
            let rel = mass.view((1, 1), (DOF - 1, DOF - 1)).into_owned();
            let inv = rel.cholesky().ok_or("the mass matrix is not positive definite")?.inverse();
            for i in 1..DOF { for j in 1..DOF { minv[i][j] = inv[(i - 1, j - 1)]; } }
        }
    } else {
        quote! {
            let inv = mass.clone().cholesky().ok_or("the mass matrix is not positive definite")?.inverse();
            for i in 0..DOF { for j in 0..DOF { minv[i][j] = inv[(i, j)]; } }
        }
    };
    let drive_force_out = if motion {
        quote! { out[3 + 2 * CONTACTS] = (0..DOF).map(|j| self.mass_col0[j] * ydot[DOF + j]).sum(); }
    } else {
        quote!()
    };
    let displacement_arms = (1..=n).map(|k| {
        let (shapes, idx) = (
            format_ident!("shapes_{}", k),
            format_ident!("INDICES_{}", k),
        );
        let k0 = k - 1;
        quote! {
            #k => {
                let (v, _) = #shapes(xi);
                for i in 0..v.len() { w += self.length_factors[#k0][i] * v[i] * z[#idx[i]]; }
            }
        }
    });

    let file = quote! {
        use telescopic_runtime::nalgebra::{DMatrix, DVector};
        use telescopic_runtime::{ContactForce, ContactState, Drive, ForceFlow, Layout, Model, ModelParams};

        /// The configuration key this module was generated for.
        pub const KEY: &str = #key;
        /// Number of sections.
        pub const SECTIONS: usize = #n;
        /// Number of generalized coordinates.
        pub const DOF: usize = #dof;
        /// Number of contact points.
        pub const CONTACTS: usize = #nc;
        /// Modes per section.
        pub const MODES: [usize; #n] = [#(#modes),*];

        #(#constants)*

        #mass_fn
        #stiffness_fn
        #(#shape_fns)*

        /// Contact vectors `g_c` (rows) and their time derivatives `gd_c`.
        #[derive(Debug, Clone, Copy)]
        struct Geometry {
            g: [[f64; DOF]; CONTACTS],
            gd: [[f64; DOF]; CONTACTS],
        }

        /// The generated model, prepared for one set of parameters.
        #[derive(Debug, Clone)]
        pub struct GeneratedModel {
            params: ModelParams,
            layout: Layout,
            mass: DMatrix<f64>,
            stiffness: DMatrix<f64>,
            drive: DVector<f64>,
            k: [[f64; DOF]; DOF],
            minv: [[f64; DOF]; DOF],
            mass_col0: [f64; DOF],
            lengths: [f64; SECTIONS],
            length_factors: Vec<Vec<f64>>,
            #geometry_field
            tip: [f64; DOF],
            top1: [f64; DOF],
        }

        impl GeneratedModel {
            /// Prepares the model: matrices from the parameters, `M^-1`, fixed contact vectors.
            ///
            /// # Errors
            /// A message if the parameters do not fit this module's configuration.
            pub fn prepare(params: &ModelParams) -> Result<Self, String> {
                let fits = params.modes() == MODES.to_vec()
                    && (SECTIONS == 1 || params.contact_points == #contacts)
                    && params.force_flow == #flow
                    && #drive_kind_check
                    && #clearance_check
                    && #positions_check;
                if !fits {
                    return Err(format!("the parameters do not fit the generated configuration {}", KEY));
                }
                let p = params;
                let mass = mass_matrix(p);
                let stiffness = stiffness_matrix(p);
                let mut drive = DVector::zeros(DOF);
                drive[0] = 1.0;
                let mut k = [[0.0; DOF]; DOF];
                for i in 0..DOF { for j in 0..DOF { k[i][j] = stiffness[(i, j)]; } }
                let mut minv = [[0.0; DOF]; DOF];
                #minv_build
                let mut mass_col0 = [0.0; DOF];
                for j in 0..DOF { mass_col0[j] = mass[(j, 0)]; }
                let mut lengths = [0.0; SECTIONS];
                for (i, s) in p.sections.iter().enumerate() { lengths[i] = s.length; }
                let p_l = lengths;
                let length_factors: Vec<Vec<f64>> = vec![#(#length_factors),*];
                let mut tip = [0.0; DOF];
                #tip_sets
                let mut top1 = [0.0; DOF];
                #top1_sets
                let model = Self {
                    params: params.clone(),
                    layout: Layout::new(&MODES, params.contact_points),
                    mass,
                    stiffness,
                    drive,
                    k,
                    minv,
                    mass_col0,
                    lengths,
                    length_factors,
                    #geometry_init
                    tip,
                    top1,
                };
                #geometry_finish
                Ok(model)
            }

            /// Contact vectors at time `t` (s), evaluated from the shape functions.
            #[allow(unused_variables, unused_mut)]
            fn exact_geometry(&self, t: f64) -> Geometry {
                #positions_at
                self.geometry_at(&positions)
            }

            /// Contact vectors for positions `a_k` (m) moving at `a_k'` (m/s), as `(a_k, a_k')`
            /// for `k = 2..n`, evaluated from the shape functions.
            #[allow(unused_variables, unused_mut)]
            fn geometry_at(&self, positions: &[(f64, f64); #n_pos]) -> Geometry {
                let mut geo = Geometry { g: [[0.0; DOF]; CONTACTS], gd: [[0.0; DOF]; CONTACTS] };
                #(#geo_stmts)*
                geo
            }

            #geometry_lookup

            fn drive_input(&self, t: f64) -> f64 {
                match &self.params.drive {
                    Drive::Force(f) => f.value(t),
                    Drive::Motion(s) => s.acceleration(t),
                }
            }

            /// Gaps and rates of every contact.
            #[allow(unused_variables)]
            fn gaps(geo: &Geometry, z: &[f64], zd: &[f64]) -> ([f64; CONTACTS], [f64; CONTACTS]) {
                let mut xi = [0.0; CONTACTS];
                let mut xi_dot = [0.0; CONTACTS];
                #(#gaps)*
                (xi, xi_dot)
            }

            /// Contact forces and their partials in the branches chosen.
            fn laws(&self, xi: &[f64; CONTACTS], xi_dot: &[f64; CONTACTS], states: Option<&[ContactState]>) -> [ContactForce; CONTACTS] {
                let mut out = [ContactForce { force: 0.0, d_gap: 0.0, d_rate: 0.0 }; CONTACTS];
                for c in 0..CONTACTS { out[c] = self.contact_force(c, xi[c], xi_dot[c], states); }
                out
            }
        }

        impl Model for GeneratedModel {
            fn layout(&self) -> &Layout { &self.layout }
            fn params(&self) -> &ModelParams { &self.params }
            fn mass_matrix(&self) -> &DMatrix<f64> { &self.mass }
            fn stiffness_matrix(&self) -> &DMatrix<f64> { &self.stiffness }
            fn drive_vector(&self) -> &DVector<f64> { &self.drive }

            #table_accessor

            fn contact_vectors(&self, t: f64, g: &mut DMatrix<f64>, gdot: &mut DMatrix<f64>) {
                #geometry_source
                for c in 0..CONTACTS { for j in 0..DOF { g[(j, c)] = geo.g[c][j]; gdot[(j, c)] = geo.gd[c][j]; } }
            }

            fn contact_vectors_at(&self, positions: &[f64], rates: &[f64], g: &mut DMatrix<f64>, gdot: &mut DMatrix<f64>) {
                let mut at = [(0.0, 0.0); #n_pos];
                for k in 0..#n_pos { at[k] = (positions[k], rates[k]); }
                let geo = self.geometry_at(&at);
                for c in 0..CONTACTS { for j in 0..DOF { g[(j, c)] = geo.g[c][j]; gdot[(j, c)] = geo.gd[c][j]; } }
            }

            fn contact_gaps(&self, t: f64, y: &[f64], xi: &mut [f64], xi_dot: &mut [f64]) {
                #geometry_source
                let (a, b) = Self::gaps(geo, &y[..DOF], &y[DOF..]);
                xi[..CONTACTS].copy_from_slice(&a);
                xi_dot[..CONTACTS].copy_from_slice(&b);
            }

            #[allow(unused_variables)]
            fn rhs(&self, t: f64, y: &[f64], states: Option<&[ContactState]>, ydot: &mut [f64]) {
                #geometry_source
                let (z, zd) = y.split_at(DOF);
                let (xi, xi_dot) = Self::gaps(geo, z, zd);
                let law = self.laws(&xi, &xi_dot, states);
                let mut f = [0.0; CONTACTS];
                for c in 0..CONTACTS { f[c] = law[c].force; }
                let f_drive = self.drive_input(t);
                #(#force_temps)*
                let mut q = [0.0; DOF];
                #(#force_sets)*
                #accel
                ydot[..DOF].copy_from_slice(zd);
                ydot[DOF..2 * DOF].copy_from_slice(&acc);
            }

            #[allow(unused_variables)]
            fn jacobian(&self, t: f64, y: &[f64], states: Option<&[ContactState]>, jac: &mut DMatrix<f64>) {
                #geometry_source
                let (z, zd) = y.split_at(DOF);
                let (xi, xi_dot) = Self::gaps(geo, z, zd);
                let law = self.laws(&xi, &xi_dot, states);
                // dq[i][j]: d q_i / d z_j (j < DOF) and d q_i / d zd_(j - DOF)
                let mut dq = [[0.0; 2 * DOF]; DOF];
                #(#jac_temps)*
                #(#jac_sets)*
                jac.fill(0.0);
                for j in 0..DOF { jac[(j, DOF + j)] = 1.0; }
                for i in 0..DOF {
                    for col in 0..2 * DOF {
                        let mut s = 0.0;
                        for m in 0..DOF { s += self.minv[i][m] * dq[m][col]; }
                        jac[(DOF + i, col)] = s;
                    }
                }
            }

            fn displacement(&self, section: usize, x: f64, z: &[f64]) -> f64 {
                let xi = x / self.lengths[section - 1];
                let mut w = z[0];
                match section {
                    #(#displacement_arms)*
                    _ => {}
                }
                w
            }

            fn outputs(&self, t: f64, y: &[f64], ydot: &[f64], out: &mut [f64]) {
                #geometry_source
                let (z, zd) = y.split_at(DOF);
                let (xi, xi_dot) = Self::gaps(geo, z, zd);
                out[0] = z[0];
                out[1] = (0..DOF).map(|j| self.tip[j] * z[j]).sum();
                out[2] = (0..DOF).map(|j| self.top1[j] * z[j]).sum();
                for c in 0..CONTACTS {
                    out[3 + c] = xi[c];
                    out[3 + CONTACTS + c] = self.contact_force(c, xi[c], xi_dot[c], None).force;
                }
                #drive_force_out
            }
        }
    };
    let text = unsuffixed(file).to_string();
    let parsed = syn::parse_file(&text).map_err(|e| {
        if let Some(dump) = std::env::var_os("TELESCOPIC_CODEGEN_DUMP") {
            let _ = std::fs::write(dump, &text);
        }
        format!("{e} (set TELESCOPIC_CODEGEN_DUMP=path to keep the unparsed tokens)")
    })?;
    let body = prettyplease::unparse(&parsed);
    let mut out = String::new();
    for line in header.lines() {
        out.push_str("// ");
        out.push_str(line);
        out.push('\n');
    }
    out.push('\n');
    for line in body.lines() {
        let indent = &line[..line.len() - line.trim_start().len()];
        match line
            .trim_start()
            .strip_prefix("///")
            .and_then(|rest| rest.strip_prefix(LINE_COMMENT))
        {
            Some(text) => {
                out.push_str(indent);
                out.push_str("//");
                out.push_str(text);
            }
            None => out.push_str(line),
        }
        out.push('\n');
    }
    Ok(out)
}
