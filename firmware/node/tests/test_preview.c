/* Preview rendering (box downscale, thresholding) and chunking back into the same image. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "node/preview.h"
#include "node/status.h"

static void downscale_and_threshold(void **state)
{
    (void)state;
    enum { W = 37, H = 21, STRIDE = 40 }; /* odd sizes: the partial last block is dropped */
    uint8_t frame[H * STRIDE];
    for (int y = 0; y < H; y++)
        for (int x = 0; x < STRIDE; x++)
            frame[y * STRIDE + x] = (uint8_t)(x < W ? (x * 3 + y * 5) % 251 : 0xEE);
    uint8_t out[W * H];
    uint32_t ow, oh;
    assert_int_equal(mn_preview_render(frame, W, H, STRIDE, 4, false, 0, out, sizeof(out), &ow, &oh), 0);
    assert_int_equal(ow, 9);
    assert_int_equal(oh, 5);
    for (uint32_t oy = 0; oy < oh; oy++) {
        for (uint32_t ox = 0; ox < ow; ox++) {
            unsigned sum = 0;
            for (int dy = 0; dy < 4; dy++)
                for (int dx = 0; dx < 4; dx++)
                    sum += frame[(oy * 4 + dy) * STRIDE + ox * 4 + dx];
            assert_int_equal(out[oy * ow + ox], (sum + 8) / 16);
        }
    }
    assert_int_equal(mn_preview_render(frame, W, H, STRIDE, 1, true, 100, out, sizeof(out), &ow, &oh), 0);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            assert_int_equal(out[y * W + x], frame[y * STRIDE + x] > 100 ? 255 : 0);
    assert_int_equal(mn_preview_render(frame, W, H, STRIDE, 3, false, 0, out, sizeof(out), &ow, &oh), -1);
    assert_int_equal(mn_preview_render(frame, W, H, STRIDE, 1, false, 0, out, 10, &ow, &oh), -1);
}

static void chunks_rebuild_the_image(void **state)
{
    (void)state;
    enum { W = 160, H = 100 };
    static uint8_t image[W * H], rebuilt[W * H];
    for (size_t i = 0; i < sizeof(image); i++)
        image[i] = (uint8_t)(i * 7);
    memset(rebuilt, 0, sizeof(rebuilt));
    uint32_t n = mn_preview_chunk_count(W, H);
    assert_int_equal(n, (W * H + MN_PREVIEW_CHUNK_BYTES - 1) / MN_PREVIEW_CHUNK_BYTES);
    mocap_v1_Packet packet, decoded;
    uint8_t datagram[MN_WIRE_MAX_DATAGRAM];
    for (uint32_t i = 0; i < n; i++) {
        mn_preview_chunk(image, W, H, true, 4, 99, i, &packet);
        size_t size;
        const char *why = NULL;
        assert_int_equal(mn_wire_encode(&packet, datagram, sizeof(datagram), &size, &why), 0);
        assert_true(size <= MN_WIRE_MAX_DATAGRAM);
        assert_int_equal(mn_wire_decode(datagram, size, &decoded, &why), 0);
        const mocap_v1_PreviewChunk *c = &decoded.body.preview_chunk;
        assert_int_equal(c->chunk_count, n);
        assert_int_equal(c->frame_number, 99);
        assert_int_equal(c->mode, mocap_v1_PreviewMode_PREVIEW_MODE_THRESHOLDED);
        memcpy(rebuilt + c->offset, c->data.bytes, c->data.size);
    }
    assert_memory_equal(image, rebuilt, sizeof(image));
}

static void temperature_file(void **state)
{
    (void)state;
    char path[] = "/tmp/mn_test_temp_XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    assert_int_equal(write(fd, "48312\n", 6), 6);
    close(fd);
    int32_t mdeg = 0;
    assert_int_equal(mn_status_read_temperature(path, &mdeg), 0);
    assert_int_equal(mdeg, 48312);
    fd = open(path, O_WRONLY | O_TRUNC);
    assert_int_equal(write(fd, "hot\n", 4), 4);
    close(fd);
    assert_int_equal(mn_status_read_temperature(path, &mdeg), -1);
    unlink(path);
    assert_int_equal(mn_status_read_temperature(path, &mdeg), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(downscale_and_threshold),
        cmocka_unit_test(chunks_rebuild_the_image),
        cmocka_unit_test(temperature_file),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
