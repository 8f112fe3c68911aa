/* The seed's opening and closing, applied only to one region at a time on a bit patch (its
 * bbox plus the radius), never to the whole frame. A (2r+1)^2 square is r passes of 3x3, each a
 * few word-wide shifts and ANDs/ORs. Outside the image counts as neutral (as OpenCV's default
 * border does), so a blob cut by the frame edge is not eroded from that side. Morphology only
 * segments: each resulting component's centroid also counts the region's bright pixels within
 * r of it that the opening trimmed, which would otherwise bias it by up to ~0.05 px. */
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

static void clear_plane(const struct patch *p, uint64_t *plane)
{
    for (uint32_t r = 0; r < p->h; r++) {
        uint64_t *w = prow(plane, p, r);
        for (size_t k = 0; k < p->words; k++)
            w[k] = 0;
    }
}

static void copy_plane(const struct patch *p, const uint64_t *src, uint64_t *dst)
{
    for (uint32_t r = 0; r < p->h; r++) {
        const uint64_t *in = src + (size_t)r * p->stride;
        uint64_t *out = prow(dst, p, r);
        for (size_t k = 0; k < p->words; k++)
            out[k] = in[k];
    }
}

/* ORs spans given in patch coordinates into a plane. */
static void paint_spans(const struct patch *p, uint64_t *plane, const struct mn_span *spans,
                        size_t n)
{
    for (size_t i = 0; i < n; i++)
        mn_bits_set_range(prow(plane, p, spans[i].y), spans[i].x0, spans[i].x1);
}

/* One 3x3 step, with the one-word fast path for narrow patches. */
static void morph_step(const struct patch *p, uint64_t *src, uint64_t *dst, uint64_t *tmp,
                       int erode)
{
    if (p->words == 1) {
        if (erode)
            morph3_one_word(p, src, dst, 1);
        else
            morph3_one_word(p, src, dst, 0);
    } else {
        morph3(p, src, dst, tmp, erode);
    }
}

/* True when rows from y on hold no pixel (rows above y were emptied already). */
static int plane_empty(const struct patch *p, const uint64_t *plane, uint32_t y)
{
    uint64_t any = 0;
    for (uint32_t r = y; r < p->h; r++) {
        const uint64_t *w = plane + (size_t)r * p->stride;
        for (size_t k = 0; k < p->words; k++)
            any |= w[k];
    }
    return any == 0;
}

/* The component's dilation by r (r >= 1) into one of the planes grown and spare; returns it. */
static uint64_t *dilate(const struct patch *p, uint32_t r, uint64_t *comp, uint64_t *grown,
                        uint64_t *spare, uint64_t *tmp)
{
    morph_step(p, comp, grown, tmp, 0);
    for (uint32_t i = 1; i < r; i++) {
        morph_step(p, grown, spare, tmp, 0);
        uint64_t *swap = grown;
        grown = spare;
        spare = swap;
    }
    return grown;
}

/* For one-word patches: true when the plane is one 8-connected set by the simplest proof,
 * nonempty rows consecutive, each a single run touching the one above. True for nearly every
 * marker; false does not mean the opposite (the general labelling then decides). */
static int one_simple_component(const struct patch *p, const uint64_t *plane)
{
    uint64_t prev = 0;
    int state = 0; /* 0 before the set, 1 inside, 2 after */
    for (uint32_t r = 0; r < p->h; r++) {
        const uint64_t c = plane[(size_t)r * p->stride];
        if (!c) {
            state = state ? 2 : 0;
            continue;
        }
        if (state == 2 || (c & (c + (c & (0 - c)))) != 0)
            return 0; /* a second piece below, or more than one run in this row */
        if (state == 1 && !(c & (prev | (prev << 1) | (prev >> 1))))
            return 0;
        state = 1;
        prev = c;
    }
    return state != 0;
}

/* Writes every run of the plane as spans in image coordinates. */
static size_t plane_spans(const struct patch *p, const uint64_t *plane, struct mn_span *out)
{
    size_t n = 0;
    for (uint32_t y = 0; y < p->h; y++) {
        const uint64_t *row = plane + (size_t)y * p->stride;
        for (size_t k = 0; k < p->words; k++) {
            uint64_t word = row[k];
            while (word) {
                uint32_t a = (uint32_t)__builtin_ctzll(word);
                uint64_t ones = ~(word >> a);
                /* ones == 0: the run reaches the word's top bit and may continue. */
                uint32_t len = ones ? (uint32_t)__builtin_ctzll(ones) : 64 - a;
                uint32_t x0 = (uint32_t)k * 64 + a, x1 = x0 + len - 1;
                word = len + a >= 64 ? 0 : word & (~0ull << (a + len));
                if (n > 0 && out[n - 1].y == y + p->y0 && out[n - 1].x1 + 1u == x0 + p->x0)
                    out[n - 1].x1 = (uint16_t)(x1 + p->x0); /* run crossing a word boundary */
                else
                    out[n++] = (struct mn_span){(uint16_t)(x0 + p->x0), (uint16_t)(x1 + p->x0),
                                                y + p->y0};
            }
        }
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

    uint64_t *region = det->patch[0], *a = det->patch[1], *b = det->patch[2];
    uint64_t *tmp = det->patch[3], *c = det->patch[4], *d = det->patch[5];
    clear_plane(&p, region);
    for (size_t i = 0; i < n; i++) {
        const struct mn_span *s = &det->spans[i];
        mn_bits_set_range(prow(region, &p, s->y - p.y0), s->x0 - p.x0, s->x1 - p.x0);
    }
    copy_plane(&p, region, a);

    /* Opening removes specks and splits blobs joined by thin necks; closing then fills
     * holes and narrow bays. Each step ping-pongs between planes a and b. */
    static const int steps[4] = {1, 0, 0, 1};
    for (int s = 0; s < 4; s++) {
        for (uint32_t i = 0; i < r; i++) {
            morph_step(&p, a, b, tmp, steps[s]);
            uint64_t *swap = a;
            a = b;
            b = swap;
        }
    }

    if (p.words == 1 && one_simple_component(&p, a)) {
        /* The usual marker: one component, a. When its final set (see below) is the whole
         * region, the fill's own spans are the blob's, with nothing to relabel. */
        uint64_t *grown = dilate(&p, r, a, d, b, tmp), diff = 0;
        for (uint32_t y = 0; y < p.h; y++) {
            const size_t i = (size_t)y * p.stride;
            const uint64_t g = (grown[i] & region[i]) | a[i];
            diff |= g ^ region[i];
            grown[i] = g;
        }
        emit(det, f, det->spans, diff ? plane_spans(&p, grown, det->spans) : n, ctx);
        return;
    }

    /* Components in raster order. Nearly always there is just one: then the plane itself (kept
     * in c before take_component empties a) is the component, with no repainting. */
    copy_plane(&p, a, c);
    int first = 1;
    for (uint32_t y = 0; y < p.h; y++) {
        uint64_t *row = prow(a, &p, y);
        for (size_t k = 0; k < p.words; k++) {
            while (row[k]) {
                uint32_t x = (uint32_t)(k * 64 + (uint32_t)__builtin_ctzll(row[k]));
                size_t m = mn_fill_plane(a, p.stride, p.w, p.h, x, y, det->spans,
                                         det->spans_cap).n;
                if (!first || !plane_empty(&p, a, y)) {
                    clear_plane(&p, c);
                    paint_spans(&p, c, det->spans, m);
                }
                first = 0;
                /* Final set: the component, plus the region's pixels within r of it that no
                 * earlier component claimed. */
                uint64_t *grown = dilate(&p, r, c, d, b, tmp);
                for (uint32_t row_i = 0; row_i < p.h; row_i++) {
                    uint64_t *g = prow(grown, &p, row_i), *reg = prow(region, &p, row_i);
                    const uint64_t *comp = prow(c, &p, row_i);
                    for (size_t k2 = 0; k2 < p.words; k2++) {
                        g[k2] = (g[k2] & reg[k2]) | comp[k2];
                        reg[k2] &= ~g[k2];
                    }
                }
                size_t total = plane_spans(&p, grown, det->spans + m);
                emit(det, f, det->spans + m, total, ctx);
            }
        }
    }
}
