/* The node's one config module: a `key = value` file and `--key value` command-line flags map
 * onto the same table of settings, each parsed and range-checked here; the rest of the node only
 * reads the typed values of struct mn_config. Errors name the file and line (or the flag).
 * Error rule (all of firmware/node): int functions return 0 on success and -1 on failure with
 * errno set; config functions also write a one-line reason into the caller's err buffer. */
#ifndef MN_NODE_CONFIG_H
#define MN_NODE_CONFIG_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "capture/capture.h"
#include "common/log.h"
#include "node/keyfile.h"
#include "sync/sync.h"

#define MN_CONFIG_STR 256
_Static_assert(MN_CONFIG_STR <= MN_CAPTURE_ARG_MAX, "a source argument must fit the capture sources");
#define MN_CONFIG_ERR 512
#define MN_CONFIG_MAX_BYTES 65536 /* a config file larger than this is refused unread */
#define MN_CONFIG_MAX_LINE 4096

/* A plain struct rather than an opaque type: it is only typed, already-checked values, read by
 * every other module, and tests build it directly. */
struct mn_config {
    uint32_t node_id;
    enum mn_source_kind source_kind;
    char source_arg[MN_CONFIG_STR]; /* device path, camera index or directory */
    enum mn_sync_kind sync_kind;
    char gpio_chip[MN_CONFIG_STR];
    uint32_t gpio_line;
    bool gpio_falling;             /* trigger on the falling edge instead of the rising one */
    char hub_host[MN_CONFIG_STR];  /* empty: find the hub by its HubAnnounce broadcast */
    uint16_t hub_port;
    uint16_t control_port;         /* 0: ephemeral (the hub answers to our source port) */
    uint16_t announce_port;        /* where HubAnnounce broadcasts arrive */
    char key_file[MN_CONFIG_STR];  /* this node's wire key (node/keyfile.h) */
    bool insecure_dev_wire;        /* no key: plain datagrams, development only */
    struct mn_keyfile keys;        /* loaded from key_file by mn_config_from_args */

    uint32_t width, height;        /* requested capture size; 0 = the source's default */
    uint32_t buffers;              /* V4L2 mmap buffers */
    char pixel_format[5];          /* V4L2 fourcc name ("NV12"); "" = the best the camera offers */
    uint32_t exposure_us;          /* 0 = leave the camera's setting */
    uint32_t gain_milli;           /* 0 = leave the camera's setting */
    int32_t brightness_pct;        /* percent of the camera's range; -1 = leave the camera's */
    int32_t contrast_pct;          /* percent of the camera's range; -1 = leave the camera's */
    uint32_t threshold;
    bool auto_threshold;
    uint32_t min_area, max_area;   /* blob area filter, pixels */
    uint32_t morph_radius;         /* per-blob opening + closing, (2r+1)^2 square; 0 = none */
    bool binary_centroid;          /* the seed's plain mean instead of the weighted centroid */

    double rate_hz;                /* trigger rate */
    int64_t epoch_ns;              /* CLOCK_REALTIME of global frame 0; 0 = start time */
    int32_t trigger_delay_us;      /* capture time stamp minus trigger edge */
    uint32_t pair_window_pct;      /* match window, percent of a period either side */
    uint32_t sim_jitter_us;        /* sim sync: edge jitter (standard deviation) */
    double sim_missed;             /* sim sync: probability an edge is lost */
    double sim_spurious;           /* sim sync: probability of an extra edge per period */
    uint32_t sim_seed;

    uint64_t frames;               /* stop after this many frames; 0 = unbounded */
    double duration_s;             /* stop after this long; 0 = unbounded */
    bool as_fast_as_possible;      /* replay: no pacing */
    bool replay_loop;              /* replay: start again at the end (long soak runs) */
    bool wait_for_start;           /* idle until the hub sends Start */

    uint32_t status_interval_ms;
    uint32_t reopen_min_ms, reopen_max_ms;
    uint32_t send_buffer_kb;
    char temperature_path[MN_CONFIG_STR];
    char identify_led[MN_CONFIG_STR]; /* LED brightness file to blink on Identify; empty: log */
    enum mn_log_level log_level;
};

/* Fills cfg with the documented defaults. */
void mn_config_defaults(struct mn_config *cfg);

/* Applies a `key = value` file on top of cfg. Only a regular file of at most
 * MN_CONFIG_MAX_BYTES is read (`--config /dev/zero`, a FIFO or a directory is refused before
 * reading a byte); lines are at most MN_CONFIG_MAX_LINE characters and hold no NUL. */
int mn_config_load_file(struct mn_config *cfg, const char *path, char *err, size_t errlen);

/* The same over an open stream, read up to MN_CONFIG_MAX_BYTES (more is refused: the stream
 * is not read further); path names it in messages. The caller closes f. */
int mn_config_load_stream(struct mn_config *cfg, FILE *f, const char *path, char *err,
                          size_t errlen);

/* The same over len bytes of text in memory (not NUL-terminated). */
int mn_config_load_text(struct mn_config *cfg, const char *text, size_t len, const char *path,
                        char *err, size_t errlen);

/* Applies one setting; origin names the place for error messages ("node.conf:12"). */
int mn_config_set(struct mn_config *cfg, const char *key, const char *value, const char *origin,
                  char *err, size_t errlen);

enum mn_config_args_result {
    MN_CONFIG_ARGS_RUN,   /* cfg is complete: run the node */
    MN_CONFIG_ARGS_EXIT,  /* --help or --version was printed: exit 0 */
    MN_CONFIG_ARGS_ERROR, /* err says why: exit non-zero */
};

/* Defaults, then --config FILE (wherever it appears), then every other flag in order, then
 * mn_config_check. Flags are the keys with '-' for '_' ("--trigger-delay-us 100"); booleans may
 * omit their value. */
enum mn_config_args_result mn_config_from_args(struct mn_config *cfg, int argc, char **argv,
                                               char *err, size_t errlen);

/* Loads cfg->key_file into cfg->keys (nothing with insecure_dev_wire) and checks it belongs to
 * cfg->node_id. mn_config_from_args calls it; tests that build a config directly may too. */
int mn_config_load_keys(struct mn_config *cfg, char *err, size_t errlen);

/* Cross-setting checks (a gpio sync needs a rate, sizes fit the source, a key or the explicit
 * development setting ...). */
int mn_config_check(const struct mn_config *cfg, char *err, size_t errlen);

/* Writes the flag/key reference (name, range, meaning) to f. */
void mn_config_print_help(FILE *f);

#endif
