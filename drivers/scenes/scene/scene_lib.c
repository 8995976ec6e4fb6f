/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * scene_lib.c -- where the scene meets the library's settings.  Every
 * setting of the library's table of settings is a variable of the scene
 * (scene.c); its value goes into the spec through the library's by-name
 * setters, converted from SI when the scene has &material; and validation
 * is those same calls (each value of a sweep too) plus
 * taper_chain_spec_check, each refusal reported against the variable the
 * library names in taper_error.field.  No bound of a library setting is
 * repeated here.  What the scene adds are its own rules of presentation:
 * a radii file, the piston's 'push'/'steady', and with &material the
 * compliances and densities that follow from the materials.
 */
#include "scene_impl.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* ---- units ------------------------------------------------------------------------ */

/* The SI value of one rescaled unit of `dim` in a configuration at one
 * point: with &material a setting of that dimension is given in SI (the
 * unit of taper_dimension_unit), divided by this to reach the library's
 * rescaled units; 1 without &material.  (A setting the scene leaves out
 * is the library's default, in the library's units: its scale is 1.) */
double scene_input_scale(const scene_config *at, taper_dimension dim)
{
    if (!at->material.on || dim == TAPER_DIM_NUMBER) return 1.0;
    scene_material_props p;
    scene_material_resolve(at, &p);
    return taper_unit_scale(dim, p.young, p.poisson, p.density, at->material.radius,
                            at->material.velocity);
}

double scene_sample_interval(const scene_config *at)
{
    return at->sensors.interval / scene_input_scale(at, TAPER_DIM_TIME);
}

/* ---- setter calls ---------------------------------------------------------------- */

/* Where refusals go: recorded against their variable in a scene being
 * validated (one error per variable), and/or the first kept for a caller. */
typedef struct sink {
    scene *sc;            /* NULL: not validating                          */
    scene_lib lib;
    taper_error *first;   /* NULL: not wanted                              */
    taper_status status;  /* the first refusal's status                    */
} sink;

static int already_reported(const scene *sc, const scene_var *var)
{
    for (size_t i = 0; i < sc->n_diags; i++)
        if (strcmp(sc->diags[i].group, var->group) == 0 && strcmp(sc->diags[i].key, var->name) == 0)
            return 1;
    return 0;
}

static void note(sink *k, taper_status status, const taper_error *e)
{
    if (status == TAPER_OK) return;
    if (k->status == TAPER_OK) {
        k->status = status;
        if (k->first) *k->first = *e;
    }
    if (!k->sc) return;
    int i = scene_error_row(k->sc, k->lib, e->field);
    if (i < 0)
        scene_error(k->sc, 0, NULL, NULL, "%s", e->message);
    else if (!already_reported(k->sc, scene_var_at((size_t)i)))
        scene_var_error(k->sc, (size_t)i, "%s", e->message);
}

static void out_of_memory_note(sink *k)
{
    taper_error e = {.status = TAPER_ENOMEM};
    snprintf(e.message, sizeof e.message, "out of memory");
    note(k, TAPER_ENOMEM, &e);
}

/* A refused value that the scene converted from SI: the library speaks of
 * the rescaled value; say what the scene gave. */
static void explain_units(taper_error *e, const scene_var *var, double given, double scale)
{
    if (scale == 1.0 || e->status != TAPER_EINVAL) return;
    size_t used = strlen(e->message);
    char g[SCENE_REAL_TEXT];
    scene_format_real(given, g);
    snprintf(e->message + used, sizeof e->message - used,
             " (the scene's %s = %s %s in the rescaled units of eq. (5))", var->name, g,
             taper_dimension_unit(var->dim));
}

/* One scalar setting of row var into its spec. */
static void set_scalar(sink *k, const scene_var *var, double value, double scale, void *spec)
{
    taper_error e;
    taper_status st = var->setting->object == TAPER_SETTING_CHAIN
                          ? taper_chain_spec_set_option(spec, var->keyword, value / scale, &e)
                          : taper_solver_spec_set_option(spec, var->keyword, value / scale, &e);
    if (st != TAPER_OK) explain_units(&e, var, value, scale);
    note(k, st, &e);
}

/* One list setting: values[0..n) divided by scale (a copy when scaled). */
static void set_list(sink *k, const scene_var *var, const double *values, size_t n, double scale,
                     taper_chain_spec *spec)
{
    double *scaled = NULL;
    if (scale != 1.0 && n > 0) {
        if (!(scaled = malloc(n * sizeof *scaled))) {
            out_of_memory_note(k);
            return;
        }
        for (size_t j = 0; j < n; j++) scaled[j] = values[j] / scale;
        values = scaled;
    }
    taper_error e;
    note(k, taper_chain_spec_set_option_list(spec, var->keyword, values, n, &e), &e);
    free(scaled);
}

static int is(const scene_var *var, const char *keyword) { return strcmp(var->keyword, keyword) == 0; }

/* The value of a scalar chain setting, with the scene's own rules: with
 * &material a wall's and the striker's compliance and density follow from
 * their materials (already relative to granule 1's: *scale 1); the piston's
 * 'steady' is an infinite duration ('none' passes the duration on, so that
 * one given without a piston is refused by name rather than ignored). */
static double chain_value(const scene_config *at, const scene_var *var,
                          const scene_material_props *mp, double *scale)
{
    double x = scene_row_value(at, scene_var_index(var), 0);
    if (at->material.on) {
        int left = is(var, "left_compliance"), right = is(var, "right_compliance");
        if (left || right) {
            *scale = 1.0;
            taper_boundary b = (taper_boundary)scene_setting(at, left ? "left" : "right");
            return b == TAPER_END_WALL ? mp->wall_compliance : 0.0;
        }
        if ((is(var, "striker_density") || is(var, "striker_compliance")) &&
            scene_setting(at, "striker_radius") > 0) {
            *scale = 1.0;
            return is(var, "striker_density") ? mp->striker_density : mp->striker_compliance;
        }
    }
    if (is(var, "piston_duration") && at->striker.piston == SCENE_PISTON_STEADY) return INFINITY;
    return x;
}

/* A list chain setting, with the scene's own rules: radii from a file, and
 * with &material a mixed chain's densities and compliances (*scale 1: the
 * library divides them by granule 1's). */
/* The scale of a row's value: SI to rescaled when the scene gave it. */
static double scale_of(const scene_config *at, const scene_var *var)
{
    return scene_setting_given(at, var) ? scene_input_scale(at, var->dim) : 1.0;
}

static void apply_chain_list(sink *k, const scene_config *at, const scene_var *var,
                             const scene_material_props *mp, taper_chain_spec *spec)
{
    double scale = scale_of(at, var);
    const scene_reals *r = scene_cfield(at, var);
    if (is(var, "radii") && at->chain.file_radii.n) r = &at->chain.file_radii;
    int from_material = at->material.on && (is(var, "densities") || is(var, "compliances"));
    if (!from_material) {
        set_list(k, var, r->v, r->n, scale, spec);
        return;
    }
    double *density = NULL, *compliance = NULL;
    size_t n = mp->mixed ? (size_t)scene_setting(at, "n_granules") : 0;
    if (n && scene_material_arrays(at, n, &density, &compliance) != 0) {
        out_of_memory_note(k);
        return;
    }
    set_list(k, var, is(var, "densities") ? density : compliance, n, 1.0, spec);
    free(density);
    free(compliance);
}

/* Every chain setting, at run `point` of a sweep. */
static void apply_chain(sink *k, const scene_config *cfg, size_t point, taper_chain_spec *spec)
{
    scene_config at; /* every swept variable at this point (scene_sweep.c) */
    scene_config_at(cfg, point, &at);
    scene_material_props mp;
    scene_material_resolve(&at, &mp);
    for (size_t i = 0; i < scene_var_count(); i++) {
        const scene_var *var = scene_var_at(i);
        if (!var->setting || var->setting->object != TAPER_SETTING_CHAIN) continue;
        if (var->type == SCENE_REAL_LIST) {
            apply_chain_list(k, &at, var, &mp, spec);
            continue;
        }
        double scale = scale_of(&at, var);
        double x = chain_value(&at, var, &mp, &scale);
        set_scalar(k, var, x, scale, spec);
    }
}

static void apply_solver(sink *k, const scene_config *cfg, size_t point, taper_solver_spec *spec)
{
    scene_config at;
    scene_config_at(cfg, point, &at);
    for (size_t i = 0; i < scene_var_count(); i++) {
        const scene_var *var = scene_var_at(i);
        if (!var->setting || var->setting->object != TAPER_SETTING_SOLVER) continue;
        set_scalar(k, var, scene_row_value(&at, i, 0), scale_of(&at, var), spec);
    }
}

/* &fit as a spec: the model, a fixed exponent when given, granules
 * k_min..k_max as the index window [k_min - 1, k_max). */
static taper_fit_spec *apply_fit(sink *k, const scene_config *cfg)
{
    taper_error e;
    taper_fit_spec *spec = taper_fit_spec_alloc((taper_fit_model)cfg->fit.model, &e);
    if (!spec) {
        note(k, e.status, &e);
        return NULL;
    }
    if (!isnan(cfg->fit.p)) note(k, taper_fit_spec_set_exponent(spec, cfg->fit.p, &e), &e);
    note(k, taper_fit_spec_set_index_window(spec, (size_t)(cfg->fit.k_min - 1),
                                            (size_t)cfg->fit.k_max, &e), &e);
    return spec;
}

static taper_status ok(taper_error *err)
{
    if (err) {
        err->status = TAPER_OK;
        err->field = NULL;
        err->message[0] = '\0';
    }
    return TAPER_OK;
}

taper_status scene_apply_chain(const scene_config *cfg, size_t point, taper_chain_spec *spec,
                               taper_error *err)
{
    sink k = {.lib = SCENE_LIB_CHAIN, .first = err};
    apply_chain(&k, cfg, point, spec);
    return k.status == TAPER_OK ? ok(err) : k.status;
}

taper_status scene_apply_solver(const scene_config *cfg, taper_solver_spec *spec,
                                taper_error *err)
{
    sink k = {.lib = SCENE_LIB_SOLVER, .first = err};
    apply_solver(&k, cfg, 0, spec);
    return k.status == TAPER_OK ? ok(err) : k.status;
}

taper_chain_spec *scene_chain_spec(const scene_config *cfg, size_t point, taper_error *err)
{
    taper_chain_spec *spec = taper_chain_spec_alloc(err);
    if (spec && scene_apply_chain(cfg, point, spec, err) != TAPER_OK) {
        taper_chain_spec_free(spec);
        return NULL;
    }
    return spec;
}

taper_solver_spec *scene_solver_spec(const scene_config *cfg, taper_error *err)
{
    taper_solver_spec *spec = taper_solver_spec_alloc(err);
    if (spec && scene_apply_solver(cfg, spec, err) != TAPER_OK) {
        taper_solver_spec_free(spec);
        return NULL;
    }
    return spec;
}

taper_fit_spec *scene_fit_spec(const scene_config *cfg, taper_error *err)
{
    taper_error local;
    if (!err) err = &local;
    if (cfg->fit.model == SCENE_FIT_NONE) {
        err->status = TAPER_EINVAL;
        err->field = "model";
        snprintf(err->message, sizeof err->message, "no fit: &fit model = 'none'");
        return NULL;
    }
    sink k = {.lib = SCENE_LIB_FIT, .first = err};
    taper_fit_spec *spec = apply_fit(&k, cfg);
    if (k.status != TAPER_OK) {
        taper_fit_spec_free(spec);
        return NULL;
    }
    ok(err);
    return spec;
}

/* ---- validation --------------------------------------------------------------------- */

static void out_of_memory(scene *sc)
{
    scene_error(sc, 0, NULL, NULL, "out of memory");
}

/* Sweeps whose every run breaks the relations are an error of the scene,
 * refused before any run: the runs are walked until one satisfies them,
 * at most this many (a grid this large whose first runs all break the
 * relations is refused too). */
#define RELATION_SCAN_MAX 100000

/* A sweep: does some run satisfy the relations?  If not, the first run's
 * refusal becomes the scene's error. */
static void check_some_run_holds(scene *sc)
{
    const scene_config *cfg = &sc->cfg;
    taper_error first = {0}, e;
    taper_status first_status = TAPER_OK;
    size_t runs = cfg->runs.n < RELATION_SCAN_MAX ? cfg->runs.n : RELATION_SCAN_MAX;
    for (size_t i = 0; i < runs; i++) {
        taper_chain_spec *spec = taper_chain_spec_alloc(NULL);
        if (!spec) {
            out_of_memory(sc);
            return;
        }
        sink k = {.sc = NULL, .lib = SCENE_LIB_CHAIN};
        apply_chain(&k, cfg, i, spec);
        taper_status st = k.status == TAPER_OK ? taper_chain_spec_check(spec, &e) : k.status;
        taper_chain_spec_free(spec);
        if (st == TAPER_OK) return;
        if (first_status == TAPER_OK && k.status == TAPER_OK) {
            first_status = st;
            first = e;
        }
    }
    if (first_status == TAPER_OK) return;
    sink k = {.sc = sc, .lib = SCENE_LIB_CHAIN};
    note(&k, first_status, &first);
}

/* The chain at every run of the sweep: every setting once, then each
 * other value of each swept variable through its setter (a value out of
 * its own range is an error of the scene).  Without a sweep the relations
 * between the settings (taper_chain_spec_check) are checked too: a value
 * that breaks them is an error of the scene.  In a sweep, of one variable
 * or several, some points may break them while others run: those runs fail
 * alone (the chain's allocation checks them, status 5, runs.tsv says why)
 * and the others go on; but a sweep where no run holds is refused
 * (check_some_run_holds). */
static void check_chain(scene *sc)
{
    const scene_config *cfg = &sc->cfg;
    taper_chain_spec *spec = taper_chain_spec_alloc(NULL);
    if (!spec) {
        out_of_memory(sc);
        return;
    }
    sink k = {.sc = sc, .lib = SCENE_LIB_CHAIN};
    taper_error e;
    int relations = cfg->runs.n_swept == 0;
    apply_chain(&k, cfg, 0, spec);
    if (k.status == TAPER_OK && relations) note(&k, taper_chain_spec_check(spec, &e), &e);
    /* The other values of a sweep, once the rest of the chain is right. */
    for (size_t v = 0; k.status == TAPER_OK && v < cfg->runs.n_swept; v++) {
        if (scene_var_at(cfg->runs.swept_row[v])->lib != SCENE_LIB_CHAIN) continue;
        for (size_t j = 1; k.status == TAPER_OK && j < cfg->runs.swept_len[v]; j++) {
            apply_chain(&k, cfg, scene_sweep_point_of(cfg, v, j), spec);
            if (k.status == TAPER_OK && relations)
                note(&k, taper_chain_spec_check(spec, &e), &e);
        }
    }
    taper_chain_spec_free(spec);
    if (k.status == TAPER_OK && !relations) check_some_run_holds(sc);
}

/* The solver's settings, each value of a swept one too. */
static void check_solver(scene *sc, taper_solver_spec *spec)
{
    const scene_config *cfg = &sc->cfg;
    sink k = {.sc = sc, .lib = SCENE_LIB_SOLVER};
    apply_solver(&k, cfg, 0, spec);
    for (size_t v = 0; k.status == TAPER_OK && v < cfg->runs.n_swept; v++) {
        if (scene_var_at(cfg->runs.swept_row[v])->lib != SCENE_LIB_SOLVER) continue;
        for (size_t j = 1; k.status == TAPER_OK && j < cfg->runs.swept_len[v]; j++)
            apply_solver(&k, cfg, scene_sweep_point_of(cfg, v, j), spec);
    }
}

size_t scene_check_library(scene *sc)
{
    size_t before = sc->n_errors;
    check_chain(sc);
    taper_solver_spec *spec = taper_solver_spec_alloc(NULL);
    if (!spec) {
        out_of_memory(sc);
        return sc->n_errors - before;
    }
    check_solver(sc, spec);
    taper_solver_spec_free(spec);
    return sc->n_errors - before;
}

size_t scene_check_fit_library(scene *sc)
{
    size_t before = sc->n_errors;
    if (sc->cfg.fit.model == SCENE_FIT_NONE) return 0;
    sink k = {.sc = sc, .lib = SCENE_LIB_FIT};
    taper_fit_spec_free(apply_fit(&k, &sc->cfg));
    return sc->n_errors - before;
}
