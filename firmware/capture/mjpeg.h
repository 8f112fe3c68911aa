/* MJPEG frames (UVC webcams) to their 8-bit luma through libjpeg-turbo's TurboJPEG API: only the
 * Y component is turned into pixels (TJPF_GRAY: no chroma upsampling or colour conversion), with
 * the accurate DCT, so the luma is exactly the Y plane of a full decode. libturbojpeg is a
 * required dependency of the node (natively and for arm64). */
#ifndef MN_MJPEG_H
#define MN_MJPEG_H

#include <stddef.h>
#include <stdint.h>

struct mn_mjpeg;

/* NULL when the decoder cannot be made (out of memory). */
struct mn_mjpeg *mn_mjpeg_new(void);
void mn_mjpeg_free(struct mn_mjpeg *d);

/* Decodes one JPEG image of exactly w x h into dst (dst_stride per row). -1 with *why when the
 * data is not a JPEG image of that size or does not decode; dst may then hold part of a frame. */
int mn_mjpeg_to_y8(struct mn_mjpeg *d, const uint8_t *jpeg, size_t size, uint32_t w, uint32_t h,
                   uint8_t *dst, size_t dst_stride, const char **why);

/* Largest side mn_mjpeg_size accepts (the framefile's limit too). */
#define MN_MJPEG_MAX_SIDE 16384

/* The size of the JPEG image in jpeg: 0, or -1 with *why when its header does not read. */
int mn_mjpeg_size(struct mn_mjpeg *d, const uint8_t *jpeg, size_t size, uint32_t *w, uint32_t *h,
                  const char **why);

/* The most bytes a JPEG image of w x h can take (TurboJPEG's bound, 4:4:4); 0 when w x h is
 * larger than TurboJPEG handles. Readers of recorded frames refuse larger files with it. */
size_t mn_mjpeg_max_bytes(uint32_t w, uint32_t h);

#endif
