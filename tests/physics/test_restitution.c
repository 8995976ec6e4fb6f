/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_restitution.c -- Kuwabara-Kono damping (docs/physics.md,
 * "Viscoelastic contacts") checked through the restitution coefficient of
 * a two-granule collision (suite 'physics').
 *
 * Two equal granules, v_1 = 1, v_2 = 0: the relative coordinate z = x_1 - x_2
 * obeys mu z'' = -F with mu = 1/2 and the contact force of taper.h,
 *     F = r (z^(n-1) + damping d(z^(n-1))/dt)  while that is > 0, else 0,
 * which for n = 5/2 is r (z^(3/2) + (3/2) damping z^(1/2) z') (Kuwabara and
 * Kono, Jpn. J. Appl. Phys. 26, 1230 (1987); Brilliantov, Spahn, Hertzsch
 * and Poeschel, Phys. Rev. E 53, 5382 (1996)).  The contact ends when F
 * returns to 0; the restitution coefficient is e = -z'(end) / z'(0).
 * Here that law is integrated by a separate quadrature (classical RK4 with
 * the end of contact found by bisection inside the last step, the step
 * halved until e changes by less than 1e-11) and compared with e from
 * taper_sim's final velocities; the energy the sim reports dissipated must
 * be the kinetic energy lost, (1 - e^2) mu / 2.  damping = 0 is the
 * elastic limit e = 1.
 */
#include "test_util.h"

#include "taper.h"

#include <stdlib.h>

typedef struct state2 {
    double z, w; /* z and z' */
} state2;

/* The contact force over r, clipped at 0 (never pulls). */
static double force(state2 s, double damping)
{
    if (s.z <= 0.0) return 0.0;
    double f = pow(s.z, 1.5) + 1.5 * damping * sqrt(s.z) * s.w;
    return f > 0.0 ? f : 0.0;
}

static state2 deriv(state2 s, double r_over_mu, double damping)
{
    state2 d = {s.w, -r_over_mu * force(s, damping)};
    return d;
}

static state2 rk4(state2 s, double h, double k, double damping)
{
    state2 k1 = deriv(s, k, damping);
    state2 a = {s.z + 0.5 * h * k1.z, s.w + 0.5 * h * k1.w};
    state2 k2 = deriv(a, k, damping);
    state2 b = {s.z + 0.5 * h * k2.z, s.w + 0.5 * h * k2.w};
    state2 k3 = deriv(b, k, damping);
    state2 c = {s.z + h * k3.z, s.w + h * k3.w};
    state2 k4 = deriv(c, k, damping);
    state2 out = {s.z + h / 6.0 * (k1.z + 2 * k2.z + 2 * k3.z + k4.z),
                  s.w + h / 6.0 * (k1.w + 2 * k2.w + 2 * k3.w + k4.w)};
    return out;
}

/* Still in contact: compressed and pushing (z' > 0 counts at the start,
 * where the force is 0 at z = 0). */
static int in_contact(state2 s, double damping)
{
    return s.z > 0.0 && (force(s, damping) > 0.0 || s.w > 0.0);
}

/* e for step h: RK4 until the contact ends, the end located by bisection
 * on the length of the last step. */
static double restitution_at(double h, double r_over_mu, double damping)
{
    state2 s = {0.0, 1.0};
    s = rk4(s, h, r_over_mu, damping); /* leaves z = 0 */
    for (long i = 0; i < 100000000L; i++) {
        state2 next = rk4(s, h, r_over_mu, damping);
        if (!in_contact(next, damping)) {
            double lo = 0.0, hi = h;
            for (int j = 0; j < 80; j++) {
                double mid = 0.5 * (lo + hi);
                if (in_contact(rk4(s, mid, r_over_mu, damping), damping))
                    lo = mid;
                else
                    hi = mid;
            }
            return -rk4(s, hi, r_over_mu, damping).w;
        }
        s = next;
    }
    return NAN;
}

static double restitution_quadrature(double r_over_mu, double damping)
{
    double h = 1e-3, e = restitution_at(h, r_over_mu, damping);
    for (int i = 0; i < 14; i++) {
        h /= 2.0;
        double e2 = restitution_at(h, r_over_mu, damping);
        if (fabs(e2 - e) < 1e-11) return e2;
        e = e2;
    }
    print_error("quadrature did not converge (e = %.15g)\n", e);
    fail();
    return NAN;
}

/* e from taper_sim: two unit granules, the run carried on to t_end well
 * past the collision (residence time about 1.2). */
static double restitution_sim(double damping, double *dissipated)
{
    taper_error err;
    taper_chain_spec *cs = taper_chain_spec_alloc(&err);
    assert_non_null(cs);
    assert_int_equal(taper_chain_spec_set_n_granules(cs, 2, &err), TAPER_OK);
    assert_int_equal(taper_chain_spec_set_damping(cs, damping, &err), TAPER_OK);
    taper_chain *chain = taper_chain_alloc(cs, &err);
    assert_non_null(chain);
    taper_solver_spec *ss = taper_solver_spec_alloc(&err);
    assert_non_null(ss);
    assert_int_equal(taper_solver_spec_set_rtol(ss, 1e-12, &err), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_t_end(ss, 20.0, &err), TAPER_OK);
    taper_sim *sim = taper_sim_alloc(chain, ss, &err);
    assert_non_null(sim);
    if (taper_sim_run(sim, &err) != TAPER_OK) {
        print_error("run: %s\n", err.message);
        fail();
    }
    double v[2];
    assert_int_equal(taper_sim_state(sim, NULL, v, &err), TAPER_OK);
    *dissipated = taper_sim_statistic(sim, TAPER_STAT_ENERGY_DISSIPATED);
    taper_sim_free(sim);
    taper_solver_spec_free(ss);
    taper_chain_free(chain);
    taper_chain_spec_free(cs);
    return v[1] - v[0];
}

static void test_restitution(void **state)
{
    (void)state;
    const double mu = 0.5, r = 1.0; /* unit granules: m = 1, r_1 = 1 (eq. (7)) */
    const double damping[] = {0.0, 0.01, 0.1, 0.3};
    for (size_t i = 0; i < sizeof damping / sizeof damping[0]; i++) {
        double e_quad = restitution_quadrature(r / mu, damping[i]);
        double lost;
        double e_sim = restitution_sim(damping[i], &lost);
        print_message("damping %g: e = %.12f (sim), %.12f (quadrature)\n", damping[i], e_sim,
                      e_quad);
        assert_true(fabs(e_sim - e_quad) <= 1e-7);
        assert_true(fabs(lost - 0.5 * mu * (1.0 - e_quad * e_quad)) <= 1e-7);
        if (damping[i] == 0.0) assert_true(fabs(e_quad - 1.0) <= 1e-9);
        if (damping[i] > 0.0) assert_true(e_quad < 1.0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_restitution),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
