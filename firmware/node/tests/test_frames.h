/* Test helpers: recordings of synthetic Gaussian spots written with the framefile writer (so
 * tests/data stays empty), their true positions, a loopback "hub" socket and temp dirs. */
#ifndef MN_NODE_TEST_FRAMES_H
#define MN_NODE_TEST_FRAMES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "node/config.h"

/* Spot i of frame k: on a grid of cells, drifting a fraction of a pixel per frame. */
void test_spot_position(uint32_t frame, uint32_t i, double *x, double *y);

/* Frame k (w x h, `spots` spots) into px (w bytes per row). */
void test_render_frame(uint32_t k, uint32_t w, uint32_t h, uint32_t spots, uint8_t *px);

/* Writes `frames` frames of w x h with `spots` spots each into dir/frames.mcf. */
void test_write_recording(const char *dir, uint32_t w, uint32_t h, uint32_t frames,
                          uint32_t spots);

/* A fresh directory under /tmp (static buffer) and its recursive removal. */
const char *test_temp_dir(void);
void test_remove_tree(const char *dir);

/* UDP socket on 127.0.0.1, any port; its port in *port. */
int test_hub_socket(uint16_t *port);

/* Node config for a replay of dir sending to 127.0.0.1:hub_port, with a wire key for node 7
 * written to dir/node.key (mode 0600) and loaded. */
void test_node_config(struct mn_config *cfg, const char *dir, uint16_t hub_port);

/* The test node's wire key (key id 1), as the test "hub" holds it. */
const uint8_t *test_node_key(void);
/* Writes a key file for node_id with key (id key_id) at path, mode 0600. */
void test_write_key_file(const char *path, uint32_t node_id, uint8_t key_id, const uint8_t *key);
/* Seals a packet as the hub does (to node 7 under test_node_key(), the given counter); returns
 * the datagram length in out. */
size_t test_seal_to_node(const uint8_t *payload, size_t len, uint64_t counter, uint8_t *out,
                         size_t cap);
/* The hub's next counter (realtime ns, strictly increasing), for test senders. */
uint64_t test_hub_counter(void);

struct mn_node;
/* mn_node_new that fails the test, with the node's reason, when the node cannot start. */
struct mn_node *test_node_new(const struct mn_config *cfg);

#endif

/* What a test "hub" received, decoded with the wire module. */
#define TEST_MAX_FRAMES 512
#define TEST_MAX_MARKERS 96

struct test_frame {
    bool seen;
    uint32_t marker_total, chunks_seen, chunk_count, flags;
    uint64_t trigger_time_ns, capture_time_ns;
    double x[TEST_MAX_MARKERS], y[TEST_MAX_MARKERS];
};

/* One ControlAck, by the sequence it answers. */
#define TEST_MAX_ACKS 16
struct test_ack {
    uint32_t count, result;
    char reason[96];
};

struct test_rx {
    struct test_frame frames[TEST_MAX_FRAMES];
    uint32_t marker_datagrams, status_datagrams, preview_datagrams, bad_datagrams;
    uint32_t last_state;
    uint64_t last_frames_sent;
    uint32_t last_control_rejected, last_camera_reopens, last_auth_rejected;
    bool saw_camera_error;
    uint32_t preview_w, preview_h, preview_chunks;
    uint8_t preview[160 * 200];
    uint32_t ack_datagrams;
    struct test_ack acks[TEST_MAX_ACKS];
    uint32_t unauthentic_datagrams; /* envelope missing, bad tag, wrong node or direction */
    uint32_t counter_regressions;   /* a node counter not above the previous one */
    uint64_t last_counter;
};

/* Reads every queued datagram from fd into rx. */
void test_drain(int fd, struct test_rx *rx);
