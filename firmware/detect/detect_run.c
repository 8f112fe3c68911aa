/* The per-frame path: a chunked scan that reads every pixel once at close to memory speed,
 * and a scanline seed fill (seed 000, 4.1.2) started only from bright pixels it finds. The
 * fill's span list doubles as its queue, so each span is found, marked and queued once. */
#include <errno.h>

#include "detect/detect.h"
#include "detect/detect_internal.h"

void mn_bits_set_range(uint64_t *row, uint32_t x0, uint32_t x1)
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

/* Largest value of 64 pixels; written as a plain reduction so that the compiler turns it into
 * byte-wise vector maxima (SSE2 pmaxub, NEON umax) without any intrinsics. */
static inline uint8_t chunk_max64(const uint8_t *p)
{
    uint8_t m = 0;
    for (int i = 0; i < 64; i++)
        m = p[i] > m ? p[i] : m;
    return m;
}

struct run_ctx {
    struct mn_blob *out;
    size_t cap;
    size_t n;
};

static inline int is_free_fg(const struct mn_detector *det, const struct mn_frame_view *f,
                             const uint8_t *row, uint32_t x, uint32_t y)
{
    if (row[x] <= f->t)
        return 0;
    if (mn_bit_get(det->visited, det->row_words, x, y))
        return 0;
    return !(det->has_mask && mn_bit_get(det->mask, det->row_words, x, y));
}

static void mark_span(struct mn_detector *det, uint32_t x0, uint32_t x1, uint32_t y)
{
    mn_bits_set_range(det->visited + (size_t)y * det->row_words, x0, x1);
    uint32_t w0 = x0 >> 6, w1 = x1 >> 6;
    if (w0 < det->dirty_lo[y])
        det->dirty_lo[y] = w0;
    if (w1 > det->dirty_hi[y])
        det->dirty_hi[y] = w1;
}

/* Fills the region holding free foreground pixel (sx, sy) with 8-connectivity. Returns the
 * number of spans in det->spans and its bbox; *complete is 0 when the queue overflowed. */
static size_t fill_region(struct mn_detector *det, const struct mn_frame_view *f, uint32_t sx,
                          uint32_t sy, uint32_t bbox[4], int *complete)
{
    struct mn_span *spans = det->spans;
    size_t n = 0;
    *complete = 1;

    const uint8_t *row = f->px + (size_t)sy * f->stride;
    uint32_t a = sx, b = sx;
    while (a > 0 && is_free_fg(det, f, row, a - 1, sy))
        a--;
    while (b + 1 < f->w && is_free_fg(det, f, row, b + 1, sy))
        b++;
    mark_span(det, a, b, sy);
    spans[n++] = (struct mn_span){(uint16_t)a, (uint16_t)b, sy};
    bbox[0] = a;
    bbox[1] = sy;
    bbox[2] = b;
    bbox[3] = sy;

    for (size_t i = 0; i < n; i++) {
        struct mn_span s = spans[i];
        uint32_t lo = s.x0 > 0 ? s.x0 - 1u : 0u;
        uint32_t hi = s.x1 + 1u < f->w ? s.x1 + 1u : f->w - 1u;
        for (int dir = -1; dir <= 1; dir += 2) {
            if ((dir < 0 && s.y == 0) || (dir > 0 && s.y + 1 >= f->h))
                continue;
            uint32_t ny = s.y + (uint32_t)dir;
            const uint8_t *nrow = f->px + (size_t)ny * f->stride;
            uint32_t x = lo;
            while (x <= hi) {
                if (!is_free_fg(det, f, nrow, x, ny)) {
                    x++;
                    continue;
                }
                uint32_t ra = x, rb = x;
                while (ra > 0 && is_free_fg(det, f, nrow, ra - 1, ny))
                    ra--;
                while (rb + 1 < f->w && is_free_fg(det, f, nrow, rb + 1, ny))
                    rb++;
                x = rb + 2; /* rb + 1 is background or the frame edge */
                if (n == det->spans_cap) {
                    *complete = 0;
                    continue;
                }
                mark_span(det, ra, rb, ny);
                spans[n++] = (struct mn_span){(uint16_t)ra, (uint16_t)rb, ny};
                if (ra < bbox[0])
                    bbox[0] = ra;
                if (rb > bbox[2])
                    bbox[2] = rb;
                if (ny < bbox[1])
                    bbox[1] = ny;
                if (ny > bbox[3])
                    bbox[3] = ny;
            }
        }
    }
    return n;
}

static void emit_blob(struct mn_detector *det, const struct mn_frame_view *f,
                      const struct mn_span *spans, size_t n, void *vctx)
{
    struct run_ctx *ctx = vctx;
    struct mn_blob blob;
    if (!mn_detect_blob_from_spans(det, f, spans, n, &blob))
        return;
    if (ctx->n >= ctx->cap || ctx->n >= det->cfg.max_blobs) {
        det->stats.dropped++;
        return;
    }
    ctx->out[ctx->n++] = blob;
}

static void process_region(struct mn_detector *det, const struct mn_frame_view *f, uint32_t x,
                           uint32_t y, struct run_ctx *ctx)
{
    uint32_t bbox[4];
    int complete;
    size_t n = fill_region(det, f, x, y, bbox, &complete);
    det->stats.candidates++;
    if (!complete) {
        det->stats.rejected_complex++;
        return;
    }
    uint32_t bw = bbox[2] - bbox[0] + 1, bh = bbox[3] - bbox[1] + 1;
    /* Checked before morphology too, because the patch is sized for max_bbox. */
    if (bw > det->cfg.max_bbox || bh > det->cfg.max_bbox) {
        det->stats.rejected_bbox++;
        return;
    }
    if (det->cfg.morph_radius == 0) {
        emit_blob(det, f, det->spans, n, ctx);
        return;
    }
    mn_detect_morph_region(det, f, n, bbox[0], bbox[1], bbox[2], bbox[3], emit_blob, ctx);
}

static void scan_pixels(struct mn_detector *det, const struct mn_frame_view *f,
                        const uint8_t *row, uint32_t x0, uint32_t x1, uint32_t y,
                        struct run_ctx *ctx)
{
    for (uint32_t x = x0; x < x1; x++) {
        if (is_free_fg(det, f, row, x, y))
            process_region(det, f, x, y, ctx);
    }
}

static void clear_visited(struct mn_detector *det, uint32_t h)
{
    for (uint32_t y = 0; y < h; y++) {
        uint32_t lo = det->dirty_lo[y], hi = det->dirty_hi[y];
        if (lo > hi)
            continue;
        uint64_t *row = det->visited + (size_t)y * det->row_words;
        for (uint32_t k = lo; k <= hi; k++)
            row[k] = 0;
        det->dirty_lo[y] = UINT32_MAX;
        det->dirty_hi[y] = 0;
    }
}

int mn_detector_run(struct mn_detector *det, const uint8_t *pixels, uint32_t w, uint32_t h,
                    size_t stride, struct mn_blob *out, size_t cap, size_t *n_out)
{
    if (!det || !pixels || !n_out || (!out && cap > 0) || w < 1 || h < 1 || w > det->max_w ||
        h > det->max_h || stride < w) {
        errno = EINVAL;
        return -1;
    }
    struct mn_frame_view f = {pixels, stride, w, h, det->cfg.threshold};
    det->stats = (struct mn_detect_stats){0};
    if (det->cfg.threshold_mode == MN_THRESHOLD_AUTO)
        f.t = mn_detect_auto_threshold(det, &f);
    det->stats.threshold = f.t;

    struct run_ctx ctx = {out, cap, 0};
    uint32_t full = w & ~63u;
    for (uint32_t y = 0; y < h; y++) {
        const uint8_t *row = pixels + (size_t)y * stride;
        for (uint32_t x = 0; x < full; x += 64) {
            if (chunk_max64(row + x) > f.t)
                scan_pixels(det, &f, row, x, x + 64, y, &ctx);
        }
        scan_pixels(det, &f, row, full, w, y, &ctx);
    }
    clear_visited(det, h);
    *n_out = ctx.n;
    return 0;
}
