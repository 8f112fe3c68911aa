/* The node's end of the authenticated wire: seals what it sends under its own key and opens what
 * the hub sends, refusing anything forged, replayed, stale, meant for another direction, or
 * plain when a key is configured. Pure: the caller passes the realtime clock; no I/O, no
 * allocation. With insecure_dev_wire the datagrams travel as plain protocol-v1 packets (a
 * development setting only; the hub must run --insecure-dev-wire too).
 *
 * Replay protection: the node's counter is its CLOCK_REALTIME in ns at each send (at least the
 * previous counter + 1), so a restarted node continues above everything it sent before without
 * keeping state on disk, as long as its clock is not set back across the restart (chrony keeps
 * it within a millisecond of the hub's). The hub's counters are checked against a window of the
 * last 64 and against the node's clock (MN_ENVELOPE_MAX_SKEW_NS). */
#ifndef MN_NODE_AUTH_H
#define MN_NODE_AUTH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "node/keyfile.h"
#include "wire/envelope.h"

struct mn_auth {
	bool insecure;
	uint32_t node_id;
	struct mn_keyfile keys;      /* keys.keys[0] signs */
	uint64_t tx_counter;
	struct mn_replay rx_window;  /* the hub's counters */
};

enum mn_auth_result {
	MN_AUTH_OK = 0,
	MN_AUTH_OTHER_NODE = 1,  /* authentic layout, but for another node (a broadcast announce
	                            sealed for a neighbour): ignored, not an attack */
	MN_AUTH_REJECTED = -1,
};

/* keys NULL: insecure development mode. -1 when libsodium cannot start or the key file is for
 * another node (err says why). */
int mn_auth_init(struct mn_auth *a, uint32_t node_id, const struct mn_keyfile *keys, char *err,
		 size_t errlen);

/* Where the caller encodes the payload in its datagram buffer (16, or 0 when insecure), and the
 * largest payload. */
size_t mn_auth_payload_offset(const struct mn_auth *a);
size_t mn_auth_max_payload(const struct mn_auth *a);

/* Seals the payload of payload_len bytes already encoded at buf + mn_auth_payload_offset();
 * *size gets the datagram length. */
int mn_auth_seal(struct mn_auth *a, uint8_t *buf, size_t cap, size_t payload_len,
		 int64_t now_real_ns, size_t *size, const char **reason);

/* Opens one datagram from the hub; on MN_AUTH_OK, *payload and *payload_len are the Packet. */
enum mn_auth_result mn_auth_open(struct mn_auth *a, const uint8_t *data, size_t len,
				 int64_t now_real_ns, const uint8_t **payload, size_t *payload_len,
				 const char **reason);

#endif
