/* Clock helpers. The node keeps every internal time stamp in CLOCK_MONOTONIC nanoseconds (what
 * V4L2 buffers and GPIO edge events carry) and converts to CLOCK_REALTIME (disciplined to the
 * hub by chrony/PTP) only where the wire or the global frame numbering needs hub time. */
#ifndef MN_COMMON_CLOCK_H
#define MN_COMMON_CLOCK_H

#include <stdint.h>
#include <time.h>

#define MN_NS_PER_SEC INT64_C(1000000000)

int64_t mn_clock_mono_ns(void);
int64_t mn_clock_real_ns(void);

/* realtime - monotonic, sampled with the realtime read bracketed by two monotonic reads so the
 * offset error is at most half the bracketing interval (well under a microsecond normally). */
int64_t mn_clock_real_minus_mono_ns(void);

int64_t mn_timespec_to_ns(const struct timespec *ts);
struct timespec mn_ns_to_timespec(int64_t ns);

#endif
