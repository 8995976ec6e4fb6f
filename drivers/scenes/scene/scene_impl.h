/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * scene_impl.h -- what the scene_*.c files share and nobody else needs:
 * the variable table, the scene object, typed access to a variable's
 * field, diagnostics.
 */
#ifndef TAPER_SCENE_IMPL_H
#define TAPER_SCENE_IMPL_H

#include "scene.h"
#include "util/text.h"

#include <stdarg.h>

#define SCENE_PRINTF(a, b) TEXT_PRINTF(a, b)

/* Limits that keep every input bounded whatever the file holds. */
#define SCENE_MAX_FILE (8u << 20)      /* bytes in a scene file                */
#define SCENE_MAX_LINE 4096            /* characters in one line               */
/* Values in one list, and in all lists of more than one value together
 * (custom radii, sweeps, table values): small enough that the echo of any
 * valid scene, up to 32 bytes a value, fits SCENE_MAX_FILE and reads back
 * (checked at compile time in scene.c). */
#define SCENE_MAX_LIST 250000

/* Bits of scene_var.flags. */
#define SCENE_SWEEP 0x1u      /* REAL or INTEGER: also accepts a list (a sweep;
                                 scene_sweep.c)                                 */
#define SCENE_LO_OPEN 0x2u    /* lower bound excluded                           */
#define SCENE_FROM_PATH 0x8u  /* default derived from the scene's file name     */
#define SCENE_EXTRA 0x20u     /* beyond the paper: the echo leaves it out unless
                                 the scene gives it, so that the paper's scenes
                                 echo as before                                 */
#define SCENE_HI_OPEN 0x40u   /* upper bound excluded                           */
#define SCENE_TIME 0x80u      /* own rows: a time (seconds with &material)      */
#define SCENE_WORDS 0x100u    /* STRING of names separated by blanks or commas:
                                 a list of strings is joined into one, as a
                                 Fortran namelist gives a character array      */

/* One row of the variable table: the scene's own variables (scene.c), and
 * one row per setting of the library's table (taper_setting_at), built
 * from it. */
typedef struct scene_var {
    const char *group;          /* "chain", "solver", "output", "fit", ...     */
    const char *name;           /* the key in its group (lower case): the
                                   variable's keyword without its group's
                                   name in front                              */
    const char *keyword;        /* the variable's one name, unique over all
                                   groups: the Python keyword, the library's
                                   name (taper_error.field)                   */
    scene_type type;
    unsigned flags;
    size_t offset;              /* of the typed field in scene_config          */
    const char *def;            /* default in namelist syntax; NULL: none
                                   (library rows: the library's default)     */
    scene_lib lib;              /* who checks the value                        */
    const char *lib_field;      /* the library's name of it (taper_error.field):
                                   the keyword, or &fit's ("model", "exponent") */
    double lo, hi;              /* range.  SCENE_OWN rows: checked here.
                                   Library rows: the library's row, shown in
                                   the documentation, checked by the library.
                                   lo == hi == 0: none                          */
    const char *const *choices; /* CHOICE: the names, NULL-terminated; value v
                                   is choices[v - choice_first]                */
    int choice_first;           /* CHOICE: the first value (-1: 'none')        */
    taper_dimension dim;        /* the unit its value is given in with
                                   &material (TAPER_DIM_NUMBER: none)          */
    const char *si_unit;        /* own rows always in SI (&material's young,
                                   density, ...): their unit; NULL: dim's     */
    const char *after;          /* own rows: the keyword of the library row
                                   it follows in its group; NULL: at the end  */
    const taper_setting *setting; /* library rows: the library's row         */
    const char *doc;            /* one line                                    */
} scene_var;

/* The profile and the number of granules of a configuration (its first
 * values in a sweep): the scene's checks read them often. */
#define SCENE_PROFILE(cfg) ((taper_profile)scene_setting((cfg), "profile"))
#define SCENE_N_GRANULES(cfg) ((long long)scene_setting((cfg), "n_granules"))
/* Writes a scalar library setting (resolving n_granules from the radii). */
void scene_setting_store(scene_config *cfg, const char *name, double value);

/* The name of choice value v of a CHOICE row; NULL outside its range. */
const char *scene_choice_name(const scene_var *var, int v);

const scene_var *scene_var_at(size_t i);
/* Index of the row of the library's setting (or &fit's) named `field`
 * (taper_error.field), or -1. */
int scene_var_of_field(scene_lib lib, const char *field);

/* The groups (chain, ends, striker, losses, material, solver, sensors,
 * output, fit, table, figure, sweep, calibrate, design), in order. */
#define SCENE_N_GROUPS 14
const char *scene_group_name(size_t i);
const char *scene_group_doc(size_t i);
int scene_group_index(const char *name);

/* Where a variable's value came from. */
typedef struct scene_origin {
    int given;        /* 1: the file (or --set, -o) set it                   */
    int line;         /* line of the key in the file (0: not from the file)  */
} scene_origin;

struct scene {
    char *path;                     /* file name used in messages ("stdin"
                                       for "-")                            */
    int from_stdin;                 /* path "-": scene_load reads stdin    */
    scene_config cfg;               /* every value, typed                  */
    scene_origin *origin;           /* one per table row                   */
    int group_line[SCENE_N_GROUPS]; /* line where each group opens (0: not) */
    int n_from_radii;               /* n_granules resolved from the radii  */
    int samples_kept;               /* scene_keep_samples                   */
    scene_diag *diags;              /* the first SCENE_MAX_DIAGS errors    */
    size_t n_diags;
    size_t n_errors;                /* errors found (may exceed n_diags)   */
};

/* Row i was given by the file (line > 0), --set or -o (line 0). */
void scene_mark_given(scene *sc, size_t i, int line);
/* 1: the library setting of row var was given (scene_config.settings_given). */
int scene_setting_given(const scene_config *cfg, const scene_var *var);

/* Records one error (line 0 / group or key NULL when unknown).  Bytes that
 * are not printable ASCII are shown as \xNN. */
void scene_error(scene *sc, int line, const char *group, const char *key, const char *fmt, ...)
    SCENE_PRINTF(5, 6);
/* Records an error against table row i, at the line its value came from
 * (or, for a value the file left out, the line its group opens). */
void scene_var_error(scene *sc, size_t i, const char *fmt, ...) SCENE_PRINTF(3, 4);
/* Records "unknown group" for &group at line, with every group and the
 * nearest one ("did you mean &sensors?"). */
void scene_unknown_group(scene *sc, int line, const char *group);

/* ---- typed access to a row's field --------------------------------------- */
void *scene_field(scene_config *cfg, const scene_var *var);
const void *scene_cfield(const scene_config *cfg, const scene_var *var);
/* The bytes a row's field occupies (for moving a value between configs). */
size_t scene_field_size(const scene_var *var);
/* Frees what a row's field owns and leaves it empty. */
void scene_field_clear(scene_config *cfg, const scene_var *var);
/* 1: the row's field is a list (REAL_LIST, or s and q). */
int scene_var_is_list(const scene_var *var);
/* The row's index in the table. */
size_t scene_var_index(const scene_var *var);
/* Values of row i: its sweep list (a sweepable row given several values),
 * the list of a list field, or its one value.  scene_row_value: value j as
 * a double (integers exactly up to 2^53). */
size_t scene_row_count(const scene_config *cfg, size_t i);
double scene_row_value(const scene_config *cfg, size_t i, size_t j);
/* Resolves scene_config.runs from the lists (scene_sweep.c): which
 * variables are swept, how many runs; errors for zipped lists of unequal
 * lengths and grids too large. */
void scene_resolve_sweep(scene *sc);
/* The run where swept variable k has its value j and every other swept
 * variable its first (grid), or the j-th run (zip). */
size_t scene_sweep_point_of(const scene_config *cfg, size_t k, size_t j);
/* Index of a CHOICE row's name (case-insensitive) among its values, 0 and
 * the value in *value when found. */
int scene_choice_find(const scene_var *var, const char *name, int *value);

/* "string", "real", ... */
const char *scene_type_name(const scene_var *var);

/* Allowed values of var as text ("[0, 1000]", "(1, 20]", "'adams', 'bdf'"),
 * "" when anything goes.  malloc'd. */
char *scene_range_text(const scene_var *var);
/* The value of var as namelist value text (no key), written to fp. */
void scene_write_value(const scene_var *var, const scene_config *cfg, FILE *fp);

/* The row a library error on `field` of object `lib` is reported against
 * (n_granules resolved from the radii: radii), or -1. */
int scene_error_row(const scene *sc, scene_lib lib, const char *field);

/* Beyond the paper (scene_physics.c): the radii file read (before N is
 * resolved from it), and the scene's own rules of &material, &sensors,
 * &output units and the seed (after the sweep is resolved). */
void scene_read_radii(scene *sc);
void scene_check_physics(scene *sc);

/* Library side (scene_lib.c): the validation of the library's settings
 * through its setters; the number of errors recorded. */
size_t scene_check_library(scene *sc);      /* chain and solver settings */
size_t scene_check_fit_library(scene *sc);  /* &fit as a taper_fit_spec  */

#endif
