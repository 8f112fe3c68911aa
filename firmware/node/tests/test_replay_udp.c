/* The real node, end to end on loopback: replay source -> pairing with the simulated trigger ->
 * detector -> wire -> UDP, decoded by a test "hub" socket; and the hub's control datagrams
 * (garbage, preview, threshold, start, stop) through the node's own socket and handler, each
 * answered with a ControlAck. */
#include <arpa/inet.h>
#include <math.h>
#include <netinet/in.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <turbojpeg.h>
#include <unistd.h>

#include <cmocka.h>

#include "common/clock.h"
#include "node/node.h"
#include "test_frames.h"
#include "wire/envelope.h"
#include "wire/wire.h"

static struct test_rx rx; /* large: keep it off the stack */

/* Every received marker lies within tol of a distinct true spot of that frame. The spots are
 * point-sampled and rounded to integers, which biases centroids by a few hundredths of a pixel;
 * the detector's own tests hold its accuracy, this one the path from pixels to datagrams. */
static void check_markers(const struct test_frame *f, uint32_t recorded_frame, uint32_t spots,
                          double tol)
{
    assert_int_equal(f->marker_total, spots);
    bool used[TEST_MAX_MARKERS] = {false};
    for (uint32_t m = 0; m < f->marker_total; m++) {
        double best = 1e9;
        uint32_t best_i = 0;
        for (uint32_t i = 0; i < spots; i++) {
            double x, y;
            test_spot_position(recorded_frame, i, &x, &y);
            double d = hypot(f->x[m] - x, f->y[m] - y);
            if (d < best) {
                best = d;
                best_i = i;
            }
        }
        if (best > tol)
            fail_msg("frame %u marker %u at (%.3f, %.3f): %.3f px from the nearest spot",
                     recorded_frame, m, f->x[m], f->y[m], best);
        assert_false(used[best_i]);
        used[best_i] = true;
    }
}


/* Checks cfg, runs a node on it to the end of its frames, then collects what the hub socket
 * received (and closes it). */
static void run_node_to_end(const struct mn_config *cfg, int hub, struct mn_node_stats *st)
{
    char err[MN_CONFIG_ERR];
    assert_int_equal(mn_config_check(cfg, err, sizeof(err)), 0);
    struct mn_node *node = test_node_new(cfg);
    assert_int_equal(mn_node_run(node), 0);
    mn_node_get_stats(node, st);
    mn_node_free(node);
    memset(&rx, 0, sizeof(rx));
    test_drain(hub, &rx);
    close(hub);
}

static void replay_as_fast_as_possible(void **state)
{
    (void)state;
    const char *dir = test_temp_dir();
    enum { FRAMES = 30, SPOTS = 60 }; /* 60 markers: two chunks per frame */
    test_write_recording(dir, 320, 400, FRAMES, SPOTS);
    uint16_t port;
    int hub = test_hub_socket(&port);
    struct mn_config cfg;
    test_node_config(&cfg, dir, port);
    cfg.as_fast_as_possible = true;
    cfg.sim_jitter_us = 200;
    cfg.sim_missed = 0.2;
    cfg.sim_seed = 3;
    cfg.frames = FRAMES;
    struct mn_node_stats st;
    run_node_to_end(&cfg, hub, &st);
    assert_int_equal(st.frames_processed, FRAMES);
    assert_int_equal(st.frames_sent, FRAMES);
    assert_int_equal(st.frames_dropped, 0);
    assert_int_equal(rx.bad_datagrams, 0);
    assert_int_equal(rx.marker_datagrams, 2 * FRAMES);
    uint32_t unmatched = 0;
    for (uint32_t k = 0; k < FRAMES; k++) {
        const struct test_frame *f = &rx.frames[k];
        assert_true(f->seen);
        assert_int_equal(f->chunk_count, 2);
        assert_int_equal(f->chunks_seen, 3);
        check_markers(f, k, SPOTS, 0.1);
        assert_false(f->flags & mocap_v1_FrameFlag_FRAME_FLAG_FREE_RUN);
        if (f->flags & mocap_v1_FrameFlag_FRAME_FLAG_UNMATCHED)
            unmatched++;
        else /* paired: the edge lies within the simulated jitter of the capture stamp */
            assert_true(llabs((long long)(f->capture_time_ns - f->trigger_time_ns)) < 2000000);
        if (k > 0) /* frames are stamped on the 100 Hz grid */
            assert_true(llabs((long long)(f->capture_time_ns - rx.frames[k - 1].capture_time_ns) -
                              10000000) <= 1);
    }
    assert_false(rx.frames[FRAMES].seen);
    /* Missed simulated edges show up as unmatched frames, in the frames and in sync health. */
    assert_true(unmatched > 0 && unmatched < FRAMES / 2);
    assert_int_equal(st.sync.unmatched_frames, unmatched);
    /* The last status on the way out says what was sent. */
    assert_true(rx.status_datagrams >= 1);
    assert_int_equal(rx.last_frames_sent, FRAMES);
    test_remove_tree(dir);
}

/* Frames k of a webcam's MJPEG stream saved as DIR/%06u.jpg: colour JPEGs (R = G = B, 4:2:2 at
 * quality 90 as UVC webcams send), frame `cut` cut to half its bytes. */
static void write_jpeg_recording(const char *dir, uint32_t w, uint32_t h, uint32_t frames,
                                 uint32_t spots, uint32_t cut)
{
    uint8_t *px = malloc((size_t)w * h), *rgb = malloc((size_t)w * h * 3);
    assert_true(px != NULL && rgb != NULL);
    tjhandle tj = tjInitCompress();
    assert_non_null(tj);
    for (uint32_t k = 0; k < frames; k++) {
        test_render_frame(k, w, h, spots, px);
        for (size_t i = 0; i < (size_t)w * h; i++)
            memset(rgb + 3 * i, px[i], 3);
        unsigned char *jpeg = NULL;
        unsigned long size = 0;
        assert_int_equal(tjCompress2(tj, rgb, (int)w, 0, (int)h, TJPF_RGB, &jpeg, &size,
                                     TJSAMP_422, 90, 0), 0);
        char path[128];
        snprintf(path, sizeof(path), "%s/%06u.jpg", dir, k);
        FILE *f = fopen(path, "wb");
        assert_non_null(f);
        size_t keep = k == cut ? size / 2 : size;
        assert_int_equal(fwrite(jpeg, 1, keep, f), keep);
        fclose(f);
        tjFree(jpeg);
    }
    tjDestroy(tj);
    free(rgb);
    free(px);
}

/* The MJPEG path end to end without a webcam: the replay of recorded JPEG frames decoded to luma,
 * detected and sent; the cut frame dropped and counted as a lost frame, the others' markers at
 * the drawn spots. */
static void replay_jpeg_frames(void **state)
{
    (void)state;
    const char *dir = test_temp_dir();
    enum { FRAMES = 12, SPOTS = 30, CUT = 5 };
    write_jpeg_recording(dir, 320, 200, FRAMES, SPOTS, CUT);
    uint16_t port;
    int hub = test_hub_socket(&port);
    struct mn_config cfg;
    test_node_config(&cfg, dir, port);
    cfg.as_fast_as_possible = true;
    cfg.frames = FRAMES - 1;
    struct mn_node_stats st;
    run_node_to_end(&cfg, hub, &st);
    assert_int_equal(st.frames_processed, FRAMES - 1);
    assert_int_equal(st.frames_sent, FRAMES - 1);
    assert_int_equal(st.frames_dropped, 1);
    assert_int_equal(rx.bad_datagrams, 0);
    for (uint32_t k = 0; k < FRAMES; k++) {
        const struct test_frame *f = &rx.frames[k];
        if (k == CUT) {
            assert_false(f->seen);
            continue;
        }
        assert_true(f->seen);
        check_markers(f, k, SPOTS, 0.1);
    }
    test_remove_tree(dir);
}

/* A Control to node_id (0: every node) with its sequence number and command tag, the command's
 * fields zero for the test to fill in. */
static mocap_v1_Control control(uint32_t node_id, uint32_t sequence, pb_size_t which_command)
{
    mocap_v1_Control c = mocap_v1_Control_init_zero;
    c.node_id = node_id;
    c.sequence = sequence;
    c.which_command = which_command;
    return c;
}

/* A node replaying a 320x200 recording in a loop to a test "hub" socket on loopback. */
struct looped_node {
    const char *dir;
    int hub;
    uint16_t hub_port;
    struct mn_config cfg;
    struct mn_node *node;
    uint16_t node_port;
};

/* Writes the recording (`frames` frames of `spots` spots) into a fresh directory, opens the hub
 * socket and fills cfg for a looping replay to it; the test may change cfg before starting. */
static void looped_node_prepare(struct looped_node *t, uint32_t frames, uint32_t spots)
{
    t->dir = test_temp_dir();
    test_write_recording(t->dir, 320, 200, frames, spots);
    t->hub = test_hub_socket(&t->hub_port);
    test_node_config(&t->cfg, t->dir, t->hub_port);
    t->cfg.replay_loop = true;
}

/* Makes the node from cfg and clears what the hub received. */
static void looped_node_start(struct looped_node *t)
{
    t->node = test_node_new(&t->cfg);
    t->node_port = mn_node_local_port(t->node);
    memset(&rx, 0, sizeof(rx));
}

static void looped_node_finish(struct looped_node *t)
{
    mn_node_free(t->node);
    close(t->hub);
    test_remove_tree(t->dir);
}

static void send_to_node(int hub, uint16_t node_port, const uint8_t *data, size_t len)
{
    struct sockaddr_in a = {.sin_family = AF_INET, .sin_port = htons(node_port),
                            .sin_addr.s_addr = htonl(INADDR_LOOPBACK)};
    assert_int_equal(sendto(hub, data, len, 0, (struct sockaddr *)&a, sizeof(a)), (ssize_t)len);
}

/* The Packet of one Control, encoded into buf; returns its length. */
static size_t encode_control(const mocap_v1_Control *c, uint8_t *buf, size_t cap)
{
    static mocap_v1_Packet p;
    p = (mocap_v1_Packet)mocap_v1_Packet_init_zero;
    p.version = 1;
    p.which_body = mocap_v1_Packet_control_tag;
    p.body.control = *c;
    size_t len;
    const char *why;
    assert_int_equal(mn_wire_encode(&p, buf, cap, &len, &why), 0);
    return len;
}

/* A Control as the hub sends it: sealed under the node's key with the hub's next counter. The
 * datagram stays in *sent (when not NULL) for a replay. */
static size_t send_control_kept(const struct looped_node *t, mocap_v1_Control *c, uint8_t *sent)
{
    uint8_t payload[MN_WIRE_MAX_PACKET], buf[MN_ENVELOPE_MAX_DATAGRAM];
    size_t n = encode_control(c, payload, sizeof(payload));
    size_t len = test_seal_to_node(payload, n, test_hub_counter(), buf, sizeof(buf));
    send_to_node(t->hub, t->node_port, buf, len);
    if (sent != NULL)
        memcpy(sent, buf, len);
    return len;
}

static void send_control(const struct looped_node *t, mocap_v1_Control *c)
{
    send_control_kept(t, c, NULL);
}

/* Steps the node for ms milliseconds, draining the hub socket as it goes. */
static void run_for(const struct looped_node *t, int ms)
{
    int64_t end = mn_clock_mono_ns() + (int64_t)ms * 1000000;
    while (mn_clock_mono_ns() < end) {
        assert_int_equal(mn_node_step(t->node, 5), 1);
        test_drain(t->hub, &rx);
    }
}

enum { PACED_RECORDED = 20, PACED_SPOTS = 5 };

static void paced_idle_and_garbage(struct looped_node *t)
{
    /* Idle: frames are captured but nothing is sent; status says IDLE. */
    run_for(t, 250);
    assert_int_equal(rx.marker_datagrams, 0);
    assert_true(rx.status_datagrams >= 1);
    assert_int_equal(rx.last_state, mocap_v1_NodeState_NODE_STATE_IDLE);

    /* Malformed datagrams are rejected by the envelope and counted, and reported in status. */
    const uint8_t garbage[] = {0x08, 0x01, 0x62, 0xff, 0xff};
    send_to_node(t->hub, t->node_port, garbage, sizeof(garbage));
    send_to_node(t->hub, t->node_port, (const uint8_t *)"hello", 5);
    run_for(t, 150);
    struct mn_node_stats st;
    mn_node_get_stats(t->node, &st);
    assert_int_equal(st.auth_rejected, 2);
    assert_int_equal(rx.last_auth_rejected, 2);
    assert_int_equal(st.control_rejected, 0);

    /* Garbage is not answered. */
    assert_int_equal(rx.ack_datagrams, 0);
}

static void paced_preview(struct looped_node *t)
{
    enum { SPOTS = PACED_SPOTS };
    /* A raw preview at half size shows the spots where they are. */
    mocap_v1_Control c = control(7, 1, mocap_v1_Control_preview_request_tag);
    c.command.preview_request.mode = mocap_v1_PreviewMode_PREVIEW_MODE_RAW;
    c.command.preview_request.downscale = 2;
    send_control(t, &c);
    run_for(t, 200);
    assert_int_equal(rx.preview_w, 160);
    assert_int_equal(rx.preview_h, 100);
    assert_int_equal(rx.preview_datagrams, rx.preview_chunks);
    unsigned bright = 0;
    for (size_t i = 0; i < 160u * 100u; i++)
        if (rx.preview[i] > 60)
            bright++;
    /* Each spot is a few bright pixels at half size; the rest is background. */
    assert_true(bright >= SPOTS && bright <= SPOTS * 12);
    double x0, y0;
    test_spot_position(0, 0, &x0, &y0);
    /* Spot 0 drifts by at most 3.4 px over the recording: 2 preview pixels. */
    uint8_t peak = 0;
    for (long y = lround(y0 / 2) - 2; y <= lround(y0 / 2) + 3; y++)
        for (long x = lround(x0 / 2) - 2; x <= lround(x0 / 2) + 3; x++)
            if (rx.preview[y * 160 + x] > peak)
                peak = rx.preview[y * 160 + x];
    assert_true(peak > 60);
    assert_int_equal(rx.acks[1].count, 1);
    assert_int_equal(rx.acks[1].result, mocap_v1_ControlResult_CONTROL_RESULT_APPLIED);
}

/* Start on the grid: every frame sent, paced at 200 Hz; another node's command ignored. */
static void paced_start(struct looped_node *t)
{
    enum { RECORDED = PACED_RECORDED, SPOTS = PACED_SPOTS };
    struct mn_node_stats st;
    /* Another node's command is ignored, not rejected, and not answered. */
    mocap_v1_Control c = control(8, 2, mocap_v1_Control_stop_tag);
    send_control(t, &c);
    /* Start a session 200 ms from now at 200 Hz: frames 0, 1, 2 ... with none missing. (The
     * margin covers a slow qemu run; a node that hears Start after the epoch skips to the
     * current slot, as a late camera would.) */
    c = control(0, 3, mocap_v1_Control_start_tag);
    c.command.start.epoch_ns = (uint64_t)mn_clock_real_ns() + 200000000;
    c.command.start.rate_millihz = 200000;
    send_control(t, &c);
    run_for(t, 600);
    mn_node_get_stats(t->node, &st);
    assert_int_equal(st.control_ignored, 1);
    assert_true(st.running);
    assert_true(st.frames_sent >= 20);
    for (uint32_t k = 0; k < st.frames_sent; k++) {
        const struct test_frame *f = &rx.frames[k];
        if (!f->seen)
            fail_msg("frame %u of %llu missing", k, (unsigned long long)st.frames_sent);
        check_markers(f, k % RECORDED, SPOTS, 0.1);
        /* On the 200 Hz grid; the realtime stamps follow the node's clock-offset refresh,
         * which may move them by its sampling noise (tens of us under qemu). */
        if (k > 0)
            assert_true(llabs((long long)(f->capture_time_ns - rx.frames[k - 1].capture_time_ns) -
                              5000000) <= 50000);
    }
    assert_int_equal(st.frames_dropped, 0);
    assert_int_equal(rx.acks[2].count, 0);
    assert_int_equal(rx.acks[3].count, 1);
    assert_int_equal(rx.acks[3].result, mocap_v1_ControlResult_CONTROL_RESULT_APPLIED);
}

static void paced_refusals(struct looped_node *t)
{
    mocap_v1_Control c;
    /* Refused requests are answered with the node's reason: one out of the node's range, two
     * the camera cannot apply (a recording's exposure and picture are fixed). */
    c = control(7, 4, mocap_v1_Control_set_threshold_tag);
    c.command.set_threshold.value = 0;
    send_control(t, &c);
    c = control(7, 5, mocap_v1_Control_set_exposure_tag);
    c.command.set_exposure.exposure_us = 800;
    send_control(t, &c);
    c = control(7, 7, mocap_v1_Control_set_picture_tag);
    c.command.set_picture.set_contrast = true;
    c.command.set_picture.contrast_pct = 40;
    send_control(t, &c);
    run_for(t, 50);
    assert_int_equal(rx.acks[4].count, 1);
    assert_int_equal(rx.acks[4].result, mocap_v1_ControlResult_CONTROL_RESULT_REJECTED);
    assert_string_equal(rx.acks[4].reason, "control: threshold outside 1..255");
    assert_int_equal(rx.acks[5].count, 1);
    assert_int_equal(rx.acks[5].result, mocap_v1_ControlResult_CONTROL_RESULT_REJECTED);
    if (strstr(rx.acks[5].reason, "cannot set exposure 800 us") == NULL)
        fail_msg("exposure ack reason: '%s'", rx.acks[5].reason);
    assert_int_equal(rx.acks[7].count, 1);
    assert_int_equal(rx.acks[7].result, mocap_v1_ControlResult_CONTROL_RESULT_REJECTED);
    assert_string_equal(rx.acks[7].reason, "cannot set contrast 40 %: the camera has no such control");
}

static void paced_stop(struct looped_node *t)
{
    struct mn_node_stats st;
    mocap_v1_Control c;
    /* Stop: nothing more is sent. */
    c = control(7, 6, mocap_v1_Control_stop_tag);
    send_control(t, &c);
    run_for(t, 50);
    uint32_t after_stop = rx.marker_datagrams;
    run_for(t, 100);
    assert_int_equal(rx.marker_datagrams, after_stop);
    mn_node_get_stats(t->node, &st);
    assert_false(st.running);
    assert_int_equal(st.control_rejected, 3); /* threshold, exposure, contrast */
    assert_int_equal(st.auth_rejected, 2);    /* the two garbage datagrams */
    assert_int_equal(rx.acks[6].count, 1);
    assert_int_equal(rx.acks[6].result, mocap_v1_ControlResult_CONTROL_RESULT_APPLIED);
    assert_int_equal(rx.ack_datagrams, 6);
    assert_int_equal(rx.bad_datagrams, 0);
    /* Everything the node sent was sealed under its key, counters strictly increasing. */
    assert_int_equal(rx.unauthentic_datagrams, 0);
    assert_int_equal(rx.counter_regressions, 0);
}

static void paced_replay_with_control(void **state)
{
    (void)state;
    struct looped_node t;
    looped_node_prepare(&t, PACED_RECORDED, PACED_SPOTS);
    t.cfg.sync_kind = MN_SYNC_SIM;
    t.cfg.rate_hz = 200.0;
    t.cfg.wait_for_start = true;
    looped_node_start(&t);
    paced_idle_and_garbage(&t);
    paced_preview(&t);
    paced_start(&t);
    paced_refusals(&t);
    paced_stop(&t);
    looped_node_finish(&t);
}

static int64_t newest_frame(void)
{
    for (int64_t k = TEST_MAX_FRAMES - 1; k >= 0; k--)
        if (rx.frames[k].seen)
            return k;
    return -1;
}

/* Frames numbered after `after` (plus a few in flight when the command arrived) all have
 * `expected` markers; there must be at least one such frame. */
static void expect_markers_after(int64_t after, uint32_t expected)
{
    int checked = 0;
    for (int64_t k = after + 3; k < TEST_MAX_FRAMES; k++) {
        if (!rx.frames[k].seen)
            continue;
        if (rx.frames[k].marker_total != expected)
            fail_msg("frame %lld: %u markers, expected %u", (long long)k,
                     rx.frames[k].marker_total, expected);
        checked++;
    }
    assert_true(checked > 0);
}

static void read_file(const char *path, char *buf, size_t cap)
{
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    size_t n = fread(buf, 1, cap - 1, f);
    buf[n] = '\0';
    fclose(f);
}

/* Masks, thresholds and identify from the hub reach the detector and the board. */
static void control_reaches_detector(void **state)
{
    (void)state;
    enum { SPOTS = 5 };
    struct looped_node t;
    looped_node_prepare(&t, 20, SPOTS);
    char led[128];
    snprintf(led, sizeof(led), "%s/led", t.dir);
    FILE *lf = fopen(led, "w");
    assert_non_null(lf);
    fclose(lf);
    t.cfg.rate_hz = 200.0;
    snprintf(t.cfg.identify_led, sizeof(t.cfg.identify_led), "%s", led);
    looped_node_start(&t);
    run_for(&t, 150);
    int64_t before = newest_frame();
    assert_true(before >= 5);
    assert_int_equal(rx.frames[before].marker_total, SPOTS);

    /* Spot 0 wanders within x 20..24, y 20..23 over the recording: mask it. */
    mocap_v1_Control c = control(7, 0, mocap_v1_Control_set_mask_tag);
    c.command.set_mask.rects_count = 1;
    c.command.set_mask.rects[0] = (mocap_v1_Rect){10, 10, 25, 25};
    send_control(&t, &c);
    run_for(&t, 150);
    expect_markers_after(before, SPOTS - 1);

    /* A threshold above the spots' peak: nothing is found. */
    before = newest_frame();
    memset(&rx, 0, sizeof(rx));
    c = control(7, 0, mocap_v1_Control_set_threshold_tag);
    c.command.set_threshold.value = 250;
    send_control(&t, &c);
    run_for(&t, 150);
    expect_markers_after(before, 0);

    /* Clear the mask and go back to the old threshold: every spot again. */
    before = newest_frame();
    memset(&rx, 0, sizeof(rx));
    c = control(7, 0, mocap_v1_Control_set_mask_tag);
    c.command.set_mask.clear = true;
    send_control(&t, &c);
    c = control(7, 0, mocap_v1_Control_set_threshold_tag);
    c.command.set_threshold.value = 60;
    send_control(&t, &c);
    run_for(&t, 150);
    expect_markers_after(before, SPOTS);

    /* Identify: the LED file goes to 1, and back to 0 after the duration. */
    c = control(7, 0, mocap_v1_Control_identify_tag);
    c.command.identify.duration_ms = 100;
    send_control(&t, &c);
    run_for(&t, 30);
    char text[8];
    read_file(led, text, sizeof(text));
    assert_string_equal(text, "1\n");
    run_for(&t, 150);
    read_file(led, text, sizeof(text));
    assert_string_equal(text, "0\n");

    struct mn_node_stats st;
    mn_node_get_stats(t.node, &st);
    assert_int_equal(st.control_rejected, 0);
    assert_int_equal(st.control_accepted, 5);
    assert_int_equal(st.frames_dropped, 0);
    looped_node_finish(&t);
}

/* Forged, plain, reflected, stale, future, unknown-key and replayed Controls: every one refused
 * and counted before it is parsed, none answered, and the node keeps doing what the real hub
 * told it (no stop, no threshold change). */
static void forged_and_replayed_control_steers_nothing(void **state)
{
    (void)state;
    enum { SPOTS = 5 };
    struct looped_node t;
    looped_node_prepare(&t, 20, SPOTS);
    t.cfg.rate_hz = 200.0;
    looped_node_start(&t);
    run_for(&t, 150);

    uint8_t payload[MN_WIRE_MAX_PACKET], buf[MN_ENVELOPE_MAX_DATAGRAM];
    uint8_t wrong_key[MN_ENVELOPE_KEY_BYTES];
    memset(wrong_key, 0x42, sizeof(wrong_key));
    const char *why;
    size_t len;
    mocap_v1_Control stop = control(7, 9, mocap_v1_Control_stop_tag);
    mocap_v1_Control blind = control(7, 10, mocap_v1_Control_set_threshold_tag);
    blind.command.set_threshold.value = 255;
    int64_t now = mn_clock_real_ns();
    struct {
        const mocap_v1_Control *c;
        uint8_t direction, key_id;
        const uint8_t *key;
        uint64_t counter;
    } attacks[] = {
        {&blind, MN_ENVELOPE_TO_NODE, 1, wrong_key, 0},           /* forged tag */
        {&stop, MN_ENVELOPE_TO_NODE, 1, wrong_key, 0},            /* forged tag */
        {&stop, MN_ENVELOPE_TO_HUB, 1, test_node_key(), 0},       /* a node's direction */
        {&stop, MN_ENVELOPE_TO_NODE, 2, test_node_key(), 0},      /* key id the node lacks */
        {&stop, MN_ENVELOPE_TO_NODE, 1, test_node_key(),
         (uint64_t)(now - 3 * MN_ENVELOPE_MAX_SKEW_NS / 2)},      /* stale */
        {&blind, MN_ENVELOPE_TO_NODE, 1, test_node_key(),
         (uint64_t)(now + 3 * MN_ENVELOPE_MAX_SKEW_NS / 2)},      /* from the future */
    };
    enum { ATTACKS = sizeof(attacks) / sizeof(attacks[0]) };
    for (size_t i = 0; i < ATTACKS; i++) {
        size_t n = encode_control(attacks[i].c, payload, sizeof(payload));
        struct mn_envelope env = {.direction = attacks[i].direction, .key_id = attacks[i].key_id,
                                  .node_id = 7, .payload = payload, .payload_len = n,
                                  .counter = attacks[i].counter ? attacks[i].counter
                                                                : test_hub_counter()};
        assert_int_equal(mn_envelope_seal(&env, attacks[i].key, buf, sizeof(buf), &len, &why), 0);
        send_to_node(t.hub, t.node_port, buf, len);
    }
    /* And the plain, unauthenticated Stop the probe used to stop a node with. */
    send_to_node(t.hub, t.node_port, payload, encode_control(&stop, payload, sizeof(payload)));
    int64_t before = newest_frame();
    run_for(&t, 150);
    struct mn_node_stats st;
    mn_node_get_stats(t.node, &st);
    assert_int_equal(st.auth_rejected, ATTACKS + 1);
    assert_int_equal(st.control_accepted + st.control_rejected + st.control_ignored, 0);
    assert_true(st.running);
    assert_int_equal(rx.ack_datagrams, 0);
    expect_markers_after(before, SPOTS);

    /* The real hub raises the threshold (kept for a replay), then lowers it again. */
    uint8_t kept[MN_ENVELOPE_MAX_DATAGRAM];
    mocap_v1_Control c = control(7, 1, mocap_v1_Control_set_threshold_tag);
    c.command.set_threshold.value = 250;
    size_t kept_len = send_control_kept(&t, &c, kept);
    run_for(&t, 100);
    before = newest_frame();
    run_for(&t, 100);
    expect_markers_after(before, 0);
    c.sequence = 2;
    c.command.set_threshold.value = 60;
    send_control(&t, &c);
    run_for(&t, 100);
    /* The recorded "threshold 250" replayed five times: refused, the threshold stays 60. */
    for (int i = 0; i < 5; i++)
        send_to_node(t.hub, t.node_port, kept, kept_len);
    before = newest_frame();
    run_for(&t, 150);
    expect_markers_after(before, SPOTS);
    mn_node_get_stats(t.node, &st);
    assert_int_equal(st.auth_rejected, ATTACKS + 1 + 5);
    assert_int_equal(rx.last_auth_rejected, ATTACKS + 1 + 5);
    assert_int_equal(st.control_accepted, 2);
    assert_int_equal(rx.acks[1].count, 1);
    assert_int_equal(rx.acks[2].count, 1);
    assert_int_equal(rx.acks[9].count + rx.acks[10].count, 0);
    assert_true(st.running);
    looped_node_finish(&t);
}

/* No hub configured: the node finds it by the HubAnnounce broadcast (sent here straight to the
 * announce port on loopback) and takes the session's epoch and rate from it. */
static void hub_found_by_announce(void **state)
{
    (void)state;
    struct looped_node t;
    looped_node_prepare(&t, 10, 3);
    uint16_t announce_port;
    int probe = test_hub_socket(&announce_port); /* a free port for the node to listen on */
    close(probe);
    t.cfg.hub_host[0] = '\0'; /* no hub: its port is not used */
    t.cfg.announce_port = announce_port;
    looped_node_start(&t);
    run_for(&t, 100);
    struct mn_node_stats st;
    mn_node_get_stats(t.node, &st);
    assert_false(st.hub_known);
    assert_int_equal(rx.marker_datagrams, 0);

    static mocap_v1_Packet p;
    p = (mocap_v1_Packet)mocap_v1_Packet_init_zero;
    p.version = 1;
    p.which_body = mocap_v1_Packet_hub_announce_tag;
    p.body.hub_announce.port = t.hub_port;
    p.body.hub_announce.epoch_ns = (uint64_t)mn_clock_real_ns() + 30000000;
    p.body.hub_announce.rate_millihz = 100000;
    uint8_t payload[MN_WIRE_MAX_PACKET], buf[MN_ENVELOPE_MAX_DATAGRAM];
    size_t n, len;
    const char *why;
    assert_int_equal(mn_wire_encode(&p, payload, sizeof(payload), &n, &why), 0);
    /* A forged announce (right layout, wrong key) pointing at an attacker's socket is refused:
     * the node's frames never go there. So is a plain one. */
    uint16_t attacker_port;
    int attacker = test_hub_socket(&attacker_port);
    p.body.hub_announce.port = attacker_port;
    assert_int_equal(mn_wire_encode(&p, payload, sizeof(payload), &n, &why), 0);
    uint8_t wrong_key[MN_ENVELOPE_KEY_BYTES];
    memset(wrong_key, 0x42, sizeof(wrong_key));
    struct mn_envelope env = {.direction = MN_ENVELOPE_TO_NODE, .key_id = 1, .node_id = 7,
                              .counter = test_hub_counter(), .payload = payload, .payload_len = n};
    assert_int_equal(mn_envelope_seal(&env, wrong_key, buf, sizeof(buf), &len, &why), 0);
    send_to_node(t.hub, announce_port, buf, len);
    send_to_node(t.hub, announce_port, payload, n);
    /* An authentic announce for another node (broadcasts carry one per node) is ignored. */
    env.node_id = 8;
    env.counter = test_hub_counter();
    assert_int_equal(mn_envelope_seal(&env, test_node_key(), buf, sizeof(buf), &len, &why), 0);
    send_to_node(t.hub, announce_port, buf, len);
    run_for(&t, 150);
    mn_node_get_stats(t.node, &st);
    assert_false(st.hub_known);
    assert_int_equal(st.auth_rejected, 2);
    assert_int_equal(st.auth_other_node, 1);
    assert_int_equal(recv(attacker, buf, sizeof(buf), MSG_DONTWAIT), -1);
    close(attacker);

    p.body.hub_announce.port = t.hub_port;
    p.body.hub_announce.epoch_ns = (uint64_t)mn_clock_real_ns() + 30000000;
    assert_int_equal(mn_wire_encode(&p, payload, sizeof(payload), &n, &why), 0);
    len = test_seal_to_node(payload, n, test_hub_counter(), buf, sizeof(buf));
    send_to_node(t.hub, announce_port, buf, len);
    run_for(&t, 300);
    mn_node_get_stats(t.node, &st);
    assert_true(st.hub_known);
    assert_int_equal(st.control_rejected, 0);
    /* Frames since the announced epoch, numbered from 0 on its grid. */
    assert_true(st.frames_sent >= 10);
    for (uint32_t k = 0; k < 10; k++)
        assert_true(rx.frames[k].seen);
    assert_true(rx.status_datagrams >= 1);
    looped_node_finish(&t);
}

static void bad_sources_refuse_to_start(void **state)
{
    (void)state;
    struct mn_config cfg;
    char err[MN_CONFIG_ERR] = "";
    test_node_config(&cfg, "/nonexistent/cam1", 9);
    assert_null(mn_node_new(&cfg, err, sizeof(err)));
    assert_non_null(strstr(err, "/nonexistent/cam1"));
    cfg.source_kind = MN_SOURCE_V4L2;
    snprintf(cfg.source_arg, sizeof(cfg.source_arg), "/dev/null");
    assert_null(mn_node_new(&cfg, err, sizeof(err)));
    assert_non_null(strstr(err, "/dev/null: not a V4L2 device"));
    snprintf(cfg.source_arg, sizeof(cfg.source_arg), "/dev/video-none");
    assert_null(mn_node_new(&cfg, err, sizeof(err)));
    assert_non_null(strstr(err, "/dev/video-none: No such file"));
    /* A trigger line that does not exist. */
    test_node_config(&cfg, "/nonexistent/cam1", 9);
    cfg.sync_kind = MN_SYNC_GPIO;
    snprintf(cfg.gpio_chip, sizeof(cfg.gpio_chip), "gpiochip-none");
    cfg.gpio_line = 4;
    assert_null(mn_node_new(&cfg, err, sizeof(err)));
    assert_non_null(strstr(err, "gpio chip 'gpiochip-none'"));
    /* Tests do not link the libcamera backend: the source says so instead of pretending. */
    cfg.sync_kind = MN_SYNC_NONE;
    cfg.source_kind = MN_SOURCE_LIBCAMERA;
    snprintf(cfg.source_arg, sizeof(cfg.source_arg), "0");
    assert_null(mn_node_new(&cfg, err, sizeof(err)));
    assert_non_null(strstr(err, "libcamera:0: this program was built without libcamera"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(replay_as_fast_as_possible),
        cmocka_unit_test(replay_jpeg_frames),
        cmocka_unit_test(paced_replay_with_control),
        cmocka_unit_test(control_reaches_detector),
        cmocka_unit_test(forged_and_replayed_control_steers_nothing),
        cmocka_unit_test(hub_found_by_announce),
        cmocka_unit_test(bad_sources_refuse_to_start),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
