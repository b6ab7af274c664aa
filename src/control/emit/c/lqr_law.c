
/* The saturated LQR force for the next tick after t on the estimate x, at position a. */
static double lqr_force(double t, const double x[TC_STATES], double a)
{
    int i, j;
    double w;
    weights(a, &i, &j, &w);
    const double next = t + PERIOD;
    double u_ref, v_ref;
    reference(next, &u_ref, &v_ref);
    double feedback = 0.0;
    for (int q = 0; q < TC_STATES; q++) {
        double e;
        if (q == 0) {
            e = x[0] - u_ref;
        } else if (q == TC_STATES / 2) {
            e = x[q] - v_ref;
        } else {
            e = x[q];
        }
        const double gain = K[i][q] + w * (K[j][q] - K[i][q]);
        feedback += gain * e;
    }
    const double f = feedforward(next) - feedback;
    return fmin(fmax(f, -LIMIT), LIMIT);
}
