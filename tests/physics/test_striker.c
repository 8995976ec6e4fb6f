/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_striker.c -- the striker (taper.h, taper_chain_spec_set_striker;
 * docs/physics.md, "Striker") and the sampler
 * (taper_solver_spec_set_sampler, _set_t_end), through the public header
 * (suite 'physics'):
 *
 *  - a striker identical to granule 1 (radius, density and compliance 1)
 *    makes the chain of N granules the paper's chain of N + 1 shifted by
 *    one: granule k of the first is granule k + 1 of the second, the
 *    striker granule 1.  Same equations, so the observables and the states
 *    at t_end agree to the tolerance: an independent check of the striker's
 *    mass, contact, initial velocity and the index offset;
 *  - a light striker rebounds, granule 1's v_peak is a maximum found by
 *    the root finder (not 1 at t = 0) below the binary-collision value
 *    2 m_s / (m_s + m_1), and momentum P(0) = m_s is conserved;
 *  - the sampler is called at exactly j * interval while the run lasts,
 *    its last call at t_end sees the state taper_sim_state reads after the
 *    run, a sample agrees with a run that ends there, sampling leaves the
 *    integration's steps unchanged, and a non-zero return stops the
 *    run (TAPER_EINTERRUPTED at that sample time).
 */
#include "test_util.h"

#include "taper.h"

#include <stdlib.h>

#define N_GRANULES 20
#define RTOL 1e-12

static taper_chain *chain_with_striker(size_t n, double radius)
{
    taper_chain_spec *spec = taper_chain_spec_alloc(NULL);
    assert_int_equal(taper_chain_spec_set_n_granules(spec, n, NULL), TAPER_OK);
    if (radius > 0.0)
        assert_int_equal(taper_chain_spec_set_striker(spec, radius, 1.0, 1.0, NULL), TAPER_OK);
    taper_chain *chain = taper_chain_alloc(spec, NULL);
    assert_non_null(chain);
    taper_chain_spec_free(spec);
    return chain;
}

static taper_sim *run(const taper_chain *chain, double t_end, double interval,
                      taper_sample_fn fn, void *user, taper_status expected)
{
    taper_solver_spec *spec = taper_solver_spec_alloc(NULL);
    assert_int_equal(taper_solver_spec_set_rtol(spec, RTOL, NULL), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_t_end(spec, t_end, NULL), TAPER_OK);
    if (fn) assert_int_equal(taper_solver_spec_set_sampler(spec, interval, fn, user, NULL), TAPER_OK);
    taper_sim *sim = taper_sim_alloc(chain, spec, NULL);
    assert_non_null(sim);
    taper_solver_spec_free(spec);
    taper_error err;
    taper_status status = taper_sim_run(sim, &err);
    if (status != expected) print_error("%s\n", err.message);
    assert_int_equal(status, expected);
    return sim;
}

static void identical_striker_is_one_more_granule(void **state)
{
    (void)state;
    taper_chain *struck = chain_with_striker(N_GRANULES, 1.0);
    taper_chain *longer = chain_with_striker(N_GRANULES + 1, 0.0);
    assert_double_rel(taper_chain_striker_mass(struck), 1.0, 1e-15);
    taper_sim *a = run(struck, 40.0, 0.0, NULL, NULL, TAPER_OK);
    taper_sim *b = run(longer, 40.0, 0.0, NULL, NULL, TAPER_OK);
    assert_double_rel(taper_sim_statistic(a, TAPER_STAT_ENERGY_INITIAL), 0.5, 1e-15);
    for (int o = 0; o < TAPER_N_OBSERVABLES; o++) {
        const double *x = taper_sim_observable(a, (taper_observable)o);
        const double *y = taper_sim_observable(b, (taper_observable)o);
        for (size_t k = 1; k + 1 < N_GRANULES; k++) {
            if (o == TAPER_T_RES) continue; /* t_pass(0) = 0 differs by definition */
            double xo = x[k - 1], yo = y[k];
            if (o == TAPER_X_PASS) { /* centres differ by the striker's place */
                xo -= taper_chain_rest_position(struck)[0];
                yo -= taper_chain_rest_position(longer)[1];
            }
            assert_double_rel(xo, yo, 1e-9);
        }
    }
    double xs, vs, *xa = malloc(N_GRANULES * sizeof(double)), *va = malloc(N_GRANULES * sizeof(double));
    double *xb = malloc((N_GRANULES + 1) * sizeof(double)), *vb = malloc((N_GRANULES + 1) * sizeof(double));
    assert_int_equal(taper_sim_striker_state(a, &xs, &vs, NULL), TAPER_OK);
    assert_int_equal(taper_sim_state(a, xa, va, NULL), TAPER_OK);
    assert_int_equal(taper_sim_state(b, xb, vb, NULL), TAPER_OK);
    assert_double_abs(xs, xb[0], 1e-9);
    assert_double_abs(vs, vb[0], 1e-9);
    for (size_t k = 0; k < N_GRANULES; k++) {
        assert_double_abs(xa[k], xb[k + 1], 1e-9);
        assert_double_abs(va[k], vb[k + 1], 1e-9);
    }
    /* GRANULE_REACHED counts granules, not bodies: N - 1 for either run
     * (the last granule has no pass); the striker, body 0, made it N. */
    assert_true(taper_sim_statistic(a, TAPER_STAT_GRANULE_REACHED) == (double)(N_GRANULES - 1));
    assert_true(taper_sim_statistic(b, TAPER_STAT_GRANULE_REACHED) == (double)N_GRANULES);
    /* a chain without a striker has no striker state */
    taper_error err;
    assert_int_equal(taper_sim_striker_state(b, &xs, &vs, &err), TAPER_EINVAL);
    free(xa), free(va), free(xb), free(vb);
    taper_sim_free(a);
    taper_sim_free(b);
    taper_chain_free(struck);
    taper_chain_free(longer);
}

static void light_striker_rebounds(void **state)
{
    (void)state;
    taper_chain *chain = chain_with_striker(N_GRANULES, 0.5);
    const double ms = taper_chain_striker_mass(chain);
    taper_sim *sim = run(chain, 0.0, 0.0, NULL, NULL, TAPER_OK);
    const double v1 = taper_sim_observable(sim, TAPER_V_PEAK)[0];
    const double t1 = taper_sim_observable(sim, TAPER_T_PEAK)[0];
    printf("striker of mass %g: v_peak(1) = %.12g at t = %.12g (binary collision %.12g)\n", ms, v1,
           t1, 2.0 * ms / (ms + 1.0));
    assert_true(t1 > 0.0);
    assert_true(v1 > 0.5 * 2.0 * ms / (ms + 1.0) && v1 < 2.0 * ms / (ms + 1.0));
    double xs, vs;
    assert_int_equal(taper_sim_striker_state(sim, &xs, &vs, NULL), TAPER_OK);
    assert_true(vs < 0.0 && xs < 0.0); /* bounced back */
    assert_double_rel(taper_sim_statistic(sim, TAPER_STAT_ENERGY_INITIAL), 0.5 * ms, 1e-15);
    /* measured 3e-12 and 1e-9: the window lets granules behind the pulse
     * leave at rest within the tolerance (docs/window.md) */
    assert_true(taper_sim_statistic(sim, TAPER_STAT_MOMENTUM_ERROR) <= 1e-10);
    assert_true(taper_sim_statistic(sim, TAPER_STAT_ENERGY_ERROR) <= 1e-9);
    /* the striker's contact: force[0] is its push, zero once it left */
    double f[N_GRANULES + 1];
    assert_int_equal(taper_sim_forces(sim, f, NULL), TAPER_OK);
    assert_true(f[0] == 0.0);
    taper_sim_free(sim);
    taper_chain_free(chain);
}

/* ---- the sampler ------------------------------------------------------------- */
typedef struct samples {
    int calls, stop_at;
    double interval;
    int times_exact;
    double x[N_GRANULES], v[N_GRANULES]; /* the last sample's state */
    double x_at[N_GRANULES];              /* the state at t_probe */
    double t_probe, last_t;
} samples;

static int record(const taper_sim *sim, void *user)
{
    samples *s = user;
    const double t = taper_sim_time(sim);
    if (t != (double)s->calls * s->interval) s->times_exact = 0;
    s->calls++;
    s->last_t = t;
    assert_int_equal(taper_sim_state(sim, s->x, s->v, NULL), TAPER_OK);
    if (t == s->t_probe) memcpy(s->x_at, s->x, sizeof s->x);
    return s->stop_at && s->calls == s->stop_at;
}

static void sampler_times_and_state(void **state)
{
    (void)state;
    taper_chain *chain = chain_with_striker(N_GRANULES, 0.0);
    samples s = {.interval = 0.25, .times_exact = 1, .t_probe = 7.5};
    taper_sim *sim = run(chain, 30.0, 0.25, record, &s, TAPER_OK);
    /* t = 0, 0.25, ..., 30: every one exactly j * interval, and the run
     * ends at t_end */
    assert_int_equal(s.calls, 121);
    assert_true(s.times_exact);
    assert_true(taper_sim_statistic(sim, TAPER_STAT_T_FINAL) == 30.0);
    assert_true(taper_sim_time(sim) == 30.0);
    /* the last sample saw the final state */
    double x[N_GRANULES], v[N_GRANULES];
    assert_int_equal(taper_sim_state(sim, x, v, NULL), TAPER_OK);
    for (size_t k = 0; k < N_GRANULES; k++) assert_true(x[k] == s.x[k] && v[k] == s.v[k]);
    /* a sample is the state a run ending there has (t_end = 7.5 comes
     * before the observables are known, so stop that run with t_max) */
    taper_solver_spec *spec = taper_solver_spec_alloc(NULL);
    assert_int_equal(taper_solver_spec_set_rtol(spec, RTOL, NULL), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_t_max(spec, s.t_probe, NULL), TAPER_OK);
    taper_sim *cut = taper_sim_alloc(chain, spec, NULL);
    assert_int_equal(taper_sim_run(cut, NULL), TAPER_ELIMIT);
    assert_true(taper_sim_time(cut) == s.t_probe);
    assert_int_equal(taper_sim_state(cut, x, NULL, NULL), TAPER_OK);
    for (size_t k = 0; k < N_GRANULES; k++) assert_double_abs(x[k], s.x_at[k], 1e-9);
    taper_sim_free(cut);
    taper_solver_spec_free(spec);
    /* sampling does not disturb the integration: CVODE interpolates at the
     * sample times and keeps its steps, so a run without the sampler takes
     * the same steps; only the root finder's iterations start elsewhere
     * (from the sample time), moving event times within its 1e-14 */
    taper_sim *plain = run(chain, 30.0, 0.0, NULL, NULL, TAPER_OK);
    assert_true(taper_sim_statistic(plain, TAPER_STAT_STEPS) == taper_sim_statistic(sim, TAPER_STAT_STEPS));
    for (int o = 0; o < TAPER_N_OBSERVABLES; o++) {
        if (o == TAPER_T_RES) continue; /* differences of pass times */
        const double *a = taper_sim_observable(sim, (taper_observable)o);
        const double *b = taper_sim_observable(plain, (taper_observable)o);
        for (size_t k = 0; k + 1 < N_GRANULES; k++) assert_double_rel(a[k], b[k], 1e-12);
    }
    assert_int_equal(taper_sim_state(plain, x, v, NULL), TAPER_OK);
    for (size_t k = 0; k < N_GRANULES; k++) {
        assert_double_abs(x[k], s.x[k], 1e-12);
        assert_double_abs(v[k], s.v[k], 1e-12);
    }
    taper_sim_free(plain);
    taper_sim_free(sim);
    taper_chain_free(chain);
}

static void sampler_stops_the_run(void **state)
{
    (void)state;
    taper_chain *chain = chain_with_striker(N_GRANULES, 0.0);
    samples s = {.interval = 0.5, .times_exact = 1, .stop_at = 4, .t_probe = -1.0};
    taper_sim *sim = run(chain, 0.0, 0.5, record, &s, TAPER_EINTERRUPTED);
    assert_int_equal(s.calls, 4);
    assert_true(taper_sim_statistic(sim, TAPER_STAT_T_FINAL) == 1.5);
    assert_true(taper_sim_statistic(sim, TAPER_STAT_COMPLETE) == 0.0);
    taper_sim_free(sim);
    taper_chain_free(chain);
}

/* t_end only ever lengthens a run: one ending before the observables are
 * known goes on until they are, as without it (taper.h). */
static void t_end_before_the_observables(void **state)
{
    (void)state;
    taper_chain *chain = chain_with_striker(N_GRANULES, 0.0);
    taper_sim *a = run(chain, 1.0, 0.0, NULL, NULL, TAPER_OK);
    taper_sim *b = run(chain, 0.0, 0.0, NULL, NULL, TAPER_OK);
    assert_true(taper_sim_statistic(a, TAPER_STAT_COMPLETE) == 1.0);
    assert_true(taper_sim_statistic(a, TAPER_STAT_T_FINAL) == taper_sim_statistic(b, TAPER_STAT_T_FINAL));
    assert_true(taper_sim_statistic(a, TAPER_STAT_T_FINAL) > 1.0);
    taper_sim_free(a);
    taper_sim_free(b);
    taper_chain_free(chain);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(identical_striker_is_one_more_granule),
        cmocka_unit_test(light_striker_rebounds),
        cmocka_unit_test(sampler_times_and_state),
        cmocka_unit_test(sampler_stops_the_run),
        cmocka_unit_test(t_end_before_the_observables),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
