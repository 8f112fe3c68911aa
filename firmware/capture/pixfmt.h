/* Pixel-format conversion to 8-bit luma for capture sources whose sensor or driver does not
 * deliver GREY: pure functions over caller-owned rows, so they are tested without a device. */
#ifndef MN_PIXFMT_H
#define MN_PIXFMT_H

#include <stddef.h>
#include <stdint.h>

enum mn_pixfmt {
    MN_PIXFMT_Y10,  /* 10 significant bits in little-endian 16-bit words */
    MN_PIXFMT_Y16,  /* 16-bit little-endian luma */
    MN_PIXFMT_YUYV, /* packed 4:2:2, Y0 U Y1 V */
};

/* Converts w x h pixels, source rows src_stride bytes apart, into dst (dst_stride per row). */
void mn_pixfmt_to_y8(enum mn_pixfmt fmt, const uint8_t *src, size_t src_stride, uint32_t w,
                     uint32_t h, uint8_t *dst, size_t dst_stride);

#endif
