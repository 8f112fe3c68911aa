/* Dispatch of camera sources through their ops tables (see capture.h). */
#include "capture/capture.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>

/* The libcamera backend is C++ and drags in libcamera's own dependencies (lttng-ust among
 * them, which hangs under qemu-user), so it lives in its own library that only the mocap-node
 * executable links and registers here; tests and tools built without it refuse libcamera:. */
static const struct mn_capture_ops *libcamera_ops;
static mn_capture_libcamera_new_fn libcamera_new;

void mn_capture_register_libcamera(const struct mn_capture_ops *ops, mn_capture_libcamera_new_fn fn)
{
    libcamera_ops = ops;
    libcamera_new = fn;
}

struct mn_capture {
    const struct mn_capture_ops *ops;
    void *impl;
    uint32_t width, height;
};

struct mn_capture *mn_capture_open(const struct mn_capture_params *params, char *err, size_t errlen)
{
    struct mn_capture *c = calloc(1, sizeof(*c));
    if (c == NULL) {
        snprintf(err, errlen, "out of memory");
        return NULL;
    }
    switch (params->kind) {
    case MN_SOURCE_V4L2:
        c->ops = &mn_capture_v4l2_ops;
        c->impl = mn_capture_v4l2_new(params->arg, params->width, params->height, params->buffers,
                                      params->pixel_format, &c->width, &c->height, err, errlen);
        break;
    case MN_SOURCE_LIBCAMERA:
        if (libcamera_new == NULL) {
            snprintf(err, errlen, "libcamera:%s: this program was built without libcamera "
                                  "(install libcamera-dev and rebuild mocap-node)",
                     params->arg);
            errno = ENOTSUP;
            break;
        }
        c->ops = libcamera_ops;
        c->impl = libcamera_new((unsigned)atoi(params->arg), params->width, params->height,
                                params->buffers, &c->width, &c->height, err, errlen);
        break;
    case MN_SOURCE_REPLAY:
        c->ops = &mn_capture_replay_ops;
        c->impl = mn_capture_replay_new(&params->replay, &c->width, &c->height, err, errlen);
        break;
    }
    if (c->impl == NULL) {
        int e = errno;
        free(c);
        errno = e;
        return NULL;
    }
    return c;
}

void mn_capture_close(struct mn_capture *c)
{
    if (c == NULL)
        return;
    c->ops->close(c->impl);
    free(c);
}

const char *mn_capture_name(const struct mn_capture *c)
{
    return c->ops->name;
}

int mn_capture_start(struct mn_capture *c)
{
    return c->ops->start(c->impl);
}

int mn_capture_stop(struct mn_capture *c)
{
    return c->ops->stop(c->impl);
}

int mn_capture_fd(const struct mn_capture *c)
{
    return c->ops->fd(c->impl);
}

int mn_capture_dequeue(struct mn_capture *c, struct mn_frame *frame)
{
    return c->ops->dequeue(c->impl, frame);
}

int mn_capture_release(struct mn_capture *c, const struct mn_frame *frame)
{
    return c->ops->release(c->impl, frame);
}

int mn_capture_set_exposure(struct mn_capture *c, uint32_t exposure_us)
{
    if (c->ops->set_exposure == NULL) {
        errno = ENOTSUP; /* the source's exposure is fixed */
        return -1;
    }
    return c->ops->set_exposure(c->impl, exposure_us);
}

bool mn_capture_exposure_fixed(const struct mn_capture *c)
{
    return c->ops->set_exposure == NULL && c->ops->set_gain == NULL;
}

int mn_capture_set_gain(struct mn_capture *c, uint32_t gain_milli)
{
    if (c->ops->set_gain == NULL) {
        errno = ENOTSUP; /* the source's gain is fixed */
        return -1;
    }
    return c->ops->set_gain(c->impl, gain_milli);
}

int mn_capture_set_picture(struct mn_capture *c, enum mn_picture_control which, uint32_t pct,
                           double *value_out)
{
    return c->ops->set_picture(c->impl, which, pct, value_out);
}

void mn_capture_max_size(const struct mn_capture *c, uint32_t *width, uint32_t *height)
{
    *width = c->width;
    *height = c->height;
}
