/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_load.c -- precompression (taper.h, taper_chain_spec_set_load;
 * docs/physics.md, "Static load"), checked as physics through the public
 * header (suite 'physics').
 *
 * A monodisperse Hertz chain (r_k = 1, m_k = 1, n = 5/2) under a static
 * force F0 sits at overlaps delta with r delta^(n-1) = F0; small motions
 * about that state are linear with the contact stiffness
 * K = (n-1) r delta^(n-2), and a weak pulse travels at the long-wave sound
 * speed of the linear chain, c0 = sqrt(K/m) granules per unit time
 * (Nesterenko, "Dynamics of Heterogeneous Materials", Springer 2001,
 * ch. 1: the weakly nonlinear limit).  With F0 = 1000 (delta = 100,
 * K = 15, c0 = 3.873) the unit impulse compresses contacts by ~0.26, a
 * 3e-3 fraction of delta: the linear limit.  Checked:
 *  - the pulse speed, from the pass times over the second half of a
 *    200-granule chain, is c0 within 1 % (without the load the pulse is
 *    the Hertz solitary wave, 4.6 times slower);
 *  - the active window and the whole chain give the same pass times and
 *    peaks (the window keeps the granules ahead exactly at rest, and they
 *    are: the last granule has x = v = 0 exactly while the pulse is far);
 *  - the energy measured from the equilibrium, computed here from the
 *    state and the chain's own factors, is conserved; the forces at the
 *    free ends are the load;
 *  - a right wall holds the loaded chain: P(t) - P(0) = F0 t - J_right.
 */
#include "test_util.h"

#include "taper.h"

#include <stdlib.h>

#define LOAD 1000.0
#define N_GRANULES 200

typedef struct watch {
    const taper_chain *chain;
    double *x, *v, *f;
    double e0, max_energy_error;
    double x_last_early, v_last_early, f_last_early; /* at t = 5 */
    int calls;
} watch;

/* (1 + u)^n - 1 - n u, without its cancellation for small u. */
static double excess(double n, double u) { return expm1(n * log1p(u)) - n * u; }

/* Kinetic energy plus U(delta + z) - U(delta) - F0 z per contact: the
 * energy above the loaded equilibrium (the loads' work included). */
static double energy_above_equilibrium(const watch *w)
{
    const size_t N = taper_chain_size(w->chain);
    const double *m = taper_chain_mass(w->chain), *r = taper_chain_contact(w->chain);
    const double n = taper_chain_exponent(w->chain);
    double e = 0.0;
    for (size_t k = 0; k < N; k++) {
        e += 0.5 * m[k] * w->v[k] * w->v[k];
        if (k + 1 < N) {
            double delta = pow(LOAD / r[k], 1.0 / (n - 1.0)), z = w->x[k] - w->x[k + 1];
            assert_true(delta + z > 0.0); /* a weak pulse: no contact opens */
            e += r[k] * pow(delta, n) / n * excess(n, z / delta);
        }
    }
    return e;
}

static int sample(const taper_sim *sim, void *user)
{
    watch *w = user;
    assert_int_equal(taper_sim_state(sim, w->x, w->v, NULL), TAPER_OK);
    assert_int_equal(taper_sim_forces(sim, w->f, NULL), TAPER_OK);
    double e = energy_above_equilibrium(w);
    if (w->calls++ == 0) w->e0 = e;
    w->max_energy_error = fmax(w->max_energy_error, fabs(e - w->e0) / w->e0);
    if (taper_sim_time(sim) == 5.0) {
        w->x_last_early = w->x[N_GRANULES - 1];
        w->v_last_early = w->v[N_GRANULES - 1];
        w->f_last_early = w->f[N_GRANULES - 1];
    }
    /* the free ends are pushed by the load */
    assert_true(w->f[0] == LOAD && w->f[N_GRANULES] == LOAD);
    return 0;
}

static taper_sim *run_loaded(const taper_chain *chain, int window, watch *w)
{
    taper_solver_spec *spec = taper_solver_spec_alloc(NULL);
    assert_int_equal(taper_solver_spec_set_window(spec, window, NULL), TAPER_OK);
    if (w) assert_int_equal(taper_solver_spec_set_sampler(spec, 0.25, sample, w, NULL), TAPER_OK);
    taper_sim *sim = taper_sim_alloc(chain, spec, NULL);
    assert_non_null(sim);
    taper_solver_spec_free(spec);
    taper_error err;
    taper_status status = taper_sim_run(sim, &err);
    if (status != TAPER_OK) print_error("%s\n", err.message);
    assert_int_equal(status, TAPER_OK);
    return sim;
}

static taper_chain *loaded_chain(double load)
{
    taper_chain_spec *spec = taper_chain_spec_alloc(NULL);
    assert_int_equal(taper_chain_spec_set_n_granules(spec, N_GRANULES, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_load(spec, load, NULL), TAPER_OK);
    taper_chain *chain = taper_chain_alloc(spec, NULL);
    assert_non_null(chain);
    taper_chain_spec_free(spec);
    return chain;
}

/* Granules per unit time over the second half of the chain. */
static double pass_speed(const taper_sim *sim)
{
    const double *tp = taper_sim_observable(sim, TAPER_T_PASS);
    const size_t a = N_GRANULES / 2, b = N_GRANULES - 10;
    return (double)(b - a) / (tp[b - 1] - tp[a - 1]);
}

static void weak_pulse_at_sound_speed(void **state)
{
    (void)state;
    taper_chain *chain = loaded_chain(LOAD);
    const double n = taper_chain_exponent(chain);
    const double delta = pow(LOAD, 1.0 / (n - 1.0)), K = (n - 1.0) * pow(delta, n - 2.0);
    const double c0 = sqrt(K / 1.0);
    watch w = {.chain = chain};
    w.x = malloc(N_GRANULES * sizeof(double));
    w.v = malloc(N_GRANULES * sizeof(double));
    w.f = malloc((N_GRANULES + 1) * sizeof(double));
    taper_sim *sim = run_loaded(chain, 1, &w);
    const double c = pass_speed(sim);
    printf("c0 = %.6f, measured %.6f (%+.2f %%); energy error %.2g\n", c0, c, 100.0 * (c / c0 - 1.0),
           w.max_energy_error);
    assert_true(fabs(c / c0 - 1.0) <= 0.01);
    /* energy above the equilibrium, from the state: conserved */
    assert_true(w.max_energy_error <= 1e-7);
    assert_true(taper_sim_statistic(sim, TAPER_STAT_ENERGY_ERROR) <= 1e-7);
    /* ahead of the pulse (at t = 5 it is near granule 20) the chain is
     * exactly at rest in its equilibrium */
    assert_true(w.x_last_early == 0.0 && w.v_last_early == 0.0 && w.f_last_early == LOAD);
    /* the same chain unloaded: the Hertz solitary wave, far slower */
    taper_chain *free_chain = loaded_chain(0.0);
    taper_sim *hertz = run_loaded(free_chain, 1, NULL);
    assert_true(pass_speed(hertz) < 0.5 * c0);
    taper_sim_free(hertz);
    taper_chain_free(free_chain);
    free(w.x), free(w.v), free(w.f);
    taper_sim_free(sim);
    taper_chain_free(chain);
}

/* The window must stay exact under a load: the contact just outside it
 * carries F0, and granules join by the linear stiffness. */
static void window_matches_whole_chain(void **state)
{
    (void)state;
    taper_chain *chain = loaded_chain(LOAD);
    taper_sim *a = run_loaded(chain, 1, NULL), *b = run_loaded(chain, 0, NULL);
    const double *ta = taper_sim_observable(a, TAPER_T_PASS), *tb = taper_sim_observable(b, TAPER_T_PASS);
    const double *va = taper_sim_observable(a, TAPER_V_PEAK), *vb = taper_sim_observable(b, TAPER_V_PEAK);
    double worst_t = 0.0, worst_v = 0.0;
    for (size_t k = 0; k + 1 < N_GRANULES; k++) {
        worst_t = fmax(worst_t, rel_diff(ta[k], tb[k]));
        worst_v = fmax(worst_v, rel_diff(va[k], vb[k]));
    }
    printf("window against whole chain: t_pass %.2g, v_peak %.2g\n", worst_t, worst_v);
    assert_true(worst_t <= 1e-8 && worst_v <= 1e-7);
    taper_sim_free(a);
    taper_sim_free(b);
    taper_chain_free(chain);
}

/* A loaded chain held by a right wall: the wall takes F0 at rest (its own
 * overlap), and the momentum balance P(t) - P(0) = F0 t - J_right holds
 * (the load pushes the free first granule, the wall the last; J_right its
 * whole impulse, static part included). */
static void wall_holds_the_load(void **state)
{
    (void)state;
    taper_chain_spec *spec = taper_chain_spec_alloc(NULL);
    assert_int_equal(taper_chain_spec_set_n_granules(spec, 40, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_load(spec, LOAD, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_end(spec, TAPER_RIGHT, TAPER_END_WALL, 0.0, NULL), TAPER_OK);
    taper_chain *chain = taper_chain_alloc(spec, NULL);
    assert_non_null(chain);
    taper_chain_spec_free(spec);
    taper_solver_spec *solver = taper_solver_spec_alloc(NULL);
    assert_int_equal(taper_solver_spec_set_rtol(solver, 1e-12, NULL), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_t_end(solver, 30.0, NULL), TAPER_OK);
    taper_sim *sim = taper_sim_alloc(chain, solver, NULL);
    assert_int_equal(taper_sim_run(sim, NULL), TAPER_OK);
    const double t = taper_sim_statistic(sim, TAPER_STAT_T_FINAL);
    const double j = taper_sim_statistic(sim, TAPER_STAT_WALL_IMPULSE_RIGHT);
    double v[40], p = 0.0;
    assert_int_equal(taper_sim_state(sim, NULL, v, NULL), TAPER_OK);
    for (size_t k = 0; k < 40; k++) p += taper_chain_mass(chain)[k] * v[k];
    printf("loaded chain against a wall: J_right - F0 t = %.12g, P(t) - P(0) = %.12g\n", j - LOAD * t,
           p - 1.0);
    assert_true(t == 30.0);
    assert_double_abs(p - 1.0, LOAD * t - j, 1e-9);
    assert_true(taper_sim_statistic(sim, TAPER_STAT_MOMENTUM_ERROR) <= 1e-12);
    /* the pulse reflected (t = 30: the wall pushed it back) */
    assert_true(p < 0.0);
    assert_true(taper_sim_statistic(sim, TAPER_STAT_WALL_PEAK_FORCE_RIGHT) > LOAD);
    taper_sim_free(sim);
    taper_solver_spec_free(solver);
    taper_chain_free(chain);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(weak_pulse_at_sound_speed),
        cmocka_unit_test(window_matches_whole_chain),
        cmocka_unit_test(wall_holds_the_load),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
