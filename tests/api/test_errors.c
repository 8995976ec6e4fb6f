/*
 * test_errors.c -- the library reports, never prints and never aborts.
 *
 * stdout and stderr are redirected to files for the whole test; every
 * failure path (invalid arguments, solver failure with CVODE's own message,
 * step and time limits, interruption by the monitor, invalid fits, domain
 * errors of the theory) must return its status with a message and leave
 * both files empty.  The verdict is printed after the descriptors are
 * restored.  Uses only the public API of the shared library.
 */
#include "taper.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char report[16384];
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

static taper_chain *chain_of(int profile, size_t n, double s)
{
    taper_chain_spec spec;
    taper_chain_spec_init(&spec);
    spec.profile = profile;
    spec.n_granules = n;
    spec.s = s;
    return taper_chain_alloc(&spec, NULL);
}

/* Runs chain with solver; returns the status and fills err and stats. */
static int run(const taper_chain *chain, const taper_solver_spec *solver, taper_error *err,
               taper_stats *stats)
{
    taper_sim *sim = taper_sim_alloc(chain, solver, err);
    if (!sim) return err->status;
    int status = taper_sim_run(sim, err);
    taper_sim_stats(sim, stats);
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
    taper_solver_spec spec;
    taper_error err;
    taper_stats stats;

    /* A tolerance the integrator cannot meet: CVODE fails, and its own
     * message (normally printed to stderr) arrives in err.message. */
    taper_solver_spec_init(&spec);
    spec.rtol = 2.3e-15;
    spec.atol = 1e-300;
    int status = run(chain, &spec, &err, &stats);
    CHECK(status == TAPER_ESOLVER, "status %d", status);
    CHECK(err.status == status, "err.status %d", err.status);
    CHECK(strstr(err.message, "CVODE") && strstr(err.message, "flag"), "message '%s'", err.message);
    CHECK(strstr(err.message, "corrector convergence") || strstr(err.message, "error test"),
          "CVODE's own text missing: '%s'", err.message);
    CHECK(!stats.complete, "complete after a failure");

    taper_solver_spec_init(&spec);
    spec.max_steps = 10;
    status = run(chain, &spec, &err, &stats);
    CHECK(status == TAPER_ELIMIT, "max_steps: status %d", status);
    CHECK(strstr(err.message, "max_steps") != NULL, "message '%s'", err.message);
    CHECK(!stats.complete && stats.steps >= 10, "steps %ld", stats.steps);

    taper_solver_spec_init(&spec);
    spec.t_max = 1e-3;
    status = run(chain, &spec, &err, &stats);
    CHECK(status == TAPER_ELIMIT, "t_max: status %d", status);
    CHECK(strstr(err.message, "t_max") != NULL, "message '%s'", err.message);
    CHECK(stats.granule_reached == 0 && !stats.complete, "reached %zu", stats.granule_reached);

    int calls = 0;
    taper_solver_spec_init(&spec);
    spec.monitor = stop_now;
    spec.monitor_data = &calls;
    status = run(chain, &spec, &err, &stats);
    CHECK(status == TAPER_EINTERRUPTED, "monitor: status %d", status);
    CHECK(strstr(err.message, "interrupted") != NULL, "message '%s'", err.message);
    CHECK(stats.granule_reached >= 1 && stats.granule_reached < 39, "reached %zu", stats.granule_reached);

    /* Both methods, windowed or not, with the BDF Newton path. */
    taper_solver_spec_init(&spec);
    spec.method = TAPER_BDF;
    spec.window = 0;
    spec.rtol = 2.3e-15;
    spec.atol = 1e-300;
    status = run(chain, &spec, &err, &stats);
    CHECK(status == TAPER_ESOLVER || status == TAPER_ELIMIT, "bdf: status %d (%s)", status, err.message);
    taper_chain_free(chain);
}

static void invalid_arguments(void)
{
    taper_error err;
    taper_chain_spec cs;
    taper_chain_spec_init(&cs);
    cs.n_granules = 1;
    CHECK(taper_chain_alloc(&cs, &err) == NULL && err.status == TAPER_EINVAL && err.message[0],
          "N = 1: %d '%s'", err.status, err.message);
    taper_chain_spec_init(&cs);
    cs.profile = TAPER_FORWARD_LINEAR;
    cs.s = 0.5;
    cs.n_granules = 10;
    CHECK(taper_chain_alloc(&cs, &err) == NULL && err.status == TAPER_EINVAL, "forward N: %d", err.status);
    taper_chain_spec_init(&cs);
    cs.profile = TAPER_BACKWARD_EXPONENTIAL;
    cs.q = 0.9;
    cs.n_granules = 100000;
    CHECK(taper_chain_alloc(&cs, &err) == NULL && err.status == TAPER_ERANGE, "overflow: %d '%s'",
          err.status, err.message);
    taper_chain_spec_init(&cs);
    cs.profile = TAPER_CUSTOM; /* radii NULL */
    CHECK(taper_chain_alloc(&cs, &err) == NULL && err.status == TAPER_EINVAL, "custom: %d", err.status);
    CHECK(taper_chain_alloc(NULL, NULL) == NULL, "NULL spec, NULL err");
    cs.profile = 99;
    CHECK(taper_chain_alloc(&cs, NULL) == NULL, "bad profile, NULL err");

    taper_chain *chain = chain_of(TAPER_MONODISPERSE, 10, 0.0);
    taper_solver_spec ss;
    taper_solver_spec_init(&ss);
    ss.rtol = -1;
    CHECK(taper_sim_alloc(chain, &ss, &err) == NULL && err.status == TAPER_EINVAL &&
              strstr(err.message, "rtol"), "rtol: '%s'", err.message);
    taper_solver_spec_init(&ss);
    ss.method = 7;
    CHECK(taper_sim_alloc(chain, &ss, &err) == NULL && err.status == TAPER_EINVAL, "method");
    taper_solver_spec_init(&ss);
    ss.last_granule = 11;
    CHECK(taper_sim_alloc(chain, &ss, &err) == NULL && err.status == TAPER_EINVAL, "last_granule");
    CHECK(taper_sim_alloc(NULL, NULL, &err) == NULL && err.status == TAPER_EINVAL, "NULL chain");
    CHECK(taper_sim_run(NULL, &err) == TAPER_EINVAL, "run NULL");
    CHECK(taper_theory_compute(NULL, NULL, NULL, NULL, NULL, &err) == TAPER_EINVAL, "theory NULL");

    taper_sim *sim = taper_sim_alloc(chain, NULL, &err);
    CHECK(sim != NULL, "default spec: '%s'", err.message);
    CHECK(taper_sim_state(sim, NULL, NULL, &err) == TAPER_EINVAL, "state before run");
    CHECK(taper_sim_run(sim, &err) == TAPER_OK, "run: '%s'", err.message);
    CHECK(taper_sim_run(sim, &err) == TAPER_EINVAL && strstr(err.message, "already"), "second run");
    CHECK(taper_sim_observable(sim, -1) == NULL && taper_sim_observable(sim, TAPER_N_OBSERVABLES) == NULL,
          "unknown observable");
    taper_sim_free(sim);
    taper_chain_free(chain);
    taper_chain_free(NULL);
    taper_sim_free(NULL);

    int p = -1;
    CHECK(taper_profile_from_name("no_such_profile", &p) == TAPER_EINVAL, "profile name");
    CHECK(taper_profile_name(42) == NULL, "profile 42");
    CHECK(strcmp(taper_strerror(12345), "unknown status") == 0, "strerror");
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
    CHECK(isnan(taper_asymptotic_exponent(99, 2.5)), "law 99");

    taper_fit_spec fs;
    taper_fit_result fr;
    taper_error err;
    double x[3] = {1, 2, 3}, y[3] = {1, -1, NAN};
    taper_fit_spec_init(&fs, TAPER_FIT_POWER);
    CHECK(taper_fit(&fs, x, y, 3, &fr, &err) == TAPER_EINVAL && err.message[0], "fit: '%s'", err.message);
    CHECK(isnan(fr.param[0]), "fit param after failure");
    taper_fit_spec_init(&fs, TAPER_FIT_DIVERGENCE_C);
    double xs[6] = {1, 1, 1, 1, 1, 1}, ys[6] = {1, 2, 3, 4, 5, 6};
    int status = taper_fit(&fs, xs, ys, 6, &fr, &err);
    CHECK(status == TAPER_EINVAL || status == TAPER_ESOLVER, "degenerate fit: %d", status);
    CHECK(taper_fit(NULL, x, y, 3, &fr, &err) == TAPER_EINVAL, "fit NULL spec");
}

/* Size of an open file (the redirected descriptors). */
static long file_size(FILE *fp)
{
    fflush(fp);
    fseek(fp, 0, SEEK_END);
    return ftell(fp);
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

    invalid_arguments();
    solver_failures();
    domain_errors();

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
    printf("errors: statuses and messages correct, nothing printed, nothing aborted\n");
    return 0;
}
