/* Feeds the emitted velocity-feedback law one tick per line of stdin ("vehicle kappa a load
 * setpoint setpoint_acceleration", strtod's forms, nan and inf included) and prints each
 * correction with 17 significant digits, then the rejected ticks. */
#include "telescopic_feedback.h"
#include <stdio.h>

int main(void)
{
    static tvf_state law;
    tvf_init(&law);
    double u, kappa, a, load, s, s_acc;
    while (scanf("%lf %lf %lf %lf %lf %lf", &u, &kappa, &a, &load, &s, &s_acc) == 6) {
        printf("%.17g\n", tvf_step(&law, u, kappa, a, load, s, s_acc));
    }
    printf("rejected %lu\n", law.rejected);
    return 0;
}
