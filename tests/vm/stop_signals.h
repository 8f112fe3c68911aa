/* Shared by the VM tests' static tools (tests/vivid/vivid_tool.c, tests/kernel/kernel_tool.c):
 * SIGTERM and SIGINT set stop_requested. No SA_RESTART: a blocked poll or recv returns EINTR and
 * the loop sees the flag. */
#ifndef MOCAP_TESTS_VM_STOP_SIGNALS_H
#define MOCAP_TESTS_VM_STOP_SIGNALS_H

#include <signal.h>
#include <string.h>

static volatile sig_atomic_t stop_requested;

static void on_stop_signal(int sig)
{
    (void)sig;
    stop_requested = 1;
}

static void catch_stop_signals(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof(sa));
    sa.sa_handler = on_stop_signal;
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGINT, &sa, NULL);
}

#endif
