/* Config module: good files and flags, and bad ones that must be refused with the file and line
 * (or the flag) named in the message. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "node/config.h"

static char *write_temp(const char *text)
{
    static char path[64];
    snprintf(path, sizeof(path), "/tmp/mn_test_config_XXXXXX");
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    size_t len = strlen(text);
    assert_int_equal(write(fd, text, len), (ssize_t)len);
    close(fd);
    return path;
}

static void good_file(void **state)
{
    (void)state;
    char *path = write_temp("# a node\n"
                            "id = 12\n"
                            "source = replay:/data/cam12   # comment after a value\n"
                            "sync = gpio:gpiochip0:17\n"
                            "hub = 10.0.0.2:7000\n"
                            "  threshold=90  \n"
                            "\n"
                            "auto_threshold = yes\n"
                            "morph_radius = 2\n"
                            "binary_centroid = yes\n"
                            "trigger_delay_us = -250\n"
                            "rate = 120\n"
                            "sim_missed = 0.25\n"
                            "log_level = debug\n"
                            "key_file = /etc/mocap/node.key\n"
                            "pixel_format = Y10\n"
                            "brightness = 60\n");
    struct mn_config cfg;
    char err[MN_CONFIG_ERR] = "";
    mn_config_defaults(&cfg);
    assert_int_equal(mn_config_load_file(&cfg, path, err, sizeof(err)), 0);
    unlink(path);
    assert_int_equal(cfg.node_id, 12);
    assert_int_equal(cfg.source_kind, MN_SOURCE_REPLAY);
    assert_string_equal(cfg.source_arg, "/data/cam12");
    assert_int_equal(cfg.sync_kind, MN_SYNC_GPIO);
    assert_string_equal(cfg.gpio_chip, "gpiochip0");
    assert_int_equal(cfg.gpio_line, 17);
    assert_string_equal(cfg.hub_host, "10.0.0.2");
    assert_int_equal(cfg.hub_port, 7000);
    assert_int_equal(cfg.threshold, 90);
    assert_string_equal(cfg.pixel_format, "Y10");
    assert_int_equal(cfg.brightness_pct, 60);
    assert_int_equal(cfg.contrast_pct, -1); /* unset: the camera's own */
    assert_true(cfg.auto_threshold);
    assert_int_equal(cfg.morph_radius, 2);
    assert_true(cfg.binary_centroid);
    assert_int_equal(cfg.trigger_delay_us, -250);
    assert_true(cfg.rate_hz == 120.0);
    assert_true(cfg.sim_missed == 0.25);
    assert_int_equal(cfg.log_level, MN_LOG_DEBUG);
    assert_string_equal(cfg.key_file, "/etc/mocap/node.key");
    assert_false(cfg.insecure_dev_wire);
    assert_int_equal(mn_config_check(&cfg, err, sizeof(err)), 0);
}

/* Each bad line must be refused, and the message must carry "file:line" and the reason. */
static void expect_bad_line(const char *text, unsigned line, const char *reason_part)
{
    char *path = write_temp(text);
    struct mn_config cfg;
    char err[MN_CONFIG_ERR] = "";
    mn_config_defaults(&cfg);
    assert_int_equal(mn_config_load_file(&cfg, path, err, sizeof(err)), -1);
    char where[128];
    snprintf(where, sizeof(where), "%s:%u:", path, line);
    unlink(path);
    if (strstr(err, where) == NULL || strstr(err, reason_part) == NULL)
        fail_msg("message '%s' lacks '%s' or '%s'", err, where, reason_part);
}

static void bad_files(void **state)
{
    (void)state;
    expect_bad_line("id = 1\nthreshold = 300\n", 2, "out of range 1..255");
    expect_bad_line("id = 0\n", 1, "out of range 1..4095");
    expect_bad_line("\n\nbogus_key = 3\n", 3, "unknown setting 'bogus_key'");
    expect_bad_line("id 5\n", 1, "expected 'key = value'");
    expect_bad_line("id =\n", 1, "both parts");
    expect_bad_line("id = 12abc\n", 1, "not an integer");
    expect_bad_line("rate = fast\n", 1, "not a number");
    expect_bad_line("rate = 5000\n", 1, "out of range");
    expect_bad_line("auto_threshold = maybe\n", 1, "yes/no");
    expect_bad_line("morph_radius = 9\n", 1, "out of range 0..8");
    expect_bad_line("source = webcam\n", 1, "v4l2:/dev/videoN");
    expect_bad_line("source = replay:\n", 1, "lacks its argument");
    expect_bad_line("source = libcamera:x\n", 1, "camera index");
    expect_bad_line("sync = gpio:gpiochip0\n", 1, "gpio:CHIP:LINE");
    expect_bad_line("sync = sim:0\n", 1, "0.1..1000");
    expect_bad_line("hub = 10.0.0.2\n", 1, "HOST:PORT");
    expect_bad_line("hub = 10.0.0.2:70000\n", 1, "HOST:PORT");
    expect_bad_line("log_level = loud\n", 1, "not error");
    expect_bad_line("trigger_delay_us = 99999999999999999999\n", 1, "not an integer");
    expect_bad_line("threshold = -5\n", 1, "out of range");
    expect_bad_line("pixel_format = NV12X\n", 1, "'NV12X' is not a fourcc name");
    expect_bad_line("pixel_format = nv12\n", 1, "1-4 of A-Z, 0-9");
    expect_bad_line("contrast = 101\n", 1, "out of range -1..100");

    /* A NUL byte (a binary file given by mistake). */
    char path[] = "/tmp/mn_test_config_XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    assert_int_equal(write(fd, "id = 1\nid\0= 2\n", 15), 15);
    close(fd);
    struct mn_config cfg;
    char err[MN_CONFIG_ERR] = "";
    mn_config_defaults(&cfg);
    assert_int_equal(mn_config_load_file(&cfg, path, err, sizeof(err)), -1);
    unlink(path);
    assert_non_null(strstr(err, ":2: NUL byte"));
}

static void missing_file(void **state)
{
    (void)state;
    struct mn_config cfg;
    char err[MN_CONFIG_ERR] = "";
    mn_config_defaults(&cfg);
    assert_int_equal(mn_config_load_file(&cfg, "/nonexistent/node.conf", err, sizeof(err)), -1);
    assert_non_null(strstr(err, "/nonexistent/node.conf: cannot open"));
}

static enum mn_config_args_result run_args(struct mn_config *cfg, char *err, size_t errlen, ...)
{
    char *argv[32];
    int argc = 0;
    argv[argc++] = "mocap-node";
    va_list ap;
    va_start(ap, errlen);
    char *a;
    while ((a = va_arg(ap, char *)) != NULL && argc < 31)
        argv[argc++] = a;
    va_end(ap);
    argv[argc] = NULL;
    return mn_config_from_args(cfg, argc, argv, err, errlen);
}

static void flags_override_file(void **state)
{
    (void)state;
    char *path = write_temp("id = 3\nthreshold = 77\nsource = v4l2:/dev/video2\n");
    char file[64];
    snprintf(file, sizeof(file), "%s", path);
    struct mn_config cfg;
    char err[MN_CONFIG_ERR] = "";
    /* The flag comes before --config on the command line and still wins. */
    assert_int_equal(run_args(&cfg, err, sizeof(err), "--threshold", "60", "--config", file,
                              "--sync", "sim:250", "--as-fast-as-possible", "--source",
                              "replay:/tmp/x", "--trigger-delay-us", "-40", "--frames", "10",
                              "--insecure-dev-wire", NULL),
                     MN_CONFIG_ARGS_RUN);
    unlink(file);
    assert_int_equal(cfg.node_id, 3);
    assert_int_equal(cfg.threshold, 60);
    assert_int_equal(cfg.sync_kind, MN_SYNC_SIM);
    assert_true(cfg.rate_hz == 250.0);
    assert_true(cfg.as_fast_as_possible);
    assert_int_equal(cfg.source_kind, MN_SOURCE_REPLAY);
    assert_int_equal(cfg.trigger_delay_us, -40);
    assert_int_equal(cfg.frames, 10);
}

static void bad_flags(void **state)
{
    (void)state;
    struct mn_config cfg;
    char err[MN_CONFIG_ERR] = "";
    assert_int_equal(run_args(&cfg, err, sizeof(err), "--id", "9999", NULL), MN_CONFIG_ARGS_ERROR);
    assert_non_null(strstr(err, "command line --id: id: 9999 is out of range"));
    assert_int_equal(run_args(&cfg, err, sizeof(err), "--nonsense", "1", NULL),
                     MN_CONFIG_ARGS_ERROR);
    assert_non_null(strstr(err, "unknown setting 'nonsense'"));
    assert_int_equal(run_args(&cfg, err, sizeof(err), "stray", NULL), MN_CONFIG_ARGS_ERROR);
    assert_non_null(strstr(err, "unexpected argument 'stray'"));
    assert_int_equal(run_args(&cfg, err, sizeof(err), "--threshold", NULL), MN_CONFIG_ARGS_ERROR);
    assert_non_null(strstr(err, "needs a value"));
    assert_int_equal(run_args(&cfg, err, sizeof(err), "--config", NULL), MN_CONFIG_ARGS_ERROR);
    assert_non_null(strstr(err, "--config needs a FILE"));
    /* Cross-setting checks run after all flags. */
    assert_int_equal(run_args(&cfg, err, sizeof(err), "--min-area", "50", "--max-area", "10", NULL),
                     MN_CONFIG_ARGS_ERROR);
    assert_non_null(strstr(err, "min_area 50 is larger than max_area 10"));
    assert_int_equal(run_args(&cfg, err, sizeof(err), "--as-fast-as-possible", NULL),
                     MN_CONFIG_ARGS_ERROR);
    assert_non_null(strstr(err, "only applies to a replay source"));
    assert_int_equal(run_args(&cfg, err, sizeof(err), "--width", "640", NULL),
                     MN_CONFIG_ARGS_ERROR);
    assert_non_null(strstr(err, "width and height must be given together"));
}

/* A node needs its wire key (or the explicit development setting); the key file must be its own
 * and private. */
static void wire_key_settings(void **state)
{
    (void)state;
    struct mn_config cfg;
    char err[MN_CONFIG_ERR] = "";
    assert_int_equal(run_args(&cfg, err, sizeof(err), "--id", "5", NULL), MN_CONFIG_ARGS_ERROR);
    assert_non_null(strstr(err, "no wire key: set key_file"));
    assert_int_equal(run_args(&cfg, err, sizeof(err), "--key-file", "/x.key", "--insecure-dev-wire",
                              NULL),
                     MN_CONFIG_ARGS_ERROR);
    assert_non_null(strstr(err, "exclude each other"));
    assert_int_equal(run_args(&cfg, err, sizeof(err), "--key-file", "/nonexistent/n.key", NULL),
                     MN_CONFIG_ARGS_ERROR);
    assert_non_null(strstr(err, "key file /nonexistent/n.key: No such file"));

    char *path = write_temp("node = 5\nkey = 1 "
                            "00112233445566778899aabbccddeeff00112233445566778899aabbccddeeff\n");
    char file[64];
    snprintf(file, sizeof(file), "%s", path);
    assert_int_equal(chmod(file, 0644), 0);
    assert_int_equal(run_args(&cfg, err, sizeof(err), "--id", "5", "--key-file", file, NULL),
                     MN_CONFIG_ARGS_ERROR);
    assert_non_null(strstr(err, "mode 644 lets others read it"));
    assert_int_equal(chmod(file, 0600), 0);
    assert_int_equal(run_args(&cfg, err, sizeof(err), "--id", "6", "--key-file", file, NULL),
                     MN_CONFIG_ARGS_ERROR);
    assert_non_null(strstr(err, "is for node 5, this node is 6"));
    assert_int_equal(run_args(&cfg, err, sizeof(err), "--id", "5", "--key-file", file, NULL),
                     MN_CONFIG_ARGS_RUN);
    unlink(file);
    assert_int_equal(cfg.keys.node_id, 5);
    assert_int_equal(cfg.keys.n_keys, 1);
    assert_int_equal(cfg.keys.keys[0].id, 1);
    assert_int_equal(cfg.keys.keys[0].bytes[31], 0xff);
    assert_int_equal(run_args(&cfg, err, sizeof(err), "--insecure-dev-wire", NULL),
                     MN_CONFIG_ARGS_RUN);
    assert_true(cfg.insecure_dev_wire);
    assert_int_equal(cfg.keys.n_keys, 0);
}

/* `--config /dev/zero` once read 4 GB and then started with the defaults: devices, FIFOs and
 * directories are refused before reading, oversized files by their size, and a stream is never
 * read past the bound. */
static void expect_refused(const char *path, const char *reason_part)
{
    struct mn_config cfg;
    char err[MN_CONFIG_ERR] = "";
    mn_config_defaults(&cfg);
    assert_int_equal(mn_config_load_file(&cfg, path, err, sizeof(err)), -1);
    if (strstr(err, path) == NULL || strstr(err, reason_part) == NULL)
        fail_msg("message '%s' lacks '%s' or '%s'", err, path, reason_part);
}

static void not_a_config_file(void **state)
{
    (void)state;
    expect_refused("/dev/zero", "not a regular file");
    expect_refused("/dev/null", "not a regular file");
    expect_refused("/tmp", "not a regular file");

    char fifo[] = "/tmp/mn_test_config_fifo_XXXXXX";
    int fd = mkstemp(fifo);
    assert_true(fd >= 0);
    close(fd);
    unlink(fifo);
    assert_int_equal(mkfifo(fifo, 0600), 0);
    expect_refused(fifo, "not a regular file"); /* returns at once: no writer is awaited */
    unlink(fifo);

    /* One byte over the bound, and a sparse file of 4 GB: refused by their size. */
    char *big = write_temp("id = 1\n");
    assert_int_equal(truncate(big, MN_CONFIG_MAX_BYTES + 1), 0);
    expect_refused(big, "larger than 65536");
    assert_int_equal(truncate(big, 4LL << 30), 0);
    expect_refused(big, "4294967296 bytes");
    /* Exactly the bound (comments and blank lines) still loads. */
    assert_int_equal(truncate(big, 0), 0);
    FILE *f = fopen(big, "w");
    assert_non_null(f);
    fputs("id = 9\n", f);
    for (long n = 7; n < MN_CONFIG_MAX_BYTES; n++)
        fputc(n % 64 == 63 ? '\n' : '#', f);
    fclose(f);
    struct mn_config cfg;
    char err[MN_CONFIG_ERR] = "";
    mn_config_defaults(&cfg);
    assert_int_equal(mn_config_load_file(&cfg, big, err, sizeof(err)), 0);
    assert_int_equal(cfg.node_id, 9);
    unlink(big);

    /* A stream (the fuzz target's way in) is read up to the bound and no further. */
    f = fopen("/dev/zero", "r");
    assert_non_null(f);
    mn_config_defaults(&cfg);
    assert_int_equal(mn_config_load_stream(&cfg, f, "zeros", err, sizeof(err)), -1);
    assert_true(ftell(f) <= MN_CONFIG_MAX_BYTES + 1 + BUFSIZ);
    fclose(f);
    assert_non_null(strstr(err, "zeros: larger than 65536 bytes"));

    /* A long line and a binary file are still refused with their line. */
    char *long_line = malloc(MN_CONFIG_MAX_LINE + 16);
    assert_non_null(long_line);
    memset(long_line, 'x', MN_CONFIG_MAX_LINE + 14);
    memcpy(long_line, "id = 1\n# ", 9);
    long_line[MN_CONFIG_MAX_LINE + 14] = '\n';
    long_line[MN_CONFIG_MAX_LINE + 15] = '\0';
    char *path = write_temp(long_line);
    free(long_line);
    expect_refused(path, ":2: line longer than 4096");
    unlink(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(good_file),         cmocka_unit_test(bad_files),
        cmocka_unit_test(missing_file),      cmocka_unit_test(flags_override_file),
        cmocka_unit_test(bad_flags),         cmocka_unit_test(wire_key_settings),
        cmocka_unit_test(not_a_config_file),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
