/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_errors.c -- the library reports, never prints and never aborts.
 *
 * stdout and stderr are redirected to files for the whole test; every
 * failure path (invalid arguments, solver failure with CVODE's own message,
 * step and time limits, interruption by the monitor, invalid fits, domain
 * errors of the theory) must return its status with a message and leave
 * both files empty.  Besides:
 *  - every setter's refusal names its setting in err.field, spelt as the
 *    setter's suffix, and leaves the spec unchanged; relations between
 *    settings, checked later, name the setting to change;
 *  - a success clears err (TAPER_OK, field NULL, empty message);
 *  - a message longer than the buffer ends in "..." (never cut silently);
 *  - the name lists (profiles, methods, fit models, statistics) end in
 *    NULL and read back through their *_from_name.
 * The verdict is printed after the descriptors are restored.  Uses only the
 * public API of the shared library.
 */
#include "taper.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char report[65536];
static int fails;

#define CHECK(cond, ...)                                                                   \
    do {                                                                                   \
        if (!(cond)) {                                                                     \
            size_t used_ = strlen(report);                                                 \
            snprintf(report + used_, sizeof report - used_, "line %d: %s: ", __LINE__, #cond); \
            used_ = strlen(report);                                                        \
            snprintf(report + used_, sizeof report - used_, __VA_ARGS__);                  \
            used_ = strlen(report);                                                        \
            snprintf(report + used_, sizeof report - used_, "\n");                         \
            fails++;                                                                       \
        }                                                                                  \
    } while (0)

/* err names `field` (NULL: no single setting) after a refusal with status. */
static int refused(taper_status got, const taper_error *err, taper_status status,
                   const char *field)
{
    if (got != status || err->status != status || !err->message[0]) return 0;
    if (!field || !err->field) return field == err->field;
    return strcmp(field, err->field) == 0;
}

#define FIELD(e) ((e).field ? (e).field : "(null)")

/* err holds a success: TAPER_OK, no field, no message. */
static int cleared(const taper_error *err)
{
    return err->status == TAPER_OK && err->field == NULL && err->message[0] == '\0';
}

static taper_chain *chain_of(taper_profile profile, size_t n, double s)
{
    taper_chain_spec *spec = taper_chain_spec_alloc(NULL);
    taper_chain *chain = NULL;
    if (spec && taper_chain_spec_set_profile(spec, profile, NULL) == TAPER_OK &&
        taper_chain_spec_set_n_granules(spec, n, NULL) == TAPER_OK &&
        taper_chain_spec_set_s(spec, s, NULL) == TAPER_OK)
        chain = taper_chain_alloc(spec, NULL);
    taper_chain_spec_free(spec);
    return chain;
}

/* Runs chain with solver; returns the status and fills err and the
 * statistics (NaN if there was no sim). */
static taper_status run(const taper_chain *chain, const taper_solver_spec *solver,
                        taper_error *err, double stats[TAPER_N_STATISTICS])
{
    taper_sim *sim = taper_sim_alloc(chain, solver, err);
    taper_status status = sim ? taper_sim_run(sim, err) : err->status;
    for (int i = 0; i < TAPER_N_STATISTICS; i++)
        stats[i] = taper_sim_statistic(sim, (taper_statistic)i);
    taper_sim_free(sim);
    return status;
}

static int stop_now(const taper_progress *p, void *user)
{
    (void)p;
    return ++*(int *)user >= 3;
}

static void solver_failures(void)
{
    taper_chain *chain = chain_of(TAPER_BACKWARD_LINEAR, 40, 0.1);
    taper_solver_spec *spec = taper_solver_spec_alloc(NULL);
    taper_error err;
    double stats[TAPER_N_STATISTICS];
    CHECK(chain && spec, "set-up");
    if (!chain || !spec) return;

    /* A tolerance the integrator cannot meet: CVODE fails, and its own
     * message (normally printed to stderr) arrives in err.message. */
    taper_solver_spec_set_rtol(spec, TAPER_RTOL_MIN, NULL);
    taper_solver_spec_set_atol(spec, 1e-300, NULL);
    taper_status status = run(chain, spec, &err, stats);
    CHECK(status == TAPER_ESOLVER, "status %d (%s)", status, err.message);
    CHECK(err.status == status, "err.status %d", err.status);
    CHECK(err.field == NULL, "a solver failure is no setting's: field %s", FIELD(err));
    CHECK(strstr(err.message, "CVODE") && strstr(err.message, "flag"), "message '%s'", err.message);
    CHECK(strstr(err.message, "corrector convergence") || strstr(err.message, "error test"),
          "CVODE's own text missing: '%s'", err.message);
    CHECK(stats[TAPER_STAT_COMPLETE] == 0.0, "complete after a failure");
    taper_solver_spec_free(spec);

    spec = taper_solver_spec_alloc(NULL);
    taper_solver_spec_set_max_steps(spec, 10, NULL);
    status = run(chain, spec, &err, stats);
    CHECK(status == TAPER_ELIMIT, "max_steps: status %d", status);
    CHECK(strstr(err.message, "max_steps") != NULL, "message '%s'", err.message);
    CHECK(stats[TAPER_STAT_COMPLETE] == 0.0 && stats[TAPER_STAT_STEPS] >= 10, "steps %g",
          stats[TAPER_STAT_STEPS]);
    taper_solver_spec_free(spec);

    spec = taper_solver_spec_alloc(NULL);
    taper_solver_spec_set_t_max(spec, 1e-3, NULL);
    status = run(chain, spec, &err, stats);
    CHECK(status == TAPER_ELIMIT, "t_max: status %d", status);
    CHECK(strstr(err.message, "t_max") != NULL, "message '%s'", err.message);
    CHECK(stats[TAPER_STAT_GRANULE_REACHED] == 0.0 && stats[TAPER_STAT_COMPLETE] == 0.0,
          "reached %g", stats[TAPER_STAT_GRANULE_REACHED]);
    taper_solver_spec_free(spec);

    int calls = 0;
    spec = taper_solver_spec_alloc(NULL);
    taper_solver_spec_set_monitor(spec, stop_now, &calls);
    status = run(chain, spec, &err, stats);
    CHECK(status == TAPER_EINTERRUPTED, "monitor: status %d", status);
    CHECK(strstr(err.message, "interrupted") != NULL, "message '%s'", err.message);
    CHECK(stats[TAPER_STAT_GRANULE_REACHED] >= 1 && stats[TAPER_STAT_GRANULE_REACHED] < 39,
          "reached %g", stats[TAPER_STAT_GRANULE_REACHED]);
    taper_solver_spec_free(spec);

    /* Both methods, windowed or not, with the BDF Newton path. */
    spec = taper_solver_spec_alloc(NULL);
    taper_solver_spec_set_method(spec, TAPER_BDF, NULL);
    taper_solver_spec_set_window(spec, 0, NULL);
    taper_solver_spec_set_rtol(spec, TAPER_RTOL_MIN, NULL);
    taper_solver_spec_set_atol(spec, 1e-300, NULL);
    status = run(chain, spec, &err, stats);
    CHECK(status == TAPER_ESOLVER || status == TAPER_ELIMIT || status == TAPER_OK,
          "bdf: status %d (%s)", status, err.message);
    taper_solver_spec_free(spec);
    taper_chain_free(chain);
}

/* Every setter refuses a value out of its range, names its own setting,
 * and leaves the spec as it was. */
static void setter_refusals(void)
{
    taper_error err;
    taper_chain_spec *cs = taper_chain_spec_alloc(&err);
    CHECK(cs && cleared(&err), "chain spec alloc: '%s'", err.message);
    if (!cs) return;

#define REFUSE(call, name, getter, before)                                                    \
    do {                                                                                    \
        taper_status st_ = (call);                                                          \
        CHECK(refused(st_, &err, TAPER_EINVAL, name), "%s: status %d field %s '%s'", #call, \
              st_, FIELD(err), err.message);                                                \
        CHECK((getter) == (before), "%s changed the spec", #call);                           \
    } while (0)

    REFUSE(taper_chain_spec_set_profile(cs, (taper_profile)TAPER_N_PROFILES, &err), "profile",
           taper_chain_spec_profile(cs), TAPER_MONODISPERSE);
    REFUSE(taper_chain_spec_set_profile(cs, (taper_profile)-1, &err), "profile",
           taper_chain_spec_profile(cs), TAPER_MONODISPERSE);
    REFUSE(taper_chain_spec_set_n_granules(cs, TAPER_N_GRANULES_MIN - 1, &err), "n_granules",
           taper_chain_spec_n_granules(cs), 100);
    REFUSE(taper_chain_spec_set_n_granules(cs, (size_t)TAPER_N_GRANULES_MAX + 1, &err),
           "n_granules", taper_chain_spec_n_granules(cs), 100);
    REFUSE(taper_chain_spec_set_s(cs, -0.1, &err), "s", taper_chain_spec_s(cs), 0.0);
    REFUSE(taper_chain_spec_set_s(cs, NAN, &err), "s", taper_chain_spec_s(cs), 0.0);
    REFUSE(taper_chain_spec_set_s(cs, TAPER_S_MAX * 2, &err), "s", taper_chain_spec_s(cs), 0.0);
    REFUSE(taper_chain_spec_set_q(cs, -0.1, &err), "q", taper_chain_spec_q(cs), 0.0);
    REFUSE(taper_chain_spec_set_q(cs, INFINITY, &err), "q", taper_chain_spec_q(cs), 0.0);
    REFUSE(taper_chain_spec_set_exponent(cs, nextafter(TAPER_EXPONENT_MIN, 0.0), &err), "exponent",
           taper_chain_spec_exponent(cs), 2.5);
    REFUSE(taper_chain_spec_set_exponent(cs, TAPER_EXPONENT_MAX * 2, &err), "exponent",
           taper_chain_spec_exponent(cs), 2.5);
    REFUSE(taper_chain_spec_set_exponent(cs, NAN, &err), "exponent",
           taper_chain_spec_exponent(cs), 2.5);
    const double bad_radii[3] = {1.0, -2.0, 1.0}, nan_radii[2] = {1.0, NAN};
    size_t n_radii = 99;
    REFUSE(taper_chain_spec_set_radii(cs, bad_radii, 3, &err), "radii",
           taper_chain_spec_radii(cs, &n_radii), NULL);
    REFUSE(taper_chain_spec_set_radii(cs, nan_radii, 2, &err), "radii",
           taper_chain_spec_radii(cs, &n_radii), NULL);
    REFUSE(taper_chain_spec_set_radii(cs, NULL, 5, &err), "radii",
           taper_chain_spec_radii(cs, &n_radii), NULL);
    CHECK(n_radii == 0, "no radii: n = %zu", n_radii);
    CHECK(taper_chain_spec_set_n_granules(cs, 7, &err) == TAPER_OK && cleared(&err),
          "a success clears err: %d %s '%s'", err.status, FIELD(err), err.message);

    taper_solver_spec *ss = taper_solver_spec_alloc(&err);
    CHECK(ss && cleared(&err), "solver spec alloc: '%s'", err.message);
    if (ss) {
        const double rtol = taper_solver_spec_rtol(ss), atol = taper_solver_spec_atol(ss);
        REFUSE(taper_solver_spec_set_method(ss, (taper_method)TAPER_N_METHODS, &err), "method",
               taper_solver_spec_method(ss), TAPER_ADAMS);
        REFUSE(taper_solver_spec_set_rtol(ss, TAPER_RTOL_MIN / 2, &err), "rtol",
               taper_solver_spec_rtol(ss), rtol);
        REFUSE(taper_solver_spec_set_rtol(ss, TAPER_RTOL_MAX * 2, &err), "rtol",
               taper_solver_spec_rtol(ss), rtol);
        REFUSE(taper_solver_spec_set_rtol(ss, NAN, &err), "rtol", taper_solver_spec_rtol(ss), rtol);
        REFUSE(taper_solver_spec_set_atol(ss, 0.0, &err), "atol", taper_solver_spec_atol(ss), atol);
        REFUSE(taper_solver_spec_set_atol(ss, TAPER_ATOL_MAX * 2, &err), "atol",
               taper_solver_spec_atol(ss), atol);
        REFUSE(taper_solver_spec_set_atol(ss, NAN, &err), "atol", taper_solver_spec_atol(ss), atol);
        REFUSE(taper_solver_spec_set_last_granule(ss, (size_t)TAPER_N_GRANULES_MAX + 1, &err),
               "last_granule", taper_solver_spec_last_granule(ss), 0);
        REFUSE(taper_solver_spec_set_max_order(ss, -1, &err), "max_order",
               taper_solver_spec_max_order(ss), 0);
        REFUSE(taper_solver_spec_set_max_order(ss, TAPER_MAX_ORDER_ADAMS + 1, &err), "max_order",
               taper_solver_spec_max_order(ss), 0);
        REFUSE(taper_solver_spec_set_t_max(ss, -1.0, &err), "t_max", taper_solver_spec_t_max(ss),
               0.0);
        REFUSE(taper_solver_spec_set_t_max(ss, NAN, &err), "t_max", taper_solver_spec_t_max(ss),
               0.0);
        REFUSE(taper_solver_spec_set_max_steps(ss, -1, &err), "max_steps",
               taper_solver_spec_max_steps(ss), 0);
        CHECK(taper_solver_spec_set_rtol(ss, 1e-8, &err) == TAPER_OK && cleared(&err),
              "a success clears err");
    }

    taper_fit_spec *fb = taper_fit_spec_alloc(TAPER_FIT_DIVERGENCE_B, &err);
    CHECK(fb && cleared(&err), "fit spec alloc: '%s'", err.message);
    if (fb) {
        REFUSE(taper_fit_spec_set_exponent(fb, -1.0, &err), "exponent",
               taper_fit_spec_exponent(fb), 1.5);
        REFUSE(taper_fit_spec_set_exponent(fb, NAN, &err), "exponent",
               taper_fit_spec_exponent(fb), 1.5);
        REFUSE(taper_fit_spec_set_index_window(fb, 5, 3, &err), "index_window",
               taper_fit_spec_model(fb), TAPER_FIT_DIVERGENCE_B);
        REFUSE(taper_fit_spec_set_x_window(fb, 2.0, 1.0, &err), "x_window",
               taper_fit_spec_model(fb), TAPER_FIT_DIVERGENCE_B);
        REFUSE(taper_fit_spec_set_x_window(fb, NAN, 1.0, &err), "x_window",
               taper_fit_spec_model(fb), TAPER_FIT_DIVERGENCE_B);
        REFUSE(taper_fit_spec_set_max_iter(fb, 0, &err), "max_iter", taper_fit_spec_model(fb),
               TAPER_FIT_DIVERGENCE_B);
        REFUSE(taper_fit_spec_set_xtol(fb, 0.0, &err), "xtol", taper_fit_spec_model(fb),
               TAPER_FIT_DIVERGENCE_B);
        REFUSE(taper_fit_spec_set_xtol(fb, NAN, &err), "xtol", taper_fit_spec_model(fb),
               TAPER_FIT_DIVERGENCE_B);
    }
    CHECK(taper_fit_spec_alloc((taper_fit_model)TAPER_N_FIT_MODELS, &err) == NULL &&
              refused(err.status, &err, TAPER_EINVAL, "model"),
          "unknown fit model: field %s", FIELD(err));
#undef REFUSE

    /* NULL specs: a status, never a crash. */
    CHECK(taper_chain_spec_set_s(NULL, 0.5, &err) == TAPER_EINVAL, "set_s(NULL)");
    CHECK(taper_solver_spec_set_rtol(NULL, 1e-8, &err) == TAPER_EINVAL, "set_rtol(NULL)");
    CHECK(taper_fit_spec_set_xtol(NULL, 1e-8, &err) == TAPER_EINVAL, "set_xtol(NULL)");
    taper_chain_spec_free(NULL);
    taper_solver_spec_free(NULL);
    taper_fit_spec_free(NULL);
    taper_fit_result_free(NULL);
    taper_dynamics_free(NULL);

    taper_fit_spec_free(fb);
    taper_solver_spec_free(ss);
    taper_chain_spec_free(cs);
}

/* Relations between settings are checked when the spec is used, and name
 * the setting to change. */
static void relation_refusals(void)
{
    taper_error err;
    taper_chain_spec *cs = taper_chain_spec_alloc(NULL);
    if (!cs) return;
    taper_chain_spec_set_profile(cs, TAPER_FORWARD_LINEAR, NULL);
    taper_chain_spec_set_s(cs, 0.5, NULL);
    taper_chain_spec_set_n_granules(cs, 10, NULL);
    CHECK(refused(taper_chain_spec_check(cs, &err), &err, TAPER_EINVAL, "n_granules"),
          "forward_linear N >= 1 + 1/S: field %s '%s'", FIELD(err), err.message);
    CHECK(taper_chain_alloc(cs, &err) == NULL &&
              refused(err.status, &err, TAPER_EINVAL, "n_granules"),
          "forward_linear alloc: field %s", FIELD(err));
    taper_chain_spec_set_n_granules(cs, 2, NULL);
    CHECK(taper_chain_spec_check(cs, &err) == TAPER_OK && cleared(&err), "forward_linear N = 2");

    /* s with a profile that does not read it is refused naming it; q = 0
     * is the monodisperse limit of the exponential taper. */
    taper_chain_spec_set_profile(cs, TAPER_BACKWARD_EXPONENTIAL, NULL);
    CHECK(refused(taper_chain_spec_check(cs, &err), &err, TAPER_EINVAL, "s"),
          "s with backward_exponential: field %s", FIELD(err));
    taper_chain_spec_set_s(cs, 0.0, NULL);
    CHECK(taper_chain_spec_check(cs, &err) == TAPER_OK && cleared(&err),
          "backward_exponential with q = 0 (the monodisperse limit): %s", err.message);
    taper_chain_spec_set_q(cs, 1.5, NULL);
    CHECK(refused(taper_chain_spec_check(cs, &err), &err, TAPER_EINVAL, "q"),
          "backward_exponential q >= 1: field %s", FIELD(err));
    taper_chain_spec_set_q(cs, 0.9, NULL);
    taper_chain_spec_set_n_granules(cs, 100000, NULL);
    CHECK(taper_chain_alloc(cs, &err) == NULL && err.status == TAPER_ERANGE && err.message[0] &&
              err.field && strcmp(err.field, "n_granules") == 0,
          "overflow: %d field %s '%s'", err.status, FIELD(err), err.message);

    taper_chain_spec_set_profile(cs, TAPER_CUSTOM, NULL);
    taper_chain_spec_set_q(cs, 0.0, NULL);
    taper_chain_spec_set_n_granules(cs, 3, NULL);
    CHECK(refused(taper_chain_spec_check(cs, &err), &err, TAPER_EINVAL, "radii"),
          "custom without radii: field %s", FIELD(err));
    const double two[2] = {1.0, 2.0}, off[3] = {2.0, 1.0, 1.0};
    taper_chain_spec_set_radii(cs, two, 2, NULL);
    CHECK(refused(taper_chain_spec_check(cs, &err), &err, TAPER_EINVAL, "radii"),
          "custom with 2 radii for 3 granules: field %s", FIELD(err));
    taper_chain_spec_set_radii(cs, off, 3, NULL);
    CHECK(refused(taper_chain_spec_check(cs, &err), &err, TAPER_EINVAL, "radii"),
          "custom with R_1 != 1: field %s", FIELD(err));
    CHECK(taper_chain_alloc(NULL, &err) == NULL && err.status == TAPER_EINVAL, "NULL spec");
    CHECK(taper_chain_alloc(NULL, NULL) == NULL, "NULL spec, NULL err");
    taper_chain_spec_free(cs);

    taper_chain *chain = chain_of(TAPER_MONODISPERSE, 10, 0.0);
    taper_solver_spec *ss = taper_solver_spec_alloc(NULL);
    CHECK(chain && ss, "set-up");
    if (!chain || !ss) return;
    taper_solver_spec_set_last_granule(ss, 11, NULL);
    CHECK(taper_sim_alloc(chain, ss, &err) == NULL &&
              refused(err.status, &err, TAPER_EINVAL, "last_granule"),
          "last_granule > N: field %s", FIELD(err));
    taper_solver_spec_set_last_granule(ss, 0, NULL);
    taper_solver_spec_set_method(ss, TAPER_BDF, NULL);
    taper_solver_spec_set_max_order(ss, TAPER_MAX_ORDER_BDF + 1, NULL);
    CHECK(taper_sim_alloc(chain, ss, &err) == NULL &&
              refused(err.status, &err, TAPER_EINVAL, "max_order"),
          "BDF max_order 6: field %s", FIELD(err));
    taper_solver_spec_free(ss);

    /* A collision shorter than the resolution of its time (the theory's
     * T_k < eps t_k) is refused before the run, naming n_granules and the
     * count that resolves: forward exponential q = 1000 for 10 granules
     * (each granule 1e9 times lighter than the one before: T_7 = 6.1e-22
     * at t_7 = 1.4e-3, 2e-3 eps t_7; it stopped with CVODE flag -4 after
     * "t + h = t" whatever the method).  Not so a last granule far lighter
     * than the one before, which is carried (sim.c, "A light end carried"):
     * forward linear at its last valid S for 100 and for 10 granules, whose
     * last radius is one or two rounding errors of 1 (T_99 = 0.004 eps
     * t_99, T_9 = 0.18 eps t_9), run to completion with every pass timed,
     * and the 100 granules' first 98 pass times are those of the 99 before
     * the last alone (granule 98 passes just before 97: the light end of a
     * steep forward taper, docs/robustness.md finding A). */
    const double s_last = nextafter(1.0 / 99.0, 0.0);
    taper_chain *steep = chain_of(TAPER_FORWARD_LINEAR, 100, s_last);
    taper_chain *cut = chain_of(TAPER_FORWARD_LINEAR, 99, s_last);
    taper_chain *steep10 = chain_of(TAPER_FORWARD_LINEAR, 10, nextafter(1.0 / 9.0, 0.0));
    CHECK(steep && cut && steep10, "forward linear chains at the last valid S");
    if (steep && cut && steep10) {
        taper_sim *full = taper_sim_alloc(steep, NULL, &err);
        CHECK(full && taper_sim_run(full, &err) == TAPER_OK &&
                  taper_sim_statistic(full, TAPER_STAT_COMPLETE) == 1.0,
              "100 granules at the last valid S, the last carried: '%s'", err.message);
        taper_sim *fine = taper_sim_alloc(cut, NULL, &err);
        CHECK(fine && taper_sim_run(fine, &err) == TAPER_OK &&
                  taper_sim_statistic(fine, TAPER_STAT_COMPLETE) == 1.0,
              "the 99 granules before the last: '%s'", err.message);
        taper_sim *ten = taper_sim_alloc(steep10, NULL, &err);
        CHECK(ten && taper_sim_run(ten, &err) == TAPER_OK && taper_sim_statistic(ten, TAPER_STAT_COMPLETE) == 1.0,
              "10 granules at the last valid S, the last carried: '%s'", err.message);
        const double *t_full = full ? taper_sim_observable(full, TAPER_T_PASS) : NULL;
        const double *t_cut = fine ? taper_sim_observable(fine, TAPER_T_PASS) : NULL;
        const double *t_ten = ten ? taper_sim_observable(ten, TAPER_T_PASS) : NULL;
        int timed = t_full && t_cut && t_ten;
        double apart = 0.0;
        for (size_t k = 0; timed && k + 1 < 100; k++) timed = isfinite(t_full[k]) && t_full[k] > 0.0;
        for (size_t k = 0; timed && k + 1 < 10; k++) timed = isfinite(t_ten[k]) && t_ten[k] > 0.0;
        for (size_t k = 0; timed && k + 2 < 99; k++)
            apart = fmax(apart, fabs(t_full[k] - t_cut[k]) / t_cut[k]);
        CHECK(timed && apart <= 1e-9, "every pass timed; 100 against 99 granules: %.2e", apart);
        taper_sim_free(full);
        taper_sim_free(fine);
        taper_sim_free(ten);
    }
    taper_chain_free(steep);
    taper_chain_free(cut);
    taper_chain_free(steep10);
    taper_chain_spec *fe = taper_chain_spec_alloc(NULL);
    taper_chain *fe1000 = NULL;
    if (fe && taper_chain_spec_set_profile(fe, TAPER_FORWARD_EXPONENTIAL, NULL) == TAPER_OK &&
        taper_chain_spec_set_n_granules(fe, 10, NULL) == TAPER_OK && taper_chain_spec_set_q(fe, 1000.0, NULL) == TAPER_OK)
        fe1000 = taper_chain_alloc(fe, NULL);
    CHECK(fe1000 && taper_sim_alloc(fe1000, NULL, &err) == NULL &&
              refused(err.status, &err, TAPER_ERANGE, "n_granules") &&
              strstr(err.message, "T_7 = ") && strstr(err.message, "use at most 7 granules, or a smaller q"),
          "forward exponential q = 1000, N = 10: %d field %s '%s'", err.status, FIELD(err), err.message);
    taper_chain_free(fe1000);
    taper_chain_spec_free(fe);

    /* Not refused on that account: a chain the theory does not describe.
     * On the dimer 1, 0.7 of 1000 granules at n = 3/2, eq. (9) loses a
     * quarter of the velocity per pair, and eq. (18)'s T ~ v^((2-n)/n)
     * falls below the resolution of t at granule 723 (T = 3e-15 at
     * t = 15), where the heavy granules carry the pulse at order 1. */
    taper_chain_spec *ds = taper_chain_spec_alloc(NULL);
    double *dimer = malloc(1000 * sizeof *dimer);
    if (ds && dimer) {
        for (size_t k = 0; k < 1000; k++) dimer[k] = k % 2 ? 0.7 : 1.0;
        taper_chain_spec_set_profile(ds, TAPER_CUSTOM, NULL);
        taper_chain_spec_set_n_granules(ds, 1000, NULL);
        taper_chain_spec_set_radii(ds, dimer, 1000, NULL);
        taper_chain_spec_set_exponent(ds, 1.5, NULL);
        taper_chain *dc = taper_chain_alloc(ds, &err);
        taper_sim *dsim = dc ? taper_sim_alloc(dc, NULL, &err) : NULL;
        CHECK(dsim != NULL, "dimer 1, 0.7 at n = 3/2 refused: '%s'", err.message);
        taper_sim_free(dsim);
        taper_chain_free(dc);
    }
    free(dimer);
    taper_chain_spec_free(ds);

    CHECK(taper_sim_alloc(NULL, NULL, &err) == NULL && err.status == TAPER_EINVAL, "NULL chain");
    CHECK(taper_sim_run(NULL, &err) == TAPER_EINVAL, "run NULL");
    CHECK(taper_theory_compute(NULL, NULL, NULL, NULL, NULL, &err) == TAPER_EINVAL, "theory NULL");
    CHECK(taper_dynamics_alloc(NULL, &err) == NULL && err.status == TAPER_EINVAL, "dynamics NULL");

    taper_sim *sim = taper_sim_alloc(chain, NULL, &err);
    CHECK(sim != NULL && cleared(&err), "default spec: '%s'", err.message);
    CHECK(taper_sim_state(sim, NULL, NULL, &err) == TAPER_EINVAL, "state before run");
    CHECK(taper_sim_run(sim, &err) == TAPER_OK && cleared(&err), "run: '%s'", err.message);
    CHECK(taper_sim_run(sim, &err) == TAPER_EINVAL && strstr(err.message, "already"), "second run");
    CHECK(taper_sim_observable(sim, (taper_observable)-1) == NULL &&
              taper_sim_observable(sim, (taper_observable)TAPER_N_OBSERVABLES) == NULL,
          "unknown observable");
    CHECK(taper_sim_theory(sim, (taper_theory_quantity)TAPER_N_THEORY_QUANTITIES) == NULL,
          "unknown theory quantity");
    CHECK(isnan(taper_sim_statistic(sim, (taper_statistic)TAPER_N_STATISTICS)) &&
              isnan(taper_sim_statistic(NULL, TAPER_STAT_STEPS)),
          "unknown statistic");
    taper_sim_free(sim);
    taper_chain_free(chain);
    taper_chain_free(NULL);
    taper_sim_free(NULL);
}

/* The one list of each kind of name: NULL past the end, and back through
 * *_from_name (any case); unknown names name their setting. */
static void names(void)
{
    taper_error err;
    int i;
    for (i = 0; taper_profile_name((taper_profile)i); i++) {
        taper_profile p = (taper_profile)-1;
        CHECK(taper_profile_from_name(taper_profile_name((taper_profile)i), &p, &err) == TAPER_OK &&
                  p == (taper_profile)i && cleared(&err),
              "profile %d", i);
    }
    CHECK(i == TAPER_N_PROFILES, "%d profile names", i);
    for (i = 0; taper_method_name((taper_method)i); i++) {
        taper_method m = (taper_method)-1;
        CHECK(taper_method_from_name(taper_method_name((taper_method)i), &m, &err) == TAPER_OK &&
                  m == (taper_method)i,
              "method %d", i);
    }
    CHECK(i == TAPER_N_METHODS, "%d method names", i);
    for (i = 0; taper_fit_model_name((taper_fit_model)i); i++) {
        taper_fit_model m = (taper_fit_model)-1;
        CHECK(taper_fit_model_from_name(taper_fit_model_name((taper_fit_model)i), &m, &err) ==
                      TAPER_OK && m == (taper_fit_model)i,
              "fit model %d", i);
    }
    CHECK(i == TAPER_N_FIT_MODELS, "%d fit model names", i);
    for (i = 0; taper_statistic_name((taper_statistic)i); i++) continue;
    CHECK(i == TAPER_N_STATISTICS, "%d statistic names", i);
    /* The enums of the options beyond the paper: boundaries and disorders round-trip, the
     * dimensions each have a name and an SI unit. */
    for (i = 0; taper_boundary_name((taper_boundary)i); i++) {
        taper_boundary b = (taper_boundary)-1;
        CHECK(taper_boundary_from_name(taper_boundary_name((taper_boundary)i), &b, &err) ==
                      TAPER_OK && b == (taper_boundary)i && cleared(&err),
              "boundary %d", i);
    }
    CHECK(i == TAPER_N_BOUNDARIES, "%d boundary names", i);
    for (i = 0; taper_disorder_name((taper_disorder)i); i++) {
        taper_disorder d = (taper_disorder)-1;
        CHECK(taper_disorder_from_name(taper_disorder_name((taper_disorder)i), &d, &err) ==
                      TAPER_OK && d == (taper_disorder)i && cleared(&err),
              "disorder %d", i);
    }
    CHECK(i == TAPER_N_DISORDERS, "%d disorder names", i);
    for (i = 0; taper_dimension_name((taper_dimension)i); i++)
        CHECK(taper_dimension_unit((taper_dimension)i) != NULL, "dimension %d has no unit", i);
    CHECK(i == TAPER_N_DIMENSIONS && taper_dimension_unit((taper_dimension)i) == NULL,
          "%d dimension names", i);
    taper_boundary bd;
    CHECK(taper_boundary_from_name("glue", &bd, &err) != TAPER_OK && err.field != NULL &&
              strstr(err.message, "wall"),
          "unknown boundary: field %s '%s'", FIELD(err), err.message);
    taper_profile p;
    CHECK(taper_profile_from_name("BACKWARD_Linear", &p, &err) == TAPER_OK &&
              p == TAPER_BACKWARD_LINEAR,
          "case-insensitive");
    CHECK(refused(taper_profile_from_name("no_such_profile", &p, &err), &err, TAPER_EINVAL,
                  "profile") && strstr(err.message, "backward_linear"),
          "unknown profile: field %s '%s'", FIELD(err), err.message);
    taper_method m;
    CHECK(refused(taper_method_from_name("rk4", &m, &err), &err, TAPER_EINVAL, "method"),
          "unknown method: field %s", FIELD(err));
    taper_fit_model fm;
    CHECK(refused(taper_fit_model_from_name("cubic", &fm, &err), &err, TAPER_EINVAL, "model"),
          "unknown fit model: field %s", FIELD(err));
    CHECK(taper_profile_name((taper_profile)42) == NULL && taper_method_name((taper_method)-1) == NULL,
          "names outside the enums");
    CHECK(strcmp(taper_strerror((taper_status)12345), "unknown status") == 0, "strerror");
    for (int s = TAPER_OK; s <= TAPER_ELIMIT; s++)
        CHECK(strcmp(taper_strerror((taper_status)s), "unknown status") != 0, "strerror(%d)", s);
}

/* A message that does not fit says so: it ends in "..." at the end of the
 * buffer. */
static void long_messages(void)
{
    char name[3 * TAPER_MESSAGE_SIZE];
    memset(name, 'x', sizeof name - 1);
    name[sizeof name - 1] = '\0';
    taper_error err;
    taper_profile p;
    CHECK(taper_profile_from_name(name, &p, &err) == TAPER_EINVAL, "long profile name");
    size_t len = strnlen(err.message, sizeof err.message);
    CHECK(len == TAPER_MESSAGE_SIZE - 1 && strcmp(err.message + len - 3, "...") == 0,
          "a long message: length %zu, ends '%s'", len, err.message + (len > 8 ? len - 8 : 0));
    taper_method m;
    CHECK(taper_method_from_name(name, &m, &err) == TAPER_EINVAL &&
              strcmp(err.message + TAPER_MESSAGE_SIZE - 4, "...") == 0,
          "long method name");
    taper_fit_model fm;
    CHECK(taper_fit_model_from_name(name, &fm, &err) == TAPER_EINVAL &&
              strcmp(err.message + TAPER_MESSAGE_SIZE - 4, "...") == 0,
          "long fit model name");
    /* A short one is not marked. */
    CHECK(taper_profile_from_name("nope", &p, &err) == TAPER_EINVAL &&
              strlen(err.message) < TAPER_MESSAGE_SIZE - 1,
          "a short message: '%s'", err.message);
}

/* Domain errors return NaN or a status: GSL's handler (which aborts by
 * default) must never be reached. */
static void domain_errors(void)
{
    CHECK(isnan(taper_theory_collision_time(1, 1, 1, NAN)), "T(n = NaN)");
    CHECK(isnan(taper_theory_collision_time(1, 1, 1, 1.0)), "T(n = 1)");
    CHECK(isnan(taper_theory_collision_time(-1, 1, 1, 2.5)), "T(mu < 0)");
    CHECK(isnan(taper_theory_collision_time(1, 1, 1, INFINITY)), "T(n = inf)");
    CHECK(isnan(taper_asymptotic_C0(0.5, NAN)) && isnan(taper_asymptotic_C(NAN, 2.5)), "C");
    CHECK(isnan(taper_asymptotic_timescale(NAN, 2.5)) && isnan(taper_asymptotic_M(-1, 2.5)), "tau");
    CHECK(isnan(taper_asymptotic_f(0, 2.5)) && isnan(taper_asymptotic_eta(2, 2.5)), "f, eta");
    CHECK(isnan(taper_asymptotic_exponent((taper_law)99, 2.5)), "law 99");

    taper_error err;
    double x[3] = {1, 2, 3}, y[3] = {1, -1, NAN};
    taper_fit_spec *fs = taper_fit_spec_alloc(TAPER_FIT_POWER, NULL);
    CHECK(fs != NULL, "fit spec");
    taper_fit_result *fr = taper_fit(fs, x, y, 3, &err);
    CHECK(fr == NULL && err.status == TAPER_EINVAL && err.message[0], "fit: '%s'", err.message);
    taper_fit_result_free(fr);
    taper_fit_spec_free(fs);
    fs = taper_fit_spec_alloc(TAPER_FIT_DIVERGENCE_C, NULL);
    double xs[6] = {1, 1, 1, 1, 1, 1}, ys[6] = {1, 2, 3, 4, 5, 6};
    fr = taper_fit(fs, xs, ys, 6, &err);
    CHECK(fr == NULL && (err.status == TAPER_EINVAL || err.status == TAPER_ESOLVER),
          "degenerate fit: %d", err.status);
    taper_fit_result_free(fr);
    taper_fit_spec_free(fs);
    CHECK(taper_fit(NULL, x, y, 3, &err) == NULL && err.status == TAPER_EINVAL, "fit NULL spec");
}

/* Size of an open file (the redirected descriptors). */
static long file_size(FILE *fp)
{
    fflush(fp);
    fseek(fp, 0, SEEK_END);
    return ftell(fp);
}

/* The entry points of taper_dynamics with NULL arguments: no crash, and
 * nothing that passes for a result (issue 36, item 7). */
static void dynamics_nulls(void)
{
    taper_chain *chain = chain_of(TAPER_BACKWARD_LINEAR, 5, 0.1);
    taper_error err;
    taper_dynamics *dyn = chain ? taper_dynamics_alloc(chain, &err) : NULL;
    CHECK(dyn != NULL, "set-up");
    if (!dyn) {
        taper_chain_free(chain);
        return;
    }
    double y[10] = {1, 0, 0, 0, 0, 0, 0, 0, 0, 0}, ydot[10], e = 0, p = 0; /* v_1 = 1 */
    taper_dynamics_rhs(NULL, y, ydot);
    taper_dynamics_rhs(NULL, NULL, NULL);
    taper_dynamics_rhs(dyn, y, NULL);
    for (int i = 0; i < 10; i++) ydot[i] = 0.0;
    taper_dynamics_rhs(dyn, NULL, ydot);
    int all_nan = 1;
    for (int i = 0; i < 10; i++) all_nan &= isnan(ydot[i]);
    CHECK(all_nan, "rhs of a NULL state: ydot not NaN");
    taper_dynamics_rhs(dyn, y, ydot);
    CHECK(ydot[0] == 0.0 && ydot[1] == 1.0, "rhs: dz_1/dt = v_1 - v_2 = 1, got %g", ydot[1]);
    taper_dynamics_energy_momentum(NULL, y, &e, &p);
    CHECK(isnan(e) && isnan(p), "energy of a NULL dynamics: %g %g", e, p);
    e = p = 0.0;
    taper_dynamics_energy_momentum(dyn, NULL, &e, &p);
    CHECK(isnan(e) && isnan(p), "energy of a NULL state: %g %g", e, p);
    taper_dynamics_energy_momentum(NULL, NULL, NULL, NULL);
    taper_dynamics_energy_momentum(dyn, y, &e, &p);
    CHECK(fabs(e - 0.5) < 1e-15 && fabs(p - 1.0) < 1e-15, "energy %g, momentum %g", e, p);
    CHECK(isnan(taper_dynamics_peak_function(NULL, y, 1)) &&
              isnan(taper_dynamics_peak_function(dyn, NULL, 1)) &&
              isnan(taper_dynamics_peak_function(NULL, NULL, 0)),
          "peak function of NULL arguments");
    CHECK(!isnan(taper_dynamics_peak_function(dyn, y, 2)), "peak function");
    taper_dynamics_free(dyn);
    taper_chain_free(chain);
}

/* The monitor stops every phase (issue 36, item 1): building the chain
 * (taper_chain_alloc_monitored), the theory
 * (taper_theory_compute_monitored and taper_sim_alloc, TAPER_EINTERRUPTED,
 * the columns NaN from where it stopped), and a sampled run past the pulse,
 * whose calls end at samples, never at an event. */
typedef struct theory_watch {
    int calls, stop_at;
    size_t last_granule;
    int window_zero;
} theory_watch;

static int watch_theory(const taper_progress *p, void *user)
{
    theory_watch *w = user;
    w->calls++;
    w->last_granule = p->granule;
    w->window_zero &= p->window_lo == 0 && p->window_hi == 0;
    return w->calls >= w->stop_at;
}

static int after_pulse(const taper_progress *p, void *user)
{
    double *t_stop = user;
    return p->window_hi > 0 && p->t >= *t_stop;
}

static int count_sample(const taper_sim *sim, void *user)
{
    (void)sim;
    ++*(long *)user;
    return 0;
}

static void monitor_phases(void)
{
    enum { N = 200000 };
    taper_chain *chain = chain_of(TAPER_MONODISPERSE, N, 0.0);
    double *v = malloc(N * sizeof *v), *t = malloc(N * sizeof *t);
    taper_error err;
    CHECK(chain && v && t, "set-up");
    if (!chain || !v || !t) goto out;
    theory_watch w = {.stop_at = 2, .window_zero = 1};
    taper_status status = taper_theory_compute_monitored(chain, v, NULL, NULL, t, watch_theory, &w, &err);
    CHECK(status == TAPER_EINTERRUPTED && err.status == status && strstr(err.message, "interrupted"),
          "theory: status %d '%s'", status, err.message);
    CHECK(w.calls == 2 && w.window_zero && w.last_granule > 0, "theory's monitor: %d calls",
          w.calls);
    char said[64];
    snprintf(said, sizeof said, "after granule %zu of %d", w.last_granule, N);
    CHECK(!isnan(v[0]) && !isnan(t[w.last_granule - 1]) && isnan(v[w.last_granule]) &&
          isnan(t[w.last_granule]) && strstr(err.message, said),
          "theory interrupted: columns known to granule %zu, NaN at the next ('%s')",
          w.last_granule, err.message);
    w = (theory_watch){.stop_at = 1000000, .window_zero = 1};
    status = taper_theory_compute_monitored(chain, v, NULL, NULL, t, watch_theory, &w, &err);
    CHECK(status == TAPER_OK && w.calls == N / 65536 && !isnan(t[N - 2]),
          "theory not stopped: status %d, %d calls", status, w.calls);
    /* Building the chain: stopped at the monitor's second look (NULL,
     * EINTERRUPTED); not stopped, asked every 65536 granules of each of
     * its two loops over the chain, and the chain taper_chain_alloc's bit
     * for bit (a backward linear chain: radii, masses, contacts, rest
     * positions all computed). */
    taper_chain_spec *cs = taper_chain_spec_alloc(NULL);
    taper_chain_spec_set_profile(cs, TAPER_BACKWARD_LINEAR, NULL);
    taper_chain_spec_set_s(cs, 1e-3, NULL);
    taper_chain_spec_set_n_granules(cs, N, NULL);
    w = (theory_watch){.stop_at = 2, .window_zero = 1};
    taper_chain *built = taper_chain_alloc_monitored(cs, watch_theory, &w, &err);
    CHECK(!built && err.status == TAPER_EINTERRUPTED && strstr(err.message, "interrupted") &&
          w.calls == 2 && w.window_zero, "chain stopped: status %d '%s', %d calls", err.status,
          err.message, w.calls);
    w = (theory_watch){.stop_at = 1000000, .window_zero = 1};
    built = taper_chain_alloc_monitored(cs, watch_theory, &w, &err);
    taper_chain *plain = taper_chain_alloc(cs, NULL);
    CHECK(built && plain && err.status == TAPER_OK && w.calls == 2 * (N / 65536),
          "chain not stopped: status %d, %d calls", err.status, w.calls);
    if (built && plain) {
        const double *a[] = {taper_chain_radius(built), taper_chain_mass(built),
                             taper_chain_contact(built), taper_chain_rest_position(built)};
        const double *b[] = {taper_chain_radius(plain), taper_chain_mass(plain),
                             taper_chain_contact(plain), taper_chain_rest_position(plain)};
        for (int c = 0; c < 4; c++)
            CHECK(memcmp(a[c], b[c], (N - (c == 2)) * sizeof(double)) == 0,
                  "monitored chain: array %d differs from taper_chain_alloc's", c);
    }
    taper_chain_free(built);
    taper_chain_free(plain);
    taper_chain_spec_free(cs);
    taper_solver_spec *spec = taper_solver_spec_alloc(NULL);
    w = (theory_watch){.stop_at = 1, .window_zero = 1};
    taper_solver_spec_set_monitor(spec, watch_theory, &w);
    taper_sim *sim = taper_sim_alloc(chain, spec, &err);
    CHECK(sim == NULL && err.status == TAPER_EINTERRUPTED, "sim_alloc's theory: status %d",
          err.status);
    taper_sim_free(sim);
    /* taper_sim_alloc of a chain this long asks between its passes over it
     * too: before and after the result arrays, then the theory's three
     * looks, after the scales and the time-resolution check (7 calls); the
     * last stops it, naming the step. */
    w = (theory_watch){.stop_at = 1000000, .window_zero = 1};
    sim = taper_sim_alloc(chain, spec, &err);
    CHECK(sim && w.calls == 7 && w.window_zero, "sim_alloc's looks: %d", w.calls);
    taper_sim_free(sim);
    w = (theory_watch){.stop_at = 7, .window_zero = 1};
    sim = taper_sim_alloc(chain, spec, &err);
    CHECK(!sim && err.status == TAPER_EINTERRUPTED && strstr(err.message, "time resolution"),
          "sim_alloc stopped at its last look: '%s'", err.message);
    taper_sim_free(sim);
    taper_solver_spec_free(spec);
    taper_chain_free(chain);

    /* 50 granules, passed by t ~ 60: samples every 0.5 to t_end = 1e4, the
     * monitor asked to stop at t >= 200, long after the last event. */
    chain = chain_of(TAPER_MONODISPERSE, 50, 0.0);
    spec = taper_solver_spec_alloc(NULL);
    double t_stop = 200.0;
    long samples = 0;
    taper_solver_spec_set_t_end(spec, 1e4, NULL);
    taper_solver_spec_set_sampler(spec, 0.5, count_sample, &samples, NULL);
    taper_solver_spec_set_monitor(spec, after_pulse, &t_stop);
    sim = chain ? taper_sim_alloc(chain, spec, &err) : NULL;
    status = sim ? taper_sim_run(sim, &err) : TAPER_ENOMEM;
    const double t_final = taper_sim_statistic(sim, TAPER_STAT_T_FINAL);
    CHECK(status == TAPER_EINTERRUPTED && t_final >= 200.0 && t_final <= 201.0 && samples <= 403,
          "sampled run past the pulse: status %d at t = %g after %ld samples", status, t_final,
          samples);
    taper_sim_free(sim);
    taper_solver_spec_free(spec);
out:
    taper_chain_free(chain);
    free(v);
    free(t);
}

static void show(FILE *fp, const char *name)
{
    char buf[512];
    rewind(fp);
    size_t n = fread(buf, 1, sizeof buf - 1, fp);
    buf[n] = '\0';
    fprintf(stderr, "library wrote to %s: %s\n", name, buf);
}

int main(void)
{
    fflush(stdout);
    fflush(stderr);
    FILE *out = tmpfile(), *errf = tmpfile();
    int saved_out = dup(1), saved_err = dup(2);
    if (!out || !errf || saved_out < 0 || saved_err < 0) return 99;
    dup2(fileno(out), 1);
    dup2(fileno(errf), 2);

    setter_refusals();
    relation_refusals();
    names();
    long_messages();
    solver_failures();
    domain_errors();
    dynamics_nulls();
    monitor_phases();

    fflush(stdout);
    fflush(stderr);
    dup2(saved_out, 1);
    dup2(saved_err, 2);
    long n_out = file_size(out), n_err = file_size(errf);
    if (n_out) show(out, "stdout"), fails++;
    if (n_err) show(errf, "stderr"), fails++;
    if (fails) {
        fprintf(stderr, "%s%d failures\n", report, fails);
        return 1;
    }
    printf("errors: statuses, fields and messages correct, nothing printed, nothing aborted\n");
    return 0;
}
