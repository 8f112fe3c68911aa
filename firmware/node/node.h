/* The node service: owns every module (capture, sync, pairing, detector, net, control) and runs
 * the one single-threaded poll loop. Buffers are allocated in mn_node_new; the per-frame path
 * allocates nothing. mn_node_step runs one loop iteration so tests can drive a node directly. */
#ifndef MN_NODE_NODE_H
#define MN_NODE_NODE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "node/config.h"
#include "sync/pairing.h"

struct mn_node;

struct mn_node_stats {
    uint64_t frames_captured;   /* frames the source delivered */
    uint64_t frames_processed;  /* frames detected while running */
    uint64_t frames_sent;       /* frames whose every chunk was sent */
    uint64_t frames_dropped;    /* source sequence gaps + frames with an unsent chunk */
    uint64_t frames_before_epoch;
    uint64_t markers_sent;
    uint64_t datagrams_sent, datagrams_dropped;
    uint32_t control_accepted, control_rejected, control_ignored;
    uint32_t auth_rejected;     /* datagrams refused by the envelope: forged, replayed, stale,
                                   unauthenticated, a node's own direction */
    uint32_t auth_other_node;   /* authentic layout but sealed for another node (broadcast) */
    uint32_t camera_errors, camera_reopens;
    bool running;               /* capturing for the hub (Start received or not awaited) */
    bool camera_ok;
    bool hub_known;
    struct mn_sync_health sync;
};

/* Opens everything cfg names. The first camera open must succeed (a bad source refuses to
 * start); later failures are retried with backoff. NULL with errno set and the reason in err;
 * free with mn_node_free. */
struct mn_node *mn_node_new(const struct mn_config *cfg, char *err, size_t errlen);
void mn_node_free(struct mn_node *node);

/* A descriptor whose readability ends the run (a signalfd from main); -1 for none. */
void mn_node_set_stop_fd(struct mn_node *node, int fd);

/* One poll-loop iteration, waiting at most max_wait_ms. 1: keep going; 0: the run is over
 * (frame or time bound reached, recording ended, stop requested); -1: fatal error. */
int mn_node_step(struct mn_node *node, int max_wait_ms);

/* Steps until the run is over; 0 or -1 as mn_node_step. Sends a last status on the way out. */
int mn_node_run(struct mn_node *node);

/* True when the run ended because the trigger chip or a camera that cannot be reopened in this
 * process went away (main exits with 3, "hardware missing", for systemd to restart it). */
bool mn_node_hardware_lost(const struct mn_node *node);

void mn_node_get_stats(const struct mn_node *node, struct mn_node_stats *out);
uint16_t mn_node_local_port(const struct mn_node *node);

#endif
