/* Faults: the recording (the "camera") vanishes mid-run; the node must report it in status,
 * retry with growing delays without stalling its loop, and pick up again when it comes back.
 * (A hub behind a full link: test_slow_link.c.) */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "common/clock.h"
#include "node/node.h"
#include "test_frames.h"
#include "wire/wire.h"

static struct test_rx rx;

static void step_until(struct mn_node *node, int hub, int max_ms, bool (*done)(struct mn_node *))
{
    int64_t end = mn_clock_mono_ns() + (int64_t)max_ms * 1000000;
    while (!done(node)) {
        if (mn_clock_mono_ns() > end)
            fail_msg("condition not reached within %d ms", max_ms);
        assert_int_equal(mn_node_step(node, 5), 1);
        test_drain(hub, &rx);
    }
}

static bool twenty_frames(struct mn_node *node)
{
    struct mn_node_stats st;
    mn_node_get_stats(node, &st);
    return st.frames_sent >= 20;
}

static bool camera_down(struct mn_node *node)
{
    struct mn_node_stats st;
    mn_node_get_stats(node, &st);
    return !st.camera_ok;
}

static bool camera_back_and_sending(struct mn_node *node)
{
    struct mn_node_stats st;
    mn_node_get_stats(node, &st);
    return st.camera_ok && st.camera_reopens == 1 && st.frames_sent >= 40;
}

static uint32_t errors_when_down;

static bool five_failed_reopens_since_down(struct mn_node *node)
{
    struct mn_node_stats st;
    mn_node_get_stats(node, &st);
    return st.camera_errors >= errors_when_down + 5;
}

static bool status_said_camera_error(struct mn_node *node)
{
    (void)node;
    return rx.saw_camera_error;
}

static bool status_said_running_after_one_reopen(struct mn_node *node)
{
    (void)node;
    return rx.last_state == mocap_v1_NodeState_NODE_STATE_RUNNING && rx.last_camera_reopens == 1;
}

static void recording_vanishes_and_returns(void **state)
{
    (void)state;
    const char *tmp = test_temp_dir();
    char dir[128], gone[128];
    snprintf(dir, sizeof(dir), "%s/cam7", tmp);
    snprintf(gone, sizeof(gone), "%s/cam7.gone", tmp);
    test_write_recording(dir, 320, 200, 10, 3);
    uint16_t port;
    int hub = test_hub_socket(&port);
    struct mn_config cfg;
    test_node_config(&cfg, dir, port);
    cfg.rate_hz = 200.0;
    cfg.replay_loop = true;
    cfg.reopen_min_ms = 20;
    cfg.reopen_max_ms = 80;
    cfg.log_level = MN_LOG_ERR;
    struct mn_node *node = test_node_new(&cfg);
    memset(&rx, 0, sizeof(rx));

    step_until(node, hub, 2000, twenty_frames);
    assert_int_equal(rename(dir, gone), 0);
    step_until(node, hub, 1000, camera_down);
    struct mn_node_stats down;
    mn_node_get_stats(node, &down);
    errors_when_down = down.camera_errors;

    /* While it is gone: reopen attempts fail, backing off 20, 40, 80, 80 ... ms, and the loop
     * keeps serving status (state CAMERA_ERROR). Waited for by events, not a wall-clock window:
     * five failed reopens cannot come sooner than the backoff allows (20 + 40 + 80 + 80 ms
     * between them), however fast or loaded the machine; a loop without backoff would make
     * them within a few milliseconds. */
    struct mn_node_stats before, after;
    mn_node_get_stats(node, &before);
    int64_t t0 = mn_clock_mono_ns();
    step_until(node, hub, 5000, five_failed_reopens_since_down);
    int64_t waited_ms = (mn_clock_mono_ns() - t0) / 1000000;
    mn_node_get_stats(node, &after);
    assert_true(waited_ms >= 20 + 40 + 80 + 80 - 5);
    assert_false(after.camera_ok);
    assert_int_equal(after.frames_sent, before.frames_sent);
    assert_int_equal(after.camera_reopens, 0);
    step_until(node, hub, 5000, status_said_camera_error);

    assert_int_equal(rename(gone, dir), 0);
    step_until(node, hub, 5000, camera_back_and_sending);
    step_until(node, hub, 5000, status_said_running_after_one_reopen);
    mn_node_free(node);
    close(hub);
    test_remove_tree(tmp);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(recording_vanishes_and_returns),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
