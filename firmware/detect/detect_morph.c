/* The seed's opening and closing, applied only to one region at a time on a bit patch (its
 * bbox plus the radius), never to the whole frame. A (2r+1)^2 square is r passes of 3x3, each a
 * few word-wide shifts and ANDs/ORs. Outside the image counts as neutral (as OpenCV's default
 * border does), so a blob cut by the frame edge is not eroded from that side. */
#include "detect/detect.h"
#include "detect/detect_internal.h"

struct patch {
    uint32_t x0, y0;     /* image position of bit 0 of row 0 */
    uint32_t w, h;       /* size in pixels */
    size_t words;        /* words used per row */
    size_t stride;       /* words allocated per row */
    uint64_t tail;       /* valid bits of the last word */
    int edge[4];         /* left, top, right, bottom patch side lies on the image edge */
};

static inline uint64_t *prow(uint64_t *plane, const struct patch *p, uint32_t r)
{
    return plane + (size_t)r * p->stride;
}

/* One 3x3 erosion (erode = 1) or dilation (erode = 0) of src into dst, tmp as scratch. */
static void morph3(const struct patch *p, uint64_t *src, uint64_t *dst, uint64_t *tmp, int erode)
{
    const size_t K = p->words;
    /* Neighbours beyond the patch: for erosion, 1 where the patch ends at the image edge (no
     * constraint), 0 inside the image; for dilation always 0. */
    uint64_t fill_l = erode && p->edge[0] ? 1u : 0u;
    uint64_t fill_r = erode && p->edge[2] ? 1u : 0u;
    uint64_t top_fill = erode && p->edge[1] ? ~0ull : 0u;
    uint64_t bot_fill = erode && p->edge[3] ? ~0ull : 0u;
    uint32_t last_bit = (p->w - 1) & 63;

    for (uint32_t r = 0; r < p->h; r++) {
        const uint64_t *in = prow(src, p, r);
        uint64_t *out = prow(tmp, p, r);
        for (size_t k = 0; k < K; k++) {
            uint64_t left = (in[k] << 1) | (k > 0 ? in[k - 1] >> 63 : fill_l);
            uint64_t right = (in[k] >> 1) | (k + 1 < K ? in[k + 1] << 63 : 0u);
            if (k + 1 == K)
                right |= fill_r << last_bit;
            out[k] = erode ? (in[k] & left & right) : (in[k] | left | right);
        }
        out[K - 1] &= p->tail;
    }
    for (uint32_t r = 0; r < p->h; r++) {
        const uint64_t *mid = prow(tmp, p, r);
        const uint64_t *up = r > 0 ? prow(tmp, p, r - 1) : NULL;
        const uint64_t *down = r + 1 < p->h ? prow(tmp, p, r + 1) : NULL;
        uint64_t *out = prow(dst, p, r);
        for (size_t k = 0; k < K; k++) {
            uint64_t u = up ? up[k] : top_fill;
            uint64_t d = down ? down[k] : bot_fill;
            out[k] = erode ? (mid[k] & u & d) : (mid[k] | u | d);
        }
        out[K - 1] &= p->tail;
    }
}

/* morph3 for patches of one word per row (blobs up to 62 pixels wide at radius 1, nearly all
 * markers): each row is shifted once and the vertical step rolls over three rows, with no
 * scratch plane. Written with erode constant at each call so the compiler specialises it. */
static inline void morph3_one_word(const struct patch *p, const uint64_t *src, uint64_t *dst,
                                   int erode)
{
    const size_t st = p->stride;
    const uint64_t fill_l = erode && p->edge[0] ? 1u : 0u;
    const uint64_t fill_r = (erode && p->edge[2] ? 1ull : 0u) << ((p->w - 1) & 63);
    const uint64_t top = erode && p->edge[1] ? ~0ull : 0u;
    const uint64_t bottom = erode && p->edge[3] ? ~0ull : 0u;
#define MN_HROW(x) (erode ? ((x) & (((x) << 1) | fill_l) & (((x) >> 1) | fill_r)) \
                          : ((x) | ((x) << 1) | ((x) >> 1)))
    uint64_t prev = top, cur = MN_HROW(src[0]);
    for (uint32_t r = 0; r < p->h; r++) {
        uint64_t next = r + 1 < p->h ? MN_HROW(src[(size_t)(r + 1) * st]) : bottom;
        dst[(size_t)r * st] = (erode ? (prev & cur & next) : (prev | cur | next)) & p->tail;
        prev = cur;
        cur = next;
    }
#undef MN_HROW
}

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

/* Takes the run of set bits through bit x out of a patch row (words long), returning its
 * ends; found a word at a time with count-trailing/leading-zeros. */
static void take_run(uint64_t *row, size_t words, uint32_t x, uint32_t *a, uint32_t *b)
{
    uint32_t k = x >> 6, off = x & 63;
    /* Rightwards: clear bits above x within the word, then whole words while full. */
    uint64_t stop = ~(row[k] >> off);
    uint32_t hi;
    if (stop != 0 && (uint32_t)__builtin_ctzll(stop) < 64 - off) {
        hi = x + (uint32_t)__builtin_ctzll(stop) - 1;
    } else {
        uint32_t kk = k + 1;
        while (kk < words && row[kk] == ~0ull)
            kk++;
        hi = kk < words ? kk * 64 + (uint32_t)__builtin_ctzll(~row[kk]) - 1 : kk * 64 - 1;
    }
    /* Leftwards, the mirror image. */
    uint64_t lstop = ~(row[k] << (63 - off));
    uint32_t lo;
    if (lstop != 0 && (uint32_t)__builtin_clzll(lstop) <= off) {
        lo = x + 1 - (uint32_t)__builtin_clzll(lstop);
    } else {
        uint32_t kk = k;
        while (kk > 0 && row[kk - 1] == ~0ull)
            kk--;
        lo = kk > 0 ? kk * 64 - (uint32_t)__builtin_clzll(~row[kk - 1]) : 0;
    }
    clear_range(row, lo, hi);
    *a = lo;
    *b = hi;
}

/* Consumes the 8-connected component through (x, y) into det->spans (image coordinates). */
static size_t take_component(struct mn_detector *det, uint64_t *plane, const struct patch *p,
                             uint32_t x, uint32_t y)
{
    struct mn_span *spans = det->spans;
    size_t n = 0;
    uint32_t a, b;
    take_run(prow(plane, p, y), p->words, x, &a, &b);
    spans[n++] = (struct mn_span){(uint16_t)a, (uint16_t)b, y};
    for (size_t i = 0; i < n; i++) {
        struct mn_span s = spans[i];
        uint32_t lo = s.x0 > 0 ? s.x0 - 1u : 0u;
        uint32_t hi = s.x1 + 1u < p->w ? s.x1 + 1u : p->w - 1u;
        for (int dir = -1; dir <= 1; dir += 2) {
            if ((dir < 0 && s.y == 0) || (dir > 0 && s.y + 1 >= p->h))
                continue;
            uint32_t ny = s.y + (uint32_t)dir;
            uint64_t *row = prow(plane, p, ny);
            uint32_t nx = lo;
            while (nx <= hi) {
                uint32_t k = nx >> 6;
                uint64_t word = row[k] & (~0ull << (nx & 63));
                if (!word) {
                    nx = (k + 1) * 64;
                    continue;
                }
                nx = k * 64 + (uint32_t)__builtin_ctzll(word);
                if (nx > hi)
                    break;
                /* The patch holds at most half its pixels as runs, and spans_cap was sized
                 * for that at creation, so this append cannot overflow. */
                take_run(row, p->words, nx, &a, &b);
                spans[n++] = (struct mn_span){(uint16_t)a, (uint16_t)b, ny};
                nx = b + 2;
            }
        }
    }
    for (size_t i = 0; i < n; i++) {
        spans[i].x0 = (uint16_t)(spans[i].x0 + p->x0);
        spans[i].x1 = (uint16_t)(spans[i].x1 + p->x0);
        spans[i].y += p->y0;
    }
    return n;
}

void mn_detect_morph_region(struct mn_detector *det, const struct mn_frame_view *f, size_t n,
                            uint32_t bx0, uint32_t by0, uint32_t bx1, uint32_t by1,
                            mn_emit_fn emit, void *ctx)
{
    const uint32_t r = det->cfg.morph_radius;
    struct patch p;
    p.x0 = bx0 >= r ? bx0 - r : 0;
    p.y0 = by0 >= r ? by0 - r : 0;
    uint32_t x1 = bx1 + r < f->w ? bx1 + r : f->w - 1;
    uint32_t y1 = by1 + r < f->h ? by1 + r : f->h - 1;
    p.w = x1 - p.x0 + 1;
    p.h = y1 - p.y0 + 1;
    p.words = (p.w + 63) / 64;
    p.stride = det->patch_words;
    p.tail = (p.w & 63) ? (~0ull >> (64 - (p.w & 63))) : ~0ull;
    p.edge[0] = p.x0 == 0;
    p.edge[1] = p.y0 == 0;
    p.edge[2] = x1 + 1 == f->w;
    p.edge[3] = y1 + 1 == f->h;

    uint64_t *a = det->patch[0], *b = det->patch[1], *tmp = det->patch[2];
    for (uint32_t row = 0; row < p.h; row++) {
        uint64_t *words = prow(a, &p, row);
        for (size_t k = 0; k < p.words; k++)
            words[k] = 0;
    }
    for (size_t i = 0; i < n; i++) {
        const struct mn_span *s = &det->spans[i];
        mn_bits_set_range(prow(a, &p, s->y - p.y0), s->x0 - p.x0, s->x1 - p.x0);
    }

    /* Opening removes specks and splits blobs joined by thin necks; closing then fills
     * holes and narrow bays. Each step ping-pongs between planes a and b. */
    static const int steps[4] = {1, 0, 0, 1};
    for (int s = 0; s < 4; s++) {
        for (uint32_t i = 0; i < r; i++) {
            if (p.words == 1) {
                if (steps[s])
                    morph3_one_word(&p, a, b, 1);
                else
                    morph3_one_word(&p, a, b, 0);
            } else {
                morph3(&p, a, b, tmp, steps[s]);
            }
            uint64_t *swap = a;
            a = b;
            b = swap;
        }
    }

    for (uint32_t y = 0; y < p.h; y++) {
        uint64_t *row = prow(a, &p, y);
        for (size_t k = 0; k < p.words; k++) {
            while (row[k]) {
                uint32_t x = (uint32_t)(k * 64 + (uint32_t)__builtin_ctzll(row[k]));
                size_t m = take_component(det, a, &p, x, y);
                emit(det, f, det->spans, m, ctx);
            }
        }
    }
}
