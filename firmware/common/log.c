/* Logging to stderr. Under systemd (JOURNAL_STREAM set) each line carries a "<N>" priority
 * prefix that journald turns into the entry's priority; on a terminal it carries a time stamp
 * and a level word instead. */
#include "common/log.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static enum mn_log_level max_level = MN_LOG_INFO;

void mn_log_set_level(enum mn_log_level level)
{
    max_level = level;
}

int mn_log_level_parse(const char *name, enum mn_log_level *out)
{
    static const struct {
        const char *name;
        enum mn_log_level level;
    } names[] = {
        {"error", MN_LOG_ERR},   {"warning", MN_LOG_WARN}, {"notice", MN_LOG_NOTICE},
        {"info", MN_LOG_INFO},   {"debug", MN_LOG_DEBUG},
    };
    for (size_t i = 0; i < sizeof(names) / sizeof(names[0]); i++) {
        if (strcmp(name, names[i].name) == 0) {
            *out = names[i].level;
            return 0;
        }
    }
    return -1;
}

static const char *level_word(enum mn_log_level level)
{
    switch (level) {
    case MN_LOG_ERR: return "error";
    case MN_LOG_WARN: return "warning";
    case MN_LOG_NOTICE: return "notice";
    case MN_LOG_INFO: return "info";
    case MN_LOG_DEBUG: return "debug";
    }
    return "?";
}

void mn_log_msg(enum mn_log_level level, const char *fmt, ...)
{
    if (level > max_level)
        return;
    char line[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof(line), fmt, ap);
    va_end(ap);
    /* One fprintf per line keeps lines whole when several nodes share a terminal. */
    if (getenv("JOURNAL_STREAM") != NULL) {
        fprintf(stderr, "<%d>%s\n", (int)level, line);
    } else {
        struct timespec ts;
        clock_gettime(CLOCK_REALTIME, &ts);
        struct tm tm;
        gmtime_r(&ts.tv_sec, &tm);
        fprintf(stderr, "%02d:%02d:%02d.%03ld mocap-node %s: %s\n", tm.tm_hour, tm.tm_min,
                tm.tm_sec, ts.tv_nsec / 1000000L, level_word(level), line);
    }
}
