/* Feeds an emitted setpoint filter the ticks of a machine's clock, built with AddressSanitizer
 * and UBSan by tests/setpoint_filter.rs. Reads lines "t p v a j position" on stdin (t the
 * clock's reading, p v a j the raw setpoint there, position the telescopic position; "nan"
 * and "inf" are read as such) and writes "shaped rejected" per line. The filter's state is
 * static, as its header asks. */
#include "telescopic_setpoint.h"
#include <stdio.h>

static ts_state state;

int main(void)
{
    double t, raw[4], position;
    ts_init(&state);
    while (scanf("%lf %lf %lf %lf %lf %lf", &t, &raw[0], &raw[1], &raw[2], &raw[3], &position)
           == 6) {
        const double shaped = ts_step(&state, t, raw, position);
        printf("%.17g %lu\n", shaped, state.rejected);
    }
    return 0;
}
