/* Settings table, parsers and range checks for struct mn_config (see config.h). One table row
 * per key: the file parser and the command-line parser both go through mn_config_set. */
#include "node/config.h"

#include <ctype.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "common/fail.h"
#include "node/version.h"

enum setting_type { T_U32, T_U16, T_I32, T_I64, T_U64, T_DOUBLE, T_BOOL, T_STRING, T_CUSTOM };

struct setting {
    const char *key;
    enum setting_type type;
    size_t offset;
    double min, max;
    int (*custom)(struct mn_config *cfg, const char *value, char *why, size_t whylen);
    const char *help;
};

static int set_source(struct mn_config *cfg, const char *value, char *why, size_t whylen);
static int set_sync(struct mn_config *cfg, const char *value, char *why, size_t whylen);
static int set_hub(struct mn_config *cfg, const char *value, char *why, size_t whylen);
static int set_log_level(struct mn_config *cfg, const char *value, char *why, size_t whylen);
static int set_pixel_format(struct mn_config *cfg, const char *value, char *why, size_t whylen);

#define OFF(field) offsetof(struct mn_config, field)

static const struct setting settings[] = {
    {"id", T_U32, OFF(node_id), 1, 4095, NULL, "node id (0 addresses all nodes on the wire)"},
    {"source", T_CUSTOM, 0, 0, 0, set_source, "v4l2:/dev/videoN | libcamera:N | replay:DIR"},
    {"sync", T_CUSTOM, 0, 0, 0, set_sync, "gpio:CHIP:LINE | sim:RATE | none"},
    {"gpio_falling", T_BOOL, OFF(gpio_falling), 0, 1, NULL, "trigger on the falling edge"},
    {"hub", T_CUSTOM, 0, 0, 0, set_hub, "HOST:PORT of the hub; unset: wait for HubAnnounce"},
    {"control_port", T_U16, OFF(control_port), 0, 65535, NULL, "local UDP port (0 = any)"},
    {"announce_port", T_U16, OFF(announce_port), 1, 65535, NULL, "HubAnnounce broadcast port"},
    {"key_file", T_STRING, OFF(key_file), 0, 0, NULL,
     "this node's wire key, mode 0600 (mocap-hub keys new ID --out DIR)"},
    {"insecure_dev_wire", T_BOOL, OFF(insecure_dev_wire), 0, 1, NULL,
     "DEVELOPMENT ONLY: no key, unauthenticated datagrams (the hub needs --insecure-dev-wire)"},
    {"width", T_U32, OFF(width), 0, 8192, NULL, "capture width (0 = source default)"},
    {"height", T_U32, OFF(height), 0, 8192, NULL, "capture height (0 = source default)"},
    {"buffers", T_U32, OFF(buffers), 2, 32, NULL, "V4L2 mmap buffers"},
    {"pixel_format", T_CUSTOM, 0, 0, 0, set_pixel_format,
     "V4L2 format as v4l2-ctl names it (GREY NV12 YUYV MJPG ...; unset = best offered)"},
    {"exposure_us", T_U32, OFF(exposure_us), 0, 1000000, NULL, "exposure (0 = camera's)"},
    {"gain_milli", T_U32, OFF(gain_milli), 0, 64000, NULL, "analogue gain x1000 (0 = camera's)"},
    {"brightness", T_I32, OFF(brightness_pct), -1, 100, NULL,
     "percent of the camera's brightness range (-1 = camera's)"},
    {"contrast", T_I32, OFF(contrast_pct), -1, 100, NULL,
     "percent of the camera's contrast range (-1 = camera's)"},
    {"threshold", T_U32, OFF(threshold), 1, 255, NULL, "binary threshold"},
    {"auto_threshold", T_BOOL, OFF(auto_threshold), 0, 1, NULL, "threshold from histogram"},
    {"min_area", T_U32, OFF(min_area), 1, 100000, NULL, "smallest blob, pixels"},
    {"max_area", T_U32, OFF(max_area), 1, 1000000, NULL, "largest blob, pixels"},
    {"morph_radius", T_U32, OFF(morph_radius), 0, 8, NULL,
     "per-blob opening + closing radius (0 = none)"},
    {"binary_centroid", T_BOOL, OFF(binary_centroid), 0, 1, NULL,
     "plain mean of blob pixels instead of intensity-weighted"},
    {"rate", T_DOUBLE, OFF(rate_hz), 0.1, 1000.0, NULL, "trigger rate, Hz"},
    {"epoch_ns", T_I64, OFF(epoch_ns), 0, 9.2e18, NULL, "realtime ns of frame 0 (0 = start)"},
    {"trigger_delay_us", T_I32, OFF(trigger_delay_us), -1000000, 1000000, NULL,
     "capture time stamp minus trigger edge"},
    {"pair_window_pct", T_U32, OFF(pair_window_pct), 1, 49, NULL,
     "frame-to-edge match window, % of a period"},
    {"sim_jitter_us", T_U32, OFF(sim_jitter_us), 0, 100000, NULL, "sim sync edge jitter (sd)"},
    {"sim_missed", T_DOUBLE, OFF(sim_missed), 0, 0.9, NULL, "sim sync missed-edge probability"},
    {"sim_spurious", T_DOUBLE, OFF(sim_spurious), 0, 0.9, NULL, "sim sync extra-edge probability"},
    {"sim_seed", T_U32, OFF(sim_seed), 0, 4294967295.0, NULL, "sim sync random seed"},
    {"frames", T_U64, OFF(frames), 0, 1e15, NULL, "stop after N frames (0 = never)"},
    {"duration", T_DOUBLE, OFF(duration_s), 0, 1e9, NULL, "stop after S seconds (0 = never)"},
    {"as_fast_as_possible", T_BOOL, OFF(as_fast_as_possible), 0, 1, NULL,
     "replay without pacing"},
    {"replay_loop", T_BOOL, OFF(replay_loop), 0, 1, NULL, "replay again from the start at end"},
    {"wait_for_start", T_BOOL, OFF(wait_for_start), 0, 1, NULL, "idle until the hub's Start"},
    {"status_interval_ms", T_U32, OFF(status_interval_ms), 100, 60000, NULL, "status period"},
    {"reopen_min_ms", T_U32, OFF(reopen_min_ms), 10, 60000, NULL, "first camera reopen delay"},
    {"reopen_max_ms", T_U32, OFF(reopen_max_ms), 10, 600000, NULL, "longest reopen delay"},
    {"send_buffer_kb", T_U32, OFF(send_buffer_kb), 16, 16384, NULL, "UDP send buffer"},
    {"temperature_path", T_STRING, OFF(temperature_path), 0, 0, NULL,
     "thermal zone file (millidegrees)"},
    {"identify_led", T_STRING, OFF(identify_led), 0, 0, NULL,
     "LED brightness file blinked on Identify"},
    {"log_level", T_CUSTOM, 0, 0, 0, set_log_level, "error|warning|notice|info|debug"},
};

void mn_config_defaults(struct mn_config *cfg)
{
    memset(cfg, 0, sizeof(*cfg));
    cfg->node_id = 1;
    cfg->source_kind = MN_SOURCE_V4L2;
    snprintf(cfg->source_arg, sizeof(cfg->source_arg), "/dev/video0");
    cfg->sync_kind = MN_SYNC_NONE;
    cfg->announce_port = 7700;
    cfg->buffers = 4;
    cfg->brightness_pct = -1;
    cfg->contrast_pct = -1;
    cfg->threshold = 128;
    cfg->min_area = 2;
    cfg->max_area = 5000;
    cfg->morph_radius = 1;
    cfg->rate_hz = 100.0;
    cfg->pair_window_pct = 25;
    cfg->sim_seed = 1;
    cfg->status_interval_ms = 1000;
    cfg->reopen_min_ms = 100;
    cfg->reopen_max_ms = 10000;
    cfg->send_buffer_kb = 1024;
    snprintf(cfg->temperature_path, sizeof(cfg->temperature_path),
             "/sys/class/thermal/thermal_zone0/temp");
    cfg->log_level = MN_LOG_INFO;
}

static int copy_string(char *dst, size_t cap, const char *src, char *why, size_t whylen)
{
    size_t n = strlen(src);
    if (n >= cap)
        return mn_fail(why, whylen, "too long (%zu characters, at most %zu)", n, cap - 1);
    memcpy(dst, src, n + 1);
    return 0;
}

static int set_source(struct mn_config *cfg, const char *value, char *why, size_t whylen)
{
    static const struct {
        const char *prefix;
        enum mn_source_kind kind;
    } kinds[] = {
        {"v4l2:", MN_SOURCE_V4L2}, {"libcamera:", MN_SOURCE_LIBCAMERA}, {"replay:", MN_SOURCE_REPLAY},
    };
    for (size_t i = 0; i < sizeof(kinds) / sizeof(kinds[0]); i++) {
        size_t plen = strlen(kinds[i].prefix);
        if (strncmp(value, kinds[i].prefix, plen) != 0)
            continue;
        const char *arg = value + plen;
        if (*arg == '\0')
            return mn_fail(why, whylen, "'%s' lacks its argument", kinds[i].prefix);
        if (kinds[i].kind == MN_SOURCE_LIBCAMERA) {
            char *end;
            errno = 0;
            unsigned long idx = strtoul(arg, &end, 10);
            if (errno != 0 || *end != '\0' || !isdigit((unsigned char)arg[0]) || idx > 63)
                return mn_fail(why, whylen, "libcamera camera index '%s' is not 0..63", arg);
        }
        if (copy_string(cfg->source_arg, sizeof(cfg->source_arg), arg, why, whylen) < 0)
            return -1;
        cfg->source_kind = kinds[i].kind;
        return 0;
    }
    return mn_fail(why, whylen, "'%s' is not v4l2:/dev/videoN, libcamera:N or replay:DIR", value);
}

static int parse_double(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (errno != 0 || end == s || *end != '\0' || !isfinite(v))
        return -1;
    *out = v;
    return 0;
}

static int parse_u64(const char *s, uint64_t *out)
{
    char *end;
    if (!isdigit((unsigned char)s[0]))
        return -1;
    errno = 0;
    unsigned long long v = strtoull(s, &end, 10);
    if (errno != 0 || *end != '\0')
        return -1;
    *out = v;
    return 0;
}

static int set_sync(struct mn_config *cfg, const char *value, char *why, size_t whylen)
{
    if (strcmp(value, "none") == 0) {
        cfg->sync_kind = MN_SYNC_NONE;
        return 0;
    }
    if (strncmp(value, "sim:", 4) == 0) {
        double rate;
        if (parse_double(value + 4, &rate) < 0 || rate < 0.1 || rate > 1000.0)
            return mn_fail(why, whylen, "sim rate '%s' is not a number in 0.1..1000 Hz", value + 4);
        cfg->sync_kind = MN_SYNC_SIM;
        cfg->rate_hz = rate;
        return 0;
    }
    if (strncmp(value, "gpio:", 5) == 0) {
        const char *chip = value + 5;
        const char *colon = strrchr(chip, ':');
        uint64_t line;
        if (colon == NULL || colon == chip || parse_u64(colon + 1, &line) < 0 || line > 1023)
            return mn_fail(why, whylen, "'%s' is not gpio:CHIP:LINE (LINE 0..1023)", value);
        size_t n = (size_t)(colon - chip);
        if (n >= sizeof(cfg->gpio_chip))
            return mn_fail(why, whylen, "gpio chip name too long");
        memcpy(cfg->gpio_chip, chip, n);
        cfg->gpio_chip[n] = '\0';
        cfg->gpio_line = (uint32_t)line;
        cfg->sync_kind = MN_SYNC_GPIO;
        return 0;
    }
    return mn_fail(why, whylen, "'%s' is not gpio:CHIP:LINE, sim:RATE or none", value);
}

static int set_hub(struct mn_config *cfg, const char *value, char *why, size_t whylen)
{
    const char *colon = strrchr(value, ':');
    uint64_t port;
    if (colon == NULL || colon == value || parse_u64(colon + 1, &port) < 0 || port < 1 ||
        port > 65535)
        return mn_fail(why, whylen, "'%s' is not HOST:PORT (PORT 1..65535)", value);
    size_t n = (size_t)(colon - value);
    if (n >= sizeof(cfg->hub_host))
        return mn_fail(why, whylen, "hub host name too long");
    memcpy(cfg->hub_host, value, n);
    cfg->hub_host[n] = '\0';
    cfg->hub_port = (uint16_t)port;
    return 0;
}

/* A fourcc name: 1-4 of A-Z, 0-9 (the V4L2 backend pads it with spaces, "Y10" = 'Y10 '). Which
 * formats a camera offers is the backend's to check when it opens the device. */
static int set_pixel_format(struct mn_config *cfg, const char *value, char *why, size_t whylen)
{
    size_t n = strlen(value);
    bool ok = n >= 1 && n <= 4;
    for (size_t i = 0; ok && i < n; i++)
        ok = (value[i] >= 'A' && value[i] <= 'Z') || (value[i] >= '0' && value[i] <= '9');
    if (!ok)
        return mn_fail(why, whylen, "'%s' is not a fourcc name (1-4 of A-Z, 0-9, e.g. NV12)",
                       value);
    memcpy(cfg->pixel_format, value, n + 1);
    return 0;
}

static int set_log_level(struct mn_config *cfg, const char *value, char *why, size_t whylen)
{
    if (mn_log_level_parse(value, &cfg->log_level) < 0)
        return mn_fail(why, whylen, "'%s' is not error, warning, notice, info or debug", value);
    return 0;
}

static int parse_bool(const char *s, bool *out)
{
    static const char *yes[] = {"1", "yes", "true", "on"};
    static const char *no[] = {"0", "no", "false", "off"};
    for (size_t i = 0; i < 4; i++) {
        if (strcmp(s, yes[i]) == 0) {
            *out = true;
            return 0;
        }
        if (strcmp(s, no[i]) == 0) {
            *out = false;
            return 0;
        }
    }
    return -1;
}

static const struct setting *find_setting(const char *key)
{
    for (size_t i = 0; i < sizeof(settings) / sizeof(settings[0]); i++)
        if (strcmp(settings[i].key, key) == 0)
            return &settings[i];
    return NULL;
}

/* Integers are parsed exactly (no detour through double) and then range-checked. */
static int set_integer(const struct setting *s, void *field, const char *value, char *why,
                       size_t whylen)
{
    char *end;
    errno = 0;
    long long v = strtoll(value, &end, 10);
    if (errno != 0 || end == value || *end != '\0')
        return mn_fail(why, whylen, "'%s' is not an integer", value);
    if ((double)v < s->min || (double)v > s->max)
        return mn_fail(why, whylen, "%lld is out of range %.0f..%.0f", v, s->min, s->max);
    switch (s->type) {
    case T_U32: *(uint32_t *)field = (uint32_t)v; break;
    case T_U16: *(uint16_t *)field = (uint16_t)v; break;
    case T_I32: *(int32_t *)field = (int32_t)v; break;
    case T_I64: *(int64_t *)field = (int64_t)v; break;
    case T_U64: *(uint64_t *)field = (uint64_t)v; break;
    default: return mn_fail(why, whylen, "internal: not an integer setting");
    }
    return 0;
}

int mn_config_set(struct mn_config *cfg, const char *key, const char *value, const char *origin,
                  char *err, size_t errlen)
{
    const struct setting *s = find_setting(key);
    if (s == NULL)
        return mn_fail(err, errlen, "%s: unknown setting '%s'", origin, key);
    char why[MN_CONFIG_ERR / 2];
    why[0] = '\0';
    void *field = (char *)cfg + s->offset;
    int rc = 0;
    switch (s->type) {
    case T_U32:
    case T_U16:
    case T_I32:
    case T_I64:
    case T_U64:
        rc = set_integer(s, field, value, why, sizeof(why));
        break;
    case T_DOUBLE: {
        double v;
        if (parse_double(value, &v) < 0)
            rc = mn_fail(why, sizeof(why), "'%s' is not a number", value);
        else if (v < s->min || v > s->max)
            rc = mn_fail(why, sizeof(why), "%g is out of range %g..%g", v, s->min, s->max);
        else
            *(double *)field = v;
        break;
    }
    case T_BOOL:
        if (parse_bool(value, (bool *)field) < 0)
            rc = mn_fail(why, sizeof(why), "'%s' is not yes/no/true/false/1/0/on/off", value);
        break;
    case T_STRING:
        rc = copy_string(field, MN_CONFIG_STR, value, why, sizeof(why));
        break;
    case T_CUSTOM:
        rc = s->custom(cfg, value, why, sizeof(why));
        break;
    }
    if (rc < 0)
        return mn_fail(err, errlen, "%s: %s: %s", origin, key, why);
    return 0;
}

static char *trim(char *s)
{
    while (isspace((unsigned char)*s))
        s++;
    char *e = s + strlen(s);
    while (e > s && isspace((unsigned char)e[-1]))
        *--e = '\0';
    return s;
}

/* Reads at most MN_CONFIG_MAX_BYTES + 1 bytes of f into buf (MN_CONFIG_MAX_BYTES + 1 long):
 * one more than allowed tells an oversized stream from a full one. */
static int read_bounded(FILE *f, char *buf, size_t *len, const char *path, char *err,
                        size_t errlen)
{
    *len = fread(buf, 1, MN_CONFIG_MAX_BYTES + 1, f);
    if (ferror(f)) {
        snprintf(err, errlen, "%s: read error", path);
        errno = EIO;
        return -1;
    }
    if (*len > MN_CONFIG_MAX_BYTES)
        return mn_fail(err, errlen, "%s: larger than %d bytes: not a node config", path,
                       MN_CONFIG_MAX_BYTES);
    return 0;
}

int mn_config_load_file(struct mn_config *cfg, const char *path, char *err, size_t errlen)
{
    /* O_NONBLOCK: opening a FIFO must not wait for a writer; the check below refuses it anyway. */
    int fd = open(path, O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
    if (fd < 0) {
        int e = errno;
        snprintf(err, errlen, "%s: cannot open: %s", path, strerror(e));
        errno = e;
        return -1;
    }
    struct stat st;
    if (fstat(fd, &st) < 0) {
        int e = errno;
        close(fd);
        snprintf(err, errlen, "%s: cannot stat: %s", path, strerror(e));
        errno = e;
        return -1;
    }
    if (!S_ISREG(st.st_mode)) {
        close(fd);
        return mn_fail(err, errlen, "%s: not a regular file (a device, FIFO or directory is no config)",
                       path);
    }
    if (st.st_size > MN_CONFIG_MAX_BYTES) {
        close(fd);
        return mn_fail(err, errlen, "%s: %lld bytes, larger than %d: not a node config", path,
                       (long long)st.st_size, MN_CONFIG_MAX_BYTES);
    }
    FILE *f = fdopen(fd, "r");
    if (f == NULL) {
        int e = errno;
        close(fd);
        snprintf(err, errlen, "%s: cannot open: %s", path, strerror(e));
        errno = e;
        return -1;
    }
    int rc = mn_config_load_stream(cfg, f, path, err, errlen);
    fclose(f);
    return rc;
}

int mn_config_load_stream(struct mn_config *cfg, FILE *f, const char *path, char *err,
                          size_t errlen)
{
    char *text = malloc(MN_CONFIG_MAX_BYTES + 1);
    if (text == NULL) {
        snprintf(err, errlen, "%s: out of memory", path);
        errno = ENOMEM;
        return -1;
    }
    size_t len = 0;
    int rc = read_bounded(f, text, &len, path, err, errlen);
    if (rc == 0)
        rc = mn_config_load_text(cfg, text, len, path, err, errlen);
    free(text);
    return rc;
}

int mn_config_load_text(struct mn_config *cfg, const char *text, size_t len, const char *path,
                        char *err, size_t errlen)
{
    char line[MN_CONFIG_MAX_LINE + 1];
    char origin[MN_CONFIG_STR + 32];
    unsigned lineno = 0;
    size_t pos = 0;
    while (pos < len) {
        const char *nl = memchr(text + pos, '\n', len - pos);
        size_t n = (nl != NULL ? (size_t)(nl - text) : len) - pos;
        lineno++;
        snprintf(origin, sizeof(origin), "%s:%u", path, lineno);
        if (n > MN_CONFIG_MAX_LINE)
            return mn_fail(err, errlen, "%s: line longer than %d characters", origin,
                           MN_CONFIG_MAX_LINE);
        if (memchr(text + pos, '\0', n) != NULL)
            return mn_fail(err, errlen, "%s: NUL byte in line (not a text file?)", origin);
        memcpy(line, text + pos, n);
        line[n] = '\0';
        pos += n + 1;
        char *hash = strchr(line, '#');
        if (hash != NULL)
            *hash = '\0';
        char *body = trim(line);
        if (*body == '\0')
            continue;
        char *eq = strchr(body, '=');
        if (eq == NULL)
            return mn_fail(err, errlen, "%s: expected 'key = value', got '%s'", origin, body);
        *eq = '\0';
        char *key = trim(body);
        char *value = trim(eq + 1);
        if (*key == '\0' || *value == '\0')
            return mn_fail(err, errlen, "%s: expected 'key = value' with both parts", origin);
        if (mn_config_set(cfg, key, value, origin, err, errlen) < 0) {
            errno = EINVAL;
            return -1;
        }
    }
    return 0;
}

int mn_config_load_keys(struct mn_config *cfg, char *err, size_t errlen)
{
    memset(&cfg->keys, 0, sizeof(cfg->keys));
    if (cfg->insecure_dev_wire)
        return 0;
    if (mn_keyfile_load(cfg->key_file, &cfg->keys, err, errlen) < 0)
        return -1;
    if (cfg->keys.node_id != cfg->node_id)
        return mn_fail(err, errlen, "key file %s is for node %u, this node is %u", cfg->key_file,
                    cfg->keys.node_id, cfg->node_id);
    return 0;
}

int mn_config_check(const struct mn_config *cfg, char *err, size_t errlen)
{
    if (cfg->min_area > cfg->max_area)
        return mn_fail(err, errlen, "min_area %u is larger than max_area %u", cfg->min_area,
                    cfg->max_area);
    if (cfg->reopen_min_ms > cfg->reopen_max_ms)
        return mn_fail(err, errlen, "reopen_min_ms %u is larger than reopen_max_ms %u",
                    cfg->reopen_min_ms, cfg->reopen_max_ms);
    if ((cfg->width == 0) != (cfg->height == 0))
        return mn_fail(err, errlen, "width and height must be given together");
    if (cfg->as_fast_as_possible && cfg->source_kind != MN_SOURCE_REPLAY)
        return mn_fail(err, errlen, "as_fast_as_possible only applies to a replay source");
    if (cfg->replay_loop && cfg->source_kind != MN_SOURCE_REPLAY)
        return mn_fail(err, errlen, "replay_loop only applies to a replay source");
    /* A real trigger period is shorter than one frame's readout at these rates anyway; the
     * pairing window must leave the neighbouring edges outside it. */
    if (cfg->sync_kind != MN_SYNC_NONE &&
        llabs((long long)cfg->trigger_delay_us) * cfg->rate_hz > 10.0 * 1e6)
        return mn_fail(err, errlen, "trigger_delay_us %d is more than 10 trigger periods",
                    cfg->trigger_delay_us);
    if (cfg->key_file[0] == '\0' && !cfg->insecure_dev_wire)
        return mn_fail(err, errlen,
                    "no wire key: set key_file (made by `mocap-hub keys new ID --out DIR`), or "
                    "insecure_dev_wire = yes for development only");
    if (cfg->key_file[0] != '\0' && cfg->insecure_dev_wire)
        return mn_fail(err, errlen, "key_file and insecure_dev_wire exclude each other");
    return 0;
}

void mn_config_print_help(FILE *f)
{
    fprintf(f, "usage: mocap-node [--config FILE] [--KEY VALUE ...]\n"
               "Every KEY is also a config file key (key = value, '_' for '-').\n\n");
    for (size_t i = 0; i < sizeof(settings) / sizeof(settings[0]); i++) {
        const struct setting *s = &settings[i];
        char flag[64];
        snprintf(flag, sizeof(flag), "--%s", s->key);
        for (char *p = flag + 2; *p; p++)
            if (*p == '_')
                *p = '-';
        if (s->type == T_DOUBLE)
            fprintf(f, "  %-24s %s [%g..%g]\n", flag, s->help, s->min, s->max);
        else if (s->type != T_STRING && s->type != T_CUSTOM && s->type != T_BOOL)
            fprintf(f, "  %-24s %s [%.0f..%.0f]\n", flag, s->help, s->min, s->max);
        else
            fprintf(f, "  %-24s %s\n", flag, s->help);
    }
    fprintf(f, "  %-24s %s\n  %-24s %s\n  %-24s %s\n", "--config FILE", "read settings from FILE first",
            "--help", "this text", "--version", "print the firmware version");
}

/* "--trigger-delay-us" -> "trigger_delay_us"; NULL when arg is not a long flag. */
static const char *flag_key(const char *arg, char *buf, size_t cap)
{
    if (strncmp(arg, "--", 2) != 0 || arg[2] == '\0')
        return NULL;
    snprintf(buf, cap, "%s", arg + 2);
    for (char *p = buf; *p; p++)
        if (*p == '-')
            *p = '_';
    return buf;
}

enum mn_config_args_result mn_config_from_args(struct mn_config *cfg, int argc, char **argv,
                                               char *err, size_t errlen)
{
    mn_config_defaults(cfg);
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            mn_config_print_help(stdout);
            return MN_CONFIG_ARGS_EXIT;
        }
        if (strcmp(argv[i], "--version") == 0) {
            printf("mocap-node %s\n", MN_VERSION);
            return MN_CONFIG_ARGS_EXIT;
        }
    }
    /* The file first, so that flags override it whatever their order. */
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--config") != 0)
            continue;
        if (i + 1 >= argc) {
            mn_fail(err, errlen, "command line: --config needs a FILE");
            return MN_CONFIG_ARGS_ERROR;
        }
        if (mn_config_load_file(cfg, argv[i + 1], err, errlen) < 0)
            return MN_CONFIG_ARGS_ERROR;
        i++;
    }
    for (int i = 1; i < argc; i++) {
        char keybuf[128];
        char origin[160];
        if (strcmp(argv[i], "--config") == 0) {
            i++;
            continue;
        }
        const char *key = flag_key(argv[i], keybuf, sizeof(keybuf));
        if (key == NULL) {
            mn_fail(err, errlen, "command line: unexpected argument '%s'", argv[i]);
            return MN_CONFIG_ARGS_ERROR;
        }
        snprintf(origin, sizeof(origin), "command line %s", argv[i]);
        const struct setting *s = find_setting(key);
        const char *value;
        /* A boolean flag followed by another flag (or nothing) means "yes". */
        if (s != NULL && s->type == T_BOOL &&
            (i + 1 >= argc || strncmp(argv[i + 1], "--", 2) == 0)) {
            value = "yes";
        } else {
            if (i + 1 >= argc) {
                mn_fail(err, errlen, "%s: needs a value", origin);
                return MN_CONFIG_ARGS_ERROR;
            }
            value = argv[++i];
        }
        if (mn_config_set(cfg, key, value, origin, err, errlen) < 0)
            return MN_CONFIG_ARGS_ERROR;
    }
    if (mn_config_check(cfg, err, errlen) < 0 || mn_config_load_keys(cfg, err, errlen) < 0)
        return MN_CONFIG_ARGS_ERROR;
    return MN_CONFIG_ARGS_RUN;
}
