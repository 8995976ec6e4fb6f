/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_losses.c -- dissipation (taper.h, taper_chain_spec_set_damping and
 * _set_drag; docs/physics.md, "Losses"), checked as physics through the
 * public header (suite 'physics'):
 *
 *  - energy balance E(t) + D(t) = E(0) to 1e-8 at rtol 1e-12, E computed
 *    here from the sampled state and the chain's own contact factors
 *    (kinetic plus r z^n / n: the elastic energy; the damping force does
 *    no conservative work) and D the energy the sim reports dissipated,
 *    with Kuwabara-Kono damping and with drag, each dissipating a real
 *    share of E(0);
 *  - with drag, the momentum balance P(t) - P(0) = -drag sum_k x_k(t)
 *    (the drag's impulse, -drag int v_k dt, integrated exactly);
 *  - the velocity peaks stay exact maxima (the peak root function of a
 *    dissipative chain is the force balance, events.c): a fine sampling of
 *    v_k never exceeds v_peak(k) and reaches it within its curvature;
 *  - the pulse is attenuated: v_peak decreases along the chain, where the
 *    elastic chain keeps its solitary wave.
 */
#include "test_util.h"

#include "taper.h"

#include <stdlib.h>
#include <string.h>

#define RTOL 1e-12
#define N_GRANULES 30
#define DT 0.002
#define PROBE 15 /* the granule whose velocity is sampled finely */

typedef struct balance {
    const taper_chain *chain;
    double *x, *v;
    double max_balance_error, max_momentum_error;
    double v_probe_max, t_probe_max;
    const taper_sim *sim;
} balance;

static double elastic_energy(const balance *b)
{
    const double *m = taper_chain_mass(b->chain), *r = taper_chain_contact(b->chain);
    const double n = taper_chain_exponent(b->chain);
    double e = 0.0;
    for (size_t k = 0; k < N_GRANULES; k++) {
        e += 0.5 * m[k] * b->v[k] * b->v[k];
        double z = k + 1 < N_GRANULES ? b->x[k] - b->x[k + 1] : 0.0;
        if (z > 0.0) e += r[k] / n * pow(z, n);
    }
    return e;
}

static int sample(const taper_sim *sim, void *user)
{
    balance *b = user;
    assert_int_equal(taper_sim_state(sim, b->x, b->v, NULL), TAPER_OK);
    if (b->v[PROBE - 1] > b->v_probe_max) {
        b->v_probe_max = b->v[PROBE - 1];
        b->t_probe_max = taper_sim_time(sim);
    }
    /* The dissipated energy is only published at the end; the balance is
     * checked there (final_balance), the momentum at every sample. */
    const double *m = taper_chain_mass(b->chain), drag = taper_chain_drag(b->chain);
    double p = 0.0, drag_impulse = 0.0;
    for (size_t k = 0; k < N_GRANULES; k++) {
        p += m[k] * b->v[k];
        drag_impulse -= drag * b->x[k];
    }
    b->max_momentum_error = fmax(b->max_momentum_error, fabs(p - 1.0 - drag_impulse));
    return 0;
}

static taper_chain *lossy_chain(double damping, double drag)
{
    taper_chain_spec *spec = taper_chain_spec_alloc(NULL);
    assert_int_equal(taper_chain_spec_set_n_granules(spec, N_GRANULES, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_damping(spec, damping, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_drag(spec, drag, NULL), TAPER_OK);
    taper_chain *chain = taper_chain_alloc(spec, NULL);
    assert_non_null(chain);
    taper_chain_spec_free(spec);
    return chain;
}

/* A sim of chain with spec, run: it must complete. */
static taper_sim *run_to_completion(const taper_chain *chain, const taper_solver_spec *spec)
{
    taper_sim *sim = taper_sim_alloc(chain, spec, NULL);
    assert_non_null(sim);
    taper_error err;
    taper_status status = taper_sim_run(sim, &err);
    if (status != TAPER_OK) print_error("%s\n", err.message);
    assert_int_equal(status, TAPER_OK);
    return sim;
}

/* Runs to t_end = 40 sampling every DT; returns E(t_end) + D - E(0)
 * relative to E(0), and D / E(0) in *share. */
static double run_balance(double damping, double drag, balance *b, double *share)
{
    taper_chain *chain = lossy_chain(damping, drag);
    b->chain = chain;
    b->x = malloc(N_GRANULES * sizeof(double));
    b->v = malloc(N_GRANULES * sizeof(double));
    taper_solver_spec *spec = taper_solver_spec_alloc(NULL);
    assert_int_equal(taper_solver_spec_set_rtol(spec, RTOL, NULL), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_t_end(spec, 40.0, NULL), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_sampler(spec, DT, sample, b, NULL), TAPER_OK);
    taper_sim *sim = run_to_completion(chain, spec);
    /* the final state (t_end = 40 is not a multiple of DT in binary: read it
     * after the run) */
    assert_int_equal(taper_sim_state(sim, b->x, b->v, NULL), TAPER_OK);
    const double e0 = taper_sim_statistic(sim, TAPER_STAT_ENERGY_INITIAL);
    const double d = taper_sim_statistic(sim, TAPER_STAT_ENERGY_DISSIPATED);
    const double balance_error = (elastic_energy(b) + d - e0) / e0;
    *share = d / e0;
    /* the budget adds up too */
    double sum = d + taper_sim_statistic(sim, TAPER_STAT_ENERGY_TRANSMITTED) +
                 taper_sim_statistic(sim, TAPER_STAT_ENERGY_REFLECTED) +
                 taper_sim_statistic(sim, TAPER_STAT_ENERGY_IN_CHAIN);
    assert_double_rel(sum, e0, 1e-8);
    assert_true(taper_sim_statistic(sim, TAPER_STAT_ENERGY_ERROR) <= 1e-8);
    /* the probe's peak: an exact maximum */
    const double vp = taper_sim_observable(sim, TAPER_V_PEAK)[PROBE - 1];
    const double tp = taper_sim_observable(sim, TAPER_T_PEAK)[PROBE - 1];
    printf("damping %g drag %g: D = %.4f E(0), balance %.2g, momentum %.2g; v_peak(%d) %.12g at "
           "%.10g, sampled %.12g at %.10g\n",
           damping, drag, *share, balance_error, b->max_momentum_error, PROBE, vp, tp,
           b->v_probe_max, b->t_probe_max);
    assert_true(b->v_probe_max <= vp * (1.0 + 1e-12));
    assert_true(b->v_probe_max >= vp * (1.0 - 1e-5));
    assert_true(fabs(b->t_probe_max - tp) <= DT);
    /* attenuation: v_peak decreases along the chain */
    const double *v_peak = taper_sim_observable(sim, TAPER_V_PEAK);
    for (size_t k = 3; k + 1 < N_GRANULES; k++) assert_true(v_peak[k] < v_peak[k - 1]);
    b->sim = NULL;
    taper_sim_free(sim);
    taper_solver_spec_free(spec);
    free(b->x), free(b->v);
    taper_chain_free(chain);
    return balance_error;
}

static void damping_balance(void **state)
{
    (void)state;
    balance b = {0};
    double share;
    double error = run_balance(0.05, 0.0, &b, &share);
    assert_true(share > 0.3); /* a real loss (measured 0.70 of E(0) by t = 40) */
    assert_true(fabs(error) <= 1e-8);
    assert_true(b.max_momentum_error <= 1e-10); /* damping is internal */
}

static void drag_balance(void **state)
{
    (void)state;
    balance b = {0};
    double share;
    double error = run_balance(0.0, 0.01, &b, &share);
    assert_true(share > 0.2);
    assert_true(fabs(error) <= 1e-8);
    assert_true(b.max_momentum_error <= 1e-10); /* P - P(0) = -drag sum x */
}

static void both_losses(void **state)
{
    (void)state;
    balance b = {0};
    double share;
    double error = run_balance(0.05, 0.01, &b, &share);
    assert_true(share > 0.4);
    assert_true(fabs(error) <= 1e-8);
    assert_true(b.max_momentum_error <= 1e-10);
}

/* Strong drag absorbs the pulse: momentum leaves the chain and the
 * granules creep on ever slower (an overdamped front).  The run ends by
 * itself once every granule moves slower than rtol of the impulse's
 * velocity (motion below the precision asked for), complete, the passes it
 * never reached NaN, with E + D = E(0) and nearly all of E(0) dissipated:
 * at t = 1.85e6, 28 granules passed.  Without that end the front crept on
 * through all 100 granules by t = 4.1e7 at velocities below the tolerance
 * (BDF; Adams, stepping at the drag's relaxation time m / drag = 0.01,
 * would need some 4e9 steps), passes of motion the run does not resolve.
 * BDF: the relaxation makes the equations stiff, and the sim says so to an
 * Adams run. */
static void log_stiff(int level, const char *message, void *user)
{
    if (level >= 1 && strstr(message, "stiff")) ++*(int *)user;
}

static void drag_absorbs_the_pulse(void **state)
{
    (void)state;
    taper_chain_spec *cs = taper_chain_spec_alloc(NULL);
    assert_int_equal(taper_chain_spec_set_n_granules(cs, 100, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_drag(cs, 100.0, NULL), TAPER_OK);
    taper_chain *chain = taper_chain_alloc(cs, NULL);
    assert_non_null(chain);
    taper_solver_spec *spec = taper_solver_spec_alloc(NULL);
    int stiff = 0;
    taper_solver_spec_set_log(spec, log_stiff, &stiff);
    taper_sim *adams = taper_sim_alloc(chain, spec, NULL); /* not run: the note only */
    assert_non_null(adams);
    assert_int_equal(stiff, 1);
    taper_sim_free(adams);
    assert_int_equal(taper_solver_spec_set_method(spec, TAPER_BDF, NULL), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_t_max(spec, 1e8, NULL), TAPER_OK);
    taper_sim *sim = run_to_completion(chain, spec);
    assert_true(taper_sim_statistic(sim, TAPER_STAT_COMPLETE) == 1.0);
    const size_t reached = (size_t)taper_sim_statistic(sim, TAPER_STAT_GRANULE_REACHED);
    const double *t_pass = taper_sim_observable(sim, TAPER_T_PASS);
    printf("drag 100: absorbed at t = %.6g, passes to granule %zu\n",
           taper_sim_statistic(sim, TAPER_STAT_T_FINAL), reached);
    assert_true(reached >= 5 && reached < 90); /* measured: 28 */
    for (size_t k = 0; k < reached; k++) assert_true(isfinite(t_pass[k]));
    for (size_t k = reached; k + 1 < 100; k++) assert_true(isnan(t_pass[k]));
    /* at rest within the tolerance, and the energy is gone into drag */
    double x[100], v[100];
    assert_int_equal(taper_sim_state(sim, x, v, NULL), TAPER_OK);
    const double rtol = taper_solver_spec_rtol(spec), atol = taper_solver_spec_atol(spec);
    for (size_t k = 0; k < 100; k++) assert_true(fabs(v[k]) <= rtol + 10.0 * atol);
    const double e0 = taper_sim_statistic(sim, TAPER_STAT_ENERGY_INITIAL);
    const double d = taper_sim_statistic(sim, TAPER_STAT_ENERGY_DISSIPATED);
    const double left = taper_sim_statistic(sim, TAPER_STAT_ENERGY_IN_CHAIN);
    assert_true(fabs(left + d - e0) <= 1e-7 * e0); /* BDF: 1.6e-8 measured */
    assert_true(left <= 1e-9 * e0);
    taper_sim_free(sim);
    taper_solver_spec_free(spec);
    taper_chain_spec_free(cs);
    taper_chain_free(chain);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(damping_balance),
        cmocka_unit_test(drag_balance),
        cmocka_unit_test(both_losses),
        cmocka_unit_test(drag_absorbs_the_pulse),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
