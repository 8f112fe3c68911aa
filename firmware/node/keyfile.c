/* Key file parser and loader (see keyfile.h). */
#include "node/keyfile.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "common/fail.h"

static int hex_value(char c)
{
	if (c >= '0' && c <= '9')
		return c - '0';
	if (c >= 'a' && c <= 'f')
		return c - 'a' + 10;
	if (c >= 'A' && c <= 'F')
		return c - 'A' + 10;
	return -1;
}

static int is_space(char c)
{
	return c == ' ' || c == '\t' || c == '\r';
}

/* Unsigned decimal in [lo, hi] spanning s[0..n) exactly. */
static int parse_uint(const char *s, size_t n, unsigned long lo, unsigned long hi,
		      unsigned long *out)
{
	unsigned long v = 0;
	if (n == 0 || n > 10)
		return -1;
	for (size_t i = 0; i < n; i++) {
		if (s[i] < '0' || s[i] > '9')
			return -1;
		v = v * 10 + (unsigned long)(s[i] - '0');
	}
	if (v < lo || v > hi)
		return -1;
	*out = v;
	return 0;
}

/* One `key = ID HEX` value. */
static int parse_key(const char *v, size_t n, struct mn_key *key)
{
	size_t i = 0;
	while (i < n && !is_space(v[i]))
		i++;
	unsigned long id;
	if (parse_uint(v, i, 1, 255, &id) < 0)
		return -1;
	while (i < n && is_space(v[i]))
		i++;
	if (n - i != 2 * MN_ENVELOPE_KEY_BYTES)
		return -1;
	for (size_t b = 0; b < MN_ENVELOPE_KEY_BYTES; b++) {
		int hi = hex_value(v[i + 2 * b]), lo = hex_value(v[i + 2 * b + 1]);
		if (hi < 0 || lo < 0)
			return -1;
		key->bytes[b] = (uint8_t)(hi << 4 | lo);
	}
	key->id = (uint8_t)id;
	return 0;
}

int mn_keyfile_parse(const char *text, size_t len, const char *origin, struct mn_keyfile *kf,
		     char *err, size_t errlen)
{
	memset(kf, 0, sizeof(*kf));
	unsigned line = 0;
	size_t pos = 0;
	if (len > MN_KEYFILE_MAX_BYTES)
		return mn_fail(err, errlen, "%s: larger than %u bytes", origin, MN_KEYFILE_MAX_BYTES);
	while (pos < len) {
		line++;
		size_t end = pos;
		while (end < len && text[end] != '\n')
			end++;
		const char *s = text + pos;
		size_t n = end - pos;
		pos = end + 1;
		for (size_t i = 0; i < n; i++)
			if (s[i] == '#' || s[i] == '\0') /* a comment, or the end of a C string */
				n = i;
		while (n > 0 && is_space(s[0])) {
			s++;
			n--;
		}
		while (n > 0 && is_space(s[n - 1]))
			n--;
		if (n == 0)
			continue;
		const char *eq = memchr(s, '=', n);
		if (eq == NULL)
			return mn_fail(err, errlen, "%s:%u: expected `key = value`", origin, line);
		size_t kn = (size_t)(eq - s);
		while (kn > 0 && is_space(s[kn - 1]))
			kn--;
		const char *v = eq + 1;
		size_t vn = n - (size_t)(v - s);
		while (vn > 0 && is_space(v[0])) {
			v++;
			vn--;
		}
		if (kn == 4 && memcmp(s, "node", 4) == 0) {
			unsigned long id;
			if (kf->node_id != 0)
				return mn_fail(err, errlen, "%s:%u: node given twice", origin, line);
			if (parse_uint(v, vn, 1, 4095, &id) < 0)
				return mn_fail(err, errlen, "%s:%u: node must be 1..4095", origin, line);
			kf->node_id = (uint32_t)id;
		} else if (kn == 3 && memcmp(s, "key", 3) == 0) {
			struct mn_key key;
			if (kf->n_keys == MN_KEYFILE_MAX_KEYS)
				return mn_fail(err, errlen, "%s:%u: more than %d keys", origin, line,
					    MN_KEYFILE_MAX_KEYS);
			if (parse_key(v, vn, &key) < 0)
				return mn_fail(err, errlen,
					    "%s:%u: key must be `ID HEX` (id 1..255, 64 hex digits)",
					    origin, line);
			if (mn_keyfile_find(kf, key.id) != NULL)
				return mn_fail(err, errlen, "%s:%u: key id %u given twice", origin, line,
					    key.id);
			kf->keys[kf->n_keys++] = key;
		} else {
			return mn_fail(err, errlen, "%s:%u: unknown key '%.*s'", origin, line, (int)kn, s);
		}
	}
	if (kf->node_id == 0)
		return mn_fail(err, errlen, "%s: no `node = ID` line", origin);
	if (kf->n_keys == 0)
		return mn_fail(err, errlen, "%s: no `key = ID HEX` line", origin);
	return 0;
}

int mn_keyfile_load(const char *path, struct mn_keyfile *kf, char *err, size_t errlen)
{
	char text[MN_KEYFILE_MAX_BYTES + 1];
	int fd = open(path, O_RDONLY | O_CLOEXEC | O_NOCTTY);
	if (fd < 0) {
		int e = errno;
		snprintf(err, errlen, "key file %s: %s", path, strerror(e));
		errno = e;
		return -1;
	}
	struct stat st;
	if (fstat(fd, &st) < 0 || !S_ISREG(st.st_mode)) {
		close(fd);
		return mn_fail(err, errlen, "key file %s: not a regular file", path);
	}
	if (st.st_mode & (S_IRWXG | S_IRWXO)) {
		close(fd);
		return mn_fail(err, errlen, "key file %s: mode %03o lets others read it; chmod 600 it",
			    path, (unsigned)(st.st_mode & 0777));
	}
	size_t len = 0;
	for (;;) {
		ssize_t n = read(fd, text + len, sizeof(text) - len);
		if (n < 0 && errno == EINTR)
			continue;
		if (n < 0) {
			int e = errno;
			close(fd);
			snprintf(err, errlen, "key file %s: %s", path, strerror(e));
			errno = e;
			return -1;
		}
		if (n == 0)
			break;
		len += (size_t)n;
		if (len == sizeof(text))
			break;
	}
	close(fd);
	int rc = mn_keyfile_parse(text, len, path, kf, err, errlen);
	memset(text, 0, sizeof(text));
	return rc;
}

const struct mn_key *mn_keyfile_find(const struct mn_keyfile *kf, uint8_t id)
{
	for (size_t i = 0; i < kf->n_keys; i++)
		if (kf->keys[i].id == id)
			return &kf->keys[i];
	return NULL;
}
