/* The node's wire key file: which node it belongs to and one or two keys (the second only during
 * a key change-over). Written by `mocap-hub keys new|rotate|retire` (hub/src/wire/key_file.h is
 * the same format in C++):
 *     # comment
 *     node = 3
 *     key = 2 <64 hex digits>      the first key signs what this side sends
 *     key = 1 <64 hex digits>      every listed key is accepted
 * The file is a secret: it must not be readable or writable by group or others (mode 0600 or
 * 0400), and it is never part of the repository (tests generate theirs). Errors name the file
 * and line. Error rule: 0 on success, -1 with errno set and a one-line reason in err. */
#ifndef MN_NODE_KEYFILE_H
#define MN_NODE_KEYFILE_H

#include <stddef.h>
#include <stdint.h>

#include "wire/envelope.h"

#define MN_KEYFILE_MAX_KEYS 2
#define MN_KEYFILE_MAX_BYTES 4096

struct mn_key {
	uint8_t id;                             /* 1..255 */
	uint8_t bytes[MN_ENVELOPE_KEY_BYTES];
};

struct mn_keyfile {
	uint32_t node_id;
	struct mn_key keys[MN_KEYFILE_MAX_KEYS]; /* keys[0] signs */
	size_t n_keys;
};

/* Parses text[0..len) (not NUL-terminated); origin names it in messages ("node.key"). */
int mn_keyfile_parse(const char *text, size_t len, const char *origin, struct mn_keyfile *kf,
		     char *err, size_t errlen);

/* Reads and parses path, refusing a file that group or others may read or write, or that is
 * larger than MN_KEYFILE_MAX_BYTES. */
int mn_keyfile_load(const char *path, struct mn_keyfile *kf, char *err, size_t errlen);

/* The key with this id, or NULL. */
const struct mn_key *mn_keyfile_find(const struct mn_keyfile *kf, uint8_t id);

#endif
