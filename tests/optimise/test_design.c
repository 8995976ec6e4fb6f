/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_design.c -- design by optimisation finds what a scan finds, in
 * fewer runs (suite 'optimise'; docs/optimal-design.md).
 *
 * A steel striker (R = 2.38 mm, 0.5 m/s) hits a chain of 20 steel beads
 * lying against a steel wall; the chain's radii are ln(R_k/R_1) = c_1 x +
 * c_2 x^2, x = (k - 1)/19 (&design log_radii: c_1 < 0 shrinks towards the
 * wall, a forward taper; c_1 > 0 a backward one), its total length held at
 * 20 beads of 2.38 mm (&design hold = 'length'), followed for 1 ms.
 *
 *  - one setting: the taper c_1 in [-2, 2] that minimises the wall's peak
 *    force: the optimiser's answer within 1 % of a 41-point scan's best
 *    (method 'grid', the same objective through the same runs), in fewer
 *    runs than the scan's 41;
 *  - an optimum inside the bounds: with Kuwabara-Kono contacts, the taper
 *    that dissipates the most energy (goal 'maximise'), against the scan;
 *  - --two (suite 'slow'): two settings, (c_1, c_2) in [-1.5, 1.5]^2, with
 *    damping, against a 21 x 21 scan (441 runs): the wall's peak force
 *    (its optimum a corner), and the energy dissipated (maximised);
 *  - Nelder-Mead and BFGS agree, and a design resumed from its journal
 *    (the same problem run again) reuses every run and finds the same
 *    optimum to the last bit;
 *  - an integer setting (n_granules) is scanned, alone (every value run)
 *    and with a real one (optimised at each value): the best of the scan
 *    is the answer.
 */
#include "optimise/design.h"
#include "test_util.h"
#include "util/text.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char physics[] =
    "&chain n_granules = 20 /\n"
    "&ends right = 'wall' /\n"
    "&striker radius = 2.38e-3 /\n"
    "&solver t_end = 1e-3 /\n"
    "&material young = 193e9, poisson = 0.3, density = 8000, radius = 2.38e-3, "
    "velocity = 0.5 /\n";

typedef struct optimum {
    opt_outcome outcome;
    double value[2], objective;
    size_t runs;
    int at_bound[2];
} optimum;

/* The design of physics + losses + &design (its keys in `design`), in a
 * journal in `dir` (NULL: memory). */
static optimum run_design(const char *losses, const char *design, const char *dir)
{
    char *text = text_printf("%s%s&design hold = 'length', profile_points = 0, %s /\n", physics,
                             losses, design);
    scene *sc = scene_new("design.nml");
    assert_non_null(sc);
    if (scene_parse(sc, text, strlen(text)) || scene_validate(sc)) {
        scene_print_diags(sc, stderr);
        fail_msg("invalid scene:\n%s", text);
    }
    opt_error e;
    design_problem *d = design_new(sc, &e);
    if (!d) fail_msg("design_new: %s", e.message);
    opt_options o = {.threads = 2, .dir = dir};
    optimum r = {.outcome = design_run(d, &o)};
    if (r.outcome != OPT_CONVERGED) fail_msg("%s", d->reason);
    for (size_t i = 0; i < d->space->n && i < 2; i++) {
        r.value[i] = d->best[i];
        r.at_bound[i] = d->at_bound[i];
    }
    r.objective = d->best_objective;
    r.runs = d->runs;
    printf("%s: %s = %.10g at (%.8g, %.8g) in %zu runs (%zu reused): %s\n", design,
           d->objective.name, r.objective, r.value[0], d->space->n > 1 ? r.value[1] : NAN, r.runs,
           d->reused, d->reason);
    design_free(d);
    scene_free(sc);
    free(text);
    return r;
}

static const char *one = "objective = 'wall_peak_force_right', free = 'log_radii(1)', "
                         "log_radii = 0, lower = -2, upper = 2";

static void one_setting_against_a_scan(void **state)
{
    (void)state;
    optimum opt = run_design("", one, NULL);
    char *scan_keys = text_printf("%s, method = 'grid', grid = 41", one);
    optimum scan = run_design("", scan_keys, NULL);
    free(scan_keys);
    assert_int_equal(scan.runs, 41);
    assert_true(opt.objective <= 1.01 * scan.objective);
    assert_true(opt.runs < scan.runs);
    /* the physics: the steepest forward taper the bounds allow */
    assert_true(opt.value[0] < -1.9);
}

static void an_optimum_inside_the_bounds(void **state)
{
    (void)state;
    const char *losses = "&losses damping = 1e-7 /\n";
    const char *keys = "objective = 'energy_dissipated', goal = 'maximise', "
                       "free = 'log_radii(1)', log_radii = 0.5, lower = -2, upper = 2";
    optimum opt = run_design(losses, keys, NULL);
    char *scan_keys = text_printf("%s, method = 'grid', grid = 41", keys);
    optimum scan = run_design(losses, scan_keys, NULL);
    free(scan_keys);
    assert_true(opt.objective >= 0.99 * scan.objective);
    assert_true(opt.runs < scan.runs);
    assert_int_equal(opt.at_bound[0], 0);
    assert_true(fabs(opt.value[0]) < 1.0);
    /* BFGS from the same grid point agrees */
    char *bfgs_keys = text_printf("%s, method = 'bfgs'", keys);
    optimum bfgs = run_design(losses, bfgs_keys, NULL);
    free(bfgs_keys);
    assert_true(bfgs.objective >= 0.99 * scan.objective);
}

static void resumed_from_the_journal(void **state)
{
    (void)state;
    char dir[] = "/tmp/taper-design-XXXXXX";
    assert_non_null(mkdtemp(dir));
    optimum first = run_design("", one, dir);
    optimum again = run_design("", one, dir);
    assert_int_equal(again.runs, 0); /* every run from the journal */
    assert_true(again.objective == first.objective);
    assert_true(again.value[0] == first.value[0]);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    assert_int_equal(system(cmd), 0);
}

/* One two-setting design against its 21 x 21 scan; sign +1 minimises. */
static int against_scan(const char *keys, double sign)
{
    const char *losses = "&losses damping = 1e-7 /\n";
    optimum opt = run_design(losses, keys, NULL);
    char *scan_keys = text_printf("%s, method = 'grid', grid = 21", keys);
    optimum scan = run_design(losses, scan_keys, NULL);
    free(scan_keys);
    printf("optimiser %.10g in %zu runs, scan %.10g in %zu runs\n", opt.objective, opt.runs,
           scan.objective, scan.runs);
    return scan.runs == 441 && sign * opt.objective <= sign * scan.objective + 0.01 * fabs(scan.objective) &&
                   opt.runs < scan.runs ? 0 : 1;
}

/* An integer setting is scanned: every value, the real ones optimised at
 * each; the best of the scan is the answer. */
static void integers_are_scanned(void **state)
{
    (void)state;
    const char *chain = "&chain n_granules = 8 /\n&ends right = 'wall' /\n"
                        "&striker radius = 2.38e-3 /\n&losses damping = 1e-7 /\n"
                        "&solver t_end = 3e-4 /\n"
                        "&material young = 193e9, poisson = 0.3, density = 8000, "
                        "radius = 2.38e-3, velocity = 0.5 /\n";
    const char *keys[] = {
        /* integers alone: every value run, at once */
        "&design objective = 'wall_peak_force_right', free = 'n_granules', lower = 5, "
        "upper = 9, profile_points = 0 /\n",
        /* with a real setting: optimised at each of the 3 values */
        "&design objective = 'wall_peak_force_right', free = 'n_granules log_radii(1)', "
        "log_radii = 0, lower = 6, -1, upper = 8, 1, hold = 'length', profile_points = 0 /\n"};
    for (int k = 0; k < 2; k++) {
        char *text = text_printf("%s%s", chain, keys[k]);
        scene *sc = scene_new("scan.nml");
        assert_non_null(sc);
        if (scene_parse(sc, text, strlen(text)) || scene_validate(sc)) {
            scene_print_diags(sc, stderr);
            fail();
        }
        opt_error e;
        design_problem *d = design_new(sc, &e);
        if (!d) fail_msg("%s", e.message);
        opt_options o = {.threads = 2};
        assert_int_equal(design_run(d, &o), OPT_CONVERGED);
        const size_t values = k == 0 ? 5 : 3;
        assert_int_equal(d->n_scan, values);
        double best = INFINITY;
        for (size_t c = 0; c < d->n_scan; c++) {
            /* each combination's integer, in order */
            assert_true(d->scan_values[c * d->space->n] == (k == 0 ? 5.0 : 6.0) + (double)c);
            best = fmin(best, d->scan_objective[c]);
        }
        assert_true(d->best_objective == best);
        if (k == 0) assert_int_equal(d->runs, 5);
        printf("%s: best %.8g N at n_granules = %g (%zu runs)\n",
               k == 0 ? "n_granules alone" : "n_granules and log_radii(1)", d->best_objective,
               d->best[0], d->runs);
        design_free(d);
        scene_free(sc);
        free(text);
    }
}

static int two_settings(void)
{
    /* the wall's peak force: the steepest shrinking chain the box allows */
    int rc = against_scan("objective = 'wall_peak_force_right', "
                          "free = 'log_radii(1) log_radii(2)', log_radii = 0, 0, "
                          "lower = -1.5, -1.5, upper = 1.5, 1.5", 1.0);
    /* the energy dissipated: an optimum inside */
    rc |= against_scan("objective = 'energy_dissipated', goal = 'maximise', "
                       "free = 'log_radii(1) log_radii(2)', log_radii = 0, 0, "
                       "lower = -1.5, -1.5, upper = 1.5, 1.5", -1.0);
    return rc;
}

int main(int argc, char **argv)
{
    if (argc > 1 && strcmp(argv[1], "--two") == 0) return two_settings();
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(one_setting_against_a_scan),
        cmocka_unit_test(an_optimum_inside_the_bounds),
        cmocka_unit_test(resumed_from_the_journal),
        cmocka_unit_test(integers_are_scanned),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
