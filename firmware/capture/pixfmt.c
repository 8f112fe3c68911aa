/* Pixel-format conversion to Y8 (see pixfmt.h). Values are truncated, not rounded: rounding
 * would map the top of the 10/16-bit range past 255 and need a clamp per pixel. */
#include "capture/pixfmt.h"

void mn_pixfmt_to_y8(enum mn_pixfmt fmt, const uint8_t *src, size_t src_stride, uint32_t w,
                     uint32_t h, uint8_t *dst, size_t dst_stride)
{
    for (uint32_t y = 0; y < h; y++) {
        const uint8_t *s = src + (size_t)y * src_stride;
        uint8_t *d = dst + (size_t)y * dst_stride;
        switch (fmt) {
        case MN_PIXFMT_Y10:
            for (uint32_t x = 0; x < w; x++)
                d[x] = (uint8_t)((((uint32_t)s[2 * x] | ((uint32_t)s[2 * x + 1] << 8)) & 0x3ff) >> 2);
            break;
        case MN_PIXFMT_Y16: /* the high byte of each word */
            for (uint32_t x = 0; x < w; x++)
                d[x] = s[2 * x + 1];
            break;
        case MN_PIXFMT_YUYV: /* luma is every other byte */
            for (uint32_t x = 0; x < w; x++)
                d[x] = s[2 * x];
            break;
        }
    }
}
