
/* The feedforward force at t: the value of the last step at or before t. */
static double feedforward(double t)
{
    int i = 0;
    while (i < FF_COUNT && FF_TIMES[i] <= t) {
        i++;
    }
    return FF_VALUES[i > 0 ? i - 1 : 0];
}

/* The rigid reference position and speed at t. */
static void reference(double t, double *u_ref, double *v_ref)
{
    int i = 0;
    while (i < REF_COUNT && REF_T[i] <= t) {
        i++;
    }
    i = i > 0 ? i - 1 : 0;
    double h = t - REF_T[i];
    if (h < 0.0) {
        h = 0.0;
    }
    *u_ref = REF_U[i] + REF_V[i] * h + 0.5 * REF_A[i] * h * h;
    *v_ref = REF_V[i] + REF_A[i] * h;
}

/* The design points around a and the weight of the second. */
static void weights(double a, int *i, int *j, double *w)
{
    const int last = TC_POINTS - 1;
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
    while (k < TC_POINTS && POSITIONS[k] <= a) {
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

/* Largest magnitude of a measurement (SI units): no reading of a crane's position, curvature,
   acceleration or strain comes near it, and a filter's state stays far from overflow. */
static const double MEASUREMENT_BOUND = 1e6;

/* Whether a tick's inputs can be used: the time and the position finite, every measurement
   finite and within MEASUREMENT_BOUND. A tick that fails this is rejected by tc_step (state
   held, force repeated, counted). */
static int inputs_are_usable(double t, const double y[TC_SENSORS], double a)
{
    if (!isfinite(t) || !isfinite(a)) {
        return 0;
    }
    for (int q = 0; q < TC_SENSORS; q++) {
        if (!(fabs(y[q]) <= MEASUREMENT_BOUND)) {
            return 0;
        }
    }
    return 1;
}

/* Whether the n values of v are all finite. */
static int all_finite(const double *v, int n)
{
    for (int k = 0; k < n; k++) {
        if (!isfinite(v[k])) {
            return 0;
        }
    }
    return 1;
}
