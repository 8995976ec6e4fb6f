/* SPDX-License-Identifier: GPL-3.0-or-later */
/* error.c -- status codes and messages.  The library reports, never prints. */
#include "core/taper_internal.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

const char *taper_version(void) { return TAPER_VERSION_STRING; }

#define STATUS_NAME(constant, name, description) [constant] = name,
#define STATUS_DESCRIPTION(constant, name, description) [constant] = description,
static const char *const status_names[] = {TAPER_STATUS_LIST(STATUS_NAME)};
static const char *const status_descriptions[] = {TAPER_STATUS_LIST(STATUS_DESCRIPTION)};
#define N_STATUSES (sizeof status_names / sizeof status_names[0])

const char *taper_strerror(taper_status status)
{
    /* Unsigned: a negative value of an int-typed enum is out of range too. */
    return (unsigned)status < N_STATUSES ? status_descriptions[status] : "unknown status";
}

const char *taper_status_name(taper_status status)
{
    return (unsigned)status < N_STATUSES ? status_names[status] : NULL;
}

/* Formats into err->message from offset `used`.  A message cut at the
 * buffer's end says so with "..." instead of ending mid-word unseen. */
static void format_at(taper_error *err, size_t used, const char *fmt, va_list ap)
{
    const size_t size = sizeof err->message;
    static const char ellipsis[] = "...";
    int needed = vsnprintf(err->message + used, size - used, fmt, ap);
    if (needed < 0) {
        /* Only an invalid format or conversion gets here: keep what was
         * there and say that the rest is missing. */
        err->message[used] = '\0';
        needed = (int)size; /* mark it below */
    }
    if ((size_t)needed >= size - used)
        memcpy(err->message + size - sizeof ellipsis, ellipsis, sizeof ellipsis);
}

static void record(taper_error *err, taper_status status, const char *field, const char *fmt,
                   va_list ap)
{
    err->status = status;
    err->field = field;
    format_at(err, 0, fmt, ap);
}

taper_status taper_fail(taper_error *err, taper_status status, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        record(err, status, NULL, fmt, ap);
        va_end(ap);
    }
    return status;
}

taper_status taper_fail_field(taper_error *err, taper_status status, const char *field,
                              const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        record(err, status, field, fmt, ap);
        va_end(ap);
    }
    return status;
}

void taper_fail_append(taper_error *err, const char *fmt, ...)
{
    if (!err) return;
    size_t used = strnlen(err->message, sizeof err->message - 1);
    va_list ap;
    va_start(ap, fmt);
    format_at(err, used, fmt, ap);
    va_end(ap);
}

taper_status taper_ok(taper_error *err)
{
    if (err) {
        err->status = TAPER_OK;
        err->field = NULL;
        err->message[0] = '\0';
    }
    return TAPER_OK;
}
