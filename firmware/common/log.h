/* One logging module for the whole node: severity levels, printf-format checking, debug
 * messages compiled out unless MN_DEBUG is defined. Everything goes to stderr so that systemd's
 * journal picks it up; library code (detect, wire, framefile) returns errors and never logs. */
#ifndef MN_COMMON_LOG_H
#define MN_COMMON_LOG_H

enum mn_log_level {
    MN_LOG_ERR = 3,     /* values are syslog priorities: the journal understands "<3>" etc. */
    MN_LOG_WARN = 4,
    MN_LOG_NOTICE = 5,
    MN_LOG_INFO = 6,
    MN_LOG_DEBUG = 7,
};

/* Messages above this level are discarded (default MN_LOG_INFO). */
void mn_log_set_level(enum mn_log_level level);

/* Parses "error", "warning", "notice", "info" or "debug"; 0 on success, -1 otherwise. */
int mn_log_level_parse(const char *name, enum mn_log_level *out);

void mn_log_msg(enum mn_log_level level, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

#define mn_log_err(...) mn_log_msg(MN_LOG_ERR, __VA_ARGS__)
#define mn_log_warn(...) mn_log_msg(MN_LOG_WARN, __VA_ARGS__)
#define mn_log_notice(...) mn_log_msg(MN_LOG_NOTICE, __VA_ARGS__)
#define mn_log_info(...) mn_log_msg(MN_LOG_INFO, __VA_ARGS__)
#ifdef MN_DEBUG
#define mn_log_debug(...) mn_log_msg(MN_LOG_DEBUG, __VA_ARGS__)
#else
/* Keeps the format checked while the call itself compiles to nothing. */
#define mn_log_debug(...)                          \
    do {                                           \
        if (0)                                     \
            mn_log_msg(MN_LOG_DEBUG, __VA_ARGS__); \
    } while (0)
#endif

#endif
