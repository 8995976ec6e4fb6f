/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_piston.c -- the piston (taper.h, taper_chain_spec_set_piston;
 * docs/physics.md, "Piston"), through the public header (suite 'physics'):
 *
 *  - balances recomputed here from the state (not the library's budget):
 *    the chain's energy, kinetic plus the contacts' (the piston's face at
 *    min(t, T) - x_1), equals the piston's work W, and its momentum the
 *    piston's impulse J, for a steady push and for a push that stopped;
 *    W = J(T) once stopped, W = J while it moves (u = 1), and the
 *    library's own energy and momentum errors are at the tolerance; with
 *    damping and drag E + D = W and P = J - drag sum x_k;
 *  - the stop is exact: the work of a push of duration T, J(T), is the
 *    momentum a steady push has given the chain at t = T (a sample there);
 *  - a short push launches a solitary wave: far along the chain it is
 *    the impulse case's wave scaled to the energy W the piston put in
 *    (amplitude ~ sqrt(W)), its speed scaled as v_m^(1/5) (Nesterenko);
 *  - a steady push sends a front faster than the piston;
 *  - the settings refuse a piston with a striker, a left wall or a load.
 */
#include "test_util.h"

#include "taper.h"

#include <math.h>
#include <stdlib.h>

#define RTOL 1e-12

static taper_chain *lossy_piston_chain(size_t n, double duration, double damping, double drag)
{
    taper_chain_spec *spec = taper_chain_spec_alloc(NULL);
    assert_int_equal(taper_chain_spec_set_n_granules(spec, n, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_damping(spec, damping, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_drag(spec, drag, NULL), TAPER_OK);
    if (duration > 0.0)
        assert_int_equal(taper_chain_spec_set_piston(spec, duration, 0.0, NULL), TAPER_OK);
    taper_chain *chain = taper_chain_alloc(spec, NULL);
    assert_non_null(chain);
    taper_chain_spec_free(spec);
    return chain;
}

static taper_chain *piston_chain(size_t n, double duration)
{
    return lossy_piston_chain(n, duration, 0.0, 0.0);
}

static taper_sim *run_sampled(const taper_chain *chain, double t_end, size_t last_granule,
                              double interval, taper_sample_fn fn, void *user)
{
    taper_solver_spec *spec = taper_solver_spec_alloc(NULL);
    assert_int_equal(taper_solver_spec_set_rtol(spec, RTOL, NULL), TAPER_OK);
    if (fn) assert_int_equal(taper_solver_spec_set_sampler(spec, interval, fn, user, NULL), TAPER_OK);
    if (t_end > 0.0) assert_int_equal(taper_solver_spec_set_t_end(spec, t_end, NULL), TAPER_OK);
    if (last_granule)
        assert_int_equal(taper_solver_spec_set_last_granule(spec, last_granule, NULL), TAPER_OK);
    taper_sim *sim = taper_sim_alloc(chain, spec, NULL);
    assert_non_null(sim);
    taper_solver_spec_free(spec);
    taper_error err;
    taper_status status = taper_sim_run(sim, &err);
    if (status != TAPER_OK) print_error("%s\n", err.message);
    assert_int_equal(status, TAPER_OK);
    return sim;
}

static taper_sim *run(const taper_chain *chain, double t_end, size_t last_granule)
{
    return run_sampled(chain, t_end, last_granule, 0.0, NULL, NULL);
}

/* The granules' momentum at the sample time 1 (the sampler's second call). */
static int momentum_at_one(const taper_sim *sim, void *user)
{
    if (taper_sim_time(sim) != 1.0) return 0;
    const taper_chain *chain = ((const taper_chain **)user)[0];
    double *p = ((double **)user)[1];
    const size_t N = taper_chain_size(chain);
    const double *m = taper_chain_mass(chain);
    double *v = malloc(N * sizeof(double));
    assert_non_null(v);
    assert_int_equal(taper_sim_state(sim, NULL, v, NULL), TAPER_OK);
    *p = 0.0;
    for (size_t k = 0; k < N; k++) *p += m[k] * v[k];
    free(v);
    return 0;
}

/* Energy and momentum of the granules at t_final, from their states and
 * the contact law r z^n / n (n = 5/2), the piston's face at min(t, T);
 * *x_sum: sum of the displacements x_k (the drag's impulse is -drag
 * times it). */
static void chain_energy_momentum(const taper_chain *chain, const taper_sim *sim, double *energy,
                                  double *momentum, double *x_sum)
{
    const size_t N = taper_chain_size(chain);
    const double *m = taper_chain_mass(chain), *r = taper_chain_contact(chain);
    double *x = malloc(N * sizeof(double)), *v = malloc(N * sizeof(double));
    assert_non_null(x);
    assert_non_null(v);
    assert_int_equal(taper_sim_state(sim, x, v, NULL), TAPER_OK);
    const double t = taper_sim_statistic(sim, TAPER_STAT_T_FINAL);
    const double face = fmin(t, taper_chain_piston_duration(chain)), n = 2.5;
    double z = face - x[0], e = 0.0, p = 0.0, xs = 0.0;
    if (z > 0.0) e += taper_chain_piston_contact(chain) / n * pow(z, n);
    for (size_t k = 1; k <= N; k++) {
        e += 0.5 * m[k - 1] * v[k - 1] * v[k - 1];
        p += m[k - 1] * v[k - 1];
        xs += x[k - 1];
        if (k < N && (z = x[k - 1] - x[k]) > 0.0) e += r[k - 1] / n * pow(z, n);
    }
    *energy = e;
    *momentum = p;
    *x_sum = xs;
    free(x);
    free(v);
}

static void check_balances(const taper_chain *chain, const taper_sim *sim, double tol)
{
    double e, p, xs;
    chain_energy_momentum(chain, sim, &e, &p, &xs);
    /* E + D = W, P = J - drag sum x_k */
    e += taper_sim_statistic(sim, TAPER_STAT_ENERGY_DISSIPATED);
    p += taper_chain_drag(chain) * xs;
    const double w = taper_sim_piston_work(sim);
    const double j = taper_sim_statistic(sim, TAPER_STAT_WALL_IMPULSE_LEFT);
    print_message("t = %g: E + D = %.15g W = %.15g (%.2e), P = %.15g J = %.15g (%.2e); library %.2e %.2e\n",
                  taper_sim_statistic(sim, TAPER_STAT_T_FINAL), e, w, fabs(e - w) / w, p, j,
                  fabs(p - j) / j, taper_sim_statistic(sim, TAPER_STAT_ENERGY_ERROR),
                  taper_sim_statistic(sim, TAPER_STAT_MOMENTUM_ERROR));
    assert_true(w > 0.0);
    assert_double_rel(e, w, tol);
    assert_double_rel(p, j, tol);
    assert_true(taper_sim_statistic(sim, TAPER_STAT_ENERGY_ERROR) <= tol);
    assert_true(taper_sim_statistic(sim, TAPER_STAT_MOMENTUM_ERROR) <= tol);
    assert_true(taper_sim_statistic(sim, TAPER_STAT_ENERGY_INITIAL) == 0.0);
}

/* A steady push: W = J (u = 1) and E = W, P = J at every t_end. */
static void steady_push_balances(void **state)
{
    (void)state;
    taper_chain *chain = piston_chain(40, INFINITY);
    const double t_ends[] = {3.0, 15.0, 40.0};
    for (size_t i = 0; i < sizeof t_ends / sizeof t_ends[0]; i++) {
        taper_sim *sim = run(chain, t_ends[i], 1);
        check_balances(chain, sim, 1e-8);
        /* u = 1 while it moves: W = J */
        assert_double_rel(taper_sim_piston_work(sim),
                          taper_sim_statistic(sim, TAPER_STAT_WALL_IMPULSE_LEFT), 1e-15);
        taper_sim_free(sim);
    }
    taper_chain_free(chain);
}

/* A push of duration T: after it W = J(T) stays, while J may grow (granule
 * 1 bouncing back on the stopped piston); E = W, P = J. */
static void stopped_push_balances(void **state)
{
    (void)state;
    const double T = 1.0;
    taper_chain *pushed = piston_chain(40, T), *steady = piston_chain(40, INFINITY);
    /* Until T the two are the same motion: the work of the push, J(T), is
     * the steady push's momentum at t = T (P = J), if the stop is exact */
    double p_at_stop = NAN;
    const void *user[2] = {steady, &p_at_stop};
    taper_sim *same = run_sampled(steady, 2.0, 1, T, momentum_at_one, (void *)user);
    taper_sim *stopped = run(pushed, 2.0, 1);
    print_message("W = %.17g, P_steady(T) = %.17g\n", taper_sim_piston_work(stopped), p_at_stop);
    assert_double_rel(taper_sim_piston_work(stopped), p_at_stop, 1e-10);
    taper_sim_free(stopped);
    taper_sim_free(same);
    const double t_ends[] = {4.0, 30.0};
    for (size_t i = 0; i < sizeof t_ends / sizeof t_ends[0]; i++) {
        taper_sim *sim = run(pushed, t_ends[i], 1);
        check_balances(pushed, sim, 1e-8);
        if (t_ends[i] > T) {
            /* the piston rests: the run is at rest behind it, W frozen */
            const double w = taper_sim_piston_work(sim);
            const double j = taper_sim_statistic(sim, TAPER_STAT_WALL_IMPULSE_LEFT);
            assert_true(j >= w * (1.0 - 1e-12));
        }
        taper_sim_free(sim);
    }
    taper_chain_free(steady);
    taper_chain_free(pushed);
}

/* Losses: E + D = W, the dissipated energy D counting no drag on the
 * piston (inverse mass 0: the drag does not act on it), P = J - drag sum x. */
static void lossy_push_balances(void **state)
{
    (void)state;
    const double durations[] = {0.5, INFINITY};
    for (size_t i = 0; i < 2; i++) {
        taper_chain *chain = lossy_piston_chain(30, durations[i], 0.05, 0.02);
        taper_sim *sim = run(chain, 0.0, 0);
        assert_true(taper_sim_statistic(sim, TAPER_STAT_ENERGY_DISSIPATED) > 0.0);
        check_balances(chain, sim, 1e-8);
        taper_sim_free(sim);
        taper_chain_free(chain);
    }
}

/* Far-field amplitude and speed of the pulse: v_peak at granule `k`, speed
 * between granules a and b from the pass times and positions. */
static void far_field(const taper_sim *sim, size_t a, size_t b, double *amplitude, double *speed)
{
    const double *tp = taper_sim_observable(sim, TAPER_T_PASS);
    const double *xp = taper_sim_observable(sim, TAPER_X_PASS);
    const double *vp = taper_sim_observable(sim, TAPER_V_PEAK);
    *amplitude = vp[b - 1];
    *speed = (xp[b - 1] - xp[a - 1]) / (tp[b - 1] - tp[a - 1]);
}

/* The solitary wave of a Hertz chain has a fixed shape: its velocities
 * scale with its amplitude v_m, its energy with v_m^2, its speed with
 * v_m^(1/5) (Nesterenko, J. Appl. Mech. Tech. Phys. 24, 733 (1983)).  The
 * impulse case (E(0) = 1/2) gives the wave of energy 1/2; a short push
 * puts the work W into the chain, and far along it the pulse is that wave
 * scaled to energy W: v_m = v_i sqrt(2 W), speed c_i (v_m / v_i)^(1/5).
 * (Not scaled by the momentum J: the push leaves the granules behind the
 * wave drifting forward slowly, momentum without much energy: W / J^2 is
 * 0.32 for T = 0.05 against the wave's 1/2.)  Measured at N = 80, granules
 * 50-70: amplitudes within 1e-3 (the impulse case's own tail keeps ~1e-3
 * of its energy), speeds within 1e-6 of the scaling. */
static void short_push_is_a_scaled_solitary_wave(void **state)
{
    (void)state;
    const size_t N = 80, a = 50, b = 70;
    taper_chain *impulse = piston_chain(N, 0.0);
    taper_sim *si = run(impulse, 0.0, b);
    double vi, ci;
    far_field(si, a, b, &vi, &ci);
    const double durations[] = {0.05, 0.3, 1.0};
    for (size_t i = 0; i < sizeof durations / sizeof durations[0]; i++) {
        taper_chain *pushed = piston_chain(N, durations[i]);
        taper_sim *sp = run(pushed, 0.0, b);
        double vp, cp;
        far_field(sp, a, b, &vp, &cp);
        const double W = taper_sim_piston_work(sp);
        print_message("T = %g: W = %.9g, v_m = %.9g (wave of energy W: %.9g), speed %.9g (%.9g)\n",
                      durations[i], W, vp, vi * sqrt(2.0 * W), cp, ci * pow(vp / vi, 0.2));
        assert_double_rel(vp, vi * sqrt(2.0 * W), 2e-3);
        assert_double_rel(cp, ci * pow(vp / vi, 0.2), 1e-5);
        taper_sim_free(sp);
        taper_chain_free(pushed);
    }
    taper_sim_free(si);
    taper_chain_free(impulse);
}

static void steady_push_front_outruns_the_piston(void **state)
{
    (void)state;
    const size_t N = 60;
    taper_chain *chain = piston_chain(N, INFINITY);
    taper_sim *sim = run(chain, 0.0, 50);
    double v, c;
    far_field(sim, 20, 50, &v, &c);
    print_message("steady push: front speed %.9g, v_peak(50) = %.9g\n", c, v);
    assert_true(c > 1.0);
    check_balances(chain, sim, 1e-8);
    taper_sim_free(sim);
    taper_chain_free(chain);
}

static void refusals(void **state)
{
    (void)state;
    taper_chain_spec *spec = taper_chain_spec_alloc(NULL);
    taper_error err;
    assert_int_equal(taper_chain_spec_set_piston(spec, -1.0, 0.0, &err), TAPER_EINVAL);
    assert_taper_error(err, TAPER_EINVAL, "piston_duration", "[0, inf]: 0 is no piston");
    assert_int_equal(taper_chain_spec_set_piston(spec, NAN, 0.0, &err), TAPER_EINVAL);
    assert_int_equal(taper_chain_spec_set_piston(spec, 1.0, -1.0, &err), TAPER_EINVAL);
    assert_taper_error(err, TAPER_EINVAL, "piston_compliance", "[0, inf): 0 is a rigid face");
    assert_int_equal(taper_chain_spec_set_piston(spec, INFINITY, 0.5, &err), TAPER_OK);
    assert_true(isinf(taper_chain_spec_piston_duration(spec)));
    assert_true(taper_chain_spec_piston_compliance(spec) == 0.5);
    assert_int_equal(taper_chain_spec_set_striker(spec, 1.0, 1.0, 1.0, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_check(spec, &err), TAPER_EINVAL);
    assert_taper_error(err, TAPER_EINVAL, "piston_duration", "striker");
    assert_int_equal(taper_chain_spec_set_striker(spec, 0.0, 1.0, 1.0, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_end(spec, TAPER_LEFT, TAPER_END_WALL, 0.0, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_check(spec, &err), TAPER_EINVAL);
    assert_taper_error(err, TAPER_EINVAL, "piston_duration", "left wall");
    assert_int_equal(taper_chain_spec_set_end(spec, TAPER_LEFT, TAPER_END_FREE, 0.0, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_load(spec, 1.0, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_check(spec, &err), TAPER_EINVAL);
    assert_taper_error(err, TAPER_EINVAL, "piston_duration", "load");
    assert_int_equal(taper_chain_spec_set_load(spec, 0.0, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_check(spec, &err), TAPER_OK);
    /* the theory does not describe a push: NaN columns with a note */
    taper_chain *chain = taper_chain_alloc(spec, NULL);
    assert_non_null(chain);
    assert_non_null(taper_chain_theory_note(chain));
    /* rigid face: 2 / (1 + c) with c = 0.5, times sqrt(2 R_1) */
    assert_double_rel(taper_chain_piston_contact(chain), sqrt(2.0) * 2.0 / 1.5, 1e-15);
    taper_chain_free(chain);
    assert_int_equal(taper_chain_spec_set_piston(spec, 0.0, 0.5, NULL), TAPER_OK);
    assert_int_equal(taper_chain_spec_check(spec, &err), TAPER_EINVAL);
    assert_taper_error(err, TAPER_EINVAL, "piston_compliance", "no effect");
    taper_chain_spec_free(spec);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(steady_push_balances),
        cmocka_unit_test(stopped_push_balances),
        cmocka_unit_test(lossy_push_balances),
        cmocka_unit_test(short_push_is_a_scaled_solitary_wave),
        cmocka_unit_test(steady_push_front_outruns_the_piston),
        cmocka_unit_test(refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
