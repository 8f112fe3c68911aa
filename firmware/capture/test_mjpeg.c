/* MJPEG to luma (mjpeg.c): webcam-like frames (colour, 4:2:2 and 4:2:0, and with the Huffman
 * tables left out as UVC cameras send them) made here with TurboJPEG's encoder, decoded by the
 * node's luma-only fast path and compared with a naive reference: TurboJPEG's full RGB decode
 * (accurate DCT) turned into BT.601 luma per pixel. Bad input (another size, a cut frame, bytes
 * that are no JPEG, every truncation of a frame) is refused without writing past the frame. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <turbojpeg.h>

#include <cmocka.h>

#include "capture/mjpeg.h"

enum { W = 160, H = 96, STRIDE = W + 8 };

/* A dark frame with bright round spots in colours (a marker scene as a webcam sees it). */
static void scene(uint8_t *rgb)
{
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double v = 0;
            for (int i = 0; i < 6; i++) {
                double cx = 14 + 26.3 * i, cy = 20 + 11.7 * i;
                double d2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
                v += 230 * exp(-d2 / (2 * 2.5 * 2.5));
            }
            uint8_t *p = rgb + 3 * (y * W + x);
            p[0] = (uint8_t)fmin(255, 12 + v);
            p[1] = (uint8_t)fmin(255, 10 + 0.9 * v);
            p[2] = (uint8_t)fmin(255, 16 + 0.7 * v);
        }
}

static unsigned char *encode(int subsamp, unsigned long *size)
{
    static uint8_t rgb[W * H * 3];
    scene(rgb);
    tjhandle tj = tjInitCompress();
    assert_non_null(tj);
    unsigned char *jpeg = NULL;
    assert_int_equal(tjCompress2(tj, rgb, W, 0, H, TJPF_RGB, &jpeg, size, subsamp, 85, 0), 0);
    tjDestroy(tj);
    return jpeg;
}

/* The reference: a full decode into Y, Cb and Cr planes with the accurate DCT, its Y plane. */
static void reference_luma(const unsigned char *jpeg, unsigned long size, double *out)
{
    static uint8_t planes[W * H * 3];
    int w, h, subsamp, cs;
    tjhandle tj = tjInitDecompress();
    assert_int_equal(tjDecompressHeader3(tj, jpeg, size, &w, &h, &subsamp, &cs), 0);
    assert_true(tjBufSizeYUV2(W, 1, H, subsamp) <= sizeof(planes));
    assert_int_equal(tjDecompressToYUV2(tj, jpeg, size, planes, W, 1, H, TJFLAG_ACCURATEDCT), 0);
    tjDestroy(tj);
    for (int i = 0; i < W * H; i++)
        out[i] = planes[i];
}

/* Decodes through mn_mjpeg and compares with the reference (equal: the luma-only path decodes
 * the same Y) and with the scene's own luma before compression (mean error under 2 levels:
 * the right picture), the padding untouched. */
static void check_against_reference(const unsigned char *jpeg, unsigned long size)
{
    static double ref[W * H];
    static uint8_t dst[STRIDE * H], rgb[W * H * 3];
    reference_luma(jpeg, size, ref);
    scene(rgb);
    struct mn_mjpeg *d = mn_mjpeg_new();
    assert_non_null(d);
    memset(dst, 0x5A, sizeof(dst));
    const char *why = NULL;
    assert_int_equal(mn_mjpeg_to_y8(d, jpeg, size, W, H, dst, STRIDE, &why), 0);
    double worst = 0, sum = 0;
    for (int y = 0; y < H; y++) {
        for (int x = 0; x < W; x++) {
            worst = fmax(worst, fabs(dst[y * STRIDE + x] - ref[y * W + x]));
            const uint8_t *p = rgb + 3 * (y * W + x);
            sum += fabs(dst[y * STRIDE + x] - (0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2]));
        }
        for (int x = W; x < STRIDE; x++)
            assert_int_equal(dst[y * STRIDE + x], 0x5A);
    }
    print_message("fast path vs accurate Y plane: worst %.0f levels; vs the scene: mean %.2f\n",
                  worst, sum / (W * H));
    assert_true(worst == 0.0);
    assert_true(sum / (W * H) <= 2.0);
    mn_mjpeg_free(d);
}

static void webcam_422(void **state)
{
    (void)state;
    unsigned long size;
    unsigned char *jpeg = encode(TJSAMP_422, &size);
    check_against_reference(jpeg, size);
    tjFree(jpeg);
}

static void webcam_420(void **state)
{
    (void)state;
    unsigned long size;
    unsigned char *jpeg = encode(TJSAMP_420, &size);
    check_against_reference(jpeg, size);
    tjFree(jpeg);
}

/* UVC cameras leave out the DHT segments and rely on the standard tables of the JPEG spec
 * (which is what the encoder used here): the frame without them decodes to the same luma. */
static void without_huffman_tables(void **state)
{
    (void)state;
    unsigned long size;
    unsigned char *jpeg = encode(TJSAMP_422, &size);
    unsigned char *bare = malloc(size);
    assert_non_null(bare);
    size_t n = 0, i = 2, removed = 0;
    memcpy(bare, jpeg, 2); /* SOI */
    n = 2;
    while (i + 4 <= size && jpeg[i] == 0xFF && jpeg[i + 1] != 0xDA) {
        size_t len = 2 + ((size_t)jpeg[i + 2] << 8 | jpeg[i + 3]);
        if (jpeg[i + 1] == 0xC4) {
            removed++;
        } else {
            memcpy(bare + n, jpeg + i, len);
            n += len;
        }
        i += len;
    }
    assert_true(removed > 0);
    memcpy(bare + n, jpeg + i, size - i); /* SOS, scan data, EOI */
    n += size - i;

    static uint8_t a[W * H], b[W * H];
    struct mn_mjpeg *d = mn_mjpeg_new();
    const char *why = NULL;
    assert_int_equal(mn_mjpeg_to_y8(d, jpeg, size, W, H, a, W, &why), 0);
    assert_int_equal(mn_mjpeg_to_y8(d, bare, n, W, H, b, W, &why), 0);
    assert_memory_equal(a, b, sizeof(a));
    mn_mjpeg_free(d);
    free(bare);
    tjFree(jpeg);
}

static void refusals(void **state)
{
    (void)state;
    unsigned long size;
    unsigned char *jpeg = encode(TJSAMP_422, &size);
    static uint8_t dst[STRIDE * H];
    struct mn_mjpeg *d = mn_mjpeg_new();
    const char *why = NULL;

    /* Another size than negotiated: refused before a byte is written. */
    memset(dst, 0x5A, sizeof(dst));
    assert_int_equal(mn_mjpeg_to_y8(d, jpeg, size, W / 2, H, dst, STRIDE, &why), -1);
    assert_non_null(strstr(why, "size"));
    for (size_t i = 0; i < sizeof(dst); i++)
        assert_int_equal(dst[i], 0x5A);

    /* Empty, and bytes that are no JPEG. */
    assert_int_equal(mn_mjpeg_to_y8(d, jpeg, 0, W, H, dst, STRIDE, &why), -1);
    static uint8_t noise[4096];
    for (size_t i = 0; i < sizeof(noise); i++)
        noise[i] = (uint8_t)(i * 131 + 7);
    assert_int_equal(mn_mjpeg_to_y8(d, noise, sizeof(noise), W, H, dst, STRIDE, &why), -1);

    /* A frame cut short (a USB transfer lost its tail): dropped, not passed on grey-filled. */
    assert_int_equal(mn_mjpeg_to_y8(d, jpeg, size / 2, W, H, dst, STRIDE, &why), -1);

    /* Every truncation of the frame returns (0 or -1) and the decoder still works after. */
    for (unsigned long n = 1; n < size; n += 37)
        (void)mn_mjpeg_to_y8(d, jpeg, n, W, H, dst, STRIDE, &why);
    assert_int_equal(mn_mjpeg_to_y8(d, jpeg, size, W, H, dst, STRIDE, &why), 0);
    mn_mjpeg_free(d);
    tjFree(jpeg);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(webcam_422),
        cmocka_unit_test(webcam_420),
        cmocka_unit_test(without_huffman_tables),
        cmocka_unit_test(refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
