
void tvf_init(tvf_state *s)
{
    s->started = 0;
    s->departure = 0.0;
    s->washed = 0.0;
    s->last = 0.0;
    s->rejected = 0;
}

/* The design points around the scheduled position a and the weight between them: the
 * first (last) point below (above) the table, one point alone everywhere. */
static void bracket(double a, int *i, int *j, double *w)
{
    const int last = TVF_POINTS - 1;
    *i = 0;
    *j = 0;
    *w = 0.0;
    if (last == 0 || a <= POSITIONS[0]) {
        return;
    }
    if (a >= POSITIONS[last]) {
        *i = last;
        *j = last;
        return;
    }
    int k = 0;
    while (k < TVF_POINTS && POSITIONS[k] <= a) {
        k++;
    }
    if (k < 1) {
        k = 1;
    }
    if (k > last) {
        k = last;
    }
    *i = k - 1;
    *j = k;
    *w = (a - POSITIONS[k - 1]) / (POSITIONS[k] - POSITIONS[k - 1]);
}

double tvf_step(tvf_state *s, double vehicle, double kappa, double a, double setpoint,
                double setpoint_acceleration)
{
    int i, j;
    double w;
    bracket(a, &i, &j, &w);
    const double gain = GAIN[i] + w * (GAIN[j] - GAIN[i]);
    const double c = CURVATURE[i] + w * (CURVATURE[j] - CURVATURE[i]);
    /* the departure from the quasi-static bending of the setpoint's acceleration, washed out */
    const double departure = kappa - c * setpoint_acceleration;
    const double washed = s->started ? WASHOUT * (s->washed + departure - s->departure) : 0.0;
    const double wanted = gain * washed - KP * (vehicle - setpoint);
    if (!isfinite(wanted)) {
        /* a non-finite input, or one that overflows: the last command holds, the state too */
        s->rejected += 1;
        return s->last;
    }
    s->started = 1;
    s->departure = departure;
    s->washed = washed;
    double v = fmin(fmax(wanted, -VELOCITY_LIMIT), VELOCITY_LIMIT);
    v = fmin(fmax(v, s->last - STEP), s->last + STEP);
    s->last = v;
    return v;
}
