
/* ---- fixed part: the same for every plan ---- */

/* The Fritsch-Butland slope of the period at knot k: zero at the ends and at an extremum,
 * else the harmonic mean of the neighbouring secants. */
static double knot_slope(int k)
{
    double a, b;
    if (k == 0 || k == TS_KNOTS - 1) {
        return 0.0;
    }
    a = (TS_KNOT_PERIODS[k] - TS_KNOT_PERIODS[k - 1])
        / (TS_KNOT_POSITIONS[k] - TS_KNOT_POSITIONS[k - 1]);
    b = (TS_KNOT_PERIODS[k + 1] - TS_KNOT_PERIODS[k])
        / (TS_KNOT_POSITIONS[k + 1] - TS_KNOT_POSITIONS[k]);
    if (a * b <= 0.0) {
        return 0.0;
    }
    return 2.0 * a * b / (a + b);
}

/* The monotone cubic through (TS_KNOT_POSITIONS, TS_KNOT_PERIODS) at x: Hermite pieces with
 * Fritsch-Butland slopes (zero at the ends and at an extremum), constant outside. */
static double monotone_cubic(double x)
{
    const int n = TS_KNOTS;
    int i = 0;
    double h, u, m0, m1;
    while (i < n && TS_KNOT_POSITIONS[i] <= x) {
        i++;
    }
    if (i == 0) {
        return TS_KNOT_PERIODS[0];
    }
    if (i == n) {
        return TS_KNOT_PERIODS[n - 1];
    }
    h = TS_KNOT_POSITIONS[i] - TS_KNOT_POSITIONS[i - 1];
    m0 = knot_slope(i - 1);
    m1 = knot_slope(i);
    u = (x - TS_KNOT_POSITIONS[i - 1]) / h;
    return (1.0 + 2.0 * u) * (1.0 - u) * (1.0 - u) * TS_KNOT_PERIODS[i - 1]
        + u * (1.0 - u) * (1.0 - u) * h * m0
        + u * u * (3.0 - 2.0 * u) * TS_KNOT_PERIODS[i]
        + u * u * (u - 1.0) * h * m1;
}

/* The stretch factor at t (s): TS_STRETCH[0] before TS_OVER[0], TS_STRETCH[1] after TS_OVER[1],
 * a quintic smoothstep between. */
static double stretch_factor(double t)
{
    const double span = TS_OVER[1] - TS_OVER[0];
    double u, s;
    if (t <= TS_OVER[0] || span <= 0.0) {
        return TS_STRETCH[0];
    }
    if (t >= TS_OVER[1]) {
        return TS_STRETCH[1];
    }
    u = (t - TS_OVER[0]) / span;
    s = u * u * u * (10.0 + u * (-15.0 + 6.0 * u));
    return TS_STRETCH[0] + (TS_STRETCH[1] - TS_STRETCH[0]) * s;
}

/* The raw setpoint (m) at tau, from the samples around it: the cubic of the constant jerk
 * from the sample before tau, or, past a jerk switch inside the tick, back from the sample
 * after it. Before the first sample, the first position (at rest); at or after the newest
 * sample, its value extrapolated (not reached for delays of at least one tick). */
static double raw_at(const ts_state *s, double tau)
{
    const ts_sample *first = &s->history[(s->newest + 1 + TS_HISTORY - s->count) % TS_HISTORY];
    const ts_sample *newest = &s->history[s->newest];
    const ts_sample *before, *after;
    long back;
    double d, switch_time;
    if (tau <= first->t) {
        return first->p;
    }
    if (tau >= newest->t) {
        d = tau - newest->t;
        return newest->p + newest->v * d + newest->a * d * d / 2.0 + newest->j * d * d * d / 6.0;
    }
    back = (long)ceil((newest->t - tau) / TS_PERIOD);
    if (back < 1) {
        back = 1;
    }
    if (back > s->count - 1) {
        back = s->count - 1;
    }
    before = &s->history[(s->newest + TS_HISTORY - back) % TS_HISTORY];
    after = &s->history[(s->newest + TS_HISTORY - back + 1) % TS_HISTORY];
    /* rounding of the division: step to the tick that holds tau */
    while (before->t > tau && back < s->count - 1) {
        back++;
        after = before;
        before = &s->history[(s->newest + TS_HISTORY - back) % TS_HISTORY];
    }
    while (after->t <= tau && back > 1) {
        back--;
        before = after;
        after = &s->history[(s->newest + TS_HISTORY - back + 1) % TS_HISTORY];
    }
    switch_time = after->t;
    if (before->j != after->j) {
        switch_time = before->t
            + (after->a - before->a - after->j * (after->t - before->t)) / (before->j - after->j);
    }
    if (tau <= switch_time) {
        d = tau - before->t;
        return before->p + before->v * d + before->a * d * d / 2.0 + before->j * d * d * d / 6.0;
    }
    d = tau - after->t;
    return after->p + after->v * d + after->a * d * d / 2.0 + after->j * d * d * d / 6.0;
}

void ts_init(ts_state *s)
{
    s->count = 0;
    s->newest = TS_HISTORY - 1;
    s->rejected = 0;
    s->shaped = 0.0;
}

double ts_step(ts_state *s, double t, const double raw[4], double position)
{
    const ts_sample *newest = &s->history[s->newest];
    double period, shaped = 0.0;
    int i;
    int finite = isfinite(t) && isfinite(position);
    for (i = 0; i < 4; i++) {
        finite = finite && isfinite(raw[i]);
    }
    /* a tick must come at least half a period after the last accepted one: a repeated or
     * early tick is refused, a late, jittered or skipped one taken (the history is read by
     * its times, not by its count); the difference of two times stays exact to the clock's
     * resolution for any start time a double can hold to a tenth of the period */
    if (!finite || (s->count > 0 && !(t - newest->t >= 0.5 * TS_PERIOD))) {
        s->rejected++;
        return s->shaped;
    }
    s->newest = (s->newest + 1) % TS_HISTORY;
    s->history[s->newest].t = t;
    s->history[s->newest].p = raw[0];
    s->history[s->newest].v = raw[1];
    s->history[s->newest].a = raw[2];
    s->history[s->newest].j = raw[3];
    if (s->count < TS_HISTORY) {
        s->count++;
    }
    period = monotone_cubic(position) * stretch_factor(t);
    for (i = 0; i < TS_IMPULSES; i++) {
        shaped += TS_AMPLITUDES[i] * raw_at(s, t - TS_MULTIPLES[i] * period);
    }
    s->shaped = shaped;
    return shaped;
}
