//! The LQR on the discrete Kalman filter of the closed-contact model, as C: what
//! [`crate::control::law::sampled::DiscreteController`] computes.

use super::common::{LQR_LAW, banner, header, nested, source_start};
use crate::Result;
use crate::control::file::schema::{Controller, DiscretePoint};
use std::fmt::Write as _;

/// The header and the source of `file`'s LQR on its discrete Kalman filter.
pub(super) fn emit_linear(file: &Controller, start: f64, end: f64) -> Result<(String, String)> {
    let n = file.states.len();
    let banner = banner(file, "an LQR on a discrete Kalman filter");
    let header = header(
        file,
        &banner,
        &format!("#define TC_STATES {n}  /* the model's states, x = [z, z'] */\n"),
        "the state estimate and the force now applied (N)",
        "    double x_hat[TC_STATES];\n    double u;\n",
    );
    let source = source(file, &banner, start, end);
    Ok((header, source))
}

/// The C source: the common part, the filter's and the LQR's tables, its functions.
fn source(file: &Controller, banner: &str, start: f64, end: f64) -> String {
    let sampled = file.sampled.as_ref().expect("checked by the caller");
    let mut s = source_start(file, banner, start, end);
    let (n, m, p) = (
        file.states.len(),
        sampled.sensors.len(),
        file.schedule.len(),
    );
    let flat = |f: &dyn Fn(&DiscretePoint) -> &Vec<Vec<f64>>| -> Vec<f64> {
        sampled
            .points
            .iter()
            .flat_map(|p| f(p).iter().flatten().copied())
            .collect()
    };
    let gains: Vec<f64> = file
        .schedule
        .iter()
        .flat_map(|p| p.k[0].iter().copied())
        .collect();
    s.push_str(
        "\n/* per design point: Ad, Bd, C, L of the discrete filter and the LQR gain K */\n",
    );
    for (decl, values, dims) in [
        (
            "AD[TC_POINTS][TC_STATES][TC_STATES]",
            flat(&|p| &p.ad),
            vec![p, n, n],
        ),
        ("BD[TC_POINTS][TC_STATES]", flat(&|p| &p.bd), vec![p, n]),
        (
            "CM[TC_POINTS][TC_SENSORS][TC_STATES]",
            flat(&|p| &p.c),
            vec![p, m, n],
        ),
        (
            "LK[TC_POINTS][TC_STATES][TC_SENSORS]",
            flat(&|p| &p.l),
            vec![p, n, m],
        ),
        ("K[TC_POINTS][TC_STATES]", gains, vec![p, n]),
    ] {
        let _ = writeln!(
            s,
            "static const double {decl} = {};",
            nested(&values, &dims, "")
        );
    }
    s.push_str(LQR_LAW);
    s.push_str(FILTER_FUNCTIONS);
    s
}

/// The linear filter's init and step.
const FILTER_FUNCTIONS: &str = include_str!("c/linear_filter.c");
