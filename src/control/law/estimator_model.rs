//! The extended filter's own copy of the nonlinear model, recorded in the controller file:
//! `M^-1`, `K`, `D_s`, the drive's response, the contact law and the contact vectors over the
//! design scene's time (tabulated as the model tabulates them). The filter predicts with it
//! rather than with the plant it runs against, so a run on a changed plant (`simulate --set`)
//! tests a controller that does not know the change, and the emitted C carries the same
//! numbers.
//!
//! The right-hand side and the Jacobian are written as plain loops in one fixed order: the
//! emitted C ([`crate::control::emit::emit_c`]) repeats them operation for operation, so the two agree to
//! the last bit. They equal the generated model's (derived by Symbolica) to rounding: a test
//! compares the two.

use crate::OptionName;
use crate::{Error, Result};
use serde::{Deserialize, Serialize};
use telescopic_runtime::nalgebra::DMatrix;
use telescopic_runtime::{ContactLaw, ContactTable, ContactTableParts, Model};

/// The estimator's model: `M z'' = b u - K z - D_s z' - sum_c f_c(xi_c, xi_dot_c) g_c(t)`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EstimatorModel {
    /// `M^-1`, rows (1/kg in the vehicle's coordinate; units of the coordinates).
    pub mass_inverse: Vec<Vec<f64>>,
    /// `K` (elastic minus prestress), rows.
    pub stiffness: Vec<Vec<f64>>,
    /// `D_s`, rows, if the model has structural damping.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<Vec<Vec<f64>>>,
    /// `M^-1 b`: the accelerations per newton of drive force.
    pub drive_response: Vec<f64>,
    /// Contact stiffness `c` (N/m).
    pub contact_stiffness: f64,
    /// Contact damping `d` (N s/m).
    pub contact_damping: f64,
    /// Total clearance `l_S` (m).
    pub clearance: f64,
    /// Number of contacts.
    pub contacts: usize,
    /// Contact vectors `g_c` (contact after contact, `dof` entries each) when the positions do
    /// not move.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fixed_geometry: Option<Vec<f64>>,
    /// The contact vectors' table over time when the positions move.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub geometry_table: Option<ContactTableParts>,
}

impl EstimatorModel {
    /// The record of `model` (the design scene's).
    ///
    /// # Errors
    /// [`Error::Model`] when the mass matrix cannot be inverted; [`Error::Option`] when the
    /// positions move but the model has no contact table (a rate with kinks).
    pub fn of(model: &dyn Model) -> Result<Self> {
        let n = model.dof();
        let nc = model.layout().contact_count();
        let minv = model
            .mass_matrix()
            .clone()
            .cholesky()
            .ok_or_else(|| Error::Model("the mass matrix is not positive definite".into()))?
            .inverse();
        let response = &minv * model.drive_vector();
        let rows = |m: &DMatrix<f64>| -> Vec<Vec<f64>> {
            (0..m.nrows())
                .map(|i| m.row(i).iter().copied().collect())
                .collect()
        };
        let moving = model.params().positions.iter().any(|p| !p.is_constant());
        let (fixed_geometry, geometry_table) = match (moving, model.contact_table()) {
            // a table whose every column is constant is the fixed geometry of those values
            (_, Some(table)) if table.varying_columns() == 0 => {
                (Some(table.parts().constant_g), None)
            }
            (_, Some(table)) => (None, Some(table.parts())),
            (false, None) => {
                let (mut g, mut gd) = (DMatrix::zeros(n, nc), DMatrix::zeros(n, nc));
                model.contact_vectors(0.0, &mut g, &mut gd);
                (Some(g.as_slice().to_vec()), None)
            }
            (true, None) => {
                return Err(Error::option(
                    OptionName::Estimator,
                    "the extended filter needs the contact vectors tabulated in time, and this \
                     scene's positions move with a rate that jumps (a piecewise-linear profile); \
                     use a smooth profile or the linear estimator",
                ));
            }
        };
        let law = model.params().contact;
        Ok(EstimatorModel {
            mass_inverse: rows(&minv),
            stiffness: rows(model.stiffness_matrix()),
            damping: model.damping_matrix().map(rows),
            drive_response: response.iter().copied().collect(),
            contact_stiffness: law.stiffness,
            contact_damping: law.damping,
            clearance: law.clearance,
            contacts: nc,
            fixed_geometry,
            geometry_table,
        })
    }

    /// Number of generalized coordinates.
    pub fn dof(&self) -> usize {
        self.drive_response.len()
    }

    /// Checks the sizes and values against `dof` coordinates and `contacts` contacts, naming
    /// the field (under `sampled.model`) that does not fit.
    ///
    /// # Errors
    /// [`Error::Option`] naming the field and the rule.
    pub fn check(&self, dof: usize, contacts: usize) -> Result<()> {
        let field = |name: &str, rule: String| {
            Error::input(format!("controller `sampled.model.{name}`"), rule)
        };
        for (name, rows) in [
            ("mass_inverse", Some(&self.mass_inverse)),
            ("stiffness", Some(&self.stiffness)),
            ("damping", self.damping.as_ref()),
        ] {
            let Some(rows) = rows else { continue };
            if rows.len() != dof || rows.iter().any(|r| r.len() != dof) {
                return Err(field(name, format!("must be {dof} x {dof}")));
            }
            if rows.iter().flatten().any(|v| !v.is_finite()) {
                return Err(field(name, "must be finite".into()));
            }
        }
        if self.drive_response.len() != dof || self.drive_response.iter().any(|v| !v.is_finite()) {
            return Err(field(
                "drive_response",
                format!("must be {dof} finite numbers"),
            ));
        }
        if self.contacts != contacts {
            return Err(field("contacts", format!("must be the scene's {contacts}")));
        }
        for (name, v) in [
            ("contact_stiffness", self.contact_stiffness),
            ("contact_damping", self.contact_damping),
            ("clearance", self.clearance),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(field(name, format!("must be finite and >= 0 (got {v})")));
            }
        }
        match (&self.fixed_geometry, &self.geometry_table) {
            (Some(g), None) => {
                if g.len() != contacts * dof || g.iter().any(|v| !v.is_finite()) {
                    return Err(field(
                        "fixed_geometry",
                        format!("must be {} finite numbers", contacts * dof),
                    ));
                }
            }
            (None, Some(parts)) => {
                if parts.constant_g.len() != contacts * dof {
                    return Err(field(
                        "geometry_table.constant_g",
                        format!("must have {} entries", contacts * dof),
                    ));
                }
                if parts.varying.is_empty() {
                    return Err(field(
                        "geometry_table.varying",
                        "must name a column that changes (else give `fixed_geometry`)".into(),
                    ));
                }
                ContactTable::from_parts(parts.clone()).map_err(|e| field("geometry_table", e))?;
            }
            _ => {
                return Err(field(
                    "fixed_geometry",
                    "exactly one of `fixed_geometry` and `geometry_table` must be given".into(),
                ));
            }
        }
        Ok(())
    }
}

/// The estimator model ready to evaluate: flat row-major matrices and the geometry's
/// interpolant. Every method is allocation-free.
pub struct PreparedEstimatorModel {
    n: usize,
    nc: usize,
    minv: Vec<f64>,
    k: Vec<f64>,
    d: Option<Vec<f64>>,
    response: Vec<f64>,
    law: ContactLaw,
    table: Option<ContactTable>,
    fixed: Vec<f64>,
    /// `g` and `gd` of the last evaluation (contact-major).
    g: Vec<f64>,
    gd: Vec<f64>,
    q: Vec<f64>,
    /// `df_c/dxi_c`, `df_c/dxi_dot_c` of the last Jacobian.
    partials: Vec<(f64, f64)>,
}

impl PreparedEstimatorModel {
    /// Prepares `record` (checked with [`EstimatorModel::check`] first).
    ///
    /// # Errors
    /// As [`EstimatorModel::check`].
    pub fn new(record: &EstimatorModel) -> Result<Self> {
        let n = record.dof();
        let nc = record.contacts;
        record.check(n, nc)?;
        let flat = |rows: &Vec<Vec<f64>>| rows.iter().flatten().copied().collect::<Vec<f64>>();
        let table = match &record.geometry_table {
            Some(parts) => Some(
                ContactTable::from_parts(parts.clone())
                    .map_err(|e| Error::input("controller `sampled.model.geometry_table`", e))?,
            ),
            None => None,
        };
        Ok(PreparedEstimatorModel {
            n,
            nc,
            minv: flat(&record.mass_inverse),
            k: flat(&record.stiffness),
            d: record.damping.as_ref().map(flat),
            response: record.drive_response.clone(),
            law: ContactLaw {
                stiffness: record.contact_stiffness,
                damping: record.contact_damping,
                clearance: record.clearance,
            },
            table,
            fixed: record.fixed_geometry.clone().unwrap_or_default(),
            g: vec![0.0; nc * n],
            gd: vec![0.0; nc * n],
            q: vec![0.0; n],
            partials: vec![(0.0, 0.0); nc],
        })
    }

    /// Number of generalized coordinates.
    pub fn dof(&self) -> usize {
        self.n
    }

    /// The drive's response `M^-1 b`.
    pub fn drive_response(&self) -> &[f64] {
        &self.response
    }

    /// Loads the contact vectors at `t` (s) into `self.g`, `self.gd`.
    fn geometry(&mut self, t: f64) {
        match &self.table {
            Some(table) => table.interpolate(t, &mut self.g, &mut self.gd),
            None => {
                self.g.copy_from_slice(&self.fixed);
                self.gd.fill(0.0);
            }
        }
    }

    /// Gap and gap rate of contact `c` at state `y` (geometry loaded).
    fn gap(&self, c: usize, y: &[f64]) -> (f64, f64) {
        let n = self.n;
        let (g, gd) = (&self.g[c * n..(c + 1) * n], &self.gd[c * n..(c + 1) * n]);
        let (mut xi, mut xi_dot) = (0.0, 0.0);
        for j in 0..n {
            xi += g[j] * y[j];
            xi_dot += g[j] * y[n + j] + gd[j] * y[j];
        }
        (xi, xi_dot)
    }

    /// `ydot` at `t` (s), state `y = [z, z']`, with the drive force `u` (N).
    // indexed loops, as in the emitted C this code is mirrored in
    #[allow(clippy::needless_range_loop)]
    pub fn rhs(&mut self, t: f64, y: &[f64], u: f64, ydot: &mut [f64]) {
        let n = self.n;
        self.geometry(t);
        // q = -K z - D_s z' - sum_c f_c g_c
        for i in 0..n {
            let mut s = 0.0;
            for j in 0..n {
                s -= self.k[i * n + j] * y[j];
            }
            if let Some(d) = &self.d {
                for j in 0..n {
                    s -= d[i * n + j] * y[n + j];
                }
            }
            self.q[i] = s;
        }
        for c in 0..self.nc {
            let (xi, xi_dot) = self.gap(c, y);
            let f = self.law.force(xi, xi_dot).force;
            for i in 0..n {
                self.q[i] -= f * self.g[c * n + i];
            }
        }
        // z'' = M^-1 q + M^-1 b u
        for i in 0..n {
            let mut s = 0.0;
            for j in 0..n {
                s += self.minv[i * n + j] * self.q[j];
            }
            ydot[i] = y[n + i];
            ydot[n + i] = s + self.response[i] * u;
        }
    }

    /// The Jacobian `d ydot / d y` (row-major, `2 dof x 2 dof`) at `t`, `y`, exact within the
    /// contact branches the gaps are in.
    pub fn jacobian(&mut self, t: f64, y: &[f64], jac: &mut [f64]) {
        let n = self.n;
        let w = 2 * n;
        self.geometry(t);
        jac.fill(0.0);
        for i in 0..n {
            jac[i * w + n + i] = 1.0;
        }
        // dq/dz = -K - sum_c g_c (kc g_c + dc gd_c)^T, dq/dz' = -D_s - sum_c dc g_c g_c^T,
        // kept in the lower rows, then multiplied by M^-1
        for c in 0..self.nc {
            let (xi, xi_dot) = self.gap(c, y);
            let law = self.law.force(xi, xi_dot);
            self.partials[c] = (law.d_gap, law.d_rate);
        }
        for r in 0..n {
            for col in 0..n {
                let mut dz = -self.k[r * n + col];
                let mut dzd = match &self.d {
                    Some(d) => -d[r * n + col],
                    None => 0.0,
                };
                for c in 0..self.nc {
                    let (kc, dc) = self.partials[c];
                    let gr = self.g[c * n + r];
                    dz -= gr * (kc * self.g[c * n + col] + dc * self.gd[c * n + col]);
                    dzd -= gr * dc * self.g[c * n + col];
                }
                // the lower-left and lower-right blocks hold dq until M^-1 is applied
                jac[(n + r) * w + col] = dz;
                jac[(n + r) * w + n + col] = dzd;
            }
        }
        for col in 0..w {
            for r in 0..n {
                self.q[r] = jac[(n + r) * w + col];
            }
            for i in 0..n {
                let mut s = 0.0;
                for j in 0..n {
                    s += self.minv[i * n + j] * self.q[j];
                }
                jac[(n + i) * w + col] = s;
            }
        }
    }
}
