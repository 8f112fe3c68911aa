/* sd_notify wrappers (see notify.h). */
#include "node/notify.h"

#include <stdio.h>
#include <stdlib.h>

#include "common/log.h"

#ifdef MN_HAVE_SYSTEMD
#include <systemd/sd-daemon.h>

int64_t mn_notify_init(void)
{
    uint64_t usec = 0;
    if (sd_watchdog_enabled(0, &usec) <= 0)
        return 0;
    mn_log_info("systemd watchdog every %llu ms", (unsigned long long)(usec / 1000));
    return (int64_t)usec * 1000 / 2;
}

void mn_notify_ready(void)
{
    sd_notify(0, "READY=1");
}

void mn_notify_watchdog(void)
{
    sd_notify(0, "WATCHDOG=1");
}

/* Formatted on the stack: sd_notifyf's vasprintf + realloc left a small chunk in glibc's fast
 * bins every call that the next call could not reuse, so the heap grew by about 100 bytes per
 * status message (measured: 64 kB over a 10-minute run; megabytes per day). */
void mn_notify_status(const char *text)
{
    char line[512];
    snprintf(line, sizeof line, "STATUS=%s", text);
    sd_notify(0, line);
}

void mn_notify_stopping(void)
{
    sd_notify(0, "STOPPING=1");
}

#else

int64_t mn_notify_init(void)
{
    if (getenv("NOTIFY_SOCKET") != NULL || getenv("WATCHDOG_USEC") != NULL)
        mn_log_err("systemd expects notifications but this mocap-node was built without "
                   "libsystemd: the unit's watchdog will restart it (use Type=simple and no "
                   "WatchdogSec, or rebuild with libsystemd-dev)");
    return 0;
}

void mn_notify_ready(void)
{
}

void mn_notify_watchdog(void)
{
}

void mn_notify_status(const char *text)
{
    (void)text;
}

void mn_notify_stopping(void)
{
}

#endif
