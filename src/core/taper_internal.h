/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * taper_internal.h -- what every part of the library shares: recording a
 * failure in a taper_error.  Not installed.  Symbols declared here have
 * hidden visibility in libtaper.so; the unit tests reach them through the
 * static part taper_part_core.
 */
#ifndef TAPER_INTERNAL_H
#define TAPER_INTERNAL_H

#include "taper.h"

#if defined(__GNUC__) || defined(__clang__)
#define TAPER_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define TAPER_PRINTF(a, b)
#endif

/* Records status, field NULL (no single setting is at fault) and the
 * formatted message in err (if non-NULL); returns status.  A message longer
 * than the buffer ends in "...". */
taper_status taper_fail(taper_error *err, taper_status status, const char *fmt, ...)
    TAPER_PRINTF(3, 4);
/* As taper_fail, naming the setting at fault: `field` is its setter's
 * suffix ("n_granules", "rtol", ...), a string literal (err keeps the
 * pointer). */
taper_status taper_fail_field(taper_error *err, taper_status status, const char *field,
                              const char *fmt, ...) TAPER_PRINTF(4, 5);
/* Appends to the message of a failure already recorded in err, with the
 * same "..." rule; status and field are kept. */
void taper_fail_append(taper_error *err, const char *fmt, ...) TAPER_PRINTF(2, 3);
/* Clears err to TAPER_OK, field NULL, empty message; returns TAPER_OK. */
taper_status taper_ok(taper_error *err);

/* Finds `name` (case-insensitive) among names[0..n): *index and TAPER_OK,
 * or TAPER_EINVAL naming `field` with "unknown WHAT 'NAME': did you mean
 * 'NEAREST'? (use 'a', 'b', ...)" (names.c).  Every *_from_name of the
 * library answers through it. */
taper_status taper_name_find(const char *name, const char *const *names, size_t n,
                             const char *field, const char *what, size_t *index,
                             taper_error *err);

#endif
