/* Dispatch of trigger-edge sources through their ops tables, and the "none" (free-run) source. */
#include "sync/sync.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>

struct mn_sync {
    const struct mn_sync_ops *ops;
    void *impl;
};

static int none_fd(void *impl)
{
    (void)impl;
    return -1;
}

static int none_read(void *impl, int64_t until, int64_t *edges, size_t cap, size_t *n)
{
    (void)impl, (void)until, (void)edges, (void)cap;
    *n = 0;
    return 0;
}

static void none_set_grid(void *impl, const struct mn_grid *grid)
{
    (void)impl, (void)grid;
}

static void none_close(void *impl)
{
    (void)impl;
}

const struct mn_sync_ops mn_sync_none_ops = {
    .name = "none",
    .free_run = true,
    .fd = none_fd,
    .read = none_read,
    .set_grid = none_set_grid,
    .close = none_close,
};

struct mn_sync *mn_sync_open(const struct mn_sync_params *params, char *err, size_t errlen)
{
    struct mn_sync *s = calloc(1, sizeof(*s));
    if (s == NULL) {
        snprintf(err, errlen, "out of memory");
        return NULL;
    }
    switch (params->kind) {
    case MN_SYNC_NONE:
        s->ops = &mn_sync_none_ops;
        s->impl = s; /* stateless; any non-NULL value */
        break;
    case MN_SYNC_GPIO:
#ifdef MN_HAVE_GPIOD
        s->ops = &mn_sync_gpio_ops;
        s->impl = mn_sync_gpio_new(params->gpio.chip, params->gpio.line, params->gpio.falling, err,
                                   errlen);
#else
        snprintf(err, errlen, "gpio:%s:%u: this mocap-node was built without libgpiod (the "
                              "static variant); use mocap-node for a trigger line",
                 params->gpio.chip, params->gpio.line);
        errno = ENOTSUP;
#endif
        break;
    case MN_SYNC_SIM:
        s->ops = &mn_sync_sim_ops;
        s->impl = mn_sync_sim_new(&params->sim);
        if (s->impl == NULL)
            snprintf(err, errlen, "sim sync: out of memory");
        break;
    }
    if (s->impl == NULL) {
        int e = errno;
        free(s);
        errno = e;
        return NULL;
    }
    return s;
}

void mn_sync_close(struct mn_sync *s)
{
    if (s == NULL)
        return;
    s->ops->close(s->impl);
    free(s);
}

const char *mn_sync_name(const struct mn_sync *s)
{
    return s->ops->name;
}

bool mn_sync_free_run(const struct mn_sync *s)
{
    return s->ops->free_run;
}

int mn_sync_fd(const struct mn_sync *s)
{
    return s->ops->fd(s->impl);
}

int mn_sync_read(struct mn_sync *s, int64_t until_mono_ns, int64_t *edges, size_t cap, size_t *n)
{
    return s->ops->read(s->impl, until_mono_ns, edges, cap, n);
}

void mn_sync_set_grid(struct mn_sync *s, const struct mn_grid *grid)
{
    s->ops->set_grid(s->impl, grid);
}
