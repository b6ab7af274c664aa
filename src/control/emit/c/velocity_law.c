
void tvf_init(tvf_state *s)
{
    s->started = 0;
    s->tip = 0.0;
    s->rate = 0.0;
    s->bias = 0.0;
    s->setpoint_acceleration = 0.0;
    s->acceleration = 0.0;
    s->last = 0.0;
    s->rejected = 0;
}

/* The entries of the ascending table x[0..count) around v and the weight of the second:
 * the first (last) entry below (above) the table, one entry alone everywhere. */
static void bracket(const double *x, int count, double v, int *i, int *j, double *w)
{
    const int last = count - 1;
    *i = 0;
    *j = 0;
    *w = 0.0;
    if (last == 0 || v <= x[0]) {
        return;
    }
    if (v >= x[last]) {
        *i = last;
        *j = last;
        return;
    }
    int k = 0;
    while (k < count && x[k] <= v) {
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
    *w = (v - x[k - 1]) / (x[k] - x[k - 1]);
}

/* A table's value at position weight w between points i and j, at load weight w_load between
 * the tables low and high: along the position in each table, then between the tables. */
static double scheduled(const double table[TVF_LOADS][TVF_POINTS], int low, int high,
                        double w_load, int i, int j, double w)
{
    const double at_low = table[low][i] + w * (table[low][j] - table[low][i]);
    const double at_high = table[high][i] + w * (table[high][j] - table[high][i]);
    return at_low + w_load * (at_high - at_low);
}

/* The gains that place the poles at a first mode of f1 Hz with tip per curvature r and
 * curvature per acceleration c: k on the vehicle's error, the correction's velocity, the
 * mode's departure and its rate; l of the observer; omega and Gamma of the mode. */
typedef struct {
    double omega, gamma;
    double k1, k2, k3, k4;
    double l1, l2, l3;
} tvf_gains;

static tvf_gains place(double f1, double r, double c)
{
    tvf_gains g;
    const double w = 6.283185307179586 * f1;
    const double w2 = w * w;
    g.omega = w;
    g.gamma = -r * c * w2;
    /* (s^2 + 2 zeta w s + w^2)(s + p1 w)(s + p2 w) */
    const double a1 = 2.0 * ZETA * w;
    const double p1 = VEHICLE_POLE_1 * w;
    const double p2 = VEHICLE_POLE_2 * w;
    const double b1 = p1 + p2;
    const double b0 = p1 * p2;
    const double d3 = a1 + b1;
    const double d2 = w2 + a1 * b1 + b0;
    const double d1 = a1 * b0 + w2 * b1;
    const double d0 = w2 * b0;
    g.k1 = d0 / w2;
    g.k2 = d1 / w2;
    g.k3 = (g.k1 + w2 - d2) / g.gamma;
    g.k4 = (g.k2 - d3) / g.gamma;
    /* the observer: (s^2 + 2 zeta_o w_o s + w_o^2)(s + p_b w) */
    const double wo = OBSERVER_FREQUENCY * w;
    const double pb = OBSERVER_BIAS_POLE * w;
    const double e2 = 2.0 * OBSERVER_ZETA * wo + pb;
    const double e1 = wo * wo + 2.0 * OBSERVER_ZETA * wo * pb;
    const double e0 = wo * wo * pb;
    g.l3 = e0 / w2;
    g.l1 = e2 - g.l3;
    g.l2 = e1 - w2;
    return g;
}

double tvf_step(tvf_state *s, double vehicle, double kappa, double a, double load,
                double setpoint, double setpoint_acceleration)
{
    if (!isfinite(load)) {
        s->rejected += 1;
        return s->last;
    }
    int i, j, low, high;
    double w, w_load;
    bracket(POSITIONS, TVF_POINTS, a, &i, &j, &w);
    bracket(LOADS, TVF_LOADS, load, &low, &high, &w_load);
    const double f1 = scheduled(FIRST_MODE, low, high, w_load, i, j, w);
    const double r = scheduled(TIP_PER_CURVATURE, low, high, w_load, i, j, w);
    const double c = scheduled(CURVATURE, low, high, w_load, i, j, w);
    const tvf_gains g = place(f1, r, c);
    const double measured = r * kappa;
    double tip = 0.0, rate = 0.0, bias = measured, jerk = 0.0;
    if (s->started) {
        /* the observer over the last tick, the base accelerated by the setpoint and the
         * correction */
        const double base = setpoint_acceleration + s->acceleration;
        const double innovation = measured - (s->tip + s->bias);
        tip = s->tip + PERIOD * (s->rate + g.l1 * innovation);
        rate = s->rate + PERIOD * (-g.omega * g.omega * s->tip - g.gamma * base + g.l2 * innovation);
        bias = s->bias + PERIOD * g.l3 * innovation;
        jerk = (setpoint_acceleration - s->setpoint_acceleration) / PERIOD;
    }
    /* the mode's departure from the bending the setpoint's own acceleration causes */
    const double quasi_static = r * c;
    const double departure = tip - quasi_static * setpoint_acceleration;
    const double departure_rate = rate - quasi_static * jerk;
    const double wanted = -(g.k1 * (vehicle - setpoint) + g.k2 * s->last + g.k3 * departure
                            + g.k4 * departure_rate);
    if (!(isfinite(wanted) && isfinite(tip) && isfinite(rate) && isfinite(bias))) {
        /* a non-finite input, or one that overflows: the last command holds, the state too */
        s->rejected += 1;
        return s->last;
    }
    s->started = 1;
    s->tip = tip;
    s->rate = rate;
    s->bias = bias;
    s->setpoint_acceleration = setpoint_acceleration;
    const double acceleration = fmin(fmax(wanted, -ACCELERATION_LIMIT), ACCELERATION_LIMIT);
    const double v = fmin(fmax(s->last + acceleration * PERIOD, -VELOCITY_LIMIT), VELOCITY_LIMIT);
    s->acceleration = (v - s->last) / PERIOD;
    s->last = v;
    return v;
}
