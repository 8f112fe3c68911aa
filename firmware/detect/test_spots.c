/* Test helpers: seeded xorshift PRNG, erf-integrated Gaussian spots, noise and quantisation,
 * and a deliberately simple per-pixel flood fill used as the detector's reference. */
#include "test_spots.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

uint64_t ts_next(struct ts_rng *r)
{
    /* splitmix64: good enough statistics, trivially seeded. */
    uint64_t z = (r->s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

double ts_uniform(struct ts_rng *r)
{
    return (double)(ts_next(r) >> 11) / 9007199254740992.0;
}

double ts_gauss(struct ts_rng *r)
{
    double u1 = ts_uniform(r), u2 = ts_uniform(r);
    if (u1 < 1e-300)
        u1 = 1e-300;
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

void ts_canvas_init(struct ts_canvas *c, uint32_t w, uint32_t h, double background)
{
    c->w = w;
    c->h = h;
    c->v = malloc((size_t)w * h * sizeof(double));
    for (size_t i = 0; i < (size_t)w * h; i++)
        c->v[i] = background;
}

void ts_canvas_free(struct ts_canvas *c)
{
    free(c->v);
    c->v = NULL;
}

/* Integral of a unit-peak Gaussian over [a, b], in units of the peak. */
static double gauss_int(double a, double b, double sigma)
{
    double k = 1.0 / (sigma * sqrt(2.0));
    return sigma * sqrt(3.141592653589793 / 2.0) * (erf(b * k) - erf(a * k));
}

void ts_canvas_spot(struct ts_canvas *c, double cx, double cy, double sigma, double amp)
{
    int reach = (int)ceil(5.0 * sigma) + 1;
    int x0 = (int)floor(cx) - reach, x1 = (int)floor(cx) + reach;
    int y0 = (int)floor(cy) - reach, y1 = (int)floor(cy) + reach;
    for (int y = y0; y <= y1; y++) {
        if (y < 0 || y >= (int)c->h)
            continue;
        double gy = gauss_int(y - 0.5 - cy, y + 0.5 - cy, sigma);
        for (int x = x0; x <= x1; x++) {
            if (x < 0 || x >= (int)c->w)
                continue;
            double gx = gauss_int(x - 0.5 - cx, x + 0.5 - cx, sigma);
            c->v[(size_t)y * c->w + x] += amp * gx * gy;
        }
    }
}

void ts_canvas_to_y8(const struct ts_canvas *c, struct ts_rng *rng, double noise, uint8_t *dst,
                     size_t stride)
{
    for (uint32_t y = 0; y < c->h; y++) {
        for (uint32_t x = 0; x < c->w; x++) {
            double v = c->v[(size_t)y * c->w + x] + (noise > 0 ? noise * ts_gauss(rng) : 0.0);
            long q = lround(v);
            dst[(size_t)y * stride + x] = (uint8_t)(q < 0 ? 0 : q > 255 ? 255 : q);
        }
    }
}

/* One erosion (erode = 1) or dilation of src into dst, square radius r, outside neutral. */
static void naive_morph(const uint8_t *src, uint8_t *dst, uint32_t w, uint32_t h, int r,
                        int erode)
{
    for (long y = 0; y < (long)h; y++) {
        for (long x = 0; x < (long)w; x++) {
            int v = erode ? 1 : 0;
            for (long dy = -r; dy <= r; dy++) {
                for (long dx = -r; dx <= r; dx++) {
                    long nx = x + dx, ny = y + dy;
                    if (nx < 0 || ny < 0 || nx >= (long)w || ny >= (long)h)
                        continue;
                    uint8_t s = src[ny * (long)w + nx];
                    v = erode ? (v && s) : (v || s);
                }
            }
            dst[y * (long)w + x] = (uint8_t)v;
        }
    }
}

/* 8-connected labels (1..n in raster order of first pixel, 0 = background); returns n. */
static uint32_t label_image(const uint8_t *bin, uint32_t w, uint32_t h, uint32_t *labels)
{
    uint32_t *stack = malloc((size_t)w * h * sizeof(uint32_t));
    uint32_t n = 0;
    memset(labels, 0, (size_t)w * h * sizeof(uint32_t));
    for (size_t i = 0; i < (size_t)w * h; i++) {
        if (!bin[i] || labels[i])
            continue;
        n++;
        size_t top = 0;
        stack[top++] = (uint32_t)i;
        labels[i] = n;
        while (top > 0) {
            uint32_t j = stack[--top];
            long x = j % w, y = j / w;
            for (long dy = -1; dy <= 1; dy++) {
                for (long dx = -1; dx <= 1; dx++) {
                    long nx = x + dx, ny = y + dy;
                    if (nx < 0 || ny < 0 || nx >= (long)w || ny >= (long)h)
                        continue;
                    size_t k = (size_t)ny * w + (size_t)nx;
                    if (bin[k] && !labels[k]) {
                        labels[k] = n;
                        stack[top++] = (uint32_t)k;
                    }
                }
            }
        }
    }
    free(stack);
    return n;
}

size_t ts_reference_morph(const uint8_t *px, uint32_t w, uint32_t h, size_t stride, uint8_t t,
                          int r, struct ts_ref_blob *out, size_t cap)
{
    size_t N = (size_t)w * h;
    uint8_t *x = malloc(N), *a = malloc(N), *b = malloc(N), *claimed = calloc(N, 1);
    uint32_t *region = malloc(N * sizeof(uint32_t)), *comp = malloc(N * sizeof(uint32_t));
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t i = 0; i < w; i++)
            x[(size_t)y * w + i] = px[(size_t)y * stride + i] > t;
    naive_morph(x, b, w, h, r, 1);
    naive_morph(b, a, w, h, r, 0);
    naive_morph(a, b, w, h, r, 0);
    naive_morph(b, a, w, h, r, 1);
    label_image(x, w, h, region);
    uint32_t nc = label_image(a, w, h, comp);
    for (uint32_t l = 1; l <= nc; l++) {
        /* The component's region: that of any of its pixels that was above threshold. */
        uint32_t reg = 0;
        for (size_t i = 0; i < N && !reg; i++)
            if (comp[i] == l && x[i])
                reg = region[i];
        double sw = 0, sx = 0, sy = 0, bx = 0, by = 0;
        uint32_t area = 0;
        for (long y = 0; y < (long)h; y++) {
            for (long i = 0; i < (long)w; i++) {
                size_t k = (size_t)y * w + (size_t)i;
                int in = comp[k] == l;
                if (!in && x[k] && region[k] == reg && !claimed[k]) {
                    for (long dy = -r; dy <= r && !in; dy++)
                        for (long dx = -r; dx <= r && !in; dx++) {
                            long nx = i + dx, ny = y + dy;
                            if (nx >= 0 && ny >= 0 && nx < (long)w && ny < (long)h &&
                                comp[(size_t)ny * w + (size_t)nx] == l)
                                in = 1;
                        }
                }
                if (!in)
                    continue;
                claimed[k] = 1;
                int v = px[(size_t)y * stride + (size_t)i];
                double wgt = v > t ? v - t : 0;
                sw += wgt;
                sx += wgt * i;
                sy += wgt * y;
                bx += i;
                by += y;
                area++;
            }
        }
        if (l - 1 < cap)
            out[l - 1] = sw > 0 ? (struct ts_ref_blob){sx / sw, sy / sw, area}
                                : (struct ts_ref_blob){bx / area, by / area, area};
    }
    free(comp);
    free(region);
    free(claimed);
    free(b);
    free(a);
    free(x);
    return nc;
}

size_t ts_reference(const uint8_t *px, uint32_t w, uint32_t h, size_t stride, uint8_t t,
                    struct ts_ref_blob *out, size_t cap)
{
    uint8_t *seen = calloc((size_t)w * h, 1);
    uint32_t *stack = malloc((size_t)w * h * sizeof(uint32_t));
    size_t n = 0;
    for (uint32_t y = 0; y < h; y++) {
        for (uint32_t x = 0; x < w; x++) {
            if (px[(size_t)y * stride + x] <= t || seen[(size_t)y * w + x])
                continue;
            double sw = 0, sx = 0, sy = 0;
            uint32_t area = 0;
            size_t top = 0;
            stack[top++] = y * w + x;
            seen[(size_t)y * w + x] = 1;
            while (top > 0) {
                uint32_t i = stack[--top];
                uint32_t px_ = i % w, py = i / w;
                double wgt = px[(size_t)py * stride + px_] - t;
                sw += wgt;
                sx += wgt * px_;
                sy += wgt * py;
                area++;
                for (int dy = -1; dy <= 1; dy++) {
                    for (int dx = -1; dx <= 1; dx++) {
                        long nx = (long)px_ + dx, ny = (long)py + dy;
                        if (nx < 0 || ny < 0 || nx >= (long)w || ny >= (long)h)
                            continue;
                        size_t j = (size_t)ny * w + (size_t)nx;
                        if (seen[j] || px[(size_t)ny * stride + (size_t)nx] <= t)
                            continue;
                        seen[j] = 1;
                        stack[top++] = (uint32_t)j;
                    }
                }
            }
            if (n < cap)
                out[n] = (struct ts_ref_blob){sx / sw, sy / sw, area};
            n++;
        }
    }
    free(stack);
    free(seen);
    return n;
}
