/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_rk8.c -- method 'rk8' (src/sim/stepper_rk8.c) integrates what CVODE does,
 * on every kind of chain the run supports, and is refused what it has not.
 *
 * rk8 at rtol 1e-12 against CVODE Adams at 1e-14, whose error is ~100
 * times smaller than rk8's (Adams at 1e-12 errs by ~1e-11 in t_pass and
 * ~1e-10 in v_peak on chains of 100, docs/benchmarks.md; its left wall's
 * peak force by 1.1e-9, rk8's by 2e-12).  The bound, 1e-9 for every
 * observable, is rk8's error with room: a missed or doubled event, a wrong
 * window move or a lost quadrature is off by far more.  Accuracy against
 * converged references is test `accuracy`.
 *
 * The method's coefficients (src/sim/stepper_rk8_tableau.h) against the
 * order conditions of Butcher's rooted trees (Hairer, Norsett and Wanner,
 * "Solving Ordinary Differential Equations I", II.2): rk8pd's weights of
 * order 8 and 7, and its dense output of order 7 at every point of the
 * step, with the stage orders its extra stages are built for.
 */
#include "test_chains.h"
#include "test_util.h"
#include "taper.h"
#include "sim/stepper_rk8_tableau.h"

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

/* ---- the coefficients against the order conditions -------------------------- */
/* Rooted trees up to order 8, each the root with its children; a tree is
 * enumerated as its child of largest index plus the tree of the root with
 * the others (`rest`, whose children have no larger index), so that each
 * multiset of children comes once: 1, 1, 2, 4, 9, 20, 48, 115 of orders 1
 * to 8.  Phi(tree)_i = prod over children c of (A Phi(c))_i, the stage
 * weights; the condition of a tree on weights b is sum_i b_i Phi_i =
 * 1 / gamma(tree). */
#define MAX_ORDER 8
#define MAX_TREES 200
#define STAGES RK8_DENSE_STAGES

typedef struct trees {
    size_t n;
    int order[MAX_TREES], max_child[MAX_TREES];
    long double gamma[MAX_TREES];
    long double phi[MAX_TREES][STAGES];
} trees;

static void tableau(long double a[STAGES][STAGES], long double c[STAGES])
{
    static const double rows[13][12] = {
        {0},
        {RK8_A21},
        {RK8_A31, RK8_A32},
        {RK8_A41, 0, RK8_A43},
        {RK8_A51, 0, RK8_A53, RK8_A54},
        {RK8_A61, 0, 0, RK8_A64, RK8_A65},
        {RK8_A71, 0, 0, RK8_A74, RK8_A75, RK8_A76},
        {RK8_A81, 0, 0, RK8_A84, RK8_A85, RK8_A86, RK8_A87},
        {RK8_A91, 0, 0, RK8_A94, RK8_A95, RK8_A96, RK8_A97, RK8_A98},
        {RK8_A10_1, 0, 0, RK8_A10_4, RK8_A10_5, RK8_A10_6, RK8_A10_7, RK8_A10_8, RK8_A10_9},
        {RK8_A11_1, 0, 0, RK8_A11_4, RK8_A11_5, RK8_A11_6, RK8_A11_7, RK8_A11_8, RK8_A11_9, RK8_A11_10},
        {RK8_A12_1, 0, 0, RK8_A12_4, RK8_A12_5, RK8_A12_6, RK8_A12_7, RK8_A12_8, RK8_A12_9, RK8_A12_10,
         RK8_A12_11},
        {RK8_A13_1, 0, 0, RK8_A13_4, RK8_A13_5, RK8_A13_6, RK8_A13_7, RK8_A13_8, RK8_A13_9, RK8_A13_10,
         RK8_A13_11, 0},
    };
    static const double b[13] = {RK8_B1, 0, 0, 0, 0, RK8_B6, RK8_B7, RK8_B8, RK8_B9, RK8_B10, RK8_B11, RK8_B12,
                                 RK8_B13};
    for (int i = 0; i < STAGES; i++)
        for (int j = 0; j < STAGES; j++) a[i][j] = 0.0L;
    for (int i = 0; i < 13; i++)
        for (int j = 0; j < i; j++) a[i][j] = rows[i][j];
    for (int j = 0; j < 13; j++) a[13][j] = b[j]; /* k_14 = y' at the step's end */
    for (int i = 0; i < RK8_DENSE_EXTRA; i++)
        for (int j = 0; j < 14 + i; j++) a[14 + i][j] = rk8_dense_a[i][j];
    for (int i = 0; i < STAGES; i++) {
        c[i] = 0.0L;
        for (int j = 0; j < i; j++) c[i] += a[i][j];
    }
}

static void grow_trees(trees *t, long double a[STAGES][STAGES])
{
    t->n = 1; /* the root alone */
    t->order[0] = 1, t->max_child[0] = -1, t->gamma[0] = 1.0L;
    for (int i = 0; i < STAGES; i++) t->phi[0][i] = 1.0L;
    for (int n = 2; n <= MAX_ORDER; n++) {
        const size_t before = t->n;
        for (size_t child = 0; child < before; child++)
            for (size_t rest = 0; rest < before; rest++) {
                if (t->order[child] + t->order[rest] != n || t->max_child[rest] > (int)child) continue;
                const size_t k = t->n++;
                assert_true(k < MAX_TREES);
                t->order[k] = n, t->max_child[k] = (int)child;
                t->gamma[k] = n * t->gamma[child] * t->gamma[rest] / t->order[rest];
                for (int i = 0; i < STAGES; i++) {
                    long double ac = 0.0L;
                    for (int j = 0; j < i; j++) ac += a[i][j] * t->phi[child][j];
                    t->phi[k][i] = ac * t->phi[rest][i];
                }
            }
    }
}

/* The largest residual of the conditions of the trees of order lo..hi on
 * weights w scaled by theta (sum w_i Phi_i = theta^order / gamma). */
static long double residual(const trees *t, const long double *w, long double theta, int lo, int hi)
{
    long double worst = 0.0L;
    for (size_t k = 0; k < t->n; k++) {
        if (t->order[k] < lo || t->order[k] > hi) continue;
        long double sum = 0.0L;
        for (int i = 0; i < STAGES; i++) sum += w[i] * t->phi[k][i];
        worst = fmaxl(worst, fabsl(sum - powl(theta, t->order[k]) / t->gamma[k]));
    }
    return worst;
}

/* The dense output's weights at theta (its Bernstein form, as the stepper
 * evaluates it). */
static void dense_weights(long double theta, long double *w)
{
    for (int i = 0; i < STAGES; i++) {
        w[i] = 0.0L;
        for (int j = 0; j <= RK8_DENSE_DEGREE; j++)
            w[i] += rk8_dense_b[i][j] * powl(theta, j) * powl(1.0L - theta, RK8_DENSE_DEGREE - j);
    }
}

static void coefficients_meet_their_order_conditions(void **state)
{
    (void)state;
    static long double a[STAGES][STAGES], c[STAGES];
    static trees t;
    tableau(a, c);
    grow_trees(&t, a);
    int count[MAX_ORDER + 1] = {0};
    for (size_t k = 0; k < t.n; k++) count[t.order[k]]++;
    static const int butcher[MAX_ORDER + 1] = {0, 1, 1, 2, 4, 9, 20, 48, 115};
    for (int n = 1; n <= MAX_ORDER; n++) assert_int_equal(count[n], butcher[n]);
    /* the pair: order 8 and 7 (GSL's rationals satisfy them to ~1e-18;
     * their doubles to rounding), and the 7th-order weights not 8 */
    long double b8[STAGES] = {0}, b7[STAGES] = {0};
    for (int j = 0; j < 13; j++) b8[j] = a[13][j];
    const double bhat[12] = {RK8_BHAT1, 0, 0, 0, 0, RK8_BHAT6, RK8_BHAT7, RK8_BHAT8, RK8_BHAT9, RK8_BHAT10,
                             RK8_BHAT11, RK8_BHAT12};
    for (int j = 0; j < 12; j++) b7[j] = bhat[j];
    const long double r8 = residual(&t, b8, 1.0L, 1, 8), r7 = residual(&t, b7, 1.0L, 1, 7);
    const long double r7_8 = residual(&t, b7, 1.0L, 8, 8);
    print_message("rk8pd: order-8 conditions to %.1Le, the embedded order-7 to %.1Le (its order-8 residual "
                  "%.1Le)\n", r8, r7, r7_8);
    assert_true(r8 < 1e-15L && r7 < 1e-15L && r7_8 > 1e-6L);
    /* the extra stages: 15, 16 of stage order 5, 17..19 of stage order 6
     * (the conditions of a stage: its row's weights, scaled by c_i) */
    for (int i = 14; i < STAGES; i++) {
        const int q = i < 16 ? 5 : 6;
        const long double r = residual(&t, a[i], c[i], 1, q);
        print_message("dense output's stage %d at c = %.3Lf: stage order %d to %.1Le\n", i + 1, c[i], q, r);
        assert_true(r < 1e-15L);
        assert_true(fabsl(c[i] - rk8_dense_c[i - 14]) < 1e-15L);
        for (int j = 1; j < 5; j++) assert_true(a[i][j] == 0.0L); /* the stepper skips stages 2..5 */
    }
    /* the dense output: order 7 at every point, b(0) = 0, b(1) = b, and
     * the stages the stepper skips weigh nothing */
    long double worst = 0.0L, principal = 0.0L, w[STAGES];
    for (int m = 1; m <= 20; m++) {
        const long double theta = m / 20.0L;
        dense_weights(theta, w);
        worst = fmaxl(worst, residual(&t, w, theta, 1, 7));
        principal = fmaxl(principal, residual(&t, w, theta, 8, 8));
    }
    dense_weights(1.0L, w);
    long double end = 0.0L;
    for (int i = 0; i < STAGES; i++) end = fmaxl(end, fabsl(w[i] - b8[i]));
    dense_weights(0.0L, w);
    for (int i = 0; i < STAGES; i++) assert_true(w[i] == 0.0L);
    print_message("dense output: order-7 conditions to %.1Le on [0, 1], its order-8 residuals up to %.1Le "
                  "(the embedded pair's: %.1Le), b(1) - b to %.1Le\n", worst, principal, r7_8, end);
    assert_true(worst < 1e-15L && end < 1e-16L && principal < r7_8);
    static const int weightless[] = {1, 2, 3, 4, 14, 15};
    for (size_t k = 0; k < sizeof weightless / sizeof *weightless; k++)
        for (int j = 0; j <= RK8_DENSE_DEGREE; j++) assert_true(rk8_dense_b[weightless[k]][j] == 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(paper_chains),
        cmocka_unit_test(ends),
        cmocka_unit_test(losses_and_load),
        cmocka_unit_test(max_order_refused),
        cmocka_unit_test(stopped_run_keeps_its_passes),
        cmocka_unit_test(coefficients_meet_their_order_conditions),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
