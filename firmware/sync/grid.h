/* The global frame-number grid of DESIGN.md: frame n is the trigger at epoch + n / rate
 * (CLOCK_REALTIME, disciplined to the hub). Pure integer arithmetic (128-bit intermediates), so
 * every node computes the same number for the same edge, and the replay and simulated-trigger
 * backends place their frames and edges on exactly the slots the pairing expects. */
#ifndef MN_GRID_H
#define MN_GRID_H

#include <stdint.h>

struct mn_grid {
    int64_t epoch_real_ns;       /* CLOCK_REALTIME of global frame 0 */
    uint32_t rate_millihz;       /* trigger rate; 100 (0.1 Hz) .. 1000000 (1 kHz) */
    int64_t real_minus_mono_ns;  /* this node's clock offset (see common/clock.h) */
};

/* round((t_real - epoch) * rate) for a monotonic time stamp; may be negative (before epoch). */
int64_t mn_grid_slot(const struct mn_grid *g, int64_t t_mono_ns);

/* Monotonic time of slot n's trigger. */
int64_t mn_grid_slot_mono(const struct mn_grid *g, int64_t slot);

/* One trigger period in ns (rounded). */
int64_t mn_grid_period_ns(const struct mn_grid *g);

/* Hz to millihertz, rounded; the config range 0.1..1000 Hz keeps it within the grid's range. */
uint32_t mn_grid_rate_millihz(double rate_hz);

#endif
