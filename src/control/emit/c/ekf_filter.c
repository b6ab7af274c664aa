
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
    s->rejected = 0;
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
    if (!inputs_are_usable(t, y, a)) {
        s->rejected += 1;
        return s->u;
    }
    /* kept to undo a tick whose finite but absurd measurement overflows the estimate */
    double x_kept[TC_STATES];
    double p_kept[TC_STATES * TC_STATES];
    for (int k = 0; k < TC_STATES * TC_STATES; k++) {
        p_kept[k] = s->p[k];
    }
    for (int k = 0; k < TC_STATES; k++) {
        x_kept[k] = s->x_hat[k];
    }
    update(s, y);
    predict_covariance(s, t);
    predict_state(s, t);
    if (!all_finite(s->x_hat, TC_STATES) || !all_finite(s->p, TC_STATES * TC_STATES)) {
        for (int k = 0; k < TC_STATES * TC_STATES; k++) {
            s->p[k] = p_kept[k];
        }
        for (int k = 0; k < TC_STATES; k++) {
            s->x_hat[k] = x_kept[k];
        }
        s->rejected += 1;
        return s->u;
    }
    s->u = lqr_force(t, s->x_hat, a);
    return s->u;
}
