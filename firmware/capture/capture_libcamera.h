/* C interface of the libcamera capture backend (capture_libcamera.cpp). Built only when
 * pkg-config finds libcamera (MN_HAVE_LIBCAMERA); otherwise mn_capture_open refuses a
 * libcamera: source with a message saying so. */
#ifndef MN_CAPTURE_LIBCAMERA_H
#define MN_CAPTURE_LIBCAMERA_H

#include <stddef.h>
#include <stdint.h>

#include "capture/capture.h"

#ifdef __cplusplus
extern "C" {
#endif

extern const struct mn_capture_ops mn_capture_libcamera_ops;

/* Opens camera number `index` of libcamera's list, configured for 8-bit luma (R8, else the Y
 * plane of YUV420) at width x height (0 x 0: the camera's default). NULL with errno set and the
 * reason in err. */
void *mn_capture_libcamera_new(unsigned index, uint32_t width, uint32_t height, uint32_t buffers,
                               uint32_t *out_width, uint32_t *out_height, char *err,
                               size_t errlen);

#ifdef __cplusplus
}
#endif

#endif
