#include "common/ratelimit.h"

void mn_ratelimit_init(struct mn_ratelimit *rl, int64_t interval_ns, uint32_t burst)
{
    rl->interval_ns = interval_ns > 0 ? interval_ns : 1;
    rl->burst = burst > 0 ? burst : 1;
    rl->window_start_ns = 0;
    rl->used = 0;
    rl->suppressed = 0;
}

static bool window_over(const struct mn_ratelimit *rl, int64_t now_ns)
{
    return rl->window_start_ns == 0 || now_ns - rl->window_start_ns >= rl->interval_ns;
}

bool mn_ratelimit_allow(struct mn_ratelimit *rl, int64_t now_ns, uint64_t *suppressed_before)
{
    *suppressed_before = 0;
    if (window_over(rl, now_ns)) {
        *suppressed_before = rl->suppressed;
        rl->suppressed = 0;
        rl->window_start_ns = now_ns;
        rl->used = 0;
    }
    if (rl->used < rl->burst) {
        rl->used++;
        return true;
    }
    rl->suppressed++;
    return false;
}

uint64_t mn_ratelimit_flush(struct mn_ratelimit *rl, int64_t now_ns)
{
    if (rl->suppressed == 0 || !window_over(rl, now_ns))
        return 0;
    uint64_t n = rl->suppressed;
    rl->suppressed = 0;
    return n;
}
