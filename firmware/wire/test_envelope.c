/* The authenticated envelope, firmware side: sealing and parsing agree, every changed byte
 * breaks the tag, malformed headers are refused with a reason, and the replay window refuses
 * duplicates, counters older than its window and counters far from the clock. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <string.h>

#include "wire/envelope.h"

static const int64_t kNow = 1700000000000000000ll;

static void key_of(uint8_t seed, uint8_t key[MN_ENVELOPE_KEY_BYTES])
{
	for (unsigned i = 0; i < MN_ENVELOPE_KEY_BYTES; i++)
		key[i] = (uint8_t)(seed + 7 * i);
}

static size_t seal(uint8_t *out, size_t cap, const uint8_t *payload, size_t n, uint64_t counter,
		   const uint8_t key[MN_ENVELOPE_KEY_BYTES])
{
	struct mn_envelope env = {.direction = MN_ENVELOPE_TO_HUB, .key_id = 3, .node_id = 4095,
				  .counter = counter, .payload = payload, .payload_len = n};
	size_t size = 0;
	const char *why = NULL;
	assert_int_equal(mn_envelope_seal(&env, key, out, cap, &size, &why), 0);
	return size;
}

static void test_seal_parse_verify(void **state)
{
	(void)state;
	uint8_t key[MN_ENVELOPE_KEY_BYTES], other[MN_ENVELOPE_KEY_BYTES];
	uint8_t payload[MN_ENVELOPE_MAX_PAYLOAD], out[MN_ENVELOPE_MAX_DATAGRAM];
	assert_int_equal(mn_envelope_init(), 0);
	key_of(1, key);
	key_of(2, other);
	for (size_t i = 0; i < sizeof payload; i++)
		payload[i] = (uint8_t)(i * 31);
	/* The largest payload fills the datagram exactly. */
	size_t size = seal(out, sizeof out, payload, sizeof payload, 0x0102030405060708ull, key);
	assert_int_equal(size, MN_ENVELOPE_MAX_DATAGRAM);
	struct mn_envelope env;
	const char *why = NULL;
	assert_int_equal(mn_envelope_parse(out, size, &env, &why), 0);
	assert_int_equal(env.direction, MN_ENVELOPE_TO_HUB);
	assert_int_equal(env.key_id, 3);
	assert_int_equal(env.node_id, 4095);
	assert_true(env.counter == 0x0102030405060708ull);
	assert_int_equal(env.payload_len, sizeof payload);
	assert_memory_equal(env.payload, payload, sizeof payload);
	/* Little-endian header, as documented. */
	assert_int_equal(out[0], MN_ENVELOPE_MAGIC);
	assert_int_equal(out[4], 0xff);
	assert_int_equal(out[5], 0x0f);
	assert_int_equal(out[8], 0x08);
	assert_int_equal(out[15], 0x01);
	assert_int_equal(mn_envelope_verify(out, size, key), 0);
	assert_int_equal(mn_envelope_verify(out, size, other), -1);
	/* Every single flipped bit anywhere breaks the tag. */
	for (size_t i = 0; i < size; i++) {
		out[i] ^= 0x10;
		assert_int_equal(mn_envelope_verify(out, size, key), -1);
		out[i] ^= 0x10;
	}
	/* Cut or extended datagrams fail too. */
	assert_int_equal(mn_envelope_verify(out, size - 1, key), -1);
	/* Sealing in place (payload already at its offset) gives the same bytes. */
	uint8_t in_place[MN_ENVELOPE_MAX_DATAGRAM];
	memcpy(in_place + MN_ENVELOPE_HEADER, payload, 100);
	size_t a = seal(in_place, sizeof in_place, in_place + MN_ENVELOPE_HEADER, 100, 9, key);
	size_t b = seal(out, sizeof out, payload, 100, 9, key);
	assert_int_equal(a, b);
	assert_memory_equal(in_place, out, a);
}

static void test_refuses_bad_headers_and_sizes(void **state)
{
	(void)state;
	uint8_t key[MN_ENVELOPE_KEY_BYTES], out[MN_ENVELOPE_MAX_DATAGRAM + 8];
	uint8_t payload[64] = {0x08, 0x01};
	struct mn_envelope env;
	const char *why = NULL;
	key_of(5, key);
	size_t size = seal(out, sizeof out, payload, sizeof payload, 77, key);
	static const struct {
		size_t offset;
		uint8_t value;
		const char *reason;
	} bad[] = {
		{0, 0x08, "not an authenticated datagram"},
		{1, 2, "envelope: unknown direction"},
		{2, 0, "envelope: key id 0"},
		{3, 1, "envelope: reserved byte not 0"},
	};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		uint8_t copy[sizeof out];
		memcpy(copy, out, size);
		copy[bad[i].offset] = bad[i].value;
		assert_int_equal(mn_envelope_parse(copy, size, &env, &why), -1);
		assert_string_equal(why, bad[i].reason);
	}
	uint8_t zero_node[sizeof out];
	memcpy(zero_node, out, size);
	memset(zero_node + 4, 0, 4);
	assert_int_equal(mn_envelope_parse(zero_node, size, &env, &why), -1);
	assert_string_equal(why, "envelope: node id 0");
	memset(zero_node + 4, 1, 4);
	memset(zero_node + 8, 0, 8);
	assert_int_equal(mn_envelope_parse(zero_node, size, &env, &why), -1);
	assert_string_equal(why, "envelope: counter 0");
	assert_int_equal(mn_envelope_parse(out, MN_ENVELOPE_OVERHEAD, &env, &why), -1);
	assert_string_equal(why, "envelope too short");
	assert_int_equal(mn_envelope_parse(out, 0, &env, &why), -1);
	assert_int_equal(mn_envelope_parse(out, MN_ENVELOPE_MAX_DATAGRAM + 1, &env, &why), -1);
	assert_string_equal(why, "datagram larger than 1400 bytes");
	/* Sealing refuses what cannot be a valid envelope. */
	struct mn_envelope e = {.direction = 0, .key_id = 1, .node_id = 1, .counter = 1,
				.payload = payload, .payload_len = MN_ENVELOPE_MAX_PAYLOAD + 1};
	size_t n;
	uint8_t big[2048];
	assert_int_equal(mn_envelope_seal(&e, key, big, sizeof big, &n, &why), -1);
	e.payload_len = sizeof payload;
	assert_int_equal(mn_envelope_seal(&e, key, big, sizeof payload + 47, &n, &why), -1);
	e.key_id = 0;
	assert_int_equal(mn_envelope_seal(&e, key, big, sizeof big, &n, &why), -1);
}

static void test_counters_only_go_up(void **state)
{
	(void)state;
	uint64_t c = mn_envelope_next_counter(0, kNow);
	assert_true(c == (uint64_t)kNow);
	/* The same instant, or a clock set back: still strictly increasing. */
	assert_true(mn_envelope_next_counter(c, kNow) == c + 1);
	assert_true(mn_envelope_next_counter(c, kNow - 5000000000ll) == c + 1);
	assert_true(mn_envelope_next_counter(c, kNow + 10) == c + 10);
}

static void test_replay_window(void **state)
{
	(void)state;
	struct mn_replay w;
	const char *why = NULL;
	memset(&w, 0, sizeof w);
	/* In order, with some reordering inside the window. */
	for (uint64_t i = 1; i <= 200; i++) {
		uint64_t c = (uint64_t)kNow + 1000 * (i ^ 1u);
		assert_int_equal(mn_replay_accept(&w, c, kNow, &why), 0);
	}
	/* Every one of them again: refused (the newest 64 as seen, the rest as older). */
	unsigned refused = 0;
	for (uint64_t i = 1; i <= 200; i++)
		refused += mn_replay_accept(&w, (uint64_t)kNow + 1000 * (i ^ 1u), kNow, &why) < 0;
	assert_int_equal(refused, 200);
	/* A new counter just above the window's floor that was never seen is accepted. */
	assert_int_equal(mn_replay_accept(&w, (uint64_t)kNow + 1000 * 180 + 1, kNow, &why), 0);
	/* Far from the clock either way: refused whatever the window holds. */
	assert_int_equal(mn_replay_accept(&w, (uint64_t)(kNow - MN_ENVELOPE_MAX_SKEW_NS - 1), kNow, &why), -1);
	assert_string_equal(why, "stale counter (replayed, or clocks apart)");
	assert_int_equal(mn_replay_accept(&w, (uint64_t)(kNow + MN_ENVELOPE_MAX_SKEW_NS + 1), kNow, &why), -1);
	assert_string_equal(why, "counter from the future (clocks apart?)");
	assert_int_equal(mn_replay_accept(&w, UINT64_MAX, kNow, &why), -1);
	/* A fresh window (a restarted receiver) still refuses what is older than the skew. */
	struct mn_replay fresh;
	memset(&fresh, 0, sizeof fresh);
	assert_int_equal(mn_replay_accept(&fresh, (uint64_t)kNow - 3000000000ull, kNow, &why), -1);
	assert_int_equal(mn_replay_accept(&fresh, (uint64_t)kNow - 1000000000ull, kNow, &why), 0);
	assert_int_equal(mn_replay_accept(&fresh, (uint64_t)kNow - 1000000000ull, kNow, &why), -1);
	assert_string_equal(why, "replayed counter");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_seal_parse_verify),
		cmocka_unit_test(test_refuses_bad_headers_and_sizes),
		cmocka_unit_test(test_counters_only_go_up),
		cmocka_unit_test(test_replay_window),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
