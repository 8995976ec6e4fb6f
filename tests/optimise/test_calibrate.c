/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_calibrate.c -- calibration recovers what produced the data (suite
 * 'optimise'; docs/calibration.md).
 *
 * A striker hits 8 stainless steel beads (R = 2.38 mm, E = 193 GPa,
 * nu = 0.3, rho = 8000 kg/m^3) lying against a steel wall at 0.5 m/s, with
 * Kuwabara-Kono contacts, A = 0.1 us.  The "measurement" is the force a
 * sensor in bead 4 reads every microsecond for 120 us, in SI, made here by
 * a run of the library at rtol 1e-12 sampled on its interval grid: not the
 * calibration's own runs (rtol 1e-10, sampled at the measured times).
 *
 *  - noise 0: Young's modulus and A come back to the integration's
 *    precision from a start 20 % and a factor 2 away;
 *  - Gaussian noise of 1 % of the peak (a fixed seed): both come back
 *    within 2 standard errors, the errors given the noise (absolute), and
 *    chi2/dof near 1; the same with the noise left out (errors scaled by
 *    the scatter): within 2 standard errors, errors within 20 % of the
 *    absolute ones;
 *  - --coverage (suite 'slow'): over 40 seeds the true values fall within
 *    1 and 2 standard errors as often as a Gaussian says (binomial bounds):
 *    the errors are the fit's uncertainty, not decoration;
 *  - Young's modulus from the wall's force alone (walls.tsv) and from
 *    the pulse's pass times (granules.tsv), to the same precision;
 *  - settings the data cannot tell apart (Young's modulus and the Poisson
 *    ratio of one material against a rigid wall: only (1 - nu^2)/E enters
 *    Hertz's law) are refused as undetermined (OPT_NOT_CONVERGED);
 *  - a fit pushed against its bound says so (OPT_NOT_CONVERGED).
 */
#include "optimise/calibrate.h"
#include "test_util.h"
#include "util/text.h"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define YOUNG 193e9
#define DAMPING 1e-7
#define SENSOR 4
#define SAMPLES 121
#define INTERVAL 1e-6

static char dir[] = "/tmp/taper-calibrate-XXXXXX";

/* The physics of every scene here: what the data come from. */
static const char physics[] =
    "&chain n_granules = 8 /\n"
    "&ends right = 'wall' /\n"
    "&striker radius = 2.38e-3 /\n"
    "&material poisson = 0.3, density = 8000, radius = 2.38e-3, velocity = 0.5,\n";

static scene *scene_of(const char *path, const char *text)
{
    scene *sc = scene_new(path);
    assert_non_null(sc);
    if (scene_parse(sc, text, strlen(text)) || scene_validate(sc)) {
        scene_print_diags(sc, stderr);
        fail_msg("invalid scene:\n%s", text);
    }
    return sc;
}

/* ---- the measurement --------------------------------------------------------------------- */

typedef struct signal {
    double t[SAMPLES], force[SAMPLES], wall[SAMPLES]; /* rescaled */
    size_t n;
} signal;

static int record(const taper_sim *sim, void *user)
{
    signal *s = user;
    double f[9];
    assert_int_equal(taper_sim_forces(sim, f, NULL), TAPER_OK);
    if (s->n < SAMPLES) {
        s->t[s->n] = taper_sim_time(sim);
        s->wall[s->n] = f[8];
        s->force[s->n++] = 0.5 * (f[SENSOR - 1] + f[SENSOR]);
    }
    return 0;
}

/* The other forms of a table, noise-free: walls.tsv's (the wall's force)
 * and granules.tsv's (pass times), written by measure() too. */
static char walls_path[256], passes_path[256];

static double peak_force;
static double truth_rtol = 1e-12; /* the measurement's integration */

/* data.tsv: the sensor's force in SI with Gaussian noise of `noise` times
 * the peak (seed), the way an experiment's table would come. */
static const char *measure(double noise, unsigned long seed)
{
    char *text = text_printf("%s          young = %.17g /\n&losses damping = %.17g /\n"
                             "&solver rtol = %g, atol = %g /\n", physics, YOUNG, DAMPING,
                             truth_rtol, truth_rtol * 1e-3);
    scene *sc = scene_of("truth.nml", text);
    free(text);
    scene_config at;
    scene_config_at(scene_cfg(sc), 0, &at);
    taper_chain_spec *cs = scene_chain_spec(&at, 0, NULL);
    taper_chain *chain = taper_chain_alloc(cs, NULL);
    taper_solver_spec *ss = scene_solver_spec(&at, NULL);
    assert_non_null(chain);
    assert_non_null(ss);
    const double unit_t = scene_unit(&at, TAPER_DIM_TIME), unit_f = scene_unit(&at, TAPER_DIM_FORCE);
    signal s = {.n = 0};
    assert_int_equal(taper_solver_spec_set_t_end(ss, (SAMPLES - 1) * INTERVAL / unit_t, NULL), TAPER_OK);
    assert_int_equal(taper_solver_spec_set_sampler(ss, INTERVAL / unit_t, record, &s, NULL), TAPER_OK);
    taper_sim *sim = taper_sim_alloc(chain, ss, NULL);
    assert_int_equal(taper_sim_run(sim, NULL), TAPER_OK);
    assert_int_equal(s.n, SAMPLES);
    peak_force = 0;
    for (size_t j = 0; j < SAMPLES; j++) peak_force = fmax(peak_force, s.force[j] * unit_f);
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng_set(rng, seed);
    static char path[256];
    snprintf(path, sizeof path, "%s/data.tsv", dir);
    FILE *fp = fopen(path, "w");
    assert_non_null(fp);
    fputs("t[s]\tgranule\tforce[N]\n# the sensor in bead 4\n", fp);
    for (size_t j = 0; j < SAMPLES; j++)
        fprintf(fp, "%.17g\t%d\t%.17g\n", (double)j * INTERVAL, SENSOR,
                s.force[j] * unit_f + (noise > 0 ? gsl_ran_gaussian(rng, noise * peak_force) : 0.0));
    fclose(fp);
    gsl_rng_free(rng);
    snprintf(walls_path, sizeof walls_path, "%s/walls.tsv", dir);
    fp = fopen(walls_path, "w");
    assert_non_null(fp);
    fputs("t[s]\tforce_right[N]\n", fp);
    for (size_t j = 0; j < SAMPLES; j++)
        fprintf(fp, "%.17g\t%.17g\n", (double)j * INTERVAL, s.wall[j] * unit_f);
    fclose(fp);
    snprintf(passes_path, sizeof passes_path, "%s/granules.tsv", dir);
    fp = fopen(passes_path, "w");
    assert_non_null(fp);
    fputs("k\tt_pass[s]\n", fp);
    const double *t_pass = taper_sim_observable(sim, TAPER_T_PASS);
    for (size_t k = 1; k < 8; k++) fprintf(fp, "%zu\t%.17g\n", k, t_pass[k - 1] * unit_t);
    fclose(fp);
    taper_sim_free(sim);
    taper_solver_spec_free(ss);
    taper_chain_free(chain);
    taper_chain_spec_free(cs);
    scene_free(sc);
    return path;
}

/* ---- the fit ------------------------------------------------------------------------------ */

/* The calibration of the data at path from (young, damping) = start, with
 * `extra` lines in &calibrate; its outcome, values and errors. */
typedef struct fitted {
    opt_outcome outcome;
    double value[2], error[2], chi2_dof;
    size_t runs;
    char reason[512];
} fitted;

static fitted calibrate_at(const char *path, double young, double damping, const char *extra,
                           const char *solver)
{
    char *text = text_printf("%s          young = %.17g /\n&losses damping = %.17g /\n%s"
                             "&calibrate data = '%s', free = 'young damping' %s /\n",
                             physics, young, damping, solver, path, extra);
    scene *sc = scene_of("fit.nml", text);
    free(text);
    opt_error e;
    calibration *c = calibration_new(sc, &e);
    if (!c) fail_msg("calibration_new: %s", e.message);
    opt_options o = {.threads = 2};
    fitted f = {.outcome = calibration_run(c, &o)};
    for (int i = 0; i < 2; i++) {
        f.value[i] = c->value[i];
        f.error[i] = c->error[i];
    }
    f.chi2_dof = c->chi2 / (double)c->dof;
    f.runs = c->runs;
    snprintf(f.reason, sizeof f.reason, "%s", c->reason ? c->reason : "");
    calibration_free(c);
    scene_free(sc);
    return f;
}

static fitted calibrate(const char *path, double young, double damping, const char *extra)
{
    return calibrate_at(path, young, damping, extra, "");
}

static void print(const char *what, const fitted *f)
{
    printf("%s: young = %.12g +- %.3g (%+.2f sigma), damping = %.12g +- %.3g (%+.2f sigma), "
           "chi2/dof = %.4g, %zu runs: %s\n", what, f->value[0], f->error[0],
           (f->value[0] - YOUNG) / f->error[0], f->value[1], f->error[1],
           (f->value[1] - DAMPING) / f->error[1], f->chi2_dof, f->runs, f->reason);
}

static void noise_free_data_to_the_tolerance(void **state)
{
    (void)state;
    const char *path = measure(0.0, 0);
    fitted f = calibrate(path, 0.8 * YOUNG, 2 * DAMPING, "");
    print("noise 0", &f);
    assert_int_equal(f.outcome, OPT_CONVERGED);
    /* The data's integration (rtol 1e-12) against the fit's (1e-10): what
     * is left is the fit's own integration error. */
    assert_double_rel(f.value[0], YOUNG, 1e-8);
    assert_double_rel(f.value[1], DAMPING, 1e-6);
    printf("relative errors: young %.2e, damping %.2e\n", fabs(f.value[0] / YOUNG - 1),
           fabs(f.value[1] / DAMPING - 1));
}

static void noisy_data_within_two_errors(void **state)
{
    (void)state;
    const char *path = measure(0.01, 1);
    char *noise = text_printf(", noise = %.17g", 0.01 * peak_force);
    fitted a = calibrate(path, 0.8 * YOUNG, 2 * DAMPING, noise);
    free(noise);
    print("1 % noise, given", &a);
    assert_int_equal(a.outcome, OPT_CONVERGED);
    assert_true(fabs(a.value[0] - YOUNG) < 2 * a.error[0]);
    assert_true(fabs(a.value[1] - DAMPING) < 2 * a.error[1]);
    /* the noise is what the fit leaves: chi2/dof within its spread
     * (sqrt(2/dof) = 0.13 for 119 degrees of freedom) */
    assert_true(fabs(a.chi2_dof - 1) < 3 * sqrt(2.0 / 119));
    /* errors that say something: below 1 % of E and 10 % of A */
    assert_true(a.error[0] < 0.01 * YOUNG && a.error[1] < 0.1 * DAMPING);
    /* the noise left out: the same fit, errors from the scatter */
    fitted b = calibrate(path, 0.8 * YOUNG, 2 * DAMPING, "");
    print("1 % noise, estimated", &b);
    assert_int_equal(b.outcome, OPT_CONVERGED);
    /* the same minimum: the two differ by what the fit's stopping rule and
     * the integration leave (xtol 1e-8, rtol 1e-10: ~1e-5 of the weakly
     * determined A), far below the statistical error */
    for (int i = 0; i < 2; i++) assert_true(fabs(b.value[i] - a.value[i]) < 1e-3 * a.error[i]);
    assert_true(fabs(b.value[0] - YOUNG) < 2 * b.error[0]);
    assert_true(fabs(b.value[1] - DAMPING) < 2 * b.error[1]);
    for (int i = 0; i < 2; i++) assert_double_rel(b.error[i], a.error[i], 0.2);
}

/* Young's modulus from the wall's force alone (walls.tsv), and from the
 * pulse's pass times (granules.tsv). */
static void the_other_tables(void **state)
{
    (void)state;
    measure(0.0, 0);
    const char *paths[] = {walls_path, passes_path};
    for (int i = 0; i < 2; i++) {
        char *text = text_printf("%s          young = 1.5e11 /\n&losses damping = %.17g /\n"
                                 "&calibrate data = '%s', free = 'young' /\n",
                                 physics, DAMPING, paths[i]);
        scene *sc = scene_of("fit.nml", text);
        free(text);
        opt_error e;
        calibration *c = calibration_new(sc, &e);
        if (!c) fail_msg("%s", e.message);
        opt_options o = {.threads = 2};
        assert_int_equal(calibration_run(c, &o), OPT_CONVERGED);
        printf("%s: young = %.12g (%.2e), %zu runs\n", paths[i], c->value[0],
               fabs(c->value[0] / YOUNG - 1), c->runs);
        assert_double_rel(c->value[0], YOUNG, 1e-8);
        calibration_free(c);
        scene_free(sc);
    }
}

/* A start beyond a tight bound: the optimum wants to leave it. */
static void a_setting_at_its_bound_says_so(void **state)
{
    (void)state;
    const char *path = measure(0.0, 0);
    fitted f = calibrate(path, 1.5e11, 2 * DAMPING, ", lower = 1e11, 0, upper = 1.6e11, 1e-6");
    print("young bounded below the truth", &f);
    assert_int_equal(f.outcome, OPT_NOT_CONVERGED);
    assert_non_null(strstr(f.reason, "young"));
    assert_non_null(strstr(f.reason, "upper bound"));
    assert_double_rel(f.value[0], 1.6e11, 1e-4);
}

static void settings_the_data_cannot_tell_apart(void **state)
{
    (void)state;
    const char *path = measure(0.0, 0);
    char *text = text_printf("%s          young = %.17g /\n&losses damping = %.17g /\n"
                             "&calibrate data = '%s', free = 'young poisson',\n"
                             "           start = 1.5e11, 0.25 /\n",
                             physics, YOUNG, DAMPING, path);
    scene *sc = scene_of("fit.nml", text);
    free(text);
    opt_error e;
    calibration *c = calibration_new(sc, &e);
    assert_non_null(c);
    opt_options o = {.threads = 2};
    assert_int_equal(calibration_run(c, &o), OPT_NOT_CONVERGED);
    printf("%s\n", c->reason);
    assert_non_null(strstr(c->reason, "do not determine poisson"));
    assert_true(isnan(c->error[1]));
    /* what the data do determine, they determine: the compliance */
    double nu = c->value[1];
    assert_double_rel((1 - nu * nu) / c->value[0], (1 - 0.09) / YOUNG, 1e-8);
    calibration_free(c);
    scene_free(sc);
}

/* --coverage: how often the truth is within 1 and 2 errors. */
static int coverage(void)
{
    enum { SEEDS = 40 };
    int in1[2] = {0}, in2[2] = {0};
    for (unsigned long seed = 1; seed <= SEEDS; seed++) {
        const char *path = measure(0.01, seed);
        char *noise = text_printf(", noise = %.17g", 0.01 * peak_force);
        fitted f = calibrate(path, 0.8 * YOUNG, 2 * DAMPING, noise);
        free(noise);
        if (f.outcome != OPT_CONVERGED) {
            printf("seed %lu: %s\n", seed, f.reason);
            return 1;
        }
        const double truth[2] = {YOUNG, DAMPING};
        for (int i = 0; i < 2; i++) {
            double z = fabs(f.value[i] - truth[i]) / f.error[i];
            in1[i] += z < 1;
            in2[i] += z < 2;
        }
    }
    /* Binomial(40, 0.683): 18..36 holds 99.9 %; Binomial(40, 0.954): 34..40. */
    int ok = 1;
    const char *names[2] = {"young", "damping"};
    for (int i = 0; i < 2; i++) {
        printf("%s: within 1 error %d/%d (expect 27.3), within 2 errors %d/%d (expect 38.2)\n",
               names[i], in1[i], SEEDS, in2[i], SEEDS);
        ok &= in1[i] >= 18 && in1[i] <= 36 && in2[i] >= 34;
    }
    return ok ? 0 : 1;
}

static int setup(void **state)
{
    (void)state;
    return 0;
}

/* --accuracy: how the integration's tolerance limits the fit (noise-free
 * data made at rtol 1e-13; docs/calibration.md, "Accuracy"). */
static int accuracy(void)
{
    const char *path = measure(0.0, 0);
    printf("rtol\tyoung_error\tdamping_error\toutcome\truns\n");
    int rc = 0;
    for (double rtol = 1e-6; rtol > 1e-13; rtol /= 100) {
        char *solver = text_printf("&solver rtol = %g, atol = %g /\n", rtol, rtol * 1e-3);
        fitted f = calibrate_at(path, 0.8 * YOUNG, 2 * DAMPING, "", solver);
        free(solver);
        printf("%g\t%.2e\t%.2e\t%s\t%zu\n", rtol, fabs(f.value[0] / YOUNG - 1),
               fabs(f.value[1] / DAMPING - 1), f.outcome == OPT_CONVERGED ? "converged" : f.reason,
               f.runs);
        rc |= f.outcome != OPT_CONVERGED;
    }
    return rc;
}

int main(int argc, char **argv)
{
    if (!mkdtemp(dir)) return 1;
    int rc;
    if (argc > 1 && strcmp(argv[1], "--accuracy") == 0) {
        truth_rtol = 1e-13;
        rc = accuracy();
    } else if (argc > 1 && strcmp(argv[1], "--coverage") == 0) {
        rc = coverage();
    } else {
        const struct CMUnitTest tests[] = {
            cmocka_unit_test(noise_free_data_to_the_tolerance),
            cmocka_unit_test(noisy_data_within_two_errors),
            cmocka_unit_test(the_other_tables),
            cmocka_unit_test(a_setting_at_its_bound_says_so),
            cmocka_unit_test(settings_the_data_cannot_tell_apart),
        };
        rc = cmocka_run_group_tests(tests, setup, NULL);
    }
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd) != 0) rc = 1;
    return rc;
}
