
void tc_init(tc_state *s)
{
    for (int r = 0; r < TC_STATES; r++) {
        s->x_hat[r] = 0.0;
    }
    s->u = 0.0;
    s->rejected = 0;
}

double tc_step(tc_state *s, double t, const double y[TC_SENSORS], double a)
{
    if (!inputs_are_usable(t, y, a)) {
        s->rejected += 1;
        return s->u;
    }
    int i, j;
    double w;
    weights(a, &i, &j, &w);
    /* the filter runs on the nearest design point's discrete model */
    const int near = w < 0.5 ? i : j;
    double innovation[TC_SENSORS];
    for (int q = 0; q < TC_SENSORS; q++) {
        double predicted = 0.0;
        for (int c = 0; c < TC_STATES; c++) {
            predicted += CM[near][q][c] * s->x_hat[c];
        }
        innovation[q] = y[q] - predicted;
    }
    double next_x[TC_STATES];
    for (int r = 0; r < TC_STATES; r++) {
        double v = 0.0;
        for (int c = 0; c < TC_STATES; c++) {
            v += AD[near][r][c] * s->x_hat[c];
        }
        v += BD[near][r] * s->u;
        for (int q = 0; q < TC_SENSORS; q++) {
            v += LK[near][r][q] * innovation[q];
        }
        next_x[r] = v;
    }
    /* a finite but absurd measurement that overflows the estimate is rejected too */
    if (!all_finite(next_x, TC_STATES)) {
        s->rejected += 1;
        return s->u;
    }
    for (int r = 0; r < TC_STATES; r++) {
        s->x_hat[r] = next_x[r];
    }
    s->u = lqr_force(t, s->x_hat, a);
    return s->u;
}
