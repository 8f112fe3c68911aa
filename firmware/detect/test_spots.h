/* Test helpers: a seeded PRNG, pixel-integrated Gaussian spots with sensor noise, and a naive
 * flood-fill reference detector to compare the fast one against. */
#ifndef MN_DETECT_TEST_SPOTS_H
#define MN_DETECT_TEST_SPOTS_H

#include <stddef.h>
#include <stdint.h>

struct ts_rng {
    uint64_t s;
};

uint64_t ts_next(struct ts_rng *r);
double ts_uniform(struct ts_rng *r);  /* [0, 1) */
double ts_gauss(struct ts_rng *r);    /* standard normal */

/* An image as float radiance before quantisation. */
struct ts_canvas {
    uint32_t w, h;
    double *v;
};

void ts_canvas_init(struct ts_canvas *c, uint32_t w, uint32_t h, double background);
void ts_canvas_free(struct ts_canvas *c);
/* Adds a Gaussian spot of peak amplitude amp and width sigma, integrated over each pixel. */
void ts_canvas_spot(struct ts_canvas *c, double cx, double cy, double sigma, double amp);
/* Adds Gaussian noise and quantises to Y8 into dst with the given stride. */
void ts_canvas_to_y8(const struct ts_canvas *c, struct ts_rng *rng, double noise, uint8_t *dst,
                     size_t stride);

/* Reference: 8-connected components of value > t, weighted centroid (value - t), radius-0. */
struct ts_ref_blob {
    double x, y;
    uint32_t area;
};
size_t ts_reference(const uint8_t *px, uint32_t w, uint32_t h, size_t stride, uint8_t t,
                    struct ts_ref_blob *out, size_t cap);

/* The detector's morphology semantics, the slow obvious way: whole-frame opening then closing
 * with a (2r+1)^2 square (outside the image neutral), 8-connected components; each component's
 * pixels plus the above-threshold pixels of its pre-morphology region within r of it that no
 * earlier component took; weights max(0, value - t). */
size_t ts_reference_morph(const uint8_t *px, uint32_t w, uint32_t h, size_t stride, uint8_t t,
                          int r, struct ts_ref_blob *out, size_t cap);

#endif
