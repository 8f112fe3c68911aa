/* Frame-to-edge pairing: a pure module (no I/O, no clock reads) that numbers trigger edges on
 * the global grid, pairs each captured frame with the edge it was exposed on, and keeps the sync
 * health the node reports.
 *
 * Assumptions (also in firmware/README.md):
 * - Clock error budget. A frame number is right when the edge's realtime stamp is within half a
 *   period of its slot. The error is: node clock vs hub clock (chrony on a quiet LAN: < 100 us;
 *   PTP with hardware stamps: < 1 us) + GPIO interrupt-to-stamp latency (< 50 us on a Pi with
 *   the stock kernel) + the mono->realtime offset sample (< 1 us). Edges further than the match
 *   window (pair_window_pct of a period, default 25 %) from any slot are rejected as spurious, so
 *   the budget must stay below window x period: 150 us against 25 % needs period >= 600 us.
 * - Maximum rate: 1000 Hz (period 1 ms, window 250 us) is the supported ceiling; at 60-250 Hz,
 *   usual for marker capture, the margin is 10-30x.
 * - The trigger-to-frame delay (capture stamp minus edge) is constant within the window: V4L2
 *   stamps at start of frame or end of readout depending on the driver, which shifts the delay
 *   but not its jitter. Configure trigger_delay_us per sensor and driver.
 * - Edges arrive no later than the frame they belong to is processed (the node drains the sync
 *   source before pairing a frame); edges are kept for the last MN_PAIRING_EDGES slots. */
#ifndef MN_PAIRING_H
#define MN_PAIRING_H

#include <stdbool.h>
#include <stdint.h>

#include "sync/grid.h"

#define MN_PAIRING_EDGES 64

struct mn_pairing;

struct mn_sync_health {
    uint32_t edge_jitter_ns;   /* RMS deviation of edge intervals from whole periods (EWMA) */
    uint64_t edges;            /* edges accepted onto the grid */
    uint32_t unmatched_frames; /* frames with no edge in their window */
    uint32_t missed_edges;     /* grid slots skipped between accepted edges */
    uint32_t spurious_edges;   /* edges off the grid or doubled within one slot */
};

struct mn_pair_result {
    int64_t frame_number;      /* may be negative: the frame precedes the epoch */
    int64_t trigger_mono_ns;   /* matched edge, or the slot's nominal time when unmatched */
    bool matched;
};

/* window_pct: match window as percent of a period (1..49). Returns NULL with errno set;
 * free with mn_pairing_free. */
struct mn_pairing *mn_pairing_new(const struct mn_grid *grid, int64_t trigger_delay_ns,
                                  uint32_t window_pct);
void mn_pairing_free(struct mn_pairing *p);

/* A new epoch or rate (hub Start) forgets the stored edges; a new clock offset alone keeps
 * them. Health counters are kept either way. */
void mn_pairing_set_grid(struct mn_pairing *p, const struct mn_grid *grid);

/* Feed one trigger edge (monotonic kernel time stamp), in time order. */
void mn_pairing_add_edge(struct mn_pairing *p, int64_t edge_mono_ns);

/* Pair a frame by its capture time stamp. */
void mn_pairing_match(struct mn_pairing *p, int64_t capture_mono_ns, struct mn_pair_result *out);

/* Free-run numbering (no trigger wire): the slot nearest capture time minus the delay. */
void mn_pairing_free_run(const struct mn_pairing *p, int64_t capture_mono_ns,
                         struct mn_pair_result *out);

void mn_pairing_health(const struct mn_pairing *p, struct mn_sync_health *out);

#endif
