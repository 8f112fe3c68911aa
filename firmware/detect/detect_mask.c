/* Static-reflection masks: rectangles or the hub's cell bitmap, rasterised once into a
 * per-pixel bitmap so that the per-frame path only tests one bit. */
#include <errno.h>
#include <string.h>

#include "detect/detect.h"
#include "detect/detect_internal.h"

static void mask_reset(struct mn_detector *det)
{
    memset(det->mask, 0, det->row_words * det->max_h * sizeof(uint64_t));
    det->has_mask = 0;
}

/* Marks [x, x+w) x [y, y+h) clipped to the maximum frame; 64-bit arithmetic avoids overflow. */
static void mask_rect(struct mn_detector *det, uint64_t x, uint64_t y, uint64_t w, uint64_t h)
{
    if (w == 0 || h == 0 || x >= det->max_w || y >= det->max_h)
        return;
    uint64_t x1 = x + w > det->max_w ? det->max_w : x + w;
    uint64_t y1 = y + h > det->max_h ? det->max_h : y + h;
    for (uint64_t r = y; r < y1; r++)
        mn_bits_set_range(det->mask + r * det->row_words, (uint32_t)x, (uint32_t)(x1 - 1));
    det->has_mask = 1;
}

int mn_detector_set_mask_rects(struct mn_detector *det, const struct mn_rect *rects, size_t n)
{
    if (!det || (!rects && n > 0)) {
        errno = EINVAL;
        return -1;
    }
    mask_reset(det);
    for (size_t i = 0; i < n; i++)
        mask_rect(det, rects[i].x, rects[i].y, rects[i].w, rects[i].h);
    return 0;
}

int mn_detector_set_mask_bits(struct mn_detector *det, uint32_t cell_px, uint32_t cells_x,
                              uint32_t cells_y, const uint8_t *bits)
{
    if (!det || !bits || cell_px < 1 || cell_px > MN_DETECT_MAX_SIDE || cells_x < 1 ||
        cells_y < 1 || cells_x > MN_DETECT_MAX_SIDE || cells_y > MN_DETECT_MAX_SIDE) {
        errno = EINVAL;
        return -1;
    }
    mask_reset(det);
    for (uint64_t cy = 0; cy < cells_y; cy++) {
        for (uint64_t cx = 0; cx < cells_x; cx++) {
            uint64_t i = cy * cells_x + cx;
            if ((bits[i >> 3] >> (i & 7)) & 1u)
                mask_rect(det, cx * cell_px, cy * cell_px, cell_px, cell_px);
        }
    }
    return 0;
}

void mn_detector_clear_mask(struct mn_detector *det)
{
    if (det)
        mask_reset(det);
}
