/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_peers.c -- the baselines of taper-bench are honest (suite 'peers').
 *
 *  - N = 2: the pass time of granule 1 is the time to maximum compression of
 *    one binary collision, which is T_1 of eq. (18) exactly, and
 *    granule 2 leaves with v = 1 (equal masses).  Velocity Verlet converges
 *    to it at order 2 (pass time by linear interpolation between steps);
 *    rk8pd reaches it to 1e-10.
 *  - A short backward linear chain: rk8pd at tight tolerance and CVODE
 *    (the library's default solver) agree on every t_pass and v_peak to 1e-8,
 *    and Verlet at a fine step to its O(dt^2) error.
 *  - The ARKODE ERK peer (every table) reaches T_1 and v = 1 to 1e-10 on
 *    N = 2 and CVODE to 1e-8 on the short chain, with events from ARKODE's
 *    root finder.
 *  - A peer's message cut at the buffer's end ends in "...", as the
 *    library's do.
 * The peers and this test use libtaper's public API only (taper.h).
 */
#include "test_chains.h"
#include "test_util.h"

#include "peers/peers.h"
#include "reference.h"
#include "taper.h"

#include <gsl/gsl_errno.h>
#include <stdlib.h>
#include <string.h>

static taper_chain *make(taper_profile profile, size_t n, double s, double q)
{
    return test_chain(profile, n, s, q, 2.5, NULL);
}

static double theory_T1(const taper_chain *c)
{
    double T[2];
    assert_int_equal(taper_theory_compute(c, NULL, NULL, T, NULL, NULL), TAPER_OK);
    return T[0];
}

static void test_verlet_order_two(void **state)
{
    (void)state;
    taper_chain *c = make(TAPER_MONODISPERSE, 2, 0, 0);
    const double T1 = theory_T1(c);
    double err[3];
    for (int i = 0; i < 3; i++) {
        taper_peer_result r;
        double dt = T1 / (40.0 * (1 << i));
        assert_int_equal(taper_peer_verlet(c, dt, 0, &r, NULL), TAPER_OK);
        assert_true(r.complete);
        err[i] = fabs(r.t_pass[0] - T1) / T1;
        assert_double_rel(r.v_peak[1], 1.0, 1e-3);
        assert_true(r.energy_drift < 1e-3);
        taper_peer_result_free(&r);
    }
    for (int i = 0; i < 2; i++) {
        double order = log2(err[i] / err[i + 1]);
        if (!(order > 1.8 && order < 2.2)) {
            print_error("Verlet order %.3f (errors %.3g %.3g)\n", order, err[i], err[i + 1]);
            fail();
        }
    }
    assert_true(err[2] < 1e-4);
    taper_chain_free(c);
}

static void test_rk8pd_binary_collision(void **state)
{
    (void)state;
    taper_chain *c = make(TAPER_MONODISPERSE, 2, 0, 0);
    taper_peer_result r;
    assert_int_equal(taper_peer_rk8pd(c, 1e-12, 1e-15, 0, &r, NULL), TAPER_OK);
    assert_true(r.complete);
    assert_double_rel(r.t_pass[0], theory_T1(c), 1e-10);
    assert_double_rel(r.v_peak[1], 1.0, 1e-10);
    assert_true(r.energy_drift < 1e-10);
    taper_peer_result_free(&r);
    taper_chain_free(c);
}

/* The CVODE run every peer is compared with: at rtol 1e-12, atol 1e-15,
 * as accurate as the peers' 1e-12..1e-13 (the defaults' v_peak error, up to
 * 1.7e-8 with Adams' order 8 and step band, is above the
 * 1e-8 these comparisons ask). */
static taper_sim *cvode_reference(const taper_chain *c)
{
    taper_solver_spec *spec = taper_solver_spec_alloc(NULL);
    assert_non_null(spec);
    assert_int_equal(taper_solver_spec_set_rtol(spec, 1e-12, NULL), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_atol(spec, 1e-15, NULL), TAPER_OK);
    taper_sim *sim = taper_sim_alloc(c, spec, NULL);
    taper_solver_spec_free(spec);
    assert_non_null(sim);
    assert_int_equal(taper_sim_run(sim, NULL), TAPER_OK);
    return sim;
}

static void test_peers_match_cvode(void **state)
{
    (void)state;
    taper_chain *c = make(TAPER_BACKWARD_LINEAR, 20, 0.5, 0);
    taper_sim *sim = cvode_reference(c);
    const double *tp = taper_sim_observable(sim, TAPER_T_PASS);
    const double *vp = taper_sim_observable(sim, TAPER_V_PEAK);

    taper_peer_result rk, vv;
    assert_int_equal(taper_peer_rk8pd(c, 1e-12, 1e-15, 0, &rk, NULL), TAPER_OK);
    assert_int_equal(taper_peer_verlet(c, 2e-3, 0, &vv, NULL), TAPER_OK);
    for (size_t k = 0; k < 20; k++) {
        if (k < 19) {
            assert_double_rel(rk.t_pass[k], tp[k], 1e-8);
            assert_double_rel(vv.t_pass[k], tp[k], 1e-5);
        }
        assert_double_rel(rk.v_peak[k], vp[k], 1e-8);
        assert_double_rel(vv.v_peak[k], vp[k], 1e-5);
    }
    assert_true(isnan(rk.t_pass[19]) && isnan(vv.t_pass[19]));
    taper_peer_result_free(&rk);
    taper_peer_result_free(&vv);
    taper_sim_free(sim);
    taper_chain_free(c);
}

static const taper_peer_erk_table erk_tables[] = {TAPER_PEER_ERK_VERNER6, TAPER_PEER_ERK_FEHLBERG8,
                                                   TAPER_PEER_ERK_DP5};
#define N_ERK (sizeof erk_tables / sizeof *erk_tables)

static void test_arkode_binary_collision(void **state)
{
    (void)state;
    taper_chain *c = make(TAPER_MONODISPERSE, 2, 0, 0);
    const double T1 = theory_T1(c);
    for (size_t i = 0; i < N_ERK; i++) {
        taper_peer_result r;
        taper_error err;
        assert_int_equal(taper_peer_arkode(c, erk_tables[i], 1e-13, 1e-16, 0, &r, &err), TAPER_OK);
        assert_true(r.complete);
        assert_double_rel(r.t_pass[0], T1, 1e-10);
        assert_double_rel(r.v_peak[1], 1.0, 1e-10);
        assert_true(r.energy_drift < 1e-10);
        assert_true(r.steps > 0 && r.rhs_evals > r.steps && r.event_evals > 0);
        taper_peer_result_free(&r);
    }
    taper_chain_free(c);
}

static void test_arkode_matches_cvode(void **state)
{
    (void)state;
    taper_chain *c = make(TAPER_BACKWARD_LINEAR, 20, 0.5, 0);
    taper_sim *sim = cvode_reference(c);
    const double *tp = taper_sim_observable(sim, TAPER_T_PASS);
    const double *vp = taper_sim_observable(sim, TAPER_V_PEAK);
    for (size_t i = 0; i < N_ERK; i++) {
        taper_peer_result r;
        assert_int_equal(taper_peer_arkode(c, erk_tables[i], 1e-13, 1e-16, 0, &r, NULL), TAPER_OK);
        assert_true(r.complete);
        for (size_t k = 0; k < 20; k++) {
            if (k < 19) assert_double_rel(r.t_pass[k], tp[k], 1e-8);
            assert_double_rel(r.v_peak[k], vp[k], 1e-8);
        }
        assert_true(isnan(r.t_pass[19]));
        taper_peer_result_free(&r);
    }
    taper_sim_free(sim);
    taper_chain_free(c);
}

static void test_invalid(void **state)
{
    (void)state;
    taper_chain *c = make(TAPER_MONODISPERSE, 3, 0, 0);
    taper_peer_result r;
    taper_error err;
    assert_int_equal(taper_peer_verlet(c, 0.0, 0, &r, &err), TAPER_EINVAL);
    assert_int_equal(taper_peer_rk8pd(c, 0.0, 1e-9, 0, &r, &err), TAPER_EINVAL);
    assert_int_equal(taper_peer_arkode(c, TAPER_PEER_ERK_DP5, 1e-9, 0.0, 0, &r, &err), TAPER_EINVAL);
    assert_int_equal(taper_peer_arkode(c, TAPER_PEER_ERK_DP5, 1e-6, 1e-9, 3, &r, &err), TAPER_ELIMIT);
    assert_false(r.complete);
    taper_peer_result_free(&r);
    assert_int_equal(taper_peer_verlet(c, 1e-3, 10, &r, &err), TAPER_ELIMIT);
    assert_false(r.complete);
    taper_peer_result_free(&r);
    taper_chain_free(c);
}

static void test_messages_cut_with_ellipsis(void **state)
{
    (void)state;
    char buf[16];
    taper_peer_format(buf, sizeof buf, "%s", "0123456789abcdefghij");
    assert_string_equal(buf, "0123456789ab...");
    taper_peer_format(buf, sizeof buf, "%s", "short");
    assert_string_equal(buf, "short");
    taper_error err;
    char long_text[2 * TAPER_MESSAGE_SIZE];
    memset(long_text, 'x', sizeof long_text - 1);
    long_text[sizeof long_text - 1] = '\0';
    assert_int_equal(taper_peer_fail(&err, TAPER_ESOLVER, "peer: %s", long_text), TAPER_ESOLVER);
    assert_int_equal(err.status, TAPER_ESOLVER);
    assert_null(err.field);
    assert_int_equal(strlen(err.message), TAPER_MESSAGE_SIZE - 1);
    assert_string_equal(err.message + TAPER_MESSAGE_SIZE - 4, "...");
    assert_int_equal(taper_peer_ok(&err), TAPER_OK);
    assert_int_equal(err.message[0], '\0');
}

int main(void)
{
    gsl_set_error_handler_off();
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_verlet_order_two),
        cmocka_unit_test(test_rk8pd_binary_collision),
        cmocka_unit_test(test_peers_match_cvode),
        cmocka_unit_test(test_arkode_binary_collision),
        cmocka_unit_test(test_arkode_matches_cvode),
        cmocka_unit_test(test_invalid),
        cmocka_unit_test(test_messages_cut_with_ellipsis),
    };
    return cmocka_run_group_tests_name("peers", tests, NULL, NULL);
}
