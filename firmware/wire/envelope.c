/* Authenticated envelope, firmware side (see envelope.h). */
#include "wire/envelope.h"

#include <string.h>

#include <sodium.h>

#if MN_ENVELOPE_TAG != crypto_auth_hmacsha512256_BYTES || \
	MN_ENVELOPE_KEY_BYTES != crypto_auth_hmacsha512256_KEYBYTES
#error "envelope sizes must match libsodium's HMAC-SHA-512/256"
#endif

static int fail(const char **reason, const char *why)
{
	if (reason)
		*reason = why;
	return -1;
}

static uint32_t get_u32(const uint8_t *p)
{
	return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static uint64_t get_u64(const uint8_t *p)
{
	return (uint64_t)get_u32(p) | (uint64_t)get_u32(p + 4) << 32;
}

static void put_u32(uint8_t *p, uint32_t v)
{
	p[0] = (uint8_t)v;
	p[1] = (uint8_t)(v >> 8);
	p[2] = (uint8_t)(v >> 16);
	p[3] = (uint8_t)(v >> 24);
}

static void put_u64(uint8_t *p, uint64_t v)
{
	put_u32(p, (uint32_t)v);
	put_u32(p + 4, (uint32_t)(v >> 32));
}

int mn_envelope_init(void)
{
	return sodium_init() < 0 ? -1 : 0;
}

int mn_envelope_parse(const uint8_t *data, size_t len, struct mn_envelope *env,
		      const char **reason)
{
	if (len == 0 || data[0] != MN_ENVELOPE_MAGIC)
		return fail(reason, "not an authenticated datagram");
	if (len > MN_ENVELOPE_MAX_DATAGRAM)
		return fail(reason, "datagram larger than 1400 bytes");
	if (len < MN_ENVELOPE_OVERHEAD + 1)
		return fail(reason, "envelope too short");
	if (data[1] > MN_ENVELOPE_TO_NODE)
		return fail(reason, "envelope: unknown direction");
	if (data[2] == 0)
		return fail(reason, "envelope: key id 0");
	if (data[3] != 0)
		return fail(reason, "envelope: reserved byte not 0");
	env->direction = data[1];
	env->key_id = data[2];
	env->node_id = get_u32(data + 4);
	env->counter = get_u64(data + 8);
	if (env->node_id == 0)
		return fail(reason, "envelope: node id 0");
	if (env->counter == 0)
		return fail(reason, "envelope: counter 0");
	env->payload = data + MN_ENVELOPE_HEADER;
	env->payload_len = len - MN_ENVELOPE_OVERHEAD;
	return 0;
}

int mn_envelope_verify(const uint8_t *data, size_t len, const uint8_t key[MN_ENVELOPE_KEY_BYTES])
{
	if (len < MN_ENVELOPE_OVERHEAD)
		return -1;
	size_t body = len - MN_ENVELOPE_TAG;
	return crypto_auth_hmacsha512256_verify(data + body, data, body, key) == 0 ? 0 : -1;
}

int mn_envelope_seal(const struct mn_envelope *env, const uint8_t key[MN_ENVELOPE_KEY_BYTES],
		     uint8_t *out, size_t cap, size_t *size, const char **reason)
{
	if (env->payload_len == 0 || env->payload_len > MN_ENVELOPE_MAX_PAYLOAD)
		return fail(reason, "envelope: payload size out of range");
	if (cap < env->payload_len + MN_ENVELOPE_OVERHEAD)
		return fail(reason, "envelope: buffer too small");
	if (env->direction > MN_ENVELOPE_TO_NODE || env->key_id == 0 || env->node_id == 0 ||
	    env->counter == 0)
		return fail(reason, "envelope: header field out of range");
	if (env->payload != out + MN_ENVELOPE_HEADER)
		memmove(out + MN_ENVELOPE_HEADER, env->payload, env->payload_len);
	out[0] = MN_ENVELOPE_MAGIC;
	out[1] = env->direction;
	out[2] = env->key_id;
	out[3] = 0;
	put_u32(out + 4, env->node_id);
	put_u64(out + 8, env->counter);
	size_t body = MN_ENVELOPE_HEADER + env->payload_len;
	crypto_auth_hmacsha512256(out + body, out, body, key);
	*size = body + MN_ENVELOPE_TAG;
	return 0;
}

uint64_t mn_envelope_next_counter(uint64_t last, int64_t now_real_ns)
{
	uint64_t now = now_real_ns > 0 ? (uint64_t)now_real_ns : 0;
	return now > last ? now : last + 1;
}

int mn_replay_accept(struct mn_replay *w, uint64_t counter, int64_t now_real_ns,
		     const char **reason)
{
	int64_t now = now_real_ns;
	if (counter > (uint64_t)INT64_MAX)
		return fail(reason, "counter from the future (clocks apart?)");
	int64_t c = (int64_t)counter;
	if (c < now - MN_ENVELOPE_MAX_SKEW_NS)
		return fail(reason, "stale counter (replayed, or clocks apart)");
	if (c > now + MN_ENVELOPE_MAX_SKEW_NS)
		return fail(reason, "counter from the future (clocks apart?)");
	for (uint32_t i = 0; i < w->count; i++)
		if (w->seen[i] == counter)
			return fail(reason, "replayed counter");
	if (w->count < MN_REPLAY_SLOTS) {
		w->seen[w->count++] = counter;
	} else {
		if (counter <= w->seen[w->min_index])
			return fail(reason, "replayed counter (older than the window)");
		w->seen[w->min_index] = counter;
	}
	if (w->count == MN_REPLAY_SLOTS) {
		uint32_t m = 0;
		for (uint32_t i = 1; i < MN_REPLAY_SLOTS; i++)
			if (w->seen[i] < w->seen[m])
				m = i;
		w->min_index = m;
	}
	return 0;
}
