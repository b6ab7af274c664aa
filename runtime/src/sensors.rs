//! What a machine's sensors measure, as rows over the generalized coordinates: the bending
//! curvature at a point of a section (a strain gauge there reads curvature times half the
//! section's height) and the absolute displacement of the load (whose second derivative a
//! tip accelerometer reads).

use crate::layout::Layout;
use crate::model::Model;
use crate::params::ModelParams;
use crate::shape::{SectionKind, SectionShapes};

/// Names of the sensor outputs appended to every run's outputs, in order.
pub const SENSOR_OUTPUTS: [&str; 2] = ["kappa_1_0", "acc_load"];

/// The row `r` with `w_k''(x) = r . z` (1/m per unit of each coordinate): the bending
/// curvature of section `k` (1-based) at `x` (m from its foot), from the shape functions'
/// second derivatives (the translation and the rigid offsets have none).
pub fn curvature_row(params: &ModelParams, section: usize, x: f64) -> Vec<f64> {
    let layout = Layout::new(&params.modes(), params.contact_points);
    let s = &params.sections[section - 1];
    let shapes = SectionShapes::new(SectionKind::of_section(section), s.modes, s.length);
    let mut row = vec![0.0; layout.dof()];
    for f in shapes.functions() {
        // section 1's first function is the vehicle's translation (no curvature)
        if section == 1 && f.index() == 1 {
            continue;
        }
        row[layout.index(section, f.index())] = f.eval(x, 2);
    }
    row
}

/// The row `r` with `w_n(l_n) = r . z` (m per unit of each coordinate): the absolute
/// transverse position of the load at the top of the last section. `model` may wrap the
/// plant with coordinates of its own after the plant's (an observer's estimate).
pub fn load_row(model: &dyn Model) -> Vec<f64> {
    let params = model.params();
    let n = params.sections.len();
    let top = params.sections[n - 1].length;
    let mut e = vec![0.0; model.dof()];
    (0..model.layout().dof())
        .map(|j| {
            e[j] = 1.0;
            let w = model.displacement(n, top, &e);
            e[j] = 0.0;
            w
        })
        .collect()
}

/// The sensor outputs of a model: `kappa_1_0` (1/m), the curvature of section 1 at its foot,
/// and `acc_load` (m/s^2), the load's absolute horizontal acceleration.
#[derive(Debug, Clone, PartialEq)]
pub struct Sensors {
    /// `kappa_1_0 = kappa . z`.
    pub kappa: Vec<f64>,
    /// `acc_load = load . z''`.
    pub load: Vec<f64>,
}

impl Sensors {
    /// The rows of `model`'s sensors.
    pub fn new(model: &dyn Model) -> Self {
        Sensors {
            kappa: curvature_row(model.params(), 1, 0.0),
            load: load_row(model),
        }
    }

    /// The sensor values at state `y = [z, z']` with derivative `ydot = [z', z'']`, into
    /// `out` (in the order of [`SENSOR_OUTPUTS`]); allocation-free. `dof` is the number of
    /// coordinates of `y` (the plant's first, as [`load_row`] assumes).
    pub fn values(&self, dof: usize, y: &[f64], ydot: &[f64], out: &mut [f64]) {
        let n = self.kappa.len();
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(a, b)| a * b).sum::<f64>();
        out[0] = dot(&self.kappa, &y[..n]);
        out[1] = dot(&self.load, &ydot[dof..dof + n]);
    }
}
