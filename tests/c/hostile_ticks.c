/* Hostile ticks for an emitted controller, built with AddressSanitizer and UBSan by
 * tests/control.rs: two controllers run the same ticks, one of them with a NaN, an infinite
 * and a 1e308 measurement, infinite times, a NaN position and a time far out among them.
 * Checked: every force finite and within the limit, each bad tick rejected (the previous
 * force returned, counted), and the controller not stuck at a limit afterwards.
 * Usage: hostile_ticks PERIOD POSITION LIMIT; prints "ok" or what failed (exit 1). */
#include "telescopic_controller.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define TICKS 400

static int failures = 0;

static void check(int ok, const char *what, int k)
{
    if (!ok) {
        fprintf(stderr, "tick %d: %s\n", k, what);
        failures++;
    }
}

int main(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "usage: hostile_ticks PERIOD POSITION LIMIT\n");
        return 2;
    }
    const double period = atof(argv[1]);
    const double position = atof(argv[2]);
    const double limit = atof(argv[3]);
    tc_state clean, hit;
    tc_init(&clean);
    tc_init(&hit);
    double previous = 0.0;
    unsigned long bad = 0;
    int away_from_limits = 0;
    for (int k = 0; k < TICKS; k++) {
        double t = k * period;
        double y[TC_SENSORS];
        for (int q = 0; q < TC_SENSORS; q++) {
            y[q] = 1e-3 * sin(0.05 * k + q);
        }
        const double f_clean = tc_step(&clean, t, y, position);
        double a = position;
        double t_hit = t;
        int rejected = 1;
        switch (k) {
        case 50: y[0] = NAN; break;
        case 60: t_hit = INFINITY; break;
        case 70: a = NAN; break;
        case 80: y[TC_SENSORS - 1] = -INFINITY; break;
        case 90: t_hit = -INFINITY; break;
        case 110: y[0] = 1e308; break;  /* finite, but overflows an estimate or a rate */
        default: rejected = 0; break;
        }
        if (k == 100) {
            t_hit = 1e300; /* finite, far beyond every table: used, must not misbehave */
        }
        const double f = tc_step(&hit, t_hit, y, a);
        bad += rejected;
        check(isfinite(f_clean) && fabs(f_clean) <= limit, "clean force out of range", k);
        check(isfinite(f) && fabs(f) <= limit, "force out of range", k);
        check(hit.rejected == bad, "rejections miscounted", k);
        if (rejected) {
            check(f == previous, "a rejected tick changed the force", k);
        }
        if (k > 150 && fabs(f) < limit) {
            away_from_limits++;
        }
        previous = f;
    }
    check(away_from_limits > 0, "stuck at the force limit after the bad ticks", TICKS);
    if (failures > 0) {
        return 1;
    }
    printf("ok\n");
    return 0;
}
