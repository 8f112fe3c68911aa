/* Pixel-format conversion to 8-bit luma for capture sources whose sensor or driver does not
 * deliver GREY: pure functions over caller-owned rows, so they are tested without a device.
 * Formats whose first plane is already 8-bit luma (GREY, YUV420, YVU420, NV12, NV21) need no
 * conversion: the sources hand that plane out in place. */
#ifndef MN_PIXFMT_H
#define MN_PIXFMT_H

#include <stddef.h>
#include <stdint.h>

enum mn_pixfmt {
    MN_PIXFMT_Y10,    /* 10 significant bits in little-endian 16-bit words */
    MN_PIXFMT_Y16,    /* 16-bit little-endian luma */
    MN_PIXFMT_YUYV,   /* packed 4:2:2, Y0 U Y1 V */
    MN_PIXFMT_UYVY,   /* packed 4:2:2, U Y0 V Y1 */
    MN_PIXFMT_RGB24,  /* R, G, B bytes (V4L2 RGB3; libcamera BGR888) */
    MN_PIXFMT_BGR24,  /* B, G, R bytes (V4L2 BGR3; libcamera RGB888) */
    MN_PIXFMT_XRGB32, /* X, R, G, B bytes (V4L2 BX24) */
    MN_PIXFMT_XBGR32, /* B, G, R, X bytes (V4L2 XR24; libcamera XRGB8888) */
};

/* Luma of one RGB pixel: BT.601 weights, full range, rounded (0 -> 0, 255 -> 255). */
static inline uint8_t mn_pixfmt_luma(uint32_t r, uint32_t g, uint32_t b)
{
    return (uint8_t)((77 * r + 150 * g + 29 * b + 128) >> 8);
}

/* Converts w x h pixels, source rows src_stride bytes apart, into dst (dst_stride per row). */
void mn_pixfmt_to_y8(enum mn_pixfmt fmt, const uint8_t *src, size_t src_stride, uint32_t w,
                     uint32_t h, uint8_t *dst, size_t dst_stride);

/* Bytes per pixel of a packed format. */
uint32_t mn_pixfmt_bytes_per_pixel(enum mn_pixfmt fmt);

#endif
