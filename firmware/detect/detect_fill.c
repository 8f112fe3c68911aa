/* Scanline seed fill (seed 000, 4.1.2) on bitmaps, with 8-connectivity. One algorithm serves
 * both the frame (the bright bitmap the scan builds) and the morphology patch: runs are found a
 * word at a time with count-trailing/leading-zeros and taken out of the bitmap as they are
 * queued, so each run is found, cleared and appended once, and the span list doubles as the
 * queue. Working on bits instead of pixels keeps the per-pixel branches out of the fill. */
#include "detect/detect.h"
#include "detect/detect_internal.h"

static void clear_range(uint64_t *row, uint32_t x0, uint32_t x1)
{
    uint32_t w0 = x0 >> 6, w1 = x1 >> 6;
    uint64_t lo = ~0ull << (x0 & 63);
    uint64_t hi = ~0ull >> (63 - (x1 & 63));
    if (w0 == w1) {
        row[w0] &= ~(lo & hi);
        return;
    }
    row[w0] &= ~lo;
    for (uint32_t k = w0 + 1; k < w1; k++)
        row[k] = 0;
    row[w1] &= ~hi;
}

/* Ends of the run of set bits through bit x of a row of `words` words. */
static inline void run_ends(const uint64_t *row, size_t words, uint32_t x, uint32_t *a,
                            uint32_t *b)
{
    uint32_t k = x >> 6, off = x & 63;
    /* Rightwards: the first clear bit above x within the word, else whole words while full. */
    uint64_t stop = ~(row[k] >> off);
    if (stop != 0 && (uint32_t)__builtin_ctzll(stop) < 64 - off) {
        *b = x + (uint32_t)__builtin_ctzll(stop) - 1;
    } else {
        uint32_t kk = k + 1;
        while (kk < words && row[kk] == ~0ull)
            kk++;
        *b = kk < words ? kk * 64 + (uint32_t)__builtin_ctzll(~row[kk]) - 1 : kk * 64 - 1;
    }
    /* Leftwards, the mirror image. */
    uint64_t lstop = ~(row[k] << (63 - off));
    if (lstop != 0 && (uint32_t)__builtin_clzll(lstop) <= off) {
        *a = x + 1 - (uint32_t)__builtin_clzll(lstop);
    } else {
        uint32_t kk = k;
        while (kk > 0 && row[kk - 1] == ~0ull)
            kk--;
        *a = kk > 0 ? kk * 64 - (uint32_t)__builtin_clzll(~row[kk - 1]) : 0;
    }
}

/* The fill itself, over rows of `words` used words `stride` apart. det is NULL for a plane; for the frame it scans rows below the scan on
 * demand. Inlined into both callers, so the plane version carries no such test. */
static inline struct mn_fill fill(uint64_t *bits, size_t stride, size_t words, uint32_t w,
                                  uint32_t h, uint32_t x, uint32_t y, struct mn_span *spans, size_t cap,
                                  struct mn_detector *det, const struct mn_frame_view *f)
{
    struct mn_fill r = {0, {0, 0, 0, 0}, 1};
    uint32_t a, b;
    uint64_t *row = bits + (size_t)y * stride;
    run_ends(row, words, x, &a, &b);
    clear_range(row, a, b);
    spans[r.n++] = (struct mn_span){(uint16_t)a, (uint16_t)b, y};
    uint32_t bx0 = a, bx1 = b, by0 = y, by1 = y;

    for (size_t i = 0; i < r.n; i++) {
        const struct mn_span s = spans[i];
        const uint32_t lo = s.x0 > 0 ? s.x0 - 1u : 0u;
        const uint32_t hi = s.x1 + 1u < w ? s.x1 + 1u : w - 1u;
        for (int dir = -1; dir <= 1; dir += 2) {
            if ((dir < 0 && s.y == 0) || (dir > 0 && s.y + 1 >= h))
                continue;
            const uint32_t ny = s.y + (uint32_t)dir;
            if (det && ny >= det->scanned_rows)
                mn_detect_scan_through(det, f, ny);
            uint64_t *nrow = bits + (size_t)ny * stride;
            uint32_t nx = lo;
            while (nx <= hi) {
                const uint32_t k = nx >> 6;
                const uint64_t word = nrow[k] & (~0ull << (nx & 63));
                if (!word) {
                    nx = (k + 1) * 64;
                    continue;
                }
                nx = k * 64 + (uint32_t)__builtin_ctzll(word);
                if (nx > hi)
                    break;
                run_ends(nrow, words, nx, &a, &b);
                nx = b + 2; /* b + 1 is clear or beyond the row */
                if (r.n == cap) {
                    r.complete = 0; /* left in the bitmap: a later seed starts from it */
                    continue;
                }
                clear_range(nrow, a, b);
                spans[r.n++] = (struct mn_span){(uint16_t)a, (uint16_t)b, ny};
                bx0 = a < bx0 ? a : bx0;
                bx1 = b > bx1 ? b : bx1;
                by0 = ny < by0 ? ny : by0;
                by1 = ny > by1 ? ny : by1;
            }
        }
    }
    r.bbox[0] = bx0;
    r.bbox[1] = by0;
    r.bbox[2] = bx1;
    r.bbox[3] = by1;
    return r;
}

struct mn_fill mn_fill_image(struct mn_detector *det, const struct mn_frame_view *f, uint32_t x,
                             uint32_t y)
{
    return fill(det->bright, det->row_words, det->row_words, f->w, f->h, x, y, det->spans,
                det->spans_cap, det, f);
}

struct mn_fill mn_fill_plane(uint64_t *plane, size_t stride, uint32_t w, uint32_t h, uint32_t x,
                             uint32_t y, struct mn_span *spans, size_t cap)
{
    return fill(plane, stride, (w + 63) / 64, w, h, x, y, spans, cap, NULL, NULL);
}
