/* A hub behind a link that cannot take the node's datagrams must never stall capture.
 *
 * The whole test process moves into a network namespace of its own (it ends with the process),
 * where the hub's address is routed out of a veth whose queue drains at 8 kbit/s, so the node's
 * socket send buffer fills within a few hundred datagrams. A blocking send would stall capture
 * right there (and this test would hang until ctest's timeout); the node must instead go on
 * capturing and detecting every frame, count the datagrams it could not send, and finish.
 * No fork: a forked child that goes on running emulated code spins forever under qemu-user, and
 * this test runs in the aarch64 build too. Needs root (CAP_NET_ADMIN) and iproute2. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sched.h>
#include <unistd.h>

#include <cmocka.h>

#include "node/node.h"
#include "test_frames.h"

enum { kFrames = 3000 };

static void enter_namespace_behind_a_slow_link(void)
{
    if (geteuid() != 0)
        fail_msg("needs root for a network namespace (tests/run.sh runs as root in CI)");
    assert_int_equal(unshare(CLONE_NEWNET), 0);
    assert_int_equal(system("ip link set lo up && ip link add mnslow0 type veth peer name mnslow1 &&"
                            " ip link set mnslow0 up && ip link set mnslow1 up &&"
                            " ip addr add 10.213.0.1/24 dev mnslow0 &&"
                            " ip neigh add 10.213.0.2 lladdr 02:00:00:00:00:02 dev mnslow0 &&"
                            " tc qdisc add dev mnslow0 root tbf rate 8kbit burst 1600 limit 50mb"),
                     0);
}

static void hub_behind_a_full_link(void **state)
{
    (void)state;
    enter_namespace_behind_a_slow_link();
    const char *dir = test_temp_dir();
    test_write_recording(dir, 320, 200, 50, 4);

    struct mn_config cfg;
    test_node_config(&cfg, dir, 9);
    snprintf(cfg.hub_host, sizeof(cfg.hub_host), "10.213.0.2");
    cfg.as_fast_as_possible = true;
    cfg.replay_loop = true;
    cfg.frames = kFrames;
    cfg.log_level = MN_LOG_ERR;
    struct mn_node *node = test_node_new(&cfg);
    assert_int_equal(mn_node_run(node), 0);
    struct mn_node_stats st;
    mn_node_get_stats(node, &st);
    mn_node_free(node);

    /* Every frame was captured and detected although the link took only a fraction. */
    assert_int_equal(st.frames_processed, kFrames);
    assert_true(st.datagrams_dropped > 0);
    assert_true(st.datagrams_sent > 0);
    assert_true(st.frames_dropped > 0);
    assert_int_equal(st.frames_sent + st.frames_dropped, kFrames);
    test_remove_tree(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(hub_behind_a_full_link),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
