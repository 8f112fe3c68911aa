/* The C client decodes a StreamFrame written by protoc itself (an independent encoder), on
 * every target it is built for (the aarch64 build runs this under qemu). The bytes are
 *   protoc --encode=mocap.stream.v1.StreamFrame -I proto proto/mocap_stream.proto <<<
 *   'frame_number: 12 trigger_time_ns: 1800000000000000000 publish_time_ns: 1800000000000900000
 *    cameras: 8 parts: 3 points { x: 1 y: 2 z: 3 residual_px: 0.2 views: 3 marker: 1 }
 *    points { x: -1 y: 5 z: 900 views: 2 provisional_track: 77 label: "LASI" }
 *    bodies { id: 1 name: "wand" tracked: true x: 1 y: 2 z: 3 qw: 1 mean_error_mm: 0.3 }'
 * (also tests/fuzz/corpus/stream_frame/frame_points_bodies). */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "mocap_stream_client.h"

static const uint8_t kFrame[] = {
    0x08, 0x0c, 0x10, 0x80, 0x80, 0xd0, 0x9d, 0xe9, 0xce, 0xb8, 0xfd, 0x18,
    0x18, 0xa0, 0xf7, 0x86, 0x9e, 0xe9, 0xce, 0xb8, 0xfd, 0x18, 0x20, 0x08,
    0x28, 0x03, 0x32, 0x18, 0x0d, 0x00, 0x00, 0x80, 0x3f, 0x15, 0x00, 0x00,
    0x00, 0x40, 0x1d, 0x00, 0x00, 0x40, 0x40, 0x25, 0xcd, 0xcc, 0x4c, 0x3e,
    0x28, 0x03, 0x30, 0x01, 0x32, 0x19, 0x0d, 0x00, 0x00, 0x80, 0xbf, 0x15,
    0x00, 0x00, 0xa0, 0x40, 0x1d, 0x00, 0x00, 0x61, 0x44, 0x28, 0x02, 0x38,
    0x4d, 0x42, 0x04, 0x4c, 0x41, 0x53, 0x49, 0x3a, 0x23, 0x08, 0x01, 0x12,
    0x04, 0x77, 0x61, 0x6e, 0x64, 0x18, 0x01, 0x25, 0x00, 0x00, 0x80, 0x3f,
    0x2d, 0x00, 0x00, 0x00, 0x40, 0x35, 0x00, 0x00, 0x40, 0x40, 0x55, 0x00,
    0x00, 0x80, 0x3f, 0x5d, 0x9a, 0x99, 0x99, 0x3e,
};

static void decodes_what_protoc_wrote(void **state)
{
    (void)state;
    mocap_stream_point points[4];
    mocap_stream_body bodies[2];
    mocap_stream_frame f = {.points = points, .point_capacity = 4, .bodies = bodies, .body_capacity = 2};
    assert_int_equal(mocap_stream_decode(kFrame, sizeof kFrame, &f), 0);
    assert_int_equal(f.frame_number, 12);
    assert_true(f.trigger_time_ns == 1800000000000000000ull);
    assert_true(f.publish_time_ns == 1800000000000900000ull);
    assert_int_equal(f.cameras, 8);
    assert_int_equal(f.parts, MOCAP_STREAM_POINTS | MOCAP_STREAM_BODIES);
    assert_int_equal(f.point_count, 2);
    assert_true(points[0].x == 1.0f && points[0].y == 2.0f && points[0].z == 3.0f);
    assert_true(points[0].residual_px == 0.2f);
    assert_int_equal(points[0].views, 3);
    assert_int_equal(points[0].marker, 1);
    assert_true(points[1].x == -1.0f && points[1].z == 900.0f);
    assert_int_equal(points[1].marker, 0);
    assert_int_equal(points[1].provisional_track, 77);
    assert_true(points[1].id == 0); /* written before the field existed: no id */
    assert_string_equal(points[1].label, "LASI");
    assert_int_equal(f.body_count, 1);
    assert_string_equal(bodies[0].name, "wand");
    assert_true(bodies[0].tracked);
    assert_true(bodies[0].qw == 1.0f && bodies[0].mean_error_mm == 0.3f);
}

static void counts_what_does_not_fit(void **state)
{
    (void)state;
    mocap_stream_point one[1];
    mocap_stream_frame f = {.points = one, .point_capacity = 1};
    assert_int_equal(mocap_stream_decode(kFrame, sizeof kFrame, &f), 0);
    assert_int_equal(f.point_count, 1);
    assert_int_equal(f.points_total, 2);
    assert_int_equal(f.body_count, 0);
    assert_int_equal(f.bodies_total, 1);
}

static void refuses_truncated_frames(void **state)
{
    (void)state;
    mocap_stream_point points[4];
    mocap_stream_frame f = {.points = points, .point_capacity = 4};
    for (size_t n = 1; n < sizeof kFrame; ++n) {
        /* Every prefix that ends inside a field is refused; one that ends between fields is a
         * shorter, valid frame. Either way nothing beyond the array is written. */
        int rc = mocap_stream_decode(kFrame, n, &f);
        assert_true(rc == 0 || rc == -EBADMSG);
        assert_true(f.point_count <= 4);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(decodes_what_protoc_wrote),
        cmocka_unit_test(counts_what_does_not_fit),
        cmocka_unit_test(refuses_truncated_frames),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
