/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_rk8.c -- method 'rk8' (src/sim/rk8.c) integrates what CVODE does,
 * on every kind of chain the run supports, and is refused what it has not.
 *
 * rk8 at rtol 1e-12 against CVODE Adams at 1e-14, whose error is ~100
 * times smaller than rk8's (Adams at 1e-12 errs by ~1e-11 in t_pass and
 * ~1e-10 in v_peak on chains of 100, docs/benchmarks.md; its left wall's
 * peak force by 1.1e-9, rk8's by 2e-12).  The bound, 1e-9 for every
 * observable, is rk8's error with room: a missed or doubled event, a wrong
 * window move or a lost quadrature is off by far more.  Accuracy against
 * converged references is test `accuracy`.
 */
#include "test_chains.h"
#include "test_util.h"
#include "taper.h"

#include <stdlib.h>

#define RTOL 1e-12
#define AGREE 1e-9
/* Sampled positions, relative to the largest: the granules a wall throws
 * back fly apart at velocities that differ by ~1e-10 between runs, and
 * their positions drift apart with time (Adams at rtol 1e-12 and at 1e-15:
 * 2.0e-8 apart by t = 150, where the largest displacement is 54: 4e-10 of
 * it; rk8 at 1e-12 against Adams at 1e-14: 1.6e-12 of it). */
#define SAMPLES_AGREE 1e-10

typedef struct options {
    double striker_radius, load, damping, drag, piston;
    int wall_left, wall_right;
    int window;      /* 0: the whole chain                                 */
    double t_end;    /* follow the pulse on (a reflection); 0: no          */
    double sample;   /* sampler interval; 0: none                          */
} options;

typedef struct samples {
    size_t n, granules;
    double x[64][8]; /* x of granules 1..8 at each sample, up to 64 samples */
} samples;

static int record(const taper_sim *sim, void *user)
{
    samples *s = user;
    if (s->n < 64) {
        double x[400];
        assert_true(s->granules <= 400);
        assert_int_equal(taper_sim_state(sim, x, NULL, NULL), TAPER_OK);
        for (size_t k = 0; k < 8; k++) s->x[s->n][k] = x[k];
    }
    s->n++;
    return 0;
}

static taper_chain *chain_with(taper_profile profile, size_t n, double param, const options *o)
{
    taper_error err;
    taper_chain_spec *spec = taper_chain_spec_alloc(&err);
    assert_non_null(spec);
    test_chain_ok(taper_chain_spec_set_profile(spec, profile, &err), &err);
    test_chain_ok(taper_chain_spec_set_n_granules(spec, n, &err), &err);
    if (profile == TAPER_BACKWARD_LINEAR || profile == TAPER_FORWARD_LINEAR)
        test_chain_ok(taper_chain_spec_set_s(spec, param, &err), &err);
    if (profile == TAPER_BACKWARD_EXPONENTIAL || profile == TAPER_FORWARD_EXPONENTIAL)
        test_chain_ok(taper_chain_spec_set_q(spec, param, &err), &err);
    if (o->striker_radius > 0.0)
        test_chain_ok(taper_chain_spec_set_striker(spec, o->striker_radius, 1.0, 1.0, &err), &err);
    if (o->wall_left) test_chain_ok(taper_chain_spec_set_end(spec, TAPER_LEFT, TAPER_END_WALL, 0.0, &err), &err);
    if (o->wall_right) test_chain_ok(taper_chain_spec_set_end(spec, TAPER_RIGHT, TAPER_END_WALL, 0.0, &err), &err);
    if (o->piston > 0.0) test_chain_ok(taper_chain_spec_set_piston(spec, o->piston, 0.0, &err), &err);
    test_chain_ok(taper_chain_spec_set_load(spec, o->load, &err), &err);
    test_chain_ok(taper_chain_spec_set_damping(spec, o->damping, &err), &err);
    test_chain_ok(taper_chain_spec_set_drag(spec, o->drag, &err), &err);
    taper_chain *c = taper_chain_alloc(spec, &err);
    test_chain_ok(c ? TAPER_OK : err.status, &err);
    taper_chain_spec_free(spec);
    return c;
}

static taper_sim *run(const taper_chain *c, taper_method method, double rtol, const options *o,
                      samples *s)
{
    taper_error err;
    taper_solver_spec *ss = taper_solver_spec_alloc(&err);
    assert_non_null(ss);
    assert_int_equal(taper_solver_spec_set_method(ss, method, &err), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_rtol(ss, rtol, &err), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_atol(ss, rtol * 1e-3, &err), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_window(ss, o->window, &err), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_t_end(ss, o->t_end, &err), TAPER_OK);
    if (o->sample > 0.0) {
        s->granules = taper_chain_size(c);
        assert_int_equal(taper_solver_spec_set_sampler(ss, o->sample, record, s, &err), TAPER_OK);
    }
    taper_sim *sim = taper_sim_alloc(c, ss, &err);
    taper_solver_spec_free(ss);
    assert_non_null(sim);
    taper_status st = taper_sim_run(sim, &err);
    if (st != TAPER_OK) print_error("%s: %s\n", taper_method_name(method), err.message);
    assert_int_equal(st, TAPER_OK);
    return sim;
}

/* Largest relative difference of an observable over granules 1..n, both
 * NaN counting as agreement (an event neither run saw), one NaN as
 * infinitely apart. */
static double apart(const taper_sim *a, const taper_sim *b, taper_observable which, size_t n, size_t *at)
{
    const double *x = taper_sim_observable(a, which), *y = taper_sim_observable(b, which);
    double worst = 0.0;
    for (size_t k = 1; k <= n; k++) {
        if (isnan(x[k - 1]) && isnan(y[k - 1])) continue;
        double d = fabs(x[k - 1] - y[k - 1]) / fmax(fabs(y[k - 1]), 1e-300);
        if (!(d <= worst)) worst = isnan(d) ? INFINITY : d, *at = k;
    }
    return worst;
}

static double stat(const taper_sim *sim, taper_statistic which) { return taper_sim_statistic(sim, which); }

static void agrees_with_adams(const char *what, taper_profile profile, size_t n, double param,
                              const options *o)
{
    taper_chain *c = chain_with(profile, n, param, o);
    samples sa = {0}, sr = {0};
    taper_sim *adams = run(c, TAPER_ADAMS, 1e-2 * RTOL, o, &sa), *rk8 = run(c, TAPER_RK8, RTOL, o, &sr);
    size_t at_t = 0, at_v = 0;
    const double dt = apart(rk8, adams, TAPER_T_PASS, n - 1, &at_t);
    const double dv = apart(rk8, adams, TAPER_V_PEAK, n, &at_v);
    const double e = stat(rk8, TAPER_STAT_ENERGY_ERROR);
    print_message("%-28s t_pass %.1e (granule %zu), v_peak %.1e (granule %zu) apart; rk8 energy error "
                  "%.1e, %g steps (adams at 1e-14: %g)\n",
                  what, dt, at_t, dv, at_v, e, stat(rk8, TAPER_STAT_STEPS), stat(adams, TAPER_STAT_STEPS));
    assert_true(dt <= AGREE);
    assert_true(dv <= AGREE);
    assert_true(e <= 1e-9); /* the budget balances, quadratures included */
    assert_true(stat(rk8, TAPER_STAT_COMPLETE) == 1.0);
    /* the walls' peaks (events: their impulses, integrals over a long run,
     * are not compared: behind a left wall granules rattle between the wall
     * and the chain, and two Adams runs at 1e-12 and 1e-15 end with
     * impulses 174.5 and 176.7) */
    static const taper_statistic peaks[] = {TAPER_STAT_WALL_PEAK_FORCE_LEFT, TAPER_STAT_WALL_PEAK_TIME_LEFT,
                                            TAPER_STAT_WALL_PEAK_FORCE_RIGHT, TAPER_STAT_WALL_PEAK_TIME_RIGHT};
    for (size_t i = 0; i < sizeof peaks / sizeof *peaks; i++) {
        const taper_statistic w = peaks[i];
        double a = stat(adams, w), r = stat(rk8, w);
        if (isnan(a)) {
            assert_true(isnan(r));
            continue;
        }
        print_message("  %-22s adams %.15g rk8 %.15g\n", taper_statistic_name(w), a, r);
        assert_true(fabs(a - r) <= AGREE * fmax(fabs(a), 1e-3));
    }
    if (o->piston > 0.0) assert_true(fabs(taper_sim_piston_work(rk8) - taper_sim_piston_work(adams)) <= AGREE);
    if (o->t_end > 0.0) assert_true(stat(rk8, TAPER_STAT_T_FINAL) == stat(adams, TAPER_STAT_T_FINAL));
    if (o->sample > 0.0) { /* the sampler sees the same states at the same times */
        assert_int_equal(sr.n, sa.n);
        double worst = 0.0, largest = 0.0;
        for (size_t j = 0; j < sr.n && j < 64; j++)
            for (size_t k = 0; k < 8; k++) {
                worst = fmax(worst, fabs(sr.x[j][k] - sa.x[j][k]));
                largest = fmax(largest, fabs(sa.x[j][k]));
            }
        print_message("  %zu samples, positions %.1e apart (%.1e of the largest)\n", sr.n, worst,
                      worst / largest);
        assert_true(worst <= SAMPLES_AGREE * largest);
        /* and the samples do not disturb the run: its steps and its pass
         * times are those of the same run without them, to the bit (a
         * sample inside a step is a fresh step from its start, the step
         * itself kept) */
        options quiet = *o;
        quiet.sample = 0.0;
        taper_sim *plain = run(c, TAPER_RK8, RTOL, &quiet, NULL);
        assert_true(stat(plain, TAPER_STAT_STEPS) == stat(rk8, TAPER_STAT_STEPS));
        const double *a = taper_sim_observable(plain, TAPER_T_PASS), *b = taper_sim_observable(rk8, TAPER_T_PASS);
        for (size_t k = 0; k + 1 < n; k++) assert_true(a[k] == b[k] || (isnan(a[k]) && isnan(b[k])));
        taper_sim_free(plain);
    }
    taper_sim_free(adams);
    taper_sim_free(rk8);
    taper_chain_free(c);
}

static void paper_chains(void **state)
{
    (void)state;
    const options none = {.window = 1}, whole = {.window = 0};
    agrees_with_adams("monodisperse", TAPER_MONODISPERSE, 100, 0.0, &none);
    agrees_with_adams("backward linear", TAPER_BACKWARD_LINEAR, 100, 0.5, &none);
    agrees_with_adams("forward exponential", TAPER_FORWARD_EXPONENTIAL, 60, 0.05, &none);
    agrees_with_adams("backward exponential, whole", TAPER_BACKWARD_EXPONENTIAL, 100, 0.05, &whole);
}

static void ends(void **state)
{
    (void)state;
    const options striker = {.window = 1, .striker_radius = 1.5};
    agrees_with_adams("striker", TAPER_MONODISPERSE, 60, 0.0, &striker);
    /* reflected from a rigid wall and followed back: granules taken back */
    const options right = {.window = 1, .wall_right = 1, .t_end = 150.0, .sample = 10.0};
    agrees_with_adams("right wall, followed back", TAPER_MONODISPERSE, 40, 0.0, &right);
    const options left = {.window = 1, .wall_left = 1};
    agrees_with_adams("left wall", TAPER_BACKWARD_LINEAR, 60, 0.5, &left);
    /* the piston's stop: a jump of the velocity, a restart */
    const options piston = {.window = 1, .piston = 2.0};
    agrees_with_adams("piston", TAPER_MONODISPERSE, 40, 0.0, &piston);
}

static void losses_and_load(void **state)
{
    (void)state;
    const options damped = {.window = 1, .damping = 0.05};
    agrees_with_adams("damping", TAPER_MONODISPERSE, 80, 0.0, &damped);
    const options drag = {.window = 1, .drag = 0.001, .sample = 5.0};
    agrees_with_adams("drag", TAPER_BACKWARD_LINEAR, 80, 0.5, &drag);
    const options load = {.window = 1, .load = 1.0};
    agrees_with_adams("load", TAPER_MONODISPERSE, 40, 0.0, &load);
}

/* rk8's order is fixed: max_order is refused, naming the field; the
 * method has its name. */
static void max_order_refused(void **state)
{
    (void)state;
    taper_error err;
    taper_method m;
    assert_int_equal(taper_method_from_name("RK8", &m, &err), TAPER_OK);
    assert_int_equal(m, TAPER_RK8);
    assert_string_equal(taper_method_name(TAPER_RK8), "rk8");
    const options none = {.window = 1};
    taper_chain *c = chain_with(TAPER_MONODISPERSE, 10, 0.0, &none);
    taper_solver_spec *ss = taper_solver_spec_alloc(&err);
    assert_int_equal(taper_solver_spec_set_method(ss, TAPER_RK8, &err), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_max_order(ss, 5, &err), TAPER_OK); /* Adams' range */
    assert_null(taper_sim_alloc(c, ss, &err));
    assert_int_equal(err.status, TAPER_EINVAL);
    assert_string_equal(err.field, "max_order");
    print_message("%s\n", err.message);
    taper_solver_spec_free(ss);
    taper_chain_free(c);
}

/* A run stopped by max_steps keeps what it found, as CVODE's does. */
static void stopped_run_keeps_its_passes(void **state)
{
    (void)state;
    const options none = {.window = 1};
    taper_chain *c = chain_with(TAPER_MONODISPERSE, 200, 0.0, &none);
    taper_error err;
    taper_solver_spec *ss = taper_solver_spec_alloc(&err);
    assert_int_equal(taper_solver_spec_set_method(ss, TAPER_RK8, &err), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_max_steps(ss, 300, &err), TAPER_OK);
    taper_sim *sim = taper_sim_alloc(c, ss, &err);
    assert_non_null(sim);
    assert_int_equal(taper_sim_run(sim, &err), TAPER_ELIMIT);
    print_message("%s\n", err.message);
    const size_t reached = (size_t)stat(sim, TAPER_STAT_GRANULE_REACHED);
    assert_true(reached > 1 && reached < 199);
    const double *t = taper_sim_observable(sim, TAPER_T_PASS);
    for (size_t k = 1; k <= reached; k++) assert_true(isfinite(t[k - 1]));
    assert_true(isnan(t[reached]));
    assert_true(stat(sim, TAPER_STAT_COMPLETE) == 0.0);
    taper_sim_free(sim);
    taper_solver_spec_free(ss);
    taper_chain_free(c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(paper_chains),
        cmocka_unit_test(ends),
        cmocka_unit_test(losses_and_load),
        cmocka_unit_test(max_order_refused),
        cmocka_unit_test(stopped_run_keeps_its_passes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
