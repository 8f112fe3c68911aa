/* Global frame-number grid arithmetic (see grid.h). */
#include "sync/grid.h"

#include <math.h>

#define PS_PER_SEC_MILLI ((__int128)1000000000000) /* ns per second x 1000 (millihertz) */

/* Round-half-away-from-zero division, correct for negative numerators. */
static __int128 div_round(__int128 num, __int128 den)
{
    if (num >= 0)
        return (num + den / 2) / den;
    return -((-num + den / 2) / den);
}

int64_t mn_grid_slot(const struct mn_grid *g, int64_t t_mono_ns)
{
    __int128 dt = (__int128)t_mono_ns + g->real_minus_mono_ns - g->epoch_real_ns;
    return (int64_t)div_round(dt * g->rate_millihz, PS_PER_SEC_MILLI);
}

int64_t mn_grid_slot_mono(const struct mn_grid *g, int64_t slot)
{
    __int128 off = div_round((__int128)slot * PS_PER_SEC_MILLI, g->rate_millihz);
    return (int64_t)((__int128)g->epoch_real_ns + off - g->real_minus_mono_ns);
}

int64_t mn_grid_period_ns(const struct mn_grid *g)
{
    return (int64_t)div_round(PS_PER_SEC_MILLI, g->rate_millihz);
}

uint32_t mn_grid_rate_millihz(double rate_hz)
{
    return (uint32_t)lround(rate_hz * 1000.0);
}
