/* libFuzzer target: the firmware's envelope parser, tag check and replay window on arbitrary
 * bytes. Whatever parses must lie within the datagram, and a datagram re-sealed under the fuzz
 * key from what was parsed must verify and parse back to the same header. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "wire/envelope.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	static const uint8_t key[MN_ENVELOPE_KEY_BYTES] = {1, 2, 3, 4, 5, 6, 7, 8};
	static struct mn_replay window;
	static int ready;
	struct mn_envelope env, back;
	uint8_t out[MN_ENVELOPE_MAX_DATAGRAM];
	size_t out_size;
	const char *reason;

	if (!ready) {
		if (mn_envelope_init() < 0)
			abort();
		ready = 1;
	}
	if (mn_envelope_parse(data, size, &env, &reason) < 0)
		return 0;
	if (env.payload < data || env.payload + env.payload_len + MN_ENVELOPE_TAG != data + size)
		abort();
	if (mn_envelope_verify(data, size, key) == 0)
		mn_replay_accept(&window, env.counter, 1700000000000000000ll, &reason);
	if (mn_envelope_seal(&env, key, out, sizeof out, &out_size, &reason) < 0 ||
	    out_size != size || mn_envelope_verify(out, out_size, key) < 0 ||
	    mn_envelope_parse(out, out_size, &back, &reason) < 0 || back.counter != env.counter ||
	    back.node_id != env.node_id || back.key_id != env.key_id ||
	    memcmp(back.payload, env.payload, env.payload_len) != 0)
		abort();
	return 0;
}
