/* Node status: the counters the loop keeps, turned into a NodeStatus datagram, and the board
 * temperature read from /sys/class/thermal where it is readable. */
#ifndef MN_NODE_STATUS_H
#define MN_NODE_STATUS_H

#include <stdbool.h>
#include <stdint.h>

#include "sync/pairing.h"
#include "wire/wire.h"

struct mn_status_counters {
    uint32_t node_id;
    mocap_v1_NodeState state;
    uint64_t uptime_ms;
    uint64_t frames_captured, frames_sent, frames_dropped;
    /* Over the last status interval: */
    uint64_t interval_frames;
    int64_t interval_ns;
    uint64_t detect_ns_sum, detect_ns_max, detect_count;
    struct mn_sync_health sync;
    uint32_t threshold, exposure_us, gain_milli;
    bool exposure_fixed; /* the source has no exposure or gain to set (a recording) */
    uint32_t control_rejected, camera_reopens, auth_rejected;
    uint32_t width, height;
};

/* Reads a thermal zone file (millidegrees Celsius as text). 0, or -1 with errno set. */
int mn_status_read_temperature(const char *path, int32_t *mdeg);

/* Builds the NodeStatus packet; temperature_path NULL or unreadable: has_temperature false. */
void mn_status_build(const struct mn_status_counters *c, const char *temperature_path,
                     mocap_v1_Packet *packet);

#endif
