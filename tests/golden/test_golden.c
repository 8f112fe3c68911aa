/* Golden vectors, firmware side: the C encoder reproduces every committed datagram byte for
 * byte, decoding then re-encoding is the identity, and every reject vector is refused.
 * Usage: test_golden GOLDEN_DIR */
#include <dirent.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdio.h>
#include <string.h>

#include "vectors.h"
#include "wire/envelope.h"
#include "wire/wire.h"

static const char *golden_dir;

static size_t read_file(const char *dir, const char *name, const char *ext, uint8_t *buf, size_t cap)
{
	char path[1024];
	FILE *f;
	size_t n;

	if (snprintf(path, sizeof path, "%s/%s%s", dir, name, ext) >= (int)sizeof path)
		fail_msg("path too long: %s/%s%s", dir, name, ext);
	f = fopen(path, "rb");
	if (!f)
		fail_msg("cannot open %s", path);
	n = fread(buf, 1, cap, f);
	fclose(f);
	return n;
}

static void test_c_encoding_matches_golden_bytes(void **state)
{
	static mocap_v1_Packet packet, back;
	uint8_t golden[2048], mine[MN_WIRE_MAX_DATAGRAM], again[MN_WIRE_MAX_DATAGRAM];
	size_t golden_size, mine_size, again_size;
	const char *reason = NULL;
	int i;
	(void)state;

	for (i = 0; i < GOLDEN_VECTOR_COUNT; i++) {
		golden_size = read_file(golden_dir, golden_vector_name(i), ".bin", golden, sizeof golden);
		golden_vector_build(i, &packet);
		assert_int_equal(mn_wire_encode(&packet, mine, sizeof mine, &mine_size, &reason), 0);
		assert_int_equal(mine_size, golden_size);
		assert_memory_equal(mine, golden, golden_size);
		assert_int_equal(mn_wire_decode(golden, golden_size, &back, &reason), 0);
		assert_int_equal(mn_wire_encode(&back, again, sizeof again, &again_size, &reason), 0);
		assert_int_equal(again_size, golden_size);
		assert_memory_equal(again, golden, golden_size);
	}
}

/* Every .bin file in reject/ is a reject vector: a new file is tested without a code change. */
static void test_reject_vectors_are_refused(void **state)
{
	static mocap_v1_Packet packet;
	uint8_t buf[2048];
	char dir[1024];
	DIR *d;
	struct dirent *entry;
	size_t n, len, count = 0;
	int dir_len;
	(void)state;

	dir_len = snprintf(dir, sizeof dir, "%s/reject", golden_dir);
	assert_true(dir_len > 0 && dir_len < (int)sizeof dir);
	d = opendir(dir);
	if (!d)
		fail_msg("cannot open %s", dir);
	while ((entry = readdir(d)) != NULL) {
		const char *reason = NULL;
		len = strlen(entry->d_name);
		if (len <= 4 || strcmp(entry->d_name + len - 4, ".bin") != 0)
			continue;
		n = read_file(dir, entry->d_name, "", buf, sizeof buf);
		if (mn_wire_decode(buf, n, &packet, &reason) == 0)
			fail_msg("accepted reject vector %s", entry->d_name);
		assert_non_null(reason);
		count++;
	}
	closedir(d);
	if (count == 0)
		fail_msg("no reject vectors in %s", dir);
}

/* The firmware seals every golden envelope byte for byte, opens the committed bytes under the
 * golden key, and finds inside exactly the committed packet. */
static void test_envelopes_match_golden_bytes(void **state)
{
	static mocap_v1_Packet packet;
	uint8_t key[32], golden[2048], payload[MN_WIRE_MAX_PACKET], plain[2048], mine[MN_ENVELOPE_MAX_DATAGRAM];
	size_t golden_size, payload_size, plain_size, mine_size;
	const char *reason = NULL;
	(void)state;

	assert_int_equal(mn_envelope_init(), 0);
	golden_envelope_key(key);
	for (int i = 0; i < GOLDEN_ENVELOPE_COUNT; i++) {
		const struct golden_envelope *g = golden_envelope_at(i);
		golden_size = read_file(golden_dir, g->name, ".bin", golden, sizeof golden);
		golden_vector_build(g->packet_vector, &packet);
		assert_int_equal(mn_wire_encode(&packet, payload, sizeof payload, &payload_size, &reason), 0);
		struct mn_envelope env = {.direction = g->direction, .key_id = g->key_id, .node_id = g->node_id,
					  .counter = g->counter, .payload = payload, .payload_len = payload_size};
		assert_int_equal(mn_envelope_seal(&env, key, mine, sizeof mine, &mine_size, &reason), 0);
		assert_int_equal(mine_size, golden_size);
		assert_memory_equal(mine, golden, golden_size);
		struct mn_envelope back;
		assert_int_equal(mn_envelope_parse(golden, golden_size, &back, &reason), 0);
		assert_int_equal(mn_envelope_verify(golden, golden_size, key), 0);
		assert_true(back.counter == g->counter && back.node_id == g->node_id && back.key_id == g->key_id);
		plain_size = read_file(golden_dir, golden_vector_name(g->packet_vector), ".bin", plain, sizeof plain);
		assert_int_equal(back.payload_len, plain_size);
		assert_memory_equal(back.payload, plain, plain_size);
	}
}

/* Every .bin file in reject_envelope/ fails to open under the golden key. */
static void test_envelope_reject_vectors_are_refused(void **state)
{
	uint8_t key[32], buf[2048];
	char dir[1024];
	size_t count = 0;
	(void)state;

	golden_envelope_key(key);
	snprintf(dir, sizeof dir, "%s/reject_envelope", golden_dir);
	DIR *d = opendir(dir);
	if (!d)
		fail_msg("cannot open %s", dir);
	struct dirent *entry;
	while ((entry = readdir(d)) != NULL) {
		size_t len = strlen(entry->d_name);
		if (len <= 4 || strcmp(entry->d_name + len - 4, ".bin") != 0)
			continue;
		size_t n = read_file(dir, entry->d_name, "", buf, sizeof buf);
		struct mn_envelope env;
		const char *reason = NULL;
		if (mn_envelope_parse(buf, n, &env, &reason) == 0 && mn_envelope_verify(buf, n, key) == 0)
			fail_msg("opened reject vector %s", entry->d_name);
		count++;
	}
	closedir(d);
	if (count == 0)
		fail_msg("no reject vectors in %s", dir);
}

int main(int argc, char **argv)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_c_encoding_matches_golden_bytes),
		cmocka_unit_test(test_reject_vectors_are_refused),
		cmocka_unit_test(test_envelopes_match_golden_bytes),
		cmocka_unit_test(test_envelope_reject_vectors_are_refused),
	};
	if (argc != 2) {
		fprintf(stderr, "usage: test_golden GOLDEN_DIR\n");
		return 2;
	}
	golden_dir = argv[1];
	return cmocka_run_group_tests(tests, NULL, NULL);
}
