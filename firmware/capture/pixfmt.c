/* Pixel-format conversion to Y8 (see pixfmt.h). Values are truncated, not rounded, for the
 * 10/16-bit formats: rounding would map the top of the range past 255 and need a clamp per
 * pixel. Each format is its own loop over a row, so the compiler vectorises them. */
#include "capture/pixfmt.h"

static void rgb_row(const uint8_t *s, uint32_t w, uint32_t step, uint32_t ri, uint32_t gi,
                    uint32_t bi, uint8_t *d)
{
    for (uint32_t x = 0; x < w; x++, s += step)
        d[x] = mn_pixfmt_luma(s[ri], s[gi], s[bi]);
}

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
        case MN_PIXFMT_UYVY:
            for (uint32_t x = 0; x < w; x++)
                d[x] = s[2 * x + 1];
            break;
        case MN_PIXFMT_RGB24:
            rgb_row(s, w, 3, 0, 1, 2, d);
            break;
        case MN_PIXFMT_BGR24:
            rgb_row(s, w, 3, 2, 1, 0, d);
            break;
        case MN_PIXFMT_XRGB32:
            rgb_row(s, w, 4, 1, 2, 3, d);
            break;
        case MN_PIXFMT_XBGR32:
            rgb_row(s, w, 4, 2, 1, 0, d);
            break;
        }
    }
}

uint32_t mn_pixfmt_bytes_per_pixel(enum mn_pixfmt fmt)
{
    switch (fmt) {
    case MN_PIXFMT_RGB24:
    case MN_PIXFMT_BGR24:
        return 3;
    case MN_PIXFMT_XRGB32:
    case MN_PIXFMT_XBGR32:
        return 4;
    case MN_PIXFMT_Y10:
    case MN_PIXFMT_Y16:
    case MN_PIXFMT_YUYV:
    case MN_PIXFMT_UYVY:
        break;
    }
    return 2;
}
