//! The extended Kalman filter ([`super::ekf`]) with its LQR law as self-contained C99: the
//! recorded model (`M^-1`, `K`, `D_s`, the drive's response, the contact law and the contact
//! vectors' table), the filter's matrices, and functions that compute what
//! [`crate::control::law::ekf::ExtendedKalman`] computes, operation for operation.

use super::common::{LQR_LAW, banner, header, list, lit, nested, source_start};
use crate::control::file::schema::Controller;
use crate::control::law::estimator_model::EstimatorModel;
use crate::{Error, Result};
use std::fmt::Write as _;

/// The header and the source of `file`'s extended filter and LQR over `[start, end]` s.
///
/// # Errors
/// [`Error::Input`] when the file does not record the filter's model or its sensors are not
/// linear in the coordinates.
pub(crate) fn emit_extended(file: &Controller, start: f64, end: f64) -> Result<(String, String)> {
    let sampled = crate::control::law::ekf::sampled_of(file)?;
    let model = sampled.model.as_ref().ok_or_else(|| {
        Error::input(
            "controller `sampled.model`",
            "is missing: the extended filter's C predicts with the model its file records",
        )
    })?;
    let (n, nc) = (model.dof(), model.contacts);
    model.check(n, nc)?;
    let w = 2 * n;
    // the tables below are fixed-size C arrays: a file whose sizes disagree is refused here
    // rather than emitted as C that does not compile
    let c = crate::control::law::ekf::measurement_rows(sampled, w)?;
    if file
        .schedule
        .iter()
        .any(|p| p.k.len() != 1 || p.k[0].len() != w)
    {
        return Err(Error::input(
            "controller `schedule[].k`",
            format!("must be one row of {w} gains per design point"),
        ));
    }
    let banner = banner(
        file,
        "an LQR on an extended Kalman filter of the nonlinear model with the clearance's \
         contact law",
    );
    let defines = format!(
        "#define TC_DOF {n}     /* generalized coordinates z */\n\
         #define TC_STATES {w}  /* the estimate x = [z, z'] */\n\
         #define TC_CONTACTS {nc} /* contact points */\n"
    );
    let header = header(
        file,
        &banner,
        &defines,
        "the estimate, its covariance (row-major), the force now applied (N) and the \
         scratch of one step",
        "    double x_hat[TC_STATES];\n    double p[TC_STATES * TC_STATES];\n    double u;\n    \
         double work[4][TC_STATES * TC_STATES];\n",
    );
    let mut s = source_start(file, &banner, start, end);
    append_model(&mut s, model);
    append_geometry(&mut s, model);
    append_filter_tables(&mut s, file, model, c, w);
    s.push_str(LQR_LAW);
    s.push_str(MODEL_FUNCTIONS);
    s.push_str(DENSE_FUNCTIONS);
    s.push_str(FILTER_FUNCTIONS);
    Ok((header, s))
}

/// The model's constants: sizes of the prediction, `M^-1`, `K`, `D_s`, the drive's response
/// and the contact law.
fn append_model(s: &mut String, model: &EstimatorModel) {
    let n = model.dof();
    let _ = writeln!(
        s,
        "\n#define TC_DAMPED {}  /* structural damping D_s in the model */\n\
         #define TC_TABLE {}   /* contact vectors tabulated in time (positions move) */\n\
         #define SUBSTEPS {}   /* RK4 steps of the prediction per period */\n\
         #define TAYLOR_DEGREE {}\n\
         #define MAX_HALVINGS {}\n\
         static const double SCALED_NORM = {};\n\
         static const double INITIAL_COVARIANCE = {};",
        u8::from(model.damping.is_some()),
        u8::from(model.geometry_table.is_some()),
        crate::control::law::ekf::SUBSTEPS,
        crate::control::law::small_dense::TAYLOR_DEGREE,
        crate::control::law::small_dense::MAX_HALVINGS,
        lit(crate::control::law::small_dense::SCALED_NORM),
        lit(crate::control::law::ekf::INITIAL_COVARIANCE),
    );
    let rows = |r: &Vec<Vec<f64>>| r.iter().flatten().copied().collect::<Vec<f64>>();
    let _ = writeln!(
        s,
        "\n/* the model: M z'' = b u - K z - D_s z' - sum_c f_c g_c(t) */"
    );
    let mut arrays: Vec<(&str, Vec<f64>, Vec<usize>)> = vec![
        (
            "MINV[TC_DOF][TC_DOF]",
            rows(&model.mass_inverse),
            vec![n, n],
        ),
        ("KS[TC_DOF][TC_DOF]", rows(&model.stiffness), vec![n, n]),
    ];
    if let Some(d) = &model.damping {
        arrays.push(("DS[TC_DOF][TC_DOF]", rows(d), vec![n, n]));
    }
    arrays.push(("RESP[TC_DOF]", model.drive_response.clone(), vec![n]));
    for (decl, values, dims) in arrays {
        let _ = writeln!(
            *s,
            "static const double {decl} = {};",
            nested(&values, &dims, "")
        );
    }
    let _ = writeln!(
        s,
        "/* the contact law: stiffness (N/m), damping (N s/m), clearance (m) */\n\
         static const double CONTACT_STIFFNESS = {};\n\
         static const double CONTACT_DAMPING = {};\n\
         static const double CLEARANCE = {};",
        lit(model.contact_stiffness),
        lit(model.contact_damping),
        lit(model.clearance)
    );
}

/// The contact vectors: their table in time (cubic Hermite, as the model's) or the fixed
/// values.
fn append_geometry(s: &mut String, model: &crate::control::law::estimator_model::EstimatorModel) {
    match (&model.geometry_table, &model.fixed_geometry) {
        (Some(t), _) => {
            let width = t.varying.len();
            let _ = writeln!(
                s,
                "\n/* the contact vectors g_c (contact after contact) on a uniform grid in \
                 time: the constant entries,\n * then g and its rate (1/s) of the varying \
                 entries at every node */\n\
                 #define G_INTERVALS {}\n#define G_VARYING {width}\n\
                 static const double G_START = {};\nstatic const double G_STEP = {};\n\
                 static const int VARYING[G_VARYING] = {{{}}};\n\
                 static const double CONSTANT_G[TC_CONTACTS * TC_DOF] = {};",
                t.intervals,
                lit(t.start),
                lit(t.step),
                t.varying
                    .iter()
                    .map(|k| k.to_string())
                    .collect::<Vec<_>>()
                    .join(", "),
                list(t.constant_g.iter().copied(), "    ")
            );
            for (name, values) in [("TABLE_G", &t.g), ("TABLE_GD", &t.gd)] {
                let _ = writeln!(
                    s,
                    "static const double {name}[G_INTERVALS + 1][G_VARYING] = {};",
                    nested(values, &[t.intervals + 1, width], "")
                );
            }
        }
        (None, fixed) => {
            let fixed = fixed.as_deref().unwrap_or_default();
            let _ = writeln!(
                s,
                "\n/* the contact vectors g_c (contact after contact): fixed positions */\n\
                 static const double FIXED_G[TC_CONTACTS * TC_DOF] = {};",
                list(fixed.iter().copied(), "    ")
            );
        }
    }
}

/// The measurement rows `c`, the noise covariances and the LQR gains per design point.
fn append_filter_tables(
    s: &mut String,
    file: &Controller,
    model: &crate::control::law::estimator_model::EstimatorModel,
    c: Vec<f64>,
    w: usize,
) {
    let sampled = file.sampled.as_ref().expect("checked by the caller");
    let m = sampled.sensors.len();
    let r = crate::control::law::ekf::measurement_noise(sampled);
    let q = crate::control::law::ekf::process_noise(sampled, &model.drive_response);
    let p = file.schedule.len();
    let gains: Vec<f64> = file
        .schedule
        .iter()
        .flat_map(|pt| pt.k[0].iter().copied())
        .collect();
    let _ = writeln!(
        s,
        "\n/* the filter: measurement rows C, measurement noise R, process noise Q per period;\n \
         * the LQR gain K per design point */"
    );
    for (decl, values, dims) in [
        ("CM[TC_SENSORS][TC_STATES]", c, vec![m, w]),
        ("RN[TC_SENSORS * TC_SENSORS]", r, vec![m * m]),
        ("QN[TC_STATES * TC_STATES]", q, vec![w * w]),
        ("K[TC_POINTS][TC_STATES]", gains, vec![p, w]),
    ] {
        let _ = writeln!(
            s,
            "static const double {decl} = {};",
            nested(&values, &dims, "")
        );
    }
}

/// The model's contact vectors, contact law, right-hand side and Jacobian.
const MODEL_FUNCTIONS: &str = include_str!("c/ekf_model.c");

/// Products, the matrix exponential and the SPD inverse of `super::small_dense`.
const DENSE_FUNCTIONS: &str = include_str!("c/ekf_dense.c");

/// The filter's init and step: update, covariance and state prediction, the law.
const FILTER_FUNCTIONS: &str = include_str!("c/ekf_filter.c");
