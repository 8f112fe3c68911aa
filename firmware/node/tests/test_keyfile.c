/* Key files: the format `mocap-hub keys` writes, every refusal with its line, the node's own
 * key first and a change-over's second key accepted. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <string.h>

#include "node/keyfile.h"

#define HEX_A "000102030405060708090a0b0c0d0e0f101112131415161718191a1b1c1d1e1f"
#define HEX_B "FFEEDDCCBBAA99887766554433221100ffeeddccbbaa99887766554433221100"

static int parse(const char *text, struct mn_keyfile *kf, char *err, size_t errlen)
{
	return mn_keyfile_parse(text, strlen(text), "k.key", kf, err, errlen);
}

static void test_good_files(void **state)
{
	(void)state;
	struct mn_keyfile kf;
	char err[256] = "";
	assert_int_equal(parse("# mocap wire key\nnode = 12\nkey = 2 " HEX_B "  # next\n"
			       "  key=1   " HEX_A "\r\n\n", &kf, err, sizeof err), 0);
	assert_int_equal(kf.node_id, 12);
	assert_int_equal(kf.n_keys, 2);
	assert_int_equal(kf.keys[0].id, 2);
	assert_int_equal(kf.keys[0].bytes[0], 0xff);
	assert_int_equal(kf.keys[0].bytes[31], 0x00);
	assert_int_equal(kf.keys[1].id, 1);
	assert_int_equal(kf.keys[1].bytes[31], 0x1f);
	assert_ptr_equal(mn_keyfile_find(&kf, 1), &kf.keys[1]);
	assert_null(mn_keyfile_find(&kf, 3));
	/* Without a final newline. */
	assert_int_equal(parse("node = 4095\nkey = 255 " HEX_A, &kf, err, sizeof err), 0);
	assert_int_equal(kf.keys[0].id, 255);
}

static void expect_refused(const char *text, const char *message)
{
	struct mn_keyfile kf;
	char err[256] = "";
	assert_int_equal(parse(text, &kf, err, sizeof err), -1);
	if (strstr(err, message) == NULL)
		fail_msg("'%s': got '%s', expected '%s'", text, err, message);
}

static void test_refusals_name_the_line(void **state)
{
	(void)state;
	expect_refused("", "k.key: no `node = ID` line");
	expect_refused("node = 3\n", "k.key: no `key = ID HEX` line");
	expect_refused("key = 1 " HEX_A "\n", "k.key: no `node = ID` line");
	expect_refused("node = 3\nnode = 3\n", "k.key:2: node given twice");
	expect_refused("node = 0\n", "k.key:1: node must be 1..4095");
	expect_refused("node = 4096\n", "k.key:1: node must be 1..4095");
	expect_refused("node = -3\n", "k.key:1: node must be 1..4095");
	expect_refused("node = 3\nkey = 0 " HEX_A "\n", "k.key:2: key must be `ID HEX`");
	expect_refused("node = 3\nkey = 256 " HEX_A "\n", "k.key:2: key must be `ID HEX`");
	expect_refused("node = 3\nkey = 1 " HEX_A "0\n", "k.key:2: key must be `ID HEX`");
	expect_refused("node = 3\nkey = 1 00\n", "k.key:2: key must be `ID HEX`");
	expect_refused("node = 3\nkey = 1 g00102030405060708090a0b0c0d0e0f101112131415161718191a1b1c1d1e1f\n",
		       "k.key:2: key must be `ID HEX`");
	expect_refused("node = 3\nkey = 1 " HEX_A "\nkey = 1 " HEX_B "\n",
		       "k.key:3: key id 1 given twice");
	expect_refused("node = 3\nkey = 1 " HEX_A "\nkey = 2 " HEX_B "\nkey = 3 " HEX_A "\n",
		       "k.key:4: more than 2 keys");
	expect_refused("node = 3\nsecret = 1\n", "k.key:2: unknown key 'secret'");
	expect_refused("node 3\n", "k.key:1: expected `key = value`");
	/* An embedded NUL ends the line's content: the rest of that line is not read as a value. */
	struct mn_keyfile kf;
	char err[256];
	const char text[] = "node = 3\0junk\nkey = 1 " HEX_A "\n";
	assert_int_equal(mn_keyfile_parse(text, sizeof text - 1, "k.key", &kf, err, sizeof err), 0);
	char big[MN_KEYFILE_MAX_BYTES + 2];
	memset(big, '#', sizeof big);
	assert_int_equal(mn_keyfile_parse(big, sizeof big, "k.key", &kf, err, sizeof err), -1);
	assert_non_null(strstr(err, "larger than 4096 bytes"));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_good_files),
		cmocka_unit_test(test_refusals_name_the_line),
	};
	return cmocka_run_group_tests(tests, NULL, NULL);
}
