//! What a machine's sensors measure, as rows over the generalized coordinates: the bending
//! curvature at a point of a section (a strain gauge there reads curvature times half the
//! section's height) and the absolute displacement of the load (whose second derivative a
//! tip accelerometer reads).

use crate::model::Model;
use crate::model::output::Sensor;

/// Names of the sensor outputs appended to every run's outputs, in order ([`Sensor::ALL`]).
pub const SENSOR_OUTPUTS: [&str; 2] = [
    Sensor::FootCurvature.name(),
    Sensor::LoadAcceleration.name(),
];

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
            kappa: model.shape_row(1, 0.0, 2),
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
