/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_sample_times.c -- the sampler at given times
 * (taper_solver_spec_set_sample_times), through the public header (suite
 * 'physics'): what a calibration reads at the times of a measurement.
 *
 *  - at times that are the grid's, the samples are bit for bit those of
 *    the interval sampler (the same call of the integrator at the same
 *    times), and the run's observables too;
 *  - at irregular times each sample agrees with a run that ends there (its
 *    state at t_max) to the tolerance, and the integration's steps are
 *    those of a run without sampler;
 *  - times beyond the run's end are not served; t_end reaches them;
 *  - the times are checked: finite, >= 0, strictly increasing, at least
 *    one (field "sample_times"); one sampler replaces the other, and fn
 *    NULL removes it.
 */
#include "test_util.h"

#include "taper.h"

#include <stdlib.h>

#define N_GRANULES 12
#define RTOL 1e-12
#define MAX_SAMPLES 96

static taper_chain *chain_with_wall(void)
{
    taper_chain_spec *spec = taper_chain_spec_alloc(NULL);
    assert_int_equal(taper_chain_spec_set_n_granules(spec, N_GRANULES, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_end(spec, TAPER_RIGHT, TAPER_END_WALL, 1.0, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_striker(spec, 1.2, 1.0, 1.0, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_damping(spec, 0.05, NULL), TAPER_OK);
    taper_chain *chain = taper_chain_alloc(spec, NULL);
    assert_non_null(chain);
    taper_chain_spec_free(spec);
    return chain;
}

typedef struct record {
    size_t n;
    double t[MAX_SAMPLES];
    double x[MAX_SAMPLES][N_GRANULES], v[MAX_SAMPLES][N_GRANULES];
    double wall[MAX_SAMPLES]; /* the right wall's force */
} record;

static int keep(const taper_sim *sim, void *user)
{
    record *r = user;
    assert_true(r->n < MAX_SAMPLES);
    double f[N_GRANULES + 1];
    r->t[r->n] = taper_sim_time(sim);
    assert_int_equal(taper_sim_state(sim, r->x[r->n], r->v[r->n], NULL), TAPER_OK);
    assert_int_equal(taper_sim_forces(sim, f, NULL), TAPER_OK);
    r->wall[r->n] = f[N_GRANULES];
    r->n++;
    return 0;
}

/* A run with t_end and t_max (0: none), sampled at `times` (n > 0) or
 * every `interval` (n = 0, interval > 0), or not at all. */
static taper_sim *run(const taper_chain *chain, double t_end, double t_max, const double *times,
                      size_t n, double interval, record *r, taper_status expected)
{
    taper_solver_spec *spec = taper_solver_spec_alloc(NULL);
    assert_int_equal(taper_solver_spec_set_rtol(spec, RTOL, NULL), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_t_end(spec, t_end, NULL), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_t_max(spec, t_max, NULL), TAPER_OK);
    if (n) assert_int_equal(taper_solver_spec_set_sample_times(spec, times, n, keep, r, NULL), TAPER_OK);
    else if (interval > 0) assert_int_equal(taper_solver_spec_set_sampler(spec, interval, keep, r, NULL), TAPER_OK);
    taper_sim *sim = taper_sim_alloc(chain, spec, NULL);
    assert_non_null(sim);
    taper_solver_spec_free(spec);
    taper_error err;
    taper_status status = taper_sim_run(sim, &err);
    if (status != expected) print_error("%s\n", err.message);
    assert_int_equal(status, expected);
    return sim;
}

static void grid_times_are_the_interval_sampler(void **state)
{
    (void)state;
    taper_chain *chain = chain_with_wall();
    /* t_end past the end of the wall's first contact (t ~ 40), where the
     * run would go on without it: both runs end at t_end */
    double times[81];
    for (size_t j = 0; j < 81; j++) times[j] = (double)j * 0.75;
    record *a = calloc(1, sizeof *a), *b = calloc(1, sizeof *b);
    taper_sim *grid = run(chain, 60.0, 0.0, NULL, 0, 0.75, a, TAPER_OK);
    taper_sim *given = run(chain, 60.0, 0.0, times, 81, 0.0, b, TAPER_OK);
    assert_int_equal(a->n, 81);
    assert_int_equal(b->n, 81);
    for (size_t j = 0; j < 81; j++) {
        assert_true(a->t[j] == b->t[j]);
        assert_true(a->wall[j] == b->wall[j]);
        for (size_t k = 0; k < N_GRANULES; k++)
            assert_true(a->x[j][k] == b->x[j][k] && a->v[j][k] == b->v[j][k]);
    }
    for (int o = 0; o < TAPER_N_OBSERVABLES; o++) {
        const double *p = taper_sim_observable(grid, (taper_observable)o);
        const double *q = taper_sim_observable(given, (taper_observable)o);
        for (size_t k = 0; k < N_GRANULES; k++) assert_true(p[k] == q[k] || (isnan(p[k]) && isnan(q[k])));
    }
    taper_sim_free(grid);
    taper_sim_free(given);
    free(a);
    free(b);
    taper_chain_free(chain);
}

static void irregular_times_are_the_state_there(void **state)
{
    (void)state;
    taper_chain *chain = chain_with_wall();
    /* irregular, with a first time after 0, and the wall's reflection */
    const double times[] = {0.013, 1.7, 2.0000001, 5.25, 9.9, 14.0, 17.31, 23.5};
    const size_t n = sizeof times / sizeof times[0];
    record *r = calloc(1, sizeof *r), *cut = calloc(1, sizeof *cut);
    taper_sim *sim = run(chain, 25.0, 0.0, times, n, 0.0, r, TAPER_OK);
    assert_int_equal(r->n, n);
    for (size_t j = 0; j < n; j++) assert_true(r->t[j] == times[j]);
    /* each sample is the state of a run that stops there (t_max before
     * the pulse has passed every granule, t_end after): CVODE's
     * interpolant against its own integration to that time */
    for (size_t j = 0; j < n; j++) {
        taper_sim *stop = run(chain, times[j], times[j], NULL, 0, 0.0, NULL,
                              times[j] < 10.0 ? TAPER_ELIMIT : TAPER_OK);
        double x[N_GRANULES], v[N_GRANULES];
        assert_true(taper_sim_time(stop) == times[j]);
        assert_int_equal(taper_sim_state(stop, x, v, NULL), TAPER_OK);
        for (size_t k = 0; k < N_GRANULES; k++) {
            assert_double_abs(r->x[j][k], x[k], 1e-9);
            assert_double_abs(r->v[j][k], v[k], 1e-9);
        }
        taper_sim_free(stop);
    }
    /* sampling leaves the integration's steps as they are */
    taper_sim *plain = run(chain, 25.0, 0.0, NULL, 0, 0.0, NULL, TAPER_OK);
    assert_true(taper_sim_statistic(plain, TAPER_STAT_STEPS) == taper_sim_statistic(sim, TAPER_STAT_STEPS));
    taper_sim_free(plain);
    taper_sim_free(sim);
    /* times after the run's end are not served ... */
    const double late[] = {1.0, 1000.0};
    taper_sim *short_run = run(chain, 0.0, 0.0, late, 2, 0.0, cut, TAPER_OK);
    assert_int_equal(cut->n, 1);
    assert_true(taper_sim_statistic(short_run, TAPER_STAT_T_FINAL) < 1000.0);
    taper_sim_free(short_run);
    /* ... t_end reaches them */
    cut->n = 0;
    taper_sim *long_run = run(chain, 1000.0, 0.0, late, 2, 0.0, cut, TAPER_OK);
    assert_int_equal(cut->n, 2);
    assert_true(cut->t[1] == 1000.0);
    taper_sim_free(long_run);
    free(r);
    free(cut);
    taper_chain_free(chain);
}

static void times_are_checked(void **state)
{
    (void)state;
    taper_solver_spec *spec = taper_solver_spec_alloc(NULL);
    record r;
    taper_error err;
    const double equal[] = {0.0, 1.0, 1.0}, down[] = {2.0, 1.0}, negative[] = {-1.0, 1.0};
    const double inf[] = {0.0, INFINITY}, ok[] = {0.5, 1.5};
    double nan_times[] = {0.0, NAN};
    assert_int_equal(taper_solver_spec_set_sample_times(spec, equal, 3, keep, &r, &err), TAPER_EINVAL);
    assert_taper_error(err, TAPER_EINVAL, "sample_times", "strictly increasing");
    assert_int_equal(taper_solver_spec_set_sample_times(spec, down, 2, keep, &r, &err), TAPER_EINVAL);
    assert_int_equal(taper_solver_spec_set_sample_times(spec, negative, 2, keep, &r, &err), TAPER_EINVAL);
    assert_int_equal(taper_solver_spec_set_sample_times(spec, inf, 2, keep, &r, &err), TAPER_EINVAL);
    assert_int_equal(taper_solver_spec_set_sample_times(spec, nan_times, 2, keep, &r, &err), TAPER_EINVAL);
    assert_int_equal(taper_solver_spec_set_sample_times(spec, ok, 0, keep, &r, &err), TAPER_EINVAL);
    assert_taper_error(err, TAPER_EINVAL, "sample_times", "no times");
    assert_int_equal(taper_solver_spec_set_sample_times(spec, NULL, 2, keep, &r, &err), TAPER_EINVAL);
    /* nothing was set by a refused call */
    size_t n = 99;
    assert_null(taper_solver_spec_sample_times(spec, &n));
    assert_int_equal(n, 0);
    /* the grid and the times replace each other */
    assert_int_equal(taper_solver_spec_set_sampler(spec, 0.5, keep, &r, NULL), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_sample_times(spec, ok, 2, keep, &r, NULL), TAPER_OK);
    assert_true(taper_solver_spec_sample_times(spec, &n) == ok);
    assert_int_equal(n, 2);
    assert_true(taper_solver_spec_sample_interval(spec) == 0.0);
    assert_int_equal(taper_solver_spec_set_sampler(spec, 0.5, keep, &r, NULL), TAPER_OK);
    assert_null(taper_solver_spec_sample_times(spec, &n));
    assert_true(taper_solver_spec_sample_interval(spec) == 0.5);
    /* fn NULL removes it */
    assert_int_equal(taper_solver_spec_set_sample_times(spec, ok, 2, keep, &r, NULL), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_sample_times(spec, NULL, 0, NULL, NULL, NULL), TAPER_OK);
    assert_null(taper_solver_spec_sample_times(spec, NULL));
    assert_int_equal(taper_solver_spec_set_sample_times(NULL, ok, 2, keep, &r, &err), TAPER_EINVAL);
    taper_solver_spec_free(spec);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(grid_times_are_the_interval_sampler),
        cmocka_unit_test(irregular_times_are_the_state_there),
        cmocka_unit_test(times_are_checked),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
