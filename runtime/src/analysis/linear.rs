//! Linear models about the straight configuration, with stable names:
//! `x' = A x + B u`, `y = C x + D u` at given telescopic positions `a_k` and speeds `a_k'`
//! (a linear parameter-varying model: [`Lpv::at`] evaluates it anywhere from the model's own
//! `M`, `K` and contact vectors, the generated model's from the same symbolic expressions as
//! its right-hand side, and assembles nothing).
//!
//! **States**, in this order (part of the format): the coordinates `z` of docs/model.md
//! section 5, then their rates:
//!
//! | name | unit | what |
//! |---|---|---|
//! | `u` | m | vehicle position `w_1(0, t)` (rigid translation of the whole telescope) |
//! | `q_1_i` (`i >= 2`) | m | section 1's shape coordinate `i`, basis `phi_1,i(x) - phi_1,i(0)` |
//! | `r_k` (`k >= 2`) | m | section `k`'s rigid offset from the vehicle (basis 1) |
//! | `q_k_2` (`k >= 2`) | rad | section `k`'s rigid rotation (basis `x`) |
//! | `q_k_i` (`k >= 2`, `i >= 3`) | m | section `k`'s free-free shape coordinate `i` |
//! | `<name>_dot` | m/s, rad/s | the rate of each of the above, same order |
//!
//! **Inputs:** `F` (N), the drive force, for a force-driven scene; `a_vehicle` (m/s^2), the
//! vehicle's acceleration, for a prescribed motion. With [`Lpv::with_disturbance`], a second
//! input `F_load` (N): a horizontal disturbance force on the load at the top of section `n`
//! (wind, a push), entering as the generalized force `w_n(l_n)` per coordinate.
//!
//! **Outputs:** `vehicle`, `tip_rel`, `top1_rel` (m), `xi_k_j` (m) for every contact, and
//! `f_k_j` (N) for every contact when the contacts are closed.
//!
//! **Contacts.** Closed: every contact obeys the linear law `f = c xi + d xi_dot` (the
//! clearance is left out, as about the straight configuration inside the band). Open: the
//! contacts are left out, so each upper section floats free; its coordinates are then not
//! controllable from the drive, nor is anything above it.

use crate::analysis::eigen::EigenError;
use crate::model::Model;
use crate::model::output::{LinearInput, Output};
use crate::model::params::Drive;
use crate::model::sensors::{SENSOR_OUTPUTS, Sensors};
use nalgebra::DMatrix;

/// How the contacts enter a linear model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ContactMode {
    /// Every contact closed with the linear law `f = c xi + d xi_dot`.
    #[default]
    Closed,
    /// No contacts: the sections are not coupled.
    Open,
}

impl ContactMode {
    /// `closed` or `open`.
    pub fn name(self) -> &'static str {
        match self {
            ContactMode::Closed => "closed",
            ContactMode::Open => "open",
        }
    }
}

impl std::str::FromStr for ContactMode {
    type Err = String;

    /// `closed` or `open`, as [`ContactMode::name`] writes them.
    fn from_str(s: &str) -> Result<Self, String> {
        [ContactMode::Closed, ContactMode::Open]
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| format!("`{s}` is not closed or open"))
    }
}

/// A named signal: a state, an input or an output.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Signal {
    /// Stable name (see the module documentation).
    pub name: String,
    /// SI unit.
    pub unit: String,
    /// What it is.
    pub description: String,
}

fn signal(name: String, unit: &str, description: String) -> Signal {
    Signal {
        name,
        unit: unit.to_string(),
        description,
    }
}

/// The matrices at one operating point.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearModel {
    /// Telescopic positions `a_2..a_n` (m).
    pub positions: Vec<f64>,
    /// Their speeds (m/s); they enter the damping through `gdot`.
    pub rates: Vec<f64>,
    /// State matrix (`2 dof x 2 dof`).
    pub a: DMatrix<f64>,
    /// Input matrix (`2 dof x inputs`).
    pub b: DMatrix<f64>,
    /// Output matrix.
    pub c: DMatrix<f64>,
    /// Feedthrough (`outputs x inputs`; nonzero only for `acc_load`).
    pub d: DMatrix<f64>,
}

/// Why a linear model cannot be had.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LinearError {
    /// A position is outside the overlap's valid range.
    #[error(
        "a{section} = {value} m is outside the valid overlap: it must lie in [{min}, {max}) m, \
         where the overlap of sections {} and {section} stays in (0, min(l_{}, l_{section})]",
        section - 1,
        section - 1
    )]
    OutOfRange {
        /// Section `k` of `a_k`.
        section: usize,
        /// The value given (m).
        value: f64,
        /// Smallest valid value (m).
        min: f64,
        /// Valid values are below this (m).
        max: f64,
    },
    /// Positions or speeds of the wrong count or not finite.
    #[error("{0}")]
    Input(String),
    /// The mass matrix could not be factored.
    #[error(transparent)]
    Eigen(#[from] EigenError),
}

/// The linear parameter-varying model of a [`Model`]: `M^-1` once, then `A`, `B`, `C`, `D` at
/// any positions.
pub struct Lpv<'m> {
    model: &'m dyn Model,
    contacts: ContactMode,
    minv: DMatrix<f64>,
    /// For a prescribed motion, `M_pp^-1` of the coordinates other than the vehicle's.
    motion: Option<DMatrix<f64>>,
    states: Vec<Signal>,
    inputs: Vec<Signal>,
    outputs: Vec<Signal>,
    /// Rows of `vehicle`, `tip_rel` and `top1_rel` over the coordinates.
    rigid_rows: DMatrix<f64>,
    /// The rows of the sensor outputs (the last two).
    sensors: Sensors,
    /// Whether the disturbance input `F_load` follows the drive input.
    disturbance: bool,
}

impl<'m> Lpv<'m> {
    /// Prepares the LPV model of `model` with `contacts`.
    ///
    /// # Errors
    /// [`LinearError::Eigen`] when the mass matrix is not positive definite.
    pub fn new(model: &'m dyn Model, contacts: ContactMode) -> Result<Self, LinearError> {
        let n = model.dof();
        let m = model.mass_matrix();
        let minv = m
            .clone()
            .cholesky()
            .ok_or(EigenError::MassNotPositiveDefinite)?
            .inverse();
        let motion = match model.params().drive {
            Drive::Motion(_) => Some(
                m.view((1, 1), (n - 1, n - 1))
                    .into_owned()
                    .cholesky()
                    .ok_or(EigenError::MassNotPositiveDefinite)?
                    .inverse(),
            ),
            Drive::Force(_) => None,
        };
        let layout = model.layout();
        let rigid_rows = rigid_rows(model);
        let states = state_signals(layout.modes());
        let inputs = vec![input_signal(if motion.is_some() {
            LinearInput::VehicleAcceleration
        } else {
            LinearInput::DriveForce
        })];
        // the contact forces only with closed contacts, no drive_force (the input)
        let outputs = layout
            .output_names(false)
            .iter()
            .map(String::as_str)
            .filter(|name| {
                contacts == ContactMode::Closed
                    || !Output::parse(name).is_some_and(|o| o.is_contact_force())
            })
            .chain(SENSOR_OUTPUTS)
            .map(output_signal)
            .collect();
        let sensors = Sensors::new(model);
        Ok(Lpv {
            model,
            contacts,
            minv,
            motion,
            states,
            inputs,
            outputs,
            sensors,
            rigid_rows,
            disturbance: false,
        })
    }

    /// Adds the second input `F_load` (N), a horizontal force on the load (see the module
    /// documentation).
    pub fn with_disturbance(mut self) -> Self {
        if !self.disturbance {
            self.disturbance = true;
            self.inputs.push(input_signal(LinearInput::LoadForce));
        }
        self
    }

    /// The states, in the order of the matrices.
    pub fn states(&self) -> &[Signal] {
        &self.states
    }

    /// The inputs.
    pub fn inputs(&self) -> &[Signal] {
        &self.inputs
    }

    /// The outputs.
    pub fn outputs(&self) -> &[Signal] {
        &self.outputs
    }

    /// How the contacts enter.
    pub fn contacts(&self) -> ContactMode {
        self.contacts
    }

    /// The valid range `[min, max)` (m) of `a_k`, `k = 2..n` (index 0 is `a_2`).
    pub fn position_range(&self, index: usize) -> (f64, f64) {
        self.model.params().position_range(index)
    }

    /// `K_e` and `D` of `M z'' + D z' + K_e z = b u`: the structural damping `D_s` and the
    /// linear law on every closed contact, `f = c g'z + d (g'z' + gdot'z)`, for contact vectors `g`, `gdot`.
    fn second_order(&self, g: &DMatrix<f64>, gdot: &DMatrix<f64>) -> (DMatrix<f64>, DMatrix<f64>) {
        let n = self.model.dof();
        let law = &self.model.params().contact;
        let mut k_e = self.model.stiffness_matrix().clone();
        // the sections' structural damping, then the closed contacts' own
        let mut d = self
            .model
            .damping_matrix()
            .cloned()
            .unwrap_or_else(|| DMatrix::zeros(n, n));
        if self.contacts == ContactMode::Closed && g.ncols() > 0 {
            k_e += law.stiffness * g * g.transpose() + law.damping * g * gdot.transpose();
            d += law.damping * g * g.transpose();
        }
        (k_e, d)
    }

    /// The second-order form at positions `a_2..a_n` (m) moving at `rates` (m/s): `(K_e, D)`
    /// of `M z'' + D z' + K_e z = b u` (with `M` the model's mass matrix).
    ///
    /// # Errors
    /// As [`Lpv::at`].
    pub fn second_order_at(
        &self,
        positions: &[f64],
        rates: &[f64],
    ) -> Result<(DMatrix<f64>, DMatrix<f64>), LinearError> {
        let (g, gdot) = self.contact_vectors(positions, rates)?;
        Ok(self.second_order(&g, &gdot))
    }

    /// The contact vectors `g`, `gdot` at positions `a_2..a_n` (m) moving at `rates` (m/s),
    /// after checking both.
    fn contact_vectors(
        &self,
        positions: &[f64],
        rates: &[f64],
    ) -> Result<(DMatrix<f64>, DMatrix<f64>), LinearError> {
        self.check_point(positions, rates)?;
        let model = self.model;
        let (n, nc) = (model.dof(), model.layout().contact_count());
        let mut g = DMatrix::zeros(n, nc);
        let mut gdot = DMatrix::zeros(n, nc);
        model.contact_vectors_at(positions, rates, &mut g, &mut gdot);
        Ok((g, gdot))
    }

    /// Checks an operating point: positions `a_2..a_n` (m) inside the valid overlaps, finite
    /// speeds (m/s), one of each per telescopic position.
    ///
    /// # Errors
    /// As [`Lpv::at`].
    pub fn check_point(&self, positions: &[f64], rates: &[f64]) -> Result<(), LinearError> {
        let model = self.model;
        let npos = model.params().sections.len() - 1;
        if positions.len() != npos || rates.len() != npos {
            return Err(LinearError::Input(format!(
                "the model has {npos} telescopic position(s), a_2..a_n; got {} position(s) and {} \
                 speed(s)",
                positions.len(),
                rates.len()
            )));
        }
        for (i, (&a, &r)) in positions.iter().zip(rates).enumerate() {
            let (min, max) = self.position_range(i);
            if !(a >= min && a < max) {
                return Err(LinearError::OutOfRange {
                    section: i + 2,
                    value: a,
                    min,
                    max,
                });
            }
            if !r.is_finite() {
                return Err(LinearError::Input(format!(
                    "the speed of a_{} must be finite (got {r})",
                    i + 2
                )));
            }
        }
        Ok(())
    }

    /// `A`, `B`, `C`, `D` at positions `a_2..a_n` (m) moving at `rates` (m/s).
    ///
    /// # Errors
    /// [`LinearError`] for positions outside the valid overlap, or of the wrong count.
    pub fn at(&self, positions: &[f64], rates: &[f64]) -> Result<LinearModel, LinearError> {
        let model = self.model;
        let n = model.dof();
        let nc = model.layout().contact_count();
        let (g, gdot) = self.contact_vectors(positions, rates)?;
        let law = &model.params().contact;
        let (k_e, d) = self.second_order(&g, &gdot);
        let mut a = DMatrix::zeros(2 * n, 2 * n);
        let mut b = DMatrix::zeros(2 * n, self.inputs.len());
        for i in 0..n {
            a[(i, n + i)] = 1.0;
        }
        if let Some(mpp_inv) = &self.motion {
            // u'' is the input; the other coordinates follow M_pp p'' = -M_p0 u'' - ...
            let r = n - 1;
            let m = model.mass_matrix();
            let kz = -(mpp_inv * k_e.view((1, 0), (r, n)));
            let dz = -(mpp_inv * d.view((1, 0), (r, n)));
            a.view_mut((n + 1, 0), (r, n)).copy_from(&kz);
            a.view_mut((n + 1, n), (r, n)).copy_from(&dz);
            b[(n, 0)] = 1.0;
            let bp = -(mpp_inv * m.view((1, 0), (r, 1)));
            b.view_mut((n + 1, 0), (r, 1)).copy_from(&bp);
            if self.disturbance {
                // the held vehicle takes the load's push as a reaction
                let load = DMatrix::from_column_slice(r, 1, &self.sensors.load[1..n]);
                b.view_mut((n + 1, 1), (r, 1)).copy_from(&(mpp_inv * load));
            }
        } else {
            a.view_mut((n, 0), (n, n))
                .copy_from(&(-(&self.minv * &k_e)));
            a.view_mut((n, n), (n, n)).copy_from(&(-(&self.minv * &d)));
            let bz = &self.minv * model.drive_vector();
            b.view_mut((n, 0), (n, 1)).copy_from(&bz);
            if self.disturbance {
                let load = DMatrix::from_column_slice(n, 1, &self.sensors.load[..n]);
                b.view_mut((n, 1), (n, 1)).copy_from(&(&self.minv * load));
            }
        }
        let mut c = DMatrix::zeros(self.outputs.len(), 2 * n);
        c.view_mut((0, 0), (3, n)).copy_from(&self.rigid_rows);
        for ci in 0..nc {
            for j in 0..n {
                c[(3 + ci, j)] = g[(j, ci)];
                if self.contacts == ContactMode::Closed {
                    c[(3 + nc + ci, j)] = law.stiffness * g[(j, ci)] + law.damping * gdot[(j, ci)];
                    c[(3 + nc + ci, n + j)] = law.damping * g[(j, ci)];
                }
            }
        }
        let mut d_mat = DMatrix::zeros(self.outputs.len(), self.inputs.len());
        // the sensors: curvature from the coordinates, the load's acceleration from x'
        let (kappa_row, acc_row) = (self.outputs.len() - 2, self.outputs.len() - 1);
        for j in 0..n {
            c[(kappa_row, j)] = self.sensors.kappa[j];
        }
        for col in 0..2 * n {
            c[(acc_row, col)] = (0..n).map(|j| self.sensors.load[j] * a[(n + j, col)]).sum();
        }
        for input in 0..self.inputs.len() {
            d_mat[(acc_row, input)] = (0..n)
                .map(|j| self.sensors.load[j] * b[(n + j, input)])
                .sum();
        }
        Ok(LinearModel {
            positions: positions.to_vec(),
            rates: rates.to_vec(),
            a,
            b,
            c,
            d: d_mat,
        })
    }
}

/// The states `[z, z']` of a model with `modes` coordinates per section: names, units and
/// what each is.
fn state_signals(modes: &[usize]) -> Vec<Signal> {
    let mut states = Vec::with_capacity(2 * modes.iter().sum::<usize>());
    for (k, &count) in (1..).zip(modes) {
        for i in 1..=count {
            let name = state_name(k, i);
            states.push(match (k, i) {
                (1, 1) => signal(
                    name,
                    "m",
                    "vehicle position w_1(0,t), the rigid translation of the telescope".into(),
                ),
                (1, i) => signal(
                    name,
                    "m",
                    format!("section 1, shape coordinate {i} (basis phi_1,{i}(x) - phi_1,{i}(0))"),
                ),
                (k, 1) => signal(
                    name,
                    "m",
                    format!("section {k}, rigid offset from the vehicle (basis 1)"),
                ),
                (k, 2) => signal(
                    name,
                    "rad",
                    format!("section {k}, rigid rotation (basis x)"),
                ),
                (k, i) => signal(
                    name,
                    "m",
                    format!("section {k}, free-free shape coordinate {i}"),
                ),
            });
        }
    }
    let rates: Vec<Signal> = states
        .iter()
        .map(|s| {
            signal(
                format!("{}_dot", s.name),
                &format!("{}/s", s.unit),
                format!("rate of: {}", s.description),
            )
        })
        .collect();
    states.extend(rates);
    states
}

/// Rows of the foot's displacement, `tip_rel` and `top1_rel` on the coordinates (their
/// rigid-body parts).
fn rigid_rows(model: &dyn Model) -> DMatrix<f64> {
    let (n, params) = (model.dof(), model.params());
    let sections = params.sections.len();
    let mut rigid_rows = DMatrix::zeros(3, n);
    let top = params.sections[sections - 1].length;
    let l1 = params.sections[0].length;
    for j in 0..n {
        let mut e = vec![0.0; n];
        e[j] = 1.0;
        let foot = model.displacement(1, 0.0, &e);
        rigid_rows[(0, j)] = foot;
        rigid_rows[(1, j)] = model.displacement(sections, top, &e) - foot;
        rigid_rows[(2, j)] = model.displacement(1, l1, &e) - foot;
    }
    rigid_rows
}

/// The signal of a linear model's input.
fn input_signal(input: LinearInput) -> Signal {
    signal(
        input.name().into(),
        input.unit(),
        input.description().into(),
    )
}

/// The unit and description of an output of a run or a linear model, by its name
/// ([`Output`]); a name that is no output has no unit and itself as description.
pub fn output_signal(name: &str) -> Signal {
    match Output::parse(name) {
        Some(output) => signal(name.to_string(), output.unit(), output.description()),
        None => signal(name.to_string(), "", name.to_string()),
    }
}

/// The name of generalized coordinate `i` of section `k` (both 1-based): `u` (the vehicle),
/// `q_1_i`, `r_k` (a section's rigid offset), `q_k_i`.
pub fn state_name(k: usize, i: usize) -> String {
    match (k, i) {
        (1, 1) => "u".into(),
        (k, 1) if k > 1 => format!("r_{k}"),
        (k, i) => format!("q_{k}_{i}"),
    }
}

/// The state names of a model with `modes` per section, in the order of the linear models:
/// the coordinates, then their rates (`NAME_dot`).
pub fn state_names(modes: &[usize]) -> Vec<String> {
    let coordinates: Vec<String> = modes
        .iter()
        .enumerate()
        .flat_map(|(k, &m)| (1..=m).map(move |i| state_name(k + 1, i)))
        .collect();
    let rates = coordinates.iter().map(|c| format!("{c}_dot"));
    coordinates.clone().into_iter().chain(rates).collect()
}
