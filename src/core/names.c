/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * names.c -- finding a name in one of the library's lists of names (the
 * enums' lists of taper.h, the table of settings), the same way for every
 * list: case-insensitive, and an unknown name answered with the nearest
 * known one and the whole list.
 */
#include "core/taper_internal.h"

#include <ctype.h>
#include <string.h>
#include <strings.h>

/* Names longer than this are never near one of ours (the longest is 22). */
#define NAME_MAX_LENGTH 64

/* Levenshtein distance, case-insensitive; NAME_MAX_LENGTH for long names. */
static size_t distance(const char *a, const char *b)
{
    size_t la = strlen(a), lb = strlen(b), row[NAME_MAX_LENGTH + 1];
    if (la >= NAME_MAX_LENGTH || lb >= NAME_MAX_LENGTH) return NAME_MAX_LENGTH;
    for (size_t j = 0; j <= lb; j++) row[j] = j;
    for (size_t i = 1; i <= la; i++) {
        size_t diag = row[0];
        row[0] = i;
        for (size_t j = 1; j <= lb; j++) {
            size_t up = row[j];
            size_t same = tolower((unsigned char)a[i - 1]) == tolower((unsigned char)b[j - 1]);
            size_t best = up + 1 < row[j - 1] + 1 ? up + 1 : row[j - 1] + 1;
            row[j] = diag + !same < best ? diag + !same : best;
            diag = up;
        }
    }
    return row[lb];
}

const char *taper_nearest_name(const char *name, const char *const *names, size_t n)
{
    if (!name || !names) return NULL;
    /* Two edits: a typo or a transposition, not another word. */
    size_t best = 3;
    const char *nearest = NULL;
    for (size_t i = 0; i < n && names[i]; i++) {
        size_t d = distance(name, names[i]);
        if (d < best) {
            best = d;
            nearest = names[i];
        }
    }
    return nearest;
}

taper_status taper_name_find(const char *name, const char *const *names, size_t n,
                             const char *field, const char *what, size_t *index,
                             taper_error *err)
{
    if (!name) return taper_fail_field(err, TAPER_EINVAL, field, "%s: the name is NULL", what);
    for (size_t i = 0; i < n; i++) {
        if (strcasecmp(name, names[i]) == 0) {
            *index = i;
            return taper_ok(err);
        }
    }
    const char *nearest = taper_nearest_name(name, names, n);
    taper_fail_field(err, TAPER_EINVAL, field, "unknown %s '%s'", what, name);
    if (nearest) taper_fail_append(err, ": did you mean '%s'?", nearest);
    taper_fail_append(err, " (use");
    for (size_t i = 0; i < n; i++) taper_fail_append(err, "%s '%s'", i ? "," : "", names[i]);
    taper_fail_append(err, ")");
    return TAPER_EINVAL;
}
