/* Golden wire vectors: packets built field by field in C (nanopb structs). Their encodings are
 * committed as NAME.bin, their meaning as NAME.txt (protobuf text format, written by the hub's
 * libprotobuf); tests on both sides check they agree in both directions. */
#ifndef MOCAP_GOLDEN_VECTORS_H
#define MOCAP_GOLDEN_VECTORS_H

#include "mocap.npb.h"

#ifdef __cplusplus
extern "C" {
#endif

#define GOLDEN_VECTOR_COUNT 17

/* Name of vector i (file stem), i < GOLDEN_VECTOR_COUNT. */
const char *golden_vector_name(int i);
/* Builds vector i into *packet. */
void golden_vector_build(int i, mocap_v1_Packet *packet);

#ifdef __cplusplus
}
#endif

#endif
