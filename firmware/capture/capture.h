/* Camera sources behind one table of function pointers: V4L2 (mmap streaming), libcamera (C++
 * shim with a C interface, when built) and replay (recorded frames). Every source hands out 8-bit
 * luma frames it owns until mn_capture_release; the node never copies a frame.
 * Lifecycle: open (allocates everything, negotiates the format) -> start -> dequeue/release ...
 * -> stop -> close. */
#ifndef MN_CAPTURE_H
#define MN_CAPTURE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "sync/grid.h"

/* Longest source argument (device path, directory) a source keeps, terminator included. */
#define MN_CAPTURE_ARG_MAX 256

enum mn_source_kind {
    MN_SOURCE_V4L2,      /* v4l2:/dev/videoN */
    MN_SOURCE_LIBCAMERA, /* libcamera:N (camera index) */
    MN_SOURCE_REPLAY,    /* replay:DIR (recorded frames) */
};

struct mn_frame {
    const uint8_t *pixels;   /* Y8, owned by the source until released */
    uint32_t width, height, stride;
    int64_t capture_mono_ns; /* kernel buffer time stamp, CLOCK_MONOTONIC */
    uint64_t sequence;       /* source's own counter (gaps = frames the source dropped) */
    int slot;                /* source's buffer index, given back on release */
};

/* Picture controls the seeds' webcams set (seed 000), where the driver has them. */
enum mn_picture_control { MN_PICTURE_BRIGHTNESS, MN_PICTURE_CONTRAST };

struct mn_capture_ops {
    const char *name;
    int (*start)(void *impl);
    int (*stop)(void *impl);
    /* Pollable descriptor (POLLIN = a frame may be ready); -1: always ready (unpaced replay). */
    int (*fd)(void *impl);
    /* 1: *frame filled; 0: no frame yet (EAGAIN); -1: error, errno set (device gone ...);
     * -1 with errno ENODATA: a recording ended (not an error: the run is over);
     * -1 with errno ENOTRECOVERABLE: the device is gone and this process cannot open it again
     * (libcamera after an unplug): close still works, and the process should exit. */
    int (*dequeue)(void *impl, struct mn_frame *frame);
    int (*release)(void *impl, const struct mn_frame *frame);
    /* Controls: -1 with errno ENOTSUP where the device has no such control. NULL for both: the
     * source's exposure and gain are fixed (a recording), as mn_capture_exposure_fixed says. */
    int (*set_exposure)(void *impl, uint32_t exposure_us);
    int (*set_gain)(void *impl, uint32_t gain_milli);
    /* A picture control at pct percent of the camera's range (0 = its minimum, 100 = maximum);
     * the value set goes to *value_out (driver units, for the log). */
    int (*set_picture)(void *impl, enum mn_picture_control which, uint32_t pct, double *value_out);
    void (*close)(void *impl);
};

/* What the replay backend needs to place frames on the grid. */
struct mn_replay_params {
    const char *dir;
    struct mn_grid grid;
    int64_t trigger_delay_ns;
    bool as_fast_as_possible;
    bool loop;
};

/* What mn_capture_open needs: the kind and its argument, the camera's size and buffers (v4l2,
 * libcamera), the pixel format asked for (v4l2) and the replay's parameters (replay). */
struct mn_capture_params {
    enum mn_source_kind kind;
    const char *arg;          /* device path, camera index or directory */
    uint32_t width, height;   /* 0 = the camera's default */
    uint32_t buffers;
    const char *pixel_format; /* V4L2 fourcc name; "" = the best the camera offers */
    struct mn_replay_params replay;
};

struct mn_capture;

/* Opens the source params name. NULL with errno set and the reason in err; close with
 * mn_capture_close. */
struct mn_capture *mn_capture_open(const struct mn_capture_params *params, char *err, size_t errlen);
void mn_capture_close(struct mn_capture *c);

const char *mn_capture_name(const struct mn_capture *c);
int mn_capture_start(struct mn_capture *c);
int mn_capture_stop(struct mn_capture *c);
int mn_capture_fd(const struct mn_capture *c);
int mn_capture_dequeue(struct mn_capture *c, struct mn_frame *frame);
int mn_capture_release(struct mn_capture *c, const struct mn_frame *frame);
int mn_capture_set_exposure(struct mn_capture *c, uint32_t exposure_us);
/* True when the source has no exposure or gain to set (recorded frames): the node then reports
 * its exposure as fixed rather than a value. */
bool mn_capture_exposure_fixed(const struct mn_capture *c);
int mn_capture_set_gain(struct mn_capture *c, uint32_t gain_milli);
int mn_capture_set_picture(struct mn_capture *c, enum mn_picture_control which, uint32_t pct,
                           double *value_out);
/* Largest frame the source can deliver (buffers sized for it); valid after open. */
void mn_capture_max_size(const struct mn_capture *c, uint32_t *width, uint32_t *height);

/* Backends. Each *_new returns its impl or NULL with errno set and the reason in err. */
typedef void *(*mn_capture_libcamera_new_fn)(unsigned index, uint32_t width, uint32_t height,
                                             uint32_t buffers, uint32_t *out_width,
                                             uint32_t *out_height, char *err, size_t errlen);
/* Makes the libcamera backend (capture_libcamera.h) available to mn_capture_open; main() does
 * this when mocap-node is built with libcamera. */
void mn_capture_register_libcamera(const struct mn_capture_ops *ops,
                                   mn_capture_libcamera_new_fn fn);
extern const struct mn_capture_ops mn_capture_v4l2_ops;
extern const struct mn_capture_ops mn_capture_replay_ops;
/* pixel_format: a V4L2 fourcc name ("NV12", "MJPG"), or "" for the best the device offers. */
void *mn_capture_v4l2_new(const char *device, uint32_t width, uint32_t height, uint32_t buffers,
                          const char *pixel_format, uint32_t *out_width, uint32_t *out_height, char *err, size_t errlen);
void *mn_capture_replay_new(const struct mn_replay_params *params, uint32_t *out_width,
                            uint32_t *out_height, char *err, size_t errlen);

#endif
