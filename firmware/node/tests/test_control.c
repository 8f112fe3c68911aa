/* Hub-to-node datagrams through the node's control handler: every command decoded to the right
 * typed command, mask images assembled from chunks in any order, malformed, out-of-range,
 * misdirected or wrong-kind datagrams rejected with a reason, and which of them the node
 * acknowledges. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>
#include <pb_encode.h>

#include "node/control.h"
#include "wire/wire.h"

static uint8_t buf[2048];

/* Encodes without the wire's validation, so tests can send what a broken hub might. */
static size_t raw_encode(const mocap_v1_Packet *p)
{
    pb_ostream_t s = pb_ostream_from_buffer(buf, sizeof(buf));
    assert_true(pb_encode(&s, mocap_v1_Packet_fields, p));
    return s.bytes_written;
}

static mocap_v1_Packet control_packet(uint32_t node_id, pb_size_t which)
{
    mocap_v1_Packet p = mocap_v1_Packet_init_zero;
    p.version = 1;
    p.which_body = mocap_v1_Packet_control_tag;
    p.body.control.node_id = node_id;
    p.body.control.sequence = 42;
    p.body.control.which_command = which;
    return p;
}

/* A HubAnnounce naming the hub's port (epoch and rate zero for the test to fill in). */
static mocap_v1_Packet announce_packet(uint32_t port)
{
    mocap_v1_Packet p = mocap_v1_Packet_init_zero;
    p.version = 1;
    p.which_body = mocap_v1_Packet_hub_announce_tag;
    p.body.hub_announce.port = port;
    return p;
}

static enum mn_control_result handle(struct mn_control *ctl, const mocap_v1_Packet *p,
                                     bool announce, struct mn_command *cmd, const char **why)
{
    size_t n = raw_encode(p);
    *why = NULL;
    return mn_control_handle(ctl, buf, n, announce, cmd, why);
}

static void commands(void **state)
{
    (void)state;
    struct mn_control *ctl = mn_control_new(5);
    struct mn_command cmd;
    const char *why;

    mocap_v1_Packet p = control_packet(5, mocap_v1_Control_start_tag);
    p.body.control.command.start.epoch_ns = 1700000000123456789ull;
    p.body.control.command.start.rate_millihz = 120000;
    assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_ACCEPTED);
    assert_int_equal(cmd.kind, MN_CMD_START);
    assert_int_equal(cmd.sequence, 42);
    assert_int_equal(cmd.u.start.epoch_ns, 1700000000123456789ll);
    assert_int_equal(cmd.u.start.rate_millihz, 120000);

    p = control_packet(0, mocap_v1_Control_stop_tag); /* node 0: every node */
    assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_ACCEPTED);
    assert_int_equal(cmd.kind, MN_CMD_STOP);

    p = control_packet(5, mocap_v1_Control_set_threshold_tag);
    p.body.control.command.set_threshold.value = 77;
    assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_ACCEPTED);
    assert_int_equal(cmd.kind, MN_CMD_THRESHOLD);
    assert_false(cmd.u.threshold.automatic);
    assert_int_equal(cmd.u.threshold.value, 77);

    p = control_packet(5, mocap_v1_Control_set_exposure_tag);
    p.body.control.command.set_exposure.exposure_us = 800;
    p.body.control.command.set_exposure.gain_milli = 2500;
    assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_ACCEPTED);
    assert_int_equal(cmd.kind, MN_CMD_EXPOSURE);
    assert_int_equal(cmd.u.exposure.exposure_us, 800);
    assert_int_equal(cmd.u.exposure.gain_milli, 2500);

    p = control_packet(5, mocap_v1_Control_set_picture_tag);
    p.body.control.command.set_picture.set_brightness = true;
    p.body.control.command.set_picture.brightness_pct = 0;
    p.body.control.command.set_picture.contrast_pct = 90; /* not flagged: unchanged */
    assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_ACCEPTED);
    assert_int_equal(cmd.kind, MN_CMD_PICTURE);
    assert_int_equal(cmd.u.picture.brightness_pct, 0);
    assert_int_equal(cmd.u.picture.contrast_pct, -1);
    p.body.control.command.set_picture.set_contrast = true;
    assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_ACCEPTED);
    assert_int_equal(cmd.u.picture.contrast_pct, 90);

    p = control_packet(5, mocap_v1_Control_preview_request_tag);
    p.body.control.command.preview_request.mode = mocap_v1_PreviewMode_PREVIEW_MODE_THRESHOLDED;
    p.body.control.command.preview_request.downscale = 4;
    assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_ACCEPTED);
    assert_int_equal(cmd.kind, MN_CMD_PREVIEW);
    assert_true(cmd.u.preview.thresholded);
    assert_int_equal(cmd.u.preview.downscale, 4);

    p = control_packet(5, mocap_v1_Control_identify_tag);
    p.body.control.command.identify.duration_ms = 3000;
    assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_ACCEPTED);
    assert_int_equal(cmd.kind, MN_CMD_IDENTIFY);
    assert_int_equal(cmd.u.identify.duration_ms, 3000);

    p = control_packet(5, mocap_v1_Control_set_mask_tag);
    p.body.control.command.set_mask.rects_count = 2;
    p.body.control.command.set_mask.rects[0] = (mocap_v1_Rect){10, 20, 30, 40};
    p.body.control.command.set_mask.rects[1] = (mocap_v1_Rect){1, 2, 3, 4};
    assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_ACCEPTED);
    assert_int_equal(cmd.kind, MN_CMD_MASK_RECTS);
    assert_int_equal(cmd.u.rects.n, 2);
    assert_int_equal(cmd.u.rects.rects[0].x, 10);
    assert_int_equal(cmd.u.rects.rects[0].h, 40);
    assert_int_equal(cmd.u.rects.rects[1].w, 3);

    p = control_packet(5, mocap_v1_Control_set_mask_tag);
    p.body.control.command.set_mask.clear = true;
    assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_ACCEPTED);
    assert_int_equal(cmd.kind, MN_CMD_MASK_CLEAR);

    /* Another node's command is well-formed but not ours. */
    p = control_packet(6, mocap_v1_Control_stop_tag);
    assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_IGNORED);

    mocap_v1_Packet a = announce_packet(7001);
    a.body.hub_announce.epoch_ns = 1700000000000000000ull;
    a.body.hub_announce.rate_millihz = 100000;
    assert_int_equal(handle(ctl, &a, true, &cmd, &why), MN_CONTROL_ACCEPTED);
    assert_int_equal(cmd.kind, MN_CMD_ANNOUNCE);
    assert_int_equal(cmd.u.announce.port, 7001);
    assert_int_equal(cmd.u.announce.rate_millihz, 100000);
    mn_control_free(ctl);
}

/* A 100 x 60 cell mask in chunks of 256 bytes (2048 cells): chunk i of the image whose chunk 0
 * has sequence first_sequence, with the image's bytes from truth. */
enum { MASK_CX = 100, MASK_CY = 60, MASK_BYTES = (MASK_CX * MASK_CY + 7) / 8, MASK_CHUNK = 256,
       MASK_CHUNKS = (MASK_BYTES + MASK_CHUNK - 1) / MASK_CHUNK };

static mocap_v1_Packet mask_chunk_packet(const uint8_t *truth, uint32_t first_sequence, uint32_t i)
{
    mocap_v1_Packet p = control_packet(5, mocap_v1_Control_set_mask_tag);
    p.body.control.sequence = first_sequence + i;
    mocap_v1_SetMask *m = &p.body.control.command.set_mask;
    m->cell_px = 8;
    m->cells_x = MASK_CX;
    m->cells_y = MASK_CY;
    m->chunk_index = i;
    m->chunk_count = MASK_CHUNKS;
    m->bit_offset = i * MASK_CHUNK * 8;
    uint32_t n = MASK_BYTES - i * MASK_CHUNK < MASK_CHUNK ? MASK_BYTES - i * MASK_CHUNK : MASK_CHUNK;
    m->bits.size = (pb_size_t)n;
    memcpy(m->bits.bytes, truth + i * MASK_CHUNK, n);
    return p;
}

/* Chunks sent out of order assemble into the image. */
static void mask_image_chunks(void **state)
{
    (void)state;
    struct mn_control *ctl = mn_control_new(5);
    enum { CX = MASK_CX, CY = MASK_CY, BYTES = MASK_BYTES };
    uint8_t truth[BYTES];
    for (int i = 0; i < BYTES; i++)
        truth[i] = (uint8_t)(i * 37 + 11);
    const uint32_t count = MASK_CHUNKS;
    const uint32_t order[] = {2, 0, 1};
    assert_int_equal(count, 3);
    struct mn_command cmd;
    const char *why;
    for (uint32_t k = 0; k < count; k++) {
        mocap_v1_Packet p = mask_chunk_packet(truth, 100, order[k]);
        assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_ACCEPTED);
        assert_true(cmd.acknowledge);
        assert_int_equal(cmd.sequence, 100 + order[k]);
        if (k + 1 < count) {
            assert_int_equal(cmd.kind, MN_CMD_NONE);
        } else {
            assert_int_equal(cmd.kind, MN_CMD_MASK_BITS);
            assert_int_equal(cmd.u.bits.cell_px, 8);
            assert_int_equal(cmd.u.bits.cells_x, CX);
            assert_int_equal(cmd.u.bits.cells_y, CY);
            assert_memory_equal(cmd.u.bits.bits, truth, BYTES);
        }
    }
    mn_control_free(ctl);
}

/* A chunk sent again (its ack was lost) is stored once and ignored after; a chunk of an image
 * with another first sequence starts that image afresh, so stale chunks never mix into it. */
static void mask_chunks_again_and_new_image(void **state)
{
    (void)state;
    struct mn_control *ctl = mn_control_new(5);
    uint8_t first[MASK_BYTES], second[MASK_BYTES];
    for (int i = 0; i < MASK_BYTES; i++) {
        first[i] = (uint8_t)(i * 37 + 11);
        second[i] = (uint8_t)(i * 11 + 5);
    }
    struct mn_command cmd;
    const char *why;
    mocap_v1_Packet p = mask_chunk_packet(first, UINT32_MAX - 1, 1); /* wraps past 2^32 */
    assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_ACCEPTED);
    assert_int_equal(cmd.kind, MN_CMD_NONE);
    assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_IGNORED);
    assert_true(cmd.acknowledge);
    assert_int_equal(cmd.sequence, UINT32_MAX);
    assert_string_equal(why, "control: mask chunk already stored");
    p = mask_chunk_packet(first, UINT32_MAX - 1, 2);
    assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_ACCEPTED);
    assert_int_equal(cmd.sequence, 0);
    assert_int_equal(cmd.kind, MN_CMD_NONE);
    p = mask_chunk_packet(first, UINT32_MAX - 1, 0);
    assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_ACCEPTED);
    assert_int_equal(cmd.kind, MN_CMD_MASK_BITS);
    assert_memory_equal(cmd.u.bits.bits, first, MASK_BYTES);
    /* Applied: the same chunk again changes nothing. */
    assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_IGNORED);

    /* The next image reuses the shape; only its own chunks make it. */
    for (uint32_t i = 0; i < MASK_CHUNKS; i++) {
        p = mask_chunk_packet(second, 500, i);
        assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_ACCEPTED);
        assert_int_equal(cmd.kind, i + 1 < MASK_CHUNKS ? MN_CMD_NONE : MN_CMD_MASK_BITS);
    }
    assert_memory_equal(cmd.u.bits.bits, second, MASK_BYTES);
    mn_control_free(ctl);
}

/* Which datagrams the node answers with a ControlAck: every v1 Control for it (or for every
 * node), applied or refused; nothing it cannot read as one, nothing for another node. */
static void acknowledgements(void **state)
{
    (void)state;
    struct mn_control *ctl = mn_control_new(5);
    struct mn_command cmd;
    const char *why;

    mocap_v1_Packet p = control_packet(5, mocap_v1_Control_stop_tag);
    p.body.control.sequence = 7;
    assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_ACCEPTED);
    assert_true(cmd.acknowledge);
    assert_int_equal(cmd.sequence, 7);
    p.body.control.node_id = 0;
    assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_ACCEPTED);
    assert_true(cmd.acknowledge);

    /* Refused by the node's range, then by the wire's own rules: answered with the reason. */
    p = control_packet(5, mocap_v1_Control_set_threshold_tag);
    p.body.control.sequence = 8;
    p.body.control.command.set_threshold.value = 0;
    assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_REJECTED);
    assert_true(cmd.acknowledge);
    assert_int_equal(cmd.sequence, 8);
    assert_string_equal(why, "control: threshold outside 1..255");
    p = control_packet(0, mocap_v1_Control_preview_request_tag);
    p.body.control.sequence = 9;
    p.body.control.command.preview_request.downscale = 3;
    assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_REJECTED);
    assert_true(cmd.acknowledge);
    assert_int_equal(cmd.sequence, 9);
    assert_string_equal(why, "control: preview downscale must be 1, 2, 4 or 8");

    /* Not answered: another node's (good or bad), other versions, the announce socket,
     * garbage, and packets that are not a Control. */
    p.body.control.node_id = 6;
    assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_REJECTED);
    assert_false(cmd.acknowledge);
    p = control_packet(6, mocap_v1_Control_stop_tag);
    assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_IGNORED);
    assert_false(cmd.acknowledge);
    p = control_packet(5, mocap_v1_Control_stop_tag);
    p.version = 2;
    assert_int_equal(handle(ctl, &p, false, &cmd, &why), MN_CONTROL_REJECTED);
    assert_false(cmd.acknowledge);
    p.version = 1;
    assert_int_equal(handle(ctl, &p, true, &cmd, &why), MN_CONTROL_REJECTED);
    assert_false(cmd.acknowledge);
    const uint8_t garbage[] = {0x08, 0x01, 0x62, 0xff, 0xff};
    assert_int_equal(mn_control_handle(ctl, garbage, sizeof(garbage), false, &cmd, &why),
                     MN_CONTROL_REJECTED);
    assert_false(cmd.acknowledge);
    mocap_v1_Packet a = announce_packet(7001);
    assert_int_equal(handle(ctl, &a, true, &cmd, &why), MN_CONTROL_ACCEPTED);
    assert_false(cmd.acknowledge);
    mn_control_free(ctl);
}

static void expect_rejected(struct mn_control *ctl, const mocap_v1_Packet *p, bool announce,
                            const char *reason_part)
{
    struct mn_command cmd;
    const char *why;
    assert_int_equal(handle(ctl, p, announce, &cmd, &why), MN_CONTROL_REJECTED);
    assert_non_null(why);
    if (strstr(why, reason_part) == NULL)
        fail_msg("reason '%s' lacks '%s'", why, reason_part);
}

static void rejections(void **state)
{
    (void)state;
    struct mn_control *ctl = mn_control_new(5);
    struct mn_command cmd;
    const char *why = NULL;

    const uint8_t garbage[] = {0xff, 0xff, 0xff, 0x01, 0x02};
    assert_int_equal(mn_control_handle(ctl, garbage, sizeof(garbage), false, &cmd, &why),
                     MN_CONTROL_REJECTED);
    assert_non_null(why);
    assert_int_equal(mn_control_handle(ctl, garbage, 0, false, &cmd, &why), MN_CONTROL_REJECTED);
    static uint8_t big[1500];
    assert_int_equal(mn_control_handle(ctl, big, sizeof(big), false, &cmd, &why),
                     MN_CONTROL_REJECTED);

    mocap_v1_Packet p = control_packet(5, mocap_v1_Control_set_threshold_tag);
    p.body.control.command.set_threshold.value = 300; /* fine on the wire, not for Y8 */
    expect_rejected(ctl, &p, false, "threshold outside 1..255");
    p.version = 2;
    expect_rejected(ctl, &p, false, "version");

    p = control_packet(5, mocap_v1_Control_start_tag);
    p.body.control.command.start.rate_millihz = 5000000;
    expect_rejected(ctl, &p, false, "rate");
    p = control_packet(5, mocap_v1_Control_preview_request_tag);
    p.body.control.command.preview_request.downscale = 3;
    expect_rejected(ctl, &p, false, "downscale");
    p = control_packet(5, mocap_v1_Control_set_exposure_tag);
    expect_rejected(ctl, &p, false, "changes nothing");
    p = control_packet(5, mocap_v1_Control_set_picture_tag);
    expect_rejected(ctl, &p, false, "picture command changes nothing");
    p.body.control.command.set_picture.set_contrast = true;
    p.body.control.command.set_picture.contrast_pct = 101;
    expect_rejected(ctl, &p, false, "outside 0..100 %");
    p = control_packet(5, mocap_v1_Control_set_mask_tag);
    expect_rejected(ctl, &p, false, "empty mask");
    p = control_packet(5, mocap_v1_Control_set_mask_tag);
    p.body.control.command.set_mask.cell_px = 1;
    p.body.control.command.set_mask.cells_x = 2000;
    p.body.control.command.set_mask.cells_y = 2000;
    p.body.control.command.set_mask.chunk_count = 1;
    p.body.control.command.set_mask.bits.size = 4;
    expect_rejected(ctl, &p, false, "larger than the node accepts");
    p = control_packet(5, 0); /* no command */
    expect_rejected(ctl, &p, false, "no command");

    /* Right bytes, wrong socket or wrong kind. */
    p = control_packet(5, mocap_v1_Control_stop_tag);
    expect_rejected(ctl, &p, true, "not a HubAnnounce");
    mocap_v1_Packet a = announce_packet(7001);
    expect_rejected(ctl, &a, false, "not a Control");
    mocap_v1_Packet f = mocap_v1_Packet_init_zero;
    f.version = 1;
    f.which_body = mocap_v1_Packet_marker_frame_tag;
    f.body.marker_frame.node_id = 3;
    f.body.marker_frame.width = 10;
    f.body.marker_frame.height = 10;
    f.body.marker_frame.chunk_count = 1;
    expect_rejected(ctl, &f, false, "not a Control");
    mn_control_free(ctl);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(commands),
        cmocka_unit_test(mask_image_chunks),
        cmocka_unit_test(mask_chunks_again_and_new_image),
        cmocka_unit_test(acknowledgements),
        cmocka_unit_test(rejections),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
