/* MJPEG to luma (see mjpeg.h). The header is read first so that a frame of another size (or
 * garbage) is refused before anything is written into the caller's buffer. A TurboJPEG handle
 * whose header read failed stays in the failed state (libjpeg-turbo 2.1: every later frame,
 * good ones too, is refused with the same message), so after any failure the handle is made
 * anew: one cut frame from a webcam must not end the stream. */
#include "capture/mjpeg.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <turbojpeg.h>

#define JMSG_LENGTH_MAX_MN 200 /* libjpeg's JMSG_LENGTH_MAX */

struct mn_mjpeg {
    tjhandle tj;
};

struct mn_mjpeg *mn_mjpeg_new(void)
{
    struct mn_mjpeg *d = calloc(1, sizeof(*d));
    if (d == NULL)
        return NULL;
    d->tj = tjInitDecompress();
    if (d->tj == NULL) {
        free(d);
        return NULL;
    }
    return d;
}

void mn_mjpeg_free(struct mn_mjpeg *d)
{
    if (d == NULL)
        return;
    if (d->tj != NULL)
        tjDestroy(d->tj);
    free(d);
}

/* The message of the failure (kept in a static buffer: the handle that held it is replaced). */
static int failed(struct mn_mjpeg *d, const char **why)
{
    static char message[JMSG_LENGTH_MAX_MN];
    snprintf(message, sizeof(message), "%s", tjGetErrorStr2(d->tj));
    *why = message;
    tjDestroy(d->tj);
    d->tj = tjInitDecompress();
    return -1;
}

/* The decoder's handle, made anew after a failure; NULL with *why when it cannot be made. */
static tjhandle handle(struct mn_mjpeg *d, const char **why)
{
    if (d->tj == NULL && (d->tj = tjInitDecompress()) == NULL)
        *why = "cannot make a JPEG decoder";
    return d->tj;
}

int mn_mjpeg_size(struct mn_mjpeg *d, const uint8_t *jpeg, size_t size, uint32_t *w, uint32_t *h,
                  const char **why)
{
    if (handle(d, why) == NULL)
        return -1;
    if (size == 0 || size > ULONG_MAX) {
        *why = "empty or oversized frame";
        return -1;
    }
    /* A header cut before its frame marker can "read" without setting the size (libjpeg-turbo
     * 2.1 then hands back whatever the handle held): zeroed first, and checked. */
    int jw = 0, jh = 0, subsamp, colorspace;
    if (tjDecompressHeader3(d->tj, jpeg, (unsigned long)size, &jw, &jh, &subsamp, &colorspace) < 0)
        return failed(d, why);
    if (jw <= 0 || jh <= 0 || jw > MN_MJPEG_MAX_SIDE || jh > MN_MJPEG_MAX_SIDE) {
        *why = "JPEG header gives no image size (cut before its frame header?)";
        return -1;
    }
    *w = (uint32_t)jw;
    *h = (uint32_t)jh;
    return 0;
}

size_t mn_mjpeg_max_bytes(uint32_t w, uint32_t h)
{
    if (w == 0 || h == 0 || w > INT_MAX || h > INT_MAX)
        return 0;
    unsigned long n = tjBufSize((int)w, (int)h, TJSAMP_444);
    return n == (unsigned long)-1 ? 0 : (size_t)n;
}

int mn_mjpeg_to_y8(struct mn_mjpeg *d, const uint8_t *jpeg, size_t size, uint32_t w, uint32_t h,
                   uint8_t *dst, size_t dst_stride, const char **why)
{
    if (handle(d, why) == NULL)
        return -1;
    if (size == 0 || size > ULONG_MAX || dst_stride > INT_MAX || w > INT_MAX || h > INT_MAX) {
        *why = "empty or oversized frame";
        return -1;
    }
    int jw = 0, jh = 0, subsamp, colorspace;
    if (tjDecompressHeader3(d->tj, jpeg, (unsigned long)size, &jw, &jh, &subsamp, &colorspace) < 0)
        return failed(d, why);
    if ((uint32_t)jw != w || (uint32_t)jh != h) {
        *why = "JPEG image size differs from the negotiated frame size";
        return -1;
    }
    if (tjDecompress2(d->tj, jpeg, (unsigned long)size, dst, (int)w, (int)dst_stride, (int)h,
                      TJPF_GRAY, TJFLAG_NOREALLOC) < 0) {
        /* Warnings come here too (a frame cut short, decoded to the end with grey fill): such
         * a frame would give false markers, so it is dropped like a corrupt one. */
        return failed(d, why);
    }
    return 0;
}
