/* The per-frame path: a chunked scan that reads every pixel once at close to memory speed,
 * and a scanline seed fill (seed 000, 4.1.2) started only from bright pixels it finds. The
 * fill's span list doubles as its queue, so each span is found, marked and queued once. */
#include <errno.h>
#include <string.h>

#include "detect/detect.h"
#include "detect/detect_internal.h"

/* Largest value of n pixels (n a multiple of 64 in the hot path); written as a plain reduction
 * so that the compiler turns it into byte-wise vector maxima (SSE2 pmaxub, NEON umax) without
 * intrinsics. */
static inline uint8_t chunk_max(const uint8_t *p, uint32_t n)
{
    uint8_t m = 0;
    for (uint32_t i = 0; i < n; i++)
        m = p[i] > m ? p[i] : m;
    return m;
}

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "chunk_bits assumes little-endian words (x86-64, arm64 Linux)"
#endif

/* Bit i set when p[i] > t, for 64 pixels, eight at a time in plain 64-bit arithmetic: byte b
 * exceeds t exactly when b + (255 - t) carries out of the byte, and that carry is the
 * majority of the two top bits and the carry into bit 7 from the low seven bits. A multiply
 * then gathers the eight per-byte flags into eight adjacent bits. */
static inline uint64_t chunk_bits(const uint8_t *p, uint8_t t)
{
    const uint64_t high = 0x8080808080808080ull, low = ~high;
    const uint64_t k = (uint64_t)(255u - t) * 0x0101010101010101ull;
    uint64_t bits = 0;
    for (int i = 0; i < 8; i++) {
        uint64_t x;
        memcpy(&x, p + 8 * i, 8);
        uint64_t carry_in = (x & low) + (k & low);
        uint64_t carry_out = ((x & k) | ((x | k) & carry_in)) & high;
        bits |= (((carry_out >> 7) * 0x0102040810204080ull) >> 56) << (8 * i);
    }
    return bits;
}

struct run_ctx {
    struct mn_blob *out;
    size_t cap;
    size_t n;
};

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
    const struct mn_fill r = mn_fill_image(det, f, x, y);
    const uint32_t *bbox = r.bbox;
    const size_t n = r.n;
    det->stats.candidates++;
    if (!r.complete) {
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

/* Seeds wait MN_SEED_LAG rows before their regions are filled: by then the scan has just read
 * the rows a marker spans, so the centroid pass finds them in the first-level cache instead of
 * meeting one cache miss per row (measured: that stall was a third of the per-blob time). */
static inline void push_seeds(struct mn_detector *det, uint32_t x, uint32_t y, uint64_t bits)
{
    const size_t word = (size_t)y * det->row_words + (x >> 6);
    if (det->has_mask)
        bits &= ~det->mask[word];
    if (!bits)
        return;
    det->bright[word] = bits;
    det->seeds[det->seed_head + det->seed_count++] = (struct mn_seed_word){y, x >> 6};
}

/* Fills the regions of queued seed words from rows up to last_y, in scan order. A word's bits
 * that an earlier fill took are gone from the bitmap already. */
static void drain_seeds(struct mn_detector *det, const struct mn_frame_view *f, uint32_t last_y,
                        struct run_ctx *ctx)
{
    while (det->seed_count > 0 && det->seeds[det->seed_head].y <= last_y) {
        const struct mn_seed_word c = det->seeds[det->seed_head++];
        det->seed_count--;
        const uint64_t *word = det->bright + (size_t)c.y * det->row_words + c.k;
        while (*word)
            process_region(det, f, c.k * 64 + (uint32_t)__builtin_ctzll(*word), c.y, ctx);
    }
}

/* One row: 256-pixel blocks are rejected with a single vector maximum (most of a marker
 * frame is dark), bright blocks are narrowed to 64-pixel chunks (exactly one word of the
 * visited and mask bitmaps), whose bright pixels are queued as seed bits. */
static void scan_row(struct mn_detector *det, const struct mn_frame_view *f, uint32_t y)
{
    const uint8_t *row = f->px + (size_t)y * f->stride;
    const uint32_t w = f->w, t = f->t;
    const uint32_t full256 = w & ~255u, full64 = w & ~63u;
    uint32_t x = 0;
    for (; x < full256; x += 256) {
        if (chunk_max(row + x, 256) <= t)
            continue;
        for (uint32_t c = x; c < x + 256; c += 64) {
            if (chunk_max(row + c, 64) > t)
                push_seeds(det, c, y, chunk_bits(row + c, f->t));
        }
    }
    for (; x < full64; x += 64) {
        if (chunk_max(row + x, 64) > t)
            push_seeds(det, x, y, chunk_bits(row + x, f->t));
    }
    uint64_t tail = 0;
    for (x = full64; x < w; x++)
        tail |= (uint64_t)(row[x] > t) << (x - full64);
    if (tail)
        push_seeds(det, full64, y, tail);
}

void mn_detect_scan_through(struct mn_detector *det, const struct mn_frame_view *f, uint32_t y)
{
    for (; det->scanned_rows <= y; det->scanned_rows++)
        scan_row(det, f, det->scanned_rows);
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
    det->seed_head = det->seed_count = 0;
    det->scanned_rows = 0;
    for (uint32_t y = 0; y < h; y++) {
        if (y >= det->scanned_rows)
            mn_detect_scan_through(det, &f, y);
        if (y >= MN_SEED_LAG)
            drain_seeds(det, &f, y - MN_SEED_LAG, &ctx);
    }
    drain_seeds(det, &f, UINT32_MAX, &ctx);
    *n_out = ctx.n;
    return 0;
}
