/* systemd service notification: READY=1 once the node runs, WATCHDOG=1 from the poll loop at
 * half the unit's WatchdogSec, STOPPING=1 on the way out. Built against libsystemd when it is
 * available (MN_HAVE_SYSTEMD); without it, a node started by a unit that expects notifications
 * says loudly at start that it cannot send them. */
#ifndef MN_NODE_NOTIFY_H
#define MN_NODE_NOTIFY_H

#include <stdint.h>

/* Reads the watchdog interval from the environment; returns the interval at which to call
 * mn_notify_watchdog in ns, or 0 when no watchdog is requested. */
int64_t mn_notify_init(void);
void mn_notify_ready(void);
void mn_notify_watchdog(void);
void mn_notify_status(const char *text);
void mn_notify_stopping(void);

#endif
