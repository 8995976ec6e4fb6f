/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * scene.h -- scene files: Fortran namelists describing one taper run,
 * resolved into a typed configuration.
 *
 * Every input variable is declared once, in the table of scene.c (group,
 * name, type, the field of scene_config it fills, default, range or
 * allowed values, one line of documentation).  From that table follow the
 * parser, the validation, the resolved-scene echo, `taper --defaults` and
 * `taper --doc`.  This module is the only code that knows group and key
 * names: everything downstream reads the fields of scene_config.
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
 * One owner per rule: the scene checks the syntax, the ranges of its own
 * variables (&material, &sensors, &output, &fit, &table, &figure, a radii
 * file) and the relations between them; the chain settings (&chain,
 * &ends, &striker, &losses), the solver's and the fit's exponent are
 * checked by the library's setters and taper_chain_spec_check, whose failing field
 * (taper_error.field) is reported as FILE:LINE: &group key: message.
 *
 * Not part of libtaper: the library never reads files.
 */
#ifndef TAPER_SCENE_H
#define TAPER_SCENE_H

#include "taper.h"

#include <stddef.h>
#include <stdio.h>

/* ---- the typed configuration ---------------------------------------------- */

/* A list of reals (a sweep, radii, the paper's table columns). */
typedef struct scene_reals {
    double *v;
    size_t n;
} scene_reals;

/* Per-granule quantities of &fit x, y and &figure x, y (results/series.c). */
typedef enum scene_quantity {
    SCENE_Q_K = 0,       /* granule number                                    */
    SCENE_Q_V = 1,       /* v_peak; theory: v_k, eq. (9)                       */
    SCENE_Q_T_RES = 2,   /* T_res; theory: T_k, eq. (18)                       */
    SCENE_Q_T = 3,       /* t_pass; theory: t_k, eq. (19)                      */
    SCENE_Q_T_REACH = 4, /* the pulse reaches k: t of k-1                      */
    SCENE_Q_T_PEAK = 5   /* time of v_peak; theory: t_reach                    */
} scene_quantity;

/* &fit report: the tabulated parameter of the fit. */
typedef enum scene_fit_report {
    SCENE_REPORT_A = 0, SCENE_REPORT_B = 1, SCENE_REPORT_C = 2,
    SCENE_REPORT_M = 3, SCENE_REPORT_P = 4, SCENE_REPORT_F = 5
} scene_fit_report;

/* &fit theory: the theory column of a table. */
typedef enum scene_fit_theory {
    SCENE_THEORY_FIT = 0,  /* the same fit of the exact binary-collision theory */
    SCENE_THEORY_RATE = 1, /* |ln A(q)|                                          */
    SCENE_THEORY_F = 2,    /* f(q)                                               */
    SCENE_THEORY_B = 3     /* S/(1+S)                                            */
} scene_fit_theory;

/* &figure curves. */
typedef enum scene_curves {
    SCENE_CURVES_BOTH = 0, SCENE_CURVES_THEORY = 1, SCENE_CURVES_NUMERICS = 2
} scene_curves;

/* &fit model = 'none'; otherwise the model is a taper_fit_model. */
#define SCENE_FIT_NONE (-1)

/* The parameters of a chain's taper that a sweep or a table runs over. */
typedef enum scene_chain_param { SCENE_PARAM_S = 0, SCENE_PARAM_Q = 1 } scene_chain_param;

/* &output units. */
typedef enum scene_units { SCENE_UNITS_RESCALED = 0, SCENE_UNITS_SI = 1 } scene_units;

/* Names as written in scene files (and in result files' headers). */
const char *scene_quantity_name(scene_quantity q);     /* "k", "v", "T_res", ...  */
const char *scene_fit_report_name(scene_fit_report r); /* "a", "b", ...           */
const char *scene_fit_theory_name(scene_fit_theory t); /* "fit", "rate", "f", "b" */
const char *scene_fit_model_name(int model);           /* "none", "power", ...    */
const char *scene_chain_param_name(scene_chain_param p); /* "s", "q"              */
const char *scene_units_name(scene_units u);           /* "rescaled", "si"        */

/* &chain: what the scene itself resolves (the library's settings of the
 * chain are in scene_config.settings, read by scene_setting). */
typedef struct scene_chain_config {
    char *radii_file;       /* "": none; otherwise the path as resolved
                               against the scene file's folder               */
    scene_reals file_radii; /* resolved: the radii read from radii_file (not
                               a table row: not echoed, not limited to
                               SCENE_MAX_LIST)                                */
} scene_chain_config;

/* &striker: radius 0 is the paper's impulse; or a piston pushing granule
 * 1 at the impulse's velocity (docs/physics.md, "Piston"). */
typedef enum scene_piston {
    SCENE_PISTON_NONE = 0,
    SCENE_PISTON_PUSH = 1,    /* for piston_duration                         */
    SCENE_PISTON_STEADY = 2   /* for ever                                    */
} scene_piston;
typedef struct scene_striker_config {
    int piston;                          /* scene_piston                      */
} scene_striker_config;

/* &material: real units (Hertz, n = 5/2).  NaN: not given. */
typedef struct scene_material_config {
    double young, poisson, density;      /* material 1 [Pa], [-], [kg/m^3]   */
    double radius, velocity;             /* R_1 [m], impulse velocity [m/s]  */
    scene_reals other_young, other_poisson, other_density; /* materials 2.. */
    scene_reals sequence;                /* material of granule k:
                                            sequence[(k-1) mod P] (1-based) */
    long long wall;                      /* walls' material; 0: rigid         */
    long long striker;                   /* the striker's material            */
    int on;                              /* resolved: the group is given      */
} scene_material_config;

/* &sensors: time series sampled during the run. */
typedef struct scene_sensors_config {
    double interval;        /* sampling interval; 0: no sampling            */
    scene_reals granules;   /* granules whose v, x, force are recorded      */
    int spacetime;          /* the space-time picture of v(k, t)            */
    long long spacetime_granules; /* at most this many columns (a stride)   */
    long long spacetime_times;    /* at most this many rows (a stride)      */
} scene_sensors_config;

typedef struct scene_solver_config {
    int numerics;           /* 0: the binary-collision theory only            */
} scene_solver_config;

/* The columns of granules.tsv, in the order they are written. */
typedef enum scene_column {
    SCENE_COL_K = 0, SCENE_COL_R, SCENE_COL_M, SCENE_COL_X0,
    SCENE_COL_T_PASS, SCENE_COL_T_RES, SCENE_COL_V_PEAK, SCENE_COL_T_PEAK, SCENE_COL_X_PASS,
    SCENE_COL_THEORY_V, SCENE_COL_THEORY_T, SCENE_COL_THEORY_CUM_T,
    SCENE_N_COLUMNS
} scene_column;
const char *scene_column_name(scene_column c);   /* "k", "R", ..., "theory_t" */
int scene_column_numerics(scene_column c);       /* 1: needs the dynamics      */

typedef struct scene_output_config {
    char *dir;
    int progress;
    long long threads;
    char *columns;          /* names of granules.tsv columns; "": all the run has */
    long long every;        /* rows k = 1, 1 + every, ..., and N              */
    double max_energy_error, max_momentum_error; /* beyond: UNTRUSTED          */
    double max_output;      /* bytes of sampled output a run may write; 0: any */
    int units;              /* scene_units                                    */
    unsigned column_set;    /* resolved: bit c for scene_column c written     */
} scene_output_config;

typedef struct scene_fit_config {
    int model;              /* SCENE_FIT_NONE (the group is off) or a
                               taper_fit_model                                */
    scene_quantity x, y;
    long long k_min, k_max; /* granules; k_max 0: the last with a value        */
    double p;               /* fixed exponent; NaN: not given                 */
    scene_fit_report report;
    double factor;
    char *label;            /* "" : the parameter's name                      */
    scene_fit_theory theory;
} scene_fit_config;

typedef struct scene_table_config {
    char *name;             /* "": no table                                   */
    char *caption;
    long long digits;
    scene_reals paper_theory, paper_numerics;
} scene_table_config;

typedef struct scene_figure_config {
    char *name;             /* "": no figure                                  */
    char *title;
    scene_quantity x, y;
    scene_curves curves;
    int log_x, log_y;
    long long every, k_max;
    char *x_label, *y_label;
    int inset;
    double inset_reference; /* NaN: none                                      */
} scene_figure_config;

/* &sweep: how the lists of several swept variables combine. */
typedef enum scene_sweep_mode {
    SCENE_SWEEP_GRID = 0,      /* every combination (cartesian), the variable
                                  last in the table fastest                   */
    SCENE_SWEEP_ZIP = 1        /* the i-th values together (equal lengths)    */
} scene_sweep_mode;

typedef struct scene_sweep_config {
    scene_sweep_mode mode;
    /* The list given to a sweepable variable whose field holds one value
     * (exponent, n_granules, rtol, ...): one entry per table row, empty
     * unless the scene gives that row more than one value (its field then
     * holds the first).  Integers are stored exactly (|x| <= 2^53).  s and
     * q keep their lists in their own fields.  NULL in a configuration at
     * one point (scene_config_at). */
    scene_reals *lists;
} scene_sweep_config;

/* &calibrate: settings fitted to measurements (drivers/scenes/optimise,
 * docs/calibration.md).  On when data is given. */
typedef struct scene_calibrate_config {
    char *data;             /* the measurements' file; "": no calibration    */
    char *columns;          /* the columns fitted; "": every measured one     */
    char *free;             /* the settings fitted, by name                  */
    scene_reals start, lower, upper; /* one per free setting; empty: the
                               scene's value, the variable's range           */
    scene_reals noise;      /* per fitted column: its noise's deviation      */
    scene_reals weights;    /* per fitted column: relative weights           */
    long long max_iter;     /* trust-region iterations                       */
    double xtol;            /* relative step at convergence                  */
} scene_calibrate_config;

/* &design goal. */
typedef enum scene_design_goal { SCENE_MINIMISE = 0, SCENE_MAXIMISE = 1 } scene_design_goal;
/* &design method. */
typedef enum scene_design_method {
    SCENE_NELDER_MEAD = 0, SCENE_BFGS = 1, SCENE_GRID = 2
} scene_design_method;
/* &design hold: what stays fixed while the free settings change. */
typedef enum scene_design_hold {
    SCENE_HOLD_NONE = 0, SCENE_HOLD_LENGTH = 1, SCENE_HOLD_MASS = 2
} scene_design_hold;

/* &design: a scalar result of the run optimised over settings
 * (drivers/scenes/optimise, docs/optimal-design.md).  On when objective is
 * given. */
typedef struct scene_design_config {
    char *objective;        /* a statistic's name or OBSERVABLE(k); "": none  */
    int goal;               /* scene_design_goal                             */
    char *free;             /* the settings varied, by name                  */
    scene_reals start, lower, upper;
    int method;             /* scene_design_method                           */
    double tolerance;       /* relative to each setting's range              */
    long long max_runs;     /* runs of the optimiser at most                 */
    int hold;               /* scene_design_hold                             */
    scene_reals log_radii;  /* c_j of ln(R_k/R_1) = sum c_j x^j; empty: none */
    long long profile_points; /* points of each cut through the optimum      */
    long long grid;         /* points per real setting of the first, coarse
                               grid; 1: none                                 */
} scene_design_config;

/* At most this many variables swept at once. */
#define SCENE_MAX_SWEPT 16

/* What scene_validate resolves from the values above. */
typedef struct scene_runs {
    size_t n;                  /* runs: the points of the sweep, or 1          */
    int swept;                 /* 1: some variable has more than one value    */
    scene_chain_param sweep;   /* the swept variable when it is s or q alone
                                  (kept for callers of the one-variable sweep) */
    size_t n_swept;            /* variables with more than one value          */
    size_t swept_row[SCENE_MAX_SWEPT]; /* their rows in the variable table,
                                  in table order                              */
    size_t swept_len[SCENE_MAX_SWEPT]; /* their numbers of values            */
    scene_chain_param param;   /* the parameter reports tabulate: q for the
                                  exponential profiles, s otherwise            */
    int fit, table, figure;    /* 1: the optional group is on                  */
} scene_runs;

/* The value of a variable the scene stores for the library: one slot per
 * row of the library's table of settings, typed as the scene variable is
 * (scene_type). */
typedef union scene_slot {
    double real;            /* SCENE_REAL                                     */
    long long integer;      /* SCENE_INTEGER                                  */
    int flag;               /* SCENE_LOGICAL, SCENE_CHOICE                    */
    scene_reals list;       /* SCENE_REAL_LIST                                */
} scene_slot;

/* At most this many library settings (the library's table has about 35). */
#define SCENE_MAX_SETTINGS 64

typedef struct scene_config {
    scene_slot settings[SCENE_MAX_SETTINGS]; /* the library's, by its row   */
    unsigned char settings_given[SCENE_MAX_SETTINGS]; /* 1: the scene gave it
                                   (a value left out is the library's
                                   default, in its units: never converted)  */
    scene_chain_config chain;
    scene_striker_config striker;
    scene_material_config material;
    scene_solver_config solver;
    scene_sensors_config sensors;
    scene_output_config output;
    scene_fit_config fit;
    scene_table_config table;
    scene_figure_config figure;
    scene_sweep_config sweep;
    scene_calibrate_config calibrate;
    scene_design_config design;
    scene_runs runs;
} scene_config;

/* Shortest %g text of x that reads back to the same double (at most 24
 * characters: SCENE_REAL_TEXT holds any).  scene.c. */
#define SCENE_REAL_TEXT 32
void scene_format_real(double x, char buf[SCENE_REAL_TEXT]);

/* ---- the library's settings in a configuration (scene.c) -------------------- */

/* The value of a library setting, by its name in the library's table of
 * settings (taper_setting.name, the variable's name): a real, an integer, a
 * logical (0 or 1) or a choice's index, as a double; for a swept variable
 * its first value (a configuration at one point, scene_config_at, has one).
 * NaN for an unknown name.  The values are as the scene gives them: in SI
 * with &material (scene_apply_chain converts them). */
double scene_setting(const scene_config *cfg, const char *name);
/* A list setting's values (radii, pattern, densities, compliances); an
 * empty list for an unknown name. */
const scene_reals *scene_setting_list(const scene_config *cfg, const char *name);

/* ---- the points of a sweep (scene_sweep.c) ------------------------------------ */

/* The value of s or q at run `point` (its only value without a sweep). */
double scene_param_value(const scene_config *cfg, scene_chain_param p, size_t point);

/* Index into the list of swept variable k (0 <= k < runs.n_swept) at run
 * `point`: grid: the last variable varies fastest; zip: `point`. */
size_t scene_point_index(const scene_config *cfg, size_t point, size_t k);
/* The value of swept variable k at run `point`. */
double scene_swept_value(const scene_config *cfg, size_t point, size_t k);
/* Name of swept variable k ("q", "exponent"), and 1 if it is an integer. */
const char *scene_swept_name(const scene_config *cfg, size_t k);
int scene_swept_integer(const scene_config *cfg, size_t k);
/* The value of swept variable k at `point` as text: %lld for integers,
 * scene_format_real for reals. */
void scene_swept_text(const scene_config *cfg, size_t point, size_t k,
                      char buf[SCENE_REAL_TEXT]);
/* The name of run `point`: "NAME=VALUE" for each swept variable, joined by
 * ',' ("s=0.1", "q=0.05,exponent=2.5"); "" without a sweep.  malloc'd. */
char *scene_point_name(const scene_config *cfg, size_t point);
/* *at = the configuration of the single run `point`: a shallow copy of cfg
 * with every swept variable at that point's value (s and q as a view of
 * one value), sweep.lists NULL.  It shares cfg's strings and lists: it is
 * valid while cfg is, and is never freed. */
void scene_config_at(const scene_config *cfg, size_t point, scene_config *at);

/* ---- materials and units (scene_physics.c) ------------------------------------ */

/* What &material makes of a configuration at one point. */
typedef struct scene_material_props {
    double young, poisson, density; /* granule 1's material (the unit scales)   */
    double wall_compliance;         /* relative to granule 1's; 0: rigid         */
    double striker_density, striker_compliance; /* relative to granule 1's      */
    int mixed;                      /* granules of more than one material         */
} scene_material_props;
/* Fills *p (all zero without &material).  0. */
int scene_material_resolve(const scene_config *cfg, scene_material_props *p);
/* Per-granule densities and compliances (1 - nu^2)/E of a mixed chain of n
 * granules, malloc'd.  0, or -1 out of memory. */
int scene_material_arrays(const scene_config *cfg, size_t n, double **density,
                          double **compliance);
/* The SI value of one rescaled unit of `dim` when the scene writes SI
 * (&output units = 'si'), else 1. */
double scene_unit(const scene_config *cfg, taper_dimension dim);
/* The dimension of a column of granules.tsv: R and X0 are sizes, X_pass
 * a size plus a displacement (its TAPER_DIM_LENGTH), k a number. */
taper_dimension scene_column_dimension(scene_column c);
/* values[0..n) of column c, in place, into the units of cfg's results
 * (&output units): unchanged when rescaled; in SI each times the unit of
 * its dimension, X_pass = X0 + x_k as X0 R_1 + x_k unit_length (rest: X0).
 * The one conversion of granules.tsv and the Python package. */
void scene_column_convert(const scene_config *cfg, scene_column c, double *values,
                          const double *rest, size_t n);
/* "s", "m", ... when the scene writes SI, else NULL. */
const char *scene_unit_suffix(const scene_config *cfg, taper_dimension dim);
/* The SI value of one rescaled unit of `dim` for the inputs of a
 * configuration at one point: with &material every dimensional setting is
 * given in SI (scene_lib.c divides by this); 1 without &material. */
double scene_input_scale(const scene_config *at, taper_dimension dim);
/* &sensors interval of a configuration at one point, in the library's
 * rescaled time (given in seconds with &material). */
double scene_sample_interval(const scene_config *at);

/* ---- reading a scene ---------------------------------------------------------- */

typedef struct scene scene;

/* A scene holding the defaults: the table's, and for the library's
 * settings those of freshly allocated library specs (their getters).  path
 * names the scene in messages and derives the default output directory
 * (out/NAME).  NULL if out of memory. */
scene *scene_new(const char *path);
void scene_free(scene *sc);

/* Parses namelist text (len bytes, need not be NUL-terminated) into sc.
 * Returns the number of errors (0: fine).  Stops at the first syntax
 * error. */
size_t scene_parse(scene *sc, const char *text, size_t len);
/* Reads and parses the scene's file.  Missing, unreadable, binary or huge
 * files are errors like any other. */
size_t scene_load(scene *sc);
/* Overrides one variable from the command line: "group.key=value", the
 * value in namelist syntax (taper --set).  Returns the number of errors. */
size_t scene_set(scene *sc, const char *assignment);
/* A value a program gives a variable (scene_set_values). */
typedef struct scene_value {
    enum { SCENE_VALUE_REAL, SCENE_VALUE_INTEGER, SCENE_VALUE_LOGICAL,
           SCENE_VALUE_STRING } kind;
    double x;               /* REAL                                         */
    long long i;            /* INTEGER                                      */
    int b;                  /* LOGICAL                                      */
    const char *s;          /* STRING (a string or a choice's name)         */
} scene_value;
/* Sets the variable named `keyword` (its one name: scene_var_keyword_at)
 * to n values, checked by type as a file's are (several values: a list, or
 * a sweep of a sweepable variable), in place of its current value, as
 * --set does, lists held to a file's limit (docs/scene.md, "Limits").
 * Returns the number of errors (recorded as diagnostics; line 0). */
size_t scene_set_values(scene *sc, const char *keyword, const scene_value *values, size_t n);
/* The program keeps every sample itself (the Python package's
 * Result.samples): &sensors interval needs no granules, spacetime or wall
 * to be useful. */
void scene_keep_samples(scene *sc);
/* Checks every value and the relations between them (the library's
 * settings through the library's setters, each value of a sweep too), and
 * resolves scene_config.runs.  Returns the number of errors. */
size_t scene_validate(scene *sc);
/* Replaces &output dir (taper -o DIR).  0, or -1 out of memory. */
int scene_set_output_dir(scene *sc, const char *dir);

const char *scene_path(const scene *sc);
const scene_config *scene_cfg(const scene *sc);

/* ---- diagnostics ---------------------------------------------------------------- */

/* One problem: line 0 when there is none, group/key "" when none. */
typedef struct scene_diag {
    int line;
    char *group;
    char *key;
    char *message;
} scene_diag;

/* At most this many diagnostics are kept (the count of all is). */
#define SCENE_MAX_DIAGS 16

size_t scene_error_count(const scene *sc);
size_t scene_diag_count(const scene *sc);
const scene_diag *scene_diag_at(const scene *sc, size_t i);
/* Prints the diagnostics as FILE:LINE: &group key: message. */
void scene_print_diags(const scene *sc, FILE *fp);

/* The line of the variable stored at `offset` in scene_config (0: not in
 * the file), e.g. SCENE_LINE(sc, chain.s). */
int scene_line(const scene *sc, size_t offset);
#define SCENE_LINE(sc, field) scene_line((sc), offsetof(scene_config, field))
/* The same by the variable's name (its keyword: "s", "striker_radius"). */
int scene_line_of(const scene *sc, const char *keyword);

/* Which library object checks a setting. */
typedef enum scene_lib {
    SCENE_OWN = 0,        /* the scene itself                             */
    SCENE_LIB_CHAIN = 1,  /* taper_chain_spec, taper_chain_alloc           */
    SCENE_LIB_SOLVER = 2, /* taper_solver_spec, taper_sim_alloc            */
    SCENE_LIB_FIT = 3     /* taper_fit_spec                                */
} scene_lib;

/* A library failure after validation (taper_chain_alloc's ERANGE,
 * taper_sim_alloc's relations to the chain), printed against the variable
 * err->field names: FILE:LINE: &group key: message.  Without a field that
 * maps to a variable: FILE: message. */
void scene_print_library_error(const scene *sc, scene_lib lib, const taper_error *err,
                               FILE *fp);
/* A problem with the output directory: FILE[:LINE]: &output dir: message. */
void scene_print_output_error(const scene *sc, const char *message, FILE *fp);

/* ---- the library's specifications ------------------------------------------------- */

/* Apply the scene's settings to a library spec through its setters (run
 * `point` of a sweep; scene_apply_solver: a configuration at one point,
 * scene_config_at, for a sweep of solver settings).  On a validated scene these cannot fail, except
 * that taper_sim_alloc and taper_chain_alloc check what needs the chain. */
taper_status scene_apply_chain(const scene_config *cfg, size_t point, taper_chain_spec *spec,
                               taper_error *err);
taper_status scene_apply_solver(const scene_config *cfg, taper_solver_spec *spec,
                                taper_error *err);
/* Allocated specs with the scene's settings (NULL with err on failure). */
taper_chain_spec *scene_chain_spec(const scene_config *cfg, size_t point, taper_error *err);
taper_solver_spec *scene_solver_spec(const scene_config *cfg, taper_error *err);
/* &fit as a library fit spec (model, exponent, granule window); NULL with
 * err without a fit. */
taper_fit_spec *scene_fit_spec(const scene_config *cfg, taper_error *err);

/* ---- writing a scene -------------------------------------------------------------- */

/* Writes the scene as a namelist (every variable of the groups that are
 * on; &sweep only when several variables are swept or its mode is given).  With doc != 0: every group, each value with its documentation as a
 * comment (taper --defaults). */
void scene_write(const scene *sc, FILE *fp, int doc);
/* The scene at one run of its sweep: the swept variable has that value. */
void scene_write_point(const scene *sc, FILE *fp, size_t point);
/* The table as Markdown, with the defaults of sc (taper --doc). */
void scene_write_doc(const scene *sc, FILE *fp);
/* Prints the value of "group.key" in namelist syntax and a newline
 * (taper --get).  0, or -1 for an unknown variable (nothing printed). */
int scene_print_value(const scene *sc, const char *name, FILE *fp);

/* ---- what to cite (scene_cite.c) ------------------------------------------------ */

/* The works the runs of a validated scene rely on, added to the set
 * *works (start from 0; several scenes may add to one set): the paper, and
 * the solvers (SUNDIALS where CVODE integrates, GSL where the theory, rk8 or
 * a fit runs) and contact models (viscoelastic damping, a static load, the
 * decorated chains' effective chain) that some run of it uses.  0, or -1
 * out of memory. */
int scene_cite_mark(const scene *sc, unsigned *works);
/* BibTeX for taper and each work of the set.  0, or -1 on a write error. */
int scene_write_citations(unsigned works, FILE *fp);

/* ---- the table, for generic walkers (tests/bindings/scene_dump.c) ----------------- */

typedef enum scene_type {
    SCENE_STRING = 0,
    SCENE_REAL = 1,       /* one value (SCENE_SWEEP: a list sweeps it)          */
    SCENE_INTEGER = 2,
    SCENE_LOGICAL = 3,
    SCENE_REAL_LIST = 4,
    SCENE_CHOICE = 5      /* one of a list of names, stored as an enum          */
} scene_type;

size_t scene_var_count(void);
const char *scene_var_group(size_t i);
const char *scene_var_name(size_t i);     /* the key in its group          */
const char *scene_var_keyword_at(size_t i); /* the variable's one name: the key,
                                     with the group's name in front where
                                     another group uses the same key
                                     (striker_radius, figure_every)           */
scene_type scene_var_type(size_t i);
/* The row of a variable by its name (keyword, case-insensitive), or -1. */
int scene_var_keyword(const char *keyword);
/* The key of `group`, or the variable's name, nearest to an unknown one
 * (at most two edits: taper_nearest_name), for "did you mean"; NULL if
 * none is that near. */
const char *scene_nearest_key(const char *group, const char *key);
const char *scene_nearest_keyword(const char *keyword);
/* The group nearest to an unknown one (without its '&'), or NULL. */
const char *scene_nearest_group(const char *group);
int scene_var_takes_list(size_t i); /* 1: a list of values sweeps it (s, q,
                                     exponent, n_granules, rtol, ...)         */
/* A choice's allowed names, NULL-terminated, in the order of their values;
 * NULL for a variable that is not a choice. */
const char *const *scene_var_choices(size_t i);
/* The row of `key` in `group` (case-insensitive), or -1: a diagnostic's
 * group and key back to the variable (its keyword). */
int scene_var_find(const char *group, const char *key);
/* What `taper --doc` says of variable i, for programs that list the
 * variables (the Python package's taper.variables()). */
typedef struct scene_var_about {
    const char *description;     /* one line                                   */
    taper_dimension dimension;   /* its unit with &material (TAPER_DIM_NUMBER:
                                    a pure number, the same in every unit, or
                                    a value that is SI in any case)            */
    const char *unit;            /* the SI unit its value is read in with
                                    &material ("s", "Pa", ...); NULL: none    */
    const char *const *choices;  /* CHOICE: its names, NULL-terminated; else
                                    NULL                                        */
    int beyond_paper;            /* 1: not part of the paper's model (the echo
                                    leaves it out unless given)                 */
    scene_lib checked_by;        /* the scene itself, or the library's object  */
} scene_var_about;
/* Fills *about for row i.  0, or -1 past the table's end. */
int scene_var_describe(size_t i, scene_var_about *about);
/* The values row i allows, as --doc writes them ("[0, 1000]", "(0, inf)",
 * "'adams', 'bdf'"; "" when anything goes).  malloc'd; NULL out of memory
 * or past the table's end. */
char *scene_var_range(size_t i);
/* The value of variable i: a string or choice's text; an integer or a
 * logical; the reals of a real (none when a real without default is left
 * out), sweep or list, and the values of an integer given a list (a sweep:
 * exact as doubles; none when it has one value). */
const char *scene_var_text(const scene *sc, size_t i);
long long scene_var_integer(const scene *sc, size_t i);
const double *scene_var_reals(const scene *sc, size_t i, size_t *n);

#endif
