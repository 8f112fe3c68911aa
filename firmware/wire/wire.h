/* Wire protocol v1, firmware side: pure encode/decode/validate of datagrams (nanopb; no I/O,
 * no allocation). Messages are the generated mocap_v1_* structs of proto/mocap.proto.
 *
 * Error rule: int functions return 0 on success, -1 on failure with *reason (when not NULL)
 * pointing at a static string that says which rule was broken.
 *
 * The rules are the hub's (hub/src/wire/limits.h) and must stay identical: datagrams of at
 * most 1400 bytes; 48 markers per chunk, chunk i carrying markers [48 i, min(48 (i+1), N));
 * centroids as 1/256 px fixed point (better than the 1/64 px the design asks for). */
#ifndef MN_WIRE_H
#define MN_WIRE_H

#include <stddef.h>
#include <stdint.h>

#include "mocap.npb.h"

#ifdef __cplusplus
extern "C" {
#endif

#define MN_WIRE_VERSION 1u
#define MN_WIRE_MAX_DATAGRAM 1400u
/* One Packet: the datagram less the authenticated envelope (wire/envelope.h), also when a
 * development rig sends it plain. */
#define MN_WIRE_MAX_PACKET 1352u
#define MN_WIRE_MARKERS_PER_CHUNK 48u
#define MN_WIRE_MAX_MARKERS 1024u
#define MN_WIRE_MAX_IMAGE_SIDE 8191u
#define MN_WIRE_MAX_BLOB_AREA ((1u << 21) - 1u)
#define MN_WIRE_MAX_BRIGHTNESS 65535u
#define MN_WIRE_MARKER_FLAGS_MASK 7u
#define MN_WIRE_FRAME_FLAGS_MASK 3u
#define MN_WIRE_SUBPIXEL_SCALE 256.0
/* ControlAck.reason: bytes of text (mocap.options max_size less nanopb's NUL). */
#define MN_WIRE_MAX_ACK_REASON 95u

/* One marker as the detector reports it, before fixed-point encoding. */
struct mn_wire_marker {
	double x, y;     /* px, pixel centres at integer coordinates */
	uint32_t area;
	uint16_t peak;
	uint16_t mean;
	uint8_t flags;   /* MARKER_FLAG_* bits */
};

/* NULL when the packet obeys every v1 rule, else the first broken rule. */
const char *mn_wire_validate(const mocap_v1_Packet *packet);

/* Parses one datagram into *packet without checking the v1 rules: for a receiver that needs a
 * field (a Control's sequence) of a packet it will still refuse; mn_wire_validate says why. */
int mn_wire_parse(const uint8_t *data, size_t size, mocap_v1_Packet *packet, const char **reason);

/* Parses and validates one datagram into *packet. */
int mn_wire_decode(const uint8_t *data, size_t size, mocap_v1_Packet *packet, const char **reason);

/* Validates and serializes *packet into out[cap]; *size gets the datagram length. */
int mn_wire_encode(const mocap_v1_Packet *packet, uint8_t *out, size_t cap, size_t *size,
		   const char **reason);

/* Number of chunks a frame of n markers travels in (an empty frame is one chunk). */
uint32_t mn_wire_chunk_count(size_t n_markers);

/* Builds chunk `chunk_index` of a frame: header fields from *header (its chunk fields and
 * markers are ignored), markers converted from markers[0..n_markers). */
int mn_wire_frame_chunk(const mocap_v1_MarkerFrame *header, const struct mn_wire_marker *markers,
			size_t n_markers, uint32_t chunk_index, mocap_v1_Packet *packet,
			const char **reason);

/* Builds the ControlAck of one Control: reason NULL or "" when applied, otherwise cut to
 * MN_WIRE_MAX_ACK_REASON bytes at a UTF-8 character boundary. */
void mn_wire_control_ack(uint32_t node_id, uint32_t sequence, mocap_v1_ControlResult result,
			 const char *reason, mocap_v1_Packet *packet);

uint32_t mn_wire_to_subpixel(double px);
double mn_wire_from_subpixel(uint32_t q);

#ifdef __cplusplus
}
#endif

#endif
