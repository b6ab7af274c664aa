
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
