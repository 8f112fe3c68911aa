/* The golden wire vectors (see vectors.h): one of every message kind, with edge values. */
#include "vectors.h"

#include <string.h>

#include "wire/wire.h"

static const char *const names[GOLDEN_VECTOR_COUNT] = {
	"marker_frame_small", "marker_frame_empty",  "marker_frame_chunk2of6", "node_status",
	"control_start",      "control_stop",        "control_threshold",      "control_exposure",
	"control_mask_rects", "control_mask_bits",   "control_preview",        "control_identify",
	"preview_chunk",      "hub_announce",        "control_ack_applied",    "control_ack_rejected",
	"control_ack_ignored", "control_picture",
};

const char *golden_vector_name(int i)
{
	return names[i];
}

static void marker_frame(mocap_v1_Packet *p, size_t n, uint32_t chunk)
{
	static struct mn_wire_marker m[256];
	mocap_v1_MarkerFrame h = mocap_v1_MarkerFrame_init_zero;
	size_t i;

	h.node_id = 12;
	h.frame_number = 987654321012ull;
	h.trigger_time_ns = 1763700000123456789ull;
	h.capture_time_ns = 1763700000124456789ull;
	h.send_time_ns = 1763700000125000000ull;
	h.exposure_us = 400;
	h.width = 1280;
	h.height = 800;
	h.flags = 2;
	for (i = 0; i < n; i++) {
		m[i].x = 0.5 + (double)i * 4.99609375;  /* exact multiples of 1/256 */
		m[i].y = 799.99609375 - (double)i * 3.125;
		m[i].area = (uint32_t)(3 + i * 7);
		m[i].peak = (uint16_t)(i % 2 ? 65535 : 255);
		m[i].mean = (uint16_t)(100 + i);
		m[i].flags = (uint8_t)(i % 8);
	}
	mn_wire_frame_chunk(&h, m, n, chunk, p, NULL);
}

static void control(mocap_v1_Packet *p, pb_size_t which)
{
	p->version = MN_WIRE_VERSION;
	p->which_body = mocap_v1_Packet_control_tag;
	p->body.control.node_id = 5;
	p->body.control.sequence = 4000000000u;
	p->body.control.which_command = which;
}

void golden_vector_build(int i, mocap_v1_Packet *p)
{
	*p = (mocap_v1_Packet)mocap_v1_Packet_init_zero;
	switch (i) {
	case 0: marker_frame(p, 3, 0); break;
	case 1: marker_frame(p, 0, 0); break;
	case 2: marker_frame(p, 256, 2); break;
	case 3: {
		mocap_v1_NodeStatus *s = &p->body.node_status;
		p->version = MN_WIRE_VERSION;
		p->which_body = mocap_v1_Packet_node_status_tag;
		s->node_id = 3;
		s->state = mocap_v1_NodeState_NODE_STATE_RUNNING;
		strcpy(s->firmware_version, "0.1.0-golden");
		s->uptime_ms = 86400000ull * 40;
		s->fps_milli = 239987;
		s->detect_time_us_mean = 812;
		s->detect_time_us_max = 2301;
		s->frames_captured = 829435904ull;
		s->frames_sent = 829435900ull;
		s->frames_dropped = 4;
		s->has_sync = true;
		s->sync.edge_jitter_ns = 1800;
		s->sync.unmatched_frames = 2;
		s->sync.missed_edges = 1;
		s->sync.spurious_edges = 7;
		s->has_temperature = true;
		s->temperature_mdeg = -5250;
		s->threshold = 90;
		s->exposure_us = 500;
		s->gain_milli = 2500;
		s->control_rejected = 11;
		s->camera_reopens = 1;
		s->width = 1280;
		s->height = 800;
		break;
	}
	case 4:
		control(p, mocap_v1_Control_start_tag);
		p->body.control.command.start.epoch_ns = 1763700000000000000ull;
		p->body.control.command.start.rate_millihz = 240000;
		break;
	case 5: control(p, mocap_v1_Control_stop_tag); break;
	case 6:
		control(p, mocap_v1_Control_set_threshold_tag);
		p->body.control.command.set_threshold.automatic = true;
		p->body.control.command.set_threshold.value = 0;
		break;
	case 7:
		control(p, mocap_v1_Control_set_exposure_tag);
		p->body.control.command.set_exposure.exposure_us = 350;
		p->body.control.command.set_exposure.gain_milli = 4000;
		break;
	case 8: {
		mocap_v1_SetMask *m = &p->body.control.command.set_mask;
		control(p, mocap_v1_Control_set_mask_tag);
		m->clear = true;
		m->rects_count = 2;
		m->rects[0] = (mocap_v1_Rect){.x = 0, .y = 0, .width = 40, .height = 800};
		m->rects[1] = (mocap_v1_Rect){.x = 600, .y = 10, .width = 17, .height = 9};
		break;
	}
	case 9: {
		mocap_v1_SetMask *m = &p->body.control.command.set_mask;
		size_t b;
		control(p, mocap_v1_Control_set_mask_tag);
		m->cell_px = 8;
		m->cells_x = 160;
		m->cells_y = 100;
		m->chunk_count = 3;
		m->chunk_index = 1;
		m->bit_offset = 896 * 8;
		m->bits.size = 896;
		for (b = 0; b < 896; b++)
			m->bits.bytes[b] = (uint8_t)(b * 37);
		break;
	}
	case 10:
		control(p, mocap_v1_Control_preview_request_tag);
		p->body.control.command.preview_request.mode = mocap_v1_PreviewMode_PREVIEW_MODE_THRESHOLDED;
		p->body.control.command.preview_request.downscale = 4;
		break;
	case 11:
		control(p, mocap_v1_Control_identify_tag);
		p->body.control.command.identify.duration_ms = 3000;
		break;
	case 12: {
		mocap_v1_PreviewChunk *c = &p->body.preview_chunk;
		size_t b;
		p->version = MN_WIRE_VERSION;
		p->which_body = mocap_v1_Packet_preview_chunk_tag;
		c->node_id = 9;
		c->frame_number = 4242;
		c->mode = mocap_v1_PreviewMode_PREVIEW_MODE_RAW;
		c->width = 320;
		c->height = 200;
		c->chunk_count = 54;
		c->chunk_index = 53;
		c->offset = 53 * 1200;
		c->data.size = 320 * 200 - 53 * 1200;
		for (b = 0; b < c->data.size; b++)
			c->data.bytes[b] = (uint8_t)(b ^ (b >> 3));
		break;
	}
	case 13:
		p->version = MN_WIRE_VERSION;
		p->which_body = mocap_v1_Packet_hub_announce_tag;
		p->body.hub_announce.port = 30001;
		p->body.hub_announce.epoch_ns = 1763700000000000000ull;
		p->body.hub_announce.rate_millihz = 120000;
		break;
	case 14:
		mn_wire_control_ack(5, 4000000000u, mocap_v1_ControlResult_CONTROL_RESULT_APPLIED, NULL, p);
		break;
	case 15:
		mn_wire_control_ack(5, 17, mocap_v1_ControlResult_CONTROL_RESULT_REJECTED,
				    "control: threshold outside 1..255", p);
		break;
	case 16:
		mn_wire_control_ack(4294967295u, 0, mocap_v1_ControlResult_CONTROL_RESULT_IGNORED,
				    "control: mask chunk already stored", p);
		break;
	case 17: /* brightness to the camera's minimum (0 % on the wire), contrast unchanged */
		control(p, mocap_v1_Control_set_picture_tag);
		p->body.control.command.set_picture.set_brightness = true;
		p->body.control.command.set_picture.brightness_pct = 0;
		p->body.control.command.set_picture.contrast_pct = 100;
		break;
	}
}

static const struct golden_envelope envelopes[GOLDEN_ENVELOPE_COUNT] = {
	{"envelope_marker_frame_small", 0, 0, 1, 7, 1700000000123456789ull},
	{"envelope_control_start", 4, 1, 1, 3, 1700000000987654321ull},
	{"envelope_hub_announce", 13, 1, 2, 4095, 0x0102030405060708ull},
};

const struct golden_envelope *golden_envelope_at(int i)
{
	return &envelopes[i];
}

void golden_envelope_key(uint8_t key[32])
{
	for (int i = 0; i < 32; i++)
		key[i] = (uint8_t)(3 * i);
}
