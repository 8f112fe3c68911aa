/* Clock helpers over clock_gettime; see clock.h for the time-domain convention. */
#include "common/clock.h"

int64_t mn_timespec_to_ns(const struct timespec *ts)
{
    return (int64_t)ts->tv_sec * MN_NS_PER_SEC + ts->tv_nsec;
}

struct timespec mn_ns_to_timespec(int64_t ns)
{
    struct timespec ts;
    ts.tv_sec = (time_t)(ns / MN_NS_PER_SEC);
    ts.tv_nsec = (long)(ns % MN_NS_PER_SEC);
    if (ts.tv_nsec < 0) {
        ts.tv_nsec += MN_NS_PER_SEC;
        ts.tv_sec -= 1;
    }
    return ts;
}

int64_t mn_clock_mono_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return mn_timespec_to_ns(&ts);
}

int64_t mn_clock_real_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return mn_timespec_to_ns(&ts);
}

int64_t mn_clock_real_minus_mono_ns(void)
{
    /* Keep the tightest of a few brackets: a preemption between the reads would otherwise
     * leak straight into every converted time stamp. */
    int64_t best_width = INT64_MAX;
    int64_t best_offset = 0;
    for (int i = 0; i < 5; i++) {
        int64_t m0 = mn_clock_mono_ns();
        int64_t r = mn_clock_real_ns();
        int64_t m1 = mn_clock_mono_ns();
        if (m1 - m0 < best_width) {
            best_width = m1 - m0;
            best_offset = r - (m0 + (m1 - m0) / 2);
        }
    }
    return best_offset;
}
