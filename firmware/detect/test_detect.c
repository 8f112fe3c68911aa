/* Detector tests on synthetic frames generated here with a seeded PRNG: centroid accuracy on
 * noisy Gaussian spots, agreement with a naive reference on random frames of odd widths and
 * strides, touching/merged blobs, border blobs, masks, morphology, many blobs, auto threshold
 * and argument checking. */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "detect/detect.h"
#include "test_spots.h"
#include "testing/alloc_counting.h"

#define BG 16.0

struct truth {
    double x, y;
};

/* Finds the detected blob nearest to (x, y); returns its index or -1 when none within 3 px. */
static int nearest(const struct mn_blob *b, size_t n, double x, double y)
{
    int best = -1;
    double bd = 9.0;
    for (size_t i = 0; i < n; i++) {
        double d = (b[i].x - x) * (b[i].x - x) + (b[i].y - y) * (b[i].y - y);
        if (d < bd) {
            bd = d;
            best = (int)i;
        }
    }
    return best;
}

static struct mn_detector *make_detector(uint8_t threshold, uint8_t radius, uint32_t w,
                                         uint32_t h)
{
    struct mn_detect_config cfg;
    mn_detect_config_default(&cfg);
    cfg.threshold = threshold;
    cfg.morph_radius = radius;
    struct mn_detector *det = mn_detector_new(&cfg, w, h);
    assert_non_null(det);
    return det;
}

/* Sets the rw x rh rectangle at (x, y) of a w-wide frame to value. */
static void fill_rect(uint8_t *px, uint32_t w, uint32_t x, uint32_t y, uint32_t rw, uint32_t rh,
                      uint8_t value)
{
    for (uint32_t row = y; row < y + rh; row++)
        memset(px + (size_t)row * w + x, value, rw);
}

/* A w x h checkerboard of 200 and 0: one 8-connected region of single-pixel runs. */
static void fill_checkerboard(uint8_t *px, uint32_t w, uint32_t h)
{
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
            px[(size_t)y * w + x] = ((x + y) & 1) ? 200 : 0;
}

/* Spots on a jittered grid with noise: every one found, centroid within 0.02 px. */
static void centroid_accuracy(enum mn_threshold_mode mode, uint8_t radius)
{
    const uint32_t w = 320, h = 240;
    struct ts_rng rng = {12345 + radius + 7 * mode};
    struct ts_canvas c;
    ts_canvas_init(&c, w, h, BG);
    struct truth t[48];
    size_t nt = 0;
    for (uint32_t gy = 0; gy < 6; gy++) {
        for (uint32_t gx = 0; gx < 8; gx++) {
            t[nt].x = 20.0 + gx * 40.0 + ts_uniform(&rng) * 10.0;
            t[nt].y = 20.0 + gy * 40.0 + ts_uniform(&rng) * 10.0;
            double sigma = 1.8 + ts_uniform(&rng) * 0.8;
            double amp = 210.0 + ts_uniform(&rng) * 30.0;
            ts_canvas_spot(&c, t[nt].x, t[nt].y, sigma, amp);
            nt++;
        }
    }
    uint8_t *px = malloc((size_t)w * h);
    ts_canvas_to_y8(&c, &rng, 1.0, px, w);

    struct mn_detect_config cfg;
    mn_detect_config_default(&cfg);
    cfg.threshold_mode = mode;
    cfg.threshold = 30;
    cfg.auto_min_contrast = 12;
    cfg.auto_sigma_k = 6.0f;
    cfg.morph_radius = radius;
    struct mn_detector *det = mn_detector_new(&cfg, w, h);
    assert_non_null(det);
    struct mn_blob blobs[128];
    size_t n = 0;
    assert_int_equal(mn_detector_run(det, px, w, h, w, blobs, 128, &n), 0);
    assert_int_equal(n, nt);
    double worst = 0.0;
    for (size_t i = 0; i < nt; i++) {
        int k = nearest(blobs, n, t[i].x, t[i].y);
        assert_true(k >= 0);
        double e = fmax(fabs(blobs[k].x - t[i].x), fabs(blobs[k].y - t[i].y));
        worst = fmax(worst, e);
        assert_true(blobs[k].area >= 3);
        assert_false(blobs[k].flags & (MN_BLOB_MERGED | MN_BLOB_BORDER));
        assert_true(blobs[k].roundness > 0.7f);
    }
    if (worst >= 0.02)
        fail_msg("worst centroid error %.4f px >= 0.02", worst);
    mn_detector_free(det);
    free(px);
    ts_canvas_free(&c);
}

static void test_centroids_fixed(void **state)
{
    (void)state;
    centroid_accuracy(MN_THRESHOLD_FIXED, 0);
    centroid_accuracy(MN_THRESHOLD_FIXED, 1);
}

static void test_centroids_auto(void **state)
{
    (void)state;
    centroid_accuracy(MN_THRESHOLD_AUTO, 1);
}

/* Random blobby frames of awkward widths and strides: identical to the naive reference. */
static void test_matches_reference(void **state)
{
    (void)state;
    static const uint32_t widths[] = {1, 7, 63, 64, 65, 127, 129, 333};
    struct ts_rng rng = {99};
    for (size_t wi = 0; wi < sizeof widths / sizeof widths[0]; wi++) {
        uint32_t w = widths[wi], h = 1 + (uint32_t)(ts_next(&rng) % 90);
        size_t stride = w + (size_t)(ts_next(&rng) % 13);
        struct ts_canvas c;
        ts_canvas_init(&c, w, h, BG);
        for (int s = 0; s < (int)(w * h / 60 + 1); s++)
            ts_canvas_spot(&c, ts_uniform(&rng) * w, ts_uniform(&rng) * h,
                           0.6 + 1.5 * ts_uniform(&rng), 60 + 190 * ts_uniform(&rng));
        uint8_t *px = malloc(stride * h);
        memset(px, 0xff, stride * h); /* padding must never be read as pixels */
        ts_canvas_to_y8(&c, &rng, 3.0, px, stride);

        struct mn_detect_config cfg;
        mn_detect_config_default(&cfg);
        cfg.threshold = 50;
        cfg.morph_radius = 0;
        cfg.min_area = 1;
        cfg.max_bbox = 1024;
        cfg.max_area = 1u << 30;
        cfg.merged_roundness = 0.0f;
        struct mn_detector *det = mn_detector_new(&cfg, 400, 100);
        assert_non_null(det);
        struct mn_blob got[4096];
        struct ts_ref_blob want[4096];
        size_t n = 0;
        assert_int_equal(mn_detector_run(det, px, w, h, stride, got, 4096, &n), 0);
        size_t nr = ts_reference(px, w, h, stride, 50, want, 4096);
        assert_int_equal(n, nr);
        for (size_t i = 0; i < n; i++) {
            assert_int_equal(got[i].area, want[i].area);
            assert_true(fabs(got[i].x - want[i].x) < 1e-9);
            assert_true(fabs(got[i].y - want[i].y) < 1e-9);
        }
        /* A second run on the same detector must give the same answer (visited state reset). */
        size_t n2 = 0;
        assert_int_equal(mn_detector_run(det, px, w, h, stride, got, 4096, &n2), 0);
        assert_int_equal(n2, nr);
        mn_detector_free(det);
        free(px);
        ts_canvas_free(&c);
    }
}

/* Big and small spots, rings with holes and noisy edges, on patches wider than one 64-bit
 * word: per-blob morphology equals a whole-frame opening and closing (blobs are far apart). */
static void test_morphology_matches_whole_frame(void **state)
{
    (void)state;
    const uint32_t w = 563, h = 341;
    struct ts_rng rng = {2024};
    struct ts_canvas c;
    ts_canvas_init(&c, w, h, BG);
    for (uint32_t gy = 0; gy < 3; gy++) {
        for (uint32_t gx = 0; gx < 5; gx++) {
            double cx = 55 + gx * 112 + ts_uniform(&rng) * 4, cy = 55 + gy * 112 + ts_uniform(&rng) * 4;
            double sigma = 1.0 + ts_uniform(&rng) * 20.0;
            ts_canvas_spot(&c, cx, cy, sigma, 230);
            if ((gx + gy) % 2 == 0) /* carve a dark hole: a ring for the closing to work on */
                ts_canvas_spot(&c, cx + 0.3, cy - 0.2, sigma * 0.35, -200);
        }
    }
    uint8_t *px = malloc((size_t)w * h);
    ts_canvas_to_y8(&c, &rng, 6.0, px, w);
    for (int radius = 1; radius <= 2; radius++) {
        struct mn_detect_config cfg;
        mn_detect_config_default(&cfg);
        cfg.threshold = 60;
        cfg.morph_radius = (uint8_t)radius;
        cfg.min_area = 1;
        cfg.max_bbox = 200;
        cfg.merged_roundness = 0.0f;
        struct mn_detector *det = mn_detector_new(&cfg, w, h);
        assert_non_null(det);
        struct mn_blob got[256];
        struct ts_ref_blob want[256];
        size_t n = 0;
        assert_int_equal(mn_detector_run(det, px, w, h, w, got, 256, &n), 0);
        size_t nr = ts_reference_morph(px, w, h, w, 60, radius, want, 256);
        assert_int_equal(n, nr);
        int wide = 0;
        for (size_t i = 0; i < nr; i++) {
            int k = nearest(got, n, want[i].x, want[i].y);
            assert_true(k >= 0);
            assert_int_equal(got[k].area, want[i].area);
            assert_true(fabs(got[k].x - want[i].x) < 1e-9 && fabs(got[k].y - want[i].y) < 1e-9);
            wide += got[k].bbox_w + 2 * radius > 64; /* its patch needs two words per row */
        }
        assert_true(wide >= 2); /* patches of more than one word were exercised */
        mn_detector_free(det);
    }
    free(px);
    ts_canvas_free(&c);
}

/* Two spots close enough to merge are one blob flagged MERGED at their mean; two spots just
 * apart are two blobs with accurate centroids. */
static void test_merged_and_touching(void **state)
{
    (void)state;
    const uint32_t w = 96, h = 64;
    uint8_t *px = malloc(w * h);
    struct ts_rng rng = {5};
    struct ts_canvas c;
    ts_canvas_init(&c, w, h, BG);
    ts_canvas_spot(&c, 20.0, 30.0, 1.5, 200);
    ts_canvas_spot(&c, 23.6, 30.4, 1.5, 200);
    ts_canvas_spot(&c, 60.0, 30.0, 1.0, 200);
    ts_canvas_spot(&c, 67.0, 30.0, 1.0, 200);
    ts_canvas_to_y8(&c, &rng, 1.0, px, w);
    struct mn_detector *det = make_detector(40, 1, w, h);
    struct mn_blob b[16];
    size_t n = 0;
    assert_int_equal(mn_detector_run(det, px, w, h, w, b, 16, &n), 0);
    assert_int_equal(n, 3);
    int m = nearest(b, n, 21.8, 30.2);
    assert_true(m >= 0);
    assert_true(b[m].flags & MN_BLOB_MERGED);
    assert_true(fabs(b[m].x - 21.8) < 0.1 && fabs(b[m].y - 30.2) < 0.1);
    int l = nearest(b, n, 60.0, 30.0), r = nearest(b, n, 67.0, 30.0);
    assert_true(l >= 0 && r >= 0 && l != r);
    assert_false(b[l].flags & MN_BLOB_MERGED);
    assert_true(fabs(b[l].x - 60.0) < 0.05 && fabs(b[r].x - 67.0) < 0.05);
    mn_detector_free(det);
    ts_canvas_free(&c);
    free(px);
}

/* Two discs joined by a one-pixel neck: one merged blob without morphology, two clean blobs
 * once the opening cuts the neck. */
static void test_opening_splits_neck(void **state)
{
    (void)state;
    const uint32_t w = 40, h = 20;
    uint8_t px[40 * 20];
    memset(px, 10, sizeof px);
    for (int y = 0; y < (int)h; y++) {
        for (int x = 0; x < (int)w; x++) {
            if ((x - 10) * (x - 10) + (y - 10) * (y - 10) <= 9 ||
                (x - 26) * (x - 26) + (y - 10) * (y - 10) <= 9 || (y == 10 && x > 10 && x < 26))
                px[y * w + x] = 200;
        }
    }
    struct mn_blob b[8];
    size_t n = 0;
    struct mn_detector *plain = make_detector(100, 0, w, h);
    assert_int_equal(mn_detector_run(plain, px, w, h, w, b, 8, &n), 0);
    assert_int_equal(n, 1);
    assert_true(b[0].flags & MN_BLOB_MERGED);
    struct mn_detector *opened = make_detector(100, 1, w, h);
    assert_int_equal(mn_detector_run(opened, px, w, h, w, b, 8, &n), 0);
    assert_int_equal(n, 2);
    assert_true(fabs(b[0].x - 10.0) < 1e-9 && fabs(b[0].y - 10.0) < 1e-9);
    assert_true(fabs(b[1].x - 26.0) < 1e-9 && fabs(b[1].y - 10.0) < 1e-9);
    /* The opening trims the 29-pixel digital disc's four tips, but being within 1 px of what
     * remains they still count; the cut neck pixels further out do not. */
    assert_int_equal(b[0].area, 29);
    assert_int_equal(b[1].area, 29);
    assert_false(b[0].flags & MN_BLOB_MERGED);
    mn_detector_free(plain);
    mn_detector_free(opened);
}

/* Two squares joined by a one-pixel neck, the second starting on the row after the first ends:
 * once the opening cuts the neck, the pieces sit on consecutive rows without touching. They
 * are two blobs, each with the neck pixel next to it (within the radius) and not the others. */
static void test_opening_splits_stepped_neck(void **state)
{
    (void)state;
    const uint32_t w = 24, h = 16;
    uint8_t px[24 * 16];
    memset(px, 10, sizeof px);
    fill_rect(px, w, 2, 2, 6, 6, 200);
    fill_rect(px, w, 12, 8, 6, 6, 200);
    px[7 * w + 8] = px[7 * w + 9] = px[7 * w + 10] = px[8 * w + 11] = 200;
    struct mn_blob b[8];
    size_t n = 0;
    struct mn_detector *det = make_detector(100, 1, w, h);
    assert_int_equal(mn_detector_run(det, px, w, h, w, b, 8, &n), 0);
    assert_int_equal(n, 2);
    assert_int_equal(b[0].area, 37);
    assert_int_equal(b[1].area, 37);
    assert_true(fabs(b[0].x - (36 * 4.5 + 8) / 37) < 1e-9);
    assert_true(fabs(b[0].y - (36 * 4.5 + 7) / 37) < 1e-9);
    assert_true(fabs(b[1].x - (36 * 14.5 + 11) / 37) < 1e-9);
    assert_true(fabs(b[1].y - (36 * 10.5 + 8) / 37) < 1e-9);
    mn_detector_free(det);
}

/* Closing fills a one-pixel hole; opening removes a lone bright pixel. */
static void test_closing_and_specks(void **state)
{
    (void)state;
    const uint32_t w = 30, h = 30;
    uint8_t px[30 * 30];
    memset(px, 10, sizeof px);
    fill_rect(px, w, 5, 5, 7, 7, 180);
    px[8 * w + 8] = 10;       /* hole */
    px[20 * w + 20] = 250;    /* speck */
    struct mn_detect_config cfg;
    mn_detect_config_default(&cfg);
    cfg.threshold = 100;
    cfg.min_area = 1;
    struct mn_detector *det = mn_detector_new(&cfg, w, h);
    struct mn_blob b[4];
    size_t n = 0;
    assert_int_equal(mn_detector_run(det, px, w, h, w, b, 4, &n), 0);
    assert_int_equal(n, 1);
    assert_int_equal(b[0].area, 49);
    assert_true(fabs(b[0].x - 8.0) < 1e-9 && fabs(b[0].y - 8.0) < 1e-9);
    cfg.morph_radius = 0;
    assert_int_equal(mn_detector_set_config(det, &cfg), 0);
    assert_int_equal(mn_detector_run(det, px, w, h, w, b, 4, &n), 0);
    assert_int_equal(n, 2);
    assert_int_equal(b[0].area, 48);
    assert_int_equal(b[1].area, 1);
    assert_int_equal(b[1].peak, 250);
    mn_detector_free(det);
}

/* Blobs cut by every edge and corner are found and flagged BORDER; erosion does not eat them
 * from the image side. */
static void test_border_blobs(void **state)
{
    (void)state;
    const uint32_t w = 37, h = 23;
    static const double pos[][2] = {{0.2, 11}, {36.6, 11}, {18, 0.0}, {18, 22.7}, {0, 0},
                                    {36.5, 22.5}};
    struct ts_canvas c;
    ts_canvas_init(&c, w, h, BG);
    for (size_t i = 0; i < 6; i++)
        ts_canvas_spot(&c, pos[i][0], pos[i][1], 1.3, 220);
    ts_canvas_spot(&c, 12, 11, 1.3, 220);
    struct ts_rng rng = {77};
    uint8_t px[37 * 23];
    ts_canvas_to_y8(&c, &rng, 1.0, px, w);
    struct mn_detector *det = make_detector(40, 1, w, h);
    struct mn_blob b[16];
    size_t n = 0;
    assert_int_equal(mn_detector_run(det, px, w, h, w, b, 16, &n), 0);
    assert_int_equal(n, 7);
    for (size_t i = 0; i < 6; i++) {
        int k = nearest(b, n, pos[i][0], pos[i][1]);
        assert_true(k >= 0);
        assert_true(b[k].flags & MN_BLOB_BORDER);
    }
    int mid = nearest(b, n, 12, 11);
    assert_true(mid >= 0);
    assert_false(b[mid].flags & MN_BLOB_BORDER);
    mn_detector_free(det);
    ts_canvas_free(&c);
}

static void render_grid(uint8_t *px, uint32_t w, uint32_t h, uint32_t step, uint64_t seed)
{
    struct ts_canvas c;
    ts_canvas_init(&c, w, h, BG);
    for (uint32_t y = step / 2; y < h; y += step)
        for (uint32_t x = step / 2; x < w; x += step)
            ts_canvas_spot(&c, x + 0.25, y - 0.25, 1.2, 200);
    struct ts_rng rng = {seed};
    ts_canvas_to_y8(&c, &rng, 1.0, px, w);
    ts_canvas_free(&c);
}

/* Rectangle and cell-bitmap masks hide exactly the covered spots; a blob half under a mask is
 * flagged BORDER; clearing restores everything. */
static void test_masks(void **state)
{
    (void)state;
    const uint32_t w = 128, h = 64;
    uint8_t *px = malloc(w * h);
    render_grid(px, w, h, 32, 3); /* spots near (16,16), (48,16), ... 8 in all */
    struct mn_detector *det = make_detector(40, 1, w, h);
    struct mn_blob b[16];
    size_t n = 0;
    assert_int_equal(mn_detector_run(det, px, w, h, w, b, 16, &n), 0);
    assert_int_equal(n, 8);

    struct mn_rect rects[2] = {{40, 8, 16, 16}, {18, 40, 20, 20}};
    assert_int_equal(mn_detector_set_mask_rects(det, rects, 2), 0);
    assert_int_equal(mn_detector_run(det, px, w, h, w, b, 16, &n), 0);
    assert_int_equal(n, 7);
    assert_true(nearest(b, n, 48.25, 15.75) < 0);
    int half = nearest(b, n, 16.25, 47.75);
    assert_true(half >= 0);
    assert_true(b[half].flags & MN_BLOB_BORDER);

    /* 16-px cells, 8 x 4 of them: hide the cells around (80,16) and (112,48). */
    uint8_t bits[4] = {0};
    uint32_t cells[][2] = {{4, 0}, {5, 0}, {4, 1}, {5, 1}, {6, 2}, {7, 2}, {6, 3}, {7, 3}};
    for (size_t i = 0; i < 8; i++) {
        uint32_t k = cells[i][1] * 8 + cells[i][0];
        bits[k / 8] |= (uint8_t)(1u << (k % 8));
    }
    assert_int_equal(mn_detector_set_mask_bits(det, 16, 8, 4, bits), 0);
    assert_int_equal(mn_detector_run(det, px, w, h, w, b, 16, &n), 0);
    assert_int_equal(n, 6);
    assert_true(nearest(b, n, 80.25, 15.75) < 0);
    assert_true(nearest(b, n, 112.25, 47.75) < 0);
    assert_true(nearest(b, n, 48.25, 15.75) >= 0);

    mn_detector_clear_mask(det);
    assert_int_equal(mn_detector_run(det, px, w, h, w, b, 16, &n), 0);
    assert_int_equal(n, 8);

    assert_int_equal(mn_detector_set_mask_bits(det, 0, 8, 4, bits), -1);
    assert_int_equal(errno, EINVAL);
    assert_int_equal(mn_detector_set_mask_bits(det, 16, 8, 4, NULL), -1);
    assert_int_equal(mn_detector_set_mask_rects(det, NULL, 1), -1);
    mn_detector_free(det);
    free(px);
}

/* Thousands of blobs: all found in scan order; a small capacity keeps the first ones and
 * counts the rest as dropped. */
static void test_many_blobs(void **state)
{
    (void)state;
    const uint32_t w = 1024, h = 512;
    uint8_t *px = malloc((size_t)w * h);
    render_grid(px, w, h, 10, 8); /* 102 x 51 = 5202 spots */
    struct mn_detect_config cfg;
    mn_detect_config_default(&cfg);
    cfg.threshold = 40;
    cfg.max_blobs = 8000;
    struct mn_detector *det = mn_detector_new(&cfg, w, h);
    assert_non_null(det);
    struct mn_blob *b = malloc(8000 * sizeof *b);
    size_t n = 0;
    assert_int_equal(mn_detector_run(det, px, w, h, w, b, 8000, &n), 0);
    assert_int_equal(n, 5202);
    for (size_t i = 0; i < n; i++) {
        double gx = (b[i].x - 5.25) / 10.0, gy = (b[i].y - 4.75) / 10.0;
        assert_true(fabs(gx - round(gx)) < 0.01 && fabs(gy - round(gy)) < 0.01);
        if (i > 0)
            assert_true(b[i].y > b[i - 1].y - 1.0);
    }
    assert_int_equal(mn_detector_run(det, px, w, h, w, b, 100, &n), 0);
    assert_int_equal(n, 100);
    assert_int_equal(mn_detector_stats(det)->dropped, 5102);
    assert_true(b[99].y < 6.0);
    mn_detector_free(det);
    free(b);
    free(px);
}

/* Auto threshold sits a few noise sigmas above the background, whatever the background. */
static void test_auto_threshold(void **state)
{
    (void)state;
    const uint32_t w = 200, h = 150;
    uint8_t *px = malloc(w * h);
    struct mn_detect_config cfg;
    mn_detect_config_default(&cfg);
    cfg.threshold_mode = MN_THRESHOLD_AUTO;
    cfg.auto_sigma_k = 8.0f;
    cfg.auto_min_contrast = 10;
    struct mn_detector *det = mn_detector_new(&cfg, w, h);
    static const double bgs[] = {5.0, 40.0, 90.0};
    for (size_t i = 0; i < 3; i++) {
        struct ts_canvas c;
        ts_canvas_init(&c, w, h, bgs[i]);
        for (int s = 0; s < 12; s++)
            ts_canvas_spot(&c, 15 + s * 15, 75, 1.4, 140);
        struct ts_rng rng = {100 + i};
        ts_canvas_to_y8(&c, &rng, 2.0, px, w);
        struct mn_blob b[32];
        size_t n = 0;
        assert_int_equal(mn_detector_run(det, px, w, h, w, b, 32, &n), 0);
        uint8_t t = mn_detector_stats(det)->threshold;
        assert_true(t >= bgs[i] + 10 && t <= bgs[i] + 40);
        assert_int_equal(n, 12);
        ts_canvas_free(&c);
    }
    mn_detector_free(det);
    free(px);
}

/* A checkerboard is one huge 8-connected region of single-pixel runs: it must neither crash
 * nor yield blobs beyond the limits, and the queue overflow is reported. */
static void test_pathological_frame(void **state)
{
    (void)state;
    const uint32_t w = 512, h = 512;
    uint8_t *px = malloc((size_t)w * h);
    fill_checkerboard(px, w, h);
    struct mn_detector *det = make_detector(100, 1, w, h);
    struct mn_blob b[64];
    size_t n = 0;
    assert_int_equal(mn_detector_run(det, px, w, h, w, b, 64, &n), 0);
    const struct mn_detect_stats *st = mn_detector_stats(det);
    assert_true(st->rejected_complex >= 1);
    for (size_t i = 0; i < n; i++)
        assert_true(b[i].bbox_w <= 128 && b[i].bbox_h <= 128);
    /* The detector is clean afterwards. */
    memset(px, 0, (size_t)w * h);
    fill_rect(px, w, 100, 100, 4, 4, 200);
    assert_int_equal(mn_detector_run(det, px, w, h, w, b, 64, &n), 0);
    assert_int_equal(n, 1);
    assert_true(fabs(b[0].x - 101.5) < 1e-9 && fabs(b[0].y - 101.5) < 1e-9);
    mn_detector_free(det);
    free(px);
}

/* Area, bbox and roundness limits reject exactly the blobs outside them, and say so. */
static void test_filters(void **state)
{
    (void)state;
    const uint32_t w = 120, h = 40;
    uint8_t px[120 * 40];
    memset(px, 5, sizeof px);
    /* squares of side 2, 4, 6 and 10, a 1x12 line and a 3x12 bar */
    static const uint32_t boxes[][4] = {{2, 2, 2, 2}, {8, 2, 4, 4}, {16, 2, 6, 6},
                                        {26, 2, 10, 10}, {40, 2, 12, 1}, {56, 2, 12, 3}};
    for (size_t i = 0; i < 6; i++)
        fill_rect(px, w, boxes[i][0], boxes[i][1], boxes[i][2], boxes[i][3], 150);
    struct mn_detect_config cfg;
    mn_detect_config_default(&cfg);
    cfg.threshold = 100;
    cfg.morph_radius = 0;
    cfg.min_area = 5;     /* drops the 2x2 */
    cfg.max_area = 50;    /* drops the 10x10 */
    cfg.min_bbox = 2;     /* drops the 1-pixel-high line */
    cfg.max_bbox = 11;    /* drops the 12-wide bar */
    cfg.min_roundness = 0.5f;
    struct mn_detector *det = mn_detector_new(&cfg, w, h);
    struct mn_blob b[8];
    size_t n = 0;
    assert_int_equal(mn_detector_run(det, px, w, h, w, b, 8, &n), 0);
    const struct mn_detect_stats *st = mn_detector_stats(det);
    assert_int_equal(st->candidates, 6);
    assert_int_equal(n, 2);
    assert_int_equal(b[0].area, 16);
    assert_int_equal(b[1].area, 36);
    assert_int_equal(st->rejected_area, 2);
    assert_int_equal(st->rejected_bbox, 2);
    assert_int_equal(st->rejected_round, 0);
    /* The bar passes the bbox limit once it is raised, then fails on roundness (3 x 12). */
    cfg.max_bbox = 12;
    assert_int_equal(mn_detector_set_config(det, &cfg), -1); /* beyond the creation size */
    mn_detector_free(det);
    det = mn_detector_new(&cfg, w, h);
    assert_int_equal(mn_detector_run(det, px, w, h, w, b, 8, &n), 0);
    assert_int_equal(n, 2);
    assert_int_equal(mn_detector_stats(det)->rejected_round, 1);
    assert_int_equal(mn_detector_stats(det)->rejected_bbox, 1);
    mn_detector_free(det);
}

static void test_saturation_flag(void **state)
{
    (void)state;
    uint8_t px[16 * 16];
    memset(px, 0, sizeof px);
    fill_rect(px, 16, 4, 4, 4, 4, 255);
    struct mn_detector *det = make_detector(50, 0, 16, 16);
    struct mn_blob b[2];
    size_t n = 0;
    assert_int_equal(mn_detector_run(det, px, 16, 16, 16, b, 2, &n), 0);
    assert_int_equal(n, 1);
    assert_true(b[0].flags & MN_BLOB_SATURATED);
    assert_int_equal(b[0].peak, 255);
    assert_int_equal(b[0].mean, 255);
    assert_int_equal(b[0].bbox_w, 4);
    assert_true(b[0].roundness > 0.99f);
    mn_detector_free(det);
}

static void test_binary_centroid(void **state)
{
    (void)state;
    uint8_t px[16 * 16];
    memset(px, 0, sizeof px);
    px[5 * 16 + 5] = 250;
    px[5 * 16 + 6] = 60;
    px[5 * 16 + 7] = 60;
    struct mn_detect_config cfg;
    mn_detect_config_default(&cfg);
    cfg.threshold = 50;
    cfg.morph_radius = 0;
    cfg.centroid_mode = MN_CENTROID_BINARY;
    cfg.merged_roundness = 0.0f;
    struct mn_detector *det = mn_detector_new(&cfg, 16, 16);
    struct mn_blob b[2];
    size_t n = 0;
    assert_int_equal(mn_detector_run(det, px, 16, 16, 16, b, 2, &n), 0);
    assert_int_equal(n, 1);
    assert_true(fabs(b[0].x - 6.0) < 1e-12);
    cfg.centroid_mode = MN_CENTROID_WEIGHTED;
    assert_int_equal(mn_detector_set_config(det, &cfg), 0);
    assert_int_equal(mn_detector_run(det, px, 16, 16, 16, b, 2, &n), 0);
    /* weights 200, 10, 10 */
    assert_true(fabs(b[0].x - (5 * 200.0 + 6 * 10.0 + 7 * 10.0) / 220.0) < 1e-12);
    mn_detector_free(det);
}

/* All memory comes from mn_detector_new: frames with morphology, masks, auto threshold, many
 * blobs and a pathological region allocate nothing. */
static void test_no_allocation_per_frame(void **state)
{
    (void)state;
    const uint32_t w = 640, h = 256;
    uint8_t *grid = malloc((size_t)w * h), *checker = malloc((size_t)w * h);
    render_grid(grid, w, h, 12, 9);
    fill_checkerboard(checker, w, h);
    struct mn_detect_config cfg;
    mn_detect_config_default(&cfg);
    cfg.threshold = 40;
    cfg.max_blobs = 4096;
    unsigned long at_start = mn_alloc_count();
    struct mn_detector *det = mn_detector_new(&cfg, w, h);
    assert_non_null(det);
    assert_true(mn_alloc_count() > at_start); /* the counting wrappers are in effect */
    struct mn_blob *b = malloc(4096 * sizeof *b);
    struct mn_rect rect = {100, 100, 50, 50};
    assert_int_equal(mn_detector_set_mask_rects(det, &rect, 1), 0);
    size_t n = 0;
    unsigned long before = mn_alloc_count();
    for (int pass = 0; pass < 3; pass++) {
        assert_int_equal(mn_detector_run(det, grid, w, h, w, b, 4096, &n), 0);
        assert_true(n > 1000);
        assert_int_equal(mn_detector_run(det, checker, w, h, w, b, 4096, &n), 0);
        assert_int_equal(mn_detector_set_threshold(det, MN_THRESHOLD_AUTO, 0), 0);
        assert_int_equal(mn_detector_run(det, grid, w - 3, h - 5, w, b, 4096, &n), 0);
        assert_int_equal(mn_detector_set_threshold(det, MN_THRESHOLD_FIXED, 40), 0);
    }
    assert_int_equal(mn_alloc_count(), before);
    mn_detector_free(det);
    free(b);
    free(grid);
    free(checker);
}

static void test_bad_arguments(void **state)
{
    (void)state;
    struct mn_detect_config cfg;
    mn_detect_config_default(&cfg);
    assert_null(mn_detect_config_check(&cfg));
    struct mn_detect_config bad = cfg;
    bad.min_area = 10;
    bad.max_area = 5;
    assert_non_null(mn_detect_config_check(&bad));
    bad = cfg;
    bad.min_roundness = 1.5f;
    assert_non_null(mn_detect_config_check(&bad));
    bad = cfg;
    bad.morph_radius = 9;
    assert_non_null(mn_detect_config_check(&bad));
    bad = cfg;
    bad.max_bbox = 0;
    assert_non_null(mn_detect_config_check(&bad));
    assert_null(mn_detector_new(&bad, 64, 64));
    assert_int_equal(errno, EINVAL);
    assert_null(mn_detector_new(&cfg, 0, 64));
    assert_null(mn_detector_new(&cfg, 64, MN_DETECT_MAX_SIDE + 1));

    struct mn_detector *det = mn_detector_new(&cfg, 64, 48);
    uint8_t px[65 * 49] = {0};
    struct mn_blob b[1];
    size_t n;
    assert_int_equal(mn_detector_run(det, px, 65, 48, 65, b, 1, &n), -1);
    assert_int_equal(errno, EINVAL);
    assert_int_equal(mn_detector_run(det, px, 64, 49, 64, b, 1, &n), -1);
    assert_int_equal(mn_detector_run(det, px, 64, 48, 63, b, 1, &n), -1);
    assert_int_equal(mn_detector_run(det, NULL, 64, 48, 64, b, 1, &n), -1);
    /* A bigger patch than the detector was built for is refused. */
    bad = cfg;
    bad.max_bbox = 200;
    assert_int_equal(mn_detector_set_config(det, &bad), -1);
    assert_int_equal(mn_detector_set_threshold(det, MN_THRESHOLD_FIXED, 77), 0);
    assert_int_equal(mn_detector_config(det)->threshold, 77);
    assert_int_equal(mn_detector_set_threshold(det, (enum mn_threshold_mode)5, 0), -1);
    mn_detector_free(det);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_centroids_fixed),
        cmocka_unit_test(test_centroids_auto),
        cmocka_unit_test(test_matches_reference),
        cmocka_unit_test(test_morphology_matches_whole_frame),
        cmocka_unit_test(test_merged_and_touching),
        cmocka_unit_test(test_opening_splits_neck),
        cmocka_unit_test(test_opening_splits_stepped_neck),
        cmocka_unit_test(test_closing_and_specks),
        cmocka_unit_test(test_border_blobs),
        cmocka_unit_test(test_masks),
        cmocka_unit_test(test_many_blobs),
        cmocka_unit_test(test_auto_threshold),
        cmocka_unit_test(test_pathological_frame),
        cmocka_unit_test(test_filters),
        cmocka_unit_test(test_saturation_flag),
        cmocka_unit_test(test_binary_centroid),
        cmocka_unit_test(test_no_allocation_per_frame),
        cmocka_unit_test(test_bad_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
