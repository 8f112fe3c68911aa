/* The parsers' error convention (see fail.h). */
#include "common/fail.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>

int mn_fail(char *err, size_t errlen, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
    errno = EINVAL;
    return -1;
}
