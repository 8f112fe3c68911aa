/* Golden wire vectors: packets built field by field in C (nanopb structs). Their encodings are
 * committed as NAME.bin, their meaning as NAME.txt (protobuf text format, written by the hub's
 * libprotobuf); tests on both sides check they agree in both directions. */
#ifndef MOCAP_GOLDEN_VECTORS_H
#define MOCAP_GOLDEN_VECTORS_H

#include "mocap.npb.h"

#ifdef __cplusplus
extern "C" {
#endif

#define GOLDEN_VECTOR_COUNT 18

/* Name of vector i (file stem), i < GOLDEN_VECTOR_COUNT. */
const char *golden_vector_name(int i);
/* Builds vector i into *packet. */
void golden_vector_build(int i, mocap_v1_Packet *packet);

/* Authenticated envelopes (wire/envelope.h) around some of the vectors above, committed as
 * envelope_NAME.bin and sealed under golden_envelope_key(); the files in reject_envelope/ must fail to
 * open under that key on both sides. */
#define GOLDEN_ENVELOPE_COUNT 3
struct golden_envelope {
	const char *name;      /* file stem */
	int packet_vector;     /* index of the payload's vector */
	uint8_t direction;     /* 0 node -> hub, 1 hub -> node */
	uint8_t key_id;
	uint32_t node_id;
	uint64_t counter;
};
const struct golden_envelope *golden_envelope_at(int i);
/* The fixed key of the golden envelopes (32 bytes: 0x00, 0x03, 0x06 ...); a test key only. */
void golden_envelope_key(uint8_t key[32]);

#ifdef __cplusplus
}
#endif

#endif
