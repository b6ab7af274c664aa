//! The fitted values' uncertainty from the Jacobian at the optimum: the covariance
//! `s^2 (J^T J)^-1` in the scale coordinates (a logarithm, or the value), with `s^2` the
//! weighted residual's variance per degree of freedom, widened by the residuals' own
//! correlation from sample to sample (an AR(1) factor `(1 + rho) / (1 - rho)`): a model
//! error that is not white noise carries fewer independent samples than the record has.

use crate::{Error, Result};
use nalgebra::{DMatrix, DVector};

/// Largest condition number of `J^T J` the fit reports a covariance for.
const MAX_CONDITION: f64 = 1e13;

/// Largest correlation of two values the fit reports: beyond it they are one value to the
/// sensors: the Jacobian's central differences (good to about 1e-4) keep such a pair
/// from exactly 1, and its deviations would be a hundred times those of either alone.
const MAX_CORRELATION: f64 = 0.9999;

/// The covariance of the scale coordinates and how it was made.
#[derive(Debug, Clone, PartialEq)]
pub struct Uncertainty {
    /// Standard deviation of each scale coordinate.
    pub std_theta: Vec<f64>,
    /// Correlation matrix (rows of the free values).
    pub correlation: Vec<Vec<f64>>,
    /// The weighted residual's variance per degree of freedom (1 when the noise figures
    /// and the model are right).
    pub variance_factor: f64,
    /// The widening for correlated residuals (1: white).
    pub correlation_factor: f64,
}

/// The uncertainty of a fit whose Jacobian in the scale coordinates is `jacobian` (rows:
/// weighted residuals) with `residuals` at the optimum, per sensor of `per_sensor` samples,
/// with `eliminated` values also fitted in closed form (offsets, a start's amplitudes); `spans`: each value's bounds' width in its scale
/// coordinate.
///
/// # Errors
/// [`Error::Input`] naming `record` and the value the record does not determine (the one
/// the nearly singular direction moves most).
pub fn uncertainty(
    jacobian: &DMatrix<f64>,
    residuals: &[f64],
    per_sensor: usize,
    eliminated: usize,
    keys: &[String],
    spans: &[f64],
    record: &str,
) -> Result<Uncertainty> {
    let (m, p) = jacobian.shape();
    let undetermined = |j: usize, why: &str| Error::Input {
        subject: record.to_string(),
        rule: format!(
            "does not determine {} ({why}); record longer or with a sensor that sees it, or \
             free fewer values",
            keys[j]
        ),
    };
    if let Some(j) = (0..p).find(|&j| jacobian.column(j).iter().any(|v| !v.is_finite())) {
        return Err(undetermined(j, "the sensitivity to it is not finite"));
    }
    let dof = m.saturating_sub(p + eliminated);
    if dof == 0 {
        return Err(undetermined(0, "fewer samples than fitted values"));
    }
    let normal = jacobian.transpose() * jacobian;
    let svd = normal.clone().svd(true, true);
    let (largest, smallest) = (svd.singular_values.max(), svd.singular_values.min());
    if !(smallest > 0.0 && largest / smallest < MAX_CONDITION) {
        let v_t = svd.v_t.as_ref().expect("asked for");
        let row = svd.singular_values.imin();
        let j = (0..p)
            .max_by(|&a, &b| v_t[(row, a)].abs().total_cmp(&v_t[(row, b)].abs()))
            .unwrap_or(0);
        return Err(undetermined(
            j,
            "the sensors do not change with it, or change with it as with another",
        ));
    }
    let rss: f64 = residuals.iter().map(|r| r * r).sum();
    let variance_factor = rss / dof as f64;
    let correlation_factor = ar1_factor(residuals, per_sensor);
    let inverse = svd.pseudo_inverse(0.0).map_err(|e| undetermined(0, e))?;
    let covariance = inverse * (variance_factor * correlation_factor);
    let std_theta: Vec<f64> = (0..p).map(|j| covariance[(j, j)].sqrt()).collect();
    let correlation: Vec<Vec<f64>> = (0..p)
        .map(|i| {
            (0..p)
                .map(|j| covariance[(i, j)] / (std_theta[i] * std_theta[j]))
                .collect()
        })
        .collect();
    if let Some(j) = (0..p).find(|&j| std_theta[j] > spans[j]) {
        return Err(undetermined(
            j,
            "its standard deviation exceeds the width of its bounds",
        ));
    }
    // two values the sensors see only together (E and I of a section) leave a direction
    // that only the differences' own noise keeps from singular
    let pairs = (0..p).flat_map(|i| (i + 1..p).map(move |j| (i, j)));
    for (i, j) in pairs {
        if correlation[i][j].abs() > MAX_CORRELATION {
            return Err(undetermined(
                j,
                &format!(
                    "the sensors change with it as with {} (correlation {:.6})",
                    keys[i], correlation[i][j]
                ),
            ));
        }
    }
    Ok(Uncertainty {
        std_theta,
        correlation,
        variance_factor,
        correlation_factor,
    })
}

/// The variance widening `(1 + rho) / (1 - rho)` of the largest lag-one autocorrelation
/// `rho` of the residuals of one sensor (blocks of `per_sensor`), at least 1.
fn ar1_factor(residuals: &[f64], per_sensor: usize) -> f64 {
    residuals
        .chunks(per_sensor.max(2))
        .map(|r| {
            let v = DVector::from_column_slice(r);
            let mean = v.mean();
            let centred = v.add_scalar(-mean);
            let lag0 = centred.norm_squared();
            if lag0 == 0.0 || r.len() < 3 {
                return 1.0;
            }
            let lag1: f64 = centred.as_slice().windows(2).map(|w| w[0] * w[1]).sum();
            let rho = (lag1 / lag0).clamp(0.0, 0.99);
            (1.0 + rho) / (1.0 - rho)
        })
        .fold(1.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A straight-line fit y = a + b x with unit noise: the covariance is the textbook one.
    #[test]
    fn a_line_fit_has_the_textbook_covariance() {
        let x: Vec<f64> = (0..50).map(|i| f64::from(i) / 10.0).collect();
        let jacobian = DMatrix::from_fn(50, 2, |i, j| if j == 0 { 1.0 } else { x[i] });
        // alternating residuals of size 1: variance factor about 1, no positive correlation
        let residuals: Vec<f64> = (0..50)
            .map(|i| if i % 2 == 0 { 1.0 } else { -1.0 })
            .collect();
        let keys = ["a".to_string(), "b".to_string()];
        let u = uncertainty(&jacobian, &residuals, 50, 0, &keys, &[1e3; 2], "r").unwrap();
        let n = 50.0;
        let sx: f64 = x.iter().sum();
        let sxx: f64 = x.iter().map(|x| x * x).sum();
        let det = n * sxx - sx * sx;
        let factor = 50.0 / 48.0;
        assert!((u.std_theta[1] - (factor * n / det).sqrt()).abs() < 1e-12);
        assert!((u.std_theta[0] - (factor * sxx / det).sqrt()).abs() < 1e-12);
        assert_eq!(u.correlation_factor, 1.0);
        // a slow residual (all one sign, a trend) widens it
        let slow: Vec<f64> = (0..50).map(|i| (f64::from(i) / 8.0).sin()).collect();
        assert!(
            uncertainty(&jacobian, &slow, 50, 0, &keys, &[1e3; 2], "r")
                .unwrap()
                .correlation_factor
                > 5.0
        );
    }

    #[test]
    fn a_value_the_record_does_not_see_is_named() {
        let jacobian =
            DMatrix::from_fn(40, 2, |i, j| if j == 0 { f64::from(i as u32) } else { 0.0 });
        let keys = ["masses.load".to_string(), "contact.damping".to_string()];
        let err =
            uncertainty(&jacobian, &[0.1; 40], 40, 0, &keys, &[1e3; 2], "run.csv").unwrap_err();
        assert!(
            err.to_string()
                .contains("does not determine contact.damping"),
            "{err}"
        );
    }
}
