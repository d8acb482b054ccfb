/* status.c - names and message formatting for texopt_status. */
#include "status.h"

#include <stdarg.h>
#include <stdio.h>

const char *texopt_strerror(texopt_status status)
{
    static const char *const names[TEXOPT_STATUS_COUNT] = {
        [TEXOPT_OK] = "ok",
        [TEXOPT_E_INVALID_ARGUMENT] = "invalid argument",
        [TEXOPT_E_IO] = "input/output error",
        [TEXOPT_E_MALFORMED] = "malformed input",
        [TEXOPT_E_UNSUPPORTED] = "unsupported input",
        [TEXOPT_E_LIMIT] = "size limit exceeded",
        [TEXOPT_E_NOMEM] = "out of memory",
        [TEXOPT_E_CANCELED] = "canceled",
        [TEXOPT_E_NUMERIC] = "numerical failure",
        [TEXOPT_E_RENDER] = "rendering failure",
        [TEXOPT_E_INTERNAL] = "internal error",
    };
    if ((unsigned)status >= TEXOPT_STATUS_COUNT)
        return "unknown status";
    return names[status];
}

texopt_status texopt_fail(char *err, size_t err_len, texopt_status status, const char *fmt, ...)
{
    if (err && err_len > 0) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err, err_len, fmt, ap);
        va_end(ap);
    }
    return status;
}
