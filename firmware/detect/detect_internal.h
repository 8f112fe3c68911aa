/* Detector internals shared by the detector source files: the detector struct, the span type and
 * the per-frame view. Not part of the public API. */
#ifndef MN_DETECT_DETECT_INTERNAL_H
#define MN_DETECT_DETECT_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

#include "detect/detect.h"

#define MN_DETECT_MAX_MORPH_RADIUS 8
#define MN_DETECT_MAX_BBOX 1024
#define MN_PATCH_PLANES 6

/* One horizontal run of blob pixels on row y, inclusive ends. Sides are <= 16384 pixels. */
struct mn_span {
    uint16_t x0, x1;
    uint32_t y;
};

/* Rows between finding a bright chunk and filling its regions (see detect_run.c). */
#define MN_SEED_LAG 24u

/* A 64-pixel chunk of row y (word k of the bright bitmap) that held bright pixels. */
struct mn_seed_word {
    uint32_t y, k;
};

struct mn_detector {
    struct mn_detect_config cfg;
    uint32_t max_w, max_h;
    uint16_t cap_bbox;   /* max_bbox at creation: sizes the morphology patch */
    uint8_t cap_radius;  /* morph_radius at creation: likewise */
    size_t row_words;    /* uint64 words per row of the bright and mask bitmaps */
    /* 1 = bright, unmasked pixel not yet taken by a region. The scan sets bits, the fill
     * consumes them, so the bitmap is all zero again when a frame is done. */
    uint64_t *bright;
    uint64_t *mask;      /* 1 = pixel hidden by the hub's mask */
    int has_mask;
    struct mn_span *spans;
    size_t spans_cap;
    struct mn_seed_word *seeds; /* bright words in scan order, up to one per bitmap word */
    size_t seed_head, seed_count;
    uint32_t scanned_rows; /* rows of the current frame the scan has read */
    uint64_t *patch[MN_PATCH_PLANES]; /* morphology bit planes, patch_rows x patch_words */
    size_t patch_words;
    size_t patch_rows;
    struct mn_detect_stats stats;
};

/* The frame being processed and the threshold chosen for it. */
struct mn_frame_view {
    const uint8_t *px;
    size_t stride;
    uint32_t w, h;
    uint8_t t;
};

static inline int mn_bit_get(const uint64_t *bits, size_t row_words, uint32_t x, uint32_t y)
{
    return (int)((bits[(size_t)y * row_words + (x >> 6)] >> (x & 63)) & 1u);
}

/* Sets bits x0..x1 (inclusive) of one bitmap row. */
static inline void mn_bits_set_range(uint64_t *row, uint32_t x0, uint32_t x1)
{
    uint32_t w0 = x0 >> 6, w1 = x1 >> 6;
    uint64_t lo = ~0ull << (x0 & 63);
    uint64_t hi = ~0ull >> (63 - (x1 & 63));
    if (w0 == w1) {
        row[w0] |= lo & hi;
        return;
    }
    row[w0] |= lo;
    for (uint32_t k = w0 + 1; k < w1; k++)
        row[k] = ~0ull;
    row[w1] |= hi;
}

/* Threshold for this frame from a sampled histogram (auto mode). */
uint8_t mn_detect_auto_threshold(const struct mn_detector *det, const struct mn_frame_view *f);

/* Scans rows up to and including y if the scan has not reached them yet (detect_run.c). */
void mn_detect_scan_through(struct mn_detector *det, const struct mn_frame_view *f, uint32_t y);

/* Spans of one 8-connected set of bits, taken out of a bitmap (detect_fill.c). */
struct mn_fill {
    size_t n;          /* spans written */
    uint32_t bbox[4];  /* x0, y0, x1, y1 */
    int complete;      /* 0 when the span list overflowed: the rest stays in the bitmap */
};

/* The region of the bright bitmap through (x, y), into det->spans; rows below the scan are
 * scanned on demand, so a region taller than the seed lag is still whole. */
struct mn_fill mn_fill_image(struct mn_detector *det, const struct mn_frame_view *f, uint32_t x,
                             uint32_t y);

/* The component through (x, y) of a w x h bit plane (rows stride words apart, bits beyond w
 * in the row's last used word zero), into spans (room for the plane's worst case). */
struct mn_fill mn_fill_plane(uint64_t *plane, size_t stride, uint32_t w, uint32_t h, uint32_t x,
                             uint32_t y, struct mn_span *spans, size_t cap);

/* Computes a blob from n spans; returns 1 if it passes the filters (counted in stats if not). */
int mn_detect_blob_from_spans(struct mn_detector *det, const struct mn_frame_view *f,
                              const struct mn_span *spans, size_t n, struct mn_blob *out);

/* Opening then closing of one region's spans on a bit patch; the resulting components are
 * handed to emit one by one as span lists. The region's spans are det->spans[0, n). */
typedef void (*mn_emit_fn)(struct mn_detector *det, const struct mn_frame_view *f,
                           const struct mn_span *spans, size_t n, void *ctx);
void mn_detect_morph_region(struct mn_detector *det, const struct mn_frame_view *f, size_t n,
                            uint32_t bx0, uint32_t by0, uint32_t bx1, uint32_t by1,
                            mn_emit_fn emit, void *ctx);

#endif
