/*
 * scene.h -- scene files: Fortran namelists describing one taper run.
 *
 * Every input variable is declared once, in the table of scene.c (group,
 * name, type, default, allowed values, one line of documentation).  From
 * that table follow the parser, the validation pass, the resolved-scene echo,
 * `taper --defaults` and `taper --doc`: adding a variable is one table row.
 *
 * Syntax (a subset of Fortran namelist input, so that gfortran can read the
 * shipped scenes too):
 *
 *     ! comment
 *     &chain  profile = 'backward_linear', s = 0.5, n_granules = 200 /
 *     &solver rtol = 1d-10
 *             window = .true. /
 *
 * Names are case-insensitive; strings are quoted ('..' or "..", a doubled
 * quote stands for itself); logicals are .true./.false./T/F/.t./.f.; reals
 * take e or d exponents; values are separated by commas or blanks and may
 * continue on the next line; lists accept repeat counts (3*1.0).
 *
 * Not part of libtaper: the library never reads files.
 */
#ifndef TAPER_SCENE_H
#define TAPER_SCENE_H

#include "taper.h"

#include <stddef.h>
#include <stdio.h>

typedef enum scene_type {
    SCENE_STRING = 0,
    SCENE_REAL = 1,
    SCENE_INTEGER = 2,
    SCENE_LOGICAL = 3,
    SCENE_REAL_LIST = 4
} scene_type;

/* Bits of scene_var.flags. */
#define SCENE_SWEEP 0x1u    /* a real that also accepts a list (a sweep)       */
#define SCENE_LIBDEF 0x2u   /* default taken from taper_solver_spec_init()     */
#define SCENE_LO_OPEN 0x4u  /* lower bound excluded                            */
#define SCENE_HI_OPEN 0x8u  /* upper bound excluded                            */
#define SCENE_POSITIVE 0x10u /* REAL_LIST: every element > 0                   */

/* One row of the variable table. */
typedef struct scene_var {
    const char *group;            /* "chain", "solver", "output", "fit", ...   */
    const char *name;             /* lower case                                */
    scene_type type;
    unsigned flags;
    const char *def;              /* default in namelist syntax; NULL: none
                                     (or SCENE_LIBDEF)                         */
    double lo, hi;                /* REAL/INTEGER range                        */
    const char *const *choices;   /* STRING: allowed values (NULL-terminated),
                                     NULL: any string                          */
    const char *doc;              /* one line                                  */
} scene_var;

/* The groups (chain, solver, output, fit, table, figure), in order. */
size_t scene_group_count(void);
const char *scene_group_name(size_t i);   /* NULL past the end */
const char *scene_group_doc(size_t i);

/* The table, and lookups in it. */
size_t scene_var_count(void);
const scene_var *scene_var_at(size_t i);
/* Index of group/name (case-insensitive) or -1. */
int scene_var_find(const char *group, const char *name);

/* The value of one variable. */
typedef struct scene_value {
    int given;        /* 1 when the file set it                                */
    int line;         /* line of the key in the file (0: default)              */
    char *str;        /* STRING                                                */
    long long ival;   /* INTEGER                                               */
    int bval;         /* LOGICAL                                               */
    double *list;     /* REAL (count 1, or a sweep), REAL_LIST                 */
    size_t count;
} scene_value;

/* One diagnostic.  line 0: no line; group/key empty: none. */
#define SCENE_MSG_SIZE 384
typedef struct scene_diag {
    int line;
    char group[32];
    char key[48];
    char message[SCENE_MSG_SIZE];
} scene_diag;

#define SCENE_MAX_DIAGS 16

typedef struct scene {
    char *path;                  /* file name used in messages               */
    scene_value *values;         /* one per table row                        */
    scene_diag diags[SCENE_MAX_DIAGS];
    size_t n_diags;              /* errors recorded (at most SCENE_MAX_DIAGS) */
    size_t n_errors;             /* errors found (may exceed n_diags)        */
} scene;

/* A scene holding the defaults: table defaults, and for SCENE_LIBDEF rows
 * the values of `lib` (normally from taper_solver_spec_init(); passed in so
 * that this module needs nothing but the table).  path names the scene in
 * messages and derives the default output directory (out/NAME).
 * NULL if out of memory. */
scene *scene_new(const char *path, const taper_solver_spec *lib);
void scene_free(scene *sc);

/* Parses namelist text (len bytes, need not be NUL-terminated) into sc.
 * Returns the number of errors (0: fine).  Stops at the first syntax error;
 * records each problem in sc->diags. */
size_t scene_parse(scene *sc, const char *text, size_t len);
/* Reads and parses sc->path.  Missing, unreadable, binary or huge files are
 * errors like any other. */
size_t scene_load(scene *sc);
/* Checks ranges, allowed strings and the relations between variables
 * (profile vs s/q/radii, forward_linear's N < 1 + 1/s, ...).  Returns the
 * number of errors. */
size_t scene_validate(scene *sc);

/* Prints the diagnostics as FILE:LINE: &group key: message. */
void scene_print_diags(const scene *sc, FILE *fp);

/* Typed access (group/name must exist in the table with that type). */
const scene_value *scene_get(const scene *sc, const char *group, const char *name);
const char *scene_str(const scene *sc, const char *group, const char *name);
double scene_real(const scene *sc, const char *group, const char *name);
long long scene_int(const scene *sc, const char *group, const char *name);
int scene_bool(const scene *sc, const char *group, const char *name);
/* Replaces a string value (e.g. -o DIR).  0 on success, -1 out of memory. */
int scene_set_str(scene *sc, const char *group, const char *name, const char *value);

/* 1 when the optional group (fit, table, figure) is switched on
 * (&fit model != 'none', &table / &figure name non-empty); 1 for the
 * groups every scene has. */
int scene_group_active(const scene *sc, const char *group);

/* The swept variable: its table index, or -1 when no variable has more than
 * one value.  scene_validate rejects sweeps of more than one variable. */
int scene_sweep_var(const scene *sc);

/* Fills the library specs from a validated scene.  sweep_index picks the
 * value of the swept variable (ignored without sweep).  The chain spec
 * points into the scene (radii): keep the scene alive while it is used. */
void scene_chain_spec(const scene *sc, size_t sweep_index, taper_chain_spec *spec);
void scene_solver_spec(const scene *sc, taper_solver_spec *spec);

/* Writes the scene as a namelist (every variable).  With doc != 0 each
 * value gets its table documentation as a comment. */
void scene_write(const scene *sc, FILE *fp, int doc);
/* The scene at one point of its sweep: the swept variable has the value
 * number sweep_index only. */
void scene_write_point(const scene *sc, FILE *fp, size_t sweep_index);
/* Writes the table as Markdown, with the defaults of sc. */
void scene_write_doc(const scene *sc, FILE *fp);

/* Shortest %g text of x that reads back to the same double. */
void scene_format_real(double x, char *buf, size_t size);

#endif
