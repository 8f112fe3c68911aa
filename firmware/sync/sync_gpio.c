/* Trigger edges from a GPIO line through libgpiod v1 (Debian bookworm's 1.6 API): edge events
 * carry the kernel's time stamp taken in the interrupt handler, which is what makes numbering
 * by time work. libgpiod types stay inside this file. */
#include <errno.h>
#include <fcntl.h>
#include <gpiod.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/clock.h"
#include "common/log.h"
#include "sync/sync.h"

struct gpio_sync {
    struct gpiod_chip *chip;
    struct gpiod_line *line;
    int fd;
    /* Kernels before 5.7 stamp v1 line events with CLOCK_REALTIME, later ones with
     * CLOCK_MONOTONIC; decided from the first event. */
    bool checked_clock;
    bool realtime_stamps;
};

void *mn_sync_gpio_new(const char *chip_name, uint32_t line_offset, bool falling, char *err,
                       size_t errlen)
{
    struct gpio_sync *g = calloc(1, sizeof(*g));
    if (g == NULL) {
        snprintf(err, errlen, "out of memory");
        return NULL;
    }
    int e;
    g->chip = gpiod_chip_open_lookup(chip_name);
    if (g->chip == NULL) {
        e = errno;
        snprintf(err, errlen, "gpio chip '%s': %s", chip_name, strerror(e));
        goto fail_free;
    }
    g->line = gpiod_chip_get_line(g->chip, line_offset);
    if (g->line == NULL) {
        e = errno;
        snprintf(err, errlen, "gpio chip '%s' line %u: %s", chip_name, line_offset, strerror(e));
        goto fail_chip;
    }
    int rc = falling ? gpiod_line_request_falling_edge_events(g->line, "mocap-node")
                     : gpiod_line_request_rising_edge_events(g->line, "mocap-node");
    if (rc < 0) {
        e = errno;
        snprintf(err, errlen, "gpio chip '%s' line %u: cannot request edge events: %s",
                 chip_name, line_offset, strerror(e));
        goto fail_chip;
    }
    g->fd = gpiod_line_event_get_fd(g->line);
    /* Reads must never block the poll loop: EAGAIN means "no edge queued". */
    int flags = fcntl(g->fd, F_GETFL);
    if (g->fd < 0 || flags < 0 || fcntl(g->fd, F_SETFL, flags | O_NONBLOCK) < 0) {
        e = errno;
        snprintf(err, errlen, "gpio line event fd: %s", strerror(e));
        goto fail_release;
    }
    return g;

fail_release:
    gpiod_line_release(g->line);
fail_chip:
    gpiod_chip_close(g->chip);
fail_free:
    free(g);
    errno = e;
    return NULL;
}

static int gpio_fd(void *impl)
{
    return ((struct gpio_sync *)impl)->fd;
}

static int gpio_read(void *impl, int64_t until, int64_t *edges, size_t cap, size_t *n)
{
    struct gpio_sync *g = impl;
    (void)until; /* a real line delivers what the kernel has queued */
    *n = 0;
    while (*n < cap) {
        struct gpiod_line_event ev[16];
        size_t want = cap - *n < 16 ? cap - *n : 16;
        int got = gpiod_line_event_read_fd_multiple(g->fd, ev, (unsigned)want);
        if (got < 0) {
            if (errno == EINTR)
                continue;
            if (errno == EAGAIN)
                return 0;
            return -1;
        }
        for (int i = 0; i < got; i++) {
            int64_t t = mn_timespec_to_ns(&ev[i].ts);
            if (!g->checked_clock) {
                int64_t dm = llabs(t - mn_clock_mono_ns());
                int64_t dr = llabs(t - mn_clock_real_ns());
                g->realtime_stamps = dr < dm;
                g->checked_clock = true;
                if (g->realtime_stamps)
                    mn_log_warn("gpio: kernel stamps edges with CLOCK_REALTIME (kernel < 5.7); "
                                "converting, a clock step will misnumber frames");
            }
            if (g->realtime_stamps)
                t -= mn_clock_real_minus_mono_ns();
            edges[(*n)++] = t;
        }
        if (got == 0)
            return 0;
    }
    return 0;
}

static void gpio_set_grid(void *impl, const struct mn_grid *grid)
{
    (void)impl, (void)grid; /* the wire sets the pace, not the grid */
}

static void gpio_close(void *impl)
{
    struct gpio_sync *g = impl;
    gpiod_line_release(g->line);
    gpiod_chip_close(g->chip);
    free(g);
}

const struct mn_sync_ops mn_sync_gpio_ops = {
    .name = "gpio",
    .free_run = false,
    .fd = gpio_fd,
    .read = gpio_read,
    .set_grid = gpio_set_grid,
    .close = gpio_close,
};
