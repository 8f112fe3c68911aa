/* The authenticated envelope around every hub<->node datagram, firmware side: pure sealing,
 * parsing and checking (libsodium's crypto_auth, HMAC-SHA-512/256), no I/O, no clock, no
 * allocation. hub/src/wire/envelope.h is the same layout in C++; tests/golden/envelope_* hold
 * vectors both sides must reproduce byte for byte.
 *
 * Layout (multi-byte fields little-endian):
 *   0   u8   MN_ENVELOPE_MAGIC (0xA1: authenticated envelope, version 1)
 *   1   u8   direction: 0 node -> hub, 1 hub -> node
 *   2   u8   key id, 1..255 (which of the node's keys made the tag; rotation)
 *   3   u8   reserved, 0
 *   4   u32  node id: the key's owner (the sender node, or the node addressed by the hub)
 *   8   u64  counter: per sender, strictly increasing (realtime ns, at least last + 1)
 *   16  ...  payload: one protocol-v1 Packet, 1..MN_ENVELOPE_MAX_PAYLOAD bytes
 *   end-32   tag: HMAC-SHA-512/256 under the node's key over every byte before it
 *
 * Error rule: int functions return 0 on success, -1 on failure with *reason (when not NULL)
 * pointing at a static string. */
#ifndef MN_WIRE_ENVELOPE_H
#define MN_WIRE_ENVELOPE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define MN_ENVELOPE_MAGIC 0xA1u
#define MN_ENVELOPE_HEADER 16u
#define MN_ENVELOPE_TAG 32u
#define MN_ENVELOPE_OVERHEAD (MN_ENVELOPE_HEADER + MN_ENVELOPE_TAG)
#define MN_ENVELOPE_MAX_DATAGRAM 1400u
#define MN_ENVELOPE_MAX_PAYLOAD (MN_ENVELOPE_MAX_DATAGRAM - MN_ENVELOPE_OVERHEAD)
#define MN_ENVELOPE_KEY_BYTES 32u
/* A counter further than this from the receiver's realtime clock is refused: node and hub
 * clocks agree within a millisecond under chrony, and a replay of recorded traffic is refused
 * once it is this old, even by a receiver that restarted and forgot its window. */
#define MN_ENVELOPE_MAX_SKEW_NS 2000000000ll

enum mn_envelope_direction {
	MN_ENVELOPE_TO_HUB = 0,
	MN_ENVELOPE_TO_NODE = 1,
};

struct mn_envelope {
	uint8_t direction;        /* enum mn_envelope_direction */
	uint8_t key_id;           /* 1..255 */
	uint32_t node_id;
	uint64_t counter;         /* > 0 */
	const uint8_t *payload;   /* parse: points into the datagram */
	size_t payload_len;
};

/* Initialises libsodium once (thread-safe in libsodium itself); -1 if it cannot start. */
int mn_envelope_init(void);

/* Reads the header of data[0..len) and points env->payload into it; checks the layout only
 * (magic, direction, reserved byte, key id, counter, sizes), never the tag. */
int mn_envelope_parse(const uint8_t *data, size_t len, struct mn_envelope *env,
		      const char **reason);

/* 0 when the tag of data[0..len) is right under key (constant time), -1 otherwise. */
int mn_envelope_verify(const uint8_t *data, size_t len, const uint8_t key[MN_ENVELOPE_KEY_BYTES]);

/* Writes header *env, env->payload and the tag into out[cap]; *size gets the datagram length.
 * env->payload may already sit at out + MN_ENVELOPE_HEADER (encoded in place). */
int mn_envelope_seal(const struct mn_envelope *env, const uint8_t key[MN_ENVELOPE_KEY_BYTES],
		     uint8_t *out, size_t cap, size_t *size, const char **reason);

/* The sender's next counter: now_real_ns, or last + 1 when the clock has not moved past it. */
uint64_t mn_envelope_next_counter(uint64_t last, int64_t now_real_ns);

/* Replay protection for one sender: the counters of the last MN_REPLAY_SLOTS datagrams accepted
 * (reordering up to that depth is tolerated); once full, anything at or below the smallest
 * remembered counter is refused, and so is a counter already seen or further than
 * MN_ENVELOPE_MAX_SKEW_NS from now. Zero-initialise before use. */
#define MN_REPLAY_SLOTS 64u
struct mn_replay {
	uint64_t seen[MN_REPLAY_SLOTS];
	uint32_t count;
	uint32_t min_index;       /* index of the smallest counter once full */
};

/* Call after the tag verified: 0 and remembers counter when it is new and fresh, -1 with the
 * reason ("replayed ...", "stale ...", "from the future ...") otherwise. */
int mn_replay_accept(struct mn_replay *w, uint64_t counter, int64_t now_real_ns,
		     const char **reason);

#ifdef __cplusplus
}
#endif

#endif
