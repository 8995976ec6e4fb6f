/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * settings.h -- the rows of the table of settings as the library reads
 * them: the public row (taper_setting) and where its value lives in its
 * spec.  Private to src/settings.
 */
#ifndef TAPER_SETTINGS_SETTINGS_H
#define TAPER_SETTINGS_SETTINGS_H

#include "settings/specs.h"

/* How a value is stored in its spec. */
typedef enum setting_storage {
    STORE_DOUBLE,   /* double                                                  */
    STORE_SIZE,     /* size_t                                                  */
    STORE_INT,      /* int, an enum (CHOICE) or a flag (BOOLEAN)               */
    STORE_LONG,     /* long                                                    */
    STORE_U64,      /* uint64_t                                                */
    STORE_LIST      /* double * (owned) and a size_t count at count_offset     */
} setting_storage;

typedef struct setting_row {
    taper_setting info;
    setting_storage storage;
    size_t offset;          /* of the value in its spec                       */
    size_t count_offset;    /* STORE_LIST: of its count                       */
    int relative;           /* STORE_LIST: stored divided by the first entry  */
} setting_row;

/* The table (table.c), chain rows first; at most SETTING_MAX_ROWS rows. */
#define SETTING_MAX_ROWS 64
extern const setting_row taper_setting_rows[];
extern const size_t taper_setting_n_rows;

/* The names of the enums a CHOICE row takes (names.c), NULL-terminated. */
extern const char *const taper_profile_names[];
extern const char *const taper_disorder_names[];
extern const char *const taper_boundary_names[];
extern const char *const taper_method_names[];

/* settings.c: the row of `name` for a spec of `object`, or NULL with
 * TAPER_EINVAL (an unknown name with the nearest, or the other object's). */
const setting_row *setting_row_of(const char *name, taper_setting_object object,
                                  taper_error *err);
/* Is `value` a value of the row (type and range)?  TAPER_OK, or
 * TAPER_EINVAL naming the row, stating the range and why. */
taper_status setting_check(const setting_row *row, double value, taper_error *err);
/* Stores a value setting_check accepted (not for lists). */
void setting_store(void *spec, const setting_row *row, double value);
/* Checks every entry of a list and makes the copy the spec will own
 * (*copy NULL for n = 0; divided by the first entry for a relative row). */
taper_status setting_copy_list(const setting_row *row, const double *values, size_t n,
                               double **copy, taper_error *err);
/* Installs a copy from setting_copy_list, freeing the spec's old list. */
void setting_put_list(void *spec, const setting_row *row, double *copy, size_t n);
/* The list of a row in spec and its length (NULL, 0 for a NULL spec). */
const double *setting_list(const void *spec, const setting_row *row, size_t *n);
/* The value of a scalar row in spec (its default for a NULL spec). */
double setting_value(const void *spec, const setting_row *row);
/* Every row of `object` at its default (lists empty: the spec owns none). */
void setting_defaults(void *spec, taper_setting_object object);
/* Frees the lists of a spec of `object`. */
void setting_free_lists(void *spec, taper_setting_object object);
/* A typed setter's refusal of a NULL spec. */
taper_status setting_null_spec(taper_error *err, const char *function);

#endif
