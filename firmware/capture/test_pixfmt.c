/* Pixel-format conversion used by the V4L2 and libcamera sources for sensors without GREY: every
 * format to Y8 with padded source rows, checked against values computed by hand (10/16-bit,
 * packed YUV) or against a naive floating-point BT.601 reference (packed RGB). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "capture/pixfmt.h"

enum { W = 5, H = 3, SRC_STRIDE = 2 * W + 6, DST_STRIDE = W + 3 };

static void fill_words(uint8_t *src, const uint16_t *words)
{
    memset(src, 0xAB, SRC_STRIDE * H); /* padding must never leak into the output */
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            uint16_t v = words[y * W + x];
            src[y * SRC_STRIDE + 2 * x] = (uint8_t)(v & 0xff);
            src[y * SRC_STRIDE + 2 * x + 1] = (uint8_t)(v >> 8);
        }
}

static void y10(void **state)
{
    (void)state;
    const uint16_t words[W * H] = {0, 3, 4, 1023, 512, 100, 101, 102, 103, 1020,
                                   0xfc00 | 8, 256, 257, 1021, 7};
    uint8_t src[SRC_STRIDE * H], dst[DST_STRIDE * H];
    fill_words(src, words);
    memset(dst, 0x55, sizeof(dst));
    mn_pixfmt_to_y8(MN_PIXFMT_Y10, src, SRC_STRIDE, W, H, dst, DST_STRIDE);
    for (int i = 0; i < W * H; i++)
        /* bits above the tenth are junk some drivers leave: ignored */
        assert_int_equal(dst[(i / W) * DST_STRIDE + i % W], (words[i] & 0x3ff) >> 2);
    assert_int_equal(dst[W], 0x55); /* nothing written past w in a row */
}

static void y16(void **state)
{
    (void)state;
    const uint16_t words[W * H] = {0, 255, 256, 65535, 32768, 1, 2, 511, 512, 40000,
                                   4095, 4096, 60000, 12345, 54321};
    uint8_t src[SRC_STRIDE * H], dst[DST_STRIDE * H];
    fill_words(src, words);
    mn_pixfmt_to_y8(MN_PIXFMT_Y16, src, SRC_STRIDE, W, H, dst, DST_STRIDE);
    for (int i = 0; i < W * H; i++)
        assert_int_equal(dst[(i / W) * DST_STRIDE + i % W], words[i] >> 8);
}

static void yuyv(void **state)
{
    (void)state;
    uint8_t src[SRC_STRIDE * H], dst[DST_STRIDE * H];
    memset(src, 0xAB, sizeof(src));
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            src[y * SRC_STRIDE + 2 * x] = (uint8_t)(10 * y + x);      /* Y */
            src[y * SRC_STRIDE + 2 * x + 1] = (uint8_t)(200 + x % 2); /* U or V */
        }
    mn_pixfmt_to_y8(MN_PIXFMT_YUYV, src, SRC_STRIDE, W, H, dst, DST_STRIDE);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            assert_int_equal(dst[y * DST_STRIDE + x], 10 * y + x);
}

static void uyvy(void **state)
{
    (void)state;
    uint8_t src[SRC_STRIDE * H], dst[DST_STRIDE * H];
    memset(src, 0xAB, sizeof(src));
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            src[y * SRC_STRIDE + 2 * x] = (uint8_t)(200 + x % 2);      /* U or V */
            src[y * SRC_STRIDE + 2 * x + 1] = (uint8_t)(10 * y + x);   /* Y */
        }
    mn_pixfmt_to_y8(MN_PIXFMT_UYVY, src, SRC_STRIDE, W, H, dst, DST_STRIDE);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            assert_int_equal(dst[y * DST_STRIDE + x], 10 * y + x);
}

/* Packed RGB: where R, G and B sit in a pixel of each format. */
struct rgb_layout {
    enum mn_pixfmt fmt;
    int bpp, r, g, b;
};

static const struct rgb_layout rgb_layouts[] = {
    {MN_PIXFMT_RGB24, 3, 0, 1, 2},
    {MN_PIXFMT_BGR24, 3, 2, 1, 0},
    {MN_PIXFMT_XRGB32, 4, 1, 2, 3},
    {MN_PIXFMT_XBGR32, 4, 2, 1, 0},
};

enum { RW = 37, RH = 11, RSTRIDE = 4 * RW + 12, RDST = RW + 5 };

/* Every pixel within one grey level of round(0.299 R + 0.587 G + 0.114 B), pure black and white
 * exact, the padding untouched, and the channel order right (a pure red and a pure blue pixel
 * differ by the weights, 76 vs 29). */
static void rgb(void **state)
{
    (void)state;
    static uint8_t src[RSTRIDE * RH], dst[RDST * RH];
    for (size_t k = 0; k < sizeof(rgb_layouts) / sizeof(rgb_layouts[0]); k++) {
        const struct rgb_layout *l = &rgb_layouts[k];
        assert_int_equal(mn_pixfmt_bytes_per_pixel(l->fmt), l->bpp);
        uint32_t seed = 12345u + (uint32_t)k;
        uint8_t rgbv[RH][RW][3];
        memset(src, 0xEE, sizeof(src)); /* padding and X bytes: must not reach the output */
        for (int y = 0; y < RH; y++)
            for (int x = 0; x < RW; x++) {
                for (int c = 0; c < 3; c++) {
                    seed = seed * 1103515245u + 12345u;
                    rgbv[y][x][c] = (uint8_t)(seed >> 16);
                }
                if (y == 0 && x < 5) { /* black, white, red, green, blue */
                    static const uint8_t fixed[5][3] = {
                        {0, 0, 0}, {255, 255, 255}, {255, 0, 0}, {0, 255, 0}, {0, 0, 255}};
                    memcpy(rgbv[y][x], fixed[x], 3);
                }
                uint8_t *px = src + y * RSTRIDE + x * l->bpp;
                px[l->r] = rgbv[y][x][0];
                px[l->g] = rgbv[y][x][1];
                px[l->b] = rgbv[y][x][2];
            }
        memset(dst, 0x55, sizeof(dst));
        mn_pixfmt_to_y8(l->fmt, src, RSTRIDE, RW, RH, dst, RDST);
        for (int y = 0; y < RH; y++) {
            for (int x = 0; x < RW; x++) {
                double ref = 0.299 * rgbv[y][x][0] + 0.587 * rgbv[y][x][1] + 0.114 * rgbv[y][x][2];
                double got = dst[y * RDST + x];
                assert_true(fabs(got - ref) <= 1.0);
            }
            for (int x = RW; x < RDST; x++)
                assert_int_equal(dst[y * RDST + x], 0x55);
        }
        assert_int_equal(dst[0], 0);
        assert_int_equal(dst[1], 255);
        assert_int_equal(dst[2], 77);
        assert_int_equal(dst[3], 149);
        assert_int_equal(dst[4], 29);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(y10),
        cmocka_unit_test(y16),
        cmocka_unit_test(yuyv),
        cmocka_unit_test(uyvy),
        cmocka_unit_test(rgb),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
