/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_nesterenko.c -- real units (docs/physics.md, "Real units") checked
 * against Nesterenko's solitary wave (suite 'physics').
 *
 * A chain of steel beads (R = 4.76 mm, E = 193 GPa, nu = 0.3,
 * rho = 8000 kg/m^3) struck at V: the impulse settles into a solitary wave
 * whose speed, measured from the pass times far from the impact and
 * converted to SI with taper_unit_scale, must agree within 1 % with
 * Nesterenko's closed form for the particle velocity it carries,
 *     V_s = (16/25)^(1/5) c^(4/5) v_m^(1/5),  c^2 = 2 E / (pi rho (1 - nu^2)),
 * the long-wave solitary wave V_s = (2/sqrt(5)) c xi_m^(1/4) (V. F.
 * Nesterenko, J. Appl. Mech. Tech. Phys. 24, 733 (1983); "Dynamics of
 * Heterogeneous Materials", Springer 2001, Chap. 1) written with the
 * maximum particle velocity v_m = V_s xi_m (a travelling wave has
 * v = V_s xi).  The long-wave approximation is not exact for a discrete
 * chain: the measured wave is 0.8 % slower than the closed form.
 */
#include "test_util.h"

#include "taper.h"

#include <stdlib.h>

#define YOUNG 193e9
#define POISSON 0.3
#define DENSITY 8000.0
#define RADIUS 4.76e-3
#define N 120

typedef struct wave {
    double time_per_granule; /* rescaled */
    double v_peak;           /* rescaled */
} wave;

/* The steady wave of a monodisperse chain: time per granule from a linear
 * fit of t_pass(k) over 40 <= k <= 100, and the peak velocity there. */
static wave measure(void)
{
    taper_error err;
    taper_chain_spec *cs = taper_chain_spec_alloc(&err);
    assert_non_null(cs);
    assert_int_equal(taper_chain_spec_set_n_granules(cs, N, &err), TAPER_OK);
    taper_chain *chain = taper_chain_alloc(cs, &err);
    assert_non_null(chain);
    taper_sim *sim = taper_sim_alloc(chain, NULL, &err);
    assert_non_null(sim);
    if (taper_sim_run(sim, &err) != TAPER_OK) {
        print_error("run: %s\n", err.message);
        fail();
    }
    const double *tp = taper_sim_observable(sim, TAPER_T_PASS);
    const double *vp = taper_sim_observable(sim, TAPER_V_PEAK);
    double sk = 0, st = 0, skk = 0, skt = 0, m = 0;
    for (size_t k = 40; k <= 100; k++) {
        double t = tp[k - 1];
        sk += (double)k;
        st += t;
        skk += (double)k * (double)k;
        skt += (double)k * t;
        m += 1.0;
    }
    wave w;
    w.time_per_granule = (m * skt - sk * st) / (m * skk - sk * sk);
    w.v_peak = vp[69];
    /* Steady: the peak no longer changes along the chain. */
    assert_double_rel(vp[39], vp[99], 1e-6);
    taper_sim_free(sim);
    taper_chain_free(chain);
    taper_chain_spec_free(cs);
    return w;
}

static void test_solitary_wave_speed(void **state)
{
    (void)state;
    wave w = measure();
    const double c = sqrt(2.0 * YOUNG / (3.14159265358979323846 * DENSITY * (1.0 - POISSON * POISSON)));
    /* The rescaled chain is the same for every striking velocity (eq. (5)):
     * one run, converted for several V. */
    const double V[3] = {0.1, 1.0, 10.0};
    for (int i = 0; i < 3; i++) {
        double time_unit = taper_unit_scale(TAPER_DIM_TIME, YOUNG, POISSON, DENSITY, RADIUS, V[i]);
        double velocity_unit =
            taper_unit_scale(TAPER_DIM_VELOCITY, YOUNG, POISSON, DENSITY, RADIUS, V[i]);
        /* Centres 2 R apart (radii are in units of R_1). */
        double speed = 2.0 * RADIUS / (w.time_per_granule * time_unit);
        double v_m = w.v_peak * velocity_unit;
        double nesterenko = pow(16.0 / 25.0, 0.2) * pow(c, 0.8) * pow(v_m, 0.2);
        double rel = speed / nesterenko - 1.0;
        print_message("V = %g m/s: solitary wave %.6g m/s, v_m = %.6g m/s, Nesterenko %.6g m/s "
                      "(%+.3f %%)\n", V[i], speed, v_m, nesterenko, 100.0 * rel);
        assert_true(fabs(rel) <= 0.01);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_solitary_wave_speed),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
