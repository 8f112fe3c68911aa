/* Recorded JPEG frames through the replay source (jpeg_frames.c, capture_replay.c): webcam-like
 * colour JPEGs (4:2:0) of bright spots written into a directory with TurboJPEG's encoder, among
 * them a frame cut short, a file that is no JPEG and a frame of another size; the replay hands
 * out the good ones as their frame numbers (the bad ones dropped as lost frames), their luma
 * gives the spots at the drawn positions through the node's detector, loops renumber as a
 * frames.mcf replay does, and a directory without a readable JPEG or one that vanishes is
 * refused. */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <turbojpeg.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "capture/capture.h"
#include "capture/jpeg_frames.h"
#include "detect/detect.h"

enum { W = 192, H = 128, SPOTS = 3, GOOD_LAST = 6 };

static char dir[64];

/* Spot i of frame k: its centre, moving a little from frame to frame. */
static void spot_centre(int k, int i, double *cx, double *cy)
{
    *cx = 30.25 + 60.5 * i + 1.37 * k;
    *cy = 24.75 + 35.2 * i + 0.61 * k;
}

static void write_file(const char *name, const void *data, size_t size)
{
    char path[128];
    snprintf(path, sizeof(path), "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(data, 1, size, f), size);
    fclose(f);
}

/* Frame k as a colour JPEG of w x h: grey spots (R = G = B, so luma is the drawn value) on a
 * dark background, 4:2:0 at quality 92 as UVC webcams send. The caller frees it with tjFree. */
static unsigned char *encode_frame(int k, int w, int h, unsigned long *size)
{
    uint8_t *rgb = malloc((size_t)w * h * 3);
    assert_non_null(rgb);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double v = 18;
            for (int i = 0; i < SPOTS; i++) {
                double cx, cy;
                spot_centre(k, i, &cx, &cy);
                double d2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
                v += 220 * exp(-d2 / (2 * 2.2 * 2.2));
            }
            memset(rgb + 3 * ((size_t)y * w + x), (int)lround(fmin(255, v)), 3);
        }
    tjhandle tj = tjInitCompress();
    assert_non_null(tj);
    unsigned char *jpeg = NULL;
    assert_int_equal(tjCompress2(tj, rgb, w, 0, h, TJPF_RGB, &jpeg, size, TJSAMP_420, 92, 0), 0);
    tjDestroy(tj);
    free(rgb);
    return jpeg;
}

/* 000.jpg .. 006.jpg: 2 cut short, 4 no JPEG, 5 of another size; a text file beside them. */
static int make_recording(void **state)
{
    (void)state;
    snprintf(dir, sizeof(dir), "/tmp/mn_jpeg_frames_XXXXXX");
    if (mkdtemp(dir) == NULL)
        return -1;
    for (int k = 0; k <= GOOD_LAST; k++) {
        char name[16];
        snprintf(name, sizeof(name), "%03d.jpg", k);
        unsigned long size;
        unsigned char *jpeg = encode_frame(k, k == 5 ? W / 2 : W, k == 5 ? H / 2 : H, &size);
        if (k == 2)
            size /= 2;
        if (k == 4)
            write_file(name, "not a JPEG frame\n", 17);
        else
            write_file(name, jpeg, size);
        tjFree(jpeg);
    }
    write_file("notes.txt", "recorded by a test\n", 19);
    return 0;
}

static int remove_recording(void **state)
{
    (void)state;
    char cmd[128];
    snprintf(cmd, sizeof(cmd), "rm -rf %s", dir);
    return system(cmd) == 0 ? 0 : -1;
}

static void *open_replay(bool loop, uint32_t *w, uint32_t *h, char *err, size_t errlen)
{
    struct mn_replay_params p = {
        .dir = dir,
        .grid = {.epoch_real_ns = 0, .rate_millihz = 100000, .real_minus_mono_ns = 0},
        .trigger_delay_ns = 0,
        .as_fast_as_possible = true,
        .loop = loop,
    };
    return mn_capture_replay_new(&p, w, h, err, errlen);
}

/* The drawn spots found in the frame's luma, each within 0.15 px. */
static void check_spots(struct mn_detector *det, const struct mn_frame *f, int k)
{
    struct mn_blob blobs[8];
    size_t n = 0;
    assert_int_equal(mn_detector_run(det, f->pixels, f->width, f->height, f->stride, blobs, 8, &n),
                     0);
    assert_int_equal(n, SPOTS);
    for (int i = 0; i < SPOTS; i++) {
        double cx, cy;
        spot_centre(k, i, &cx, &cy);
        double best = 1e9;
        for (size_t b = 0; b < n; b++)
            best = fmin(best, hypot(blobs[b].x - cx, blobs[b].y - cy));
        if (best > 0.15)
            fail_msg("frame %d spot %d: nearest blob %.3f px from (%.2f, %.2f)", k, i, best, cx, cy);
    }
}

static void good_frames_in_order_bad_ones_dropped(void **state)
{
    (void)state;
    char err[256] = "";
    uint32_t w = 0, h = 0;
    void *r = open_replay(false, &w, &h, err, sizeof(err));
    if (r == NULL)
        fail_msg("%s", err);
    assert_int_equal(w, W);
    assert_int_equal(h, H);
    struct mn_detect_config cfg;
    mn_detect_config_default(&cfg);
    cfg.threshold = 100;
    struct mn_detector *det = mn_detector_new(&cfg, W, H);
    assert_non_null(det);

    const uint64_t expected[] = {0, 1, 3, 6};
    assert_int_equal(mn_capture_replay_ops.start(r), 0);
    for (size_t i = 0; i < sizeof(expected) / sizeof(expected[0]); i++) {
        struct mn_frame f;
        assert_int_equal(mn_capture_replay_ops.dequeue(r, &f), 1);
        assert_int_equal(f.sequence, expected[i]);
        assert_int_equal(f.width, W);
        assert_int_equal(f.height, H);
        check_spots(det, &f, (int)expected[i]);
        assert_int_equal(mn_capture_replay_ops.release(r, &f), 0);
    }
    struct mn_frame f;
    errno = 0;
    assert_int_equal(mn_capture_replay_ops.dequeue(r, &f), -1);
    assert_int_equal(errno, ENODATA);
    mn_detector_free(det);
    mn_capture_replay_ops.close(r);
}

static void loops_renumber(void **state)
{
    (void)state;
    char err[256] = "";
    uint32_t w, h;
    void *r = open_replay(true, &w, &h, err, sizeof(err));
    assert_non_null(r);
    assert_int_equal(mn_capture_replay_ops.start(r), 0);
    /* Seven files a pass: pass p's frame k is k + 7p. */
    const uint64_t expected[] = {0, 1, 3, 6, 7, 8, 10, 13, 14};
    for (size_t i = 0; i < sizeof(expected) / sizeof(expected[0]); i++) {
        struct mn_frame f;
        assert_int_equal(mn_capture_replay_ops.dequeue(r, &f), 1);
        assert_int_equal(f.sequence, expected[i]);
        assert_int_equal(mn_capture_replay_ops.release(r, &f), 0);
    }
    mn_capture_replay_ops.close(r);
}

static void directory_without_readable_jpeg_refused(void **state)
{
    (void)state;
    char bad[96];
    snprintf(bad, sizeof(bad), "%s/bad", dir);
    assert_int_equal(mkdir(bad, 0700), 0);
    char path[128];
    snprintf(path, sizeof(path), "%s/0.jpg", bad);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    fputs("\xff\xd8 no more", f);
    fclose(f);
    char err[256] = "";
    uint32_t w, h;
    struct mn_jpeg_frames *jf = mn_jpeg_frames_open(bad, &w, &h, err, sizeof(err));
    assert_null(jf);
    if (strstr(err, "no JPEG file whose header reads") == NULL)
        fail_msg("unexpected refusal: %s", err);
    assert_int_equal(unlink(path), 0);
    assert_int_equal(rmdir(bad), 0);
    assert_false(mn_jpeg_frames_present(bad));
}

static void vanished_recording_is_an_unplug(void **state)
{
    (void)state;
    char err[256] = "";
    uint32_t w, h;
    void *r = open_replay(false, &w, &h, err, sizeof(err));
    assert_non_null(r);
    assert_int_equal(mn_capture_replay_ops.start(r), 0);
    struct mn_frame f;
    assert_int_equal(mn_capture_replay_ops.dequeue(r, &f), 1);
    assert_int_equal(mn_capture_replay_ops.release(r, &f), 0);
    assert_int_equal(remove_recording(NULL), 0);
    errno = 0;
    assert_int_equal(mn_capture_replay_ops.dequeue(r, &f), -1);
    assert_int_not_equal(errno, ENODATA);
    mn_capture_replay_ops.close(r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(good_frames_in_order_bad_ones_dropped),
        cmocka_unit_test(loops_renumber),
        cmocka_unit_test(directory_without_readable_jpeg_refused),
        cmocka_unit_test(vanished_recording_is_an_unplug), /* last: removes the recording */
    };
    return cmocka_run_group_tests(tests, make_recording, remove_recording);
}
