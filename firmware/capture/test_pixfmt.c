/* Pixel-format conversion used by the V4L2 source for sensors without GREY: every format to Y8
 * with padded source rows, checked against values computed by hand. */
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(y10),
        cmocka_unit_test(y16),
        cmocka_unit_test(yuyv),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
