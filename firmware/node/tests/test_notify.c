/* systemd notifications: with NOTIFY_SOCKET pointing at a datagram socket the test owns, the
 * node's READY / WATCHDOG / STATUS / STOPPING messages arrive there as systemd would read them,
 * the watchdog interval is half of WATCHDOG_USEC, and without a socket nothing is sent. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cmocka.h>

#include "node/notify.h"

static int listener(char *path, size_t cap)
{
    snprintf(path, cap, "/tmp/mn_notify_%ld.sock", (long)getpid());
    unlink(path);
    int fd = socket(AF_UNIX, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    assert_true(fd >= 0);
    struct sockaddr_un addr;
    memset(&addr, 0, sizeof(addr));
    addr.sun_family = AF_UNIX;
    snprintf(addr.sun_path, sizeof(addr.sun_path), "%s", path);
    assert_int_equal(bind(fd, (struct sockaddr *)&addr, sizeof(addr)), 0);
    return fd;
}

/* The next message, "" when none is waiting. */
static const char *next_message(int fd)
{
    static char buf[1024];
    ssize_t n = recv(fd, buf, sizeof(buf) - 1, 0);
    buf[n > 0 ? n : 0] = '\0';
    return buf;
}

#ifdef MN_HAVE_SYSTEMD
static void messages_reach_the_socket(void **state)
{
    (void)state;
    char path[108];
    int fd = listener(path, sizeof(path));
    char pid[32];
    snprintf(pid, sizeof(pid), "%ld", (long)getpid());
    setenv("NOTIFY_SOCKET", path, 1);
    setenv("WATCHDOG_USEC", "200000", 1);
    setenv("WATCHDOG_PID", pid, 1);

    assert_int_equal(mn_notify_init(), 100000000); /* half the unit's 200 ms, in ns */
    mn_notify_ready();
    assert_string_equal(next_message(fd), "READY=1");
    mn_notify_watchdog();
    assert_string_equal(next_message(fd), "WATCHDOG=1");
    mn_notify_status("running, 120.0 fps");
    assert_string_equal(next_message(fd), "STATUS=running, 120.0 fps");

    /* An over-long status is cut to the line buffer, never overrun. */
    char long_text[2000];
    memset(long_text, 'x', sizeof(long_text) - 1);
    long_text[sizeof(long_text) - 1] = '\0';
    mn_notify_status(long_text);
    const char *cut = next_message(fd);
    assert_int_equal(strncmp(cut, "STATUS=xxx", 10), 0);
    assert_int_equal(strlen(cut), 511);

    mn_notify_stopping();
    assert_string_equal(next_message(fd), "STOPPING=1");
    assert_string_equal(next_message(fd), "");

    /* A watchdog meant for another process is not ours to feed. */
    setenv("WATCHDOG_PID", "1", 1);
    assert_int_equal(mn_notify_init(), 0);
    close(fd);
    unlink(path);
}
#endif

static void nothing_without_a_socket(void **state)
{
    (void)state;
    char path[108];
    int fd = listener(path, sizeof(path));
    unsetenv("NOTIFY_SOCKET");
    unsetenv("WATCHDOG_USEC");
    unsetenv("WATCHDOG_PID");
    assert_int_equal(mn_notify_init(), 0);
    mn_notify_ready();
    mn_notify_watchdog();
    mn_notify_status("idle");
    mn_notify_stopping();
    assert_string_equal(next_message(fd), "");
    close(fd);
    unlink(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
#ifdef MN_HAVE_SYSTEMD
        cmocka_unit_test(messages_reach_the_socket),
#endif
        cmocka_unit_test(nothing_without_a_socket),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
