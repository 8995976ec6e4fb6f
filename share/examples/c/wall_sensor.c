/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * wall_sensor.c -- a bench experiment: a striker, a chain of steel beads, a
 * force sensor in the far wall.
 *
 * Twenty stainless-steel beads (radius 4.76 mm, Young's modulus 193 GPa,
 * Poisson ratio 0.3, density 8000 kg/m^3) lie in a guide, just touching,
 * the last against a steel wall that holds a force sensor.  A steel bead of
 * the same size, the striker, hits the first at 0.5 m/s.  The impact
 * becomes a solitary wave that crosses the chain, presses on the wall and
 * comes back.  The sensor records a single pulse of force; its peak is what
 * a shock-mitigation study wants small, its time integral (the impulse) is
 * fixed by momentum.
 *
 * taper integrates the rescaled equations of arXiv:0905.4512 (eq. (6));
 * taper_unit_scale gives the SI value of each rescaled unit (eqs. (4)-(5)),
 * here the force and the time, so the sensor's record is printed in
 * newtons against microseconds.  The wall's peak force and its time are
 * located exactly by CVODE's root finder (a statistic of the run), the
 * samples only draw the curve; the energy budget at the end says where the
 * striker's energy went (docs/physics.md).
 *
 * As in pulse.c, every return value is checked, and the settings are
 * objects the library allocates (docs/api.md); the program exits non-zero
 * when a call fails or a balance is off by more than MAX_BALANCE_ERROR.
 *
 * Build against an installed libtaper:
 *     cc wall_sensor.c $(pkg-config --cflags --libs taper) \
 *        -Wl,-rpath,$(pkg-config --variable=libdir taper) -lm -o wall_sensor
 */
#include <taper.h>

#include <stdio.h>
#include <stdlib.h>

#define N 20              /* beads                                    */
#define YOUNG 193e9       /* Pa                                       */
#define POISSON 0.3
#define DENSITY 8000.0    /* kg/m^3                                   */
#define RADIUS 4.76e-3    /* m                                        */
#define VELOCITY 0.5      /* m/s, the striker's                       */
#define T_END 40.0        /* rescaled: the pulse is back from the wall */
#define INTERVAL 0.5      /* rescaled time between sensor readings     */
#define MAX_BALANCE_ERROR 1e-6 /* energy and momentum balances, relative */

static int check_status(taper_status status, const char *funcname, const taper_error *err)
{
    if (status == TAPER_OK) return 0;
    fprintf(stderr, "\nERROR: %s() failed with status %d (%s)%s%s%s\n  %s\n", funcname,
            (int)status, taper_strerror(status), err->field ? ": setting '" : "",
            err->field ? err->field : "", err->field ? "'" : "", err->message);
    return 1;
}

static int check_pointer(const void *pointer, const char *funcname, const taper_error *err)
{
    return pointer ? 0 : check_status(err->status, funcname, err);
}

/* What the sensor needs to turn the library's rescaled force and time into
 * newtons and microseconds. */
typedef struct sensor {
    double force_unit, time_unit;
    double force[N + 1];   /* taper_sim_forces: force[N] is the right wall's */
} sensor;

/* Called by the library at t = 0, INTERVAL, 2 INTERVAL, ... with the sim
 * positioned at that time.  Returning non-zero would stop the run. */
static int read_sensor(const taper_sim *sim, void *user)
{
    sensor *s = user;
    taper_error err;
    if (check_status(taper_sim_forces(sim, s->force, &err), "taper_sim_forces", &err)) return 1;
    printf("%10.3f  %10.3f\n", taper_sim_time(sim) * s->time_unit * 1e6,
           s->force[N] * s->force_unit);
    return 0;
}

int main(void)
{
    taper_error err;
    taper_chain_spec *chain_spec = NULL;
    taper_solver_spec *solver_spec = NULL;
    taper_chain *chain = NULL;
    taper_sim *sim = NULL;
    int retval = EXIT_FAILURE;

    sensor s;
    s.force_unit = taper_unit_scale(TAPER_DIM_FORCE, YOUNG, POISSON, DENSITY, RADIUS, VELOCITY);
    s.time_unit = taper_unit_scale(TAPER_DIM_TIME, YOUNG, POISSON, DENSITY, RADIUS, VELOCITY);
    double energy_unit = taper_unit_scale(TAPER_DIM_ENERGY, YOUNG, POISSON, DENSITY, RADIUS,
                                          VELOCITY);
    double impulse_unit = taper_unit_scale(TAPER_DIM_IMPULSE, YOUNG, POISSON, DENSITY, RADIUS,
                                           VELOCITY);

    /* 1. The chain: N equal beads (the monodisperse profile, Hertz
     *    contacts), a wall of the beads' own steel at the right end
     *    (compliance 1: relative to bead 1's), and a striker of bead 1's
     *    size, density and compliance. */
    chain_spec = taper_chain_spec_alloc(&err);
    if (check_pointer(chain_spec, "taper_chain_spec_alloc", &err)) goto cleanup;
    if (check_status(taper_chain_spec_set_n_granules(chain_spec, N, &err),
                     "taper_chain_spec_set_n_granules", &err))
        goto cleanup;
    if (check_status(taper_chain_spec_set_end(chain_spec, TAPER_RIGHT, TAPER_END_WALL, 1.0, &err),
                     "taper_chain_spec_set_end", &err))
        goto cleanup;
    if (check_status(taper_chain_spec_set_striker(chain_spec, 1.0, 1.0, 1.0, &err),
                     "taper_chain_spec_set_striker", &err))
        goto cleanup;
    chain = taper_chain_alloc(chain_spec, &err);
    if (check_pointer(chain, "taper_chain_alloc", &err)) goto cleanup;

    /* 2. The run: past the reflection (t_end), with the sensor read every
     *    INTERVAL. */
    solver_spec = taper_solver_spec_alloc(&err);
    if (check_pointer(solver_spec, "taper_solver_spec_alloc", &err)) goto cleanup;
    if (check_status(taper_solver_spec_set_t_end(solver_spec, T_END, &err),
                     "taper_solver_spec_set_t_end", &err))
        goto cleanup;
    if (check_status(taper_solver_spec_set_sampler(solver_spec, INTERVAL, read_sensor, &s, &err),
                     "taper_solver_spec_set_sampler", &err))
        goto cleanup;
    sim = taper_sim_alloc(chain, solver_spec, &err);
    if (check_pointer(sim, "taper_sim_alloc", &err)) goto cleanup;

    printf("# %d steel beads (R = %g mm) against a steel wall, struck at %g m/s\n", N,
           RADIUS * 1e3, VELOCITY);
    printf("# %8s  %10s\n", "t [us]", "F_wall [N]");
    if (check_status(taper_sim_run(sim, &err), "taper_sim_run", &err)) goto cleanup;

    /* 3. What the sensor measured, located exactly, and the balances that
     *    say whether to trust it. */
    printf("#\n# wall: peak %.4g N at %.4g us, impulse %.4g N s\n",
           taper_sim_statistic(sim, TAPER_STAT_WALL_PEAK_FORCE_RIGHT) * s.force_unit,
           taper_sim_statistic(sim, TAPER_STAT_WALL_PEAK_TIME_RIGHT) * s.time_unit * 1e6,
           taper_sim_statistic(sim, TAPER_STAT_WALL_IMPULSE_RIGHT) * impulse_unit);
    double e0 = taper_sim_statistic(sim, TAPER_STAT_ENERGY_INITIAL);
    printf("# energy: striker %.4g mJ; at the end %.1f %% reflected, %.1f %% transmitted, "
           "%.1f %% in the chain\n",
           e0 * energy_unit * 1e3,
           100 * taper_sim_statistic(sim, TAPER_STAT_ENERGY_REFLECTED) / e0,
           100 * taper_sim_statistic(sim, TAPER_STAT_ENERGY_TRANSMITTED) / e0,
           100 * taper_sim_statistic(sim, TAPER_STAT_ENERGY_IN_CHAIN) / e0);
    const double energy_error = taper_sim_statistic(sim, TAPER_STAT_ENERGY_ERROR);
    const double momentum_error = taper_sim_statistic(sim, TAPER_STAT_MOMENTUM_ERROR);
    const int trusted = energy_error <= MAX_BALANCE_ERROR && momentum_error <= MAX_BALANCE_ERROR;
    printf("# checks: energy error %.2g, momentum balance error %.2g (steps %.0f; at most %g): "
           "%s\n", energy_error, momentum_error, taper_sim_statistic(sim, TAPER_STAT_STEPS),
           MAX_BALANCE_ERROR, trusted ? "all hold" : "FAILED");
    if (trusted) retval = EXIT_SUCCESS;

cleanup:
    taper_sim_free(sim);
    taper_solver_spec_free(solver_spec);
    taper_chain_free(chain);
    taper_chain_spec_free(chain_spec);
    return retval;
}
