/* The parsers' error convention (config, key files): write the reason into the caller's buffer,
 * set errno to EINVAL and return -1, so `return mn_fail(err, len, "...", ...);` ends a parse. */
#ifndef MN_COMMON_FAIL_H
#define MN_COMMON_FAIL_H

#include <stddef.h>

int mn_fail(char *err, size_t errlen, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

#endif
