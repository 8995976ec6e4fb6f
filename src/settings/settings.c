/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * settings.c -- reading and writing the settings of a spec through the
 * table (table.c): every check of a single value, every range message and
 * every default come from the value's row, whether the caller used a typed
 * setter (chain_spec.c, solver_spec.c) or a name (taper_*_spec_set_option).
 */
#include "settings/settings.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* ---- the table, by index and by name ---------------------------------------- */

size_t taper_setting_count(void) { return taper_setting_n_rows; }

const taper_setting *taper_setting_at(size_t i)
{
    return i < taper_setting_n_rows ? &taper_setting_rows[i].info : NULL;
}

/* Room for the names of every row, for "did you mean" (table.c checks). */
#define MAX_ROWS SETTING_MAX_ROWS

/* The first letter compared first: a scene sets every row by its name
 * (docs/python.md, "Overheads"). */
static const setting_row *row_named(const char *name)
{
    for (size_t i = 0; name && i < taper_setting_n_rows; i++) {
        const char *row = taper_setting_rows[i].info.name;
        if (tolower((unsigned char)row[0]) == tolower((unsigned char)name[0]) &&
            strcasecmp(row, name) == 0)
            return &taper_setting_rows[i];
    }
    return NULL;
}

static taper_status unknown(const char *name, taper_error *err)
{
    const char *names[MAX_ROWS];
    for (size_t i = 0; i < taper_setting_n_rows; i++) names[i] = taper_setting_rows[i].info.name;
    const char *nearest = taper_nearest_name(name, names, taper_setting_n_rows);
    taper_fail(err, TAPER_EINVAL, "unknown setting '%s'", name ? name : "(null)");
    if (nearest) taper_fail_append(err, ": did you mean '%s'?", nearest);
    return TAPER_EINVAL;
}

const taper_setting *taper_setting_find(const char *name, taper_error *err)
{
    const setting_row *row = row_named(name);
    if (!row) {
        unknown(name, err);
        return NULL;
    }
    taper_ok(err);
    return &row->info;
}

static const char *object_name(taper_setting_object object)
{
    return object == TAPER_SETTING_CHAIN ? "taper_chain_spec" : "taper_solver_spec";
}

const setting_row *setting_row_of(const char *name, taper_setting_object object,
                                  taper_error *err)
{
    const setting_row *row = row_named(name);
    if (!row) {
        unknown(name, err);
        return NULL;
    }
    if (row->info.object != object) {
        taper_fail_field(err, TAPER_EINVAL, row->info.name, "%s is a setting of %s, not of %s",
                         row->info.name, object_name(row->info.object), object_name(object));
        return NULL;
    }
    return row;
}

/* ---- checking a value --------------------------------------------------------- */

/* Shortest %g text that reads back to x: a message shows the value given,
 * not a rounding of it. */
static void format_real(double x, char buf[32])
{
    for (int prec = 6; prec <= 17; prec++) {
        snprintf(buf, 32, "%.*g", prec, x);
        if (strtod(buf, NULL) == x || isnan(x)) return;
    }
}

static int in_range(const taper_setting *s, double x)
{
    int lo = s->min_open ? x > s->min : x >= s->min;
    int hi = s->max_open ? x < s->max : x <= s->max;
    return lo && hi;
}

/* "NAME = VALUE" or "NAME(k) = VALUE" (k >= 1: a list's entry). */
static taper_status out_of_range(const taper_setting *s, size_t k, double x, taper_error *err)
{
    char v[32], lo[32], hi[32];
    format_real(x, v);
    format_real(s->min, lo);
    format_real(s->max, hi);
    taper_fail_field(err, TAPER_EINVAL, s->name, "%s", s->name);
    if (k) taper_fail_append(err, "(%zu)", k);
    taper_fail_append(err, " = %s is out of range %c%s, %s%c", v, s->min_open ? '(' : '[', lo, hi,
                      s->max_open ? ')' : ']');
    if (s->bounds_reason[0]) taper_fail_append(err, ": %s", s->bounds_reason);
    return TAPER_EINVAL;
}

static size_t n_choices(const taper_setting *s)
{
    size_t n = 0;
    while (s->choices[n]) n++;
    return n;
}

taper_status setting_check(const setting_row *row, double value, taper_error *err)
{
    const taper_setting *s = &row->info;
    char v[32]; /* the value as text, written only for a refusal */
    switch (s->type) {
    case TAPER_SETTING_CHOICE: {
        size_t n = n_choices(s);
        if (!(value >= 0 && value < (double)n && value == floor(value))) {
            format_real(value, v);
            taper_fail_field(err, TAPER_EINVAL, s->name, "%s = %s: no such %s (use", s->name, v,
                             s->name);
            for (size_t i = 0; i < n; i++)
                taper_fail_append(err, "%s %zu for '%s'", i ? "," : "", i, s->choices[i]);
            taper_fail_append(err, ")");
            return TAPER_EINVAL;
        }
        return taper_ok(err);
    }
    case TAPER_SETTING_BOOLEAN:
        if (value != 0.0 && value != 1.0) {
            format_real(value, v);
            return taper_fail_field(err, TAPER_EINVAL, s->name, "%s = %s: must be 0 (false) or "
                                    "1 (true)", s->name, v);
        }
        return taper_ok(err);
    case TAPER_SETTING_LIST:
        return taper_fail_field(err, TAPER_EINVAL, s->name, "%s is a list: set it with a list "
                                "of values", s->name);
    case TAPER_SETTING_INTEGER:
        if (in_range(s, value) && value != floor(value)) {
            format_real(value, v);
            return taper_fail_field(err, TAPER_EINVAL, s->name, "%s = %s: must be a whole number",
                                    s->name, v);
        }
        /* fall through */
    case TAPER_SETTING_REAL:
        if (!in_range(s, value)) return out_of_range(s, 0, value, err);
        return taper_ok(err);
    }
    return taper_fail_field(err, TAPER_EINVAL, s->name, "%s: unknown type", s->name);
}

/* ---- storing and reading --------------------------------------------------------- */

static void *at(void *spec, size_t offset) { return (char *)spec + offset; }
static const void *cat(const void *spec, size_t offset) { return (const char *)spec + offset; }

void setting_store(void *spec, const setting_row *row, double value)
{
    void *p = at(spec, row->offset);
    switch (row->storage) {
    case STORE_DOUBLE: *(double *)p = value; break;
    case STORE_SIZE: *(size_t *)p = (size_t)value; break;
    case STORE_INT: *(int *)p = (int)value; break;
    case STORE_LONG: *(long *)p = (long)value; break;
    case STORE_U64: *(uint64_t *)p = (uint64_t)value; break;
    case STORE_LIST: break; /* setting_put_list */
    }
}

double setting_value(const void *spec, const setting_row *row)
{
    if (!spec || row->storage == STORE_LIST) return spec ? NAN : row->info.default_value;
    const void *p = cat(spec, row->offset);
    switch (row->storage) {
    case STORE_DOUBLE: return *(const double *)p;
    case STORE_SIZE: return (double)*(const size_t *)p;
    case STORE_INT: return (double)*(const int *)p;
    case STORE_LONG: return (double)*(const long *)p;
    case STORE_U64: return (double)*(const uint64_t *)p;
    case STORE_LIST: break;
    }
    return NAN;
}

taper_status setting_copy_list(const setting_row *row, const double *values, size_t n,
                               double **copy, taper_error *err)
{
    const taper_setting *s = &row->info;
    *copy = NULL;
    if (n == 0) return taper_ok(err);
    if (!values) return taper_fail_field(err, TAPER_EINVAL, s->name, "%s: NULL with n = %zu",
                                         s->name, n);
    /* More values than a chain has granules could never be used, and would
     * only make the copy absurdly large. */
    if (n > TAPER_N_GRANULES_MAX)
        return taper_fail_field(err, TAPER_EINVAL, s->name, "%s: %zu values, but a chain has at "
                                "most %d granules", s->name, n, TAPER_N_GRANULES_MAX);
    for (size_t k = 1; k <= n; k++)
        if (!in_range(s, values[k - 1])) return out_of_range(s, k, values[k - 1], err);
    double *c = malloc(n * sizeof *c);
    if (!c) return taper_fail(err, TAPER_ENOMEM, "cannot copy %zu values of %s", n, s->name);
    for (size_t k = 0; k < n; k++) c[k] = row->relative ? values[k] / values[0] : values[k];
    if (row->relative) c[0] = 1.0;
    *copy = c;
    return taper_ok(err);
}

void setting_put_list(void *spec, const setting_row *row, double *copy, size_t n)
{
    double **list = at(spec, row->offset);
    free(*list);
    *list = copy;
    *(size_t *)at(spec, row->count_offset) = copy ? n : 0;
}

const double *setting_list(const void *spec, const setting_row *row, size_t *n)
{
    if (n) *n = spec ? *(const size_t *)cat(spec, row->count_offset) : 0;
    return spec ? *(double *const *)cat(spec, row->offset) : NULL;
}

void setting_defaults(void *spec, taper_setting_object object)
{
    for (size_t i = 0; i < taper_setting_n_rows; i++) {
        const setting_row *row = &taper_setting_rows[i];
        if (row->info.object != object) continue;
        if (row->storage == STORE_LIST) {
            *(double **)at(spec, row->offset) = NULL;
            *(size_t *)at(spec, row->count_offset) = 0;
        } else {
            setting_store(spec, row, row->info.default_value);
        }
    }
}

void setting_free_lists(void *spec, taper_setting_object object)
{
    for (size_t i = 0; i < taper_setting_n_rows; i++)
        if (taper_setting_rows[i].info.object == object &&
            taper_setting_rows[i].storage == STORE_LIST)
            setting_put_list(spec, &taper_setting_rows[i], NULL, 0);
}

taper_status setting_null_spec(taper_error *err, const char *function)
{
    return taper_fail(err, TAPER_EINVAL, "%s: spec is NULL", function);
}

/* ---- by name --------------------------------------------------------------------- */

static taper_status set_value(void *spec, taper_setting_object object, const char *function,
                              const char *name, double value, taper_error *err)
{
    if (!spec) return setting_null_spec(err, function);
    const setting_row *row = setting_row_of(name, object, err);
    if (!row) return TAPER_EINVAL;
    taper_status st = setting_check(row, value, err);
    if (st == TAPER_OK) setting_store(spec, row, value);
    return st;
}

/* A choice by name, anything else as a number written out in full. */
static taper_status set_text(void *spec, taper_setting_object object, const char *function,
                             const char *name, const char *text, taper_error *err)
{
    if (!spec) return setting_null_spec(err, function);
    const setting_row *row = setting_row_of(name, object, err);
    if (!row) return TAPER_EINVAL;
    const taper_setting *s = &row->info;
    if (!text) return taper_fail_field(err, TAPER_EINVAL, s->name, "%s: the value is NULL", s->name);
    double value;
    if (s->type == TAPER_SETTING_CHOICE) {
        size_t i = 0;
        taper_status st = taper_name_find(text, s->choices, n_choices(s), s->name, s->name, &i, err);
        if (st != TAPER_OK) return st;
        value = (double)i;
    } else {
        char *end;
        value = strtod(text, &end);
        if (end == text || *end)
            return taper_fail_field(err, TAPER_EINVAL, s->name, "%s = '%s' is not a number",
                                    s->name, text);
    }
    taper_status st = setting_check(row, value, err);
    if (st == TAPER_OK) setting_store(spec, row, value);
    return st;
}

taper_status taper_chain_spec_set_option(taper_chain_spec *spec, const char *name, double value,
                                         taper_error *err)
{
    return set_value(spec, TAPER_SETTING_CHAIN, __func__, name, value, err);
}

taper_status taper_chain_spec_set_option_text(taper_chain_spec *spec, const char *name,
                                              const char *value, taper_error *err)
{
    return set_text(spec, TAPER_SETTING_CHAIN, __func__, name, value, err);
}

taper_status taper_chain_spec_set_option_list(taper_chain_spec *spec, const char *name,
                                              const double *values, size_t n, taper_error *err)
{
    if (!spec) return setting_null_spec(err, __func__);
    const setting_row *row = setting_row_of(name, TAPER_SETTING_CHAIN, err);
    if (!row) return TAPER_EINVAL;
    if (row->storage != STORE_LIST)
        return taper_fail_field(err, TAPER_EINVAL, row->info.name, "%s is a single value, not a "
                                "list", row->info.name);
    double *copy;
    taper_status st = setting_copy_list(row, values, n, &copy, err);
    if (st == TAPER_OK) setting_put_list(spec, row, copy, n);
    return st;
}

taper_status taper_solver_spec_set_option(taper_solver_spec *spec, const char *name, double value,
                                          taper_error *err)
{
    return set_value(spec, TAPER_SETTING_SOLVER, __func__, name, value, err);
}

taper_status taper_solver_spec_set_option_text(taper_solver_spec *spec, const char *name,
                                               const char *value, taper_error *err)
{
    return set_text(spec, TAPER_SETTING_SOLVER, __func__, name, value, err);
}

static double get_value(const void *spec, taper_setting_object object, const char *name)
{
    const setting_row *row = setting_row_of(name, object, NULL);
    return row && row->storage != STORE_LIST ? setting_value(spec, row) : NAN;
}

double taper_chain_spec_option(const taper_chain_spec *spec, const char *name)
{
    return get_value(spec, TAPER_SETTING_CHAIN, name);
}

double taper_solver_spec_option(const taper_solver_spec *spec, const char *name)
{
    return get_value(spec, TAPER_SETTING_SOLVER, name);
}

const double *taper_chain_spec_option_list(const taper_chain_spec *spec, const char *name,
                                           size_t *n)
{
    const setting_row *row = setting_row_of(name, TAPER_SETTING_CHAIN, NULL);
    if (!row || row->storage != STORE_LIST) {
        if (n) *n = 0;
        return NULL;
    }
    return setting_list(spec, row, n);
}
