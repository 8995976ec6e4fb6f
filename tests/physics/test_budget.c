/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_budget.c -- the energy budget's words mean what they say
 * (docs/physics.md, "Energy budget"): energy is reflected or transmitted
 * once the clusters carrying it can never meet the rest of the chain again,
 * and in the chain otherwise.  Checked against exact limits:
 *
 *  - two spheres (a chain of two granules) that separate: the elastic
 *    collision of masses m1, m2 gives v1' = (m1 - m2)/(m1 + m2) and
 *    v2' = 2 m1/(m1 + m2); a lighter second sphere leaves both moving
 *    forward, the second faster: all transmitted; a heavier one sends the
 *    first back: reflected ((m1 - m2)/(m1 + m2))^2 of E(0), transmitted
 *    4 m1 m2 / (m1 + m2)^2, nothing in the chain;
 *  - a pulse reflected from a rigid wall: nothing transmitted through the
 *    wall, and once the granules have all separated moving back, none
 *    faster than the one before, nothing left in the chain;
 *  - under a static load the ends are pushed back: all in the chain;
 *  - a pulse that leaves the chain early ends the run (the stop rule of
 *    solve.c that reads this budget).
 */
#include "test_util.h"

#include "taper.h"

#include <stdlib.h>
#include <string.h>

#define RTOL 1e-12

static const taper_sim *run(const taper_chain **chain, taper_chain_spec *cs, double t_end)
{
    taper_error err;
    taper_chain *c = taper_chain_alloc(cs, &err);
    if (!c) fail_msg("chain: %s", err.message);
    taper_solver_spec *ss = taper_solver_spec_alloc(NULL);
    assert_int_equal(taper_solver_spec_set_rtol(ss, RTOL, NULL), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_atol(ss, 1e-15, NULL), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_t_end(ss, t_end, NULL), TAPER_OK);
    taper_sim *sim = taper_sim_alloc(c, ss, &err);
    taper_solver_spec_free(ss);
    if (!sim) fail_msg("sim: %s", err.message);
    if (taper_sim_run(sim, &err) != TAPER_OK) fail_msg("run: %s", err.message);
    *chain = c;
    return sim;
}

static double stat(const taper_sim *sim, taper_statistic which)
{
    return taper_sim_statistic(sim, which);
}

static void two_spheres(double r2)
{
    taper_chain_spec *cs = taper_chain_spec_alloc(NULL);
    const double radii[2] = {1.0, r2};
    assert_int_equal(taper_chain_spec_set_profile(cs, TAPER_CUSTOM, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_n_granules(cs, 2, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_radii(cs, radii, 2, NULL), TAPER_OK);
    const taper_chain *chain;
    /* the collision lasts about 3 units: at t = 40 they have long separated */
    const taper_sim *sim = run(&chain, cs, 40.0);
    const double m1 = 1.0, m2 = r2 * r2 * r2, e0 = stat(sim, TAPER_STAT_ENERGY_INITIAL);
    const double back = (m1 - m2) / (m1 + m2);
    const double want_reflected = m2 > m1 ? back * back * e0 : 0.0;
    assert_double_abs(stat(sim, TAPER_STAT_ENERGY_REFLECTED), want_reflected, 1e-9 * e0);
    assert_double_abs(stat(sim, TAPER_STAT_ENERGY_TRANSMITTED), e0 - want_reflected, 1e-9 * e0);
    assert_double_abs(stat(sim, TAPER_STAT_ENERGY_IN_CHAIN), 0.0, 1e-9 * e0);
    taper_sim_free((taper_sim *)sim);
    taper_chain_free((taper_chain *)chain);
    taper_chain_spec_free(cs);
}

static void two_spheres_lighter(void **state)
{
    (void)state;
    two_spheres(0.8); /* both forward, the second faster: all transmitted */
}

static void two_spheres_heavier(void **state)
{
    (void)state;
    two_spheres(1.3); /* the first sent back */
}

static void wall_reflection(void **state)
{
    (void)state;
    taper_chain_spec *cs = taper_chain_spec_alloc(NULL);
    assert_int_equal(taper_chain_spec_set_n_granules(cs, 12, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_end(cs, TAPER_RIGHT, TAPER_END_WALL, 0.0, NULL),
                     TAPER_OK);
    const taper_chain *chain;
    const taper_sim *sim = run(&chain, cs, 400.0);
    const double e0 = stat(sim, TAPER_STAT_ENERGY_INITIAL);
    double *x = malloc(12 * sizeof *x), *v = malloc(12 * sizeof *v);
    assert_int_equal(taper_sim_state(sim, x, v, NULL), TAPER_OK);
    /* every granule separated, moving back, none faster than the one before */
    int settled = 1;
    for (int k = 0; k < 11; k++)
        if (!(x[k] < x[k + 1] && v[k] <= v[k + 1] && v[k + 1] < 0)) settled = 0;
    assert_true(stat(sim, TAPER_STAT_ENERGY_TRANSMITTED) == 0.0);
    assert_true(settled); /* monodisperse, 12 granules: by t = 400 */
    assert_double_rel(stat(sim, TAPER_STAT_ENERGY_REFLECTED), e0, 1e-9);
    free(x);
    free(v);
    taper_sim_free((taper_sim *)sim);
    taper_chain_free((taper_chain *)chain);
    taper_chain_spec_free(cs);
}

static void under_load(void **state)
{
    (void)state;
    taper_chain_spec *cs = taper_chain_spec_alloc(NULL);
    assert_int_equal(taper_chain_spec_set_n_granules(cs, 20, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_load(cs, 0.01, NULL), TAPER_OK);
    const taper_chain *chain;
    const taper_sim *sim = run(&chain, cs, 0.0);
    assert_true(stat(sim, TAPER_STAT_ENERGY_REFLECTED) == 0.0);
    assert_true(stat(sim, TAPER_STAT_ENERGY_TRANSMITTED) == 0.0);
    assert_double_rel(stat(sim, TAPER_STAT_ENERGY_IN_CHAIN), stat(sim, TAPER_STAT_ENERGY_INITIAL),
                      1e-6);
    taper_sim_free((taper_sim *)sim);
    taper_chain_free((taper_chain *)chain);
    taper_chain_spec_free(cs);
}

/* A pulse that leaves the chain before it has passed every granule: the
 * heavy granule 3 sends it back and the light granule 4 rattles between
 * heavy ones for ever.  The run ends by itself, complete, once the energy
 * that can still be exchanged is below rtol E(0), the passes it never saw
 * nan, and says so. */
static void log_message(int level, const char *message, void *user)
{
    if (level >= 1 && strstr(message, "the pulse has left the chain")) *(int *)user = 1;
}

static void pulse_leaves(void **state)
{
    (void)state;
    taper_chain_spec *cs = taper_chain_spec_alloc(NULL);
    const double radii[6] = {1.0, 1e-3, 1e3, 1e-3, 1e3, 1.0};
    assert_int_equal(taper_chain_spec_set_profile(cs, TAPER_CUSTOM, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_n_granules(cs, 6, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_radii(cs, radii, 6, NULL), TAPER_OK);
    taper_chain *chain = taper_chain_alloc(cs, NULL);
    taper_solver_spec *ss = taper_solver_spec_alloc(NULL);
    int said = 0;
    taper_solver_spec_set_log(ss, log_message, &said);
    /* a bound the run must not need (it stopped by itself at t = 72) */
    assert_int_equal(taper_solver_spec_set_t_max(ss, 1e5, NULL), TAPER_OK);
    taper_sim *sim = taper_sim_alloc(chain, ss, NULL);
    taper_error err;
    assert_int_equal(taper_sim_run(sim, &err), TAPER_OK);
    assert_true(stat(sim, TAPER_STAT_COMPLETE) == 1.0);
    assert_true(said);
    const double e0 = stat(sim, TAPER_STAT_ENERGY_INITIAL);
    assert_true(stat(sim, TAPER_STAT_ENERGY_IN_CHAIN) <= 1e-10 * e0);
    assert_double_rel(stat(sim, TAPER_STAT_ENERGY_REFLECTED), e0, 1e-6);
    assert_true(isnan(taper_sim_observable(sim, TAPER_T_PASS)[2]));
    taper_sim_free(sim);
    taper_solver_spec_free(ss);
    taper_chain_free(chain);
    taper_chain_spec_free(cs);
}

/* `test_budget` runs the quick cases, `test_budget --long` the pulse that
 * leaves a chain of radii 1e-3 to 1e3 (its mass ratios of 1e18 make the
 * stiffest run here; test budget_long, in the suite 'slow' too:
 * tests/physics/meson.build). */
int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(two_spheres_lighter),
        cmocka_unit_test(two_spheres_heavier),
        cmocka_unit_test(wall_reflection),
        cmocka_unit_test(under_load),
    };
    const struct CMUnitTest long_tests[] = {
        cmocka_unit_test(pulse_leaves),
    };
    if (argc == 2 && strcmp(argv[1], "--long") == 0)
        return cmocka_run_group_tests_name("budget_long", long_tests, NULL, NULL);
    if (argc != 1) {
        print_error("usage: test_budget [--long]\n");
        return 2;
    }
    return cmocka_run_group_tests_name("budget", tests, NULL, NULL);
}
