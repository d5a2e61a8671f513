#include "common/error.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

plm_result plm_fail(plm_error *err, plm_result code, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->message, sizeof err->message, fmt, ap);
        va_end(ap);
    }
    return code;
}

void plm_error_prefix(plm_error *err, const char *fmt, ...)
{
    if (!err)
        return;
    char prefix[512], old[sizeof err->message];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(prefix, sizeof prefix, fmt, ap);
    va_end(ap);
    memcpy(old, err->message, sizeof old);
    size_t n = strlen(prefix);
    if (n >= sizeof err->message)
        n = sizeof err->message - 1;
    memcpy(err->message, prefix, n);
    snprintf(err->message + n, sizeof err->message - n, "%.*s", (int)(sizeof err->message - n - 1), old);
}

const char *plm_result_name(plm_result code)
{
    switch (code) {
    case PLM_OK: return "ok";
    case PLM_ERR_INVALID: return "invalid input";
    case PLM_ERR_IO: return "i/o error";
    case PLM_ERR_PARSE: return "parse error";
    case PLM_ERR_NO_MEMORY: return "out of memory";
    case PLM_ERR_INTERRUPTED: return "interrupted";
    case PLM_ERR_INTERNAL: return "internal error";
    }
    return "unknown error";
}
