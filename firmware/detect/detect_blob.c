/* Blob statistics from a span list: centroid (intensity-weighted or binary mean), area,
 * peak/mean, bbox, roundness from second moments, flags, and the acceptance filters. Sums are
 * exact 64-bit integers, so the only rounding is the final division. */
#include <math.h>

#include "detect/detect.h"
#include "detect/detect_internal.h"

/* sum of k^2 for k = a..b; the polynomial form holds for negative a and b too. */
static inline int64_t sum_sq(int64_t a, int64_t b)
{
    return (b * (b + 1) * (2 * b + 1) - (a - 1) * a * (2 * a - 1)) / 6;
}

/* True when any pixel 8-adjacent to the span is masked: the blob may be cut by the mask. */
static int span_touches_mask(const struct mn_detector *det, const struct mn_frame_view *f,
                             const struct mn_span *s)
{
    uint32_t lo = s->x0 > 0 ? s->x0 - 1u : 0u;
    uint32_t hi = s->x1 + 1u < f->w ? s->x1 + 1u : f->w - 1u;
    for (int dy = -1; dy <= 1; dy++) {
        if ((dy < 0 && s->y == 0) || (dy > 0 && s->y + 1 >= f->h))
            continue;
        uint32_t y = s->y + (uint32_t)dy;
        for (uint32_t x = lo; x <= hi; x++) {
            if (mn_bit_get(det->mask, det->row_words, x, y))
                return 1;
        }
    }
    return 0;
}

int mn_detect_blob_from_spans(struct mn_detector *det, const struct mn_frame_view *f,
                              const struct mn_span *spans, size_t n, struct mn_blob *out)
{
    const struct mn_detect_config *cfg = &det->cfg;
    const int weighted = cfg->centroid_mode == MN_CENTROID_WEIGHTED;
    const uint32_t t = f->t;
    uint64_t sw = 0, swx = 0, swy = 0, sum = 0, area = 0;
    int64_t sdx = 0, sdy = 0, sdxx = 0, sdyy = 0, sdxy = 0;
    const int64_t rx = spans[0].x0, ry = spans[0].y; /* moment origin keeps sums small */
    uint32_t peak = 0, bx0 = UINT32_MAX, by0 = UINT32_MAX, bx1 = 0, by1 = 0;
    int touches_mask = 0;

    for (size_t i = 0; i < n; i++) {
        const struct mn_span *s = &spans[i];
        const uint8_t *row = f->px + (size_t)s->y * f->stride;
        uint64_t rw = 0, rwx = 0;
        for (uint32_t x = s->x0; x <= s->x1; x++) {
            uint32_t v = row[x];
            uint32_t wgt = weighted ? (v > t ? v - t : 0u) : 1u;
            rw += wgt;
            rwx += (uint64_t)wgt * x;
            sum += v;
            peak = v > peak ? v : peak;
        }
        sw += rw;
        swx += rwx;
        swy += rw * s->y;

        int64_t cnt = (int64_t)s->x1 - s->x0 + 1, a = s->x0 - rx, b = s->x1 - rx;
        int64_t dy = (int64_t)s->y - ry, sx = (a + b) * cnt / 2;
        area += (uint64_t)cnt;
        sdx += sx;
        sdxx += sum_sq(a, b);
        sdy += dy * cnt;
        sdyy += dy * dy * cnt;
        sdxy += dy * sx;
        bx0 = s->x0 < bx0 ? s->x0 : bx0;
        bx1 = s->x1 > bx1 ? s->x1 : bx1;
        by0 = s->y < by0 ? s->y : by0;
        by1 = s->y > by1 ? s->y : by1;
        if (det->has_mask && !touches_mask)
            touches_mask = span_touches_mask(det, f, s);
    }

    uint32_t bw = bx1 - bx0 + 1, bh = by1 - by0 + 1;
    if (area < cfg->min_area || area > cfg->max_area) {
        det->stats.rejected_area++;
        return 0;
    }
    if (bw < cfg->min_bbox || bh < cfg->min_bbox || bw > cfg->max_bbox || bh > cfg->max_bbox) {
        det->stats.rejected_bbox++;
        return 0;
    }

    /* Second moments of the pixel squares (each adds 1/12 per axis), so that single pixels
     * count as round and the measure does not depend on where the origin sits. */
    double A = (double)area;
    double mx = sdx / A, my = sdy / A;
    double cxx = sdxx / A - mx * mx + 1.0 / 12.0;
    double cyy = sdyy / A - my * my + 1.0 / 12.0;
    double cxy = sdxy / A - mx * my;
    double half_tr = 0.5 * (cxx + cyy);
    double disc = sqrt(0.25 * (cxx - cyy) * (cxx - cyy) + cxy * cxy);
    double major = half_tr + disc, minor = half_tr - disc;
    float roundness = minor > 0.0 ? (float)sqrt(minor / major) : 0.0f;
    if (roundness < cfg->min_roundness) {
        det->stats.rejected_round++;
        return 0;
    }

    if (sw > 0) {
        out->x = (double)swx / (double)sw;
        out->y = (double)swy / (double)sw;
    } else {
        /* Only possible for pixels that closing added below the threshold. */
        out->x = (double)rx + mx;
        out->y = (double)ry + my;
    }
    out->area = (uint32_t)area;
    out->peak = (uint16_t)peak;
    out->mean = (uint16_t)((sum + area / 2) / area);
    out->bbox_w = (uint16_t)bw;
    out->bbox_h = (uint16_t)bh;
    out->roundness = roundness;
    out->flags = 0;
    if (peak >= cfg->saturation_level)
        out->flags |= MN_BLOB_SATURATED;
    if (roundness < cfg->merged_roundness)
        out->flags |= MN_BLOB_MERGED;
    if (touches_mask || bx0 == 0 || by0 == 0 || bx1 + 1 == f->w || by1 + 1 == f->h)
        out->flags |= MN_BLOB_BORDER;
    return 1;
}
