/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * scene_check.c -- validation of a parsed scene.  The scene checks what is
 * its own: the ranges of its own variables (the table's lo, hi), that a
 * number of granules is not negative before it becomes a size_t, and the
 * relations between keys that only the scene has (a value given to a
 * profile that ignores it, one sweep at a time, &fit / &table / &figure
 * against each other and against the chain).  The library's settings are
 * checked by the library (scene_lib.c).  Every problem is reported at once,
 * each with the line of its key and what to change.
 */
#include "scene_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int in_range(const scene_var *var, double x)
{
    int lo_ok = (var->flags & SCENE_LO_OPEN) ? x > var->lo : x >= var->lo;
    int hi_ok = (var->flags & SCENE_HI_OPEN) ? x < var->hi : x <= var->hi;
    return lo_ok && hi_ok;
}

static void range_error(scene *sc, size_t i, double x)
{
    char xs[SCENE_REAL_TEXT];
    char *range = scene_range_text(scene_var_at(i));
    scene_format_real(x, xs);
    scene_var_error(sc, i, "%s is out of range: give a value in %s", xs, range ? range : "?");
    free(range);
}

/* A row the scene checks itself: numbers against the table's range. */
static void check_own(scene *sc, size_t i)
{
    const scene_var *var = scene_var_at(i);
    const void *f = scene_cfield(&sc->cfg, var);
    if (var->lo == 0 && var->hi == 0) return; /* no range */
    if (var->type == SCENE_INTEGER) {
        long long x;
        memcpy(&x, f, sizeof x);
        if (!in_range(var, (double)x)) range_error(sc, i, (double)x);
    } else if (var->type == SCENE_REAL || var->type == SCENE_REAL_LIST) {
        /* Each value of a sweep or a list; NaN: a real left out. */
        for (size_t j = 0; j < scene_row_count(&sc->cfg, i); j++) {
            double x = scene_row_value(&sc->cfg, i, j);
            if (!isnan(x) && !in_range(var, x)) {
                range_error(sc, i, x);
                return;
            }
        }
    }
}

static int row(const char *group, const char *name) { return scene_var_find(group, name); }

static int is_exponential(taper_profile p)
{
    return p == TAPER_BACKWARD_EXPONENTIAL || p == TAPER_FORWARD_EXPONENTIAL;
}

/* radii only mean something for the custom profile: given to another
 * profile they are a mistake in the scene.  (s and q given to a profile
 * that does not read them, and a tapered profile without its parameter,
 * are refused by the library's taper_chain_spec_check, reported at s or q
 * by scene_lib.c: one owner per rule.) */
static void check_unused(scene *sc)
{
    int r = scene_var_keyword("radii");
    if (SCENE_PROFILE(&sc->cfg) != TAPER_CUSTOM && sc->origin[r].given)
        scene_var_error(sc, (size_t)r,
                        "radii are only used with profile = 'custom': remove them or set the "
                        "profile");
}

/* A tapered profile needs its tapering given: left out, it would run the
 * monodisperse chain (s = q = 0, the library's default and the limit of
 * the taper) under another name.  s = 0 or q = 0 given (a sweep's
 * baseline) is that limit, meant. */
static void check_taper_given(scene *sc)
{
    taper_profile p = SCENE_PROFILE(&sc->cfg);
    int linear = p == TAPER_BACKWARD_LINEAR || p == TAPER_FORWARD_LINEAR;
    if (!linear && !is_exponential(p)) return;
    const char *key = linear ? "s" : "q";
    int r = scene_var_keyword(key);
    if (r < 0 || sc->origin[r].given) return;
    scene_var_error(sc, (size_t)r,
                    linear ? "profile = '%s' needs its tapering s (R_k = 1 %s s (k-1)): give s "
                             "(s = 0 is the monodisperse chain, the limit of the taper)"
                           : "profile = '%s' needs its tapering q (R_k = (1 %s q)^(1-k)): give q "
                             "(q = 0 is the monodisperse chain, the limit of the taper)",
                    taper_profile_name(p),
                    p == TAPER_BACKWARD_LINEAR || p == TAPER_FORWARD_EXPONENTIAL ? "+" : "-");
}

/* A custom chain may leave n_granules out: N is the number of radii. */
static void resolve_custom(scene *sc)
{
    scene_config *cfg = &sc->cfg;
    int n = scene_var_keyword("n_granules");
    size_t radii = cfg->chain.file_radii.n ? cfg->chain.file_radii.n
                                           : scene_setting_list(cfg, "radii")->n; /* a file, or inline */
    if (SCENE_PROFILE(cfg) == TAPER_CUSTOM && radii > 0 && !sc->origin[n].given) {
        scene_setting_store(cfg, "n_granules", (double)radii);
        sc->n_from_radii = 1;
    }
}

/* Which runs the scene asks for: one per point of its sweep
 * (scene_sweep.c). */
static void resolve_runs(scene *sc)
{
    scene_config *cfg = &sc->cfg;
    scene_runs *runs = &cfg->runs;
    scene_resolve_sweep(sc);
    runs->param = is_exponential(SCENE_PROFILE(cfg)) ? SCENE_PARAM_Q : SCENE_PARAM_S;
    runs->fit = cfg->fit.model != SCENE_FIT_NONE;
    runs->table = cfg->table.name[0] != '\0';
    runs->figure = cfg->figure.name[0] != '\0';
}

/* The fit's tabulated parameter must be one the model has. */
static void check_fit_report(scene *sc)
{
    /* The parameters of each taper_fit_model, in the order of taper.h. */
    static const char *const params[TAPER_N_FIT_MODELS] = {
        [TAPER_FIT_POWER] = "ab", [TAPER_FIT_EXPONENTIAL] = "ab", [TAPER_FIT_DIVERGENCE_B] = "abp",
        [TAPER_FIT_DIVERGENCE_C] = "acp", [TAPER_FIT_DIVERGENCE_M] = "amf",
    };
    const scene_fit_config *fit = &sc->cfg.fit;
    const char *model = scene_fit_model_name(fit->model);
    const char *report = scene_fit_report_name(fit->report);
    if (!strchr(params[fit->model], report[0]))
        scene_var_error(sc, (size_t)row("fit", "report"),
                        "model '%s' has no parameter '%s': report one of %s", model, report,
                        params[fit->model]);
    if (!isnan(fit->p) && fit->model != TAPER_FIT_DIVERGENCE_B &&
        fit->model != TAPER_FIT_DIVERGENCE_C)
        scene_var_error(sc, (size_t)row("fit", "p"),
                        "p is the fixed exponent of divergence_b and divergence_c, not of '%s': "
                        "remove it", model);
}

/* A closed-form theory column exists only for its profile. */
static void check_fit_theory(scene *sc)
{
    const scene_config *cfg = &sc->cfg;
    scene_fit_theory t = cfg->fit.theory;
    taper_profile p = SCENE_PROFILE(cfg);
    const char *profile = taper_profile_name(p);
    size_t r = (size_t)row("fit", "theory");
    if ((t == SCENE_THEORY_RATE || t == SCENE_THEORY_F) && !is_exponential(p))
        scene_var_error(sc, r, "theory = '%s' is a law of the exponential chains, not of '%s': "
                        "use 'fit'", scene_fit_theory_name(t), profile);
    if (t == SCENE_THEORY_B && p != TAPER_FORWARD_LINEAR)
        scene_var_error(sc, r, "theory = 'b' (S/(1+S)) is a law of forward_linear chains: use "
                        "'fit'");
}

static void check_window(scene *sc, const char *group, const char *key, long long k)
{
    long long n = SCENE_N_GRANULES(&sc->cfg);
    /* A sweep of n_granules: the shortest chain. */
    size_t nr = (size_t)scene_var_keyword("n_granules");
    for (size_t j = 0; j < scene_row_count(&sc->cfg, nr); j++)
        if ((long long)scene_row_value(&sc->cfg, nr, j) < n)
            n = (long long)scene_row_value(&sc->cfg, nr, j);
    if (k > n)
        scene_var_error(sc, (size_t)row(group, key),
                        "%s = %lld is beyond the chain (n_granules = %lld)", key, k, n);
}

static void check_fit(scene *sc)
{
    const scene_fit_config *fit = &sc->cfg.fit;
    check_fit_report(sc);
    check_fit_theory(sc);
    check_window(sc, "fit", "k_min", fit->k_min);
    check_window(sc, "fit", "k_max", fit->k_max);
    if (fit->k_max > 0 && fit->k_max < fit->k_min + 2)
        scene_var_error(sc, (size_t)row("fit", "k_max"),
                        "the window k_min = %lld .. k_max = %lld has fewer than 3 granules",
                        fit->k_min, fit->k_max);
}

/* &output columns -> column_set: known names, and none the run cannot
 * have (the numerics' columns without numerics). */
static void resolve_columns(scene *sc)
{
    scene_output_config *o = &sc->cfg.output;
    int numerics = sc->cfg.solver.numerics;
    size_t r = (size_t)row("output", "columns");
    unsigned set = 1u << SCENE_COL_K;
    const char *p = o->columns;
    int named = 0;
    while (*p) {
        size_t n = strcspn(p, " ,\t");
        if (n == 0) {
            p++;
            continue;
        }
        int c = 0;
        while (c < SCENE_N_COLUMNS && !(strlen(scene_column_name((scene_column)c)) == n &&
                                          strncmp(scene_column_name((scene_column)c), p, n) == 0))
            c++;
        if (c == SCENE_N_COLUMNS) {
            scene_var_error(sc, r, "no column '%.*s' (columns: k R m X0 t_pass T_res v_peak "
                            "t_peak X_pass theory_v theory_T theory_t)", n > 31 ? 31 : (int)n, p);
            return;
        }
        if (!numerics && scene_column_numerics((scene_column)c)) {
            scene_var_error(sc, r, "column %s is a result of the dynamics, and &solver "
                            "numerics = .false.: drop it or turn the numerics on",
                            scene_column_name((scene_column)c));
            return;
        }
        set |= 1u << c;
        named = 1;
        p += n;
    }
    if (!named)
        for (int c = 0; c < SCENE_N_COLUMNS; c++)
            if (numerics || !scene_column_numerics((scene_column)c)) set |= 1u << c;
    o->column_set = set;
}

/* Optional groups: what each needs from the others. */
static void check_optional(scene *sc)
{
    const scene_config *cfg = &sc->cfg;
    if (cfg->runs.fit) check_fit(sc);
    if (cfg->runs.table) {
        if (!cfg->runs.fit)
            scene_var_error(sc, (size_t)row("table", "name"),
                            "a table tabulates the fit: give &fit model (and x, y, window)");
        const char *lists[] = {"paper_theory", "paper_numerics"};
        const scene_reals *values[] = {&cfg->table.paper_theory, &cfg->table.paper_numerics};
        for (int i = 0; i < 2; i++) {
            int r = row("table", lists[i]);
            if (sc->origin[r].given && values[i]->n != cfg->runs.n)
                scene_var_error(sc, (size_t)r,
                                "%zu values for %zu runs: give one value per swept value",
                                values[i]->n, cfg->runs.n);
        }
    }
    if (cfg->runs.figure) {
        check_window(sc, "figure", "k_max", cfg->figure.k_max);
        /* Curves of the dynamics without the dynamics: a figure with no
         * data, which gnuplot refuses after the runs (issue 36, item 6). */
        if (cfg->figure.curves == SCENE_CURVES_NUMERICS && !cfg->solver.numerics)
            scene_var_error(sc, (size_t)row("figure", "curves"),
                            "curves = 'numerics' draws the dynamics, and &solver numerics = "
                            ".false.: draw curves = 'theory' (or 'both'), or turn the numerics "
                            "on");
        if (cfg->figure.inset && !cfg->runs.fit)
            scene_var_error(sc, (size_t)row("figure", "inset"),
                            "the inset shows the fit: give &fit model (and x, y, window)");
    }
}

size_t scene_validate(scene *sc)
{
    size_t before = sc->n_errors;
    for (size_t i = 0; i < scene_var_count(); i++) {
        const scene_var *var = scene_var_at(i);
        if (var->lib == SCENE_OWN) check_own(sc, i);
    }
    if (sc->n_errors != before) return sc->n_errors - before;
    scene_read_radii(sc);
    if (sc->n_errors != before) return sc->n_errors - before;
    resolve_custom(sc);
    check_unused(sc);
    resolve_runs(sc);
    resolve_columns(sc);
    scene_check_physics(sc);
    if (!sc->cfg.output.dir[0])
        scene_var_error(sc, (size_t)row("output", "dir"), "the output directory must not be empty");
    /* The library checks its settings one by one, then their relations;
     * the scene's own relations assume values the library accepted. */
    scene_check_library(sc);
    if (sc->n_errors == before) check_taper_given(sc);
    if (sc->n_errors == before) check_optional(sc);
    if (sc->n_errors == before) scene_check_fit_library(sc);
    return sc->n_errors - before;
}
