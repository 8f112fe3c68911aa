/* Faults: the recording (the "camera") vanishes mid-run; the node must report it in status,
 * retry with growing delays without stalling its loop, and pick up again when it comes back.
 * And a hub behind a link that cannot take the node's datagrams must never stall capture. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sched.h>
#include <sys/wait.h>
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

/* The node's side of a link that cannot keep up: in a network namespace of its own, the hub's
 * address is routed out of a veth whose queue drains at 8 kbit/s, so the node's socket send
 * buffer fills within a few hundred datagrams. A blocking send would stall capture right there
 * (and this test would hang until ctest's timeout); the node must instead go on capturing and
 * detecting every frame, count the datagrams it could not send, and finish. Run in a child so
 * that the namespace ends with it; needs root (CAP_NET_ADMIN) and iproute2. */
static int run_behind_a_slow_link(const char *dir, struct mn_node_stats *out)
{
    if (unshare(CLONE_NEWNET) != 0)
        return -1;
    if (system("ip link set lo up && ip link add mnslow0 type veth peer name mnslow1 &&"
               " ip link set mnslow0 up && ip link set mnslow1 up &&"
               " ip addr add 10.213.0.1/24 dev mnslow0 &&"
               " ip neigh add 10.213.0.2 lladdr 02:00:00:00:00:02 dev mnslow0 &&"
               " tc qdisc add dev mnslow0 root tbf rate 8kbit burst 1600 limit 50mb") != 0)
        return -1;
    struct mn_config cfg;
    test_node_config(&cfg, dir, 9);
    snprintf(cfg.hub_host, sizeof(cfg.hub_host), "10.213.0.2");
    cfg.as_fast_as_possible = true;
    cfg.replay_loop = true;
    cfg.frames = 3000;
    cfg.log_level = MN_LOG_ERR;
    struct mn_node *node = test_node_new(&cfg);
    if (mn_node_run(node) != 0)
        return -1;
    mn_node_get_stats(node, out);
    mn_node_free(node);
    return 0;
}

static void hub_behind_a_full_link(void **state)
{
    (void)state;
    if (geteuid() != 0)
        fail_msg("needs root for a network namespace (tests/run.sh runs as root in CI)");
    const char *dir = test_temp_dir();
    test_write_recording(dir, 320, 200, 50, 4);
    int fds[2];
    assert_int_equal(pipe(fds), 0);
    pid_t child = fork();
    assert_true(child >= 0);
    if (child == 0) {
        struct mn_node_stats st;
        memset(&st, 0, sizeof(st));
        int rc = run_behind_a_slow_link(dir, &st);
        ssize_t w = write(fds[1], &st, sizeof(st));
        _exit(rc == 0 && w == (ssize_t)sizeof(st) ? 0 : 1);
    }
    close(fds[1]);
    struct mn_node_stats st;
    assert_int_equal(read(fds[0], &st, sizeof(st)), (ssize_t)sizeof(st));
    close(fds[0]);
    int status;
    assert_int_equal(waitpid(child, &status, 0), child);
    assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    /* Every frame was captured and detected although the link took only a fraction. */
    assert_int_equal(st.frames_processed, 3000);
    assert_true(st.datagrams_dropped > 0);
    assert_true(st.datagrams_sent > 0);
    assert_true(st.frames_dropped > 0);
    assert_int_equal(st.frames_sent + st.frames_dropped, 3000);
    test_remove_tree(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(recording_vanishes_and_returns),
        cmocka_unit_test(hub_behind_a_full_link),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
