/* Test helpers (see test_frames.h). */
#include "test_frames.h"

#include <arpa/inet.h>
#include <math.h>
#include <netinet/in.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "framefile/framefile.h"
#include "node/node.h"
#include "common/clock.h"
#include "wire/envelope.h"
#include "wire/wire.h"

#define CELL 40 /* spots sit one per 40 x 40 cell, away from the borders */
#define BACKGROUND 12
#define PEAK 220.0
#define SIGMA 1.4

void test_spot_position(uint32_t frame, uint32_t i, double *x, double *y)
{
    uint32_t per_row = 7;
    *x = CELL * (double)(i % per_row) + 20.0 + 0.37 * (frame % 10) + 0.013 * i;
    *y = CELL * (double)(i / per_row) + 20.0 + 0.21 * (frame % 10) + 0.029 * i;
}

void test_render_frame(uint32_t k, uint32_t w, uint32_t h, uint32_t spots, uint8_t *px)
{
    assert_true(spots <= (w / CELL) * (h / CELL) && w / CELL >= 7);
    memset(px, BACKGROUND, (size_t)w * h);
    for (uint32_t i = 0; i < spots; i++) {
        double cx, cy;
        test_spot_position(k, i, &cx, &cy);
        for (int y = (int)cy - 6; y <= (int)cy + 6; y++) {
            for (int x = (int)cx - 6; x <= (int)cx + 6; x++) {
                double d2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
                double v = BACKGROUND + PEAK * exp(-d2 / (2 * SIGMA * SIGMA));
                px[(size_t)y * w + x] = (uint8_t)lround(v > 255 ? 255 : v);
            }
        }
    }
}

void test_write_recording(const char *dir, uint32_t w, uint32_t h, uint32_t frames,
                          uint32_t spots)
{
    struct mn_ff_info info = {.width = w, .height = h, .rate_mhz = 100000,
                              .background = BACKGROUND, .noise_sigma_q8 = 0, .noise_seed = 1};
    struct mn_ff_write_options opts = {.zlib_level = 1, .dark_level = -1};
    struct mn_ff_writer *wr = mn_ff_writer_open(dir, &info, &opts);
    assert_non_null(wr);
    uint8_t *px = malloc((size_t)w * h);
    assert_non_null(px);
    for (uint32_t k = 0; k < frames; k++) {
        test_render_frame(k, w, h, spots, px);
        assert_int_equal(mn_ff_writer_add(wr, k, (uint64_t)k * 10000000u, px, w), 0);
    }
    free(px);
    assert_int_equal(mn_ff_writer_close(wr), 0);
}

const char *test_temp_dir(void)
{
    static char path[64];
    snprintf(path, sizeof(path), "/tmp/mn_test_node_XXXXXX");
    assert_non_null(mkdtemp(path));
    return path;
}

void test_remove_tree(const char *dir)
{
    char cmd[256];
    snprintf(cmd, sizeof(cmd), "rm -rf '%s'", dir);
    assert_int_equal(system(cmd), 0);
}

int test_hub_socket(uint16_t *port)
{
    int fd = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK, 0);
    assert_true(fd >= 0);
    int rcvbuf = 4 << 20;
    setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof(rcvbuf));
    struct sockaddr_in a = {.sin_family = AF_INET, .sin_addr.s_addr = htonl(INADDR_LOOPBACK)};
    assert_int_equal(bind(fd, (struct sockaddr *)&a, sizeof(a)), 0);
    socklen_t len = sizeof(a);
    assert_int_equal(getsockname(fd, (struct sockaddr *)&a, &len), 0);
    *port = ntohs(a.sin_port);
    return fd;
}

const uint8_t *test_node_key(void)
{
    static uint8_t key[MN_ENVELOPE_KEY_BYTES];
    for (unsigned i = 0; i < sizeof(key); i++)
        key[i] = (uint8_t)(0x5a ^ (i * 13));
    return key;
}

void test_write_key_file(const char *path, uint32_t node_id, uint8_t key_id, const uint8_t *key)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fprintf(f, "# test key\nnode = %u\nkey = %u ", node_id, key_id);
    for (unsigned i = 0; i < MN_ENVELOPE_KEY_BYTES; i++)
        fprintf(f, "%02x", key[i]);
    fprintf(f, "\n");
    assert_int_equal(fclose(f), 0);
    assert_int_equal(chmod(path, 0600), 0);
}

uint64_t test_hub_counter(void)
{
    static uint64_t last;
    last = mn_envelope_next_counter(last, mn_clock_real_ns());
    return last;
}

size_t test_seal_to_node(const uint8_t *payload, size_t len, uint64_t counter, uint8_t *out,
                         size_t cap)
{
    struct mn_envelope env = {.direction = MN_ENVELOPE_TO_NODE, .key_id = 1, .node_id = 7,
                              .counter = counter, .payload = payload, .payload_len = len};
    size_t size;
    const char *why;
    assert_int_equal(mn_envelope_seal(&env, test_node_key(), out, cap, &size, &why), 0);
    return size;
}

void test_node_config(struct mn_config *cfg, const char *dir, uint16_t hub_port)
{
    mn_config_defaults(cfg);
    cfg->node_id = 7;
    cfg->source_kind = MN_SOURCE_REPLAY;
    snprintf(cfg->source_arg, sizeof(cfg->source_arg), "%s", dir);
    cfg->sync_kind = MN_SYNC_SIM;
    cfg->rate_hz = 100.0;
    snprintf(cfg->hub_host, sizeof(cfg->hub_host), "127.0.0.1");
    cfg->hub_port = hub_port;
    cfg->announce_port = 0; /* tests run in parallel: no shared broadcast port */
    cfg->threshold = 60;
    cfg->status_interval_ms = 100;
    cfg->temperature_path[0] = '\0';
    cfg->log_level = MN_LOG_WARN;
    /* The key goes to a file of its own (dir may not exist: some tests want a missing source);
     * once loaded the file is not needed any more. */
    snprintf(cfg->key_file, sizeof(cfg->key_file), "/tmp/mn_test_node_key_XXXXXX");
    int fd = mkstemp(cfg->key_file);
    assert_true(fd >= 0);
    close(fd);
    test_write_key_file(cfg->key_file, 7, 1, test_node_key());
    char err[MN_CONFIG_ERR];
    int rc = mn_config_load_keys(cfg, err, sizeof(err));
    unlink(cfg->key_file);
    if (rc < 0)
        fail_msg("%s", err);
}

void test_drain(int fd, struct test_rx *rx)
{
    static uint8_t buf[2048];
    static mocap_v1_Packet p;
    for (;;) {
        ssize_t n = recv(fd, buf, sizeof(buf), MSG_DONTWAIT);
        if (n < 0)
            return;
        const char *why;
        struct mn_envelope env;
        if (mn_envelope_parse(buf, (size_t)n, &env, &why) < 0 ||
            env.direction != MN_ENVELOPE_TO_HUB || env.node_id != 7 || env.key_id != 1 ||
            mn_envelope_verify(buf, (size_t)n, test_node_key()) < 0) {
            rx->unauthentic_datagrams++;
            continue;
        }
        if (env.counter <= rx->last_counter)
            rx->counter_regressions++;
        rx->last_counter = env.counter;
        if (mn_wire_decode(env.payload, env.payload_len, &p, &why) < 0) {
            rx->bad_datagrams++;
            continue;
        }
        if (p.which_body == mocap_v1_Packet_marker_frame_tag) {
            const mocap_v1_MarkerFrame *f = &p.body.marker_frame;
            rx->marker_datagrams++;
            if (f->frame_number >= TEST_MAX_FRAMES || f->marker_total > TEST_MAX_MARKERS) {
                rx->bad_datagrams++;
                continue;
            }
            struct test_frame *t = &rx->frames[f->frame_number];
            t->seen = true;
            t->marker_total = f->marker_total;
            t->chunk_count = f->chunk_count;
            t->chunks_seen |= 1u << f->chunk_index;
            t->flags = f->flags;
            t->trigger_time_ns = f->trigger_time_ns;
            t->capture_time_ns = f->capture_time_ns;
            for (pb_size_t i = 0; i < f->markers_count; i++) {
                t->x[f->first_marker + i] = mn_wire_from_subpixel(f->markers[i].x_q8);
                t->y[f->first_marker + i] = mn_wire_from_subpixel(f->markers[i].y_q8);
            }
        } else if (p.which_body == mocap_v1_Packet_node_status_tag) {
            const mocap_v1_NodeStatus *s = &p.body.node_status;
            rx->status_datagrams++;
            rx->last_state = s->state;
            rx->last_frames_sent = s->frames_sent;
            rx->last_control_rejected = s->control_rejected;
            rx->last_auth_rejected = s->auth_rejected;
            rx->last_camera_reopens = s->camera_reopens;
            if (s->state == mocap_v1_NodeState_NODE_STATE_CAMERA_ERROR)
                rx->saw_camera_error = true;
        } else if (p.which_body == mocap_v1_Packet_preview_chunk_tag) {
            const mocap_v1_PreviewChunk *c = &p.body.preview_chunk;
            rx->preview_datagrams++;
            if ((size_t)c->width * c->height > sizeof(rx->preview)) {
                rx->bad_datagrams++;
                continue;
            }
            rx->preview_w = c->width;
            rx->preview_h = c->height;
            rx->preview_chunks = c->chunk_count;
            memcpy(rx->preview + c->offset, c->data.bytes, c->data.size);
        } else if (p.which_body == mocap_v1_Packet_control_ack_tag) {
            const mocap_v1_ControlAck *a = &p.body.control_ack;
            rx->ack_datagrams++;
            if (a->sequence >= TEST_MAX_ACKS) {
                rx->bad_datagrams++;
                continue;
            }
            struct test_ack *t = &rx->acks[a->sequence];
            t->count++;
            t->result = a->result;
            memcpy(t->reason, a->reason, sizeof(t->reason));
        } else {
            rx->bad_datagrams++;
        }
    }
}

struct mn_node *test_node_new(const struct mn_config *cfg)
{
    char err[MN_CONFIG_ERR];
    struct mn_node *node = mn_node_new(cfg, err, sizeof(err));
    if (node == NULL)
        fail_msg("node: %s", err);
    return node;
}
