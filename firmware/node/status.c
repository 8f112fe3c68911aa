/* NodeStatus assembly and temperature reading (see status.h). */
#include "node/status.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "node/version.h"

int mn_status_read_temperature(const char *path, int32_t *mdeg)
{
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return -1;
    char buf[32];
    ssize_t n = read(fd, buf, sizeof(buf) - 1);
    int e = errno;
    close(fd);
    if (n <= 0) {
        errno = n < 0 ? e : EINVAL;
        return -1;
    }
    buf[n] = '\0';
    char *end;
    errno = 0;
    long v = strtol(buf, &end, 10);
    /* Thermal zones print one integer and a newline; reject anything else and absurd values. */
    if (errno != 0 || end == buf || (*end != '\n' && *end != '\0') || v < -100000 || v > 200000) {
        errno = EINVAL;
        return -1;
    }
    *mdeg = (int32_t)v;
    return 0;
}

static uint32_t clamp_u32(uint64_t v)
{
    return v > UINT32_MAX ? UINT32_MAX : (uint32_t)v;
}

void mn_status_build(const struct mn_status_counters *c, const char *temperature_path,
                     mocap_v1_Packet *packet)
{
    *packet = (mocap_v1_Packet)mocap_v1_Packet_init_zero;
    packet->version = MN_WIRE_VERSION;
    packet->which_body = mocap_v1_Packet_node_status_tag;
    mocap_v1_NodeStatus *s = &packet->body.node_status;
    s->node_id = c->node_id;
    s->state = c->state;
    snprintf(s->firmware_version, sizeof(s->firmware_version), "%s", MN_VERSION);
    s->uptime_ms = c->uptime_ms;
    if (c->interval_ns > 0)
        s->fps_milli = clamp_u32(c->interval_frames * UINT64_C(1000000000000) /
                                 (uint64_t)c->interval_ns);
    if (c->detect_count > 0) {
        s->detect_time_us_mean = clamp_u32(c->detect_ns_sum / c->detect_count / 1000);
        s->detect_time_us_max = clamp_u32(c->detect_ns_max / 1000);
    }
    s->frames_captured = c->frames_captured;
    s->frames_sent = c->frames_sent;
    s->frames_dropped = c->frames_dropped;
    s->has_sync = true;
    s->sync.edge_jitter_ns = c->sync.edge_jitter_ns;
    s->sync.unmatched_frames = c->sync.unmatched_frames;
    s->sync.missed_edges = c->sync.missed_edges;
    s->sync.spurious_edges = c->sync.spurious_edges;
    int32_t mdeg;
    if (temperature_path != NULL && temperature_path[0] != '\0' &&
        mn_status_read_temperature(temperature_path, &mdeg) == 0) {
        s->has_temperature = true;
        s->temperature_mdeg = mdeg;
    }
    s->threshold = c->threshold;
    s->exposure_us = c->exposure_us;
    s->gain_milli = c->gain_milli;
    s->exposure_fixed = c->exposure_fixed;
    s->control_rejected = c->control_rejected;
    s->auth_rejected = c->auth_rejected;
    s->camera_reopens = c->camera_reopens;
    s->width = c->width;
    s->height = c->height;
}
