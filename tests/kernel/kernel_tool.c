/* mocap-kernel: the half of the kernel test (run_kernel.sh) that runs inside the VM, linked
 * -static into its initramfs. Commands:
 *   recv PORT DUMP NODE_PID [EXPOSURE_US GAIN_MILLI AFTER_S]
 *       decodes mocap-node's datagrams on 127.0.0.1:PORT by the wire rules until SIGTERM and
 *       writes DUMP: "F number flags trigger capture send receive markers" per frame,
 *       "M x y area peak mean flags ..." per chunk (the markers, in the node's order),
 *       "S state reopens missed spurious unmatched" per status, "A sequence result reason" per
 *       control ack. With EXPOSURE_US, one SetExposure goes to the node AFTER_S seconds after
 *       its first frame. At the end it prints the frame count, the send - capture latency and
 *       the node's CPU time per frame (/proc/NODE_PID/schedstat between its first and last).
 *   gpio PORT PULL_FILE RATE_HZ EDGES SKIP_EVERY rising|falling DELAY_US NODE_PID
 *       the hub and the trigger generator of the GPIO test: waits for the node's first frames
 *       (a free-running camera at RATE_HZ, no edges yet), finds the camera's phase from their
 *       capture stamps, sends Start with an epoch DELAY_US before a coming frame, and then
 *       drives the gpio-sim line through PULL_FILE at the camera's rate: EDGES slots, the edge
 *       of every SKIP_EVERY-th slot left out. Then it checks what the node sent (frame number =
 *       slot = edge count, unmatched exactly where the edge was skipped, the kernel's edge stamp
 *       next to the moment the line was driven, the missed edges in NodeStatus) and prints one
 *       "KERNEL: PASS|FAIL" line per check and the trigger -> send latency.
 *   cam2mcf FORMAT WIDTH HEIGHT OUTDIR FILE...
 *       converts raw frames written by libcamera's cam tool (FORMAT: RGB888 or BGR888, libcamera's
 *       names) to 8-bit luma with the node's own conversion and writes OUTDIR/frames.mcf, frame k
 *       numbered k, for the node's replay source.
 *   ctrl DEVICE NAME VALUE
 *       sets a V4L2 control by its name (a subdevice's too: the vimc sensor's test pattern).
 *   rate DEVICE WIDTH HEIGHT FPS
 *       sets a capture device (vivid's webcam) to GREY WIDTH x HEIGHT at FPS frames a second,
 *       which it keeps when mocap-node asks for the same format. */
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
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/timerfd.h>
#include <time.h>
#include <unistd.h>

#include "capture/pixfmt.h"
#include "framefile/framefile.h"
#include "wire/wire.h"
#include "stop_signals.h"

#define MAX_SAMPLES 100000
#define MAX_SLOTS 4096


static int64_t real_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (int64_t)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

static int cmp_i64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return x < y ? -1 : x > y;
}

/* CPU time process pid has used, ns (first field of /proc/PID/schedstat); -1 when gone. */
static int64_t cpu_ns(long pid)
{
    char path[64];
    snprintf(path, sizeof(path), "/proc/%ld/schedstat", pid);
    FILE *f = fopen(path, "r");
    long long v = -1;
    if (f == NULL)
        return -1;
    if (fscanf(f, "%lld", &v) != 1)
        v = -1;
    fclose(f);
    return v;
}

/* Node CPU per frame over the frames between two samples. */
struct cpu_meter {
    long pid;
    int64_t first_ns, last_ns;
    uint64_t first_frame, last_frame;
};

static void cpu_sample(struct cpu_meter *m, uint64_t frames)
{
    int64_t v = cpu_ns(m->pid);
    if (v < 0)
        return;
    if (m->first_frame == 0) {
        m->first_ns = v;
        m->first_frame = frames;
    }
    m->last_ns = v;
    m->last_frame = frames;
}

static double cpu_ms_per_frame(const struct cpu_meter *m)
{
    if (m->last_frame <= m->first_frame)
        return NAN;
    return (double)(m->last_ns - m->first_ns) / 1e6 / (double)(m->last_frame - m->first_frame);
}

/* p-th percentile (nearest rank) of v[0..n), sorted in place. */
static double percentile_ms(int64_t *v, size_t n, double p)
{
    if (n == 0)
        return NAN;
    qsort(v, n, sizeof(*v), cmp_i64);
    size_t k = (size_t)ceil(p / 100.0 * (double)n);
    return (double)v[k == 0 ? 0 : k - 1] / 1e6;
}

/* A loopback UDP socket on PORT with a 50 ms receive time-out (a stop signal is seen soon). */
static int bind_port(const char *port_arg)
{
    char *end;
    long port = strtol(port_arg, &end, 10);
    if (*end != '\0' || port < 1 || port > 65535) {
        fprintf(stderr, "bad port %s\n", port_arg);
        return -1;
    }
    int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    struct sockaddr_in a = {.sin_family = AF_INET, .sin_port = htons((uint16_t)port),
                            .sin_addr.s_addr = htonl(INADDR_LOOPBACK)};
    if (fd < 0 || bind(fd, (struct sockaddr *)&a, sizeof(a)) < 0) {
        fprintf(stderr, "bind 127.0.0.1:%ld: %s\n", port, strerror(errno));
        return -1;
    }
    struct timeval tv = {.tv_sec = 0, .tv_usec = 50000};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv));
    return fd;
}

/* One datagram decoded into *p; 1, 0 on time-out, -1 on a socket error. The sender's address
 * (the node's control port) goes to *from. */
static int receive(int fd, mocap_v1_Packet *p, struct sockaddr_in *from, uint64_t *rejected)
{
    uint8_t buf[MN_WIRE_MAX_DATAGRAM + 1];
    socklen_t len = sizeof(*from);
    ssize_t n = recvfrom(fd, buf, sizeof(buf), 0, (struct sockaddr *)from, &len);
    if (n < 0)
        return errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK ? 0 : -1;
    const char *why = NULL;
    if (mn_wire_decode(buf, (size_t)n, p, &why) < 0) {
        (*rejected)++;
        printf("rejected a %zd-byte datagram: %s\n", n, why);
        return 0;
    }
    return 1;
}

static int send_control(int fd, const struct sockaddr_in *node, mocap_v1_Control *c)
{
    static mocap_v1_Packet p;
    memset(&p, 0, sizeof(p));
    p.version = MN_WIRE_VERSION;
    p.which_body = mocap_v1_Packet_control_tag;
    p.body.control = *c;
    uint8_t buf[MN_WIRE_MAX_DATAGRAM];
    size_t size;
    const char *why = NULL;
    if (mn_wire_encode(&p, buf, sizeof(buf), &size, &why) < 0) {
        fprintf(stderr, "encode control: %s\n", why);
        return -1;
    }
    if (sendto(fd, buf, size, 0, (const struct sockaddr *)node, sizeof(*node)) < 0) {
        fprintf(stderr, "send control: %s\n", strerror(errno));
        return -1;
    }
    return 0;
}

static void dump_frame(FILE *out, const mocap_v1_MarkerFrame *mf, int64_t now)
{
    if (mf->chunk_index == 0)
        fprintf(out, "F %llu %u %llu %llu %llu %lld %u\n", (unsigned long long)mf->frame_number,
                mf->flags, (unsigned long long)mf->trigger_time_ns,
                (unsigned long long)mf->capture_time_ns, (unsigned long long)mf->send_time_ns,
                (long long)now, mf->marker_total);
    fputc('M', out);
    for (pb_size_t k = 0; k < mf->markers_count; k++) {
        const mocap_v1_Marker *m = &mf->markers[k];
        fprintf(out, " %u,%u,%u,%u,%u,%u", m->x_q8, m->y_q8, m->area, m->peak, m->mean, m->flags);
    }
    fputc('\n', out);
}

static void dump_status(FILE *out, const mocap_v1_NodeStatus *st)
{
    fprintf(out, "S %d %u %u %u %u\n", (int)st->state, st->camera_reopens, st->sync.missed_edges,
            st->sync.spurious_edges, st->sync.unmatched_frames);
}

/* ---- recv ---------------------------------------------------------------------------------- */

static int cmd_recv(int argc, char **argv)
{
    int fd = bind_port(argv[2]);
    FILE *out = fopen(argv[3], "w");
    if (fd < 0 || out == NULL) {
        fprintf(stderr, "recv: cannot open %s\n", argv[3]);
        return 2;
    }
    struct cpu_meter cpu = {.pid = strtol(argv[4], NULL, 10)};
    bool control = argc == 8;
    uint32_t exposure = control ? (uint32_t)strtoul(argv[5], NULL, 10) : 0;
    uint32_t gain = control ? (uint32_t)strtoul(argv[6], NULL, 10) : 0;
    int64_t after_ns = control ? (int64_t)(atof(argv[7]) * 1e9) : 0;
    catch_stop_signals();
    static mocap_v1_Packet p;
    static int64_t lat[MAX_SAMPLES];
    size_t n_lat = 0;
    uint64_t frames = 0, rejected = 0;
    int64_t first_ns = 0;
    bool sent = false;
    struct sockaddr_in node;
    while (!stop_requested) {
        int rc = receive(fd, &p, &node, &rejected);
        if (rc < 0) {
            fprintf(stderr, "recv: %s\n", strerror(errno));
            return 2;
        }
        if (rc == 0)
            continue;
        int64_t now = real_ns();
        if (p.which_body == mocap_v1_Packet_marker_frame_tag) {
            const mocap_v1_MarkerFrame *mf = &p.body.marker_frame;
            dump_frame(out, mf, now);
            if (mf->chunk_index == 0) {
                if (frames++ == 0)
                    first_ns = now;
                /* From the tenth frame on: start-up (libcamera, buffers) is not per frame. */
                if (frames >= 10)
                    cpu_sample(&cpu, frames);
                if (n_lat < MAX_SAMPLES)
                    lat[n_lat++] = (int64_t)(mf->send_time_ns - mf->capture_time_ns);
            }
        } else if (p.which_body == mocap_v1_Packet_node_status_tag) {
            dump_status(out, &p.body.node_status);
        } else if (p.which_body == mocap_v1_Packet_control_ack_tag) {
            fprintf(out, "A %u %d %s\n", p.body.control_ack.sequence,
                    (int)p.body.control_ack.result, p.body.control_ack.reason);
        }
        if (control && !sent && frames > 0 && now - first_ns >= after_ns) {
            mocap_v1_Control c = mocap_v1_Control_init_zero;
            c.sequence = 1;
            c.which_command = mocap_v1_Control_set_exposure_tag;
            c.command.set_exposure.exposure_us = exposure;
            c.command.set_exposure.gain_milli = gain;
            if (send_control(fd, &node, &c) < 0)
                return 2;
            fprintf(out, "C %llu exposure %u gain %u\n", (unsigned long long)frames, exposure, gain);
            sent = true;
        }
        fflush(out);
    }
    fclose(out);
    close(fd);
    printf("recv: %llu frames, %llu rejected datagrams\n", (unsigned long long)frames,
           (unsigned long long)rejected);
    printf("KERNEL: FIGURE capture -> send latency p50 %.2f ms p99 %.2f ms, node CPU %.2f ms per "
           "frame over %llu frames\n",
           percentile_ms(lat, n_lat, 50), percentile_ms(lat, n_lat, 99), cpu_ms_per_frame(&cpu),
           (unsigned long long)(cpu.last_frame - cpu.first_frame));
    return rejected == 0 ? 0 : 1;
}

/* ---- gpio ---------------------------------------------------------------------------------- */

struct slot {
    int64_t driven_ns; /* when the line was set to make this slot's edge (0: skipped) */
    bool seen;
    uint32_t flags;
    int64_t trigger_ns, send_ns;
};

static int drive(int pull_fd, bool high)
{
    const char *v = high ? "pull-up" : "pull-down";
    if (pwrite(pull_fd, v, strlen(v), 0) < 0) {
        fprintf(stderr, "gpio: write %s: %s\n", v, strerror(errno));
        return -1;
    }
    return 0;
}

static int check(bool ok, const char *what, const char *detail)
{
    printf("KERNEL: %s %s: %s\n", ok ? "PASS" : "FAIL", what, detail);
    return ok ? 0 : 1;
}

static int cmd_gpio(char **argv)
{
    int fd = bind_port(argv[2]);
    int pull_fd = open(argv[3], O_WRONLY | O_CLOEXEC);
    double rate_hz = atof(argv[4]);
    long edges = strtol(argv[5], NULL, 10);
    long skip_every = strtol(argv[6], NULL, 10);
    bool falling = strcmp(argv[7], "falling") == 0;
    int64_t delay_ns = strtoll(argv[8], NULL, 10) * 1000;
    struct cpu_meter cpu = {.pid = strtol(argv[9], NULL, 10)};
    if (fd < 0 || pull_fd < 0 || edges < 8 || edges > MAX_SLOTS || skip_every < 2 ||
        rate_hz < 1 || rate_hz > 100) {
        fprintf(stderr, "gpio: bad arguments (or %s: %s)\n", argv[3], strerror(errno));
        return 2;
    }
    catch_stop_signals();
    /* Idle level: the edge the node waits for is the change away from it. */
    if (drive(pull_fd, falling) < 0)
        return 2;

    /* 1. The camera's period and phase from 12 free-running frames. */
    static mocap_v1_Packet p;
    struct sockaddr_in node;
    uint64_t rejected = 0;
    int64_t stamps[12];
    int n_stamps = 0;
    int64_t give_up = real_ns() + 20000000000LL;
    while (n_stamps < 12 && !stop_requested && real_ns() < give_up) {
        if (receive(fd, &p, &node, &rejected) == 1 && p.which_body == mocap_v1_Packet_marker_frame_tag &&
            p.body.marker_frame.chunk_index == 0)
            stamps[n_stamps++] = (int64_t)p.body.marker_frame.capture_time_ns;
    }
    if (n_stamps < 12) {
        check(false, "gpio: camera frames", "fewer than 12 frames from the node in 20 s");
        return 1;
    }
    /* The camera runs at its nominal rate (vivid keeps it on average), but each stamp is late
     * by its thread's wake-up and a VM's timer slack, and frames may be dropped: the phase is
     * the median of the stamps' offsets from the last one, taken modulo the period. */
    int64_t period = llround(1e9 / rate_hz);
    int64_t offsets[12];
    for (int i = 0; i < n_stamps; i++) {
        int64_t d = (stamps[i] - stamps[n_stamps - 1]) % period;
        if (d < -period / 2)
            d += period;
        if (d >= period / 2)
            d -= period;
        offsets[i] = d;
    }
    qsort(offsets, (size_t)n_stamps, sizeof(offsets[0]), cmp_i64);
    int64_t last_frame = stamps[n_stamps - 1] + offsets[n_stamps / 2];
    printf("gpio: camera phase from %d frames: offsets %.1f..%.1f ms around the median\n",
           n_stamps, (offsets[0] - offsets[n_stamps / 2]) / 1e6,
           (offsets[n_stamps - 1] - offsets[n_stamps / 2]) / 1e6);
    uint32_t rate_mhz = (uint32_t)llround(rate_hz * 1000);
    /* Slot 0 is a frame about half a second ahead; the edge comes delay_ns before the frame's
     * stamp, as a trigger comes before the exposure it starts. */
    int64_t epoch = last_frame + ((500000000LL + period - 1) / period) * period - delay_ns;
    mocap_v1_Control c = mocap_v1_Control_init_zero;
    c.sequence = 1;
    c.which_command = mocap_v1_Control_start_tag;
    c.command.start.epoch_ns = (uint64_t)epoch;
    c.command.start.rate_millihz = rate_mhz;
    if (send_control(fd, &node, &c) < 0)
        return 2;
    printf("gpio: Start epoch %lld rate %u mHz, %ld edges (%s), every %ld-th left out\n",
           (long long)epoch, rate_mhz, edges, falling ? "falling" : "rising", skip_every);

    /* 2. Drive the line: the edge at epoch + k period, back to idle half a period later;
     * frames are read between the timer expiries. */
    static struct slot slots[MAX_SLOTS];
    memset(slots, 0, sizeof(slots));
    int tfd = timerfd_create(CLOCK_REALTIME, TFD_CLOEXEC);
    uint64_t frames = 0, frames_outside = 0;
    uint32_t last_missed = 0, last_spurious = 0;
    static int64_t lat[MAX_SLOTS], fill_lat[MAX_SLOTS];
    size_t n_lat = 0;
    long step = 0; /* 2k: edge of slot k; 2k+1: back to idle */
    int64_t end_ns = epoch + (int64_t)(edges + 3) * period;
    while (!stop_requested && real_ns() < end_ns + 500000000LL) {
        if (step < 2 * edges) {
            int64_t at = epoch + (step / 2) * period + (step % 2) * (period / 2);
            struct itimerspec its = {.it_value = {.tv_sec = at / 1000000000LL,
                                                  .tv_nsec = at % 1000000000LL}};
            timerfd_settime(tfd, TFD_TIMER_ABSTIME, &its, NULL);
        }
        struct pollfd pf[2] = {{.fd = fd, .events = POLLIN}, {.fd = tfd, .events = POLLIN}};
        if (poll(pf, step < 2 * edges ? 2 : 1, 100) < 0 && errno != EINTR)
            return 2;
        if (pf[1].revents & POLLIN) {
            uint64_t expirations;
            if (read(tfd, &expirations, sizeof(expirations)) < 0)
                return 2;
            long k = step / 2;
            bool edge = step % 2 == 0;
            bool skipped = k % skip_every == skip_every - 1;
            if (!skipped || !edge) {
                int64_t before = real_ns();
                if (drive(pull_fd, edge != falling) < 0)
                    return 2;
                if (edge)
                    slots[k].driven_ns = before;
            }
            step++;
        }
        if (!(pf[0].revents & POLLIN))
            continue;
        int rc = receive(fd, &p, &node, &rejected);
        if (rc != 1)
            continue;
        if (p.which_body == mocap_v1_Packet_node_status_tag) {
            last_missed = p.body.node_status.sync.missed_edges;
            last_spurious = p.body.node_status.sync.spurious_edges;
            continue;
        }
        if (p.which_body != mocap_v1_Packet_marker_frame_tag || p.body.marker_frame.chunk_index != 0)
            continue;
        const mocap_v1_MarkerFrame *mf = &p.body.marker_frame;
        frames++;
        if (mf->frame_number >= (uint64_t)edges) {
            frames_outside++;
            continue;
        }
        cpu_sample(&cpu, frames);
        struct slot *s = &slots[mf->frame_number];
        s->seen = true;
        s->flags = mf->flags;
        s->trigger_ns = (int64_t)mf->trigger_time_ns;
        s->send_ns = (int64_t)mf->send_time_ns;
        if (mf->flags == 0 && n_lat < MAX_SLOTS) {
            /* vivid stamps a buffer 0.9 period after it fills it (its end of exposure). */
            fill_lat[n_lat] = s->send_ns - ((int64_t)mf->capture_time_ns - period * 9 / 10);
            lat[n_lat++] = s->send_ns - s->trigger_ns;
        }
    }
    close(tfd);
    drive(pull_fd, falling);

    /* 3. What the node made of it. Slots before the first frame the node sent after Start
     * (it needs a moment to apply it) are not judged. */
    long first = 0;
    while (first < edges && !slots[first].seen)
        first++;
    long judged = 0, unseen = 0, numbered_right = 0, skipped_right = 0, skipped = 0;
    long unpaired = 0, paired_without_edge = 0;
    int64_t min_stamp = INT64_MAX, max_stamp = INT64_MIN;
    for (long k = first; k < edges; k++) {
        const struct slot *s = &slots[k];
        bool was_skipped = s->driven_ns == 0;
        judged++;
        skipped += was_skipped;
        if (!s->seen) {
            unseen++;
            continue;
        }
        if (was_skipped) {
            skipped_right += s->flags == mocap_v1_FrameFlag_FRAME_FLAG_UNMATCHED;
            paired_without_edge += s->flags != mocap_v1_FrameFlag_FRAME_FLAG_UNMATCHED;
            continue;
        }
        if (s->flags != 0) {
            unpaired++;
            continue;
        }
        numbered_right++;
        /* The kernel stamps the edge after the write that made it returns: stamp - write start
         * is positive and small. */
        int64_t d = s->trigger_ns - s->driven_ns;
        if (d < min_stamp)
            min_stamp = d;
        if (d > max_stamp)
            max_stamp = d;
    }
    char d[256];
    int failed = 0;
    snprintf(d, sizeof(d), "%llu frames, slots %ld..%ld judged (%ld), %ld without a frame",
             (unsigned long long)frames, first, edges - 1, judged, unseen);
    failed += check(first < edges / 4 && unseen <= judged / 20, "gpio: frames for the slots", d);
    snprintf(d, sizeof(d), "%ld of %ld frames paired with their slot's edge (number = edge "
                           "count), %ld unpaired", numbered_right, judged - skipped - unseen,
             unpaired);
    /* A frame can miss its edge when the VM's timers run late (the edge then lands outside the
     * window, or after the frame): most must pair; a paired frame's edge is checked below. */
    failed += check(numbered_right >= (judged - skipped) * 8 / 10, "gpio: frame number = edge count", d);
    snprintf(d, sizeof(d), "%ld of %ld slots whose edge was left out sent unmatched with the "
                           "slot's number, %ld paired with an edge that never was",
             skipped_right, skipped, paired_without_edge);
    failed += check(skipped > 0 && skipped_right >= skipped - unseen && paired_without_edge == 0,
                    "gpio: skipped edges", d);
    /* Missed edges in the status cover every skipped slot since Start, the unjudged first
     * ones too. */
    long skipped_all = 0;
    for (long k = 0; k < edges - 1; k++)
        skipped_all += k % skip_every == skip_every - 1;
    snprintf(d, sizeof(d), "NodeStatus missed_edges %u, spurious %u (edges left out: %ld)",
             last_missed, last_spurious, skipped_all);
    /* An edge the VM drove too late (outside the window) is spurious and leaves its slot missed
     * and its frame unpaired: allowed only as often as frames went unpaired. */
    failed += check(last_missed >= (uint32_t)skipped &&
                        last_missed <= (uint32_t)(skipped_all + last_spurious) &&
                        last_spurious <= (uint32_t)(unpaired + unseen),
                    "gpio: missed edges counted", d);
    snprintf(d, sizeof(d), "kernel edge stamp - line write %+.3f..%+.3f ms (CLOCK_MONOTONIC, "
                           "sent as realtime)", min_stamp / 1e6, max_stamp / 1e6);
    /* Within half a period: the stamp is this slot's edge, not a neighbour's. */
    failed += check(numbered_right > 0 && min_stamp >= 0 && max_stamp < period / 2,
                    "gpio: edge time stamps", d);
    snprintf(d, sizeof(d), "%llu frames numbered beyond the last slot", (unsigned long long)frames_outside);
    failed += check(rejected == 0, "gpio: wire", rejected == 0 ? "every datagram decoded" : d);
    printf("KERNEL: FIGURE gpio trigger -> send latency p50 %.2f ms p99 %.2f ms over %zu frames "
           "(the edge leads vivid's buffer by %.0f ms; buffer filled -> send p50 %.2f ms p99 "
           "%.2f ms), node CPU %.2f ms per frame\n",
           percentile_ms(lat, n_lat, 50), percentile_ms(lat, n_lat, 99), n_lat,
           (delay_ns - period * 9 / 10) / 1e6, percentile_ms(fill_lat, n_lat, 50),
           percentile_ms(fill_lat, n_lat, 99), cpu_ms_per_frame(&cpu));
    return failed == 0 ? 0 : 1;
}

/* ---- cam2mcf ------------------------------------------------------------------------------- */

static int cmd_cam2mcf(int argc, char **argv)
{
    enum mn_pixfmt fmt;
    /* libcamera names packed RGB by the 32-bit word: RGB888 is B, G, R in memory. */
    if (strcmp(argv[2], "RGB888") == 0)
        fmt = MN_PIXFMT_BGR24;
    else if (strcmp(argv[2], "BGR888") == 0)
        fmt = MN_PIXFMT_RGB24;
    else {
        fprintf(stderr, "cam2mcf: format %s is not RGB888 or BGR888\n", argv[2]);
        return 2;
    }
    uint32_t w = (uint32_t)strtoul(argv[3], NULL, 10), h = (uint32_t)strtoul(argv[4], NULL, 10);
    if (w == 0 || h == 0 || w > 4096 || h > 4096) {
        fprintf(stderr, "cam2mcf: bad size %ux%u\n", w, h);
        return 2;
    }
    struct mn_ff_info info = {.width = w, .height = h};
    struct mn_ff_write_options opts = {.zlib_level = 1, .dark_level = -1};
    struct mn_ff_writer *wr = mn_ff_writer_open(argv[5], &info, &opts);
    uint8_t *raw = malloc((size_t)w * h * 4), *y8 = malloc((size_t)w * h);
    if (wr == NULL || raw == NULL || y8 == NULL) {
        fprintf(stderr, "cam2mcf: %s: %s\n", argv[5], strerror(errno));
        return 2;
    }
    for (int i = 6; i < argc; i++) {
        FILE *f = fopen(argv[i], "rb");
        struct stat st;
        if (f == NULL || fstat(fileno(f), &st) < 0) {
            fprintf(stderr, "cam2mcf: %s: %s\n", argv[i], strerror(errno));
            return 2;
        }
        /* cam writes the plane's bytes as mapped: height rows of the stream's stride. */
        size_t stride = (size_t)st.st_size / h;
        if ((size_t)st.st_size % h != 0 || stride < (size_t)w * 3 || stride > (size_t)w * 4 ||
            fread(raw, 1, (size_t)st.st_size, f) != (size_t)st.st_size) {
            fprintf(stderr, "cam2mcf: %s: %lld bytes is not %u rows of >= %u\n", argv[i],
                    (long long)st.st_size, h, w * 3);
            return 2;
        }
        fclose(f);
        mn_pixfmt_to_y8(fmt, raw, stride, w, h, y8, w);
        if (mn_ff_writer_add(wr, (uint64_t)(i - 6), 0, y8, w) < 0) {
            fprintf(stderr, "cam2mcf: write: %s\n", strerror(errno));
            return 2;
        }
        uint64_t sum = 0;
        uint8_t lo = 255, hi = 0;
        for (size_t k = 0; k < (size_t)w * h; k++) {
            sum += y8[k];
            lo = y8[k] < lo ? y8[k] : lo;
            hi = y8[k] > hi ? y8[k] : hi;
        }
        printf("cam2mcf: %s (stride %zu) -> frame %d, luma %u..%u mean %.1f\n", argv[i], stride,
               i - 6, lo, hi, (double)sum / ((double)w * h));
    }
    free(raw);
    free(y8);
    return mn_ff_writer_close(wr) < 0 ? 2 : 0;
}

/* ---- ctrl ---------------------------------------------------------------------------------- */

static int cmd_ctrl(char **argv)
{
    int fd = open(argv[2], O_RDWR | O_CLOEXEC);
    if (fd < 0) {
        fprintf(stderr, "ctrl: %s: %s\n", argv[2], strerror(errno));
        return 2;
    }
    struct v4l2_queryctrl q;
    memset(&q, 0, sizeof(q));
    q.id = V4L2_CTRL_FLAG_NEXT_CTRL;
    while (ioctl(fd, VIDIOC_QUERYCTRL, &q) == 0) {
        if (strcmp((const char *)q.name, argv[3]) == 0) {
            struct v4l2_control c = {.id = q.id, .value = atoi(argv[4])};
            if (ioctl(fd, VIDIOC_S_CTRL, &c) < 0) {
                fprintf(stderr, "ctrl: %s \"%s\" = %s: %s\n", argv[2], argv[3], argv[4],
                        strerror(errno));
                return 1;
            }
            close(fd);
            return 0;
        }
        q.id |= V4L2_CTRL_FLAG_NEXT_CTRL;
    }
    fprintf(stderr, "ctrl: %s has no control \"%s\"\n", argv[2], argv[3]);
    return 1;
}

/* ---- rate ---------------------------------------------------------------------------------- */

static int cmd_rate(char **argv)
{
    int fd = open(argv[2], O_RDWR | O_CLOEXEC);
    if (fd < 0) {
        fprintf(stderr, "rate: %s: %s\n", argv[2], strerror(errno));
        return 2;
    }
    struct v4l2_format fmt;
    memset(&fmt, 0, sizeof(fmt));
    fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    fmt.fmt.pix.width = (uint32_t)strtoul(argv[3], NULL, 10);
    fmt.fmt.pix.height = (uint32_t)strtoul(argv[4], NULL, 10);
    fmt.fmt.pix.pixelformat = V4L2_PIX_FMT_GREY;
    fmt.fmt.pix.field = V4L2_FIELD_NONE;
    struct v4l2_streamparm parm;
    memset(&parm, 0, sizeof(parm));
    parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    parm.parm.capture.timeperframe.numerator = 1;
    parm.parm.capture.timeperframe.denominator = (uint32_t)strtoul(argv[5], NULL, 10);
    if (ioctl(fd, VIDIOC_S_FMT, &fmt) < 0 || ioctl(fd, VIDIOC_S_PARM, &parm) < 0) {
        fprintf(stderr, "rate: %s: %s\n", argv[2], strerror(errno));
        return 1;
    }
    printf("rate: %s %ux%u at %u/%u s\n", argv[2], fmt.fmt.pix.width, fmt.fmt.pix.height,
           parm.parm.capture.timeperframe.numerator, parm.parm.capture.timeperframe.denominator);
    close(fd);
    return 0;
}

int main(int argc, char **argv)
{
    if ((argc == 5 || argc == 8) && strcmp(argv[1], "recv") == 0)
        return cmd_recv(argc, argv);
    if (argc == 10 && strcmp(argv[1], "gpio") == 0)
        return cmd_gpio(argv);
    if (argc >= 7 && strcmp(argv[1], "cam2mcf") == 0)
        return cmd_cam2mcf(argc, argv);
    if (argc == 5 && strcmp(argv[1], "ctrl") == 0)
        return cmd_ctrl(argv);
    if (argc == 6 && strcmp(argv[1], "rate") == 0)
        return cmd_rate(argv);
    fprintf(stderr, "usage: %s recv PORT DUMP NODE_PID [EXPOSURE_US GAIN_MILLI AFTER_S]\n"
                    "       %s gpio PORT PULL_FILE RATE_HZ EDGES SKIP_EVERY rising|falling "
                    "DELAY_US NODE_PID\n"
                    "       %s cam2mcf RGB888|BGR888 WIDTH HEIGHT OUTDIR FILE...\n"
                    "       %s ctrl DEVICE NAME VALUE\n"
                    "       %s rate DEVICE WIDTH HEIGHT FPS\n",
            argv[0], argv[0], argv[0], argv[0], argv[0]);
    return 2;
}
