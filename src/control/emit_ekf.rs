//! The extended Kalman filter ([`super::ekf`]) with its LQR law as self-contained C99: the
//! recorded model (`M^-1`, `K`, `D_s`, the drive's response, the contact law and the contact
//! vectors' table), the filter's matrices, and functions that compute what
//! [`super::ekf::ExtendedKalman`] computes, operation for operation.

use super::design::Controller;
use super::emit_c::{LQR_LAW, banner, header, list, lit, nested, source_start};
use crate::{Error, Result};
use std::fmt::Write as _;

/// The header and the source of `file`'s extended filter and LQR over `[start, end]` s.
///
/// # Errors
/// [`Error::Option`] when the file does not record the filter's model (written before it
/// was) or its sensors are not linear in the coordinates.
pub(crate) fn emit_extended(file: &Controller, start: f64, end: f64) -> Result<(String, String)> {
    let sampled = super::ekf::sampled_of(file)?;
    let model = sampled.model.as_ref().ok_or_else(|| {
        Error::option(
            "controller `sampled.model`",
            "is missing (a file written before the filter's model was recorded): design it \
             again to emit it",
        )
    })?;
    let (n, nc) = (model.dof(), model.contacts);
    model.check(n, nc)?;
    let w = 2 * n;
    // the tables below are fixed-size C arrays: a file whose sizes disagree is refused here
    // rather than emitted as C that does not compile
    let c = super::ekf::measurement_rows(sampled, w)?;
    if file
        .schedule
        .iter()
        .any(|p| p.k.len() != 1 || p.k[0].len() != w)
    {
        return Err(Error::option(
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
        super::ekf::SUBSTEPS,
        super::small_dense::TAYLOR_DEGREE,
        super::small_dense::MAX_HALVINGS,
        lit(super::small_dense::SCALED_NORM),
        lit(super::ekf::INITIAL_COVARIANCE),
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
            s,
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
    append_geometry(&mut s, model);
    append_filter_tables(&mut s, file, model, c, w);
    s.push_str(LQR_LAW);
    s.push_str(MODEL_FUNCTIONS);
    s.push_str(DENSE_FUNCTIONS);
    s.push_str(FILTER_FUNCTIONS);
    Ok((header, s))
}

/// The contact vectors: their table in time (cubic Hermite, as the model's) or the fixed
/// values.
fn append_geometry(s: &mut String, model: &super::estimator_model::EstimatorModel) {
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
    model: &super::estimator_model::EstimatorModel,
    c: Vec<f64>,
    w: usize,
) {
    let sampled = file.sampled.as_ref().expect("checked by the caller");
    let m = sampled.sensors.len();
    let r = super::ekf::measurement_noise(sampled);
    let q = super::ekf::process_noise(sampled, &model.drive_response);
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
const MODEL_FUNCTIONS: &str = r#"
/* The contact vectors g and their rates gd at t (s), contact after contact. */
static void geometry(double t, double g[TC_CONTACTS * TC_DOF], double gd[TC_CONTACTS * TC_DOF])
{
#if TC_TABLE
    double s = (t - G_START) / G_STEP;
    s = s < 0.0 ? 0.0 : (s > (double)G_INTERVALS ? (double)G_INTERVALS : s);
    int i = (int)s;
    if (i > G_INTERVALS - 1) {
        i = G_INTERVALS - 1;
    }
    const double u = s - (double)i;
    const double h = G_STEP;
    const double v = 1.0 - u;
    /* cubic Hermite basis and its derivative in u */
    const double h00 = (1.0 + 2.0 * u) * v * v;
    const double h10 = u * v * v;
    const double h01 = u * u * (3.0 - 2.0 * u);
    const double h11 = -u * u * v;
    const double d00 = -6.0 * u * v / h;
    const double d10 = v * (1.0 - 3.0 * u);
    const double d01 = 6.0 * u * v / h;
    const double d11 = u * (3.0 * u - 2.0);
    for (int k = 0; k < TC_CONTACTS * TC_DOF; k++) {
        g[k] = CONSTANT_G[k];
        gd[k] = 0.0;
    }
    for (int j = 0; j < G_VARYING; j++) {
        const int k = VARYING[j];
        g[k] = h00 * TABLE_G[i][j] + h01 * TABLE_G[i + 1][j]
            + h * (h10 * TABLE_GD[i][j] + h11 * TABLE_GD[i + 1][j]);
        gd[k] = d00 * TABLE_G[i][j] + d01 * TABLE_G[i + 1][j] + d10 * TABLE_GD[i][j]
            + d11 * TABLE_GD[i + 1][j];
    }
#else
    (void)t;
    for (int k = 0; k < TC_CONTACTS * TC_DOF; k++) {
        g[k] = FIXED_G[k];
        gd[k] = 0.0;
    }
#endif
}

/* The clearance contact law: force f (N) at gap xi (m) and rate xi_dot (m/s), and its
 * partials kc = df/dxi, dc = df/dxi_dot in the branch the gap is in. */
static void contact_law(double xi, double xi_dot, double *f, double *kc, double *dc)
{
    const double h = 0.5 * CLEARANCE;
    int state; /* -1 against the lower guide, 0 inside the clearance, 1 against the upper */
    if (CLEARANCE == 0.0) {
        state = xi < 0.0 ? -1 : 1;
    } else if (xi > h) {
        state = 1;
    } else if (xi < -h) {
        state = -1;
    } else {
        state = 0;
    }
    if (state == 0) {
        *f = 0.0;
        *kc = 0.0;
        *dc = 0.0;
        return;
    }
    *f = CONTACT_STIFFNESS * (state > 0 ? xi - h : xi + h) + CONTACT_DAMPING * xi_dot;
    *kc = CONTACT_STIFFNESS;
    *dc = CONTACT_DAMPING;
}

/* Gap and gap rate of contact c at state y. */
static void gap(const double *g, const double *gd, int c, const double y[TC_STATES],
                double *xi, double *xi_dot)
{
    *xi = 0.0;
    *xi_dot = 0.0;
    for (int j = 0; j < TC_DOF; j++) {
        *xi += g[c * TC_DOF + j] * y[j];
        *xi_dot += g[c * TC_DOF + j] * y[TC_DOF + j] + gd[c * TC_DOF + j] * y[j];
    }
}

/* ydot at t (s), state y = [z, z'], with the drive force u (N). */
static void rhs(double t, const double y[TC_STATES], double u, double ydot[TC_STATES])
{
    double g[TC_CONTACTS * TC_DOF], gd[TC_CONTACTS * TC_DOF], q[TC_DOF];
    geometry(t, g, gd);
    /* q = -K z - D_s z' - sum_c f_c g_c */
    for (int i = 0; i < TC_DOF; i++) {
        double s = 0.0;
        for (int j = 0; j < TC_DOF; j++) {
            s -= KS[i][j] * y[j];
        }
#if TC_DAMPED
        for (int j = 0; j < TC_DOF; j++) {
            s -= DS[i][j] * y[TC_DOF + j];
        }
#endif
        q[i] = s;
    }
    for (int c = 0; c < TC_CONTACTS; c++) {
        double xi, xi_dot, f, kc, dc;
        gap(g, gd, c, y, &xi, &xi_dot);
        contact_law(xi, xi_dot, &f, &kc, &dc);
        for (int i = 0; i < TC_DOF; i++) {
            q[i] -= f * g[c * TC_DOF + i];
        }
    }
    /* z'' = M^-1 q + M^-1 b u */
    for (int i = 0; i < TC_DOF; i++) {
        double s = 0.0;
        for (int j = 0; j < TC_DOF; j++) {
            s += MINV[i][j] * q[j];
        }
        ydot[i] = y[TC_DOF + i];
        ydot[TC_DOF + i] = s + RESP[i] * u;
    }
}

/* The Jacobian d ydot / d y (row-major) at t, y, in the contact branches the gaps are in. */
static void jacobian(double t, const double y[TC_STATES], double jac[TC_STATES * TC_STATES])
{
    double g[TC_CONTACTS * TC_DOF], gd[TC_CONTACTS * TC_DOF], q[TC_DOF];
    double kc[TC_CONTACTS], dc[TC_CONTACTS];
    const int w = TC_STATES;
    geometry(t, g, gd);
    for (int i = 0; i < w * w; i++) {
        jac[i] = 0.0;
    }
    for (int i = 0; i < TC_DOF; i++) {
        jac[i * w + TC_DOF + i] = 1.0;
    }
    for (int c = 0; c < TC_CONTACTS; c++) {
        double xi, xi_dot, f;
        gap(g, gd, c, y, &xi, &xi_dot);
        contact_law(xi, xi_dot, &f, &kc[c], &dc[c]);
    }
    /* dq/dz = -K - sum_c g_c (kc g_c + dc gd_c)^T, dq/dz' = -D_s - sum_c dc g_c g_c^T */
    for (int r = 0; r < TC_DOF; r++) {
        for (int col = 0; col < TC_DOF; col++) {
            double dz = -KS[r][col];
#if TC_DAMPED
            double dzd = -DS[r][col];
#else
            double dzd = 0.0;
#endif
            for (int c = 0; c < TC_CONTACTS; c++) {
                const double gr = g[c * TC_DOF + r];
                dz -= gr * (kc[c] * g[c * TC_DOF + col] + dc[c] * gd[c * TC_DOF + col]);
                dzd -= gr * dc[c] * g[c * TC_DOF + col];
            }
            jac[(TC_DOF + r) * w + col] = dz;
            jac[(TC_DOF + r) * w + TC_DOF + col] = dzd;
        }
    }
    /* the lower rows times M^-1 */
    for (int col = 0; col < w; col++) {
        for (int r = 0; r < TC_DOF; r++) {
            q[r] = jac[(TC_DOF + r) * w + col];
        }
        for (int i = 0; i < TC_DOF; i++) {
            double s = 0.0;
            for (int j = 0; j < TC_DOF; j++) {
                s += MINV[i][j] * q[j];
            }
            jac[(TC_DOF + i) * w + col] = s;
        }
    }
}
"#;

/// Products, the matrix exponential and the SPD inverse of `super::small_dense`.
const DENSE_FUNCTIONS: &str = r#"
/* c = a B for a (rows x inner), the factor's entry (k, col) at b[k * bk + col * bc]: b
 * itself (bk = cols, bc = 1) or a transposed one (bk = 1, bc = inner), row-major c. */
static void product(const double *a, const double *b, double *c, int rows, int inner, int cols,
                    int bk, int bc)
{
    for (int r = 0; r < rows; r++) {
        for (int col = 0; col < cols; col++) {
            double s = 0.0;
            for (int k = 0; k < inner; k++) {
                s += a[r * inner + k] * b[k * bk + col * bc];
            }
            c[r * cols + col] = s;
        }
    }
}

/* c = a b for a (rows x inner) and b (inner x cols), row-major. */
static void multiply(const double *a, const double *b, double *c, int rows, int inner, int cols)
{
    product(a, b, c, rows, inner, cols, cols, 1);
}

/* c = a b^T for a (rows x inner) and b (cols x inner), row-major. */
static void multiply_transposed(const double *a, const double *b, double *c, int rows,
                                int inner, int cols)
{
    product(a, b, c, rows, inner, cols, 1, inner);
}

/* out = exp(a) (TC_STATES square) by scaling and squaring of a Taylor polynomial; t1, t2
 * scratch. Returns 0 when a is not finite. */
static int exponential(const double *a, double *out, double *t1, double *t2)
{
    const int n = TC_STATES;
    double norm = 0.0;
    for (int col = 0; col < n; col++) {
        double s = 0.0;
        for (int r = 0; r < n; r++) {
            s += fabs(a[r * n + col]);
        }
        if (!isfinite(s)) {
            return 0;
        }
        norm = fmax(norm, s);
    }
    int halvings = 0;
    double scale = 1.0;
    while (norm > SCALED_NORM && halvings < MAX_HALVINGS) {
        norm *= 0.5;
        scale *= 0.5;
        halvings++;
    }
    for (int i = 0; i < n * n; i++) {
        t1[i] = a[i] * scale;
    }
    for (int r = 0; r < n; r++) {
        for (int col = 0; col < n; col++) {
            const double identity = r == col ? 1.0 : 0.0;
            out[r * n + col] = identity + t1[r * n + col] / (double)TAYLOR_DEGREE;
        }
    }
    for (int k = TAYLOR_DEGREE - 1; k >= 1; k--) {
        multiply(t1, out, t2, n, n, n);
        for (int r = 0; r < n; r++) {
            for (int col = 0; col < n; col++) {
                const double identity = r == col ? 1.0 : 0.0;
                out[r * n + col] = identity + t2[r * n + col] / (double)k;
            }
        }
    }
    for (int h = 0; h < halvings; h++) {
        multiply(out, out, t2, n, n, n);
        for (int i = 0; i < n * n; i++) {
            out[i] = t2[i];
        }
    }
    return 1;
}

/* inverse = s^-1 for a symmetric positive definite s (m x m) through its Cholesky factor l
 * (scratch). Returns 0 when s is not positive definite. */
static int invert_spd(const double *s, int m, double *l, double *inverse)
{
    for (int i = 0; i < m * m; i++) {
        l[i] = 0.0;
    }
    for (int j = 0; j < m; j++) {
        double d = s[j * m + j];
        for (int k = 0; k < j; k++) {
            d -= l[j * m + k] * l[j * m + k];
        }
        if (!(d > 0.0)) {
            return 0;
        }
        l[j * m + j] = sqrt(d);
        for (int i = j + 1; i < m; i++) {
            double v = s[i * m + j];
            for (int k = 0; k < j; k++) {
                v -= l[i * m + k] * l[j * m + k];
            }
            l[i * m + j] = v / l[j * m + j];
        }
    }
    for (int i = 0; i < m * m; i++) {
        inverse[i] = 0.0;
    }
    for (int j = 0; j < m; j++) {
        inverse[j * m + j] = 1.0 / l[j * m + j];
        for (int i = j + 1; i < m; i++) {
            double v = 0.0;
            for (int k = j; k < i; k++) {
                v += l[i * m + k] * inverse[k * m + j];
            }
            inverse[i * m + j] = -v / l[i * m + i];
        }
    }
    for (int i = 0; i < m * m; i++) {
        l[i] = inverse[i];
    }
    for (int r = 0; r < m; r++) {
        for (int c = 0; c < m; c++) {
            double v = 0.0;
            for (int k = r > c ? r : c; k < m; k++) {
                v += l[k * m + r] * l[k * m + c];
            }
            inverse[r * m + c] = v;
        }
    }
    return 1;
}
"#;

/// The filter's init and step: update, covariance and state prediction, the law.
const FILTER_FUNCTIONS: &str = r#"
void tc_init(tc_state *s)
{
    for (int r = 0; r < TC_STATES; r++) {
        s->x_hat[r] = 0.0;
    }
    for (int i = 0; i < TC_STATES * TC_STATES; i++) {
        s->p[i] = 0.0;
    }
    for (int r = 0; r < TC_STATES; r++) {
        s->p[r * TC_STATES + r] = INITIAL_COVARIANCE;
    }
    s->u = 0.0;
}

/* The measurement update with y: Kalman gain from S = C P C^T + R, Joseph's form of the
 * covariance; skipped when S is not positive definite. */
static void update(tc_state *s, const double y[TC_SENSORS])
{
    const int w = TC_STATES, m = TC_SENSORS;
    double innovation[TC_SENSORS], pc[TC_STATES * TC_SENSORS], sm[TC_SENSORS * TC_SENSORS];
    double s_inv[TC_SENSORS * TC_SENSORS], factor[TC_SENSORS * TC_SENSORS];
    double gain[TC_STATES * TC_SENSORS], gain_r[TC_STATES * TC_SENSORS];
    double *keep = s->work[0], *m1 = s->work[1];
    for (int q = 0; q < m; q++) {
        double predicted = 0.0;
        for (int col = 0; col < w; col++) {
            predicted += CM[q][col] * s->x_hat[col];
        }
        innovation[q] = y[q] - predicted;
    }
    multiply_transposed(s->p, &CM[0][0], pc, w, w, m);
    multiply(&CM[0][0], pc, sm, m, w, m);
    for (int i = 0; i < m * m; i++) {
        sm[i] += RN[i];
    }
    if (!invert_spd(sm, m, factor, s_inv)) {
        return;
    }
    multiply(pc, s_inv, gain, w, m, m);
    for (int r = 0; r < w; r++) {
        double dx = 0.0;
        for (int q = 0; q < m; q++) {
            dx += gain[r * m + q] * innovation[q];
        }
        s->x_hat[r] += dx;
    }
    /* keep = I - G C; P = keep P keep^T + G R G^T */
    multiply(gain, &CM[0][0], keep, w, m, w);
    for (int r = 0; r < w; r++) {
        for (int col = 0; col < w; col++) {
            const double identity = r == col ? 1.0 : 0.0;
            keep[r * w + col] = identity - keep[r * w + col];
        }
    }
    multiply(keep, s->p, m1, w, w, w);
    multiply_transposed(m1, keep, s->p, w, w, w);
    multiply(gain, RN, gain_r, w, m, m);
    multiply_transposed(gain_r, gain, m1, w, m, w);
    for (int i = 0; i < w * w; i++) {
        s->p[i] += m1[i];
    }
}

/* The covariance through one period: F = exp(J T) at the estimate, P = F P F^T + Q,
 * symmetrized. */
static void predict_covariance(tc_state *s, double t)
{
    const int w = TC_STATES;
    double *m1 = s->work[0], *m2 = s->work[1], *m3 = s->work[2], *m4 = s->work[3];
    jacobian(t, s->x_hat, m1);
    for (int i = 0; i < w * w; i++) {
        m1[i] *= PERIOD;
    }
    if (!exponential(m1, m2, m3, m4)) {
        return;
    }
    multiply(m2, s->p, m1, w, w, w);
    multiply_transposed(m1, m2, m3, w, w, w);
    for (int r = 0; r < w; r++) {
        for (int col = 0; col < w; col++) {
            s->p[r * w + col] = 0.5 * ((m3[r * w + col] + QN[r * w + col])
                                       + (m3[col * w + r] + QN[col * w + r]));
        }
    }
}

/* The estimate through one period with the force held (classic RK4). */
static void predict_state(tc_state *s, double t)
{
    const double h = PERIOD / (double)SUBSTEPS;
    double y[TC_STATES], k1[TC_STATES], k2[TC_STATES], k3[TC_STATES], k4[TC_STATES];
    double tmp[TC_STATES];
    for (int i = 0; i < TC_STATES; i++) {
        y[i] = s->x_hat[i];
    }
    for (int step = 0; step < SUBSTEPS; step++) {
        const double ts = t + (double)step * h;
        rhs(ts, y, s->u, k1);
        for (int i = 0; i < TC_STATES; i++) {
            tmp[i] = y[i] + 0.5 * h * k1[i];
        }
        rhs(ts + 0.5 * h, tmp, s->u, k2);
        for (int i = 0; i < TC_STATES; i++) {
            tmp[i] = y[i] + 0.5 * h * k2[i];
        }
        rhs(ts + 0.5 * h, tmp, s->u, k3);
        for (int i = 0; i < TC_STATES; i++) {
            tmp[i] = y[i] + h * k3[i];
        }
        rhs(ts + h, tmp, s->u, k4);
        for (int i = 0; i < TC_STATES; i++) {
            y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
    }
    for (int i = 0; i < TC_STATES; i++) {
        s->x_hat[i] = y[i];
    }
}

double tc_step(tc_state *s, double t, const double y[TC_SENSORS], double a)
{
    update(s, y);
    predict_covariance(s, t);
    predict_state(s, t);
    s->u = lqr_force(t, s->x_hat, a);
    return s->u;
}
"#;
