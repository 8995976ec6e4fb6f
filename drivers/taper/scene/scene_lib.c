/*
 * scene_lib.c -- where the scene meets the library's settings: the
 * defaults of the chain and solver variables are read from freshly
 * allocated library specs; the settings go into the specs through the
 * library's setters; and validation is those same setter calls (each value
 * of a sweep too) plus taper_chain_spec_check, each refusal reported
 * against the variable the library names in taper_error.field.  No bound
 * of a library setting is repeated here.
 */
#include "scene_impl.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* ---- defaults ---------------------------------------------------------------- */

static int one_value(scene_reals *r, double x)
{
    free(r->v);
    r->n = 0;
    if (!(r->v = malloc(sizeof *r->v))) return -1;
    r->v[0] = x;
    r->n = 1;
    return 0;
}

int scene_library_defaults(scene_config *cfg)
{
    taper_chain_spec *chain = taper_chain_spec_alloc(NULL);
    taper_solver_spec *solver = taper_solver_spec_alloc(NULL);
    int rc = -1;
    if (!chain || !solver) goto out;
    cfg->chain.profile = taper_chain_spec_profile(chain);
    cfg->chain.n_granules = (long long)taper_chain_spec_n_granules(chain);
    if (one_value(&cfg->chain.s, taper_chain_spec_s(chain)) != 0) goto out;
    if (one_value(&cfg->chain.q, taper_chain_spec_q(chain)) != 0) goto out;
    cfg->chain.exponent = taper_chain_spec_exponent(chain);
    cfg->chain.disorder = (int)taper_chain_spec_disorder(chain);
    cfg->chain.disorder_amplitude = taper_chain_spec_disorder_amplitude(chain);
    cfg->chain.seed = (long long)taper_chain_spec_disorder_seed(chain);
    cfg->chain.load = taper_chain_spec_load(chain);
    cfg->ends.left = (int)taper_chain_spec_end(chain, TAPER_LEFT);
    cfg->ends.right = (int)taper_chain_spec_end(chain, TAPER_RIGHT);
    cfg->ends.left_compliance = taper_chain_spec_end_compliance(chain, TAPER_LEFT);
    cfg->ends.right_compliance = taper_chain_spec_end_compliance(chain, TAPER_RIGHT);
    cfg->striker.radius = taper_chain_spec_striker_radius(chain);
    cfg->striker.density = taper_chain_spec_striker_density(chain);
    cfg->striker.compliance = taper_chain_spec_striker_compliance(chain);
    {
        const double T = taper_chain_spec_piston_duration(chain);
        cfg->striker.piston = T > 0.0 ? (isinf(T) ? SCENE_PISTON_STEADY : SCENE_PISTON_PUSH)
                                      : SCENE_PISTON_NONE;
        cfg->striker.piston_duration = isinf(T) ? 0.0 : T;
        cfg->striker.piston_compliance = taper_chain_spec_piston_compliance(chain);
    }
    cfg->losses.damping = taper_chain_spec_damping(chain);
    cfg->losses.drag = taper_chain_spec_drag(chain);
    cfg->solver.method = taper_solver_spec_method(solver);
    cfg->solver.rtol = taper_solver_spec_rtol(solver);
    cfg->solver.atol = taper_solver_spec_atol(solver);
    cfg->solver.window = taper_solver_spec_window(solver) != 0;
    cfg->solver.last_granule = (long long)taper_solver_spec_last_granule(solver);
    cfg->solver.t_max = taper_solver_spec_t_max(solver);
    cfg->solver.max_steps = taper_solver_spec_max_steps(solver);
    cfg->solver.t_end = taper_solver_spec_t_end(solver);
    rc = 0;
out:
    taper_chain_spec_free(chain);
    taper_solver_spec_free(solver);
    return rc;
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

static void set_s_or_q(sink *k, const scene_config *cfg, scene_chain_param p, size_t point,
                       taper_chain_spec *spec)
{
    taper_error e;
    double x = scene_param_value(cfg, p, point);
    if (p == SCENE_PARAM_S)
        note(k, taper_chain_spec_set_s(spec, x, &e), &e);
    else
        note(k, taper_chain_spec_set_q(spec, x, &e), &e);
}

/* The settings of issue 15 (ends, striker, load, losses, disorder,
 * pattern, materials) of a configuration at one point.  With &material, the
 * walls' and the striker's compliances and density follow from their
 * materials (scene_physics.c). */
static void apply_beyond_paper(sink *k, const scene_config *at, taper_chain_spec *spec)
{
    const scene_chain_config *c = &at->chain;
    taper_error e;
    note(k, taper_chain_spec_set_pattern(spec, c->pattern.v, c->pattern.n, &e), &e);
    note(k, taper_chain_spec_set_disorder(spec, (taper_disorder)c->disorder,
                                          c->disorder_amplitude, (uint64_t)c->seed, &e), &e);
    note(k, taper_chain_spec_set_load(spec, c->load, &e), &e);

    /* With &material: a wall's compliance from its material (a free end
     * keeps the library's 0), the striker's density and compliance from
     * its material (none: the library's 1). */
    scene_material_props mp;
    scene_material_resolve(at, &mp);
    int mat = at->material.on;
    const scene_ends_config *ends = &at->ends;
    double cl = !mat ? ends->left_compliance : ends->left == TAPER_END_WALL ? mp.wall_compliance : 0;
    double cr = !mat ? ends->right_compliance : ends->right == TAPER_END_WALL ? mp.wall_compliance : 0;
    note(k, taper_chain_spec_set_end(spec, TAPER_LEFT, (taper_boundary)ends->left, cl, &e), &e);
    note(k, taper_chain_spec_set_end(spec, TAPER_RIGHT, (taper_boundary)ends->right, cr, &e), &e);
    const scene_striker_config *st = &at->striker;
    int striker_mat = mat && st->radius > 0;
    note(k, taper_chain_spec_set_striker(spec, st->radius,
                                         striker_mat ? mp.striker_density : st->density,
                                         striker_mat ? mp.striker_compliance : st->compliance, &e),
         &e);
    /* The piston: 'steady' is an infinite duration (a scene holds finite
     * numbers); 'none' passes the duration on, so that one given without a
     * piston is refused by name (scene_check.c) rather than ignored. */
    const double T = st->piston == SCENE_PISTON_STEADY ? INFINITY
                     : st->piston == SCENE_PISTON_PUSH ? st->piston_duration : 0.0;
    note(k, taper_chain_spec_set_piston(spec, T, st->piston_compliance, &e), &e);
    note(k, taper_chain_spec_set_damping(spec, at->losses.damping, &e), &e);
    note(k, taper_chain_spec_set_drag(spec, at->losses.drag, &e), &e);

    /* Mixed chains: per-granule materials; one material: none (exactly the
     * library's single-material chain). */
    double *density = NULL, *compliance = NULL;
    size_t n = mat && mp.mixed ? (size_t)c->n_granules : 0;
    if (n && scene_material_arrays(at, n, &density, &compliance) != 0) {
        e.status = TAPER_ENOMEM;
        e.field = NULL;
        snprintf(e.message, sizeof e.message, "out of memory");
        note(k, TAPER_ENOMEM, &e);
        return;
    }
    note(k, taper_chain_spec_set_materials(spec, density, compliance, n, &e), &e);
    free(density);
    free(compliance);
}

/* Every chain setting, at run `point` of a sweep. */
static void apply_chain(sink *k, const scene_config *cfg, size_t point, taper_chain_spec *spec)
{
    scene_config at; /* every swept variable at this point (scene_sweep.c) */
    scene_config_at(cfg, point, &at);
    const scene_chain_config *c = &at.chain;
    taper_error e;
    note(k, taper_chain_spec_set_profile(spec, c->profile, &e), &e);
    /* Negative counts never get here (scene_check.c). */
    note(k, taper_chain_spec_set_n_granules(spec, (size_t)c->n_granules, &e), &e);
    set_s_or_q(k, &at, SCENE_PARAM_S, 0, spec);
    set_s_or_q(k, &at, SCENE_PARAM_Q, 0, spec);
    note(k, taper_chain_spec_set_exponent(spec, c->exponent, &e), &e);
    /* Radii from a file (scene_physics.c) or inline. */
    const scene_reals *radii = c->file_radii.n ? &c->file_radii : &c->radii;
    note(k, taper_chain_spec_set_radii(spec, radii->v, radii->n, &e), &e);
    apply_beyond_paper(k, &at, spec);
}

static void apply_solver(sink *k, const scene_config *cfg, size_t point, taper_solver_spec *spec)
{
    scene_config at;
    scene_config_at(cfg, point, &at);
    const scene_solver_config *s = &at.solver;
    taper_error e;
    note(k, taper_solver_spec_set_method(spec, s->method, &e), &e);
    note(k, taper_solver_spec_set_rtol(spec, s->rtol, &e), &e);
    note(k, taper_solver_spec_set_atol(spec, s->atol, &e), &e);
    note(k, taper_solver_spec_set_window(spec, s->window, &e), &e);
    note(k, taper_solver_spec_set_last_granule(spec, (size_t)s->last_granule, &e), &e);
    note(k, taper_solver_spec_set_t_max(spec, s->t_max, &e), &e);
    note(k, taper_solver_spec_set_max_steps(spec, (long)s->max_steps, &e), &e);
    note(k, taper_solver_spec_set_t_end(spec, s->t_end, &e), &e);
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

/* Sweeps of several variables whose every run breaks the relations are an
 * error of the scene (issue 18: refused before any run): the runs are
 * walked until one satisfies them, at most this many (a grid this large
 * whose first runs all break the relations is refused too). */
#define RELATION_SCAN_MAX 100000

/* A grid of several swept variables: does some run satisfy the relations?
 * If not, the first run's refusal becomes the scene's error. */
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
 * other value of each swept variable through its setter.  With one swept
 * variable (or none) the relations between the settings
 * (taper_chain_spec_check) are checked at every point: a value that breaks
 * them is an error of the scene.  In a sweep of several variables some
 * combinations may break them while others run: those runs fail alone
 * (the chain's allocation checks them) and the sweep marks them; but a
 * grid where no run holds is refused (check_some_run_holds). */
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
    int relations = cfg->runs.n_swept <= 1;
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
