/* Faults: the recording (the "camera") vanishes mid-run; the node must report it in status,
 * retry with growing delays without stalling its loop, and pick up again when it comes back. */
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

    /* While it is gone: reopen attempts fail, backing off 20, 40, 80, 80 ... ms; the loop keeps
     * serving status (state CAMERA_ERROR) meanwhile. */
    struct mn_node_stats before, after;
    mn_node_get_stats(node, &before);
    int64_t end = mn_clock_mono_ns() + 800000000;
    while (mn_clock_mono_ns() < end) {
        assert_int_equal(mn_node_step(node, 5), 1);
        test_drain(hub, &rx);
    }
    mn_node_get_stats(node, &after);
    assert_false(after.camera_ok);
    assert_int_equal(after.frames_sent, before.frames_sent);
    /* 800 ms at <= 80 ms per attempt: at least 5 failed reopens, and no more than 25 (the
     * first delays are 20 and 40 ms, so a loop without backoff would make hundreds). */
    uint32_t attempts = after.camera_errors - before.camera_errors;
    assert_true(attempts >= 5 && attempts <= 25);
    assert_true(rx.saw_camera_error);
    assert_int_equal(after.camera_reopens, 0);

    assert_int_equal(rename(gone, dir), 0);
    step_until(node, hub, 2000, camera_back_and_sending);
    int64_t status_end = mn_clock_mono_ns() + 150000000;
    while (mn_clock_mono_ns() < status_end) {
        assert_int_equal(mn_node_step(node, 5), 1);
        test_drain(hub, &rx);
    }
    assert_int_equal(rx.last_state, mocap_v1_NodeState_NODE_STATE_RUNNING);
    assert_int_equal(rx.last_camera_reopens, 1);
    mn_node_free(node);
    close(hub);
    test_remove_tree(tmp);
}

/* The hub unreachable (nothing listens on its port): capture and detection go on; the sends
 * fail without blocking and the frames are counted, not lost in a stall. */
static void hub_unreachable(void **state)
{
    (void)state;
    const char *dir = test_temp_dir();
    test_write_recording(dir, 320, 200, 50, 4);
    uint16_t port;
    int hub = test_hub_socket(&port);
    close(hub); /* nobody listens there now: ICMP port unreachable */
    struct mn_config cfg;
    test_node_config(&cfg, dir, port);
    cfg.as_fast_as_possible = true;
    cfg.frames = 50;
    struct mn_node *node = test_node_new(&cfg);
    assert_int_equal(mn_node_run(node), 0);
    struct mn_node_stats st;
    mn_node_get_stats(node, &st);
    assert_int_equal(st.frames_processed, 50);
    assert_int_equal(st.frames_sent + st.frames_dropped, 50);
    mn_node_free(node);
    test_remove_tree(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(recording_vanishes_and_returns),
        cmocka_unit_test(hub_unreachable),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
