/* mocap stream client (see mocap_stream_client.h). */
#define _DEFAULT_SOURCE /* struct ip_mreq, alongside POSIX */
#include "mocap_stream_client.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <errno.h>
#include <netdb.h>
#include <poll.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <pb_decode.h>
#include <pb_encode.h>

#include "mocap_stream.npb.h"

#define RENEW_NS 1000000000ull
#define MAX_DATAGRAM 65536

struct mocap_stream_client {
    int fd;
    int subscribed;
    uint8_t cookie[32]; /* the hub's subscribe_cookie: proves this address (none yet: size 0) */
    size_t cookie_size;
    struct sockaddr_in hub;
    uint32_t parts;
    uint64_t next_renew_ns;
    uint8_t buffer[MAX_DATAGRAM];
};

static uint64_t now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint64_t)ts.tv_sec * 1000000000ull + (uint64_t)ts.tv_nsec;
}

/* ---- decoding: points and bodies arrive one by one through nanopb callbacks ---- */

static bool decode_point(pb_istream_t *stream, const pb_field_t *field, void **arg)
{
    (void)field;
    mocap_stream_frame *frame = *arg;
    mocap_stream_v1_Point p = mocap_stream_v1_Point_init_zero;
    if (!pb_decode(stream, mocap_stream_v1_Point_fields, &p))
        return false;
    frame->points_total++;
    if (frame->point_count >= frame->point_capacity)
        return true;
    mocap_stream_point *out = &frame->points[frame->point_count++];
    out->x = p.x;
    out->y = p.y;
    out->z = p.z;
    out->residual_px = p.residual_px;
    out->views = p.views;
    out->marker = p.marker;
    out->provisional_track = p.provisional_track;
    memcpy(out->label, p.label, sizeof out->label);
    out->label[sizeof out->label - 1] = '\0';
    return true;
}

static bool decode_body(pb_istream_t *stream, const pb_field_t *field, void **arg)
{
    (void)field;
    mocap_stream_frame *frame = *arg;
    mocap_stream_v1_RigidBody b = mocap_stream_v1_RigidBody_init_zero;
    if (!pb_decode(stream, mocap_stream_v1_RigidBody_fields, &b))
        return false;
    frame->bodies_total++;
    if (frame->body_count >= frame->body_capacity)
        return true;
    mocap_stream_body *out = &frame->bodies[frame->body_count++];
    out->id = b.id;
    memcpy(out->name, b.name, sizeof out->name);
    out->name[sizeof out->name - 1] = '\0';
    out->tracked = b.tracked;
    out->predicted = b.predicted;
    out->markers = b.markers;
    out->x = b.x;
    out->y = b.y;
    out->z = b.z;
    out->qx = b.qx;
    out->qy = b.qy;
    out->qz = b.qz;
    out->qw = b.qw;
    out->mean_error_mm = b.mean_error_mm;
    return true;
}

/* Decodes a StreamFrame: 0 for a frame; 1 for the hub's challenge (subscribe_cookie set), whose
 * cookie is copied to cookie/cookie_size when those are given; -EBADMSG. */
static int decode_message(const uint8_t *data, size_t size, mocap_stream_frame *frame, uint8_t *cookie,
                          size_t *cookie_size)
{
    mocap_stream_v1_StreamFrame m = mocap_stream_v1_StreamFrame_init_zero;
    frame->point_count = frame->points_total = 0;
    frame->body_count = frame->bodies_total = 0;
    if (!frame->points)
        frame->point_capacity = 0;
    if (!frame->bodies)
        frame->body_capacity = 0;
    m.points.funcs.decode = decode_point;
    m.points.arg = frame;
    m.bodies.funcs.decode = decode_body;
    m.bodies.arg = frame;
    pb_istream_t stream = pb_istream_from_buffer(data, size);
    if (!pb_decode(&stream, mocap_stream_v1_StreamFrame_fields, &m))
        return -EBADMSG;
    frame->frame_number = m.frame_number;
    frame->trigger_time_ns = m.trigger_time_ns;
    frame->publish_time_ns = m.publish_time_ns;
    frame->cameras = m.cameras;
    frame->parts = m.parts;
    frame->points_dropped = m.points_dropped;
    if (!m.subscribe_cookie.size)
        return 0;
    if (cookie_size) {
        *cookie_size = m.subscribe_cookie.size;
        memcpy(cookie, m.subscribe_cookie.bytes, m.subscribe_cookie.size);
    }
    return 1;
}

int mocap_stream_decode(const uint8_t *data, size_t size, mocap_stream_frame *frame)
{
    return decode_message(data, size, frame, NULL, NULL) < 0 ? -EBADMSG : 0;
}

/* ---- the socket ---- */

static int send_request(mocap_stream_client *c, int subscribe)
{
    mocap_stream_v1_StreamRequest r = mocap_stream_v1_StreamRequest_init_zero;
    r.version = 1;
    if (subscribe) {
        r.which_body = mocap_stream_v1_StreamRequest_subscribe_tag;
        r.body.subscribe.parts = c->parts;
        r.body.subscribe.cookie.size = (pb_size_t)c->cookie_size;
        memcpy(r.body.subscribe.cookie.bytes, c->cookie, c->cookie_size);
        /* A first request is padded: the hub answers none smaller than its challenge. */
        if (!c->cookie_size)
            r.body.subscribe.padding.size = 24;
    } else {
        r.which_body = mocap_stream_v1_StreamRequest_unsubscribe_tag;
        r.body.unsubscribe.cookie.size = (pb_size_t)c->cookie_size;
        memcpy(r.body.unsubscribe.cookie.bytes, c->cookie, c->cookie_size);
    }
    uint8_t bytes[96];
    pb_ostream_t out = pb_ostream_from_buffer(bytes, sizeof bytes);
    if (!pb_encode(&out, mocap_stream_v1_StreamRequest_fields, &r))
        return -EINVAL;
    if (sendto(c->fd, bytes, out.bytes_written, 0, (const struct sockaddr *)&c->hub, sizeof c->hub) < 0)
        return -errno;
    return 0;
}

static int new_client(mocap_stream_client **client)
{
    mocap_stream_client *c = calloc(1, sizeof *c);
    if (!c)
        return -ENOMEM;
    c->fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (c->fd < 0) {
        int e = -errno;
        free(c);
        return e;
    }
    *client = c;
    return 0;
}

static int fail(mocap_stream_client *c, int error)
{
    close(c->fd);
    free(c);
    return error;
}

int mocap_stream_open(mocap_stream_client **client, const char *host, uint16_t port, uint32_t parts)
{
    struct addrinfo hints = {.ai_family = AF_INET, .ai_socktype = SOCK_DGRAM};
    struct addrinfo *found = NULL;
    if (!client || !host || getaddrinfo(host, NULL, &hints, &found) != 0 || !found)
        return -EINVAL;
    mocap_stream_client *c = NULL;
    int rc = new_client(&c);
    if (rc < 0) {
        freeaddrinfo(found);
        return rc;
    }
    c->hub = *(struct sockaddr_in *)found->ai_addr;
    c->hub.sin_port = htons(port);
    freeaddrinfo(found);
    c->parts = parts;
    /* A deep receive buffer rides out the moments the application is busy. */
    int size = 1 << 20;
    setsockopt(c->fd, SOL_SOCKET, SO_RCVBUF, &size, sizeof size);
    rc = send_request(c, 1);
    if (rc < 0)
        return fail(c, rc);
    c->subscribed = 1;
    c->next_renew_ns = now_ns() + RENEW_NS;
    *client = c;
    return 0;
}

int mocap_stream_open_multicast(mocap_stream_client **client, const char *group, uint16_t port,
                                const char *interface_ip)
{
    struct ip_mreq join;
    memset(&join, 0, sizeof join);
    if (!client || !group || inet_pton(AF_INET, group, &join.imr_multiaddr) != 1)
        return -EINVAL;
    join.imr_interface.s_addr = htonl(INADDR_ANY);
    if (interface_ip && inet_pton(AF_INET, interface_ip, &join.imr_interface) != 1)
        return -EINVAL;
    mocap_stream_client *c = NULL;
    int rc = new_client(&c);
    if (rc < 0)
        return rc;
    int one = 1;
    setsockopt(c->fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    struct sockaddr_in local = {.sin_family = AF_INET, .sin_port = htons(port)};
    local.sin_addr = join.imr_multiaddr;
    if (bind(c->fd, (const struct sockaddr *)&local, sizeof local) != 0 ||
        setsockopt(c->fd, IPPROTO_IP, IP_ADD_MEMBERSHIP, &join, sizeof join) != 0)
        return fail(c, -errno);
    *client = c;
    return 0;
}

int mocap_stream_receive(mocap_stream_client *c, mocap_stream_frame *frame, int timeout_ms)
{
    uint64_t deadline = now_ns() + (uint64_t)(timeout_ms > 0 ? timeout_ms : 0) * 1000000ull;
    for (;;) {
        uint64_t now = now_ns();
        if (c->subscribed && now >= c->next_renew_ns) {
            int rc = send_request(c, 1);
            if (rc < 0)
                return rc;
            c->next_renew_ns = now + RENEW_NS;
        }
        uint64_t until = deadline;
        if (c->subscribed && c->next_renew_ns < until)
            until = c->next_renew_ns;
        int wait_ms = until > now ? (int)((until - now + 999999) / 1000000) : 0;
        struct pollfd p = {.fd = c->fd, .events = POLLIN};
        int n = poll(&p, 1, wait_ms);
        if (n < 0) {
            if (errno == EINTR)
                continue;
            return -errno;
        }
        if (n > 0) {
            ssize_t got = recv(c->fd, c->buffer, sizeof c->buffer, 0);
            if (got < 0) {
                /* A refused subscription request comes back as an error on the next call:
                 * the hub may not be up yet; keep trying until the deadline. */
                if (errno != ECONNREFUSED && errno != EINTR && errno != EAGAIN)
                    return -errno;
            } else {
                int kind = decode_message(c->buffer, (size_t)got, frame, c->cookie, &c->cookie_size);
                if (kind == 0)
                    return 1;
                if (kind == 1 && c->subscribed) {
                    /* The hub's challenge: its cookie goes back at once, and in every renewal. */
                    int rc = send_request(c, 1);
                    if (rc < 0)
                        return rc;
                    c->next_renew_ns = now_ns() + RENEW_NS;
                }
            }
        }
        if (now_ns() >= deadline)
            return 0;
    }
}

void mocap_stream_close(mocap_stream_client *c)
{
    if (!c)
        return;
    if (c->subscribed)
        send_request(c, 0);
    close(c->fd);
    free(c);
}
