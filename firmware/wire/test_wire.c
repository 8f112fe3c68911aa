/* Firmware wire rules: chunking, limits, precision and rejection of bad datagrams. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <string.h>

#include "wire/wire.h"

static struct mn_wire_marker markers[256];

static mocap_v1_MarkerFrame header(void)
{
	mocap_v1_MarkerFrame h = mocap_v1_MarkerFrame_init_zero;
	h.node_id = 7;
	h.frame_number = 123456789;
	h.width = 1280;
	h.height = 800;
	return h;
}

static void fill_markers(size_t n)
{
	size_t i;
	for (i = 0; i < n; i++) {
		markers[i].x = 1279.99 - (double)i * 4.9;
		markers[i].y = 799.99 - (double)i * 3.1;
		markers[i].area = MN_WIRE_MAX_BLOB_AREA;
		markers[i].peak = MN_WIRE_MAX_BRIGHTNESS;
		markers[i].mean = MN_WIRE_MAX_BRIGHTNESS;
		markers[i].flags = MN_WIRE_MARKER_FLAGS_MASK;
	}
}

static void test_256_markers_chunk_and_reassemble(void **state)
{
	static mocap_v1_Packet packet, back;
	mocap_v1_MarkerFrame h = header();
	uint8_t buf[MN_WIRE_MAX_DATAGRAM];
	size_t size, seen = 0;
	uint32_t c, chunks;
	const char *reason = NULL;
	(void)state;

	h.trigger_time_ns = h.capture_time_ns = h.send_time_ns = UINT64_MAX;
	h.exposure_us = UINT32_MAX;
	h.flags = MN_WIRE_FRAME_FLAGS_MASK;
	fill_markers(256);
	chunks = mn_wire_chunk_count(256);
	assert_int_equal(chunks, 6);
	for (c = 0; c < chunks; c++) {
		pb_size_t i;
		assert_int_equal(mn_wire_frame_chunk(&h, markers, 256, c, &packet, &reason), 0);
		assert_int_equal(mn_wire_encode(&packet, buf, sizeof buf, &size, &reason), 0);
		assert_true(size <= MN_WIRE_MAX_DATAGRAM);
		assert_int_equal(mn_wire_decode(buf, size, &back, &reason), 0);
		assert_int_equal(back.body.marker_frame.first_marker, seen);
		for (i = 0; i < back.body.marker_frame.markers_count; i++) {
			const mocap_v1_Marker *m = &back.body.marker_frame.markers[i];
			assert_true(fabs(mn_wire_from_subpixel(m->x_q8) - markers[seen].x) <= 1.0 / 512);
			assert_true(fabs(mn_wire_from_subpixel(m->y_q8) - markers[seen].y) <= 1.0 / 512);
			seen++;
		}
	}
	assert_int_equal(seen, 256);
	assert_int_equal(mn_wire_frame_chunk(&h, markers, 256, chunks, &packet, &reason), -1);
}

static void test_subpixel_precision(void **state)
{
	double x;
	(void)state;
	for (x = 0.0; x < 4000.0; x += 0.173)
		assert_true(fabs(mn_wire_from_subpixel(mn_wire_to_subpixel(x)) - x) <= 1.0 / 512 + 1e-12);
	assert_int_equal(mn_wire_to_subpixel(-3.0), 0);
}

static void test_rejects_truncated_and_garbage(void **state)
{
	static mocap_v1_Packet packet, back;
	mocap_v1_MarkerFrame h = header();
	uint8_t buf[MN_WIRE_MAX_DATAGRAM], big[MN_WIRE_MAX_DATAGRAM + 1];
	const uint8_t garbage[] = {0xff, 0xff, 0xff, 0xff, 0x0f};
	size_t size, cut;
	const char *reason = NULL;
	(void)state;

	fill_markers(10);
	assert_int_equal(mn_wire_frame_chunk(&h, markers, 10, 0, &packet, &reason), 0);
	assert_int_equal(mn_wire_encode(&packet, buf, sizeof buf, &size, &reason), 0);
	for (cut = 1; cut < size; cut++)
		assert_int_equal(mn_wire_decode(buf, cut, &back, &reason), -1);
	assert_int_equal(mn_wire_decode(garbage, sizeof garbage, &back, &reason), -1);
	assert_non_null(reason);
	memset(big, 0, sizeof big);
	assert_int_equal(mn_wire_decode(big, sizeof big, &back, &reason), -1);
	assert_string_equal(reason, "packet larger than 1352 bytes (1400 with its envelope)");
	assert_int_equal(mn_wire_decode(big, 0, &back, &reason), -1);
}

static void test_rejects_wrong_version_and_bad_fields(void **state)
{
	static mocap_v1_Packet packet, back;
	mocap_v1_MarkerFrame h = header();
	uint8_t buf[MN_WIRE_MAX_DATAGRAM];
	size_t size;
	const char *reason = NULL;
	(void)state;

	fill_markers(3);
	assert_int_equal(mn_wire_frame_chunk(&h, markers, 3, 0, &packet, &reason), 0);
	packet.version = 2;
	assert_int_equal(mn_wire_encode(&packet, buf, sizeof buf, &size, &reason), -1);
	assert_string_equal(reason, "unsupported protocol version");
	packet.version = 1;
	packet.body.marker_frame.markers[0].x_q8 = 1280 * 256;
	assert_int_equal(mn_wire_encode(&packet, buf, sizeof buf, &size, &reason), -1);
	packet.body.marker_frame.markers[0].x_q8 = 5;
	packet.body.marker_frame.markers_count = 2;
	assert_string_equal(mn_wire_validate(&packet), "marker frame: wrong number of markers in chunk");
	packet.body.marker_frame.markers_count = 3;
	assert_null(mn_wire_validate(&packet));
	assert_int_equal(mn_wire_encode(&packet, buf, sizeof buf, &size, &reason), 0);
	assert_int_equal(mn_wire_decode(buf, size, &back, &reason), 0);
	assert_int_equal(mn_wire_encode(&packet, buf, 10, &size, &reason), -1);
}

static void test_control_rules(void **state)
{
	static mocap_v1_Packet packet;
	(void)state;
	packet = (mocap_v1_Packet)mocap_v1_Packet_init_zero;
	packet.version = 1;
	packet.which_body = mocap_v1_Packet_control_tag;
	assert_string_equal(mn_wire_validate(&packet), "control: no command");
	packet.body.control.which_command = mocap_v1_Control_preview_request_tag;
	packet.body.control.command.preview_request.downscale = 3;
	assert_non_null(mn_wire_validate(&packet));
	packet.body.control.command.preview_request.downscale = 8;
	assert_null(mn_wire_validate(&packet));
	packet.body.control.which_command = mocap_v1_Control_set_mask_tag;
	packet.body.control.command.set_mask.rects_count = 1;
	packet.body.control.command.set_mask.rects[0].x = 8000;
	packet.body.control.command.set_mask.rects[0].width = 500;
	packet.body.control.command.set_mask.rects[0].height = 5;
	assert_string_equal(mn_wire_validate(&packet), "control: mask rect out of range");
}

static void test_status_version_must_be_utf8(void **state)
{
	static mocap_v1_Packet packet;
	(void)state;
	packet = (mocap_v1_Packet)mocap_v1_Packet_init_zero;
	packet.version = 1;
	packet.which_body = mocap_v1_Packet_node_status_tag;
	packet.body.node_status.node_id = 1;
	strcpy(packet.body.node_status.firmware_version, "0.1 \xc3\xa9");
	assert_null(mn_wire_validate(&packet));
	strcpy(packet.body.node_status.firmware_version, "0.1 \xc3");
	assert_string_equal(mn_wire_validate(&packet), "node status: version is not UTF-8");
	strcpy(packet.body.node_status.firmware_version, "\xed\xa0\x80");
	assert_non_null(mn_wire_validate(&packet));
}

/* Acks: the result decides whether a reason is required, and long reasons are cut whole. */
static void test_control_ack_rules(void **state)
{
	static mocap_v1_Packet packet, back;
	uint8_t buf[MN_WIRE_MAX_DATAGRAM];
	char long_reason[200];
	size_t size, i;
	const char *reason;
	(void)state;

	mn_wire_control_ack(3, 4000000000u, mocap_v1_ControlResult_CONTROL_RESULT_APPLIED, NULL,
			    &packet);
	assert_int_equal(mn_wire_encode(&packet, buf, sizeof buf, &size, &reason), 0);
	assert_int_equal(mn_wire_decode(buf, size, &back, &reason), 0);
	assert_int_equal(back.which_body, mocap_v1_Packet_control_ack_tag);
	assert_int_equal(back.body.control_ack.node_id, 3);
	assert_int_equal(back.body.control_ack.sequence, 4000000000u);
	assert_string_equal(back.body.control_ack.reason, "");

	mn_wire_control_ack(3, 1, mocap_v1_ControlResult_CONTROL_RESULT_REJECTED, "", &packet);
	assert_string_equal(mn_wire_validate(&packet), "control ack: rejected without a reason");
	mn_wire_control_ack(3, 1, mocap_v1_ControlResult_CONTROL_RESULT_APPLIED, "why", &packet);
	assert_string_equal(mn_wire_validate(&packet), "control ack: applied with a reason");
	mn_wire_control_ack(3, 1, mocap_v1_ControlResult_CONTROL_RESULT_IGNORED, "", &packet);
	assert_null(mn_wire_validate(&packet));
	mn_wire_control_ack(0, 1, mocap_v1_ControlResult_CONTROL_RESULT_IGNORED, "x", &packet);
	assert_string_equal(mn_wire_validate(&packet), "control ack: node_id 0");
	mn_wire_control_ack(3, 1, (mocap_v1_ControlResult)3, "x", &packet);
	assert_string_equal(mn_wire_validate(&packet), "control ack: unknown result");
	mn_wire_control_ack(3, 1, mocap_v1_ControlResult_CONTROL_RESULT_REJECTED, "bad \xc3", &packet);
	assert_string_equal(mn_wire_validate(&packet), "control ack: reason is not UTF-8");

	/* 94 ASCII bytes then a two-byte character straddling the 95-byte limit: cut before it. */
	memset(long_reason, 'a', sizeof long_reason);
	long_reason[94] = (char)0xc3;
	long_reason[95] = (char)0xa9;
	long_reason[sizeof long_reason - 1] = '\0';
	mn_wire_control_ack(3, 1, mocap_v1_ControlResult_CONTROL_RESULT_REJECTED, long_reason,
			    &packet);
	assert_int_equal(strlen(packet.body.control_ack.reason), 94);
	assert_null(mn_wire_validate(&packet));
	long_reason[94] = 'a';
	long_reason[95] = 'a';
	mn_wire_control_ack(3, 1, mocap_v1_ControlResult_CONTROL_RESULT_REJECTED, long_reason,
			    &packet);
	assert_int_equal(strlen(packet.body.control_ack.reason), MN_WIRE_MAX_ACK_REASON);
	assert_int_equal(mn_wire_encode(&packet, buf, sizeof buf, &size, &reason), 0);
	assert_int_equal(mn_wire_decode(buf, size, &back, &reason), 0);
	for (i = 0; i < MN_WIRE_MAX_ACK_REASON; i++)
		assert_int_equal(back.body.control_ack.reason[i], 'a');
}

/* The parse step alone keeps a packet the rules refuse, so a node can still read its sequence. */
static void test_parse_without_rules(void **state)
{
	static mocap_v1_Packet packet;
	uint8_t buf[MN_WIRE_MAX_DATAGRAM];
	const uint8_t garbage[] = {0xff, 0xff, 0xff, 0xff, 0x0f};
	size_t size;
	const char *reason;
	(void)state;

	packet = (mocap_v1_Packet)mocap_v1_Packet_init_zero;
	packet.version = 1;
	packet.which_body = mocap_v1_Packet_control_tag;
	packet.body.control.node_id = 4;
	packet.body.control.sequence = 77;
	packet.body.control.which_command = mocap_v1_Control_preview_request_tag;
	packet.body.control.command.preview_request.downscale = 8;
	assert_int_equal(mn_wire_encode(&packet, buf, sizeof buf, &size, &reason), 0);
	buf[size - 1] = 3; /* downscale 8 -> 3: well-formed protobuf, against the rules */
	assert_int_equal(mn_wire_decode(buf, size, &packet, &reason), -1);
	assert_string_equal(reason, "control: preview downscale must be 1, 2, 4 or 8");
	packet = (mocap_v1_Packet)mocap_v1_Packet_init_zero;
	assert_int_equal(mn_wire_parse(buf, size, &packet, &reason), 0);
	assert_int_equal(packet.body.control.sequence, 77);
	assert_non_null(mn_wire_validate(&packet));
	assert_int_equal(mn_wire_parse(garbage, sizeof garbage, &packet, &reason), -1);
	assert_int_equal(mn_wire_parse(buf, 0, &packet, &reason), -1);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_256_markers_chunk_and_reassemble),
		cmocka_unit_test(test_subpixel_precision),
		cmocka_unit_test(test_rejects_truncated_and_garbage),
		cmocka_unit_test(test_rejects_wrong_version_and_bad_fields),
		cmocka_unit_test(test_control_rules),
		cmocka_unit_test(test_status_version_must_be_utf8),
		cmocka_unit_test(test_control_ack_rules),
		cmocka_unit_test(test_parse_without_rules),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
