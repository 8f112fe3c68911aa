/* mocap stream client: receives the live 3D stream of `mocap-hub serve` (proto/mocap_stream.proto)
 * over UDP, by subscription or from a multicast group. C11, POSIX sockets, nanopb; no C++.
 *
 *   mocap_stream_client *c;
 *   mocap_stream_point points[512];
 *   mocap_stream_frame frame = {.points = points, .point_capacity = 512};
 *   if (mocap_stream_open(&c, "192.168.10.1", 7802, MOCAP_STREAM_POINTS) == 0) {
 *       while (mocap_stream_receive(c, &frame, 1000) >= 0) { ... frame.point_count ... }
 *       mocap_stream_close(c);
 *   }
 *
 * A subscription lasts 5 s on the hub; mocap_stream_receive renews it every second, so call it
 * at least that often. The hub answers the first request with a challenge (a cookie that proves
 * this address); mocap_stream_receive sends it back and frames flow from then on. Units: millimetres, world frame; times: ns since the Unix epoch.
 * Thread safety: one client per thread. */
#ifndef MOCAP_STREAM_CLIENT_H
#define MOCAP_STREAM_CLIENT_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

enum {
    MOCAP_STREAM_POINTS = 1,
    MOCAP_STREAM_BODIES = 2,
    MOCAP_STREAM_LABELS = 4,
};

typedef struct {
    float x, y, z;              /* mm */
    float residual_px;          /* reprojection RMS over its views */
    uint32_t views;
    int32_t marker;             /* confirmed marker, 1-based; 0 when provisional */
    uint64_t provisional_track; /* tentative track's serial; 0 for none */
    char label[64];             /* name once labelled, else "" */
} mocap_stream_point;

typedef struct {
    uint32_t id;
    char name[64];
    int tracked;                /* fitted to this frame's points */
    int predicted;              /* not seen: pose predicted through a short occlusion */
    uint32_t markers;           /* markers fitted */
    float x, y, z;              /* mm */
    float qx, qy, qz, qw;       /* body -> world */
    float mean_error_mm;
} mocap_stream_body;

typedef struct {
    uint64_t frame_number;
    uint64_t trigger_time_ns;   /* trigger edge on the session clock; 0 if unknown */
    uint64_t publish_time_ns;   /* the hub had the result */
    uint32_t cameras;
    uint32_t parts;             /* MOCAP_STREAM_* bits this frame carries */
    uint32_t points_dropped;    /* left out by the hub to fit its datagram */
    /* The caller's arrays; *_count are the entries filled, *_total those in the message
     * (more than the capacity: the rest were skipped). */
    mocap_stream_point *points;
    size_t point_capacity, point_count, points_total;
    mocap_stream_body *bodies;
    size_t body_capacity, body_count, bodies_total;
} mocap_stream_frame;

typedef struct mocap_stream_client mocap_stream_client;

/* Subscribes to the hub's stream at host:port (numeric IPv4 or a name) for `parts`.
 * 0 on success, else a negative errno. */
int mocap_stream_open(mocap_stream_client **client, const char *host, uint16_t port, uint32_t parts);

/* Joins a multicast group the hub sends to (serve --stream-multicast GROUP:PORT); interface_ip
 * is the local address to join on (NULL: the default). 0 or a negative errno. */
int mocap_stream_open_multicast(mocap_stream_client **client, const char *group, uint16_t port,
                                const char *interface_ip);

/* Waits up to timeout_ms for the next frame: 1 with *frame filled, 0 on timeout, negative errno
 * on a socket error. Datagrams that are not frames are skipped. */
int mocap_stream_receive(mocap_stream_client *client, mocap_stream_frame *frame, int timeout_ms);

/* Unsubscribes (when subscribed) and frees the client. */
void mocap_stream_close(mocap_stream_client *client);

/* Decodes one StreamFrame message into *frame (its arrays and capacities set by the caller).
 * 0 on success, -EBADMSG when the bytes are not a StreamFrame. */
int mocap_stream_decode(const uint8_t *data, size_t size, mocap_stream_frame *frame);

#ifdef __cplusplus
}
#endif

#endif
