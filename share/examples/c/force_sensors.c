/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * force_sensors.c -- how fast a solitary wave runs in a chain of steel
 * beads, and how that depends on how hard it pushes.
 *
 * Experiments on chains of stainless-steel beads (Coste, Falcon and Fauve,
 * Phys. Rev. E 56, 6104 (1997); Daraio, Nesterenko, Herbold and Jin, Phys.
 * Rev. E 73, 026610 (2006)) strike the first bead and time the pulse between
 * force sensors placed in the chain.  Without precompression the pulse is
 * Nesterenko's solitary wave, whose speed is set by its own amplitude:
 * in the long-wave limit
 *
 *     V_s = (2/sqrt(5)) c xi_m^(1/4),   c^2 = 2 E / (pi rho (1 - nu^2)),
 *
 * with xi_m the largest strain, which Hertz's law turns into the largest
 * contact force F_m = E a^2 xi_m^(3/2) / (3 (1 - nu^2)) of two beads of
 * diameter a (Nesterenko, J. Appl. Mech. Tech. Phys. 24, 733 (1983);
 * "Dynamics of Heterogeneous Materials", Springer 2001, Chap. 1).  So
 * V_s ~ F_m^(1/6): a wave ten times stronger is only 47 % faster.
 *
 * Here 40 beads of 4.76 mm diameter (E = 193 GPa, nu = 0.3, rho =
 * 8000 kg/m^3, handbook values of type 316 stainless steel) lie just
 * touching; a steel striker at 0.5 m/s hits bead 1.  Strikers of different
 * sizes launch waves of different amplitudes.  Two force sensors read the
 * contacts (15, 16) and (25, 26); the time between their peaks gives the
 * speed, and the peak force the amplitude.  The program prints, for each
 * striker, the measured speed next to Nesterenko's, and fits the exponent of
 * V_s against F_m.  What to look at: the discrete chain's wave runs 1.2 %
 * faster than the long-wave formula says for its peak force, by the same
 * factor at every amplitude, so that the exponent is 1/6 to five digits.
 * That is no accident of the fit: the Hertz chain's equations keep their
 * form under x -> l x, t -> l^(-1/4) t, so its solitary waves are one
 * shape at every amplitude, and the striker only chooses the amplitude
 * (the wave has formed well before bead 15).
 *
 * The sensors are a sampler (taper_solver_spec_set_sampler) reading
 * taper_sim_forces every SAMPLE_DT; a parabola through the three samples
 * around the largest gives the peak's time and height.  The library's
 * rescaled units (eq. (5) of arXiv:0905.4512) become SI through
 * taper_unit_scale.  As in pulse.c every return value is checked; the
 * program exits non-zero when a call fails or a check below does not hold.
 *
 * Build against an installed libtaper:
 *     cc force_sensors.c $(pkg-config --cflags --libs taper) \
 *        -Wl,-rpath,$(pkg-config --variable=libdir taper) -lm -o force_sensors
 */
#include <taper.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define N 40                /* beads                                    */
#define YOUNG 193e9         /* Pa                                       */
#define POISSON 0.3
#define DENSITY 8000.0      /* kg/m^3                                   */
#define DIAMETER 4.76e-3    /* m                                        */
#define VELOCITY 0.5        /* m/s, the striker's                       */
#define SENSOR_1 15         /* sensors read the contacts (k, k+1)       */
#define SENSOR_2 25
#define SAMPLE_DT 0.02      /* rescaled time between readings           */
#define N_STRIKERS 4

/* What the checks allow: the discrete chain against the long-wave formula
 * (measured: 1.24 % faster), the spread of that ratio over the strikers
 * (one shape at every amplitude: measured below 1e-5), and the fitted
 * exponent against 1/6. */
#define MAX_SPEED_DEVIATION 0.02
#define MAX_RATIO_SPREAD 1e-4
#define MAX_EXPONENT_DEVIATION 1e-4
#define MAX_ENERGY_ERROR 1e-6

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

/* One sensor: the last three readings and the parabola through the three
 * around the largest reading so far. */
typedef struct sensor {
    size_t contact;       /* reads force[contact]: the contact (k, k+1) */
    double t[3], f[3];    /* the last three readings, oldest first      */
    int n;                /* readings so far                            */
    double t_peak, f_peak;
} sensor;

static void sensor_read(sensor *s, double t, double f)
{
    s->t[0] = s->t[1], s->f[0] = s->f[1];
    s->t[1] = s->t[2], s->f[1] = s->f[2];
    s->t[2] = t, s->f[2] = f;
    if (++s->n < 3 || !(s->f[1] >= s->f[0] && s->f[1] > s->f[2]) || s->f[1] <= s->f_peak) return;
    /* vertex of the parabola through three equally spaced readings */
    double curvature = s->f[0] - 2 * s->f[1] + s->f[2];
    double shift = 0.5 * (s->f[0] - s->f[2]) / curvature;   /* in samples, |shift| <= 1/2 */
    s->t_peak = s->t[1] + shift * (s->t[2] - s->t[1]);
    s->f_peak = s->f[1] - 0.25 * (s->f[0] - s->f[2]) * shift;
}

typedef struct sensors {
    sensor s[2];
    double force[N + 1];  /* taper_sim_forces: force[k] is the contact (k, k+1) */
} sensors;

/* Called by the library every SAMPLE_DT with the sim at that time. */
static int read_sensors(const taper_sim *sim, void *user)
{
    sensors *ss = user;
    taper_error err;
    if (check_status(taper_sim_forces(sim, ss->force, &err), "taper_sim_forces", &err)) return 1;
    for (int i = 0; i < 2; i++) sensor_read(&ss->s[i], taper_sim_time(sim), ss->force[ss->s[i].contact]);
    return 0;
}

/* One experiment: a striker of radius `striker` (relative to the beads'),
 * the same steel.  Fills the rescaled speed and peak force. */
static int strike(double striker, double *speed, double *f_peak, double *energy_error,
                  double *steps)
{
    taper_error err;
    taper_chain_spec *chain_spec = NULL;
    taper_solver_spec *solver_spec = NULL;
    taper_chain *chain = NULL;
    taper_sim *sim = NULL;
    sensors ss = {.s = {{.contact = SENSOR_1}, {.contact = SENSOR_2}}};
    int retval = 1;

    chain_spec = taper_chain_spec_alloc(&err);
    if (check_pointer(chain_spec, "taper_chain_spec_alloc", &err)) goto cleanup;
    if (check_status(taper_chain_spec_set_n_granules(chain_spec, N, &err),
                     "taper_chain_spec_set_n_granules", &err))
        goto cleanup;
    if (check_status(taper_chain_spec_set_striker(chain_spec, striker, 1.0, 1.0, &err),
                     "taper_chain_spec_set_striker", &err))
        goto cleanup;
    chain = taper_chain_alloc(chain_spec, &err);
    if (check_pointer(chain, "taper_chain_alloc", &err)) goto cleanup;

    /* The run ends by itself once the pulse has passed every bead, long
     * after it crossed the second sensor. */
    solver_spec = taper_solver_spec_alloc(&err);
    if (check_pointer(solver_spec, "taper_solver_spec_alloc", &err)) goto cleanup;
    if (check_status(taper_solver_spec_set_sampler(solver_spec, SAMPLE_DT, read_sensors, &ss, &err),
                     "taper_solver_spec_set_sampler", &err))
        goto cleanup;
    sim = taper_sim_alloc(chain, solver_spec, &err);
    if (check_pointer(sim, "taper_sim_alloc", &err)) goto cleanup;
    if (check_status(taper_sim_run(sim, &err), "taper_sim_run", &err)) goto cleanup;

    /* Distance between the two contacts at rest, in bead radii (the unit of
     * size), over the time of flight (the unit of time). */
    const double *x0 = taper_chain_rest_position(chain);
    *speed = (x0[SENSOR_2 - 1] - x0[SENSOR_1 - 1]) / (ss.s[1].t_peak - ss.s[0].t_peak);
    *f_peak = ss.s[1].f_peak;
    *energy_error = taper_sim_statistic(sim, TAPER_STAT_ENERGY_ERROR);
    *steps = taper_sim_statistic(sim, TAPER_STAT_STEPS);
    retval = 0;

cleanup:
    taper_sim_free(sim);
    taper_solver_spec_free(solver_spec);
    taper_chain_free(chain);
    taper_chain_spec_free(chain_spec);
    return retval;
}

int main(void)
{
    const double radius = 0.5 * DIAMETER;
    const double size_unit = taper_unit_scale(TAPER_DIM_SIZE, YOUNG, POISSON, DENSITY, radius, VELOCITY);
    const double time_unit = taper_unit_scale(TAPER_DIM_TIME, YOUNG, POISSON, DENSITY, radius, VELOCITY);
    const double force_unit = taper_unit_scale(TAPER_DIM_FORCE, YOUNG, POISSON, DENSITY, radius, VELOCITY);
    const double mass_unit = taper_unit_scale(TAPER_DIM_MASS, YOUNG, POISSON, DENSITY, radius, VELOCITY);
    if (!isfinite(size_unit * time_unit * force_unit * mass_unit)) {
        fprintf(stderr, "ERROR: taper_unit_scale refused the material\n");
        return EXIT_FAILURE;
    }
    /* Nesterenko's long-wave speed for a peak contact force f [N]. */
    const double pi = acos(-1.0);
    const double c = sqrt(2 * YOUNG / (pi * DENSITY * (1 - POISSON * POISSON)));
    const double strikers[N_STRIKERS] = {0.5, 0.63, 0.8, 1.0};   /* radii, relative */

    printf("# %d steel beads, diameter %.2f mm (%.3f g each), struck at %.2f m/s;\n", N,
           DIAMETER * 1e3, mass_unit * 1e3, VELOCITY);
    printf("# sensors at the contacts (%d, %d) and (%d, %d)\n", SENSOR_1, SENSOR_1 + 1, SENSOR_2,
           SENSOR_2 + 1);
    printf("# %9s %9s %9s %10s %11s %8s %6s %9s\n", "striker", "m_s [g]", "F_m [N]", "V_s [m/s]",
           "Nesterenko", "ratio", "steps", "E error");

    double ln_f[N_STRIKERS], ln_v[N_STRIKERS], ratio_min = INFINITY, ratio_max = -INFINITY;
    int failed = 0;
    for (int i = 0; i < N_STRIKERS; i++) {
        double speed, f_peak, energy_error, steps;
        if (strike(strikers[i], &speed, &f_peak, &energy_error, &steps)) return EXIT_FAILURE;
        const double f_si = f_peak * force_unit;
        const double v_si = speed * size_unit / time_unit;
        const double xi_m = pow(3 * (1 - POISSON * POISSON) * f_si / (YOUNG * DIAMETER * DIAMETER),
                                2.0 / 3.0);
        const double v_nesterenko = 2 / sqrt(5.0) * c * pow(xi_m, 0.25);
        const double ratio = v_si / v_nesterenko;
        printf("  %9.2f %9.4f %9.3f %10.3f %11.3f %8.5f %6.0f %9.2g\n", strikers[i],
               pow(strikers[i], 3) * mass_unit * 1e3, f_si, v_si, v_nesterenko, ratio, steps,
               energy_error);
        ratio_min = fmin(ratio_min, ratio), ratio_max = fmax(ratio_max, ratio);
        ln_f[i] = log(f_si);
        ln_v[i] = log(v_si);
        if (!(fabs(ratio - 1) <= MAX_SPEED_DEVIATION)) {
            fprintf(stderr, "FAIL: striker %g: speed %.4g m/s is %.2f %% from Nesterenko's\n",
                    strikers[i], v_si, 100 * (ratio - 1));
            failed = 1;
        }
        if (!(energy_error <= MAX_ENERGY_ERROR)) {
            fprintf(stderr, "FAIL: striker %g: energy error %.3g\n", strikers[i], energy_error);
            failed = 1;
        }
    }

    /* Least-squares slope of ln V_s against ln F_m. */
    double mf = 0, mv = 0, sff = 0, sfv = 0;
    for (int i = 0; i < N_STRIKERS; i++) mf += ln_f[i] / N_STRIKERS, mv += ln_v[i] / N_STRIKERS;
    for (int i = 0; i < N_STRIKERS; i++)
        sff += (ln_f[i] - mf) * (ln_f[i] - mf), sfv += (ln_f[i] - mf) * (ln_v[i] - mv);
    const double exponent = sfv / sff;
    printf("#\n# V_s ~ F_m^p: fitted p = %.6f, Nesterenko 1/6 = %.6f; "
           "the ratio spreads by %.2g\n", exponent, 1.0 / 6, ratio_max - ratio_min);
    if (!(ratio_max - ratio_min <= MAX_RATIO_SPREAD)) {
        fprintf(stderr, "FAIL: the ratio to Nesterenko's speed changes with the amplitude\n");
        failed = 1;
    }
    if (!(fabs(exponent - 1.0 / 6) <= MAX_EXPONENT_DEVIATION)) {
        fprintf(stderr, "FAIL: exponent %.5f is not 1/6\n", exponent);
        failed = 1;
    }
    printf("# checks: speed within %g %% of the long-wave formula, the same ratio within %g, "
           "exponent within %g of 1/6, energy error below %g: %s\n",
           100 * MAX_SPEED_DEVIATION, MAX_RATIO_SPREAD, MAX_EXPONENT_DEVIATION, MAX_ENERGY_ERROR,
           failed ? "FAILED" : "all hold");
    return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
