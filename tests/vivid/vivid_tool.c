/* mocap-vivid: the half of the vivid test (run_vivid.sh) that runs inside the VM, linked -static
 * into its initramfs next to mocap-node-static. Commands:
 *   feed CAPTURE OUTPUT [FOURCC]
 *                        sets up vivid's output-to-capture loop (FOURCC, default GREY, and the
 *                        capture's size on both sides, "Loop Video" on, OSD text off) and streams a frame of five marker
 *                        spots into OUTPUT through mmap buffers until SIGTERM. When the device
 *                        goes away it closes everything, waits for it to come back and starts
 *                        again, so the module can be removed and reloaded under it.
 *   recv PORT            decodes mocap-node's datagrams on 127.0.0.1:PORT by the wire rules until
 *                        SIGTERM, then prints one "VIVID: PASS|FAIL" line per check (markers at
 *                        the fed positions, capture time stamps, camera loss and reopen seen in
 *                        NodeStatus) and exits 0 only if all passed.
 *   formats CAPTURE      lists the capture device's pixel formats.
 *   spots PORT N T       exits 0 once N frames with the fed spots came from the node, 1 after T s.
 * Both sides place the spots from the frame size alone (spot_position), so nothing else needs to
 * be passed between them. */
#include <errno.h>
#include <fcntl.h>
#include <linux/videodev2.h>
#include <math.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

#include "capture/v4l2_buffers.h"
#include "wire/wire.h"
#include "stop_signals.h"

#define N_SPOTS 5
#define SPOT_SIGMA 1.8
#define SPOT_PEAK 230.0
#define BACKGROUND 12
#define OUT_BUFFERS 4
/* Centroid error allowed against the rendered spot centre; the detector is far better (its own
 * tests ask 0.02 px), this only has to tell the fed spots from anything else. */
#define POSITION_TOLERANCE_PX 0.25
#define MIN_GOOD_FRAMES 10
/* Receive time minus capture time. vivid stamps each buffer with its nominal frame time (stream
 * start + sequence x period, at the end of the frame), which can lie up to a frame period after
 * the moment the buffer is handed out; 100 ms covers that at any rate vivid runs here, while a
 * stamp from another clock (boot time, realtime taken as monotonic) is off by seconds to years. */
#define MIN_CAPTURE_LAG_NS (-100000000LL)
#define MAX_CAPTURE_LAG_NS 2000000000LL


/* Spot i of a w x h frame: spread over the image, at different sub-pixel phases. */
static void spot_position(uint32_t w, uint32_t h, int i, double *x, double *y)
{
    static const double fx[N_SPOTS] = {0.20, 0.50, 0.80, 0.35, 0.70};
    static const double fy[N_SPOTS] = {0.25, 0.40, 0.30, 0.75, 0.80};
    static const double phase[N_SPOTS] = {0.25, 0.50, 0.75, 0.10, 0.60};
    *x = floor(fx[i] * w) + phase[i];
    *y = floor(fy[i] * h) + phase[N_SPOTS - 1 - i];
}

static void render_spots(uint8_t *img, uint32_t w, uint32_t h, uint32_t stride)
{
    for (uint32_t y = 0; y < h; y++)
        memset(img + (size_t)y * stride, BACKGROUND, w);
    int r = (int)ceil(4 * SPOT_SIGMA);
    for (int i = 0; i < N_SPOTS; i++) {
        double cx, cy;
        spot_position(w, h, i, &cx, &cy);
        for (int y = (int)cy - r; y <= (int)cy + r + 1; y++) {
            for (int x = (int)cx - r; x <= (int)cx + r + 1; x++) {
                if (x < 0 || y < 0 || x >= (int)w || y >= (int)h)
                    continue;
                double d2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
                double v = BACKGROUND + SPOT_PEAK * exp(-d2 / (2 * SPOT_SIGMA * SPOT_SIGMA));
                img[(size_t)y * stride + (size_t)x] = (uint8_t)(v > 255 ? 255 : v + 0.5);
            }
        }
    }
}

/* ---- feed ---------------------------------------------------------------------------------- */

struct feed {
    const char *cap_path, *out_path;
    uint32_t fourcc; /* the same on both sides: vivid loops only like to like */
    int out_fd;
    uint32_t w, h, stride, sizeimage;
    struct mn_v4l2_map maps[OUT_BUFFERS];
    uint32_t n_maps;
    char err[256];
};

/* Finds a control of the capture device by its name; 0 and *id, or -1. */
static int find_ctrl(int fd, const char *name, struct v4l2_queryctrl *q)
{
    memset(q, 0, sizeof(*q));
    q->id = V4L2_CTRL_FLAG_NEXT_CTRL;
    while (mn_v4l2_ioctl(fd, VIDIOC_QUERYCTRL, q) == 0) {
        if (strcmp((const char *)q->name, name) == 0)
            return 0;
        q->id |= V4L2_CTRL_FLAG_NEXT_CTRL;
    }
    return -1;
}

static int set_ctrl_by_name(struct feed *f, int fd, const char *name, const char *menu_item,
                            int32_t value)
{
    struct v4l2_queryctrl q;
    if (find_ctrl(fd, name, &q) < 0) {
        snprintf(f->err, sizeof(f->err), "%s has no control \"%s\"", f->cap_path, name);
        return -1;
    }
    if (menu_item != NULL) {
        value = -1;
        for (int32_t i = q.minimum; i <= q.maximum; i++) {
            struct v4l2_querymenu m = {.id = q.id, .index = (uint32_t)i};
            if (mn_v4l2_ioctl(fd, VIDIOC_QUERYMENU, &m) == 0 && strcmp((const char *)m.name, menu_item) == 0)
                value = i;
        }
        if (value < 0) {
            snprintf(f->err, sizeof(f->err), "control \"%s\" has no item \"%s\"", name, menu_item);
            return -1;
        }
    }
    struct v4l2_control c = {.id = q.id, .value = value};
    if (mn_v4l2_ioctl(fd, VIDIOC_S_CTRL, &c) < 0) {
        snprintf(f->err, sizeof(f->err), "set \"%s\": %s", name, strerror(errno));
        return -1;
    }
    return 0;
}

/* Capture side: GREY, progressive, at the input's own size. A capture that is already
 * streaming (mocap-node came back first) refuses S_FMT with EBUSY and keeps its format. */
static int setup_capture(struct feed *f)
{
    int fd = open(f->cap_path, O_RDWR | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        snprintf(f->err, sizeof(f->err), "%s: %s", f->cap_path, strerror(errno));
        return -1;
    }
    struct v4l2_format fmt;
    memset(&fmt, 0, sizeof(fmt));
    fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    int rc = -1;
    if (mn_v4l2_ioctl(fd, VIDIOC_G_FMT, &fmt) < 0) {
        snprintf(f->err, sizeof(f->err), "%s: G_FMT: %s", f->cap_path, strerror(errno));
        goto out;
    }
    fmt.fmt.pix.pixelformat = f->fourcc;
    fmt.fmt.pix.field = V4L2_FIELD_NONE;
    if (mn_v4l2_ioctl(fd, VIDIOC_S_FMT, &fmt) < 0 && errno != EBUSY) {
        snprintf(f->err, sizeof(f->err), "%s: S_FMT %.4s: %s", f->cap_path,
                 (const char *)&f->fourcc, strerror(errno));
        goto out;
    }
    if (mn_v4l2_ioctl(fd, VIDIOC_G_FMT, &fmt) < 0 || fmt.fmt.pix.pixelformat != f->fourcc ||
        fmt.fmt.pix.field != V4L2_FIELD_NONE) {
        snprintf(f->err, sizeof(f->err), "%s: capture is %ux%u %.4s field %u, not progressive %.4s",
                 f->cap_path, fmt.fmt.pix.width, fmt.fmt.pix.height,
                 (const char *)&fmt.fmt.pix.pixelformat, fmt.fmt.pix.field,
                 (const char *)&f->fourcc);
        goto out;
    }
    f->w = fmt.fmt.pix.width;
    f->h = fmt.fmt.pix.height;
    if (set_ctrl_by_name(f, fd, "Loop Video", NULL, 1) < 0 ||
        set_ctrl_by_name(f, fd, "OSD Text Mode", "None", 0) < 0)
        goto out;
    rc = 0;
out:
    close(fd); /* controls and format stay with the device */
    return rc;
}

static void feed_teardown(struct feed *f)
{
    mn_v4l2_unmap_buffers(f->maps, &f->n_maps);
    if (f->out_fd >= 0)
        close(f->out_fd); /* also stops streaming and frees the buffers */
    f->out_fd = -1;
}

static int queue_out(struct feed *f, uint32_t index)
{
    struct v4l2_buffer b = mn_v4l2_mmap_buffer(V4L2_BUF_TYPE_VIDEO_OUTPUT, index);
    b.bytesused = f->sizeimage;
    b.field = V4L2_FIELD_NONE;
    return mn_v4l2_ioctl(f->out_fd, VIDIOC_QBUF, &b);
}

/* The Y8 picture in the feed's format, such that the node's luma of it is the picture again:
 * chroma neutral (128), R = G = B, 10/16-bit words with the value in their top bits. */
static void pack(const struct feed *f, const uint8_t *y8, uint8_t *buf)
{
    uint32_t w = f->w, h = f->h;
    for (uint32_t y = 0; y < h; y++) {
        const uint8_t *s = y8 + (size_t)y * w;
        uint8_t *d = buf + (size_t)y * f->stride;
        for (uint32_t x = 0; x < w; x++) {
            switch (f->fourcc) {
            case V4L2_PIX_FMT_Y10:
            case V4L2_PIX_FMT_Y16: {
                uint16_t v = f->fourcc == V4L2_PIX_FMT_Y10 ? (uint16_t)(s[x] << 2) : (uint16_t)(s[x] << 8);
                d[2 * x] = (uint8_t)(v & 0xff);
                d[2 * x + 1] = (uint8_t)(v >> 8);
                break;
            }
            case V4L2_PIX_FMT_YUYV:
                d[2 * x] = s[x];
                d[2 * x + 1] = 128;
                break;
            case V4L2_PIX_FMT_UYVY:
                d[2 * x] = 128;
                d[2 * x + 1] = s[x];
                break;
            case V4L2_PIX_FMT_RGB24:
            case V4L2_PIX_FMT_BGR24:
                memset(d + 3 * x, s[x], 3);
                break;
            case V4L2_PIX_FMT_XRGB32:
            case V4L2_PIX_FMT_XBGR32:
                memset(d + 4 * x, s[x], 4);
                break;
            default: /* GREY and the Y plane of the planar formats */
                d[x] = s[x];
                break;
            }
        }
    }
    /* The planar formats' chroma after the Y plane. */
    size_t luma = (size_t)f->stride * h;
    if (f->sizeimage > luma && (f->fourcc == V4L2_PIX_FMT_NV12 || f->fourcc == V4L2_PIX_FMT_NV21 ||
                                f->fourcc == V4L2_PIX_FMT_YUV420 || f->fourcc == V4L2_PIX_FMT_YVU420))
        memset(buf + luma, 128, f->sizeimage - luma);
}

static int setup_output(struct feed *f)
{
    f->out_fd = open(f->out_path, O_RDWR | O_NONBLOCK | O_CLOEXEC);
    if (f->out_fd < 0) {
        snprintf(f->err, sizeof(f->err), "%s: %s", f->out_path, strerror(errno));
        return -1;
    }
    struct v4l2_format fmt;
    memset(&fmt, 0, sizeof(fmt));
    fmt.type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
    fmt.fmt.pix.width = f->w;
    fmt.fmt.pix.height = f->h;
    fmt.fmt.pix.pixelformat = f->fourcc;
    fmt.fmt.pix.field = V4L2_FIELD_NONE;
    if (mn_v4l2_ioctl(f->out_fd, VIDIOC_S_FMT, &fmt) < 0) {
        snprintf(f->err, sizeof(f->err), "%s: S_FMT: %s", f->out_path, strerror(errno));
        return -1;
    }
    if (fmt.fmt.pix.pixelformat != f->fourcc || fmt.fmt.pix.width != f->w ||
        fmt.fmt.pix.height != f->h) {
        snprintf(f->err, sizeof(f->err), "%s: output took %ux%u %.4s, capture is %ux%u %.4s",
                 f->out_path, fmt.fmt.pix.width, fmt.fmt.pix.height,
                 (const char *)&fmt.fmt.pix.pixelformat, f->w, f->h, (const char *)&f->fourcc);
        return -1;
    }
    f->stride = fmt.fmt.pix.bytesperline;
    f->sizeimage = fmt.fmt.pix.sizeimage;
    if (mn_v4l2_map_buffers(f->out_fd, f->out_path, V4L2_BUF_TYPE_VIDEO_OUTPUT, OUT_BUFFERS,
                            f->maps, OUT_BUFFERS, &f->n_maps, f->err, sizeof(f->err)) < 0)
        return -1;
    uint8_t *y8 = malloc((size_t)f->w * f->h);
    if (y8 == NULL) {
        snprintf(f->err, sizeof(f->err), "out of memory");
        return -1;
    }
    render_spots(y8, f->w, f->h, f->w);
    for (uint32_t i = 0; i < f->n_maps; i++)
        pack(f, y8, f->maps[i].start);
    free(y8);
    for (uint32_t i = 0; i < f->n_maps; i++) {
        if (queue_out(f, i) < 0) {
            snprintf(f->err, sizeof(f->err), "%s: QBUF: %s", f->out_path, strerror(errno));
            return -1;
        }
    }
    enum v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_OUTPUT;
    if (mn_v4l2_ioctl(f->out_fd, VIDIOC_STREAMON, &type) < 0) {
        snprintf(f->err, sizeof(f->err), "%s: STREAMON: %s", f->out_path, strerror(errno));
        return -1;
    }
    return 0;
}

/* Hands every buffer the driver has shown back to it, unchanged; -1 when the device failed. */
static int feed_stream(struct feed *f)
{
    while (!stop_requested) {
        struct pollfd p = {.fd = f->out_fd, .events = POLLOUT};
        int rc = poll(&p, 1, 200);
        if (rc < 0 && errno != EINTR) {
            snprintf(f->err, sizeof(f->err), "poll: %s", strerror(errno));
            return -1;
        }
        if (rc <= 0)
            continue;
        struct v4l2_buffer b = mn_v4l2_mmap_buffer(V4L2_BUF_TYPE_VIDEO_OUTPUT, 0);
        if (mn_v4l2_ioctl(f->out_fd, VIDIOC_DQBUF, &b) < 0) {
            if (errno == EAGAIN)
                continue;
            snprintf(f->err, sizeof(f->err), "%s: DQBUF: %s", f->out_path, strerror(errno));
            return -1;
        }
        if (queue_out(f, b.index) < 0) {
            snprintf(f->err, sizeof(f->err), "%s: QBUF: %s", f->out_path, strerror(errno));
            return -1;
        }
    }
    return 0;
}

static uint32_t fourcc_of(const char *name)
{
    char c[4] = {' ', ' ', ' ', ' '};
    for (size_t i = 0; i < 4 && name[i] != '\0'; i++)
        c[i] = name[i];
    return v4l2_fourcc(c[0], c[1], c[2], c[3]);
}

static int cmd_feed(const char *cap_path, const char *out_path, const char *format)
{
    struct feed f = {.cap_path = cap_path, .out_path = out_path, .out_fd = -1,
                     .fourcc = fourcc_of(format)};
    char last_err[sizeof(f.err)] = "";
    catch_stop_signals();
    while (!stop_requested) {
        if (setup_capture(&f) == 0 && setup_output(&f) == 0) {
            printf("feed: looping %ux%u %.4s from %s into %s\n", f.w, f.h,
                   (const char *)&f.fourcc, out_path, cap_path);
            fflush(stdout);
            last_err[0] = '\0';
            if (feed_stream(&f) < 0)
                printf("feed: %s; waiting for the device\n", f.err);
        } else if (strcmp(f.err, last_err) != 0) {
            /* Say each distinct reason once, not every retry. */
            printf("feed: not ready: %s\n", f.err);
            snprintf(last_err, sizeof(last_err), "%s", f.err);
        }
        fflush(stdout);
        feed_teardown(&f);
        if (!stop_requested)
            usleep(100000);
    }
    return 0;
}

/* ---- recv ---------------------------------------------------------------------------------- */

struct recv_stats {
    uint64_t datagrams, rejected, frames, other_frames;
    uint64_t good_before, good_after; /* frames with exactly the fed spots, before/after loss */
    double max_error_px;
    bool have_last;
    uint64_t last_capture_ns;
    uint64_t non_increasing;          /* capture stamps that did not move forward */
    int64_t max_lag_ns, min_lag_ns;   /* receive time - capture time */
    bool saw_camera_error;
    uint32_t reopens;
    uint32_t width, height;
};

static int64_t real_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (int64_t)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

/* True when the frame holds exactly the fed spots; *err gets the largest centroid error. */
static bool frame_matches(const mocap_v1_MarkerFrame *mf, double *err)
{
    if (mf->chunk_count != 1 || mf->marker_total != N_SPOTS || mf->markers_count != N_SPOTS)
        return false;
    double worst = 0;
    for (int i = 0; i < N_SPOTS; i++) {
        double x, y, best = INFINITY;
        spot_position(mf->width, mf->height, i, &x, &y);
        for (pb_size_t k = 0; k < mf->markers_count; k++) {
            double dx = mn_wire_from_subpixel(mf->markers[k].x_q8) - x;
            double dy = mn_wire_from_subpixel(mf->markers[k].y_q8) - y;
            double d = sqrt(dx * dx + dy * dy);
            if (d < best)
                best = d;
        }
        if (best > worst)
            worst = best;
    }
    *err = worst;
    return worst <= POSITION_TOLERANCE_PX;
}

static void on_frame(struct recv_stats *s, const mocap_v1_MarkerFrame *mf, int64_t now)
{
    /* A frame of many blobs (vivid's test pattern while the loop is not up) travels in several
     * chunks with the same stamps: count and check each frame once, by its first chunk. */
    if (mf->chunk_index != 0)
        return;
    s->frames++;
    s->width = mf->width;
    s->height = mf->height;
    int64_t lag = now - (int64_t)mf->capture_time_ns;
    if (s->frames == 1 || lag > s->max_lag_ns)
        s->max_lag_ns = lag;
    if (s->frames == 1 || lag < s->min_lag_ns)
        s->min_lag_ns = lag;
    if (s->have_last && mf->capture_time_ns <= s->last_capture_ns)
        s->non_increasing++;
    s->have_last = true;
    s->last_capture_ns = mf->capture_time_ns;
    double err = 0;
    if (!frame_matches(mf, &err)) {
        s->other_frames++;
        return;
    }
    if (err > s->max_error_px)
        s->max_error_px = err;
    if (s->saw_camera_error)
        s->good_after++;
    else
        s->good_before++;
}

static int check(bool ok, const char *what, const char *detail)
{
    printf("VIVID: %s %s: %s\n", ok ? "PASS" : "FAIL", what, detail);
    return ok ? 0 : 1;
}

static int report(const struct recv_stats *s)
{
    char d[256];
    int failed = 0;
    printf("recv: %llu datagrams, %llu marker frames (%llu with other content), %ux%u\n",
           (unsigned long long)s->datagrams, (unsigned long long)s->frames,
           (unsigned long long)s->other_frames, s->width, s->height);
    snprintf(d, sizeof(d), "%llu datagrams decoded, %llu rejected",
             (unsigned long long)s->datagrams, (unsigned long long)s->rejected);
    failed += check(s->datagrams > 0 && s->rejected == 0, "wire", d);
    snprintf(d, sizeof(d), "%llu frames with the %d fed spots, largest centroid error %.3f px",
             (unsigned long long)s->good_before, N_SPOTS, s->max_error_px);
    failed += check(s->good_before >= MIN_GOOD_FRAMES, "markers detected and sent", d);
    snprintf(d, sizeof(d), "%llu stamps not after their predecessor; receive - capture %.1f..%.1f ms",
             (unsigned long long)s->non_increasing, s->min_lag_ns / 1e6, s->max_lag_ns / 1e6);
    failed += check(s->frames > 0 && s->non_increasing == 0 && s->min_lag_ns >= MIN_CAPTURE_LAG_NS &&
                        s->max_lag_ns <= MAX_CAPTURE_LAG_NS,
                    "capture time stamps", d);
    failed += check(s->saw_camera_error, "camera loss reported",
                    s->saw_camera_error ? "NodeStatus state CAMERA_ERROR"
                                        : "no NodeStatus with state CAMERA_ERROR");
    snprintf(d, sizeof(d), "NodeStatus camera_reopens %u, %llu frames with the fed spots after",
             s->reopens, (unsigned long long)s->good_after);
    failed += check(s->reopens >= 1 && s->good_after >= MIN_GOOD_FRAMES, "camera reopened", d);
    return failed == 0 ? 0 : 1;
}

static int cmd_recv(const char *port_arg)
{
    char *end;
    long port = strtol(port_arg, &end, 10);
    if (*end != '\0' || port < 1 || port > 65535) {
        fprintf(stderr, "recv: bad port %s\n", port_arg);
        return 2;
    }
    int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    struct sockaddr_in a = {.sin_family = AF_INET, .sin_port = htons((uint16_t)port),
                            .sin_addr.s_addr = htonl(INADDR_LOOPBACK)};
    if (fd < 0 || bind(fd, (struct sockaddr *)&a, sizeof(a)) < 0) {
        fprintf(stderr, "recv: bind 127.0.0.1:%ld: %s\n", port, strerror(errno));
        return 2;
    }
    /* A time-out on recv, so that a SIGTERM arriving just before it blocks is still seen. */
    struct timeval tv = {.tv_sec = 0, .tv_usec = 200000};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv));
    catch_stop_signals();
    printf("recv: listening on 127.0.0.1:%ld\n", port);
    fflush(stdout);
    struct recv_stats s;
    memset(&s, 0, sizeof(s));
    static mocap_v1_Packet packet;
    uint8_t buf[MN_WIRE_MAX_DATAGRAM + 1];
    while (!stop_requested) {
        ssize_t n = recv(fd, buf, sizeof(buf), 0);
        if (n < 0) {
            if (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK)
                continue;
            fprintf(stderr, "recv: %s\n", strerror(errno));
            close(fd);
            return 2;
        }
        int64_t now = real_ns();
        s.datagrams++;
        const char *why = NULL;
        if (mn_wire_decode(buf, (size_t)n, &packet, &why) < 0) {
            s.rejected++;
            printf("recv: rejected a %zd-byte datagram: %s\n", n, why);
            continue;
        }
        if (packet.which_body == mocap_v1_Packet_marker_frame_tag) {
            on_frame(&s, &packet.body.marker_frame, now);
        } else if (packet.which_body == mocap_v1_Packet_node_status_tag) {
            const mocap_v1_NodeStatus *st = &packet.body.node_status;
            if (st->state == mocap_v1_NodeState_NODE_STATE_CAMERA_ERROR && !s.saw_camera_error) {
                printf("recv: status: camera error after %llu frames\n",
                       (unsigned long long)s.frames);
                s.saw_camera_error = true;
            }
            if (st->camera_reopens > s.reopens)
                printf("recv: status: camera reopened (%u)\n", st->camera_reopens);
            if (st->camera_reopens > s.reopens)
                s.reopens = st->camera_reopens;
        }
        fflush(stdout);
    }
    close(fd);
    return report(&s);
}

/* ---- formats, spots ------------------------------------------------------------------------ */

/* The capture device's pixel formats, one fourcc a line. */
static int cmd_formats(const char *cap_path)
{
    int fd = open(cap_path, O_RDWR | O_CLOEXEC);
    if (fd < 0) {
        fprintf(stderr, "formats: %s: %s\n", cap_path, strerror(errno));
        return 2;
    }
    for (uint32_t i = 0;; i++) {
        struct v4l2_fmtdesc d = {.index = i, .type = V4L2_BUF_TYPE_VIDEO_CAPTURE};
        if (mn_v4l2_ioctl(fd, VIDIOC_ENUM_FMT, &d) < 0)
            break;
        /* Bit 31 marks a big-endian variant ("Y16" big-endian is 'Y16 ' | 1 << 31). */
        uint32_t pf = d.pixelformat & ~(1u << 31);
        char name[5];
        memcpy(name, &pf, 4);
        name[4] = '\0';
        for (int k = 3; k > 0 && name[k] == ' '; k--)
            name[k] = '\0';
        printf("%s%s\n", name, (d.pixelformat & (1u << 31)) ? "-BE" : "");
    }
    close(fd);
    return 0;
}

/* Receives the node's datagrams on PORT until `want` frames with the fed spots came (exit 0,
 * the largest centroid error printed) or timeout_s passed (exit 1). */
static int cmd_spots(const char *port_arg, const char *want_arg, const char *timeout_arg)
{
    long port = strtol(port_arg, NULL, 10), want = strtol(want_arg, NULL, 10);
    double timeout_s = atof(timeout_arg);
    int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    struct sockaddr_in a = {.sin_family = AF_INET, .sin_port = htons((uint16_t)port),
                            .sin_addr.s_addr = htonl(INADDR_LOOPBACK)};
    if (fd < 0 || port < 1 || port > 65535 || want < 1 ||
        bind(fd, (struct sockaddr *)&a, sizeof(a)) < 0) {
        fprintf(stderr, "spots: bind 127.0.0.1:%ld: %s\n", port, strerror(errno));
        return 2;
    }
    struct timeval tv = {.tv_sec = 0, .tv_usec = 200000};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv));
    static mocap_v1_Packet packet;
    uint8_t buf[MN_WIRE_MAX_DATAGRAM + 1];
    long good = 0, other = 0;
    double worst = 0;
    int64_t end = real_ns() + (int64_t)(timeout_s * 1e9);
    while (good < want && real_ns() < end) {
        ssize_t n = recv(fd, buf, sizeof(buf), 0);
        const char *why = NULL;
        if (n <= 0 || mn_wire_decode(buf, (size_t)n, &packet, &why) < 0 ||
            packet.which_body != mocap_v1_Packet_marker_frame_tag ||
            packet.body.marker_frame.chunk_index != 0)
            continue;
        double err = 0;
        if (frame_matches(&packet.body.marker_frame, &err)) {
            good++;
            worst = err > worst ? err : worst;
        } else {
            other++;
        }
    }
    close(fd);
    printf("spots: %ld frames with the %d fed spots (largest centroid error %.3f px), %ld others\n",
           good, N_SPOTS, worst, other);
    return good >= want ? 0 : 1;
}

int main(int argc, char **argv)
{
    if ((argc == 4 || argc == 5) && strcmp(argv[1], "feed") == 0)
        return cmd_feed(argv[2], argv[3], argc == 5 ? argv[4] : "GREY");
    if (argc == 3 && strcmp(argv[1], "recv") == 0)
        return cmd_recv(argv[2]);
    if (argc == 3 && strcmp(argv[1], "formats") == 0)
        return cmd_formats(argv[2]);
    if (argc == 5 && strcmp(argv[1], "spots") == 0)
        return cmd_spots(argv[2], argv[3], argv[4]);
    fprintf(stderr, "usage: %s feed CAPTURE_DEVICE OUTPUT_DEVICE [FOURCC]\n"
                    "       %s recv PORT\n"
                    "       %s formats CAPTURE_DEVICE\n"
                    "       %s spots PORT FRAMES TIMEOUT_S\n",
            argv[0], argv[0], argv[0], argv[0]);
    return 2;
}
