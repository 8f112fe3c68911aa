/* A log-line budget for messages that outside traffic can trigger at any rate (rejected control
 * datagrams from a chatty host): at most `burst` lines per `interval_ns`, the rest suppressed and
 * counted, and the count handed back once the interval is over so the caller can say how many
 * were left out. Pure: the caller passes the time; nothing here logs or reads a clock. */
#ifndef MN_COMMON_RATELIMIT_H
#define MN_COMMON_RATELIMIT_H

#include <stdbool.h>
#include <stdint.h>

struct mn_ratelimit {
    int64_t interval_ns;
    uint32_t burst;
    int64_t window_start_ns;  /* start of the current interval; 0 before the first event */
    uint32_t used;            /* lines allowed in the current interval */
    uint64_t suppressed;      /* events suppressed since the last report */
};

/* A limiter allowing `burst` lines per `interval_ns` (both > 0). */
void mn_ratelimit_init(struct mn_ratelimit *rl, int64_t interval_ns, uint32_t burst);

/* One event at now_ns: true when its line may be logged. *suppressed_before gets the number of
 * events suppressed in earlier intervals that nobody has been told of yet (0 mostly); the caller
 * logs that count before its own line. */
bool mn_ratelimit_allow(struct mn_ratelimit *rl, int64_t now_ns, uint64_t *suppressed_before);

/* The suppressed events not yet reported, when the interval they fell in is over (for a caller
 * that reports on a timer, so a burst's count is not held until the next event); 0 otherwise. */
uint64_t mn_ratelimit_flush(struct mn_ratelimit *rl, int64_t now_ns);

#endif
