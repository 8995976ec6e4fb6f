/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_decorated.c -- the effective chain of a decorated chain against the
 * numerics (suite 'physics'; docs/physics.md, "Decorated chains").
 *
 * The binary collision theory of the effective chain (one granule per
 * period, the period's masses summed, its contacts as Hertz springs in
 * series) predicts the time the pulse takes per period, T of eq. (18) for
 * the effective pair.  Far from the impact the numerics give that time as
 * the slope of t_pass over the large granules.  The binary collision
 * approximation is not exact even for the monodisperse chain (its T is
 * 2.5 % longer than the solitary wave's time per granule): the effective
 * chain is asked to be as good for a decorated chain as the approximation
 * is for the monodisperse one, within one percentage point more, and the
 * large granules' velocity to settle to a constant, as the effective
 * chain's equal granules predict.
 */
#include "test_util.h"

#include "taper.h"

#include <stdlib.h>

typedef struct measured {
    double period_numerics; /* slope of t_pass over walked granules      */
    double period_theory;   /* T of the walked granules (effective pair) */
    double v_first, v_last; /* large granules' peak velocity, mid-window and at K2 */
} measured;

/* Runs a chain of n granules (pattern of p radii, or monodisperse for p
 * = 1) and compares the time per period between walked granules K1 and
 * K2. */
static measured run(const double *pattern, size_t p, size_t n, size_t K1, size_t K2)
{
    taper_error err;
    taper_chain_spec *cs = taper_chain_spec_alloc(&err);
    assert_non_null(cs);
    assert_int_equal(taper_chain_spec_set_n_granules(cs, n, &err), TAPER_OK);
    if (p > 1) {
        assert_int_equal(taper_chain_spec_set_profile(cs, TAPER_DECORATED, &err), TAPER_OK);
        assert_int_equal(taper_chain_spec_set_pattern(cs, pattern, p, &err), TAPER_OK);
    }
    taper_chain *chain = taper_chain_alloc(cs, &err);
    assert_non_null(chain);
    assert_null(taper_chain_theory_note(chain));
    taper_sim *sim = taper_sim_alloc(chain, NULL, &err);
    assert_non_null(sim);
    if (taper_sim_run(sim, &err) != TAPER_OK) {
        print_error("run: %s\n", err.message);
        fail();
    }
    const double *tp = taper_sim_observable(sim, TAPER_T_PASS);
    const double *vp = taper_sim_observable(sim, TAPER_V_PEAK);
    const double *T = taper_sim_theory(sim, TAPER_THEORY_T_RES);
    size_t i1 = (K1 - 1) * p, i2 = (K2 - 1) * p;
    measured m;
    m.period_numerics = (tp[i2] - tp[i1]) / (double)(K2 - K1);
    m.period_theory = T[i1];
    assert_double_rel(T[i1], T[i2 - p], 1e-12); /* equal effective granules */
    /* Compared over the second half of the window, where every pattern
     * within the limit has settled. */
    m.v_first = vp[((K1 + K2) / 2 - 1) * p];
    m.v_last = vp[i2];
    /* The small granules have no column of their own. */
    if (p > 1) assert_true(isnan(T[i1 + 1]) && isnan(taper_sim_theory(sim, TAPER_THEORY_V)[i1 + 1]));
    taper_sim_free(sim);
    taper_chain_free(chain);
    taper_chain_spec_free(cs);
    return m;
}

static void test_period(void **state)
{
    (void)state;
    const double one[1] = {1.0};
    measured mono = run(one, 1, 100, 30, 80);
    double mono_error = mono.period_theory / mono.period_numerics - 1.0;
    print_message("monodisperse: binary collision T %.6f, numerics %.6f (%+.2f %%)\n",
                  mono.period_theory, mono.period_numerics, 100.0 * mono_error);
    /* Small radius 0.45 is the limit of the effective chain. */
    const double p2[2] = {1.0, 0.3}, p3[3] = {1.0, 0.3, 0.2}, p2b[2] = {1.0, 0.2},
                 p2c[2] = {1.0, 0.45};
    const struct { const double *pattern; size_t p; } cases[] = {
        {p2, 2}, {p2b, 2}, {p3, 3}, {p2c, 2}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        size_t p = cases[i].p;
        measured m = run(cases[i].pattern, p, 80 * p + 1, 20, 60);
        double error = m.period_theory / m.period_numerics - 1.0;
        print_message("pattern of %zu (small %g): effective T %.6f, numerics %.6f (%+.2f %%)\n", p,
                      cases[i].pattern[1], m.period_theory, m.period_numerics, 100.0 * error);
        assert_true(fabs(error) <= fabs(mono_error) + 0.01);
        /* Steady: the large granules keep one velocity. */
        assert_double_rel(m.v_first, m.v_last, 1e-3);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_period),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
