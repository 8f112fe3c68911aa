/* mocap-node: parse the config and flags, start the node, run its poll loop until a bound is
 * reached or SIGTERM/SIGINT arrives (through a signalfd, so signals are one more descriptor of
 * the same loop). Exit status: 0 done; 1 bad configuration (restarting cannot help: the unit's
 * RestartPreventExitStatus); 2 run-time failure; 3 could not start (camera or GPIO missing,
 * network down: worth restarting). */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/signalfd.h>
#include <unistd.h>

#include "common/log.h"
#include "capture/capture.h"
#include "node/config.h"
#include "node/node.h"
#include "node/notify.h"

#ifdef MN_HAVE_LIBCAMERA
#include "capture/capture_libcamera.h"
#endif

int main(int argc, char **argv)
{
    struct mn_config cfg;
    char err[MN_CONFIG_ERR];
    switch (mn_config_from_args(&cfg, argc, argv, err, sizeof(err))) {
    case MN_CONFIG_ARGS_EXIT:
        return 0;
    case MN_CONFIG_ARGS_ERROR:
        mn_log_err("bad configuration, not starting: %s", err);
        return 1;
    case MN_CONFIG_ARGS_RUN:
        break;
    }
    mn_log_set_level(cfg.log_level);
#ifdef MN_HAVE_LIBCAMERA
    mn_capture_register_libcamera(&mn_capture_libcamera_ops, mn_capture_libcamera_new);
#endif

    sigset_t mask;
    sigemptyset(&mask);
    sigaddset(&mask, SIGTERM);
    sigaddset(&mask, SIGINT);
    if (sigprocmask(SIG_BLOCK, &mask, NULL) < 0) {
        mn_log_err("sigprocmask: %s", strerror(errno));
        return 2;
    }
    int sfd = signalfd(-1, &mask, SFD_NONBLOCK | SFD_CLOEXEC);
    if (sfd < 0) {
        mn_log_err("signalfd: %s", strerror(errno));
        return 2;
    }

    struct mn_node *node = mn_node_new(&cfg, err, sizeof(err));
    if (node == NULL) {
        mn_log_err("cannot start: %s", err);
        close(sfd);
        return 3;
    }
    mn_node_set_stop_fd(node, sfd);
    mn_notify_ready();
    int rc = mn_node_run(node);
    bool lost = mn_node_hardware_lost(node);
    mn_notify_stopping();
    mn_node_free(node);
    close(sfd);
    return rc < 0 ? 2 : lost ? 3 : 0;
}
