/* The node's end of the authenticated wire (see auth.h). */
#include "node/auth.h"

#include <stdio.h>
#include <string.h>

int mn_auth_init(struct mn_auth *a, uint32_t node_id, const struct mn_keyfile *keys, char *err,
		 size_t errlen)
{
	memset(a, 0, sizeof(*a));
	a->node_id = node_id;
	if (keys == NULL) {
		a->insecure = true;
		return 0;
	}
	if (keys->node_id != node_id || keys->n_keys == 0) {
		snprintf(err, errlen, "the key file is for node %u, this node is %u", keys->node_id,
			 node_id);
		return -1;
	}
	if (mn_envelope_init() < 0) {
		snprintf(err, errlen, "libsodium cannot start");
		return -1;
	}
	a->keys = *keys;
	return 0;
}

size_t mn_auth_payload_offset(const struct mn_auth *a)
{
	return a->insecure ? 0 : MN_ENVELOPE_HEADER;
}

size_t mn_auth_max_payload(const struct mn_auth *a)
{
	(void)a;
	/* Plain packets keep the same budget, so a development rig behaves like a real one. */
	return MN_ENVELOPE_MAX_PAYLOAD;
}

int mn_auth_seal(struct mn_auth *a, uint8_t *buf, size_t cap, size_t payload_len,
		 int64_t now_real_ns, size_t *size, const char **reason)
{
	if (a->insecure) {
		*size = payload_len;
		return 0;
	}
	a->tx_counter = mn_envelope_next_counter(a->tx_counter, now_real_ns);
	struct mn_envelope env = {
		.direction = MN_ENVELOPE_TO_HUB,
		.key_id = a->keys.keys[0].id,
		.node_id = a->node_id,
		.counter = a->tx_counter,
		.payload = buf + MN_ENVELOPE_HEADER,
		.payload_len = payload_len,
	};
	return mn_envelope_seal(&env, a->keys.keys[0].bytes, buf, cap, size, reason);
}

enum mn_auth_result mn_auth_open(struct mn_auth *a, const uint8_t *data, size_t len,
				 int64_t now_real_ns, const uint8_t **payload, size_t *payload_len,
				 const char **reason)
{
	bool enveloped = len > 0 && data[0] == MN_ENVELOPE_MAGIC;
	if (a->insecure) {
		if (enveloped) {
			*reason = "authenticated datagram, but this node runs insecure_dev_wire";
			return MN_AUTH_REJECTED;
		}
		*payload = data;
		*payload_len = len;
		return MN_AUTH_OK;
	}
	struct mn_envelope env;
	if (!enveloped) {
		*reason = "unauthenticated datagram (no envelope)";
		return MN_AUTH_REJECTED;
	}
	if (mn_envelope_parse(data, len, &env, reason) < 0)
		return MN_AUTH_REJECTED;
	if (env.direction != MN_ENVELOPE_TO_NODE) {
		*reason = "envelope: a node's datagram, not the hub's";
		return MN_AUTH_REJECTED;
	}
	if (env.node_id != a->node_id)
		return MN_AUTH_OTHER_NODE;
	const struct mn_key *key = mn_keyfile_find(&a->keys, env.key_id);
	if (key == NULL) {
		*reason = "envelope: unknown key id";
		return MN_AUTH_REJECTED;
	}
	if (mn_envelope_verify(data, len, key->bytes) < 0) {
		*reason = "envelope: bad tag (forged, or sealed with another key)";
		return MN_AUTH_REJECTED;
	}
	if (mn_replay_accept(&a->rx_window, env.counter, now_real_ns, reason) < 0)
		return MN_AUTH_REJECTED;
	*payload = env.payload;
	*payload_len = env.payload_len;
	return MN_AUTH_OK;
}
