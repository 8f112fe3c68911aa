/* Replay capture: recorded frames (framefile reader, DIR/frames.mcf) served like a camera in
 * external-trigger mode. Frame k of the recording is global frame k: it is stamped at its slot's
 * time plus the trigger-to-frame delay and, when paced, released at that time by a timerfd, so
 * the simulated trigger and the pairing number it k. A node started late skips to the current
 * slot, as a real camera would. Unpaced (as fast as possible), every frame is released at once
 * with the same synthetic stamps. The recording vanishing is reported like an unplugged camera.
 * A directory without frames.mcf but with *.jpg files is a webcam's recorded MJPEG frames
 * (jpeg_frames.h): file k is frame k, decoded to luma by the V4L2 source's MJPEG decoder; a
 * file that does not decode is dropped (its frame number skipped, as a camera's lost frame) and
 * counted, with a warning at most every few seconds. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include "common/clock.h"
#include "common/log.h"
#include "common/ratelimit.h"
#include "framefile/framefile.h"
#include "capture/capture.h"
#include "capture/jpeg_frames.h"

struct replay {
    struct mn_replay_params p;
    char dir[MN_CAPTURE_ARG_MAX];
    char file[MN_CAPTURE_ARG_MAX + 16];
    struct mn_ff_reader *reader;     /* frames.mcf, or */
    struct mn_jpeg_frames *jpegs;    /* recorded JPEG frames */
    size_t jpeg_next;                /* index of the next JPEG file */
    uint64_t undecodable;            /* JPEG frames dropped */
    struct mn_ratelimit drop_log;
    struct mn_ff_info info;          /* size (and, for frames.mcf, the rest of its header) */
    uint8_t *pixels;          /* the one "capture buffer" */
    int timer_fd;             /* paced mode only */
    bool loaded;              /* pixels hold the next frame to release */
    bool handed_out;          /* the frame is with the node until release */
    int64_t frame_number;     /* of the loaded frame, loops included */
    uint64_t loop_offset;     /* added to file frame numbers after each loop */
    uint64_t pass_span;       /* highest file frame number + 1 of this pass */
    bool started;
    int64_t started_mono_ns;  /* frames due before this were "exposed" before we existed */
};

void *mn_capture_replay_new(const struct mn_replay_params *params, uint32_t *out_width,
                            uint32_t *out_height, char *err, size_t errlen)
{
    struct replay *r = calloc(1, sizeof(*r));
    if (r == NULL) {
        snprintf(err, errlen, "out of memory");
        return NULL;
    }
    int e;
    r->p = *params;
    r->timer_fd = -1;
    snprintf(r->dir, sizeof(r->dir), "%s", params->dir);
    r->p.dir = r->dir;
    snprintf(r->file, sizeof(r->file), "%s/%s", r->dir, MN_FF_FILE_NAME);
    if (access(r->file, F_OK) < 0 && mn_jpeg_frames_present(r->dir)) {
        char why[320];
        r->jpegs = mn_jpeg_frames_open(r->dir, &r->info.width, &r->info.height, why,
                                       sizeof(why));
        if (r->jpegs == NULL) {
            e = errno;
            snprintf(err, errlen, "replay %s", why);
            goto fail_free;
        }
        mn_ratelimit_init(&r->drop_log, 5 * MN_NS_PER_SEC, 1);
        snprintf(r->file, sizeof(r->file), "%s", r->dir); /* what must stay readable */
        mn_log_info("replay %s: %zu JPEG frames, %ux%u", r->dir, mn_jpeg_frames_count(r->jpegs),
                    r->info.width, r->info.height);
    } else {
        const char *why = "unknown reason";
        r->reader = mn_ff_reader_open(r->dir, &why);
        if (r->reader == NULL) {
            e = errno;
            snprintf(err, errlen, "replay %s: %s", r->dir, why);
            goto fail_free;
        }
        r->info = *mn_ff_reader_info(r->reader);
    }
    r->pixels = malloc((size_t)r->info.width * r->info.height);
    if (r->pixels == NULL) {
        e = ENOMEM;
        snprintf(err, errlen, "replay %s: out of memory for a %ux%u frame", r->dir,
                 r->info.width, r->info.height);
        goto fail_reader;
    }
    if (!params->as_fast_as_possible) {
        r->timer_fd = timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC);
        if (r->timer_fd < 0) {
            e = errno;
            snprintf(err, errlen, "replay: timerfd: %s", strerror(e));
            goto fail_pixels;
        }
    }
    *out_width = r->info.width;
    *out_height = r->info.height;
    return r;

fail_pixels:
    free(r->pixels);
fail_reader:
    mn_ff_reader_close(r->reader);
    mn_jpeg_frames_close(r->jpegs);
fail_free:
    free(r);
    errno = e;
    return NULL;
}

static int arm_timer(struct replay *r, int64_t at_mono_ns);

static int replay_start(void *impl)
{
    struct replay *r = impl;
    r->started = true;
    r->started_mono_ns = mn_clock_mono_ns();
    /* Paced: the first dequeue finds out when the first frame is due and re-arms. */
    if (r->timer_fd >= 0 && arm_timer(r, mn_clock_mono_ns()) < 0)
        return -1;
    return 0;
}

static int replay_stop(void *impl)
{
    ((struct replay *)impl)->started = false;
    return 0;
}

static int replay_fd(void *impl)
{
    return ((struct replay *)impl)->timer_fd;
}

static int64_t due_time(const struct replay *r, int64_t frame_number)
{
    return mn_grid_slot_mono(&r->p.grid, frame_number) + r->p.trigger_delay_ns;
}

/* A JPEG file that did not decode: counted, and said at most once per few seconds. */
static void jpeg_dropped(struct replay *r, const char *why)
{
    r->undecodable++;
    uint64_t before = 0;
    if (mn_ratelimit_allow(&r->drop_log, mn_clock_mono_ns(), &before))
        mn_log_warn("replay: dropping a frame that does not decode (%llu so far): %s",
                    (unsigned long long)r->undecodable, why);
}

/* The next JPEG file that decodes into pixels, as load_next. */
static int load_next_jpeg(struct replay *r)
{
    size_t count = mn_jpeg_frames_count(r->jpegs);
    for (size_t tried = 0; tried <= count; tried++) {
        if (access(r->file, R_OK) < 0)
            return -1;
        if (r->jpeg_next == count) {
            if (!r->p.loop)
                return 0;
            r->loop_offset += count;
            r->jpeg_next = 0;
        }
        size_t index = r->jpeg_next++;
        char why[512];
        if (mn_jpeg_frames_read(r->jpegs, index, r->pixels, why, sizeof(why)) < 0) {
            jpeg_dropped(r, why);
            continue;
        }
        r->frame_number = (int64_t)(index + r->loop_offset);
        r->loaded = true;
        return 1;
    }
    return 0; /* a whole pass without one frame that decodes */
}

/* Reads the next recorded frame into pixels; 1, 0 at the end (no loop), -1 on error. */
static int load_next(struct replay *r)
{
    if (r->jpegs != NULL)
        return load_next_jpeg(r);
    /* A camera that disappears: the recording's file is gone (its directory removed). */
    if (access(r->file, R_OK) < 0)
        return -1;
    struct mn_ff_frame meta;
    for (int attempt = 0; attempt < 2; attempt++) {
        int rc = mn_ff_reader_next(r->reader, r->pixels, r->info.width, &meta);
        if (rc < 0)
            return -1;
        if (rc == 1) {
            if (meta.frame_number + 1 > r->pass_span)
                r->pass_span = meta.frame_number + 1;
            r->frame_number = (int64_t)(meta.frame_number + r->loop_offset);
            r->loaded = true;
            return 1;
        }
        if (mn_ff_reader_damaged(r->reader))
            mn_log_warn("replay %s: %s", r->dir, mn_ff_reader_message(r->reader));
        if (!r->p.loop || r->pass_span == 0)
            return 0;
        r->loop_offset += r->pass_span;
        r->pass_span = 0;
        if (mn_ff_reader_rewind(r->reader) < 0)
            return -1;
    }
    return 0;
}

static int arm_timer(struct replay *r, int64_t at_mono_ns)
{
    struct itimerspec its;
    memset(&its, 0, sizeof(its));
    its.it_value = mn_ns_to_timespec(at_mono_ns);
    return timerfd_settime(r->timer_fd, TFD_TIMER_ABSTIME, &its, NULL);
}

static int replay_dequeue(void *impl, struct mn_frame *frame)
{
    struct replay *r = impl;
    if (!r->started || r->handed_out)
        return 0;
    if (r->timer_fd >= 0) {
        uint64_t expirations;
        if (read(r->timer_fd, &expirations, sizeof(expirations)) < 0 && errno != EAGAIN)
            return -1;
    }
    int64_t now = mn_clock_mono_ns();
    int64_t period = mn_grid_period_ns(&r->p.grid);
    for (;;) {
        if (!r->loaded) {
            int rc = load_next(r);
            if (rc < 0)
                return -1;
            if (rc == 0) {
                errno = ENODATA;
                return -1;
            }
        }
        if (r->p.as_fast_as_possible)
            break;
        int64_t due = due_time(r, r->frame_number);
        /* Joining a session late: frames triggered before the source started were never
         * "captured". Frames due since then are served even when the loop is late. */
        if (due < r->started_mono_ns - period) {
            r->loaded = false;
            continue;
        }
        if (due > now) {
            if (arm_timer(r, due) < 0)
                return -1;
            return 0;
        }
        break;
    }
    frame->pixels = r->pixels;
    frame->width = r->info.width;
    frame->height = r->info.height;
    frame->stride = r->info.width;
    frame->capture_mono_ns = due_time(r, r->frame_number);
    frame->sequence = (uint64_t)r->frame_number;
    frame->slot = 0;
    r->handed_out = true;
    return 1;
}

static int replay_release(void *impl, const struct mn_frame *frame)
{
    struct replay *r = impl;
    (void)frame;
    r->handed_out = false;
    r->loaded = false;
    /* Paced: make the timer fire for the next frame right away so dequeue can arm it. */
    if (r->timer_fd >= 0 && arm_timer(r, mn_clock_mono_ns()) < 0)
        return -1;
    return 0;
}

static int no_picture(void *impl, enum mn_picture_control which, uint32_t pct, double *value_out)
{
    (void)impl, (void)which, (void)pct, (void)value_out;
    errno = ENOTSUP; /* a recording's picture is fixed */
    return -1;
}

static void replay_close(void *impl)
{
    struct replay *r = impl;
    if (r->timer_fd >= 0)
        close(r->timer_fd);
    free(r->pixels);
    mn_ff_reader_close(r->reader);
    mn_jpeg_frames_close(r->jpegs);
    free(r);
}

const struct mn_capture_ops mn_capture_replay_ops = {
    .name = "replay",
    .start = replay_start,
    .stop = replay_stop,
    .fd = replay_fd,
    .dequeue = replay_dequeue,
    .release = replay_release,
    .set_exposure = NULL, /* a recording's exposure and gain are fixed */
    .set_gain = NULL,
    .set_picture = no_picture,
    .close = replay_close,
};
