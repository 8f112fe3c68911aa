/* V4L2 capture: mmap streaming with the buffers owned by this handle (open / init / start / stop
 * / uninit / close), DQBUF -> process bytesused -> QBUF, EINTR retried, EAGAIN = no frame yet.
 * GREY and the Y plane of YUV420, YVU420, NV12 and NV21 are handed out in place; the packed
 * formats (Y10, Y16, YUYV, UYVY, RGB24, BGR24, XRGB32, XBGR32) are converted to Y8, and MJPEG
 * decoded to its luma (libjpeg-turbo), into one buffer allocated at open. Sensors in
 * external-trigger mode simply deliver a buffer per pulse, so nothing here assumes a frame rate. V4L2 uAPI types stay inside this file and v4l2_buffers.h (the buffer
 * calls it shares with the vivid test's feeder). */
#include <errno.h>
#include <fcntl.h>
#include <linux/videodev2.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "common/clock.h"
#include "common/log.h"
#include "common/ratelimit.h"
#include "capture/capture.h"
#include "capture/pixfmt.h"
#include "capture/mjpeg.h"
#include "capture/v4l2_buffers.h"

#define MAX_BUFFERS 32

/* What the node does with a V4L2 pixel format. */
enum handling { IN_PLACE, CONVERT, DECODE };

struct format {
    uint32_t fourcc;
    enum handling how;
    enum mn_pixfmt pixfmt;    /* CONVERT */
    uint32_t bytes_per_pixel; /* of the first plane; 0 for a compressed format */
};

/* Formats we accept, best first: the in-place ones need no pass over the pixels, the packed
 * ones one pass, MJPEG a decode. A configured pixel_format picks one of them instead. */
static const struct format formats[] = {
    {V4L2_PIX_FMT_GREY, IN_PLACE, MN_PIXFMT_Y16, 1},
    {V4L2_PIX_FMT_NV12, IN_PLACE, MN_PIXFMT_Y16, 1},
    {V4L2_PIX_FMT_NV21, IN_PLACE, MN_PIXFMT_Y16, 1},
    {V4L2_PIX_FMT_YUV420, IN_PLACE, MN_PIXFMT_Y16, 1},
    {V4L2_PIX_FMT_YVU420, IN_PLACE, MN_PIXFMT_Y16, 1},
    {V4L2_PIX_FMT_Y10, CONVERT, MN_PIXFMT_Y10, 2},
    {V4L2_PIX_FMT_Y16, CONVERT, MN_PIXFMT_Y16, 2},
    {V4L2_PIX_FMT_YUYV, CONVERT, MN_PIXFMT_YUYV, 2},
    {V4L2_PIX_FMT_UYVY, CONVERT, MN_PIXFMT_UYVY, 2},
    {V4L2_PIX_FMT_XRGB32, CONVERT, MN_PIXFMT_XRGB32, 4},
    {V4L2_PIX_FMT_XBGR32, CONVERT, MN_PIXFMT_XBGR32, 4},
    {V4L2_PIX_FMT_RGB24, CONVERT, MN_PIXFMT_RGB24, 3},
    {V4L2_PIX_FMT_BGR24, CONVERT, MN_PIXFMT_BGR24, 3},
    {V4L2_PIX_FMT_MJPEG, DECODE, MN_PIXFMT_Y16, 0},
};
#define N_FORMATS (sizeof(formats) / sizeof(formats[0]))

struct v4l2 {
    int fd;
    char device[MN_CAPTURE_ARG_MAX];
    const struct format *format;
    uint32_t fourcc;
    uint32_t width, height, bytesperline, sizeimage;
    struct mn_v4l2_map maps[MAX_BUFFERS];
    uint32_t n_maps;
    uint8_t *y8; /* conversion target for formats not used in place */
    struct mn_mjpeg *mjpeg;
    uint64_t undecodable;         /* MJPEG frames dropped */
    struct mn_ratelimit drop_log; /* their warnings */
    bool streaming;
    bool warned_stamps; /* said once that the driver has no monotonic time stamps */
};

static bool device_offers(int fd, uint32_t fourcc)
{
    struct v4l2_fmtdesc d;
    for (uint32_t i = 0;; i++) {
        memset(&d, 0, sizeof(d));
        d.index = i;
        d.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        if (mn_v4l2_ioctl(fd, VIDIOC_ENUM_FMT, &d) < 0)
            return false;
        if (d.pixelformat == fourcc)
            return true;
    }
}

/* "Y10" -> v4l2_fourcc('Y', '1', '0', ' '): the name as v4l2-ctl --list-formats prints it. */
static uint32_t fourcc_of(const char *name)
{
    char c[4] = {' ', ' ', ' ', ' '};
    for (size_t i = 0; i < 4 && name[i] != '\0'; i++)
        c[i] = name[i];
    return v4l2_fourcc(c[0], c[1], c[2], c[3]);
}

/* Appends the fourcc as v4l2-ctl --list-formats names it ("Y10", no trailing blank, "-BE" for
 * a big-endian variant) to the comma-separated list in buf; false when it does not fit (the
 * list then ends in ", ..."). */
static bool append_fourcc(char *buf, size_t len, size_t *used, uint32_t fourcc)
{
    char name[5];
    uint32_t plain = fourcc & ~(1u << 31); /* the big-endian variant flag */
    memcpy(name, &plain, 4);
    name[4] = '\0';
    for (int i = 3; i > 0 && name[i] == ' '; i--)
        name[i] = '\0';
    int n = snprintf(buf + *used, len - *used, "%s%s%s", *used ? ", " : "", name,
                     plain != fourcc ? "-BE" : "");
    if (n < 0 || (size_t)n >= len - *used) {
        /* Cut here, and say so when there is room. */
        snprintf(buf + *used, len - *used, "%s", *used && len - *used > 5 ? ", ..." : "");
        return false;
    }
    *used += (size_t)n;
    return true;
}

/* The fourccs the device offers ("none" when it lists none) and those the node reads in its
 * order of preference, for the messages that refuse a device. */
static void list_formats(int fd, char *offered, size_t offered_len, char *readable,
                         size_t readable_len)
{
    size_t used = 0;
    offered[0] = '\0';
    struct v4l2_fmtdesc d;
    for (uint32_t i = 0; i < 64; i++) {
        memset(&d, 0, sizeof(d));
        d.index = i;
        d.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        if (mn_v4l2_ioctl(fd, VIDIOC_ENUM_FMT, &d) < 0 ||
            !append_fourcc(offered, offered_len, &used, d.pixelformat))
            break;
    }
    if (used == 0)
        snprintf(offered, offered_len, "none");
    used = 0;
    readable[0] = '\0';
    for (size_t i = 0; i < N_FORMATS; i++)
        if (!append_fourcc(readable, readable_len, &used, formats[i].fourcc))
            break;
}

/* The format to ask for: the configured one (refused when the node cannot use it or the device
 * does not offer it), else the first of the table the device offers. */
static const struct format *choose_format(struct v4l2 *v, const char *wanted, char *err,
                                          size_t errlen)
{
    if (wanted[0] != '\0') {
        uint32_t fourcc = fourcc_of(wanted);
        for (size_t i = 0; i < N_FORMATS; i++) {
            if (formats[i].fourcc != fourcc)
                continue;
            if (device_offers(v->fd, fourcc))
                return &formats[i];
            char offered[160], readable[160];
            list_formats(v->fd, offered, sizeof(offered), readable, sizeof(readable));
            snprintf(err, errlen, "%s: pixel_format %s is not offered by the device (it offers %s)",
                     v->device, wanted, offered);
            errno = ENOTSUP;
            return NULL;
        }
        char offered[160], readable[160];
        list_formats(v->fd, offered, sizeof(offered), readable, sizeof(readable));
        snprintf(err, errlen, "%s: pixel_format %s is not one this mocap-node reads (%s)",
                 v->device, wanted, readable);
        errno = ENOTSUP;
        return NULL;
    }
    for (size_t i = 0; i < N_FORMATS; i++)
        if (device_offers(v->fd, formats[i].fourcc))
            return &formats[i];
    char offered[160], readable[160];
    list_formats(v->fd, offered, sizeof(offered), readable, sizeof(readable));
    snprintf(err, errlen, "%s: offers none of the formats this mocap-node reads (it offers %s; "
                          "the node reads, best first, %s)",
             v->device, offered, readable);
    errno = ENOTSUP;
    return NULL;
}

/* Bytes a buffer must hold for the luma the node reads (a compressed frame: any). */
static size_t luma_bytes(const struct v4l2 *v)
{
    if (v->format->how == DECODE)
        return 1;
    return (size_t)v->bytesperline * (v->height - 1) + (size_t)v->width * v->format->bytes_per_pixel;
}

static int negotiate(struct v4l2 *v, uint32_t want_w, uint32_t want_h, const char *want_format,
                     char *err, size_t errlen)
{
    struct v4l2_format fmt;
    memset(&fmt, 0, sizeof(fmt));
    fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (mn_v4l2_ioctl(v->fd, VIDIOC_G_FMT, &fmt) < 0) {
        snprintf(err, errlen, "%s: VIDIOC_G_FMT: %s", v->device, strerror(errno));
        return -1;
    }
    v->format = choose_format(v, want_format, err, errlen);
    if (v->format == NULL)
        return -1;
    uint32_t fourcc = v->format->fourcc;
    fmt.fmt.pix.pixelformat = fourcc;
    fmt.fmt.pix.field = V4L2_FIELD_NONE;
    if (want_w != 0) {
        fmt.fmt.pix.width = want_w;
        fmt.fmt.pix.height = want_h;
    }
    if (mn_v4l2_ioctl(v->fd, VIDIOC_S_FMT, &fmt) < 0) {
        snprintf(err, errlen, "%s: VIDIOC_S_FMT: %s", v->device, strerror(errno));
        return -1;
    }
    if (fmt.fmt.pix.pixelformat != fourcc) {
        snprintf(err, errlen, "%s: driver replaced the pixel format", v->device);
        errno = ENOTSUP;
        return -1;
    }
    if (want_w != 0 && (fmt.fmt.pix.width != want_w || fmt.fmt.pix.height != want_h))
        mn_log_warn("%s: asked for %ux%u, driver chose %ux%u", v->device, want_w, want_h,
                    fmt.fmt.pix.width, fmt.fmt.pix.height);
    v->fourcc = fourcc;
    v->width = fmt.fmt.pix.width;
    v->height = fmt.fmt.pix.height;
    v->bytesperline = fmt.fmt.pix.bytesperline;
    /* Some drivers leave bytesperline 0 for packed formats. */
    if (v->bytesperline < v->width * v->format->bytes_per_pixel)
        v->bytesperline = v->width * v->format->bytes_per_pixel;
    v->sizeimage = fmt.fmt.pix.sizeimage;
    if (v->width == 0 || v->height == 0 || v->sizeimage < luma_bytes(v)) {
        snprintf(err, errlen, "%s: driver reports an inconsistent format %ux%u/%u/%u", v->device,
                 v->width, v->height, v->bytesperline, v->sizeimage);
        errno = EPROTO;
        return -1;
    }
    return 0;
}

static void unmap_buffers(struct v4l2 *v)
{
    mn_v4l2_unmap_buffers(v->maps, &v->n_maps);
    struct v4l2_requestbuffers req;
    memset(&req, 0, sizeof(req));
    req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    req.memory = V4L2_MEMORY_MMAP;
    mn_v4l2_ioctl(v->fd, VIDIOC_REQBUFS, &req); /* count 0 frees them; may fail if the device is gone */
}

void *mn_capture_v4l2_new(const char *device, uint32_t width, uint32_t height, uint32_t buffers,
                          const char *pixel_format, uint32_t *out_width, uint32_t *out_height, char *err, size_t errlen)
{
    struct v4l2 *v = calloc(1, sizeof(*v));
    if (v == NULL) {
        snprintf(err, errlen, "out of memory");
        return NULL;
    }
    int e;
    snprintf(v->device, sizeof(v->device), "%s", device);
    v->fd = open(device, O_RDWR | O_NONBLOCK | O_CLOEXEC);
    if (v->fd < 0) {
        e = errno;
        snprintf(err, errlen, "%s: %s", device, strerror(e));
        goto fail_free;
    }
    struct v4l2_capability cap;
    memset(&cap, 0, sizeof(cap));
    if (mn_v4l2_ioctl(v->fd, VIDIOC_QUERYCAP, &cap) < 0) {
        e = errno;
        snprintf(err, errlen, "%s: not a V4L2 device (%s)", device, strerror(e));
        goto fail_close;
    }
    uint32_t caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
    if (!(caps & V4L2_CAP_VIDEO_CAPTURE) || !(caps & V4L2_CAP_STREAMING)) {
        snprintf(err, errlen, "%s: not a single-planar streaming capture device%s", device,
                 (caps & V4L2_CAP_VIDEO_CAPTURE_MPLANE) ? " (multi-planar is not supported)" : "");
        e = ENOTSUP;
        goto fail_close;
    }
    if (negotiate(v, width, height, pixel_format, err, errlen) < 0) {
        e = errno;
        goto fail_close;
    }
    if (v->format->how != IN_PLACE) {
        v->y8 = malloc((size_t)v->width * v->height);
        if (v->y8 == NULL) {
            e = ENOMEM;
            snprintf(err, errlen, "out of memory for the Y8 conversion buffer");
            goto fail_close;
        }
    }
    if (v->format->how == DECODE && (v->mjpeg = mn_mjpeg_new()) == NULL) {
        e = ENOMEM;
        snprintf(err, errlen, "%s: cannot start the JPEG decoder", device);
        goto fail_y8;
    }
    mn_ratelimit_init(&v->drop_log, 5 * MN_NS_PER_SEC, 1);
    if (mn_v4l2_map_buffers(v->fd, v->device, V4L2_BUF_TYPE_VIDEO_CAPTURE, buffers, v->maps,
                            MAX_BUFFERS, &v->n_maps, err, errlen) < 0) {
        e = errno;
        goto fail_unmap;
    }
    *out_width = v->width;
    *out_height = v->height;
    mn_log_info("%s: %s %ux%u (%.4s), %u mmap buffers", device, (const char *)cap.card, v->width,
                v->height, (const char *)&v->fourcc, v->n_maps);
    return v;

fail_unmap:
    unmap_buffers(v);
    mn_mjpeg_free(v->mjpeg);
fail_y8:
    free(v->y8);
fail_close:
    close(v->fd);
fail_free:
    free(v);
    errno = e;
    return NULL;
}

static int queue(struct v4l2 *v, uint32_t index)
{
    struct v4l2_buffer buf = mn_v4l2_mmap_buffer(V4L2_BUF_TYPE_VIDEO_CAPTURE, index);
    return mn_v4l2_ioctl(v->fd, VIDIOC_QBUF, &buf);
}

static int v4l2_start(void *impl)
{
    struct v4l2 *v = impl;
    for (uint32_t i = 0; i < v->n_maps; i++)
        if (queue(v, i) < 0)
            return -1;
    enum v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (mn_v4l2_ioctl(v->fd, VIDIOC_STREAMON, &type) < 0)
        return -1;
    v->streaming = true;
    return 0;
}

static int v4l2_stop(void *impl)
{
    struct v4l2 *v = impl;
    if (!v->streaming)
        return 0;
    v->streaming = false;
    enum v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    return mn_v4l2_ioctl(v->fd, VIDIOC_STREAMOFF, &type); /* also dequeues every buffer */
}

static int v4l2_fd(void *impl)
{
    return ((struct v4l2 *)impl)->fd;
}

/* The frame's luma into v->y8; -1 when a compressed frame does not decode. */
static int convert(struct v4l2 *v, const uint8_t *src, size_t bytesused)
{
    if (v->format->how == CONVERT) {
        mn_pixfmt_to_y8(v->format->pixfmt, src, v->bytesperline, v->width, v->height, v->y8,
                        v->width);
        return 0;
    }
    const char *why = NULL;
    if (mn_mjpeg_to_y8(v->mjpeg, src, bytesused, v->width, v->height, v->y8, v->width, &why) < 0) {
        /* Counted here and, as a sequence gap, in the node's dropped frames. */
        v->undecodable++;
        uint64_t before = 0;
        if (mn_ratelimit_allow(&v->drop_log, mn_clock_mono_ns(), &before))
            mn_log_warn("%s: dropping an MJPEG frame that does not decode (%llu so far): %s",
                        v->device, (unsigned long long)v->undecodable, why);
        return -1;
    }
    return 0;
}

static int v4l2_dequeue(void *impl, struct mn_frame *frame)
{
    struct v4l2 *v = impl;
    struct v4l2_buffer buf = mn_v4l2_mmap_buffer(V4L2_BUF_TYPE_VIDEO_CAPTURE, 0);
    if (mn_v4l2_ioctl(v->fd, VIDIOC_DQBUF, &buf) < 0)
        return errno == EAGAIN ? 0 : -1;
    if (buf.index >= v->n_maps) {
        errno = EPROTO;
        return -1;
    }
    if ((buf.flags & V4L2_BUF_FLAG_ERROR) || buf.bytesused < luma_bytes(v) ||
        buf.bytesused > v->maps[buf.index].length) {
        /* A corrupted or short frame: give the buffer back and report "no frame". */
        mn_log_debug("%s: dropping buffer %u (flags 0x%x, %u bytes)", v->device, buf.index,
                     buf.flags, buf.bytesused);
        if (queue(v, buf.index) < 0)
            return -1;
        errno = EAGAIN;
        return 0;
    }
    uint32_t ts_type = buf.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK;
    if (ts_type == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC) {
        frame->capture_mono_ns = (int64_t)buf.timestamp.tv_sec * MN_NS_PER_SEC +
                                 (int64_t)buf.timestamp.tv_usec * 1000;
    } else {
        /* No kernel stamp: dequeue time is the best we have (adds scheduling jitter). */
        if (!v->warned_stamps)
            mn_log_warn("%s: driver gives no monotonic time stamps; using dequeue time",
                        v->device);
        v->warned_stamps = true;
        frame->capture_mono_ns = mn_clock_mono_ns();
    }
    const uint8_t *data = v->maps[buf.index].start;
    if (v->format->how == IN_PLACE) {
        frame->pixels = data;
        frame->stride = v->bytesperline;
    } else {
        if (convert(v, data, buf.bytesused) < 0) {
            if (queue(v, buf.index) < 0)
                return -1;
            errno = EAGAIN;
            return 0;
        }
        frame->pixels = v->y8;
        frame->stride = v->width;
    }
    frame->width = v->width;
    frame->height = v->height;
    frame->sequence = buf.sequence;
    frame->slot = (int)buf.index;
    return 1;
}

static int v4l2_release(void *impl, const struct mn_frame *frame)
{
    return queue(impl, (uint32_t)frame->slot);
}

static int set_ctrl(struct v4l2 *v, uint32_t id, int32_t value)
{
    struct v4l2_control c = {.id = id, .value = value};
    return mn_v4l2_ioctl(v->fd, VIDIOC_S_CTRL, &c);
}

static int query_ctrl(struct v4l2 *v, uint32_t id, struct v4l2_queryctrl *q)
{
    memset(q, 0, sizeof(*q));
    q->id = id;
    if (mn_v4l2_ioctl(v->fd, VIDIOC_QUERYCTRL, q) < 0 || (q->flags & V4L2_CTRL_FLAG_DISABLED))
        return -1;
    return 0;
}

static int32_t clamp_ctrl(const struct v4l2_queryctrl *q, int64_t value)
{
    if (value < q->minimum)
        return q->minimum;
    if (value > q->maximum)
        return q->maximum;
    return (int32_t)value;
}

static int v4l2_set_exposure(void *impl, uint32_t exposure_us)
{
    struct v4l2 *v = impl;
    struct v4l2_queryctrl q;
    /* EXPOSURE_ABSOLUTE is in 100 us units; manual mode first or the driver ignores it. */
    if (query_ctrl(v, V4L2_CID_EXPOSURE_ABSOLUTE, &q) == 0) {
        set_ctrl(v, V4L2_CID_EXPOSURE_AUTO, V4L2_EXPOSURE_MANUAL);
        return set_ctrl(v, V4L2_CID_EXPOSURE_ABSOLUTE, clamp_ctrl(&q, (exposure_us + 50) / 100));
    }
    errno = ENOTSUP;
    return -1;
}

static int v4l2_set_gain(void *impl, uint32_t gain_milli)
{
    struct v4l2 *v = impl;
    struct v4l2_queryctrl q;
    /* Gain controls are in driver units; the control's default is taken as unity gain, which
     * holds for the UVC and most sensor drivers. */
    uint32_t ids[] = {V4L2_CID_ANALOGUE_GAIN, V4L2_CID_GAIN};
    for (size_t i = 0; i < 2; i++) {
        if (query_ctrl(v, ids[i], &q) < 0)
            continue;
        int64_t unity = q.default_value > 0 ? q.default_value : 1;
        return set_ctrl(v, ids[i], clamp_ctrl(&q, (unity * gain_milli + 500) / 1000));
    }
    errno = ENOTSUP;
    return -1;
}

static int v4l2_set_picture(void *impl, enum mn_picture_control which, uint32_t pct,
                            double *value_out)
{
    struct v4l2 *v = impl;
    struct v4l2_queryctrl q;
    uint32_t id = which == MN_PICTURE_BRIGHTNESS ? V4L2_CID_BRIGHTNESS : V4L2_CID_CONTRAST;
    if (query_ctrl(v, id, &q) < 0) {
        errno = ENOTSUP;
        return -1;
    }
    int64_t value = q.minimum + ((int64_t)q.maximum - q.minimum) * pct / 100;
    if (q.step > 1)
        value = q.minimum + (value - q.minimum) / q.step * q.step;
    *value_out = (double)value;
    return set_ctrl(v, id, clamp_ctrl(&q, value));
}

static void v4l2_close(void *impl)
{
    struct v4l2 *v = impl;
    v4l2_stop(v);
    unmap_buffers(v);
    mn_mjpeg_free(v->mjpeg);
    free(v->y8);
    close(v->fd);
    free(v);
}

const struct mn_capture_ops mn_capture_v4l2_ops = {
    .name = "v4l2",
    .start = v4l2_start,
    .stop = v4l2_stop,
    .fd = v4l2_fd,
    .dequeue = v4l2_dequeue,
    .release = v4l2_release,
    .set_exposure = v4l2_set_exposure,
    .set_gain = v4l2_set_gain,
    .set_picture = v4l2_set_picture,
    .close = v4l2_close,
};
