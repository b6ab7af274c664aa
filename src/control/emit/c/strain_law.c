
void tc_init(tc_state *s)
{
    s->started = 0;
    s->vehicle_prev = 0.0;
    s->kappa_prev = 0.0;
    s->vehicle_rate = 0.0;
    s->kappa_rate = 0.0;
    s->u = 0.0;
    s->rejected = 0;
}

double tc_step(tc_state *s, double t, const double y[TC_SENSORS], double a)
{
    if (!inputs_are_usable(t, y, a)) {
        s->rejected += 1;
        return s->u;
    }
    const double u = y[VEHICLE];
    const double kappa = y[KAPPA];
    if (s->started) {
        const double v = (u - s->vehicle_prev) / PERIOD;
        const double kappa_dot = (kappa - s->kappa_prev) / PERIOD;
        const double rates[2] = {
            s->vehicle_rate + ALPHA * (v - s->vehicle_rate),
            s->kappa_rate + ALPHA * (kappa_dot - s->kappa_rate),
        };
        /* a finite but absurd measurement that overflows the rates is rejected too */
        if (!all_finite(rates, 2)) {
            s->rejected += 1;
            return s->u;
        }
        s->vehicle_rate = rates[0];
        s->kappa_rate = rates[1];
    }
    s->started = 1;
    s->vehicle_prev = u;
    s->kappa_prev = kappa;
    const double next = t + PERIOD;
    double u_ref, v_ref;
    reference(next, &u_ref, &v_ref);
    int i, j;
    double w;
    weights(a, &i, &j, &w);
    const double gain = GAIN[i] + w * (GAIN[j] - GAIN[i]);
    const double vehicle = KP * (u - u_ref) + KD * (s->vehicle_rate - v_ref);
    const double f = feedforward(next) - vehicle + gain * s->kappa_rate;
    s->u = fmin(fmax(f, -LIMIT), LIMIT);
    return s->u;
}
