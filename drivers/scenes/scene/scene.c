/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * scene.c -- the table of scene variables, the scene object (typed values
 * and where they came from), and typed access to a row's field.  What is
 * said about a scene (errors, "did you mean") is scene_diag.c's.
 *
 * The table is the only place a variable is declared: one row per setting
 * of the library's table of settings (taper_setting_at: name, group, type,
 * range, default, dimension, description), and below the scene's own
 * variables (&material, &sensors, &output, &fit, &table, &figure, &sweep,
 * and a few of the other groups).  The parser (scene_parse.c), the
 * validation (scene_check.c, scene_lib.c), the echo, --defaults, --doc and
 * --get (scene_write.c) all walk it.  Each row names the field of
 * scene_config it fills, so that resolving is generic.
 *
 * Names: every variable has one name (its keyword: the Python keyword, the
 * library's field), unique over all groups; a scene file writes it inside
 * its group without the group's name in front, if it has it:
 * striker_radius is &striker radius, figure_every is &figure every, load
 * is &chain load.
 */
#include "scene_impl.h"

#include <ctype.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* Choice fields are enums written through int: they must be int-sized. */
_Static_assert(sizeof(taper_profile) == sizeof(int), "enum size");
_Static_assert(sizeof(taper_method) == sizeof(int), "enum size");
_Static_assert(sizeof(scene_quantity) == sizeof(int), "enum size");
_Static_assert(sizeof(scene_fit_report) == sizeof(int), "enum size");
_Static_assert(sizeof(scene_fit_theory) == sizeof(int), "enum size");
_Static_assert(sizeof(scene_curves) == sizeof(int), "enum size");
_Static_assert(sizeof(taper_boundary) == sizeof(int), "enum size");
_Static_assert(sizeof(taper_disorder) == sizeof(int), "enum size");
_Static_assert(sizeof(scene_units) == sizeof(int), "enum size");
_Static_assert(sizeof(scene_design_goal) == sizeof(int), "enum size");
_Static_assert(sizeof(scene_design_method) == sizeof(int), "enum size");
_Static_assert(sizeof(scene_design_hold) == sizeof(int), "enum size");
/* No field is larger than a list (scene_set moves fields through one). */
_Static_assert(sizeof(scene_reals) >= sizeof(double) && sizeof(scene_reals) >= sizeof(long long) &&
               sizeof(scene_reals) >= sizeof(char *) && sizeof(scene_slot) == sizeof(scene_reals),
               "field size");

/* ---- names of the choices -------------------------------------------------- */

#define ENUM_NAME(constant, name) name,
static const char *const pistons[] = {"none", "push", "steady", NULL};
static const char *const fit_models[] = {"none", TAPER_FIT_MODEL_LIST(ENUM_NAME) NULL};
static const char *const quantities[] = {"k", "v", "T_res", "t", "t_reach", "t_peak", NULL};
static const char *const fit_reports[] = {"a", "b", "c", "m", "p", "f", NULL};
static const char *const fit_theories[] = {"fit", "rate", "f", "b", NULL};
static const char *const curves[] = {"both", "theory", "numerics", NULL};
static const char *const chain_params[] = {"s", "q", NULL};
static const char *const sweep_modes[] = {"grid", "zip", NULL};
static const char *const units[] = {"rescaled", "si", NULL};
static const char *const design_goals[] = {"minimise", "maximise", NULL};
static const char *const design_methods[] = {"nelder_mead", "bfgs", "grid", NULL};
static const char *const design_holds[] = {"none", "length", "mass", NULL};
static const char *const columns[SCENE_N_COLUMNS + 1] = {
    "k", "R", "m", "X0", "t_pass", "T_res", "v_peak", "t_peak", "X_pass",
    "theory_v", "theory_T", "theory_t", NULL};

/* names[i] of a NULL-terminated list, NULL past its end. */
static const char *name_at(const char *const *names, int i)
{
    for (int j = 0; j < i; j++)
        if (!names[j]) return NULL;
    return i >= 0 ? names[i] : NULL;
}

const char *scene_column_name(scene_column c) { return name_at(columns, (int)c); }
int scene_column_numerics(scene_column c) { return c >= SCENE_COL_T_PASS && c <= SCENE_COL_X_PASS; }

const char *scene_quantity_name(scene_quantity q) { return name_at(quantities, (int)q); }
const char *scene_fit_report_name(scene_fit_report r) { return name_at(fit_reports, (int)r); }
const char *scene_fit_theory_name(scene_fit_theory t) { return name_at(fit_theories, (int)t); }
const char *scene_chain_param_name(scene_chain_param p) { return name_at(chain_params, (int)p); }
const char *scene_fit_model_name(int model) { return name_at(fit_models, model + 1); }
const char *scene_units_name(scene_units u) { return name_at(units, (int)u); }

const char *scene_choice_name(const scene_var *var, int v)
{
    return var->choices ? name_at(var->choices, v - var->choice_first) : NULL;
}

/* ---- groups ------------------------------------------------------------------ */

/* The groups, in the order they are written and documented. */
static const char *const groups[SCENE_N_GROUPS][2] = {
    {"chain", "the granular chain: radius profile, size, contact law, disorder, static load"},
    {"ends", "what holds the chain at each end: nothing (free) or a wall"},
    {"striker", "a striker (granule 0) hitting granule 1, or a piston pushing it, instead of "
                "the paper's impulse"},
    {"losses", "dissipation: viscoelastic contacts and drag"},
    {"material", "real units (Hertz contacts, n = 5/2): materials, R_1 and the impact velocity"},
    {"solver", "the integration of the equations of motion (CVODE)"},
    {"sensors", "time series sampled during the run: chosen granules, wall forces, v(k, t)"},
    {"output", "where and how results are written"},
    {"fit", "a fit applied to every run of the scene, to numerics and theory alike"},
    {"table", "a table of the fitted parameter over the sweep, next to the paper's values"},
    {"figure", "a figure: per-granule data of every run, and the fit as an inset"},
    {"sweep", "how the lists of several swept variables combine into runs"},
    {"calibrate", "settings fitted to measurements: nonlinear least squares over runs of the "
                  "scene (docs/calibration.md)"},
    {"design", "a result of the run minimised or maximised over settings within bounds "
               "(docs/optimal-design.md)"},
};

const char *scene_group_name(size_t i) { return i < SCENE_N_GROUPS ? groups[i][0] : NULL; }
const char *scene_group_doc(size_t i) { return i < SCENE_N_GROUPS ? groups[i][1] : NULL; }

int scene_group_index(const char *name)
{
    for (size_t i = 0; i < SCENE_N_GROUPS; i++)
        if (strcmp(groups[i][0], name) == 0) return (int)i;
    return -1;
}

/* ---- the table ----------------------------------------------------------------- */

#define AT(field) offsetof(scene_config, field)

/* The scene's own variables.  Their bounds are generous but finite: a
 * number outside them is a typo, not a physics question.  Each sits in its
 * group after the library's settings of that group, or after the one its
 * `after` names. */
static const scene_var own[] = {
    {.group = "chain", .keyword = "radii_file", .type = SCENE_STRING, .flags = SCENE_EXTRA,
     .offset = AT(chain.radii_file), .def = "''", .lib = SCENE_OWN, .after = "radii",
     .doc = "custom profile only, instead of radii: a text file with one radius per line ('#' "
            "starts a comment), its path relative to the scene file; any number of granules"},

    {.group = "striker", .keyword = "piston", .type = SCENE_CHOICE, .flags = SCENE_EXTRA,
     .offset = AT(striker.piston), .lib = SCENE_OWN, .choices = pistons,
     .after = "striker_compliance",
     .doc = "'none', or a piston touching granule 1 (at rest) that moves at unit velocity: "
            "'push' for piston_duration, then stops; 'steady' for ever (not with a striker, a "
            "left wall or a load). The energy budget adds up to its work (docs/physics.md, "
            "\"Piston\")"},

    {.group = "material", .keyword = "young", .si_unit = "Pa", .type = SCENE_REAL,
     .flags = SCENE_LO_OPEN | SCENE_SWEEP | SCENE_EXTRA, .offset = AT(material.young),
     .lib = SCENE_OWN, .lo = 0, .hi = INFINITY,
     .doc = "Young's modulus E of material 1 [Pa] (e.g. 193e9, stainless steel); the group "
            "needs young, poisson, density, radius, velocity"},
    {.group = "material", .keyword = "poisson", .type = SCENE_REAL,
     .flags = SCENE_LO_OPEN | SCENE_HI_OPEN | SCENE_SWEEP | SCENE_EXTRA,
     .offset = AT(material.poisson), .lib = SCENE_OWN, .lo = -1, .hi = 0.5,
     .doc = "Poisson ratio nu of material 1"},
    {.group = "material", .keyword = "density", .si_unit = "kg/m^3", .type = SCENE_REAL,
     .flags = SCENE_LO_OPEN | SCENE_SWEEP | SCENE_EXTRA, .offset = AT(material.density),
     .lib = SCENE_OWN, .lo = 0, .hi = INFINITY,
     .doc = "density of material 1 [kg/m^3]"},
    {.group = "material", .keyword = "radius", .si_unit = "m", .type = SCENE_REAL,
     .flags = SCENE_LO_OPEN | SCENE_SWEEP | SCENE_EXTRA, .offset = AT(material.radius),
     .lib = SCENE_OWN, .lo = 0, .hi = INFINITY,
     .doc = "radius R_1 of granule 1 [m] (every length of the scene is relative to it)"},
    {.group = "material", .keyword = "velocity", .si_unit = "m/s", .type = SCENE_REAL,
     .flags = SCENE_LO_OPEN | SCENE_SWEEP | SCENE_EXTRA, .offset = AT(material.velocity),
     .lib = SCENE_OWN, .lo = 0, .hi = INFINITY,
     .doc = "velocity of the impulse given to granule 1, or of the striker [m/s]"},
    {.group = "material", .keyword = "other_young", .si_unit = "Pa", .type = SCENE_REAL_LIST,
     .flags = SCENE_LO_OPEN | SCENE_EXTRA, .offset = AT(material.other_young), .lib = SCENE_OWN,
     .lo = 0, .hi = INFINITY,
     .doc = "mixed chains: Young's moduli of materials 2, 3, ... [Pa]"},
    {.group = "material", .keyword = "other_poisson", .type = SCENE_REAL_LIST,
     .flags = SCENE_LO_OPEN | SCENE_HI_OPEN | SCENE_EXTRA, .offset = AT(material.other_poisson),
     .lib = SCENE_OWN, .lo = -1, .hi = 0.5,
     .doc = "Poisson ratios of materials 2, 3, ..."},
    {.group = "material", .keyword = "other_density", .si_unit = "kg/m^3", .type = SCENE_REAL_LIST,
     .flags = SCENE_LO_OPEN | SCENE_EXTRA, .offset = AT(material.other_density), .lib = SCENE_OWN,
     .lo = 0, .hi = INFINITY,
     .doc = "densities of materials 2, 3, ... [kg/m^3]"},
    {.group = "material", .keyword = "sequence", .type = SCENE_REAL_LIST, .flags = SCENE_EXTRA,
     .offset = AT(material.sequence), .lib = SCENE_OWN, .lo = 1, .hi = 1000,
     .doc = "the material of granules 1, 2, ..., repeated along the chain (e.g. 1, 2: "
            "alternating); left out: material 1 throughout"},
    {.group = "material", .keyword = "wall", .type = SCENE_INTEGER, .flags = SCENE_EXTRA,
     .offset = AT(material.wall), .def = "0", .lib = SCENE_OWN, .lo = 0, .hi = 1000,
     .doc = "the walls' material (&ends); 0: rigid"},
    {.group = "material", .keyword = "striker", .type = SCENE_INTEGER, .flags = SCENE_EXTRA,
     .offset = AT(material.striker), .def = "1", .lib = SCENE_OWN, .lo = 1, .hi = 1000,
     .doc = "the striker's material (&striker)"},

    {.group = "solver", .keyword = "numerics", .type = SCENE_LOGICAL,
     .offset = AT(solver.numerics), .def = ".true.", .lib = SCENE_OWN,
     .doc = "integrate the dynamics; .false.: binary-collision theory only (fast)"},

    {.group = "sensors", .keyword = "interval", .type = SCENE_REAL,
     .flags = SCENE_SWEEP | SCENE_EXTRA | SCENE_TIME, .offset = AT(sensors.interval), .def = "0",
     .lib = SCENE_OWN, .lo = 0, .hi = INFINITY,
     .doc = "sampling interval (a time: in s with &material) of the sensors (DIR/sensors.tsv), the wall "
            "forces (DIR/walls.tsv) and the space-time picture; 0: no sampling"},
    {.group = "sensors", .keyword = "granules", .type = SCENE_REAL_LIST, .flags = SCENE_EXTRA,
     .offset = AT(sensors.granules), .lib = SCENE_OWN, .lo = 1, .hi = TAPER_N_GRANULES_MAX,
     .doc = "granules whose displacement x, velocity v and contact forces are written to "
            "DIR/sensors.tsv at every sample"},
    {.group = "sensors", .keyword = "spacetime", .type = SCENE_LOGICAL, .flags = SCENE_EXTRA,
     .offset = AT(sensors.spacetime), .def = ".false.", .lib = SCENE_OWN,
     .doc = "the space-time picture of v(k, t): DIR/spacetime.tsv and DIR/spacetime.png "
            "(gnuplot)"},
    {.group = "sensors", .keyword = "spacetime_granules", .type = SCENE_INTEGER,
     .flags = SCENE_EXTRA, .offset = AT(sensors.spacetime_granules), .def = "200",
     .lib = SCENE_OWN, .lo = 2, .hi = 100000,
     .doc = "at most this many granules across the picture: every ceil(N / this)-th granule"},
    {.group = "sensors", .keyword = "spacetime_times", .type = SCENE_INTEGER, .flags = SCENE_EXTRA,
     .offset = AT(sensors.spacetime_times), .def = "500", .lib = SCENE_OWN, .lo = 2, .hi = 1000000,
     .doc = "at most this many times down the picture: whenever more samples come, every other "
            "row is dropped (the picture's interval doubles)"},

    {.group = "output", .keyword = "dir", .type = SCENE_STRING, .flags = SCENE_FROM_PATH,
     .offset = AT(output.dir), .lib = SCENE_OWN,
     .doc = "output directory, created if missing (default out/NAME for scene NAME.nml; -o "
            "overrides)"},
    {.group = "output", .keyword = "progress", .type = SCENE_LOGICAL,
     .offset = AT(output.progress), .def = ".true.", .lib = SCENE_OWN,
     .doc = "show a progress line on stderr when it is a terminal"},
    {.group = "output", .keyword = "threads", .type = SCENE_INTEGER, .offset = AT(output.threads),
     .def = "0", .lib = SCENE_OWN, .lo = 0, .hi = 256,
     .doc = "runs of a sweep, or of a calibration's or a design's batch, computed at once "
            "(results identical to one at a time); 0: one per core"},
    {.group = "output", .keyword = "columns", .type = SCENE_STRING, .flags = SCENE_WORDS,
     .offset = AT(output.columns), .def = "''", .lib = SCENE_OWN,
     .doc = "columns of granules.tsv and sweep.tsv, names separated by blanks or commas in "
            "one string or a list of strings, "
            "written in the file's order with k always first (e.g. 'v_peak theory_v'); empty: "
            "every column the run has (without numerics: k R m X0 theory_v theory_T theory_t)"},
    {.group = "output", .keyword = "every", .type = SCENE_INTEGER, .offset = AT(output.every),
     .def = "1", .lib = SCENE_OWN, .lo = 1, .hi = 1e7,
     .doc = "write the rows of granules k = 1, 1 + every, 1 + 2 every, ... and the last"},
    {.group = "output", .keyword = "max_energy_error", .type = SCENE_REAL, .flags = SCENE_LO_OPEN,
     .offset = AT(output.max_energy_error), .def = "1e-3", .lib = SCENE_OWN, .lo = 0, .hi = 1e300,
     .doc = "a run whose relative energy error exceeds this is UNTRUSTED: its granules.tsv says"
            " so and taper exits with status 4"},
    {.group = "output", .keyword = "max_momentum_error", .type = SCENE_REAL,
     .flags = SCENE_LO_OPEN, .offset = AT(output.max_momentum_error), .def = "1e-3",
     .lib = SCENE_OWN, .lo = 0, .hi = 1e300,
     .doc = "the same bound on the relative momentum error"},
    {.group = "output", .keyword = "max_output", .type = SCENE_REAL, .flags = SCENE_EXTRA,
     .offset = AT(output.max_output), .def = "1e9", .lib = SCENE_OWN, .lo = 0, .hi = 1e18,
     .doc = "bytes: a run whose sampled files (sensors.tsv, walls.tsv; in Python the samples' "
            "memory) would take more by the estimate made before it is refused, saying the "
            "estimate; 0: no limit"},
    {.group = "output", .keyword = "units", .type = SCENE_CHOICE, .flags = SCENE_EXTRA,
     .offset = AT(output.units), .def = "'rescaled'", .lib = SCENE_OWN, .choices = units,
     .doc = "units of the result files: 'rescaled' (eq. (5) of arXiv:0905.4512), or 'si' (needs"
            " &material; each column's unit in its header, e.g. t_pass[s])"},

    {.group = "fit", .keyword = "fit_model", .type = SCENE_CHOICE, .offset = AT(fit.model),
     .def = "'none'", .lib = SCENE_LIB_FIT, .lib_field = "model", .choices = fit_models,
     .choice_first = -1,
     .doc = "'none' (no fit), or y = 'power' a x^b, 'exponential' a e^(b x), 'divergence_b' a "
            "(1 - b x)^-p, 'divergence_c' a (1 - x/C)^-p, 'divergence_m' a (1 + x/M)^-f; fitted"
            " to ln y; writes DIR/fits.tsv"},
    {.group = "fit", .keyword = "fit_x", .type = SCENE_CHOICE, .offset = AT(fit.x), .def = "'k'",
     .lib = SCENE_OWN, .choices = quantities,
     .doc = "abscissa: k (granule), v (numerics: v_peak; theory: v_k, eq. (9)), T_res (T_res; "
            "T_k), t (pulse passes k: t_pass; eq. (19)), t_reach (pulse reaches k: t of k-1), "
            "t_peak (time of v_peak; theory: t_reach, when k leaves its collision with k-1)"},
    {.group = "fit", .keyword = "fit_y", .type = SCENE_CHOICE, .offset = AT(fit.y), .def = "'v'",
     .lib = SCENE_OWN, .choices = quantities,
     .doc = "ordinate, one of the quantities of x"},
    {.group = "fit", .keyword = "fit_k_min", .type = SCENE_INTEGER, .offset = AT(fit.k_min),
     .def = "1", .lib = SCENE_OWN, .lo = 1, .hi = 1e7,
     .doc = "first granule of the fit window"},
    {.group = "fit", .keyword = "fit_k_max", .type = SCENE_INTEGER, .offset = AT(fit.k_max),
     .def = "0", .lib = SCENE_OWN, .lo = 0, .hi = 1e7,
     .doc = "last granule of the fit window; 0: the last granule with a value"},
    {.group = "fit", .keyword = "fit_p", .type = SCENE_REAL, .flags = SCENE_LO_OPEN,
     .offset = AT(fit.p), .lib = SCENE_LIB_FIT, .lib_field = "exponent", .lo = 0, .hi = INFINITY,
     .doc = "fixed exponent p of divergence_b and divergence_c; left out: 3/2 (divergence_b), "
            "fitted (divergence_c)"},
    {.group = "fit", .keyword = "fit_report", .type = SCENE_CHOICE, .offset = AT(fit.report),
     .def = "'b'", .lib = SCENE_OWN, .choices = fit_reports,
     .doc = "the parameter tabulated: a or b (power, exponential, divergence_b), p "
            "(divergence_b, _c), c (divergence_c), m or f (divergence_m)"},
    {.group = "fit", .keyword = "fit_factor", .type = SCENE_REAL, .offset = AT(fit.factor),
     .def = "1", .lib = SCENE_OWN, .lo = -1e3, .hi = 1e3,
     .doc = "the tabulated value is factor * parameter (e.g. -1: a decay rate from b < 0)"},
    {.group = "fit", .keyword = "fit_label", .type = SCENE_STRING, .offset = AT(fit.label),
     .def = "''", .lib = SCENE_OWN,
     .doc = "name of the tabulated value in tables and plots; empty: the parameter's name"},
    {.group = "fit", .keyword = "fit_theory", .type = SCENE_CHOICE, .offset = AT(fit.theory),
     .def = "'fit'", .lib = SCENE_OWN, .choices = fit_theories,
     .doc = "theory column: 'fit' (the same fit of the exact binary-collision theory), or the "
            "closed form: 'rate' |ln A(q)|, 'f' f(q) (q -> -q for forward chains), 'b' S/(1+S)"},

    {.group = "table", .keyword = "table_name", .type = SCENE_STRING, .offset = AT(table.name),
     .def = "''", .lib = SCENE_OWN,
     .doc = "table label (e.g. 'Table I'); non-empty: write DIR/table.tsv and print the table"},
    {.group = "table", .keyword = "table_caption", .type = SCENE_STRING,
     .offset = AT(table.caption), .def = "''", .lib = SCENE_OWN,
     .doc = "one line printed above the table"},
    {.group = "table", .keyword = "table_digits", .type = SCENE_INTEGER,
     .offset = AT(table.digits), .def = "4", .lib = SCENE_OWN, .lo = 1, .hi = 12,
     .doc = "decimals printed on stdout (table.tsv has every digit)"},
    {.group = "table", .keyword = "table_paper_theory", .type = SCENE_REAL_LIST,
     .offset = AT(table.paper_theory), .lib = SCENE_OWN,
     .doc = "the paper's theory column, one value per swept value"},
    {.group = "table", .keyword = "table_paper_numerics", .type = SCENE_REAL_LIST,
     .offset = AT(table.paper_numerics), .lib = SCENE_OWN,
     .doc = "the paper's numerics column, one value per swept value"},

    {.group = "figure", .keyword = "figure_name", .type = SCENE_STRING, .offset = AT(figure.name),
     .def = "''", .lib = SCENE_OWN,
     .doc = "figure label (e.g. 'Fig. 1'); non-empty: write DIR/figure.gp, its data, and "
            "DIR/figure.png when gnuplot is installed"},
    {.group = "figure", .keyword = "figure_title", .type = SCENE_STRING,
     .offset = AT(figure.title), .def = "''", .lib = SCENE_OWN,
     .doc = "title line of the plot"},
    {.group = "figure", .keyword = "figure_x", .type = SCENE_CHOICE, .offset = AT(figure.x),
     .def = "'k'", .lib = SCENE_OWN, .choices = quantities,
     .doc = "abscissa of the main panel (quantities as for &fit x)"},
    {.group = "figure", .keyword = "figure_y", .type = SCENE_CHOICE, .offset = AT(figure.y),
     .def = "'v'", .lib = SCENE_OWN, .choices = quantities,
     .doc = "ordinate of the main panel"},
    {.group = "figure", .keyword = "figure_curves", .type = SCENE_CHOICE,
     .offset = AT(figure.curves), .def = "'both'", .lib = SCENE_OWN, .choices = curves,
     .doc = "series drawn: theory (open circles), numerics (filled circles), or both"},
    {.group = "figure", .keyword = "figure_log_x", .type = SCENE_LOGICAL,
     .offset = AT(figure.log_x), .def = ".false.", .lib = SCENE_OWN,
     .doc = "logarithmic x axis"},
    {.group = "figure", .keyword = "figure_log_y", .type = SCENE_LOGICAL,
     .offset = AT(figure.log_y), .def = ".false.", .lib = SCENE_OWN,
     .doc = "logarithmic y axis"},
    {.group = "figure", .keyword = "figure_every", .type = SCENE_INTEGER,
     .offset = AT(figure.every), .def = "1", .lib = SCENE_OWN, .lo = 1, .hi = 1e6,
     .doc = "draw every n-th granule (the first and every n-th after it)"},
    {.group = "figure", .keyword = "figure_k_max", .type = SCENE_INTEGER,
     .offset = AT(figure.k_max), .def = "0", .lib = SCENE_OWN, .lo = 0, .hi = 1e7,
     .doc = "last granule drawn; 0: the whole chain"},
    {.group = "figure", .keyword = "figure_x_label", .type = SCENE_STRING,
     .offset = AT(figure.x_label), .def = "''", .lib = SCENE_OWN,
     .doc = "x axis label; empty: from x"},
    {.group = "figure", .keyword = "figure_y_label", .type = SCENE_STRING,
     .offset = AT(figure.y_label), .def = "''", .lib = SCENE_OWN,
     .doc = "y axis label; empty: from y"},
    {.group = "figure", .keyword = "figure_inset", .type = SCENE_LOGICAL,
     .offset = AT(figure.inset), .def = ".false.", .lib = SCENE_OWN,
     .doc = "an inset inside the main panel (as the paper's Figs. 1, 2, 9): the &fit value of "
            "theory and numerics against the swept variable"},
    {.group = "figure", .keyword = "figure_inset_reference", .type = SCENE_REAL,
     .offset = AT(figure.inset_reference), .lib = SCENE_OWN, .lo = -1e3, .hi = 1e3,
     .doc = "a horizontal line in the inset (e.g. an asymptotic exponent); left out: none"},

    {.group = "sweep", .keyword = "sweep_mode", .type = SCENE_CHOICE, .offset = AT(sweep.mode),
     .def = "'grid'", .lib = SCENE_OWN, .choices = sweep_modes,
     .doc = "several variables given lists: 'grid' runs every combination (the variable later "
            "in this table varies fastest), 'zip' the i-th values together (lists of equal "
            "length)"},

    {.group = "calibrate", .keyword = "calibrate_data", .type = SCENE_STRING,
     .flags = SCENE_EXTRA, .offset = AT(calibrate.data), .def = "''", .lib = SCENE_OWN,
     .doc = "measurements to fit, its path relative to the scene file: a table as taper writes "
            "sensors.tsv (t, granule, x, v, f_left, f_right, force), walls.tsv (t, force_left, "
            "force_right) or granules.tsv (k, t_pass, T_res, v_peak, t_peak, X_pass), any subset "
            "of its rows and columns: column names on the first line with their units as taper "
            "writes them with &material (t[s], force[N]; none: rescaled units), '#' comments; "
            "given: the scene is a calibration (DIR/calibration.tsv, docs/calibration.md)"},
    {.group = "calibrate", .keyword = "calibrate_columns", .type = SCENE_STRING,
     .flags = SCENE_EXTRA | SCENE_WORDS, .offset = AT(calibrate.columns), .def = "''",
     .lib = SCENE_OWN,
     .doc = "the measured columns fitted, names separated by blanks or commas in one string or "
            "a list of strings (e.g. 'force'); "
            "empty: every measured column of the data"},
    {.group = "calibrate", .keyword = "calibrate_free", .type = SCENE_STRING,
     .flags = SCENE_EXTRA | SCENE_WORDS, .offset = AT(calibrate.free), .def = "''",
     .lib = SCENE_OWN,
     .doc = "the settings fitted, names separated by blanks or commas in one string or a list "
            "of strings: any real variable by its name or GROUP.KEY ('young damping', "
            "'material.young', 'losses.damping'), an element "
            "of a real list as NAME(i) ('pattern(2)')"},
    {.group = "calibrate", .keyword = "calibrate_start", .type = SCENE_REAL_LIST,
     .flags = SCENE_EXTRA, .offset = AT(calibrate.start), .lib = SCENE_OWN,
     .doc = "starting values, one per free setting, each in its variable's unit (SI with "
            "&material); left out: the scene's values"},
    {.group = "calibrate", .keyword = "calibrate_lower", .type = SCENE_REAL_LIST,
     .flags = SCENE_EXTRA, .offset = AT(calibrate.lower), .lib = SCENE_OWN,
     .doc = "lower bounds, one per free setting (-inf: none); left out: each variable's range"},
    {.group = "calibrate", .keyword = "calibrate_upper", .type = SCENE_REAL_LIST,
     .flags = SCENE_EXTRA, .offset = AT(calibrate.upper), .lib = SCENE_OWN,
     .doc = "upper bounds, one per free setting (inf: none); left out: each variable's range"},
    {.group = "calibrate", .keyword = "calibrate_noise", .type = SCENE_REAL_LIST,
     .flags = SCENE_LO_OPEN | SCENE_EXTRA, .offset = AT(calibrate.noise), .lib = SCENE_OWN,
     .lo = 0, .hi = INFINITY,
     .doc = "standard deviation of each fitted column's noise, in its unit (one value: every "
            "column): residuals are divided by it and the standard errors are absolute; left "
            "out: residuals relative to each column's peak, errors scaled by sqrt(chi2/dof)"},
    {.group = "calibrate", .keyword = "calibrate_weights", .type = SCENE_REAL_LIST,
     .flags = SCENE_LO_OPEN | SCENE_EXTRA, .offset = AT(calibrate.weights), .lib = SCENE_OWN,
     .lo = 0, .hi = INFINITY,
     .doc = "instead of noise: relative weight of each fitted column (one value: every "
            "column), multiplying its squared residuals relative to its peak"},
    {.group = "calibrate", .keyword = "calibrate_max_iter", .type = SCENE_INTEGER,
     .flags = SCENE_EXTRA, .offset = AT(calibrate.max_iter), .def = "50", .lib = SCENE_OWN,
     .lo = 1, .hi = 10000,
     .doc = "trust-region iterations at most; a fit that needs more has not converged (exit "
            "status 6)"},
    {.group = "calibrate", .keyword = "calibrate_xtol", .type = SCENE_REAL,
     .flags = SCENE_LO_OPEN | SCENE_EXTRA, .offset = AT(calibrate.xtol), .def = "1e-8",
     .lib = SCENE_OWN, .lo = 0, .hi = 0.1,
     .doc = "converged when no setting moves by more than this, relative to its value, in an "
            "iteration"},

    {.group = "design", .keyword = "design_objective", .type = SCENE_STRING, .flags = SCENE_EXTRA,
     .offset = AT(design.objective), .def = "''", .lib = SCENE_OWN,
     .doc = "the result optimised: a statistic of the run by its name in granules.tsv's header "
            "(wall_peak_force_right, energy_transmitted, energy_in_chain, ...), or a granule's "
            "observable as NAME(k) (v_peak(20), t_pass(20)); given: the scene is a design "
            "(DIR/design.tsv, docs/optimal-design.md)"},
    {.group = "design", .keyword = "design_goal", .type = SCENE_CHOICE, .flags = SCENE_EXTRA,
     .offset = AT(design.goal), .def = "'minimise'", .lib = SCENE_OWN, .choices = design_goals,
     .doc = "'minimise' or 'maximise' the objective"},
    {.group = "design", .keyword = "design_free", .type = SCENE_STRING,
     .flags = SCENE_EXTRA | SCENE_WORDS, .offset = AT(design.free), .def = "''", .lib = SCENE_OWN,
     .doc = "the settings varied, names as for &calibrate free; an integer setting "
            "(n_granules) is scanned over every value from lower to upper, the others "
            "optimised at each"},
    {.group = "design", .keyword = "design_start", .type = SCENE_REAL_LIST, .flags = SCENE_EXTRA,
     .offset = AT(design.start), .lib = SCENE_OWN,
     .doc = "starting values, one per free setting; left out: the scene's values"},
    {.group = "design", .keyword = "design_lower", .type = SCENE_REAL_LIST, .flags = SCENE_EXTRA,
     .offset = AT(design.lower), .lib = SCENE_OWN,
     .doc = "lower bounds, one per free setting (finite: they set the optimiser's scale)"},
    {.group = "design", .keyword = "design_upper", .type = SCENE_REAL_LIST, .flags = SCENE_EXTRA,
     .offset = AT(design.upper), .lib = SCENE_OWN,
     .doc = "upper bounds, one per free setting (finite)"},
    {.group = "design", .keyword = "design_grid", .type = SCENE_INTEGER, .flags = SCENE_EXTRA,
     .offset = AT(design.grid), .def = "5", .lib = SCENE_OWN, .lo = 1, .hi = 1001,
     .doc = "points per real setting of a coarse grid run first, all at once, lower to upper "
            "(at most 10000 points in all); the optimiser starts from the best of them and the "
            "start: a local method finds the optimum of the basin it starts in, the grid picks "
            "the basin; 1: start at the start alone"},
    {.group = "design", .keyword = "design_method", .type = SCENE_CHOICE, .flags = SCENE_EXTRA,
     .offset = AT(design.method), .def = "'nelder_mead'", .lib = SCENE_OWN,
     .choices = design_methods,
     .doc = "'nelder_mead' (GSL's nmsimplex2: no derivatives), 'bfgs' (GSL's vector_bfgs2, "
            "the gradient by finite differences, its runs in parallel), each from the best point "
            "of the coarse grid; or 'grid': the grid alone, its best point the answer (a scan)"},
    {.group = "design", .keyword = "design_tolerance", .type = SCENE_REAL,
     .flags = SCENE_LO_OPEN | SCENE_EXTRA, .offset = AT(design.tolerance), .def = "1e-3",
     .lib = SCENE_OWN, .lo = 0, .hi = 0.5,
     .doc = "converged when the simplex (Nelder-Mead) or the last step (BFGS) is smaller than "
            "this fraction of each setting's range, upper - lower"},
    {.group = "design", .keyword = "design_max_runs", .type = SCENE_INTEGER, .flags = SCENE_EXTRA,
     .offset = AT(design.max_runs), .def = "1000", .lib = SCENE_OWN, .lo = 1, .hi = 10000000,
     .doc = "runs the optimiser may make at most (each value of a scanned integer: its own); "
            "an optimiser that needs more has not converged (exit status 6)"},
    {.group = "design", .keyword = "design_hold", .type = SCENE_CHOICE, .flags = SCENE_EXTRA,
     .offset = AT(design.hold), .def = "'none'", .lib = SCENE_OWN, .choices = design_holds,
     .doc = "held at the scene's value while the free settings change, by scaling &material "
            "radius (R_1, and radii or pattern with it; the striker keeps its size): 'length' "
            "(the chain's sum of diameters) or 'mass' (its total mass); 'none'"},
    {.group = "design", .keyword = "design_log_radii", .type = SCENE_REAL_LIST,
     .flags = SCENE_EXTRA, .offset = AT(design.log_radii), .lib = SCENE_OWN,
     .doc = "a smooth chain of n_granules: ln(R_k / R_1) = c_1 x + c_2 x^2 + ..., x = (k - 1) "
            "/ (N - 1), these the c_j (c_1 > 0 grows, < 0 shrinks: the backward and forward "
            "taper in one setting); at every run the chain is profile 'custom' with these radii "
            "(the scene's profile: 'monodisperse'); free = 'log_radii(1)' varies c_1"},
    {.group = "design", .keyword = "design_profile_points", .type = SCENE_INTEGER,
     .flags = SCENE_EXTRA, .offset = AT(design.profile_points), .def = "21", .lib = SCENE_OWN,
     .lo = 0, .hi = 10001,
     .doc = "runs along each free setting through the optimum, lower to upper, for "
            "DIR/profile.tsv and its figure; 0: none"},
};
#define N_OWN (sizeof own / sizeof own[0])

/* The whole table: the library's settings and the scene's own, in the order
 * they are written and documented.  Built once (pthread_once: Python
 * threads read scenes concurrently) and read-only after. */
static scene_var table[N_OWN + SCENE_MAX_SETTINGS];
static size_t n_vars;
static pthread_once_t table_once = PTHREAD_ONCE_INIT;

/* The key of a keyword in its group: without the group's name in front. */
static const char *key_of(const char *group, const char *keyword)
{
    size_t n = strlen(group);
    return strncmp(keyword, group, n) == 0 && keyword[n] == '_' ? keyword + n + 1 : keyword;
}

/* A scene row for row i of the library's table. */
static scene_var library_row(size_t i)
{
    const taper_setting *s = taper_setting_at(i);
    static const scene_type types[] = {
        [TAPER_SETTING_REAL] = SCENE_REAL,       [TAPER_SETTING_INTEGER] = SCENE_INTEGER,
        [TAPER_SETTING_BOOLEAN] = SCENE_LOGICAL, [TAPER_SETTING_CHOICE] = SCENE_CHOICE,
        [TAPER_SETTING_LIST] = SCENE_REAL_LIST,
    };
    scene_var v = {
        .group = s->group,
        .keyword = s->name,
        .type = types[s->type],
        .offset = AT(settings) + i * sizeof(scene_slot),
        .lib = s->object == TAPER_SETTING_CHAIN ? SCENE_LIB_CHAIN : SCENE_LIB_SOLVER,
        .lo = s->min,
        .hi = s->max,
        .choices = s->type == TAPER_SETTING_CHOICE ? s->choices : NULL,
        .dim = s->dimension,
        .setting = s,
        .doc = s->description,
    };
    if (s->type == TAPER_SETTING_REAL || s->type == TAPER_SETTING_INTEGER) v.flags |= SCENE_SWEEP;
    if (s->min_open) v.flags |= SCENE_LO_OPEN;
    if (s->max_open) v.flags |= SCENE_HI_OPEN;
    if (s->beyond_paper) v.flags |= SCENE_EXTRA;
    if (s->type == TAPER_SETTING_BOOLEAN || s->type == TAPER_SETTING_CHOICE) v.lo = v.hi = 0;
    return v;
}

static void append(scene_var v)
{
    v.name = key_of(v.group, v.keyword);
    if (!v.lib_field) v.lib_field = v.keyword;
    if (!v.setting) v.dim = (v.flags & SCENE_TIME) ? TAPER_DIM_TIME : TAPER_DIM_NUMBER;
    table[n_vars++] = v;
}

/* The own rows of `group` that follow `after` (NULL: the group's end). */
static void append_own(const char *group, const char *after)
{
    for (size_t j = 0; j < N_OWN; j++)
        if (strcmp(own[j].group, group) == 0 &&
            (after ? own[j].after && strcmp(own[j].after, after) == 0 : !own[j].after))
            append(own[j]);
}

static void build_table(void)
{
    size_t n_lib = taper_setting_count();
    if (n_lib > SCENE_MAX_SETTINGS) n_lib = SCENE_MAX_SETTINGS; /* tests/driver: scene_table */
    for (size_t g = 0; g < SCENE_N_GROUPS; g++) {
        const char *group = scene_group_name(g);
        for (size_t i = 0; i < n_lib; i++) {
            if (strcmp(taper_setting_at(i)->group, group) != 0) continue;
            append(library_row(i));
            append_own(group, taper_setting_at(i)->name);
        }
        append_own(group, NULL);
    }
}

/* Set once the table is built: loops ask scene_var_count() for every row,
 * and pthread_once costs a call each time. */
static atomic_int table_built;

static void build_table_once(void)
{
    build_table();
    atomic_store_explicit(&table_built, 1, memory_order_release);
}

static void ensure_table(void)
{
    if (!atomic_load_explicit(&table_built, memory_order_acquire))
        pthread_once(&table_once, build_table_once);
}

/* Every validated scene's echo must read back (docs/robustness.md,
 * "Fuzzing the scene parser").  The echo writes a list value in at most 32
 * bytes (24 for %.17g of a double, then ',' and at most a line break and 6
 * spaces); all lists of more than one value hold at most SCENE_MAX_LIST
 * values together (scene_parse.c); every other variable is one line: an own row of
 * at most SCENE_MAX_LINE characters (a string echoes as long as it was
 * written) plus its name and unit, a library row (a number or a choice's
 * name, never a string) of at most 256. */
_Static_assert(32ull * SCENE_MAX_LIST + N_OWN * (SCENE_MAX_LINE + 160ull) +
                       SCENE_MAX_SETTINGS * 256ull <= SCENE_MAX_FILE,
               "the echo of a valid scene may exceed SCENE_MAX_FILE");

size_t scene_var_count(void)
{
    ensure_table();
    return n_vars;
}
const scene_var *scene_var_at(size_t i) { return i < scene_var_count() ? &table[i] : NULL; }
const char *scene_var_group(size_t i) { return i < scene_var_count() ? table[i].group : NULL; }
const char *scene_var_name(size_t i) { return i < scene_var_count() ? table[i].name : NULL; }
const char *scene_var_keyword_at(size_t i)
{
    return i < scene_var_count() ? table[i].keyword : NULL;
}
scene_type scene_var_type(size_t i) { return i < scene_var_count() ? table[i].type : SCENE_STRING; }
int scene_var_takes_list(size_t i)
{
    return i < scene_var_count() && (table[i].flags & SCENE_SWEEP) != 0;
}
const char *const *scene_var_choices(size_t i)
{
    return i < scene_var_count() && table[i].type == SCENE_CHOICE ? table[i].choices : NULL;
}
size_t scene_var_index(const scene_var *var) { return (size_t)(var - table); }

int scene_var_describe(size_t i, scene_var_about *about)
{
    if (i >= scene_var_count()) return -1;
    const scene_var *var = &table[i];
    *about = (scene_var_about){.description = var->doc, .dimension = var->dim,
                               .unit = var->si_unit ? var->si_unit
                                       : var->dim == TAPER_DIM_NUMBER ? NULL
                                       : taper_dimension_unit(var->dim),
                               .choices = var->choices,
                               .beyond_paper = (var->flags & SCENE_EXTRA) != 0,
                               .checked_by = var->lib};
    return 0;
}

/* strcasecmp(a, b) == 0, its first letter compared first: every scene a
 * Python call builds looks rows up by name (docs/python.md, "Overheads"). */
static int same_name(const char *a, const char *b)
{
    return tolower((unsigned char)a[0]) == tolower((unsigned char)b[0]) && strcasecmp(a, b) == 0;
}

int scene_var_find(const char *group, const char *name)
{
    if (!group || !name) return -1;
    const size_t n = scene_var_count();
    for (size_t i = 0; i < n; i++)
        if (same_name(table[i].name, name) && same_name(table[i].group, group)) return (int)i;
    return -1;
}

int scene_var_keyword(const char *keyword)
{
    const size_t n = scene_var_count();
    for (size_t i = 0; keyword && i < n; i++)
        if (same_name(table[i].keyword, keyword)) return (int)i;
    return -1;
}

/* The library checks its settings by their names (taper_error.field); the
 * chain's and the solver's are one table, so either spec's refusal finds
 * its row (taper_sim_alloc checks the chain with the solver). */
int scene_var_of_field(scene_lib lib, const char *field)
{
    if (lib == SCENE_OWN || !field) return -1;
    for (size_t i = 0; i < scene_var_count(); i++) {
        const scene_var *v = &table[i];
        int library = v->setting && (lib == SCENE_LIB_CHAIN || lib == SCENE_LIB_SOLVER);
        if ((library || v->lib == lib) && v->lib != SCENE_OWN && strcmp(v->lib_field, field) == 0)
            return (int)i;
    }
    return -1;
}

/* ---- the library's settings by name ---------------------------------------------- */

double scene_setting(const scene_config *cfg, const char *name)
{
    int i = scene_var_keyword(name);
    if (i < 0 || !table[i].setting || table[i].type == SCENE_REAL_LIST) return NAN;
    return scene_row_value(cfg, (size_t)i, 0);
}

void scene_setting_store(scene_config *cfg, const char *name, double value)
{
    int i = scene_var_keyword(name);
    if (i < 0 || !table[i].setting) return;
    void *f = scene_field(cfg, &table[i]);
    long long n = (long long)value;
    int b = (int)value;
    switch (table[i].type) {
    case SCENE_REAL: memcpy(f, &value, sizeof value); break;
    case SCENE_INTEGER: memcpy(f, &n, sizeof n); break;
    case SCENE_LOGICAL:
    case SCENE_CHOICE: memcpy(f, &b, sizeof b); break;
    default: break;
    }
}

const scene_reals *scene_setting_list(const scene_config *cfg, const char *name)
{
    static const scene_reals none = {0};
    int i = scene_var_keyword(name);
    if (i < 0 || table[i].type != SCENE_REAL_LIST) return &none;
    return scene_cfield(cfg, &table[i]);
}

const char *scene_type_name(const scene_var *var)
{
    static const char *const names[] = {"string", "real", "integer", "logical", "real list",
                                        "string"};
    if (var->type == SCENE_REAL && (var->flags & SCENE_SWEEP)) return "real (list: sweep)";
    if (var->type == SCENE_INTEGER && (var->flags & SCENE_SWEEP)) return "integer (list: sweep)";
    return names[var->type];
}

/* ---- typed fields ------------------------------------------------------------- */

void *scene_field(scene_config *cfg, const scene_var *var) { return (char *)cfg + var->offset; }

const void *scene_cfield(const scene_config *cfg, const scene_var *var)
{
    return (const char *)cfg + var->offset;
}

int scene_var_is_list(const scene_var *var) { return var->type == SCENE_REAL_LIST; }

size_t scene_field_size(const scene_var *var)
{
    if (scene_var_is_list(var)) return sizeof(scene_reals);
    switch (var->type) {
    case SCENE_STRING: return sizeof(char *);
    case SCENE_REAL: return sizeof(double);
    case SCENE_INTEGER: return sizeof(long long);
    default: return sizeof(int); /* LOGICAL, CHOICE */
    }
}

void scene_field_clear(scene_config *cfg, const scene_var *var)
{
    void *f = scene_field(cfg, var);
    if (cfg->sweep.lists) {
        scene_reals *l = &cfg->sweep.lists[scene_var_index(var)];
        free(l->v);
        l->v = NULL;
        l->n = 0;
    }
    if (scene_var_is_list(var)) {
        scene_reals *r = f;
        free(r->v);
        r->v = NULL;
        r->n = 0;
    } else if (var->type == SCENE_STRING) {
        char **s = f;
        free(*s);
        *s = NULL;
    }
}

int scene_choice_find(const scene_var *var, const char *name, int *value)
{
    for (int v = var->choice_first; scene_choice_name(var, v); v++) {
        if (strcasecmp(scene_choice_name(var, v), name) == 0) {
            *value = v;
            return 0;
        }
    }
    return -1;
}

const char *scene_var_text(const scene *sc, size_t i)
{
    if (i >= scene_var_count()) return "";
    const scene_var *var = &table[i];
    const void *f = scene_cfield(&sc->cfg, var);
    if (var->type == SCENE_STRING) {
        char *const *s = f;
        return *s ? *s : "";
    }
    if (var->type == SCENE_CHOICE) {
        int v;
        memcpy(&v, f, sizeof v);
        const char *name = scene_choice_name(var, v);
        return name ? name : "";
    }
    return "";
}

long long scene_var_integer(const scene *sc, size_t i)
{
    if (i >= scene_var_count()) return 0;
    const void *f = scene_cfield(&sc->cfg, &table[i]);
    if (table[i].type == SCENE_INTEGER) {
        long long x;
        memcpy(&x, f, sizeof x);
        return x;
    }
    if (table[i].type == SCENE_LOGICAL || table[i].type == SCENE_CHOICE) {
        int x;
        memcpy(&x, f, sizeof x);
        return x;
    }
    return 0;
}

const double *scene_var_reals(const scene *sc, size_t i, size_t *n)
{
    *n = 0;
    if (i >= scene_var_count()) return NULL;
    const scene_var *var = &table[i];
    const void *f = scene_cfield(&sc->cfg, var);
    if (scene_var_is_list(var)) {
        const scene_reals *r = f;
        *n = r->n;
        return r->v;
    }
    if (var->type == SCENE_REAL || var->type == SCENE_INTEGER) {
        if (sc->cfg.sweep.lists && sc->cfg.sweep.lists[i].n > 1) {
            *n = sc->cfg.sweep.lists[i].n;
            return sc->cfg.sweep.lists[i].v;
        }
        if (var->type == SCENE_INTEGER) return NULL; /* one value: scene_var_integer */
        const double *x = f;
        *n = isnan(*x) ? 0 : 1; /* NaN: a real without default, left out */
        return x;
    }
    return NULL;
}

size_t scene_row_count(const scene_config *cfg, size_t i)
{
    const scene_var *var = &table[i];
    if (scene_var_is_list(var)) return ((const scene_reals *)scene_cfield(cfg, var))->n;
    if (cfg->sweep.lists && cfg->sweep.lists[i].n > 1) return cfg->sweep.lists[i].n;
    return 1;
}

double scene_row_value(const scene_config *cfg, size_t i, size_t j)
{
    const scene_var *var = &table[i];
    const void *f = scene_cfield(cfg, var);
    if (scene_var_is_list(var)) {
        const scene_reals *r = f;
        return j < r->n ? r->v[j] : NAN;
    }
    if (cfg->sweep.lists && cfg->sweep.lists[i].n > 1)
        return j < cfg->sweep.lists[i].n ? cfg->sweep.lists[i].v[j] : NAN;
    if (var->type == SCENE_INTEGER) {
        long long x;
        memcpy(&x, f, sizeof x);
        return (double)x;
    }
    if (var->type == SCENE_LOGICAL || var->type == SCENE_CHOICE) {
        int x;
        memcpy(&x, f, sizeof x);
        return (double)x;
    }
    double x;
    memcpy(&x, f, sizeof x);
    return x;
}

/* ---- numbers as scene text ------------------------------------------------- */

void scene_format_real(double x, char buf[SCENE_REAL_TEXT])
{
    /* Shortest representation that reads back exactly: tidy scenes, and
     * the echo re-parses to the same doubles.  At most 24 characters
     * (%.17g of a double), so buf cannot overflow. */
    const size_t size = SCENE_REAL_TEXT;
    int prec = 15;
    snprintf(buf, size, "%.*g", prec, x);
    if (strtod(buf, NULL) == x) {
        /* 15 digits suffice: the shortest from 1 up (tidy values are short) */
        for (prec = 1; prec < 15; prec++) {
            snprintf(buf, size, "%.*g", prec, x);
            if (strtod(buf, NULL) == x) break;
        }
    } else {
        /* a value with 16 or 17 significant digits (most computed ones):
         * two tries rather than 17, so that long lists echo quickly */
        for (prec = 16; prec < 17; prec++) {
            snprintf(buf, size, "%.*g", prec, x);
            if (strtod(buf, NULL) == x) break;
        }
    }
    /* %g switches to an exponent once it has fewer digits than the integer
     * part: print 20 rather than 2e+01, keep 1e+06 and beyond short. */
    double mag = fabs(x);
    if (mag >= 1.0 && mag < 1e6) {
        int digits = (int)floor(log10(mag)) + 1;
        if (digits > prec) prec = digits;
    }
    snprintf(buf, size, "%.*g", prec, x);
}

int scene_line(const scene *sc, size_t offset)
{
    for (size_t i = 0; i < scene_var_count(); i++)
        if (table[i].offset == offset) return sc->origin[i].line;
    return 0;
}

/* The index of a library row's slot in scene_config.settings. */
static size_t slot_of(const scene_var *var)
{
    return (var->offset - offsetof(scene_config, settings)) / sizeof(scene_slot);
}

void scene_mark_given(scene *sc, size_t i, int line)
{
    sc->origin[i].given = 1;
    sc->origin[i].line = line;
    if (table[i].setting) sc->cfg.settings_given[slot_of(&table[i])] = 1;
}

int scene_setting_given(const scene_config *cfg, const scene_var *var)
{
    return var->setting && cfg->settings_given[slot_of(var)];
}

int scene_line_of(const scene *sc, const char *keyword)
{
    int i = scene_var_keyword(keyword);
    return i < 0 ? 0 : sc->origin[i].line;
}
