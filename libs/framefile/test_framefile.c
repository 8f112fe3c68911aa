/* frames.mcf tests: lossless round trip (raw and zlib, odd sizes with clipped edge tiles),
 * dark-level recordings, the noise model's statistics and determinism, truncation at every
 * byte, corruption, bad headers and bad arguments. */
#define _XOPEN_SOURCE 700

#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "framefile/framefile.h"
#include "testing/alloc_counting.h"

#define W 100
#define H 37
#define FRAMES 5

static char tmpdir[64];


static int make_tmp(void **state)
{
    (void)state;
    strcpy(tmpdir, "/tmp/mn_ff_testXXXXXX");
    return mkdtemp(tmpdir) ? 0 : -1;
}

static int remove_tmp(void **state)
{
    (void)state;
    char path[128];
    snprintf(path, sizeof path, "%s/cam1/%s", tmpdir, MN_FF_FILE_NAME);
    unlink(path);
    snprintf(path, sizeof path, "%s/cam1", tmpdir);
    rmdir(path);
    rmdir(tmpdir);
    return 0;
}

static struct mn_ff_info test_info(void)
{
    struct mn_ff_info info = {0};
    info.width = W;
    info.height = H;
    info.rate_mhz = 120000;
    info.background = 14;
    info.noise_sigma_q8 = 2 * 256;
    info.noise_seed = 42;
    return info;
}

/* Frame k: the model's background and noise, plus a few bright squares that move. */
static void make_frame(const struct mn_ff_noise *noise, uint64_t number, uint8_t *px)
{
    mn_ff_noise_fill(noise, number, 0, 0, W, H, px, W);
    for (int s = 0; s < 3; s++) {
        int cx = (int)(10 + 30 * s + 3 * number) % (W - 4), cy = (int)(5 + 11 * s) % (H - 4);
        for (int y = cy; y < cy + 4; y++)
            for (int x = cx; x < cx + 4; x++)
                px[y * W + x] = (uint8_t)(150 + 20 * s + y);
    }
    px[(H - 1) * W + (W - 1)] = 250; /* a clipped corner tile */
}

static char *write_file(int zlib_level, size_t *file_size)
{
    struct mn_ff_info info = test_info();
    struct mn_ff_write_options opts = {zlib_level, -1};
    static char dir[128];
    snprintf(dir, sizeof dir, "%s/cam1", tmpdir);
    struct mn_ff_writer *wr = mn_ff_writer_open(dir, &info, &opts);
    assert_non_null(wr);
    struct mn_ff_noise *noise = mn_ff_noise_new(W, 14, 2 * 256, 42);
    uint8_t px[W * H];
    for (uint64_t k = 0; k < FRAMES; k++) {
        make_frame(noise, 1000 + k, px);
        assert_int_equal(mn_ff_writer_add(wr, 1000 + k, 5000000ull * k, px, W), 0);
    }
    *file_size = (size_t)mn_ff_writer_bytes(wr);
    assert_int_equal(mn_ff_writer_close(wr), 0);
    mn_ff_noise_free(noise);
    return dir;
}

static void *slurp(const char *dir, size_t *size)
{
    char path[160];
    snprintf(path, sizeof path, "%s/%s", dir, MN_FF_FILE_NAME);
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    *size = (size_t)ftell(f);
    fseek(f, 0, SEEK_SET);
    void *buf = malloc(*size);
    assert_int_equal(fread(buf, 1, *size, f), *size);
    fclose(f);
    return buf;
}

static void check_round_trip(int zlib_level)
{
    size_t written;
    char *dir = write_file(zlib_level, &written);
    const char *why = NULL;
    struct mn_ff_reader *rd = mn_ff_reader_open(dir, &why);
    assert_non_null(rd);
    const struct mn_ff_info *info = mn_ff_reader_info(rd);
    assert_int_equal(info->width, W);
    assert_int_equal(info->height, H);
    assert_int_equal(info->rate_mhz, 120000);
    assert_int_equal(info->frame_count, FRAMES);
    struct mn_ff_noise *noise = mn_ff_noise_new(W, 14, 2 * 256, 42);
    uint8_t want[W * H], got[(W + 3) * H];
    struct mn_ff_frame fr;
    for (int pass = 0; pass < 2; pass++) {
        for (uint64_t k = 0; k < FRAMES; k++) {
            assert_int_equal(mn_ff_reader_next(rd, got, W + 3, &fr), 1);
            make_frame(noise, 1000 + k, want);
            for (int y = 0; y < H; y++)
                assert_memory_equal(got + y * (W + 3), want + y * W, W);
            assert_int_equal(fr.frame_number, 1000 + k);
            assert_int_equal(fr.timestamp_ns, 5000000ull * k);
            /* 7 x 3 tiles in all; the squares and the corner touch at most 13. */
            assert_true(fr.stored_tiles >= 4 && fr.stored_tiles <= 13);
        }
        assert_int_equal(mn_ff_reader_next(rd, got, W + 3, &fr), 0);
        assert_false(mn_ff_reader_damaged(rd));
        assert_string_equal(mn_ff_reader_message(rd), "");
        assert_int_equal(mn_ff_reader_rewind(rd), 0);
    }
    mn_ff_reader_close(rd);
    mn_ff_noise_free(noise);

    /* The file is far smaller than the raw frames. */
    assert_true(written < FRAMES * W * H / 2);
}

static void test_round_trip_raw(void **state)
{
    (void)state;
    check_round_trip(0);
}

static void test_round_trip_zlib(void **state)
{
    (void)state;
    check_round_trip(6);
}

/* Real recordings: flat background model, tiles at or below the dark level are dropped. */
static void test_dark_level(void **state)
{
    (void)state;
    struct mn_ff_info info = test_info();
    info.noise_sigma_q8 = 0;
    info.background = 3;
    struct mn_ff_write_options opts = {1, 20};
    char dir[128];
    snprintf(dir, sizeof dir, "%s/cam1", tmpdir);
    struct mn_ff_writer *wr = mn_ff_writer_open(dir, &info, &opts);
    assert_non_null(wr);
    uint8_t px[W * H];
    for (int i = 0; i < W * H; i++)
        px[i] = (uint8_t)(i % 7); /* dark noise, all <= 20 */
    px[20 * W + 50] = 200;
    px[20 * W + 51] = 21;
    assert_int_equal(mn_ff_writer_add(wr, 7, 0, px, W), 0);
    assert_int_equal(mn_ff_writer_close(wr), 0);

    struct mn_ff_reader *rd = mn_ff_reader_open(dir, NULL);
    assert_non_null(rd);
    uint8_t got[W * H];
    struct mn_ff_frame fr;
    assert_int_equal(mn_ff_reader_next(rd, got, W, &fr), 1);
    assert_int_equal(fr.stored_tiles, 1);
    /* The tile with content is exact; everything else is the flat background. */
    for (int y = 0; y < H; y++) {
        for (int x = 0; x < W; x++) {
            int in_tile = y >= 16 && y < 32 && x >= 48 && x < 64;
            assert_int_equal(got[y * W + x], in_tile ? px[y * W + x] : 3);
        }
    }
    mn_ff_reader_close(rd);
}

static void test_noise_model(void **state)
{
    (void)state;
    const uint32_t w = 640, h = 200;
    struct mn_ff_noise *a = mn_ff_noise_new(w, 40, 3 * 256, 7);
    struct mn_ff_noise *b = mn_ff_noise_new(w, 40, 3 * 256, 7);
    uint8_t *p = malloc(w * h), *q = malloc(w * h);
    mn_ff_noise_fill(a, 5, 0, 0, w, h, p, w);
    mn_ff_noise_fill(b, 5, 0, 0, w, h, q, w);
    assert_memory_equal(p, q, w * h);
    double s = 0, s2 = 0;
    for (uint32_t i = 0; i < w * h; i++) {
        s += p[i];
        s2 += (double)p[i] * p[i];
    }
    double mean = s / (w * h), sd = sqrt(s2 / (w * h) - mean * mean);
    assert_true(fabs(mean - 40.0) < 0.1);
    /* Rounding to integers adds 1/12 to the variance. */
    assert_true(fabs(sd - sqrt(9.0 + 1.0 / 12.0)) < 0.15);
    /* Another frame gives another pattern; a sub-rectangle matches the full frame. */
    mn_ff_noise_fill(a, 6, 0, 0, w, h, q, w);
    assert_true(memcmp(p, q, w * h) != 0);
    uint8_t sub[10 * 20];
    mn_ff_noise_fill(a, 5, 100, 50, 20, 10, sub, 20);
    for (int r = 0; r < 10; r++)
        assert_memory_equal(sub + r * 20, p + (50 + r) * w + 100, 20);
    assert_null(mn_ff_noise_new(0, 0, 0, 0));
    mn_ff_noise_free(a);
    mn_ff_noise_free(b);
    free(p);
    free(q);
}

/* Every prefix of the file reads the whole frames it holds and reports the cut. */
static void test_truncation_everywhere(void **state)
{
    (void)state;
    size_t written, size;
    char *dir = write_file(6, &written);
    uint8_t *buf = slurp(dir, &size);
    assert_int_equal(size, written);

    /* Record ends, found by reading the full file. */
    size_t ends[FRAMES];
    {
        size_t off = 64;
        for (int k = 0; k < FRAMES; k++) {
            uint32_t len = buf[off + 4] | buf[off + 5] << 8 | (uint32_t)buf[off + 6] << 16 |
                           (uint32_t)buf[off + 7] << 24;
            off += 12 + len;
            ends[k] = off;
        }
        assert_int_equal(off, size);
    }
    uint8_t px[W * H];
    for (size_t cut = 0; cut <= size; cut++) {
        const char *why = NULL;
        struct mn_ff_reader *rd = mn_ff_reader_open_mem(buf, cut, &why);
        if (cut < 64) {
            assert_null(rd);
            assert_true(strlen(why) > 0);
            continue;
        }
        assert_non_null(rd);
        int whole = 0;
        for (int k = 0; k < FRAMES; k++)
            whole += ends[k] <= cut;
        int n = 0, rc;
        while ((rc = mn_ff_reader_next(rd, px, W, NULL)) == 1)
            n++;
        assert_int_equal(rc, 0);
        assert_int_equal(n, whole);
        /* Only the complete file is undamaged (the header promises 5 frames). */
        assert_int_equal(mn_ff_reader_damaged(rd), cut != size);
        if (cut != size)
            assert_true(strlen(mn_ff_reader_message(rd)) > 0);
        mn_ff_reader_close(rd);
    }
    free(buf);
}

/* A flipped byte anywhere after the header stops the stream at the frame before it. */
static void test_corruption(void **state)
{
    (void)state;
    size_t written, size;
    char *dir = write_file(0, &written);
    uint8_t *buf = slurp(dir, &size);
    uint8_t px[W * H];
    for (size_t pos = 64; pos < size; pos += 37) {
        buf[pos] ^= 0x5a;
        struct mn_ff_reader *rd = mn_ff_reader_open_mem(buf, size, NULL);
        assert_non_null(rd);
        int n = 0, rc;
        while ((rc = mn_ff_reader_next(rd, px, W, NULL)) == 1)
            n++;
        assert_int_equal(rc, 0);
        assert_true(n < FRAMES);
        assert_true(mn_ff_reader_damaged(rd));
        mn_ff_reader_close(rd);
        buf[pos] ^= 0x5a;
    }
    free(buf);
}

static void test_bad_headers(void **state)
{
    (void)state;
    size_t written, size;
    char *dir = write_file(0, &written);
    uint8_t *buf = slurp(dir, &size);
    const char *why = NULL;
    /* Each field change also breaks the CRC; either reason is a refusal with a message. */
    static const size_t fields[] = {0, 8, 10, 12, 16, 29, 32, 60};
    for (size_t i = 0; i < sizeof fields / sizeof fields[0]; i++) {
        buf[fields[i]] ^= 0xff;
        assert_null(mn_ff_reader_open_mem(buf, size, &why));
        assert_true(strlen(why) > 0);
        buf[fields[i]] ^= 0xff;
    }
    assert_non_null(why);
    struct mn_ff_reader *rd = mn_ff_reader_open_mem(buf, size, &why);
    assert_non_null(rd);
    mn_ff_reader_close(rd);
    assert_null(mn_ff_reader_open("/nonexistent/frames", &why));
    assert_true(strlen(why) > 0);
    assert_null(mn_ff_reader_open(tmpdir, &why)); /* a directory without frames.mcf */
    assert_string_equal(why, "directory holds no readable frames.mcf");
    char file[160];
    snprintf(file, sizeof file, "%s/%s", dir, MN_FF_FILE_NAME);
    rd = mn_ff_reader_open(file, &why);
    assert_non_null(rd);
    mn_ff_reader_close(rd);
    free(buf);
}

static void test_no_allocation_per_frame(void **state)
{
    (void)state;
    size_t written;
    char *dir = write_file(6, &written);
    unsigned long at_open = mn_alloc_count();
    struct mn_ff_reader *rd = mn_ff_reader_open(dir, NULL);
    assert_non_null(rd);
    assert_true(mn_alloc_count() > at_open); /* the counting wrappers are in effect */
    uint8_t px[W * H];
    unsigned long before = mn_alloc_count();
    for (int pass = 0; pass < 3; pass++) {
        int n = 0;
        while (mn_ff_reader_next(rd, px, W, NULL) == 1)
            n++;
        assert_int_equal(n, FRAMES);
        assert_int_equal(mn_ff_reader_rewind(rd), 0);
    }
    assert_int_equal(mn_alloc_count(), before);
    mn_ff_reader_close(rd);
}

static void test_bad_arguments(void **state)
{
    (void)state;
    struct mn_ff_info info = test_info();
    struct mn_ff_write_options opts = {0, -1};
    char dir[128];
    snprintf(dir, sizeof dir, "%s/cam1", tmpdir);
    info.width = 0;
    assert_null(mn_ff_writer_open(dir, &info, &opts));
    assert_int_equal(errno, EINVAL);
    info = test_info();
    opts.zlib_level = 10;
    assert_null(mn_ff_writer_open(dir, &info, &opts));
    opts.zlib_level = 0;
    opts.dark_level = 256;
    assert_null(mn_ff_writer_open(dir, &info, &opts));
    opts.dark_level = -1;
    /* A regular file in the way of the directory. */
    char file[160];
    snprintf(file, sizeof file, "%s/plainfile", tmpdir);
    FILE *f = fopen(file, "w");
    fclose(f);
    assert_null(mn_ff_writer_open(file, &info, &opts));
    unlink(file);
    struct mn_ff_writer *wr = mn_ff_writer_open(dir, &info, &opts);
    assert_non_null(wr);
    uint8_t px[W * H] = {0};
    assert_int_equal(mn_ff_writer_add(wr, 0, 0, px, W - 1), -1);
    assert_int_equal(mn_ff_writer_add(wr, 0, 0, NULL, W), -1);
    assert_int_equal(mn_ff_writer_close(wr), 0);
    struct mn_ff_reader *rd = mn_ff_reader_open(dir, NULL);
    assert_non_null(rd);
    assert_int_equal(mn_ff_reader_next(rd, px, W - 1, NULL), -1);
    assert_int_equal(mn_ff_reader_next(rd, px, W, NULL), 0); /* no frames, undamaged */
    assert_false(mn_ff_reader_damaged(rd));
    mn_ff_reader_close(rd);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip_raw),
        cmocka_unit_test(test_round_trip_zlib),
        cmocka_unit_test(test_dark_level),
        cmocka_unit_test(test_noise_model),
        cmocka_unit_test(test_truncation_everywhere),
        cmocka_unit_test(test_corruption),
        cmocka_unit_test(test_bad_headers),
        cmocka_unit_test(test_no_allocation_per_frame),
        cmocka_unit_test(test_bad_arguments),
    };
    return cmocka_run_group_tests(tests, make_tmp, remove_tmp);
}
