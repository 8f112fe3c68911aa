/* Wire protocol v1 rules and (de)serialization for the firmware (see wire.h). */
#include "wire/wire.h"

#include <math.h>
#include <string.h>
#include <pb_decode.h>
#include <pb_encode.h>

static const char *validate_marker_frame(const mocap_v1_MarkerFrame *f)
{
	uint32_t expected_chunks, remaining, expected_here;
	uint64_t max_x, max_y;
	pb_size_t i;

	if (f->node_id == 0)
		return "marker frame: node_id 0";
	if (f->width == 0 || f->height == 0 || f->width > MN_WIRE_MAX_IMAGE_SIDE ||
	    f->height > MN_WIRE_MAX_IMAGE_SIDE)
		return "marker frame: image size out of range";
	if (f->marker_total > MN_WIRE_MAX_MARKERS)
		return "marker frame: too many markers";
	expected_chunks = mn_wire_chunk_count(f->marker_total);
	if (f->chunk_count != expected_chunks)
		return "marker frame: chunk_count does not match marker_total";
	if (f->chunk_index >= f->chunk_count)
		return "marker frame: chunk_index out of range";
	if (f->first_marker != f->chunk_index * MN_WIRE_MARKERS_PER_CHUNK)
		return "marker frame: first_marker does not match chunk_index";
	remaining = f->marker_total - f->first_marker;
	expected_here = remaining < MN_WIRE_MARKERS_PER_CHUNK ? remaining : MN_WIRE_MARKERS_PER_CHUNK;
	if (f->markers_count != expected_here)
		return "marker frame: wrong number of markers in chunk";
	if (f->flags & ~MN_WIRE_FRAME_FLAGS_MASK)
		return "marker frame: unknown frame flags";
	max_x = (uint64_t)f->width * 256u;
	max_y = (uint64_t)f->height * 256u;
	for (i = 0; i < f->markers_count; i++) {
		const mocap_v1_Marker *m = &f->markers[i];
		if (m->x_q8 >= max_x || m->y_q8 >= max_y)
			return "marker: centroid outside the image";
		if (m->area == 0 || m->area > MN_WIRE_MAX_BLOB_AREA)
			return "marker: area out of range";
		if (m->peak > MN_WIRE_MAX_BRIGHTNESS || m->mean > m->peak)
			return "marker: brightness out of range";
		if (m->flags & ~MN_WIRE_MARKER_FLAGS_MASK)
			return "marker: unknown marker flags";
	}
	return NULL;
}

/* proto3 strings must be UTF-8; libprotobuf refuses anything else, so the firmware does too. */
static int is_utf8(const char *text)
{
	const unsigned char *p = (const unsigned char *)text;

	while (*p) {
		unsigned int n, i;
		uint32_t cp;
		if (*p < 0x80) {
			p++;
			continue;
		} else if ((*p & 0xe0) == 0xc0) {
			n = 1, cp = *p & 0x1f;
		} else if ((*p & 0xf0) == 0xe0) {
			n = 2, cp = *p & 0x0f;
		} else if ((*p & 0xf8) == 0xf0) {
			n = 3, cp = *p & 0x07;
		} else {
			return 0;
		}
		for (i = 1; i <= n; i++) {
			if ((p[i] & 0xc0) != 0x80)
				return 0;
			cp = (cp << 6) | (p[i] & 0x3f);
		}
		if ((n == 1 && cp < 0x80) || (n == 2 && cp < 0x800) || (n == 3 && cp < 0x10000) ||
		    cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff))
			return 0;
		p += n + 1;
	}
	return 1;
}

static const char *validate_node_status(const mocap_v1_NodeStatus *s)
{
	if (!is_utf8(s->firmware_version))
		return "node status: version is not UTF-8";
	if (s->node_id == 0)
		return "node status: node_id 0";
	if (s->state < _mocap_v1_NodeState_MIN || s->state > _mocap_v1_NodeState_MAX)
		return "node status: unknown state";
	return NULL;
}

static const char *validate_set_mask(const mocap_v1_SetMask *m)
{
	pb_size_t i;

	if (m->bits.size > 0) {
		uint64_t total_bits = (uint64_t)m->cells_x * m->cells_y;
		if (m->cell_px == 0 || m->cells_x == 0 || m->cells_y == 0)
			return "control: mask image without size";
		if (m->chunk_count == 0 || m->chunk_index >= m->chunk_count)
			return "control: mask chunk out of range";
		if (m->bit_offset % 8 != 0 ||
		    (uint64_t)m->bit_offset + 8ull * m->bits.size > total_bits + 7)
			return "control: mask bits outside the mask image";
	}
	for (i = 0; i < m->rects_count; i++) {
		const mocap_v1_Rect *r = &m->rects[i];
		if (r->width == 0 || r->height == 0 ||
		    (uint64_t)r->x + r->width > MN_WIRE_MAX_IMAGE_SIDE + 1ull ||
		    (uint64_t)r->y + r->height > MN_WIRE_MAX_IMAGE_SIDE + 1ull)
			return "control: mask rect out of range";
	}
	return NULL;
}

static const char *validate_control(const mocap_v1_Control *c)
{
	switch (c->which_command) {
	case mocap_v1_Control_start_tag:
		return c->command.start.rate_millihz == 0 ? "control: start with rate 0" : NULL;
	case mocap_v1_Control_set_threshold_tag:
		if (!c->command.set_threshold.automatic &&
		    c->command.set_threshold.value > MN_WIRE_MAX_BRIGHTNESS)
			return "control: threshold out of range";
		return NULL;
	case mocap_v1_Control_set_mask_tag:
		return validate_set_mask(&c->command.set_mask);
	case mocap_v1_Control_preview_request_tag: {
		uint32_t d = c->command.preview_request.downscale;
		mocap_v1_PreviewMode mode = c->command.preview_request.mode;
		if (d != 1 && d != 2 && d != 4 && d != 8)
			return "control: preview downscale must be 1, 2, 4 or 8";
		if (mode < _mocap_v1_PreviewMode_MIN || mode > _mocap_v1_PreviewMode_MAX)
			return "control: unknown preview mode";
		return NULL;
	}
	case mocap_v1_Control_set_picture_tag: {
		const mocap_v1_SetPicture *p = &c->command.set_picture;
		if (!p->set_brightness && !p->set_contrast)
			return "control: picture command changes nothing";
		if ((p->set_brightness && p->brightness_pct > 100) ||
		    (p->set_contrast && p->contrast_pct > 100))
			return "control: picture control outside 0..100 %";
		return NULL;
	}
	case mocap_v1_Control_stop_tag:
	case mocap_v1_Control_set_exposure_tag:
	case mocap_v1_Control_identify_tag:
		return NULL;
	default:
		return "control: no command";
	}
}

static const char *validate_control_ack(const mocap_v1_ControlAck *a)
{
	const char *end = memchr(a->reason, '\0', sizeof(a->reason));
	size_t len;

	if (a->node_id == 0)
		return "control ack: node_id 0";
	if (a->result < _mocap_v1_ControlResult_MIN || a->result > _mocap_v1_ControlResult_MAX)
		return "control ack: unknown result";
	if (end == NULL)
		return "control ack: reason too long";
	len = (size_t)(end - a->reason);
	if (!is_utf8(a->reason))
		return "control ack: reason is not UTF-8";
	if (a->result == mocap_v1_ControlResult_CONTROL_RESULT_APPLIED && len > 0)
		return "control ack: applied with a reason";
	if (a->result == mocap_v1_ControlResult_CONTROL_RESULT_REJECTED && len == 0)
		return "control ack: rejected without a reason";
	return NULL;
}

static const char *validate_preview_chunk(const mocap_v1_PreviewChunk *p)
{
	if (p->node_id == 0)
		return "preview: node_id 0";
	if (p->mode < _mocap_v1_PreviewMode_MIN || p->mode > _mocap_v1_PreviewMode_MAX)
		return "preview: unknown mode";
	if (p->width == 0 || p->height == 0 || p->width > MN_WIRE_MAX_IMAGE_SIDE ||
	    p->height > MN_WIRE_MAX_IMAGE_SIDE)
		return "preview: image size out of range";
	if (p->chunk_count == 0 || p->chunk_index >= p->chunk_count)
		return "preview: chunk out of range";
	if ((uint64_t)p->offset + p->data.size > (uint64_t)p->width * p->height)
		return "preview: data outside the image";
	return NULL;
}

const char *mn_wire_validate(const mocap_v1_Packet *packet)
{
	if (packet->version != MN_WIRE_VERSION)
		return "unsupported protocol version";
	switch (packet->which_body) {
	case mocap_v1_Packet_marker_frame_tag:
		return validate_marker_frame(&packet->body.marker_frame);
	case mocap_v1_Packet_node_status_tag:
		return validate_node_status(&packet->body.node_status);
	case mocap_v1_Packet_control_tag:
		return validate_control(&packet->body.control);
	case mocap_v1_Packet_preview_chunk_tag:
		return validate_preview_chunk(&packet->body.preview_chunk);
	case mocap_v1_Packet_hub_announce_tag:
		if (packet->body.hub_announce.port == 0 || packet->body.hub_announce.port > 65535)
			return "hub announce: port out of range";
		return NULL;
	case mocap_v1_Packet_control_ack_tag:
		return validate_control_ack(&packet->body.control_ack);
	default:
		return "packet without body";
	}
}

static int fail(const char **reason, const char *why)
{
	if (reason)
		*reason = why;
	return -1;
}

int mn_wire_parse(const uint8_t *data, size_t size, mocap_v1_Packet *packet, const char **reason)
{
	pb_istream_t stream;

	if (size == 0)
		return fail(reason, "empty datagram");
	if (size > MN_WIRE_MAX_PACKET)
		return fail(reason, "packet larger than 1352 bytes (1400 with its envelope)");
	stream = pb_istream_from_buffer(data, size);
	if (!pb_decode(&stream, mocap_v1_Packet_fields, packet))
		return fail(reason, "not a protocol buffer packet");
	return 0;
}

int mn_wire_decode(const uint8_t *data, size_t size, mocap_v1_Packet *packet, const char **reason)
{
	const char *problem;

	if (mn_wire_parse(data, size, packet, reason) < 0)
		return -1;
	problem = mn_wire_validate(packet);
	if (problem)
		return fail(reason, problem);
	return 0;
}

int mn_wire_encode(const mocap_v1_Packet *packet, uint8_t *out, size_t cap, size_t *size,
		   const char **reason)
{
	pb_ostream_t stream;
	const char *problem = mn_wire_validate(packet);

	if (problem)
		return fail(reason, problem);
	stream = pb_ostream_from_buffer(out, cap < MN_WIRE_MAX_PACKET ? cap : MN_WIRE_MAX_PACKET);
	if (!pb_encode(&stream, mocap_v1_Packet_fields, packet))
		return fail(reason, "packet does not fit the buffer or 1352 bytes");
	*size = stream.bytes_written;
	return 0;
}

void mn_wire_control_ack(uint32_t node_id, uint32_t sequence, mocap_v1_ControlResult result,
			 const char *reason, mocap_v1_Packet *packet)
{
	mocap_v1_ControlAck *a;
	size_t len = reason ? strlen(reason) : 0;

	*packet = (mocap_v1_Packet)mocap_v1_Packet_init_zero;
	packet->version = MN_WIRE_VERSION;
	packet->which_body = mocap_v1_Packet_control_ack_tag;
	a = &packet->body.control_ack;
	a->node_id = node_id;
	a->sequence = sequence;
	a->result = result;
	if (len > MN_WIRE_MAX_ACK_REASON) {
		len = MN_WIRE_MAX_ACK_REASON;
		while (len > 0 && ((unsigned char)reason[len] & 0xc0) == 0x80)
			len--; /* never cut a multi-byte character */
	}
	if (len > 0)
		memcpy(a->reason, reason, len);
	a->reason[len] = '\0';
}

uint32_t mn_wire_chunk_count(size_t n_markers)
{
	if (n_markers == 0)
		return 1;
	return (uint32_t)((n_markers + MN_WIRE_MARKERS_PER_CHUNK - 1) / MN_WIRE_MARKERS_PER_CHUNK);
}

uint32_t mn_wire_to_subpixel(double px)
{
	double q;

	if (!(px > 0.0))
		return 0;
	q = round(px * MN_WIRE_SUBPIXEL_SCALE);
	return q >= 4294967295.0 ? 4294967295u : (uint32_t)q;
}

double mn_wire_from_subpixel(uint32_t q)
{
	return q / MN_WIRE_SUBPIXEL_SCALE;
}

int mn_wire_frame_chunk(const mocap_v1_MarkerFrame *header, const struct mn_wire_marker *markers,
			size_t n_markers, uint32_t chunk_index, mocap_v1_Packet *packet,
			const char **reason)
{
	mocap_v1_MarkerFrame *f;
	size_t first, end, i;

	if (n_markers > MN_WIRE_MAX_MARKERS)
		return fail(reason, "marker frame: too many markers");
	if (chunk_index >= mn_wire_chunk_count(n_markers))
		return fail(reason, "marker frame: chunk_index out of range");
	*packet = (mocap_v1_Packet)mocap_v1_Packet_init_zero;
	packet->version = MN_WIRE_VERSION;
	packet->which_body = mocap_v1_Packet_marker_frame_tag;
	f = &packet->body.marker_frame;
	*f = *header;
	f->chunk_index = chunk_index;
	f->chunk_count = mn_wire_chunk_count(n_markers);
	f->marker_total = (uint32_t)n_markers;
	first = (size_t)chunk_index * MN_WIRE_MARKERS_PER_CHUNK;
	f->first_marker = (uint32_t)first;
	end = first + MN_WIRE_MARKERS_PER_CHUNK < n_markers ? first + MN_WIRE_MARKERS_PER_CHUNK : n_markers;
	f->markers_count = (pb_size_t)(end - first);
	for (i = first; i < end; i++) {
		mocap_v1_Marker *m = &f->markers[i - first];
		m->x_q8 = mn_wire_to_subpixel(markers[i].x);
		m->y_q8 = mn_wire_to_subpixel(markers[i].y);
		m->area = markers[i].area;
		m->peak = markers[i].peak;
		m->mean = markers[i].mean;
		m->flags = markers[i].flags;
	}
	return 0;
}
