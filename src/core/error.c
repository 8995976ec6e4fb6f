/* error.c -- status codes and messages.  The library reports, never prints. */
#include "core/taper_internal.h"

#include <stdio.h>
#include <string.h>

const char *taper_version(void) { return TAPER_VERSION_STRING; }

const char *taper_strerror(int status)
{
    switch (status) {
    case TAPER_OK: return "success";
    case TAPER_EINVAL: return "invalid argument";
    case TAPER_ENOMEM: return "out of memory";
    case TAPER_ERANGE: return "value out of double-precision range";
    case TAPER_ESOLVER: return "integrator failure";
    case TAPER_EINTERRUPTED: return "interrupted";
    case TAPER_ELIMIT: return "time or step limit reached";
    case TAPER_EIO: return "input/output error";
    default: return "unknown status";
    }
}

int taper_fail(taper_error *err, int status, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->message, sizeof err->message, fmt, ap);
        va_end(ap);
        err->status = status;
    }
    return status;
}

int taper_ok(taper_error *err)
{
    if (err) {
        err->status = TAPER_OK;
        err->message[0] = '\0';
    }
    return TAPER_OK;
}
