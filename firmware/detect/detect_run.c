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

/* Bitmaps and frame of one fill, copied into locals: stores into the visited bitmap could
 * alias the detector's own fields, which would force a reload after every store. */
struct fill_view {
    const uint8_t *px;
    size_t stride;
    uint64_t *visited;
    const uint64_t *mask; /* NULL without a mask */
    size_t row_words;
    uint32_t w, h;
    uint8_t t;
};

static inline int is_free_fg(const struct fill_view *v, const uint8_t *row,
                             const uint64_t *vrow, const uint64_t *mrow, uint32_t x)
{
    if (row[x] <= v->t)
        return 0;
    if ((vrow[x >> 6] >> (x & 63)) & 1u)
        return 0;
    return !(mrow && ((mrow[x >> 6] >> (x & 63)) & 1u));
}

static void mark_span(struct mn_detector *det, uint64_t *vrow, uint32_t x0, uint32_t x1,
                      uint32_t y)
{
    mn_bits_set_range(vrow, x0, x1);
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
    const struct fill_view v = {f->px, f->stride, det->visited,
                                det->has_mask ? det->mask : NULL, det->row_words, f->w, f->h,
                                f->t};
    struct mn_span *spans = det->spans;
    const size_t cap = det->spans_cap;
    size_t n = 0;
    *complete = 1;

    const uint8_t *row = v.px + (size_t)sy * v.stride;
    uint64_t *vrow = v.visited + (size_t)sy * v.row_words;
    const uint64_t *mrow = v.mask ? v.mask + (size_t)sy * v.row_words : NULL;
    uint32_t a = sx, b = sx;
    while (a > 0 && is_free_fg(&v, row, vrow, mrow, a - 1))
        a--;
    while (b + 1 < v.w && is_free_fg(&v, row, vrow, mrow, b + 1))
        b++;
    mark_span(det, vrow, a, b, sy);
    spans[n++] = (struct mn_span){(uint16_t)a, (uint16_t)b, sy};
    uint32_t bx0 = a, bx1 = b, by0 = sy, by1 = sy;

    for (size_t i = 0; i < n; i++) {
        struct mn_span s = spans[i];
        uint32_t lo = s.x0 > 0 ? s.x0 - 1u : 0u;
        uint32_t hi = s.x1 + 1u < v.w ? s.x1 + 1u : v.w - 1u;
        for (int dir = -1; dir <= 1; dir += 2) {
            if ((dir < 0 && s.y == 0) || (dir > 0 && s.y + 1 >= v.h))
                continue;
            uint32_t ny = s.y + (uint32_t)dir;
            const uint8_t *nrow = v.px + (size_t)ny * v.stride;
            uint64_t *nvrow = v.visited + (size_t)ny * v.row_words;
            const uint64_t *nmrow = v.mask ? v.mask + (size_t)ny * v.row_words : NULL;
            uint32_t x = lo;
            while (x <= hi) {
                /* Jump over visited and masked pixels a word at a time: the row a span was
                 * found from is mostly visited already. */
                uint64_t taken = nvrow[x >> 6] | (nmrow ? nmrow[x >> 6] : 0u);
                uint64_t free_bits = ~taken >> (x & 63);
                if (!free_bits) {
                    x = (x | 63u) + 1u;
                    continue;
                }
                x += (uint32_t)__builtin_ctzll(free_bits);
                if (x > hi)
                    break;
                if (nrow[x] <= v.t) {
                    x++;
                    continue;
                }
                uint32_t ra = x, rb = x;
                while (ra > 0 && is_free_fg(&v, nrow, nvrow, nmrow, ra - 1))
                    ra--;
                while (rb + 1 < v.w && is_free_fg(&v, nrow, nvrow, nmrow, rb + 1))
                    rb++;
                x = rb + 2; /* rb + 1 is background or the frame edge */
                if (n == cap) {
                    *complete = 0;
                    continue;
                }
                mark_span(det, nvrow, ra, rb, ny);
                spans[n++] = (struct mn_span){(uint16_t)ra, (uint16_t)rb, ny};
                bx0 = ra < bx0 ? ra : bx0;
                bx1 = rb > bx1 ? rb : bx1;
                by0 = ny < by0 ? ny : by0;
                by1 = ny > by1 ? ny : by1;
            }
        }
    }
    bbox[0] = bx0;
    bbox[1] = by0;
    bbox[2] = bx1;
    bbox[3] = by1;
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

/* The last w % 64 pixels of a row, one by one. */
/* Seeds wait MN_SEED_LAG rows before their regions are filled: by then the scan has just read
 * the rows a marker spans, so the fill finds them in the first-level cache instead of meeting
 * one cache miss per row (measured: that stall was a third of the per-blob time). */
static void push_seeds(struct mn_detector *det, uint32_t x, uint32_t y, uint64_t bits)
{
    if (det->has_mask)
        bits &= ~det->mask[(size_t)y * det->row_words + (x >> 6)];
    if (!bits)
        return;
    size_t slot = (det->seed_head + det->seed_count) % det->seed_cap;
    det->seeds[slot] = (struct mn_seed_chunk){y, x, bits};
    det->seed_count++;
}

/* Fills the regions of queued seed chunks from rows up to last_y, in scan order. */
static void drain_seeds(struct mn_detector *det, const struct mn_frame_view *f, uint32_t last_y,
                        struct run_ctx *ctx)
{
    while (det->seed_count > 0 && det->seeds[det->seed_head].y <= last_y) {
        struct mn_seed_chunk c = det->seeds[det->seed_head];
        det->seed_head = (det->seed_head + 1) % det->seed_cap;
        det->seed_count--;
        const uint64_t *vword = det->visited + (size_t)c.y * det->row_words + (c.x >> 6);
        uint64_t seeds = c.bits & ~*vword;
        while (seeds) {
            uint32_t i = (uint32_t)__builtin_ctzll(seeds);
            process_region(det, f, c.x + i, c.y, ctx);
            /* The fill may have visited more of this chunk; drop bits up to i as well. */
            seeds = c.bits & ~*vword & (~1ull << i);
        }
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
    det->seed_head = det->seed_count = 0;
    for (uint32_t y = 0; y < h; y++) {
        scan_row(det, &f, y);
        if (y >= MN_SEED_LAG)
            drain_seeds(det, &f, y - MN_SEED_LAG, &ctx);
    }
    drain_seeds(det, &f, UINT32_MAX, &ctx);
    clear_visited(det, h);
    *n_out = ctx.n;
    return 0;
}
