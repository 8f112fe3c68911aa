/* mocap-wire-bench: what the authenticated wire costs one node per datagram, on this machine:
 * sealing and opening (HMAC-SHA-512/256, libsodium's crypto_auth, which the envelope uses) at
 * the sizes the node sends, beside ChaCha20-Poly1305 (IETF AEAD, authenticating the same bytes)
 * for comparison. Prints one line per size and primitive: ns per datagram and MB/s.
 * usage: mocap-wire-bench [--json] [ITERATIONS] */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <sodium.h>

#include "wire/envelope.h"

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static volatile unsigned sink;

int main(int argc, char **argv)
{
	int json = argc > 1 && strcmp(argv[1], "--json") == 0;
	long iterations = argc > 1 + json ? strtol(argv[1 + json], NULL, 10) : 20000;
	if (iterations < 10 || iterations > 100000000) {
		fprintf(stderr, "mocap-wire-bench: ITERATIONS must be 10..100000000\n");
		return 2;
	}
	if (mn_envelope_init() < 0) {
		fprintf(stderr, "mocap-wire-bench: libsodium cannot start\n");
		return 1;
	}
	/* A status (~80 B), a typical frame chunk (12 markers), a full 48-marker chunk, the largest. */
	static const size_t sizes[] = {80, 330, 1231, MN_ENVELOPE_MAX_PAYLOAD};
	uint8_t key[MN_ENVELOPE_KEY_BYTES], out[MN_ENVELOPE_MAX_DATAGRAM + 64];
	uint8_t payload[MN_ENVELOPE_MAX_PAYLOAD], nonce[crypto_aead_chacha20poly1305_IETF_NPUBBYTES];
	randombytes_buf(key, sizeof key);
	randombytes_buf(payload, sizeof payload);
	memset(nonce, 0, sizeof nonce);
	if (json)
		printf("[");
	for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
		size_t n = sizes[s], size = 0;
		const char *why;
		struct mn_envelope env = {.direction = 0, .key_id = 1, .node_id = 1, .counter = 1,
					  .payload = payload, .payload_len = n};
		double t0 = now_s();
		for (long i = 0; i < iterations; i++) {
			env.counter = (uint64_t)i + 1;
			mn_envelope_seal(&env, key, out, sizeof out, &size, &why);
			sink += out[size - 1];
		}
		double seal_ns = (now_s() - t0) * 1e9 / (double)iterations;
		t0 = now_s();
		for (long i = 0; i < iterations; i++) {
			struct mn_envelope parsed;
			sink += (unsigned)mn_envelope_parse(out, size, &parsed, &why);
			sink += (unsigned)mn_envelope_verify(out, size, key);
		}
		double open_ns = (now_s() - t0) * 1e9 / (double)iterations;
		/* The AEAD alternative: the same header + payload as associated data, no secrecy. */
		unsigned char tag[crypto_aead_chacha20poly1305_IETF_ABYTES], none[1] = {0};
		unsigned long long tag_len;
		t0 = now_s();
		for (long i = 0; i < iterations; i++) {
			memcpy(nonce, &i, sizeof i);
			crypto_aead_chacha20poly1305_ietf_encrypt_detached(none, tag, &tag_len, none, 0,
									    out, n + 16, NULL, nonce, key);
			sink += tag[0];
		}
		double aead_ns = (now_s() - t0) * 1e9 / (double)iterations;
		if (json)
			printf("%s{\"payload_bytes\": %zu, \"datagram_bytes\": %zu, \"seal_ns\": %.0f, "
			       "\"open_ns\": %.0f, \"chacha20poly1305_ns\": %.0f}",
			       s ? ", " : "", n, size, seal_ns, open_ns, aead_ns);
		else
			printf("payload %4zu B (datagram %4zu B): seal %6.0f ns, open %6.0f ns "
			       "(HMAC-SHA-512/256, %5.1f MB/s); ChaCha20-Poly1305 tag %6.0f ns\n",
			       n, size, seal_ns, open_ns, (double)size / seal_ns * 1e3, aead_ns);
	}
	if (json)
		printf("]\n");
	return 0;
}
