/*
 * scene.c -- the table of scene variables, the values of a scene, typed
 * access, and the conversion to the library's specs.
 *
 * The table below is the only place a variable is declared: the parser
 * (scene_parse.c), the validation (scene_check.c), the echo, --defaults and
 * --doc (scene_write.c) all walk it.
 */
#include "scene_impl.h"

#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static const char *const profiles[] = {
    "monodisperse", "backward_linear", "forward_linear",
    "backward_exponential", "forward_exponential", "custom", NULL,
};
static const char *const methods[] = {"adams", "bdf", NULL};
static const char *const fit_models[] = {
    "none", "power", "exponential", "divergence_b", "divergence_c", "divergence_m", NULL,
};
/* Per-granule quantities, each for the numerics and for the theory alike
 * (series.c): see the doc strings of &fit x and y. */
static const char *const quantities[] = {"k", "v", "T_res", "t", "t_reach", "t_peak", NULL};
static const char *const fit_params[] = {"a", "b", "c", "m", "p", "f", NULL};
static const char *const theories[] = {"fit", "rate", "f", "b", NULL};
static const char *const curves[] = {"both", "theory", "numerics", NULL};

/* The groups, in the order they are written and documented. */
static const char *const groups[][2] = {
    {"chain", "the granular chain: radius profile, size, contact law"},
    {"solver", "the integration of the equations of motion (CVODE)"},
    {"output", "where and how results are written"},
    {"fit", "a fit applied to every run of the scene, to numerics and theory alike"},
    {"table", "a table of the fitted parameter over the sweep, next to the paper's values"},
    {"figure", "a figure: per-granule data of every run, and the fit as an inset"},
};
#define N_GROUPS (sizeof groups / sizeof groups[0])

size_t scene_group_count(void) { return N_GROUPS; }
const char *scene_group_name(size_t i) { return i < N_GROUPS ? groups[i][0] : NULL; }
const char *scene_group_doc(size_t i) { return i < N_GROUPS ? groups[i][1] : NULL; }

/* Bounds are generous but finite: a number outside them is a typo, not a
 * physics question (the stress matrix of issue 7 stays well inside). */
static const scene_var table[] = {
    {"chain", "profile", SCENE_STRING, 0, "'monodisperse'", 0, 0, profiles,
     "radius profile R_k: monodisperse (1), backward_linear (1+s(k-1)), forward_linear "
     "(1-s(k-1)), backward_exponential ((1-q)^(1-k)), forward_exponential ((1+q)^(1-k)), "
     "custom (radii)"},
    {"chain", "n_granules", SCENE_INTEGER, 0, "100", 2, 1e7, NULL,
     "number of granules N (custom profile: may be left out, then N = number of radii)"},
    {"chain", "s", SCENE_REAL, SCENE_SWEEP, "0", 0, 1e3, NULL,
     "linear tapering S (backward_linear, forward_linear); a list of values sweeps it"},
    {"chain", "q", SCENE_REAL, SCENE_SWEEP, "0", 0, 1e3, NULL,
     "exponential tapering q (backward_exponential needs q < 1); a list of values sweeps it"},
    {"chain", "exponent", SCENE_REAL, SCENE_LO_OPEN, "2.5", 1, 20, NULL,
     "contact exponent n: force ~ overlap^(n-1); 2.5 is Hertz"},
    {"chain", "radii", SCENE_REAL_LIST, SCENE_POSITIVE, NULL, 0, 0, NULL,
     "custom profile only: the radii R_1, ..., R_N (R_1 = 1 is the unit of length)"},

    {"solver", "method", SCENE_STRING, SCENE_LIBDEF, NULL, 0, 0, methods,
     "integrator: 'adams' (Adams-Moulton, fixed point) or 'bdf' (BDF, banded Jacobian)"},
    {"solver", "rtol", SCENE_REAL, SCENE_LIBDEF, NULL, 1e-14, 0.1, NULL,
     "relative tolerance of the integrator (below 1e-14 double precision cannot follow)"},
    {"solver", "atol", SCENE_REAL, SCENE_LIBDEF | SCENE_LO_OPEN, NULL, 0, 0.1, NULL,
     "absolute tolerance, in units of each granule's binary-collision velocity and maximum "
     "compression (relative to the pulse wherever it is)"},
    {"solver", "window", SCENE_LOGICAL, SCENE_LIBDEF, NULL, 0, 0, NULL,
     "integrate only the granules that can move (exact and faster); .false.: the whole chain"},
    {"solver", "last_granule", SCENE_INTEGER, 0, "0", 0, 1e7, NULL,
     "stop once the pulse has passed this granule; 0: the whole chain"},
    {"solver", "t_max", SCENE_REAL, 0, "0", 0, 1e300, NULL,
     "stop at this time with a partial result; 0: no limit"},
    {"solver", "max_steps", SCENE_INTEGER, 0, "0", 0, 1e15, NULL,
     "stop after this many internal steps with a partial result; 0: no limit"},
    {"solver", "numerics", SCENE_LOGICAL, 0, ".true.", 0, 0, NULL,
     "integrate the dynamics; .false.: binary-collision theory only (fast)"},

    {"output", "dir", SCENE_STRING, 0, NULL, 0, 0, NULL,
     "output directory, created if missing (default out/NAME for scene NAME.nml; -o overrides)"},
    {"output", "progress", SCENE_LOGICAL, 0, ".true.", 0, 0, NULL,
     "show a progress line on stderr when it is a terminal"},
    {"output", "threads", SCENE_INTEGER, 0, "0", 0, 256, NULL,
     "runs of a sweep computed at once (results identical to one at a time); 0: one per core"},

    {"fit", "model", SCENE_STRING, 0, "'none'", 0, 0, fit_models,
     "'none' (no fit), or y = 'power' a x^b, 'exponential' a e^(b x), 'divergence_b' "
     "a (1 - b x)^-p, 'divergence_c' a (1 - x/C)^-p, 'divergence_m' a (1 + x/M)^-f; fitted "
     "to ln y; writes DIR/fits.tsv"},
    {"fit", "x", SCENE_STRING, 0, "'k'", 0, 0, quantities,
     "abscissa: k (granule), v (numerics: v_peak; theory: v_k, eq. recv), T_res (T_res; T_k), "
     "t (pulse passes k: t_pass; eq. totaltime), t_reach (pulse reaches k: t of k-1), "
     "t_peak (time of v_peak; theory: t_reach, when k leaves its collision with k-1)"},
    {"fit", "y", SCENE_STRING, 0, "'v'", 0, 0, quantities,
     "ordinate, one of the quantities of x"},
    {"fit", "k_min", SCENE_INTEGER, 0, "1", 1, 1e7, NULL,
     "first granule of the fit window"},
    {"fit", "k_max", SCENE_INTEGER, 0, "0", 0, 1e7, NULL,
     "last granule of the fit window; 0: the last granule with a value"},
    {"fit", "p", SCENE_REAL, SCENE_LO_OPEN, NULL, 0, 100, NULL,
     "fixed exponent p of divergence_b and divergence_c; left out: 3/2 (divergence_b), "
     "fitted (divergence_c)"},
    {"fit", "report", SCENE_STRING, 0, "'b'", 0, 0, fit_params,
     "the parameter tabulated: a or b (power, exponential, divergence_b), p (divergence_b, "
     "_c), c (divergence_c), m or f (divergence_m)"},
    {"fit", "factor", SCENE_REAL, 0, "1", -1e3, 1e3, NULL,
     "the tabulated value is factor * parameter (e.g. -1: a decay rate from b < 0)"},
    {"fit", "label", SCENE_STRING, 0, "''", 0, 0, NULL,
     "name of the tabulated value in tables and plots; empty: the parameter's name"},
    {"fit", "theory", SCENE_STRING, 0, "'fit'", 0, 0, theories,
     "theory column: 'fit' (the same fit of the exact binary-collision theory), or the "
     "closed form: 'rate' |ln A(q)|, 'f' f(q) (q -> -q for forward chains), 'b' S/(1+S)"},

    {"table", "name", SCENE_STRING, 0, "''", 0, 0, NULL,
     "table label (e.g. 'Table I'); non-empty: write DIR/table.tsv and print the table"},
    {"table", "caption", SCENE_STRING, 0, "''", 0, 0, NULL, "one line printed above the table"},
    {"table", "digits", SCENE_INTEGER, 0, "4", 1, 12, NULL,
     "decimals printed on stdout (table.tsv has every digit)"},
    {"table", "paper_theory", SCENE_REAL_LIST, 0, NULL, 0, 0, NULL,
     "the paper's theory column, one value per swept value"},
    {"table", "paper_numerics", SCENE_REAL_LIST, 0, NULL, 0, 0, NULL,
     "the paper's numerics column, one value per swept value"},

    {"figure", "name", SCENE_STRING, 0, "''", 0, 0, NULL,
     "figure label (e.g. 'Fig. 1'); non-empty: write DIR/figure.gp, its data, and "
     "DIR/figure.png when gnuplot is installed"},
    {"figure", "title", SCENE_STRING, 0, "''", 0, 0, NULL, "title line of the plot"},
    {"figure", "x", SCENE_STRING, 0, "'k'", 0, 0, quantities,
     "abscissa of the main panel (quantities as for &fit x)"},
    {"figure", "y", SCENE_STRING, 0, "'v'", 0, 0, quantities, "ordinate of the main panel"},
    {"figure", "curves", SCENE_STRING, 0, "'both'", 0, 0, curves,
     "series drawn: theory (open circles), numerics (filled circles), or both"},
    {"figure", "log_x", SCENE_LOGICAL, 0, ".false.", 0, 0, NULL, "logarithmic x axis"},
    {"figure", "log_y", SCENE_LOGICAL, 0, ".false.", 0, 0, NULL, "logarithmic y axis"},
    {"figure", "every", SCENE_INTEGER, 0, "1", 1, 1e6, NULL,
     "draw every n-th granule (the first and every n-th after it)"},
    {"figure", "k_max", SCENE_INTEGER, 0, "0", 0, 1e7, NULL,
     "last granule drawn; 0: the whole chain"},
    {"figure", "x_label", SCENE_STRING, 0, "''", 0, 0, NULL, "x axis label; empty: from x"},
    {"figure", "y_label", SCENE_STRING, 0, "''", 0, 0, NULL, "y axis label; empty: from y"},
    {"figure", "inset", SCENE_LOGICAL, 0, ".false.", 0, 0, NULL,
     "second panel: the &fit value of theory and numerics against the swept variable"},
    {"figure", "inset_reference", SCENE_REAL, 0, NULL, -1e3, 1e3, NULL,
     "a horizontal line in the inset (e.g. an asymptotic exponent); left out: none"},
};
#define N_VARS (sizeof table / sizeof table[0])

/* Every validated scene's echo must read back (docs/robustness.md, finding
 * B).  The echo writes a list value in at most 32 bytes (24 for %.17g of a
 * double, then ',' and at most a line break and 6 spaces); all lists of
 * more than one value hold at most SCENE_MAX_LIST values together
 * (scene_parse.c); every other variable is one line of at most
 * SCENE_MAX_LINE characters (a string echoes as long as it was written)
 * plus its name. */
_Static_assert(32ull * SCENE_MAX_LIST + N_VARS * (SCENE_MAX_LINE + 128ull) <= SCENE_MAX_FILE,
               "the echo of a valid scene may exceed SCENE_MAX_FILE");

int scene_group_active(const scene *sc, const char *group)
{
    if (strcmp(group, "fit") == 0) return strcmp(scene_str(sc, "fit", "model"), "none") != 0;
    if (strcmp(group, "table") == 0 || strcmp(group, "figure") == 0)
        return scene_str(sc, group, "name")[0] != '\0';
    return 1;
}

size_t scene_var_count(void) { return N_VARS; }

const scene_var *scene_var_at(size_t i) { return i < N_VARS ? &table[i] : NULL; }

int scene_var_find(const char *group, const char *name)
{
    if (!group || !name) return -1;
    for (size_t i = 0; i < N_VARS; i++)
        if (strcasecmp(table[i].group, group) == 0 && strcasecmp(table[i].name, name) == 0)
            return (int)i;
    return -1;
}

const char *scene_type_name(const scene_var *var)
{
    static const char *const names[] = {"string", "real", "integer", "logical", "real list"};
    if (var->type == SCENE_REAL && (var->flags & SCENE_SWEEP)) return "real (list: sweep)";
    return names[var->type];
}

/* src into dst (size > 4) with every byte that is not printable ASCII
 * (control bytes, UTF-8, Latin-1, ...) shown as \xNN, so that a message
 * says exactly which bytes the file has; "..." ends a text cut short. */
static void copy_escaped(char *dst, size_t size, const char *src)
{
    size_t o = 0;
    for (const unsigned char *c = (const unsigned char *)src; *c; c++) {
        int plain = *c >= 0x20 && *c < 0x7f;
        size_t need = plain ? 1 : 4;
        if (o + need > size - 1) {
            memcpy(dst + (o <= size - 4 ? o : size - 4), "...", 4);
            return;
        }
        if (plain)
            dst[o++] = (char)*c;
        else
            o += (size_t)snprintf(dst + o, size - o, "\\x%02x", *c);
    }
    dst[o] = '\0';
}

void scene_error(scene *sc, int line, const char *group, const char *key, const char *fmt, ...)
{
    sc->n_errors++;
    if (sc->n_diags >= SCENE_MAX_DIAGS) return;
    scene_diag *d = &sc->diags[sc->n_diags++];
    d->line = line;
    copy_escaped(d->group, sizeof d->group, group ? group : "");
    copy_escaped(d->key, sizeof d->key, key ? key : "");
    char raw[SCENE_MSG_SIZE];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(raw, sizeof raw, fmt, ap);
    va_end(ap);
    copy_escaped(d->message, sizeof d->message, raw);
}

void scene_print_diags(const scene *sc, FILE *fp)
{
    for (size_t i = 0; i < sc->n_diags; i++) {
        const scene_diag *d = &sc->diags[i];
        fprintf(fp, "%s:", sc->path);
        if (d->line > 0) fprintf(fp, "%d:", d->line);
        if (d->group[0]) fprintf(fp, " &%s", d->group);
        if (d->key[0]) fprintf(fp, " %s", d->key);
        fprintf(fp, "%s %s\n", d->group[0] || d->key[0] ? ":" : "", d->message);
    }
    if (sc->n_errors > sc->n_diags)
        fprintf(fp, "%s: %zu more errors not shown\n", sc->path, sc->n_errors - sc->n_diags);
}

void scene_value_clear(scene_value *v)
{
    free(v->str);
    free(v->list);
    memset(v, 0, sizeof *v);
}

void scene_free(scene *sc)
{
    if (!sc) return;
    if (sc->values)
        for (size_t i = 0; i < N_VARS; i++) scene_value_clear(&sc->values[i]);
    free(sc->values);
    free(sc->path);
    free(sc);
}

static char *dup_str(const char *s)
{
    size_t n = strlen(s) + 1;
    char *p = malloc(n);
    if (p) memcpy(p, s, n);
    return p;
}

static int set_real(scene_value *v, double x)
{
    free(v->list);
    v->list = malloc(sizeof *v->list);
    if (!v->list) return -1;
    v->list[0] = x;
    v->count = 1;
    return 0;
}

/* Table default text -> value.  The table's defaults are a fixed, tested
 * subset of the syntax, so this needs no error reporting beyond memory. */
static int set_table_default(const scene_var *var, scene_value *v)
{
    if (!var->def) return 0;
    switch (var->type) {
    case SCENE_STRING: {
        size_t n = strlen(var->def);
        v->str = malloc(n);
        if (!v->str) return -1;
        memcpy(v->str, var->def + 1, n - 2); /* strip the quotes */
        v->str[n - 2] = '\0';
        return 0;
    }
    case SCENE_REAL: return set_real(v, strtod(var->def, NULL));
    case SCENE_INTEGER: v->ival = strtoll(var->def, NULL, 10); return 0;
    case SCENE_LOGICAL: v->bval = strcasecmp(var->def, ".true.") == 0; return 0;
    default: return 0;
    }
}

/* Defaults that the library measured: one source of truth. */
static int set_library_default(const scene_var *var, scene_value *v, const taper_solver_spec *lib)
{
    if (strcmp(var->name, "method") == 0) {
        v->str = dup_str(lib->method == TAPER_BDF ? "bdf" : "adams");
        return v->str ? 0 : -1;
    }
    if (strcmp(var->name, "rtol") == 0) return set_real(v, lib->rtol);
    if (strcmp(var->name, "atol") == 0) return set_real(v, lib->atol);
    if (strcmp(var->name, "window") == 0) v->bval = lib->window != 0;
    return 0;
}

/* out/NAME for scene file .../NAME.nml. */
static char *derived_dir(const char *path)
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    size_t n = strlen(base);
    if (n > 4 && strcasecmp(base + n - 4, ".nml") == 0) n -= 4;
    if (n == 0) base = "scene", n = 5;
    char *dir = malloc(n + 5);
    if (!dir) return NULL;
    memcpy(dir, "out/", 4);
    memcpy(dir + 4, base, n);
    dir[n + 4] = '\0';
    return dir;
}

scene *scene_new(const char *path, const taper_solver_spec *lib)
{
    scene *sc = calloc(1, sizeof *sc);
    if (!sc) return NULL;
    sc->path = dup_str(path ? path : "<scene>");
    sc->values = calloc(N_VARS, sizeof *sc->values);
    if (!sc->path || !sc->values) goto fail;
    for (size_t i = 0; i < N_VARS; i++) {
        const scene_var *var = &table[i];
        int rc = (var->flags & SCENE_LIBDEF) ? set_library_default(var, &sc->values[i], lib)
                                             : set_table_default(var, &sc->values[i]);
        if (rc != 0) goto fail;
    }
    int d = scene_var_find("output", "dir");
    if (!(sc->values[d].str = derived_dir(sc->path))) goto fail;
    return sc;
fail:
    scene_free(sc);
    return NULL;
}

/* ---- typed access ------------------------------------------------------ */

const scene_value *scene_get(const scene *sc, const char *group, const char *name)
{
    int i = scene_var_find(group, name);
    return i < 0 ? NULL : &sc->values[i];
}

const char *scene_str(const scene *sc, const char *group, const char *name)
{
    const scene_value *v = scene_get(sc, group, name);
    return v && v->str ? v->str : "";
}

double scene_real(const scene *sc, const char *group, const char *name)
{
    const scene_value *v = scene_get(sc, group, name);
    return v && v->count > 0 ? v->list[0] : NAN;
}

long long scene_int(const scene *sc, const char *group, const char *name)
{
    const scene_value *v = scene_get(sc, group, name);
    return v ? v->ival : 0;
}

int scene_bool(const scene *sc, const char *group, const char *name)
{
    const scene_value *v = scene_get(sc, group, name);
    return v ? v->bval : 0;
}

int scene_set_str(scene *sc, const char *group, const char *name, const char *value)
{
    int i = scene_var_find(group, name);
    if (i < 0 || table[i].type != SCENE_STRING) return -1;
    char *s = dup_str(value);
    if (!s) return -1;
    free(sc->values[i].str);
    sc->values[i].str = s;
    sc->values[i].line = 0; /* no longer from the file: messages name no line */
    return 0;
}

int scene_sweep_var(const scene *sc)
{
    for (size_t i = 0; i < N_VARS; i++)
        if ((table[i].flags & SCENE_SWEEP) && sc->values[i].count > 1) return (int)i;
    return -1;
}

/* The value of a sweepable real at sweep_index (its only value otherwise). */
static double swept_real(const scene *sc, const char *name, size_t sweep_index)
{
    const scene_value *v = scene_get(sc, "chain", name);
    if (!v || v->count == 0) return NAN;
    return v->list[v->count > 1 && sweep_index < v->count ? sweep_index : 0];
}

void scene_chain_spec(const scene *sc, size_t sweep_index, taper_chain_spec *spec)
{
    taper_chain_spec_init(spec);
    int profile = TAPER_MONODISPERSE;
    taper_profile_from_name(scene_str(sc, "chain", "profile"), &profile);
    spec->profile = profile;
    spec->n_granules = (size_t)scene_int(sc, "chain", "n_granules");
    spec->s = swept_real(sc, "s", sweep_index);
    spec->q = swept_real(sc, "q", sweep_index);
    spec->exponent = scene_real(sc, "chain", "exponent");
    const scene_value *radii = scene_get(sc, "chain", "radii");
    if (profile == TAPER_CUSTOM && radii->count > 0) {
        spec->radii = radii->list;
        spec->n_granules = radii->count; /* validation made them agree */
    }
}

void scene_solver_spec(const scene *sc, taper_solver_spec *spec)
{
    /* Only the fields the scene describes: the caller started from
     * taper_solver_spec_init() and adds monitor and log. */
    spec->method = strcmp(scene_str(sc, "solver", "method"), "bdf") == 0 ? TAPER_BDF : TAPER_ADAMS;
    spec->rtol = scene_real(sc, "solver", "rtol");
    spec->atol = scene_real(sc, "solver", "atol");
    spec->window = scene_bool(sc, "solver", "window");
    spec->last_granule = (size_t)scene_int(sc, "solver", "last_granule");
    spec->t_max = scene_real(sc, "solver", "t_max");
    spec->max_steps = (long)scene_int(sc, "solver", "max_steps");
}
