/* The node's poll loop: frames in, numbered, detected, encoded and sent; control datagrams
 * applied; status, camera reopen, preview and watchdog driven by deadlines of the same loop.
 * Module start order: net, control, sync, pairing, capture, detector; freed in reverse. */
#include "node/node.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "common/clock.h"
#include "common/log.h"
#include "common/ratelimit.h"
#include "detect/detect.h"
#include "capture/capture.h"
#include "node/auth.h"
#include "node/control.h"
#include "node/net.h"
#include "node/notify.h"
#include "node/preview.h"
#include "node/status.h"
#include "sync/sync.h"
#include "wire/wire.h"

#define MAX_BLOBS MN_WIRE_MAX_MARKERS
#define EDGE_BATCH 64
#define FRAMES_PER_STEP 4        /* bounded work per iteration keeps control responsive */
#define DATAGRAMS_PER_STEP 32
#define PREVIEW_CHUNKS_PER_STEP 8
/* Rejected-datagram log lines: 5 per 10 s, the rest counted and reported once. */
#define REJECT_LOG_INTERVAL_NS (10LL * 1000000000LL)
#define REJECT_LOG_BURST 5

struct preview_state {
    bool requested;            /* waiting for the next frame to render */
    bool thresholded;
    uint32_t downscale;
    bool sending;
    uint32_t w, h, next_chunk, chunk_count;
    uint64_t frame_number;
    uint8_t *image;            /* capture-sized, allocated at start */
    size_t cap;
};

struct mn_node {
    struct mn_config cfg;
    struct mn_grid grid;
    bool running;
    bool finished;

    struct mn_net *net;
    struct mn_auth auth;
    struct mn_control *control;
    struct mn_sync *sync;        /* NULL while a failed trigger source is being reopened */
    bool free_run;               /* the configured sync source has no edges */
    bool hardware_lost;          /* camera or trigger gone for good: exit 3, systemd restarts */
    struct mn_pairing *pairing;
    struct mn_capture *capture;  /* NULL while the camera is being reopened */
    struct mn_detector *detector;
    uint32_t max_w, max_h;

    int64_t reopen_at_ns;
    uint32_t reopen_delay_ms;
    bool have_last_sequence;
    uint64_t last_sequence;
    uint32_t threshold, exposure_us, gain_milli;
    bool auto_threshold;

    struct mn_blob blobs[MAX_BLOBS];
    struct mn_wire_marker markers[MAX_BLOBS];
    int64_t edges[EDGE_BATCH];
    mocap_v1_Packet packet;
    uint8_t datagram[MN_ENVELOPE_MAX_DATAGRAM];
    uint8_t rx[MN_WIRE_MAX_DATAGRAM + 1];
    struct preview_state preview;
    char apply_error[MN_WIRE_MAX_ACK_REASON + 1]; /* why the last command failed, for its ack */

    int stop_fd;
    int64_t start_ns, end_ns;    /* end_ns 0: no time bound */
    int64_t next_status_ns;
    int64_t next_watchdog_ns, watchdog_interval_ns;
    int64_t identify_until_ns;   /* 0: not identifying */

    struct mn_node_stats stats;
    struct mn_ratelimit reject_log; /* rejected datagrams: a chatty host must not flood the journal */
    /* Status interval accumulators. */
    int64_t interval_start_ns;
    uint64_t interval_frames, detect_ns_sum, detect_ns_max, detect_count;
};

static void node_grid_init(struct mn_node *n)
{
    n->grid.real_minus_mono_ns = mn_clock_real_minus_mono_ns();
    n->grid.rate_millihz = mn_grid_rate_millihz(n->cfg.rate_hz);
    n->grid.epoch_real_ns = n->cfg.epoch_ns;
    if (n->grid.epoch_real_ns == 0) {
        /* No session epoch yet: frame 0 is the next whole period from now (a hub Start or
         * announce replaces it). */
        int64_t now = mn_clock_real_ns();
        int64_t period = mn_grid_period_ns(&n->grid);
        n->grid.epoch_real_ns = (now / period + 1) * period;
    }
}

/* A picture control from the config (pct -1: left as the camera has it). */
/* Sets a picture control (pct < 0: leave the camera's own); 0, or -1 with errno after a warning. */
static int set_picture(struct mn_capture *c, enum mn_picture_control which, const char *name,
                       int32_t pct)
{
    if (pct < 0)
        return 0;
    double value = 0;
    if (mn_capture_set_picture(c, which, (uint32_t)pct, &value) < 0) {
        int e = errno;
        mn_log_warn("%s: cannot set %s: %s", mn_capture_name(c), name, strerror(e));
        errno = e;
        return -1;
    }
    mn_log_info("%s: %s %d %% of the camera's range = %g", mn_capture_name(c), name, pct, value);
    return 0;
}

static int open_capture(struct mn_node *n, char *err, size_t errlen)
{
    const struct mn_config *cfg = &n->cfg;
    const struct mn_capture_params params = {
        .kind = cfg->source_kind,
        .arg = cfg->source_arg,
        .width = cfg->width,
        .height = cfg->height,
        .buffers = cfg->buffers,
        .pixel_format = cfg->pixel_format,
        .replay = {.dir = cfg->source_arg,
                   .grid = n->grid,
                   .trigger_delay_ns = (int64_t)cfg->trigger_delay_us * 1000,
                   .as_fast_as_possible = cfg->as_fast_as_possible,
                   .loop = cfg->replay_loop},
    };
    struct mn_capture *c = mn_capture_open(&params, err, errlen);
    if (c == NULL)
        return -1;
    if (mn_capture_start(c) < 0) {
        int e = errno;
        snprintf(err, errlen, "%s: cannot start streaming: %s", n->cfg.source_arg, strerror(e));
        mn_capture_close(c);
        errno = e;
        return -1;
    }
    /* Controls the hub (or the config) set survive a reopen. */
    if (n->exposure_us != 0 && mn_capture_set_exposure(c, n->exposure_us) < 0)
        mn_log_warn("%s: cannot set exposure %u us: %s", mn_capture_name(c), n->exposure_us,
                    strerror(errno));
    if (n->gain_milli != 0 && mn_capture_set_gain(c, n->gain_milli) < 0)
        mn_log_warn("%s: cannot set gain %u/1000: %s", mn_capture_name(c), n->gain_milli,
                    strerror(errno));
    (void)set_picture(c, MN_PICTURE_BRIGHTNESS, "brightness", n->cfg.brightness_pct);
    (void)set_picture(c, MN_PICTURE_CONTRAST, "contrast", n->cfg.contrast_pct);
    n->capture = c;
    n->have_last_sequence = false;
    return 0;
}

static void camera_failed(struct mn_node *n, const char *what, int e)
{
    n->stats.camera_errors++;
    /* e 0: what already says why (a reopen's own message). */
    mn_log_err("camera %s: %s%s%s; reopening in %u ms", n->cfg.source_arg, what, e ? ": " : "",
               e ? strerror(e) : "", n->reopen_delay_ms);
    mn_capture_close(n->capture);
    n->capture = NULL;
    n->reopen_at_ns = mn_clock_mono_ns() + (int64_t)n->reopen_delay_ms * 1000000;
    /* Exponential backoff: a camera that keeps failing is not hammered. */
    n->reopen_delay_ms = n->reopen_delay_ms * 2 > n->cfg.reopen_max_ms ? n->cfg.reopen_max_ms
                                                                       : n->reopen_delay_ms * 2;
}

static void try_reopen(struct mn_node *n)
{
    char err[MN_CONFIG_ERR];
    if (open_capture(n, err, sizeof(err)) < 0) {
        camera_failed(n, err, 0);
        return;
    }
    n->stats.camera_reopens++;
    mn_log_notice("camera %s reopened", n->cfg.source_arg);
}

/* A new epoch or rate: the pairing forgets its edges, the simulated trigger and a replay
 * restart on the new grid. */
static void set_grid(struct mn_node *n, int64_t epoch_ns, uint32_t rate_millihz)
{
    if (epoch_ns == n->grid.epoch_real_ns && rate_millihz == n->grid.rate_millihz)
        return;
    n->grid.epoch_real_ns = epoch_ns;
    n->grid.rate_millihz = rate_millihz;
    n->grid.real_minus_mono_ns = mn_clock_real_minus_mono_ns();
    mn_pairing_set_grid(n->pairing, &n->grid);
    if (n->sync != NULL)
        mn_sync_set_grid(n->sync, &n->grid);
    mn_log_notice("session grid: epoch %lld ns, %.3f Hz", (long long)epoch_ns,
                  rate_millihz / 1000.0);
    if (n->cfg.source_kind == MN_SOURCE_REPLAY && n->capture != NULL) {
        char err[MN_CONFIG_ERR];
        mn_capture_close(n->capture);
        n->capture = NULL;
        if (open_capture(n, err, sizeof(err)) < 0) {
            mn_log_err("replay restart: %s", err);
            n->reopen_at_ns = mn_clock_mono_ns();
        }
    }
}

struct mn_node *mn_node_new(const struct mn_config *cfg, char *err, size_t errlen)
{
    struct mn_node *n = calloc(1, sizeof(*n));
    if (n == NULL) {
        snprintf(err, errlen, "out of memory");
        return NULL;
    }
    int e;
    n->cfg = *cfg;
    n->stop_fd = -1;
    n->running = !cfg->wait_for_start;
    n->threshold = cfg->threshold;
    n->auto_threshold = cfg->auto_threshold;
    n->exposure_us = cfg->exposure_us;
    n->gain_milli = cfg->gain_milli;
    n->reopen_delay_ms = cfg->reopen_min_ms;
    node_grid_init(n);

    if (mn_auth_init(&n->auth, cfg->node_id, cfg->insecure_dev_wire ? NULL : &cfg->keys, err,
                     errlen) < 0) {
        errno = EINVAL;
        goto fail;
    }
    if (cfg->insecure_dev_wire)
        mn_log_warn("INSECURE WIRE: insecure_dev_wire is set, datagrams are not authenticated; "
                    "anyone on the network can steer this node (development only)");
    n->net = mn_net_new(cfg->hub_host, cfg->hub_port, cfg->control_port, cfg->announce_port,
                        cfg->send_buffer_kb, err, errlen);
    if (n->net == NULL)
        goto fail;
    n->control = mn_control_new(cfg->node_id);
    if (n->control == NULL) {
        snprintf(err, errlen, "out of memory");
        goto fail;
    }
    const struct mn_sync_params sync = {
        .kind = cfg->sync_kind,
        .gpio = {.chip = cfg->gpio_chip, .line = cfg->gpio_line, .falling = cfg->gpio_falling},
        .sim = {.grid = n->grid,
                .jitter_ns = (int64_t)cfg->sim_jitter_us * 1000,
                .missed = cfg->sim_missed,
                .spurious = cfg->sim_spurious,
                .seed = cfg->sim_seed},
    };
    n->sync = mn_sync_open(&sync, err, errlen);
    if (n->sync == NULL)
        goto fail;
    n->free_run = mn_sync_free_run(n->sync);
    n->pairing = mn_pairing_new(&n->grid, (int64_t)cfg->trigger_delay_us * 1000,
                                cfg->pair_window_pct);
    if (n->pairing == NULL) {
        snprintf(err, errlen, "pairing: %s", strerror(errno));
        goto fail;
    }
    if (open_capture(n, err, errlen) < 0)
        goto fail;
    mn_capture_max_size(n->capture, &n->max_w, &n->max_h);

    struct mn_detect_config dc;
    mn_detect_config_default(&dc);
    dc.threshold_mode = cfg->auto_threshold ? MN_THRESHOLD_AUTO : MN_THRESHOLD_FIXED;
    dc.threshold = (uint8_t)cfg->threshold;
    dc.min_area = cfg->min_area;
    dc.max_area = cfg->max_area;
    dc.morph_radius = (uint8_t)cfg->morph_radius;
    dc.centroid_mode = cfg->binary_centroid ? MN_CENTROID_BINARY : MN_CENTROID_WEIGHTED;
    dc.max_blobs = MAX_BLOBS;
    const char *bad = mn_detect_config_check(&dc);
    if (bad != NULL) {
        snprintf(err, errlen, "detector settings: %s", bad);
        errno = EINVAL;
        goto fail;
    }
    n->detector = mn_detector_new(&dc, n->max_w, n->max_h);
    if (n->detector == NULL) {
        snprintf(err, errlen, "detector for %ux%u: %s", n->max_w, n->max_h, strerror(errno));
        goto fail;
    }
    n->preview.cap = (size_t)n->max_w * n->max_h;
    n->preview.image = malloc(n->preview.cap);
    if (n->preview.image == NULL) {
        snprintf(err, errlen, "out of memory for the preview buffer");
        errno = ENOMEM;
        goto fail;
    }

    n->start_ns = mn_clock_mono_ns();
    n->end_ns = cfg->duration_s > 0 ? n->start_ns + (int64_t)(cfg->duration_s * 1e9) : 0;
    n->interval_start_ns = n->start_ns;
    n->next_status_ns = n->start_ns + (int64_t)cfg->status_interval_ms * 1000000;
    mn_ratelimit_init(&n->reject_log, REJECT_LOG_INTERVAL_NS, REJECT_LOG_BURST);
    n->watchdog_interval_ns = mn_notify_init();
    n->next_watchdog_ns = n->start_ns;
    mn_log_info("node %u: %s %s %ux%u, sync %s, hub %s, %s", cfg->node_id,
                mn_capture_name(n->capture), cfg->source_arg, n->max_w, n->max_h,
                mn_sync_name(n->sync), cfg->hub_host[0] ? cfg->hub_host : "(from announce)",
                n->running ? "running" : "waiting for start");
    return n;

fail:
    e = errno;
    mn_node_free(n);
    errno = e;
    return NULL;
}

void mn_node_free(struct mn_node *n)
{
    if (n == NULL)
        return;
    free(n->preview.image);
    mn_detector_free(n->detector);
    mn_capture_close(n->capture);
    mn_pairing_free(n->pairing);
    mn_sync_close(n->sync);
    mn_control_free(n->control);
    mn_net_free(n->net);
    free(n);
}

void mn_node_set_stop_fd(struct mn_node *n, int fd)
{
    n->stop_fd = fd;
}

uint16_t mn_node_local_port(const struct mn_node *n)
{
    return mn_net_local_port(n->net);
}

void mn_node_get_stats(const struct mn_node *n, struct mn_node_stats *out)
{
    *out = n->stats;
    struct mn_net_stats ns;
    mn_net_get_stats(n->net, &ns);
    out->datagrams_sent = ns.sent;
    out->datagrams_dropped = ns.dropped;
    out->running = n->running;
    out->camera_ok = n->capture != NULL;
    out->hub_known = mn_net_hub_known(n->net);
    mn_pairing_health(n->pairing, &out->sync);
}

static int send_packet(struct mn_node *n)
{
    size_t payload, size;
    const char *why;
    size_t offset = mn_auth_payload_offset(&n->auth);
    if (mn_wire_encode(&n->packet, n->datagram + offset, mn_auth_max_payload(&n->auth), &payload,
                       &why) < 0 ||
        mn_auth_seal(&n->auth, n->datagram, sizeof(n->datagram), payload, mn_clock_real_ns(), &size,
                     &why) < 0) {
        mn_log_err("encode: %s", why); /* our own bug: say so, never send it */
        errno = EPROTO;
        return -1;
    }
    return mn_net_send(n->net, n->datagram, size);
}

static void report_suppressed_rejections(uint64_t count)
{
    if (count)
        mn_log_warn("suppressed %llu similar messages (rejected datagrams; all are counted in "
                    "status)", (unsigned long long)count);
}

static void send_status(struct mn_node *n, int64_t now)
{
    report_suppressed_rejections(mn_ratelimit_flush(&n->reject_log, now));
    struct mn_status_counters c;
    memset(&c, 0, sizeof(c));
    c.node_id = n->cfg.node_id;
    c.state = n->capture == NULL ? mocap_v1_NodeState_NODE_STATE_CAMERA_ERROR
              : n->running       ? mocap_v1_NodeState_NODE_STATE_RUNNING
                                 : mocap_v1_NodeState_NODE_STATE_IDLE;
    c.uptime_ms = (uint64_t)(now - n->start_ns) / 1000000;
    c.frames_captured = n->stats.frames_captured;
    c.frames_sent = n->stats.frames_sent;
    c.frames_dropped = n->stats.frames_dropped;
    c.interval_frames = n->interval_frames;
    c.interval_ns = now - n->interval_start_ns;
    c.detect_ns_sum = n->detect_ns_sum;
    c.detect_ns_max = n->detect_ns_max;
    c.detect_count = n->detect_count;
    mn_pairing_health(n->pairing, &c.sync);
    c.threshold = n->auto_threshold ? mn_detector_stats(n->detector)->threshold : n->threshold;
    c.exposure_us = n->exposure_us;
    c.gain_milli = n->gain_milli;
    c.exposure_fixed = n->capture != NULL && mn_capture_exposure_fixed(n->capture);
    c.control_rejected = n->stats.control_rejected;
    c.auth_rejected = n->stats.auth_rejected;
    c.camera_reopens = n->stats.camera_reopens;
    c.width = n->max_w;
    c.height = n->max_h;
    mn_status_build(&c, n->cfg.temperature_path, &n->packet);
    send_packet(n);
    /* One line for `systemctl status`; the same at debug level in the journal. */
    const char *state = c.state == mocap_v1_NodeState_NODE_STATE_CAMERA_ERROR ? "camera error"
                        : n->running                                       ? "running"
                                                                           : "idle";
    char line[160];
    snprintf(line, sizeof(line), "%s, %.1f fps, %llu sent, %llu dropped, %u unmatched", state,
             n->packet.body.node_status.fps_milli / 1000.0, (unsigned long long)c.frames_sent,
             (unsigned long long)c.frames_dropped, c.sync.unmatched_frames);
    mn_notify_status(line);
    mn_log_debug("status: %s", line);
    n->interval_start_ns = now;
    n->interval_frames = n->detect_ns_sum = n->detect_ns_max = n->detect_count = 0;
    /* Follow chrony's slewing of the realtime clock; changes below a microsecond are sampling
     * noise and would only jitter the time stamps we send. */
    int64_t offset = mn_clock_real_minus_mono_ns();
    if (llabs(offset - n->grid.real_minus_mono_ns) > 1000) {
        n->grid.real_minus_mono_ns = offset;
        mn_pairing_set_grid(n->pairing, &n->grid);
    }
}

static void set_identify_led(struct mn_node *n, bool on)
{
    int fd = open(n->cfg.identify_led, O_WRONLY | O_CLOEXEC);
    if (fd < 0 || write(fd, on ? "1\n" : "0\n", 2) != 2)
        mn_log_warn("identify LED %s: %s", n->cfg.identify_led, strerror(errno));
    if (fd >= 0)
        close(fd);
}

/* Logs why a command could not be applied and keeps the text for its ControlAck. */
static const char *apply_failed(struct mn_node *n, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

static const char *apply_failed(struct mn_node *n, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(n->apply_error, sizeof(n->apply_error), fmt, ap);
    va_end(ap);
    mn_log_warn("%s", n->apply_error);
    return n->apply_error;
}

/* NULL when the command took effect, otherwise why not (valid until the next command). */
static const char *apply_command(struct mn_node *n, const struct mn_command *cmd,
                                 uint32_t from_ipv4)
{
    const char *failed = NULL;
    switch (cmd->kind) {
    case MN_CMD_NONE:
        break;
    case MN_CMD_START:
        set_grid(n, cmd->u.start.epoch_ns, cmd->u.start.rate_millihz);
        if (!n->running)
            mn_log_notice("start (control %u)", cmd->sequence);
        n->running = true;
        break;
    case MN_CMD_STOP:
        if (n->running)
            mn_log_notice("stop (control %u)", cmd->sequence);
        n->running = false;
        break;
    case MN_CMD_THRESHOLD:
        n->auto_threshold = cmd->u.threshold.automatic;
        if (!n->auto_threshold)
            n->threshold = cmd->u.threshold.value;
        mn_detector_set_threshold(n->detector,
                                  n->auto_threshold ? MN_THRESHOLD_AUTO : MN_THRESHOLD_FIXED,
                                  (uint8_t)n->threshold);
        mn_log_info("threshold %s %u", n->auto_threshold ? "auto" : "fixed", n->threshold);
        break;
    case MN_CMD_EXPOSURE:
        if (cmd->u.exposure.exposure_us != 0)
            n->exposure_us = cmd->u.exposure.exposure_us;
        if (cmd->u.exposure.gain_milli != 0)
            n->gain_milli = cmd->u.exposure.gain_milli;
        if (n->capture != NULL && cmd->u.exposure.exposure_us != 0 &&
            mn_capture_set_exposure(n->capture, n->exposure_us) < 0)
            failed = apply_failed(n, "cannot set exposure %u us: %s", n->exposure_us,
                                  strerror(errno));
        if (n->capture != NULL && cmd->u.exposure.gain_milli != 0 &&
            mn_capture_set_gain(n->capture, n->gain_milli) < 0 && failed == NULL)
            failed = apply_failed(n, "cannot set gain %u/1000: %s", n->gain_milli,
                                  strerror(errno));
        break;
    case MN_CMD_PICTURE: {
        /* Kept like exposure: set again at every reopen (the config's values are the start). */
        const int32_t pct[2] = {cmd->u.picture.brightness_pct, cmd->u.picture.contrast_pct};
        const char *const name[2] = {"brightness", "contrast"};
        int32_t *kept[2] = {&n->cfg.brightness_pct, &n->cfg.contrast_pct};
        for (int i = 0; i < 2; i++) {
            if (pct[i] < 0)
                continue;
            *kept[i] = pct[i];
            if (n->capture != NULL &&
                set_picture(n->capture, i == 0 ? MN_PICTURE_BRIGHTNESS : MN_PICTURE_CONTRAST,
                            name[i], pct[i]) < 0 && failed == NULL)
                failed = apply_failed(n, "cannot set %s %d %%: %s", name[i], pct[i],
                                      errno == ENOTSUP ? "the camera has no such control"
                                                       : strerror(errno));
        }
        break;
    }
    case MN_CMD_MASK_CLEAR:
        mn_detector_clear_mask(n->detector);
        mn_log_info("mask cleared");
        break;
    case MN_CMD_MASK_RECTS: {
        struct mn_rect rects[MN_CONTROL_MAX_RECTS];
        for (size_t i = 0; i < cmd->u.rects.n; i++) {
            rects[i].x = cmd->u.rects.rects[i].x;
            rects[i].y = cmd->u.rects.rects[i].y;
            rects[i].w = cmd->u.rects.rects[i].w;
            rects[i].h = cmd->u.rects.rects[i].h;
        }
        if (mn_detector_set_mask_rects(n->detector, rects, cmd->u.rects.n) < 0)
            failed = apply_failed(n, "mask rectangles refused: %s", strerror(errno));
        else
            mn_log_info("mask: %zu rectangles", cmd->u.rects.n);
        break;
    }
    case MN_CMD_MASK_BITS:
        if (mn_detector_set_mask_bits(n->detector, cmd->u.bits.cell_px, cmd->u.bits.cells_x,
                                      cmd->u.bits.cells_y, cmd->u.bits.bits) < 0)
            failed = apply_failed(n, "mask image refused: %s", strerror(errno));
        else
            mn_log_info("mask: %ux%u cells of %u px", cmd->u.bits.cells_x, cmd->u.bits.cells_y,
                        cmd->u.bits.cell_px);
        break;
    case MN_CMD_PREVIEW:
        n->preview.requested = true;
        n->preview.thresholded = cmd->u.preview.thresholded;
        n->preview.downscale = cmd->u.preview.downscale;
        break;
    case MN_CMD_IDENTIFY: {
        uint32_t ms = cmd->u.identify.duration_ms ? cmd->u.identify.duration_ms : 5000;
        mn_log_notice("IDENTIFY: node %u, %u ms%s", n->cfg.node_id, ms,
                      n->cfg.identify_led[0] ? "" : " (no identify_led configured)");
        if (n->cfg.identify_led[0])
            set_identify_led(n, true);
        n->identify_until_ns = mn_clock_mono_ns() + (int64_t)ms * 1000000;
        break;
    }
    case MN_CMD_ANNOUNCE:
        if (mn_net_set_hub_from_announce(n->net, from_ipv4, cmd->u.announce.port))
            mn_log_notice("hub found by announce, port %u", cmd->u.announce.port);
        if (cmd->u.announce.rate_millihz != 0 && cmd->u.announce.epoch_ns != 0)
            set_grid(n, cmd->u.announce.epoch_ns, cmd->u.announce.rate_millihz);
        break;
    }
    return failed;
}

/* Answers one Control addressed to this node, so the hub knows its request's fate. */
static void send_ack(struct mn_node *n, uint32_t sequence, enum mn_control_result r,
                     const char *why)
{
    switch (r) {
    case MN_CONTROL_ACCEPTED:
        mn_wire_control_ack(n->cfg.node_id, sequence, mocap_v1_ControlResult_CONTROL_RESULT_APPLIED,
                            NULL, &n->packet);
        break;
    case MN_CONTROL_IGNORED:
        mn_wire_control_ack(n->cfg.node_id, sequence, mocap_v1_ControlResult_CONTROL_RESULT_IGNORED,
                            why, &n->packet);
        break;
    case MN_CONTROL_REJECTED:
        mn_wire_control_ack(n->cfg.node_id, sequence,
                            mocap_v1_ControlResult_CONTROL_RESULT_REJECTED, why, &n->packet);
        break;
    }
    send_packet(n);
}

static void handle_datagrams(struct mn_node *n, int fd, bool announce_socket)
{
    for (int i = 0; i < DATAGRAMS_PER_STEP; i++) {
        bool from_hub = false;
        uint32_t from_ipv4 = 0;
        ssize_t len = mn_net_recv(n->net, fd, n->rx, sizeof(n->rx), &from_hub, &from_ipv4);
        if (len <= 0) {
            if (len < 0)
                mn_log_warn("receive: %s", strerror(errno));
            return;
        }
        const char *why = NULL;
        struct mn_command cmd;
        enum mn_control_result r;
        memset(&cmd, 0, sizeof(cmd));
        if (!announce_socket && !from_hub) {
            r = MN_CONTROL_REJECTED; /* control only from the hub we send to */
            why = mn_net_hub_known(n->net) ? "control from a host that is not the hub"
                                           : "control before the hub is known";
        } else if ((size_t)len > MN_WIRE_MAX_DATAGRAM) {
            r = MN_CONTROL_REJECTED;
            why = "datagram larger than 1400 bytes";
        } else {
            const uint8_t *payload = NULL;
            size_t payload_len = 0;
            enum mn_auth_result a = mn_auth_open(&n->auth, n->rx, (size_t)len, mn_clock_real_ns(),
                                                 &payload, &payload_len, &why);
            if (a == MN_AUTH_OTHER_NODE) {
                n->stats.auth_other_node++; /* a neighbour's announce on a shared port */
                continue;
            }
            if (a == MN_AUTH_REJECTED) {
                /* Forged, replayed, stale or plain: never parsed, never answered. */
                n->stats.auth_rejected++;
                uint64_t earlier;
                if (mn_ratelimit_allow(&n->reject_log, mn_clock_mono_ns(), &earlier)) {
                    report_suppressed_rejections(earlier);
                    mn_log_warn("rejected unauthentic %s datagram (%zd bytes): %s",
                                announce_socket ? "announce" : "control", len, why);
                }
                continue;
            }
            r = mn_control_handle(n->control, payload, payload_len, announce_socket, &cmd, &why);
        }
        if (r == MN_CONTROL_REJECTED) {
            n->stats.control_rejected++;
            uint64_t earlier;
            if (mn_ratelimit_allow(&n->reject_log, mn_clock_mono_ns(), &earlier)) {
                report_suppressed_rejections(earlier);
                mn_log_warn("rejected %s datagram (%zd bytes): %s",
                            announce_socket ? "announce" : "control", len, why);
            }
        } else if (r == MN_CONTROL_IGNORED) {
            n->stats.control_ignored++;
        } else if ((why = apply_command(n, &cmd, from_ipv4)) != NULL) {
            r = MN_CONTROL_REJECTED; /* well-formed, but the camera or detector refused it */
            n->stats.control_rejected++;
        } else {
            n->stats.control_accepted++;
        }
        if (cmd.acknowledge)
            send_ack(n, cmd.sequence, r, why);
    }
}

/* A trigger source that fails (GPIO chip gone) ends the run as "hardware missing" (exit 3):
 * frames without their edges would carry numbers guessed from time stamps, which the hub cannot
 * tell from good ones in a synchronised rig, and systemd restarts the node, which then waits for
 * the chip at start like any missing hardware. */
static void sync_failed(struct mn_node *n, int e)
{
    mn_log_err("trigger %s: %s; exiting (status 3) to be restarted", mn_sync_name(n->sync),
               strerror(e));
    mn_sync_close(n->sync);
    n->sync = NULL;
    n->hardware_lost = true;
    n->finished = true;
}

static void drain_sync(struct mn_node *n, int64_t until_mono_ns)
{
    while (n->sync != NULL) {
        size_t got = 0;
        if (mn_sync_read(n->sync, until_mono_ns, n->edges, EDGE_BATCH, &got) < 0) {
            sync_failed(n, errno);
            return;
        }
        for (size_t i = 0; i < got; i++)
            mn_pairing_add_edge(n->pairing, n->edges[i]);
        if (got < EDGE_BATCH)
            return;
    }
}

static void send_frame(struct mn_node *n, const struct mn_frame *f, const struct mn_pair_result *pr,
                       size_t n_blobs)
{
    int64_t offset = n->grid.real_minus_mono_ns;
    mocap_v1_MarkerFrame header = mocap_v1_MarkerFrame_init_zero;
    header.node_id = n->cfg.node_id;
    header.frame_number = (uint64_t)pr->frame_number;
    bool free_run = n->free_run;
    header.trigger_time_ns = free_run ? 0 : (uint64_t)(pr->trigger_mono_ns + offset);
    header.capture_time_ns = (uint64_t)(f->capture_mono_ns + offset);
    header.exposure_us = n->exposure_us;
    header.width = f->width;
    header.height = f->height;
    header.flags = free_run ? mocap_v1_FrameFlag_FRAME_FLAG_FREE_RUN
                   : pr->matched ? 0 : mocap_v1_FrameFlag_FRAME_FLAG_UNMATCHED;
    for (size_t i = 0; i < n_blobs; i++) {
        n->markers[i].x = n->blobs[i].x;
        n->markers[i].y = n->blobs[i].y;
        n->markers[i].area = n->blobs[i].area;
        n->markers[i].peak = n->blobs[i].peak;
        n->markers[i].mean = n->blobs[i].mean;
        n->markers[i].flags = n->blobs[i].flags;
    }
    uint32_t chunks = mn_wire_chunk_count(n_blobs);
    bool all_sent = true;
    for (uint32_t i = 0; i < chunks; i++) {
        const char *why;
        header.send_time_ns = (uint64_t)mn_clock_real_ns();
        if (mn_wire_frame_chunk(&header, n->markers, n_blobs, i, &n->packet, &why) < 0) {
            mn_log_err("frame chunk: %s", why);
            all_sent = false;
            break;
        }
        if (send_packet(n) < 0)
            all_sent = false;
    }
    if (all_sent) {
        n->stats.frames_sent++;
        n->stats.markers_sent += n_blobs;
    } else {
        n->stats.frames_dropped++;
    }
}

static void start_preview(struct mn_node *n, const struct mn_frame *f, uint64_t frame_number)
{
    struct preview_state *p = &n->preview;
    p->requested = false;
    /* Thresholded previews show what the detector sees: in auto mode, its latest estimate. */
    uint8_t t = n->auto_threshold ? mn_detector_stats(n->detector)->threshold
                                  : (uint8_t)n->threshold;
    if (mn_preview_render(f->pixels, f->width, f->height, f->stride, p->downscale,
                          p->thresholded, t, p->image, p->cap, &p->w, &p->h) < 0) {
        mn_log_warn("preview: cannot render %ux%u / %u", f->width, f->height, p->downscale);
        return;
    }
    p->sending = true;
    p->next_chunk = 0;
    p->chunk_count = mn_preview_chunk_count(p->w, p->h);
    p->frame_number = frame_number;
}

static void send_preview_chunks(struct mn_node *n)
{
    struct preview_state *p = &n->preview;
    for (int i = 0; i < PREVIEW_CHUNKS_PER_STEP && p->sending; i++) {
        mn_preview_chunk(p->image, p->w, p->h, p->thresholded, n->cfg.node_id, p->frame_number,
                         p->next_chunk, &n->packet);
        send_packet(n);
        if (++p->next_chunk == p->chunk_count)
            p->sending = false;
    }
}

static void process_frame(struct mn_node *n, const struct mn_frame *f)
{
    n->stats.frames_captured++;
    if (n->have_last_sequence && f->sequence > n->last_sequence + 1)
        n->stats.frames_dropped += f->sequence - n->last_sequence - 1;
    n->have_last_sequence = true;
    n->last_sequence = f->sequence;
    n->reopen_delay_ms = n->cfg.reopen_min_ms; /* frames flow: the next failure starts over */

    struct mn_pair_result pr;
    if (n->free_run) {
        mn_pairing_free_run(n->pairing, f->capture_mono_ns, &pr);
    } else {
        int64_t window = mn_grid_period_ns(&n->grid) * n->cfg.pair_window_pct / 100;
        drain_sync(n, f->capture_mono_ns - (int64_t)n->cfg.trigger_delay_us * 1000 + window);
        mn_pairing_match(n->pairing, f->capture_mono_ns, &pr);
    }
    if (n->preview.requested && !n->preview.sending)
        start_preview(n, f, pr.frame_number < 0 ? 0 : (uint64_t)pr.frame_number);
    if (!n->running)
        return;
    if (pr.frame_number < 0) {
        n->stats.frames_before_epoch++;
        return;
    }
    if (f->width > n->max_w || f->height > n->max_h) {
        n->stats.frames_dropped++;
        mn_log_warn("frame %ux%u larger than at start (%ux%u): dropped", f->width, f->height,
                    n->max_w, n->max_h);
        return;
    }
    int64_t t0 = mn_clock_mono_ns();
    size_t n_blobs = 0;
    if (mn_detector_run(n->detector, f->pixels, f->width, f->height, f->stride, n->blobs,
                        MAX_BLOBS, &n_blobs) < 0) {
        n->stats.frames_dropped++;
        mn_log_warn("detector refused a %ux%u frame: %s", f->width, f->height, strerror(errno));
        return;
    }
    int64_t dt = mn_clock_mono_ns() - t0;
    n->detect_ns_sum += (uint64_t)dt;
    if ((uint64_t)dt > n->detect_ns_max)
        n->detect_ns_max = (uint64_t)dt;
    n->detect_count++;
    n->interval_frames++;
    n->stats.frames_processed++;
    send_frame(n, f, &pr, n_blobs);
    if (n->cfg.frames != 0 && n->stats.frames_processed >= n->cfg.frames)
        n->finished = true;
}

static void handle_capture(struct mn_node *n)
{
    for (int i = 0; i < FRAMES_PER_STEP && n->capture != NULL && !n->finished; i++) {
        struct mn_frame f;
        int rc = mn_capture_dequeue(n->capture, &f);
        if (rc == 0)
            return;
        if (rc < 0) {
            if (errno == ENODATA) {
                mn_log_info("recording ended after %llu frames",
                            (unsigned long long)n->stats.frames_captured);
                n->finished = true;
                return;
            }
            if (errno == ENOTRECOVERABLE) {
                mn_log_err("camera %s: gone and not reopenable by this process; exiting "
                           "(status 3) to be restarted", n->cfg.source_arg);
                n->hardware_lost = true;
                n->finished = true;
                return;
            }
            camera_failed(n, "capture failed", errno);
            return;
        }
        process_frame(n, &f);
        if (mn_capture_release(n->capture, &f) < 0) {
            camera_failed(n, "cannot requeue a buffer", errno);
            return;
        }
    }
}

static int64_t min_deadline(int64_t a, int64_t b)
{
    return (b != 0 && b < a) ? b : a;
}

int mn_node_step(struct mn_node *n, int max_wait_ms)
{
    if (n->finished)
        return 0;
    int64_t now = mn_clock_mono_ns();
    int64_t deadline = now + (int64_t)max_wait_ms * 1000000;
    deadline = min_deadline(deadline, n->next_status_ns);
    deadline = min_deadline(deadline, n->end_ns);
    deadline = min_deadline(deadline, n->identify_until_ns);
    if (n->watchdog_interval_ns > 0)
        deadline = min_deadline(deadline, n->next_watchdog_ns);
    if (n->capture == NULL)
        deadline = min_deadline(deadline, n->reopen_at_ns);
    if (n->preview.sending || (n->capture != NULL && mn_capture_fd(n->capture) < 0))
        deadline = now; /* work is waiting: only look at the descriptors */

    struct pollfd fds[5];
    int nfds = 0, cap_i = -1, sync_i = -1, net_i, ann_i = -1, stop_i = -1;
    net_i = nfds;
    fds[nfds++] = (struct pollfd){.fd = mn_net_fd(n->net), .events = POLLIN};
    if (mn_net_announce_fd(n->net) >= 0) {
        ann_i = nfds;
        fds[nfds++] = (struct pollfd){.fd = mn_net_announce_fd(n->net), .events = POLLIN};
    }
    if (n->sync != NULL && mn_sync_fd(n->sync) >= 0) {
        sync_i = nfds;
        fds[nfds++] = (struct pollfd){.fd = mn_sync_fd(n->sync), .events = POLLIN};
    }
    if (n->capture != NULL && mn_capture_fd(n->capture) >= 0) {
        cap_i = nfds;
        fds[nfds++] = (struct pollfd){.fd = mn_capture_fd(n->capture), .events = POLLIN};
    }
    if (n->stop_fd >= 0) {
        stop_i = nfds;
        fds[nfds++] = (struct pollfd){.fd = n->stop_fd, .events = POLLIN};
    }
    int64_t wait_ns = deadline - now;
    int timeout_ms = wait_ns <= 0 ? 0 : (int)((wait_ns + 999999) / 1000000);
    int rc = poll(fds, (nfds_t)nfds, timeout_ms);
    if (rc < 0 && errno != EINTR) {
        mn_log_err("poll: %s", strerror(errno));
        return -1;
    }
    if (rc < 0)
        rc = 0;

    if (stop_i >= 0 && (fds[stop_i].revents & POLLIN)) {
        mn_log_notice("stop requested");
        n->finished = true;
        return 0;
    }
    if (fds[net_i].revents & POLLIN)
        handle_datagrams(n, fds[net_i].fd, false);
    if (ann_i >= 0 && (fds[ann_i].revents & POLLIN))
        handle_datagrams(n, fds[ann_i].fd, true);
    if (sync_i >= 0 && (fds[sync_i].revents & (POLLIN | POLLERR | POLLHUP)))
        drain_sync(n, mn_clock_mono_ns());
    if (n->capture != NULL) {
        if (cap_i < 0 || (fds[cap_i].revents & POLLIN))
            handle_capture(n);
        else if (cap_i >= 0 && (fds[cap_i].revents & (POLLERR | POLLHUP | POLLNVAL)))
            /* V4L2 reports an unplugged device as POLLERR; dequeue gives the reason. */
            handle_capture(n);
    }
    if (n->preview.sending)
        send_preview_chunks(n);

    now = mn_clock_mono_ns();
    if (n->capture == NULL && now >= n->reopen_at_ns)
        try_reopen(n);
    if (n->identify_until_ns != 0 && now >= n->identify_until_ns) {
        n->identify_until_ns = 0;
        if (n->cfg.identify_led[0])
            set_identify_led(n, false);
    }
    if (now >= n->next_status_ns) {
        send_status(n, now);
        n->next_status_ns = now + (int64_t)n->cfg.status_interval_ms * 1000000;
    }
    if (n->watchdog_interval_ns > 0 && now >= n->next_watchdog_ns) {
        mn_notify_watchdog();
        n->next_watchdog_ns = now + n->watchdog_interval_ns;
    }
    if (n->end_ns != 0 && now >= n->end_ns)
        n->finished = true;
    return n->finished ? 0 : 1;
}

bool mn_node_hardware_lost(const struct mn_node *n)
{
    return n->hardware_lost;
}

int mn_node_run(struct mn_node *n)
{
    int rc;
    while ((rc = mn_node_step(n, 1000)) == 1)
        ;
    send_status(n, mn_clock_mono_ns());
    struct mn_node_stats s;
    mn_node_get_stats(n, &s);
    mn_log_info("done: %llu frames captured, %llu sent, %llu dropped, %u camera reopens",
                (unsigned long long)s.frames_captured, (unsigned long long)s.frames_sent,
                (unsigned long long)s.frames_dropped, s.camera_reopens);
    return rc;
}
