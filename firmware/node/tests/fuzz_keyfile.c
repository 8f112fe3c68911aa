/* libFuzzer target: arbitrary bytes as a node key file; a file either parses into a node id and
 * one or two distinct keys, or is refused with a message naming it. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "node/keyfile.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct mn_keyfile kf;
	char err[256];
	err[0] = '\0';
	if (mn_keyfile_parse((const char *)data, size, "fuzz.key", &kf, err, sizeof err) == 0) {
		if (kf.node_id < 1 || kf.node_id > 4095 || kf.n_keys < 1 ||
		    kf.n_keys > MN_KEYFILE_MAX_KEYS ||
		    (kf.n_keys == 2 && kf.keys[0].id == kf.keys[1].id) || kf.keys[0].id == 0)
			abort();
	} else if (strncmp(err, "fuzz.key", 8) != 0) {
		abort();
	}
	return 0;
}
