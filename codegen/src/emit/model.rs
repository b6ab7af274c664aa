//! The emitted module as a whole: its constants and free functions, the `GeneratedModel`
//! struct with `prepare` and its helpers, and the `Model` impl.

use super::matrix_fn;
use super::parts::{
    DriveCode, PositionsCode, clearance_check, constants, drive_code, force_flow, force_rows,
    gap_statements, geometry_statements, jacobian_rows, positions_code, shape_functions,
};
use crate::derive::Derivation;
use proc_macro2::TokenStream;
use quote::{format_ident, quote};

/// The whole module's tokens.
pub(super) fn module(d: &Derivation) -> TokenStream {
    let positions = positions_code(&d.config);
    let drive = drive_code(&d.config);
    let items = free_items(d);
    let prepare = prepare_fn(d, &positions, &drive);
    let helpers = inherent_helpers(d, &positions);
    let model_impl = model_impl(d, &positions, &drive);
    quote! {
        #items

        impl GeneratedModel {
            #prepare
            #helpers
        }

        #model_impl
    }
}

/// Imports, configuration constants, derived constants, `M`, `K`, shape functions, and
/// the `Geometry` and `GeneratedModel` structs.
fn free_items(d: &Derivation) -> TokenStream {
    let c = &d.config;
    let (key, n, dof, nc) = (c.key(), c.sections(), c.dof(), c.contact_count());
    let modes = &c.modes;
    let coordinates: Vec<usize> = (1..=n).map(|k| c.coordinates(k)).collect();
    let constants = constants(d);
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
    let shape_fns = shape_functions(d);
    let geometry_field = positions_code(c).field;
    quote! {
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
        /// Coordinates per section: its modes and its static correction shapes.
        pub const COORDINATES: [usize; #n] = [#(#coordinates),*];

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
            damping: Option<DMatrix<f64>>,
            drive: DVector<f64>,
            k: [[f64; DOF]; DOF],
            /// Structural damping `D_s`, used when `damped`.
            d: [[f64; DOF]; DOF],
            damped: bool,
            minv: [[f64; DOF]; DOF],
            mass_col0: [f64; DOF],
            lengths: [f64; SECTIONS],
            length_factors: Vec<Vec<f64>>,
            #geometry_field
            tip: [f64; DOF],
            top1: [f64; DOF],
        }
    }
}

/// `GeneratedModel::prepare`: the configuration check, then the per-scene work.
fn prepare_fn(d: &Derivation, positions: &PositionsCode, drive: &DriveCode) -> TokenStream {
    let c = &d.config;
    let n = c.sections();
    let contacts = c.contacts;
    let flow = force_flow(c);
    let clearance_check = clearance_check(c);
    let (drive_kind_check, positions_check) = (&drive.check, &positions.check);
    let basis_check = match &c.static_knots {
        None => quote!(params.basis == telescopic_runtime::Basis::Modes),
        Some(_) => {
            let lists = (1..=n).map(|k| {
                let name = format_ident!("KNOTS_{}", k);
                quote!(#name.to_vec())
            });
            quote! {
                telescopic_runtime::config_of(params).static_knots
                    == Some(telescopic_runtime::StaticKnots(vec![#(#lists),*]))
            }
        }
    };
    let (minv_build, geometry_init, geometry_finish) =
        (&drive.minv_build, &positions.init, &positions.finish);
    let length_factors = (0..n).map(|k| {
        let lp = format_ident!("LENGTH_POWERS_{}", k + 1);
        quote!(#lp.map(|p| p_l[#k].powi(p)).to_vec())
    });
    let tip_sets = {
        let (idx, tops) = (format_ident!("INDICES_{}", n), format_ident!("TOPS_{}", n));
        quote! { for i in 0..#idx.len() { tip[#idx[i]] = length_factors[#n - 1][i] * #tops[i]; } }
    };
    let top1_sets = quote! { for i in 0..INDICES_1.len() { top1[INDICES_1[i]] = length_factors[0][i] * TOPS_1[i]; } };
    quote! {
        /// Prepares the model: matrices from the parameters, `M^-1`, fixed contact vectors.
        ///
        /// # Errors
        /// A message if the parameters do not fit this module's configuration.
        pub fn prepare(params: &ModelParams) -> Result<Self, String> {
            let fits = params.modes() == MODES.to_vec()
                && (SECTIONS == 1 || params.contact_points == #contacts)
                && params.force_flow == #flow
                && #basis_check
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
                layout: Layout::new(&COORDINATES, params.contact_points),
                mass,
                stiffness,
                damping: None,
                drive,
                k,
                d: [[0.0; DOF]; DOF],
                damped: false,
                minv,
                mass_col0,
                lengths,
                length_factors,
                #geometry_init
                tip,
                top1,
            };
            #geometry_finish
            // structural damping is a numeric matrix (modal damping needs the modes)
            let mut model = model;
            let damping = telescopic_runtime::structural_damping(&model)
                .map_err(|e| format!("structural damping: {e}"))?;
            if let Some(ds) = &damping {
                for i in 0..DOF { for j in 0..DOF { model.d[i][j] = ds[(i, j)]; } }
            }
            model.damped = damping.is_some();
            model.damping = damping;
            Ok(model)
        }
    }
}

/// The private helpers of `GeneratedModel`: contact vectors, the drive input, gaps and
/// contact laws.
fn inherent_helpers(d: &Derivation, positions: &PositionsCode) -> TokenStream {
    let n_pos = d.config.sections() - 1;
    let geo_stmts = geometry_statements(&d.config);
    let gaps = gap_statements(d);
    let (positions_at, geometry_lookup) = (&positions.at_time, &positions.lookup);
    quote! {
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
}

/// `impl Model for GeneratedModel`: the per-call path.
fn model_impl(d: &Derivation, positions: &PositionsCode, drive: &DriveCode) -> TokenStream {
    let geometry = geometry_methods(d, positions);
    let rhs = rhs_method(d, positions, drive);
    let jacobian = jacobian_method(d, positions);
    let outputs = output_methods(d, positions, drive);
    quote! {
        impl Model for GeneratedModel {
            fn layout(&self) -> &Layout { &self.layout }
            fn params(&self) -> &ModelParams { &self.params }
            fn mass_matrix(&self) -> &DMatrix<f64> { &self.mass }
            fn stiffness_matrix(&self) -> &DMatrix<f64> { &self.stiffness }
            fn damping_matrix(&self) -> Option<&DMatrix<f64>> { self.damping.as_ref() }
            fn drive_vector(&self) -> &DVector<f64> { &self.drive }
            #geometry
            #rhs
            #jacobian
            #outputs
        }
    }
}

/// The contact geometry's methods: the table accessor, contact vectors and gaps.
fn geometry_methods(d: &Derivation, positions: &PositionsCode) -> TokenStream {
    let n_pos = d.config.sections() - 1;
    let (table_accessor, geometry_source) = (&positions.table_accessor, &positions.source);
    quote! {
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
    }
}

/// `rhs`: the contact forces of the closed contacts, the generalized forces, `M^-1`.
fn rhs_method(d: &Derivation, positions: &PositionsCode, drive: &DriveCode) -> TokenStream {
    let (force_temps, force_sets) = force_rows(d);
    let rhs_geometry_source = &positions.rhs_source;
    let accel = &drive.accel;
    quote! {
    #[allow(unused_variables)]
    fn rhs(&self, t: f64, y: &[f64], states: Option<&[ContactState]>, ydot: &mut [f64]) {
        let (z, zd) = y.split_at(DOF);
        // every contact held inside its band: no contact force, no gaps to compute
        let open = states.is_some_and(|s| s.iter().all(|&s| s == ContactState::Free));
        #rhs_geometry_source
        let mut f = [0.0; CONTACTS];
        if !open {
            let (xi, xi_dot) = Self::gaps(geo, z, zd);
            let law = self.laws(&xi, &xi_dot, states);
            for c in 0..CONTACTS { f[c] = law[c].force; }
        }
        let f_drive = self.drive_input(t);
        #(#force_temps)*
        let mut q = [0.0; DOF];
        #(#force_sets)*
        if self.damped {
            for i in 0..DOF { let mut s = 0.0; for j in 0..DOF { s += self.d[i][j] * zd[j]; } q[i] -= s; }
        }
        #accel
        ydot[..DOF].copy_from_slice(zd);
        ydot[DOF..2 * DOF].copy_from_slice(&acc);
    }
    }
}

/// `jacobian`: the generalized forces' derivatives through `M^-1`.
fn jacobian_method(d: &Derivation, positions: &PositionsCode) -> TokenStream {
    let (jac_temps, jac_sets) = jacobian_rows(d);
    let geometry_source = &positions.source;
    quote! {
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
        if self.damped {
            for i in 0..DOF { for j in 0..DOF { dq[i][DOF + j] -= self.d[i][j]; } }
        }
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
    }
}

/// `displacement` and `outputs`.
fn output_methods(d: &Derivation, positions: &PositionsCode, drive: &DriveCode) -> TokenStream {
    let geometry_source = &positions.source;
    let drive_force_out = &drive.drive_force_out;
    let displacement_arms = displacement_arms(d);
    quote! {
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
}

/// The arms of `displacement`'s match: one per section, its shapes at `xi`.
fn displacement_arms(d: &Derivation) -> Vec<TokenStream> {
    (1..=d.config.sections())
        .map(|k| {
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
        })
        .collect()
}
