//! The emitted items one by one: constants, shape functions, contact geometry, gaps,
//! generalized forces, Jacobian rows, and the code that depends on the configuration's
//! positions (fixed or moving) and drive (force or prescribed motion).

use super::tokens::{call_symbol, float, line_comment, tokens};
use crate::config::{DriveKind, ForceFlow, ModelConfig, Positions};
use crate::derive::{Corrections, Derivation};
use crate::expr::{Expr, eliminate_common};
use proc_macro2::TokenStream;
use quote::{format_ident, quote};

/// `let tN = ...;` for each common subexpression, its symbols read through `map`.
fn temporaries(temps: &[Expr], map: &dyn Fn(&str) -> Option<TokenStream>) -> Vec<TokenStream> {
    temps
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let id = format_ident!("t{}", i);
            let v = tokens(t, map);
            quote!(let #id = #v;)
        })
        .collect()
}

/// The derivation's named constants (`pub const NAME: f64`).
pub(super) fn constants(d: &Derivation) -> Vec<TokenStream> {
    d.constants
        .iter()
        .map(|k| {
            let id = format_ident!("{}", k.name.to_uppercase());
            let v = float(k.value);
            let doc = format!(" {}", k.doc);
            quote!(#[doc = #doc] pub const #id: f64 = #v;)
        })
        .collect()
}

/// Per section: `shapes_k(xi)` (values and slopes) and its index, length-power and top
/// constants; with static correction shapes, their knots and combinations.
pub(super) fn shape_functions(d: &Derivation) -> Vec<TokenStream> {
    let mut items = Vec::new();
    for (k0, basis) in d.bases.iter().enumerate() {
        let k = k0 + 1;
        let fname = format_ident!("shapes_{}", k);
        let modes = basis.len();
        let corrections = d.corrections[k0].as_ref();
        let len = modes + corrections.map_or(0, |c| c.combination.len());
        let exprs: Vec<Expr> = basis
            .iter()
            .flat_map(|b| [b.value.clone(), b.slope.clone()])
            .collect();
        let (temps, exprs) = eliminate_common(&exprs);
        let temp_lets = temporaries(&temps, &|_| None);
        let sets = exprs.chunks(2).enumerate().map(|(i, pair)| {
            let (v, s) = (tokens(&pair[0], &|_| None), tokens(&pair[1], &|_| None));
            let doc = format!(" psi_{k},{} = {}", basis[i].index, basis[i].value.to_text());
            let note = line_comment(&doc);
            quote! { #note { value[#i] = #v; slope[#i] = #s; } }
        });
        let (correction_items, correction_sets) = match corrections {
            Some(c) => correction_code(k, modes, c),
            None => (quote!(), quote!()),
        };
        let doc = format!(
            " Basis functions of section {k} at `xi = x / l_{k}` (cancellation-free forms) and their `d/dxi`, \
             without the factor `l_{k}^p` (see `LENGTH_POWERS_{k}`)."
        );
        items.push(quote! {
            #correction_items

            #[doc = #doc]
            #[inline]
            pub fn #fname(xi: f64) -> ([f64; #len], [f64; #len]) {
                #(#temp_lets)*
                let mut value = [0.0; #len];
                let mut slope = [0.0; #len];
                #(#sets)*
                #correction_sets
                (value, slope)
            }
        });
        let idx_name = format_ident!("INDICES_{}", k);
        let lp_name = format_ident!("LENGTH_POWERS_{}", k);
        let top_name = format_ident!("TOPS_{}", k);
        let mut idx: Vec<usize> = basis.iter().map(|b| b.index).collect();
        let mut lps: Vec<i32> = basis.iter().map(|b| b.length_power).collect();
        let mut top_names: Vec<&str> = basis.iter().map(|b| b.top.as_str()).collect();
        if let Some(c) = corrections {
            idx.extend((0..c.combination.len()).map(|e| c.first_index + e));
            lps.extend(c.combination.iter().map(|_| 0));
            top_names.extend(c.tops.iter().map(String::as_str));
        }
        let tops = top_names
            .iter()
            .map(|t| format_ident!("{}", t.to_uppercase()));
        let doc_i = format!(" Global indices of section {k}'s basis functions.");
        let doc_l = format!(" Powers of `l_{k}` in front of section {k}'s basis functions.");
        let doc_t =
            format!(" Section {k}'s basis functions at its top (`xi = 1`), without `l_{k}^p`.");
        items.push(quote! {
            #[doc = #doc_i] pub const #idx_name: [usize; #len] = [#(#idx),*];
            #[doc = #doc_l] pub const #lp_name: [i32; #len] = [#(#lps),*];
            #[doc = #doc_t] pub const #top_name: [f64; #len] = [#(#tops),*];
        });
    }
    items
}

/// Section `k`'s correction constants (`KNOTS_k`, `CORRECTIONS_k`), and the statements of
/// `shapes_k` that set the corrections after its `modes` mode values.
fn correction_code(k: usize, modes: usize, c: &Corrections) -> (TokenStream, TokenStream) {
    let (knots_name, combination_name) = (
        format_ident!("KNOTS_{}", k),
        format_ident!("CORRECTIONS_{}", k),
    );
    let (m, shapes) = (c.knots.len(), c.combination.len());
    let width = modes + shapes;
    let knots = c.knots.iter().map(|&x| float(x));
    let rows = c.combination.iter().map(|row| {
        let entries = row.iter().map(|&x| float(x));
        quote!([#(#entries),*])
    });
    let doc_k = format!(
        " Interior knots of section {k}'s cubic B-splines (fractions of `l_{k}`): the clamped \
         B-splines on `0, 0, 0, 0, knots, 1, 1, 1, 1` without the first two."
    );
    let doc_c = format!(
        " Section {k}'s static correction shapes: row `e` combines its {modes} mode functions \
         (as `shapes_{k}` gives them) and then its {shapes} B-splines; orthogonal to the modes \
         and orthonormal in `int_0^1 psi psi dxi`, derived exactly (512 bits)."
    );
    let items = quote! {
        #[doc = #doc_k]
        pub const #knots_name: [f64; #m] = [#(#knots),*];
        #[doc = #doc_c]
        pub const #combination_name: [[f64; #width]; #shapes] = [#(#rows),*];
    };
    let sets = quote! {
        // the static correction shapes: combinations of the modes above and the B-splines
        let mut spline = [0.0; #shapes];
        let mut spline_slope = [0.0; #shapes];
        telescopic_runtime::shape::spline::correction_values(&#knots_name, xi, &mut spline, &mut spline_slope);
        for (e, row) in #combination_name.iter().enumerate() {
            let (mut v, mut s) = (0.0, 0.0);
            for j in 0..#modes {
                v += row[j] * value[j];
                s += row[j] * slope[j];
            }
            for j in 0..#shapes {
                v += row[#modes + j] * spline[j];
                s += row[#modes + j] * spline_slope[j];
            }
            value[#modes + e] = v;
            slope[#modes + e] = s;
        }
    };
    (items, sets)
}

/// `factor * x`, folded when the factor is 0 (`None`: the term vanishes), 1 or -1.
fn scaled(factor: f64, x: TokenStream) -> Option<TokenStream> {
    if factor == 0.0 {
        None
    } else if factor == 1.0 {
        Some(x)
    } else if factor == -1.0 {
        Some(quote!(-#x))
    } else {
        let f = float(factor);
        Some(quote!(#f * #x))
    }
}

/// `numerator / denominator`, or `0.0` for a vanished numerator.
fn ratio(numerator: Option<TokenStream>, denominator: TokenStream) -> TokenStream {
    match numerator {
        Some(n) => quote!(#n / #denominator),
        None => quote!(0.0),
    }
}

/// The contact geometry: for each overlap and contact point, the shapes of both sections at
/// the moving contact point `x_in = s (l_out - a)`, `x_out = a + s (l_out - a)`, with the
/// trivial factors of the first (`s = 0`) and last (`s = 1`) points folded.
pub(super) fn geometry_statements(c: &ModelConfig) -> Vec<TokenStream> {
    let mut statements = Vec::new();
    let mut cidx = 0usize;
    for k in 2..=c.sections() {
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
            let xi_in = ratio(scaled(s, quote!((l_out - a))), quote!(l_in));
            let xi_out = match scaled(s, quote!((l_out - a))) {
                Some(reach) => quote!((a + #reach) / l_out),
                None => quote!(a / l_out),
            };
            let rate_in = ratio(scaled(-s, quote!(a_dot)), quote!(l_in));
            let rate_out = ratio(scaled(1.0 - s, quote!(a_dot)), quote!(l_out));
            statements.push(quote! {
                {
                    let l_out = self.lengths[#ko];
                    let l_in = self.lengths[#ki];
                    let (a, a_dot) = (positions[#ko].0, positions[#ko].1);
                    // x_in = s (l_out - a) on section k, x_out = a + s (l_out - a) on section k - 1
                    let xi_in = #xi_in;
                    let xi_out = #xi_out;
                    let rate_in = #rate_in;
                    let rate_out = #rate_out;
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
    statements
}

/// The generalized forces `q[i]`: temporaries, then one commented assignment per row.
pub(super) fn force_rows(d: &Derivation) -> (Vec<TokenStream>, Vec<TokenStream>) {
    let (temps, forces) = eliminate_common(&d.forces);
    let sets = forces
        .iter()
        .enumerate()
        .map(|(i, e)| {
            let v = tokens(e, &call_symbol);
            let doc = format!(" q[{i}] = {}", d.forces[i].to_text());
            let note = line_comment(&doc);
            quote!(#note { q[#i] = #v; })
        })
        .collect();
    (temporaries(&temps, &call_symbol), sets)
}

/// The Jacobian rows of the forces, `dq[i][j]` by `z_j` (then by `zd_j` from column DOF).
pub(super) fn jacobian_rows(d: &Derivation) -> (Vec<TokenStream>, Vec<TokenStream>) {
    let all: Vec<Expr> = d
        .jacobian_z
        .iter()
        .chain(&d.jacobian_zd)
        .map(|(_, e)| e.clone())
        .collect();
    let (temps, all) = eliminate_common(&all);
    let (nz, dof) = (d.jacobian_z.len(), d.config.dof());
    let sets = d
        .jacobian_z
        .iter()
        .chain(&d.jacobian_zd)
        .zip(&all)
        .enumerate()
        .map(|(m, (((i, j), _), e))| {
            let col = if m < nz { *j } else { dof + *j };
            let v = tokens(e, &call_symbol);
            quote!(dq[#i][#col] = #v;)
        })
        .collect();
    (temporaries(&temps, &call_symbol), sets)
}

/// Gap and gap rate of each contact over the coordinates its vector touches.
pub(super) fn gap_statements(d: &Derivation) -> Vec<TokenStream> {
    (0..d.config.contact_count())
        .map(|ci| {
            let pat = &d.contact_pattern[ci];
            let xi_terms = pat.iter().map(|&j| quote!(geo.g[#ci][#j] * z[#j]));
            let xid_terms = pat
                .iter()
                .map(|&j| quote!(geo.g[#ci][#j] * zd[#j] + geo.gd[#ci][#j] * z[#j]));
            quote! {
                xi[#ci] = #(#xi_terms)+*;
                xi_dot[#ci] = #(#xid_terms)+*;
            }
        })
        .collect()
}

/// Code that differs between fixed and moving telescopic positions.
pub(super) struct PositionsCode {
    /// The struct field holding the contact vectors (fixed) or their table (moving).
    pub field: TokenStream,
    /// Its initial value in `prepare`.
    pub init: TokenStream,
    /// What `prepare` does after building the struct (fill the vectors or the table).
    pub finish: TokenStream,
    /// The `geometry(t)` lookup (moving positions only).
    pub lookup: TokenStream,
    /// `Model::contact_table` (moving positions only).
    pub table_accessor: TokenStream,
    /// How a per-call method gets `geo`.
    pub source: TokenStream,
    /// How the right-hand side gets `geo`, given `open` (every contact inside its band).
    pub rhs_source: TokenStream,
    /// `positions` at `t` for `exact_geometry`.
    pub at_time: TokenStream,
    /// How `prepare` checks the parameters' positions fit.
    pub check: TokenStream,
}

/// Fixed positions: contact vectors once per scene (constant profiles, so any time will
/// do); moving positions: a table in time, built once per scene (runtime::ContactTable).
pub(super) fn positions_code(c: &ModelConfig) -> PositionsCode {
    let n_pos = c.sections() - 1;
    let at_time = if n_pos > 0 {
        quote! {
            let mut positions = [(0.0, 0.0); #n_pos];
            for (k, p) in self.params.positions.iter().enumerate() {
                positions[k] = (p.value(t), p.rate(t));
            }
        }
    } else {
        quote!(let positions: [(f64, f64); 0] = [];)
    };
    if c.positions == Positions::Fixed {
        return PositionsCode {
            field: quote!(fixed_geometry: Geometry,),
            init: quote!(fixed_geometry: Geometry { g: [[0.0; DOF]; CONTACTS], gd: [[0.0; DOF]; CONTACTS] },),
            finish: quote!(let mut model = model; model.fixed_geometry = model.exact_geometry(0.0);),
            lookup: quote!(),
            table_accessor: quote!(),
            source: quote!(let geo = &self.fixed_geometry;),
            rhs_source: quote!(let geo = &self.fixed_geometry;),
            at_time,
            check: quote!(params.positions.iter().all(|p| p.is_constant())),
        };
    }
    PositionsCode {
        field: quote!(contact_table: Option<telescopic_runtime::ContactTable>,),
        init: quote!(contact_table: None,),
        finish: quote! {
            let mut model = model;
            let tolerances = model.params.basis.table_tolerances();
            model.contact_table = telescopic_runtime::ContactTable::build_to(&model.params.positions, CONTACTS * DOF, tolerances, |t, g, gd| {
                let geo = model.exact_geometry(t);
                g.copy_from_slice(geo.g.as_flattened());
                gd.copy_from_slice(geo.gd.as_flattened());
            });
        },
        lookup: quote! {
            /// Contact vectors of no contact, for a right-hand side with every contact open.
            const NO_CONTACT: Geometry = Geometry { g: [[0.0; DOF]; CONTACTS], gd: [[0.0; DOF]; CONTACTS] };

            /// The contact vectors at time `t` (s) of the contacts not held open in `states`
            /// (every contact's with `None`) into `geo`, whose other rows are left as they are.
            #[inline]
            fn closed_geometry(&self, t: f64, states: Option<&[ContactState]>, geo: &mut Geometry) {
                match &self.contact_table {
                    Some(table) => {
                        let closed = |c: usize| states.is_none_or(|s| s[c] != ContactState::Free);
                        table.interpolate_rows(t, DOF, closed, geo.g.as_flattened_mut(), geo.gd.as_flattened_mut());
                    }
                    None => *geo = self.exact_geometry(t),
                }
            }

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
        table_accessor: quote! {
            fn contact_table(&self) -> Option<&telescopic_runtime::ContactTable> { self.contact_table.as_ref() }
        },
        source: quote!(let geo = &self.geometry(t);),
        rhs_source: quote! {
            // only a closed contact's vector carries force: the open ones' rows stay zero
            let mut looked_up = Self::NO_CONTACT;
            if !open { self.closed_geometry(t, states, &mut looked_up); }
            let geo = &looked_up;
        },
        at_time,
        check: quote!(true),
    }
}

/// Code that differs between a force drive and a prescribed vehicle motion.
pub(super) struct DriveCode {
    /// How `prepare` checks the parameters' drive fits.
    pub check: TokenStream,
    /// Accelerations from the forces `q`.
    pub accel: TokenStream,
    /// `M^-1` (of the relative coordinates for a prescribed motion).
    pub minv_build: TokenStream,
    /// The `drive_force` output (prescribed motion only: the force the motion takes).
    pub drive_force_out: TokenStream,
}

/// A force drive solves `M acc = q`; a prescribed motion gives `u'' = s''(t)`, and the
/// other rows carry `-M_p0 s''` and drop the reaction.
pub(super) fn drive_code(c: &ModelConfig) -> DriveCode {
    if c.drive == DriveKind::Force {
        return DriveCode {
            check: quote!(matches!(params.drive, Drive::Force(_))),
            accel: quote! {
                let mut acc = [0.0; DOF];
                for i in 0..DOF { let mut s = 0.0; for j in 0..DOF { s += self.minv[i][j] * q[j]; } acc[i] = s; }
            },
            minv_build: quote! {
                let inv = mass.clone().cholesky().ok_or("the mass matrix is not positive definite")?.inverse();
                for i in 0..DOF { for j in 0..DOF { minv[i][j] = inv[(i, j)]; } }
            },
            drive_force_out: quote!(),
        };
    }
    DriveCode {
        check: quote!(matches!(params.drive, Drive::Motion(_))),
        accel: quote! {
            // u'' = s''(t) is given; the other rows carry -M_p0 s'' and drop the reaction
            let s_acc = self.drive_input(t);
            for j in 1..DOF { q[j] -= self.mass_col0[j] * s_acc; }
            let mut acc = [0.0; DOF];
            for i in 1..DOF { let mut s = 0.0; for j in 1..DOF { s += self.minv[i][j] * q[j]; } acc[i] = s; }
            acc[0] = s_acc;
        },
        minv_build: quote! {
            let rel = mass.view((1, 1), (DOF - 1, DOF - 1)).into_owned();
            let inv = rel.cholesky().ok_or("the mass matrix is not positive definite")?.inverse();
            for i in 1..DOF { for j in 1..DOF { minv[i][j] = inv[(i - 1, j - 1)]; } }
        },
        drive_force_out: quote! {
            // reaction: row 0 of M zdd + D_s zd (K's row 0 and every g_c[0] vanish)
            out[3 + 2 * CONTACTS] = (0..DOF).map(|j| self.mass_col0[j] * ydot[DOF + j] + self.d[0][j] * zd[j]).sum();
        },
    }
}

/// The runtime's name of the configuration's force flow.
pub(super) fn force_flow(c: &ModelConfig) -> TokenStream {
    match c.force_flow {
        ForceFlow::Cable => quote!(ForceFlow::Cable),
        ForceFlow::External => quote!(ForceFlow::External),
        ForceFlow::None => quote!(ForceFlow::None),
    }
}

/// `prepare`'s check of the parameters against the configuration.
pub(super) fn clearance_check(c: &ModelConfig) -> TokenStream {
    if c.clearance {
        quote!(params.contact.clearance > 0.0)
    } else {
        quote!(params.contact.clearance == 0.0)
    }
}
