/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * taper-bench -- work-precision study of the pulse-propagation solvers.
 *
 *   taper-bench [--quick] [-o DIR] [--reps R] [--chain NAME]
 *               [--no-scaling | --scaling-only] [--scaling-max N]
 *   taper-bench [--heyoka-python PATH] --single CHAIN METHOD TOL [N [REF]]
 *               (one run, for profiling and paired timings: wall and CPU
 *               seconds; with REF, taper-reference's output for the chain,
 *               err_t over granules 1..N-2 as in the study)
 *   taper-bench --write-chain CHAIN N FILE    (the chain file of
 *               peers/peer_heyoka.py: libtaper's masses and contact factors)
 *   taper-bench --options [-o DIR] [--chain NAME] [--options-max N]
 *               [--options-sizes N,N,...] [--options-limit S]
 *               (the chains with options, below)
 *   taper-bench --goal [--baseline BIN] [--driver BIN] [--goal-n N]
 *               [--reps R] [-o DIR]     (the speed goal, below)
 *   taper-bench --choosing [--chain TEXT] [--reps R] [--options-limit S]
 *               [-o DIR]   (docs/choosing.md's measurements: choosing.c)
 *
 * For a fixed set of chains, runs each method over a sweep of tolerances
 * (step sizes for Verlet), measures the error of t_pass and v_peak against
 * a reference (CVODE Adams, rtol 1e-13, atol 1e-16, cross-checked with
 * rk8pd at the same tolerances) and the cost, and writes into DIR:
 *   work-precision.tsv   one row per (chain, method, tol)
 *   references.tsv       agreement of the two references per chain
 *   orders.tsv           observed order: slope of -log err against log steps
 *   pareto.tsv           the non-dominated (seconds, err_t_pass) points
 *   speed-ratios.tsv     time of each method to reach 1e-6, 1e-8, 1e-9, 1e-10, 1e-12
 *   leaders.tsv          who is fastest to each error, by family (taper's
 *                        CVODE settings, taper's rk8, each peer), and
 *                        leaders.md, the same as a table
 *   scaling.tsv          default settings, N = 10^2 .. --scaling-max (10^4; 10^6 to check flat cost per granule)
 *   work-precision.gp    gnuplot script -> work-precision.png
 * Methods: adams (window, the default order; "default" is the shipped
 * setting of a fresh taper_solver_spec_alloc), adams-nowin (whole chain), adams-q4,
 * adams-q12, bdf-band (banded analytic Jacobian, whole chain), rk8pd, verlet,
 * and ARKODE ERKStep on the whole chain with ARKODE's root finder:
 * erk-verner6 (ARKODE_VERNER_8_5_6, order 6(5)), erk-fehlberg8
 * (ARKODE_FEHLBERG_13_7_8, order 8(7)), erk-dp5 (ARKODE_DORMAND_PRINCE_7_4_5);
 * rk8: taper's method 'rk8' (GSL's rk8pd in the window, max-norm error
 * control with taper's scaled tolerances, src/sim/rk8.c); heyoka: the Taylor
 * integrator heyoka on the whole chain (peers/peer_heyoka.py, run by the
 * Python of --heyoka-python PATH, default python3; skipped with one line
 * where that Python cannot import heyoka).
 * Times are CPU seconds, medians of R repetitions (default 3); heyoka's
 * are the CPU seconds of its integration alone (its compilation in the
 * column compile_seconds).
 *
 * --options: the cost of the chains experimenters build (a damping, a drag,
 * a static load, walls) on the monodisperse chain (or --chain NAME), at the
 * default settings: for each option and N = 2000, 16000 and 10^5 (up to
 * --options-max; --options-sizes N,N,... for others) the CPU time per
 * granule crossed, the steps per granule, the window's mean size (weighted by steps) and its largest, the energy
 * error and whether the run completed; a run stops after S seconds of CPU
 * (--options-limit, default 120), and the row says how far it got.  Then,
 * at N = 500, the window against the whole chain: the largest relative
 * difference of t_pass and v_peak over the granules.  Writes options.tsv and
 * options-agreement.tsv.
 *
 * --goal: the speed goal's figures (issue 38), monodisperse N = 10^6
 * (--goal-n) at the defaults and with method 'rk8', each run by the taper
 * driver as a whole process (this build's, or --driver BIN) on a scene
 * written into DIR: CPU seconds (user + system of the process), steps and
 * right-hand sides per granule and the energy error, from the header of
 * its granules.tsv.  With --baseline BIN (a taper driver of another build,
 * the previous release's) every run is paired with the same run of BIN,
 * the two in turn and the order swapped every round, R rounds (--reps,
 * default 1), and the ratios this/baseline are per round: the machine's
 * speed drifts between rounds, not within a pair.  Prints a table and the
 * largest relative difference of t_pass between the two builds; writes
 * goal.tsv (every run).
 */
#include "choosing.h"
#include "peers/peers.h"
#include "reference.h"
#include "taper.h"

#include <gsl/gsl_errno.h>

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

/* A chain of the study, named by its profile (taper_profile_name: the one
 * list of profile names). */
typedef struct chain_def {
    taper_profile profile;
    size_t n;
    double s, q;
} chain_def;

static const chain_def full_chains[] = {
    {TAPER_MONODISPERSE, 1000, 0, 0},
    {TAPER_BACKWARD_LINEAR, 400, 0.5, 0},
    {TAPER_BACKWARD_EXPONENTIAL, 200, 0, 0.05},
    {TAPER_FORWARD_LINEAR, 100, 0.009, 0},
    {TAPER_FORWARD_EXPONENTIAL, 100, 0, 0.05},
};
static const chain_def quick_chains[] = {
    {TAPER_MONODISPERSE, 100, 0, 0},
    {TAPER_BACKWARD_LINEAR, 60, 0.5, 0},
    {TAPER_FORWARD_EXPONENTIAL, 40, 0, 0.05},
};

static const char *chain_name(const chain_def *c) { return taper_profile_name(c->profile); }

enum { M_ADAMS, M_DEFAULT, M_ADAMS_NOWIN, M_ADAMS_Q4, M_ADAMS_Q12, M_BDF, M_RK8PD, M_VERLET,
       M_ERK_VERNER6, M_ERK_FEHLBERG8, M_ERK_DP5, M_RK8, M_HEYOKA, N_METHODS };
static const char *method_names[N_METHODS] = {"adams", "default", "adams-nowin", "adams-q4",
                                              "adams-q12", "bdf-band", "rk8pd", "verlet",
                                              "erk-verner6", "erk-fehlberg8", "erk-dp5", "rk8",
                                              "heyoka"};

static int is_erk(int m) { return m == M_ERK_VERNER6 || m == M_ERK_FEHLBERG8 || m == M_ERK_DP5; }

/* One run's results. */
typedef struct run {
    size_t n;
    double *t_pass, *v_peak;
    double seconds, cpu, energy_drift;
    double compile_seconds; /* heyoka: building its integrator; NaN for the others */
    long steps, rhs_evals, root_evals, jac_evals;
    taper_status status;
    int complete;
} run;

static double wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The chain of c with n granules (0: c's own); NULL after saying why. */
static taper_chain *make_chain(const chain_def *c, size_t n)
{
    taper_error err;
    taper_chain *chain = NULL;
    taper_chain_spec *spec = taper_chain_spec_alloc(&err);
    if (spec && taper_chain_spec_set_profile(spec, c->profile, &err) == TAPER_OK &&
        taper_chain_spec_set_n_granules(spec, n ? n : c->n, &err) == TAPER_OK &&
        taper_chain_spec_set_s(spec, c->s, &err) == TAPER_OK &&
        taper_chain_spec_set_q(spec, c->q, &err) == TAPER_OK)
        chain = taper_chain_alloc(spec, &err);
    taper_chain_spec_free(spec);
    if (!chain) fprintf(stderr, "taper-bench: chain %s: %s\n", chain_name(c), err.message);
    return chain;
}

/* The solver settings of method m (not a peer) at tolerance tol; NULL
 * after saying why. */
static taper_solver_spec *solver_spec(int m, double tol, long max_steps)
{
    taper_error err;
    taper_solver_spec *spec = taper_solver_spec_alloc(&err);
    int ok = spec != NULL;
    if (ok && m != M_DEFAULT)
        ok = taper_solver_spec_set_rtol(spec, tol, &err) == TAPER_OK &&
             taper_solver_spec_set_atol(spec, tol * 1e-3, &err) == TAPER_OK;
    if (ok && m == M_ADAMS_NOWIN) ok = taper_solver_spec_set_window(spec, 0, &err) == TAPER_OK;
    if (ok && m == M_ADAMS_Q4) ok = taper_solver_spec_set_max_order(spec, 4, &err) == TAPER_OK;
    if (ok && m == M_ADAMS_Q12) ok = taper_solver_spec_set_max_order(spec, 12, &err) == TAPER_OK;
    if (ok && m == M_BDF)
        ok = taper_solver_spec_set_method(spec, TAPER_BDF, &err) == TAPER_OK &&
             taper_solver_spec_set_window(spec, 0, &err) == TAPER_OK;
    if (ok && m == M_RK8) ok = taper_solver_spec_set_method(spec, TAPER_RK8, &err) == TAPER_OK;
    if (ok) ok = taper_solver_spec_set_max_steps(spec, max_steps, &err) == TAPER_OK;
    if (!ok) {
        fprintf(stderr, "taper-bench: %s tol %g: %s\n", method_names[m], tol, err.message);
        taper_solver_spec_free(spec);
        return NULL;
    }
    return spec;
}

static double cpu_seconds(void);

/* ---- heyoka (peers/peer_heyoka.py) --------------------------------------- */
#ifndef TAPER_BENCH_HEYOKA_SCRIPT
#define TAPER_BENCH_HEYOKA_SCRIPT "peer_heyoka.py"
#endif
static const char *heyoka_python = "python3"; /* --heyoka-python PATH */

/* Quoted for sh -c: 'text' with every ' as '\''; 0, or -1 if it does not fit. */
static int sh_quote(char *buf, size_t size, const char *text)
{
    size_t k = 0;
    if (size < 3) return -1;
    buf[k++] = '\'';
    for (const char *c = text; *c; c++) {
        if (*c == '\'') {
            if (k + 4 >= size) return -1;
            memcpy(buf + k, "'\\''", 4);
            k += 4;
        } else {
            if (k + 1 >= size) return -1;
            buf[k++] = *c;
        }
    }
    if (k + 2 > size) return -1;
    buf[k++] = '\'';
    buf[k] = '\0';
    return 0;
}

/* 1 when heyoka_python imports heyoka (asked once); else 0 after one line
 * on stderr saying that heyoka is skipped and why. */
static int heyoka_available(void)
{
    static int known = -1;
    if (known >= 0) return known;
    char py[1200], cmd[1400];
    known = sh_quote(py, sizeof py, heyoka_python) == 0 &&
            snprintf(cmd, sizeof cmd, "%s -c 'import heyoka' >/dev/null 2>&1", py) < (int)sizeof cmd &&
            system(cmd) == 0;
    if (!known)
        fprintf(stderr, "taper-bench: heyoka skipped: %s cannot import heyoka (--heyoka-python PATH names a "
                        "Python that can)\n", heyoka_python);
    return known;
}

/* The chain file of peer_heyoka.py: "m_k r_k" per granule, r_N = nan (the
 * doubles libtaper integrates).  0, or -1 after a message. */
static int write_chain_file(const taper_chain *chain, FILE *f, const char *path)
{
    size_t n = taper_chain_size(chain);
    const double *m = taper_chain_mass(chain), *r = taper_chain_contact(chain);
    fprintf(f, "# m_k r_k (libtaper's masses and contact factors), k = 1..%zu\n", n);
    for (size_t k = 0; k < n; k++)
        if (k + 1 < n) fprintf(f, "%.17g %.17g\n", m[k], r[k]);
        else fprintf(f, "%.17g nan\n", m[k]);
    if (fflush(f) != 0 || ferror(f)) {
        fprintf(stderr, "taper-bench: cannot write %s: %s\n", path, strerror(errno));
        return -1;
    }
    return 0;
}

/* One heyoka run at tolerance tol (its `tol`; the contact threshold is the
 * script's default).  Fills out as run_once does; seconds and cpu are
 * the integration's CPU seconds. */
static taper_status run_heyoka(const taper_chain *chain, double tol, run *out)
{
    size_t n = taper_chain_size(chain);
    const char *tmp = getenv("TMPDIR");
    char path[1024], py[1200], script[1200], file[1200], cmd[4000];
    snprintf(path, sizeof path, "%s/taper-bench-chain-XXXXXX", tmp && *tmp ? tmp : "/tmp");
    int fd = mkstemp(path);
    FILE *f = fd >= 0 ? fdopen(fd, "w") : NULL;
    if (!f) {
        fprintf(stderr, "taper-bench: heyoka: cannot create %s: %s\n", path, strerror(errno));
        if (fd >= 0) close(fd), unlink(path);
        return TAPER_EINVAL;
    }
    int bad = write_chain_file(chain, f, path);
    fclose(f);
    if (!bad && (sh_quote(py, sizeof py, heyoka_python) || sh_quote(script, sizeof script, TAPER_BENCH_HEYOKA_SCRIPT) ||
                 sh_quote(file, sizeof file, path) ||
                 snprintf(cmd, sizeof cmd, "%s %s %s %.17g", py, script, file, tol) >= (int)sizeof cmd)) {
        fprintf(stderr, "taper-bench: heyoka: command too long\n");
        bad = 1;
    }
    FILE *p = bad ? NULL : popen(cmd, "r");
    if (!p) {
        unlink(path);
        return TAPER_EINVAL;
    }
    for (size_t k = 0; k < n; k++) out->t_pass[k] = out->v_peak[k] = NAN;
    char line[512];
    int complete = 0, got = 0;
    while (fgets(line, sizeof line, p)) {
        char key[64];
        double a, b, c;
        size_t k;
        if (sscanf(line, "granule %zu %lf %lf %lf", &k, &a, &b, &c) == 4 && k >= 1 && k <= n) {
            out->t_pass[k - 1] = k < n ? a : NAN;
            out->v_peak[k - 1] = b;
            got++;
        } else if (sscanf(line, "%63s %lf", key, &a) == 2) {
            if (!strcmp(key, "integration_seconds")) out->seconds = out->cpu = a;
            else if (!strcmp(key, "compile_seconds")) out->compile_seconds = a;
            else if (!strcmp(key, "steps")) out->steps = (long)a;
            else if (!strcmp(key, "events")) out->root_evals = (long)a;
            else if (!strcmp(key, "energy_drift")) out->energy_drift = a;
            else if (!strcmp(key, "complete")) complete = a != 0.0;
        }
    }
    int status = pclose(p);
    unlink(path);
    if (status != 0 || (size_t)got != n) {
        fprintf(stderr, "taper-bench: heyoka tol %g: %s failed (exit status %d, %d of %zu granules)\n", tol,
                TAPER_BENCH_HEYOKA_SCRIPT, status, got, n);
        return TAPER_ESOLVER;
    }
    out->complete = complete;
    return TAPER_OK;
}

static void run_free(run *r)
{
    free(r->t_pass);
    free(r->v_peak);
    r->t_pass = r->v_peak = NULL;
}

/* Runs method m once with tolerance tol (rtol, or dt for Verlet); atol = rtol * 1e-3
 * except for the default.  Keeps observables when keep != 0. */
static taper_status run_once(const taper_chain *chain, int m, double tol, long max_steps, run *out)
{
    size_t n = taper_chain_size(chain);
    memset(out, 0, sizeof *out);
    out->n = n;
    out->compile_seconds = NAN;
    out->t_pass = malloc(n * sizeof(double));
    out->v_peak = malloc(n * sizeof(double));
    if (!out->t_pass || !out->v_peak) return TAPER_ENOMEM;
    taper_error err;
    if (m == M_HEYOKA) {
        out->status = run_heyoka(chain, tol, out);
        return out->status;
    }
    double t0 = wall_seconds(), c0 = cpu_seconds();
    if (m == M_RK8PD || m == M_VERLET || is_erk(m)) {
        taper_peer_result r;
        taper_status status;
        if (m == M_RK8PD) status = taper_peer_rk8pd(chain, tol, tol * 1e-3, max_steps, &r, &err);
        else if (m == M_VERLET) status = taper_peer_verlet(chain, tol, max_steps, &r, &err);
        else {
            taper_peer_erk_table table = m == M_ERK_VERNER6   ? TAPER_PEER_ERK_VERNER6
                                         : m == M_ERK_FEHLBERG8 ? TAPER_PEER_ERK_FEHLBERG8
                                                                : TAPER_PEER_ERK_DP5;
            status = taper_peer_arkode(chain, table, tol, tol * 1e-3, max_steps, &r, &err);
        }
        out->seconds = wall_seconds() - t0;
        out->cpu = cpu_seconds() - c0;
        out->status = status;
        if (status != TAPER_OK && status != TAPER_ELIMIT) {
            fprintf(stderr, "taper-bench: %s: %s\n", method_names[m], err.message);
            return status;
        }
        memcpy(out->t_pass, r.t_pass, n * sizeof(double));
        memcpy(out->v_peak, r.v_peak, n * sizeof(double));
        out->energy_drift = r.energy_drift;
        out->steps = r.steps;
        out->rhs_evals = r.rhs_evals;
        out->root_evals = r.event_evals;
        out->complete = r.complete;
        taper_peer_result_free(&r);
        return status;
    }
    taper_solver_spec *spec = solver_spec(m, tol, max_steps);
    if (!spec) return TAPER_EINVAL;
    taper_sim *sim = taper_sim_alloc(chain, spec, &err);
    taper_solver_spec_free(spec); /* the sim keeps a copy */
    if (!sim) {
        fprintf(stderr, "taper-bench: %s: %s\n", method_names[m], err.message);
        return err.status;
    }
    taper_status status = taper_sim_run(sim, &err);
    out->seconds = wall_seconds() - t0;
    out->cpu = cpu_seconds() - c0;
    out->status = status;
    if (status != TAPER_OK)
        fprintf(stderr, "taper-bench: %s tol %g: %s\n", method_names[m], tol, err.message);
    memcpy(out->t_pass, taper_sim_observable(sim, TAPER_T_PASS), n * sizeof(double));
    memcpy(out->v_peak, taper_sim_observable(sim, TAPER_V_PEAK), n * sizeof(double));
    out->energy_drift = taper_sim_statistic(sim, TAPER_STAT_ENERGY_ERROR);
    out->steps = (long)taper_sim_statistic(sim, TAPER_STAT_STEPS);
    out->rhs_evals = (long)taper_sim_statistic(sim, TAPER_STAT_RHS_EVALS);
    out->root_evals = (long)taper_sim_statistic(sim, TAPER_STAT_ROOT_EVALS);
    out->jac_evals = (long)taper_sim_statistic(sim, TAPER_STAT_JAC_EVALS);
    out->complete = taper_sim_statistic(sim, TAPER_STAT_COMPLETE) != 0.0;
    taper_sim_free(sim);
    return status;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median CPU time of reps runs (the process's CPU clock around the run;
 * heyoka's: its integration's, measured by the script); the first run's
 * observables are kept.  CPU time, not wall time: on a shared machine a
 * run's wall time counts the other jobs' time slices, its CPU time only
 * its own, and heyoka's figure is CPU time too. */
static taper_status run_median(const taper_chain *chain, int m, double tol, long max_steps,
                               int reps, run *out, double *t_min, double *t_max)
{
    double times[16];
    if (reps > 16) reps = 16;
    taper_status status = run_once(chain, m, tol, max_steps, out);
    if (status != TAPER_OK && status != TAPER_ELIMIT) return status;
    out->seconds = out->cpu;
    times[0] = out->seconds;
    if (out->seconds > 5.0) reps = 1; /* slow points: one run (far off the front) */
    for (int i = 1; i < reps; i++) {
        run again;
        run_once(chain, m, tol, max_steps, &again);
        times[i] = again.cpu;
        run_free(&again);
    }
    qsort(times, (size_t)reps, sizeof(double), cmp_double);
    out->seconds = times[reps / 2];
    *t_min = times[0];
    *t_max = times[reps - 1];
    return status;
}

/* Max relative difference over granules where the reference is finite;
 * *missing counts those the run lacks. */
static double max_rel_err(const double *x, const double *ref, size_t n, size_t *missing)
{
    double e = 0.0;
    for (size_t k = 0; k < n; k++) {
        if (!isfinite(ref[k]) || ref[k] == 0.0) continue;
        if (!isfinite(x[k])) {
            if (missing) (*missing)++;
            continue;
        }
        double d = fabs(x[k] - ref[k]) / fabs(ref[k]);
        if (d > e) e = d;
    }
    return e;
}

/* ---- sweeps ---------------------------------------------------------- */

typedef struct row {
    int chain, method;
    double tol, err_t, err_v, drift, seconds, t_min, t_max, compile_seconds;
    long steps, rhs, roots, jacs;
    size_t missing;
    int complete;
} row;

typedef struct study {
    const chain_def *chains;
    size_t n_chains;
    int quick, reps;
    row *rows;
    size_t n_rows, cap;
    double ref_agree_t[8], ref_agree_v[8];
    double ld_vs_adams[8], ld_vs_rk8pd[8]; /* the CVODE and rk8pd references against taper-reference */
    unsigned methods; /* bit m: method m runs (--methods; all by default) */
} study;

static int add_row(study *s, const row *r)
{
    if (s->n_rows == s->cap) {
        size_t cap = s->cap ? 2 * s->cap : 256;
        row *p = realloc(s->rows, cap * sizeof *p);
        if (!p) return -1;
        s->rows = p, s->cap = cap;
    }
    s->rows[s->n_rows++] = *r;
    return 0;
}

/* Tolerance sweeps. */
static size_t sweep(int m, int quick, const taper_chain *chain, double *tol)
{
    size_t k = 0;
    if (m == M_DEFAULT) { /* the shipped defaults: the row's tol is their rtol */
        taper_solver_spec *d = taper_solver_spec_alloc(NULL);
        if (d) tol[k++] = taper_solver_spec_rtol(d);
        taper_solver_spec_free(d);
        return k;
    }
    if (m == M_VERLET) {
        /* dt as fractions of the shortest binary-collision time of the chain */
        size_t n = taper_chain_size(chain);
        double *T = malloc(n * sizeof(double));
        double tmin = INFINITY;
        if (T && taper_theory_compute(chain, NULL, NULL, T, NULL, NULL) == TAPER_OK)
            for (size_t i = 0; i + 1 < n; i++)
                if (T[i] < tmin) tmin = T[i];
        free(T);
        if (!isfinite(tmin)) tmin = 1.0;
        static const double frac[] = {0.1, 0.05, 0.02, 0.01, 0.005, 0.002, 0.001, 5e-4};
        for (size_t i = 0; i < sizeof frac / sizeof *frac; i += quick ? 2 : 1) tol[k++] = frac[i] * tmin;
        return k;
    }
    /* Adams with the window and rk8pd down to the tightest rtol taper
     * accepts (the long-double reference resolves their errors there);
     * ARKODE ERK (whole chain, orders 5-8): 1e-11 and below take 10^5-10^6
     * whole-chain steps on N = 1000, so its sweep ends at 1e-11, as the
     * whole-chain CVODE runs do. */
    int tight = m == M_ADAMS || m == M_ADAMS_Q4 || m == M_ADAMS_Q12 || m == M_RK8PD || m == M_RK8 ||
                m == M_HEYOKA;
    double lo = m == M_BDF ? 1e-11 : tight ? 1e-14 : 1e-11;
    double hi = m == M_BDF ? 1e-4 : 1e-5;
    if (m == M_BDF && !quick) lo = 1e-10;
    if (quick) lo = fmax(lo, 1e-11);
    for (double t = hi; t >= lo * 0.99; t /= quick ? 100.0 : 10.0) tol[k++] = t;
    /* CVODE Adams on to the tightest rtol taper accepts: the backward
     * chains need it below 1e-14 (docs/design.md, "Accuracy at tight
     * tolerances") */
    if (m == M_ADAMS && !quick) tol[k++] = 1e-15, tol[k++] = TAPER_RTOL_MIN;
    return k;
}

/* Estimated full-chain work of a Verlet run: steps times granules. */
static double verlet_work(const taper_chain *chain, double dt, double *t_end)
{
    size_t n = taper_chain_size(chain);
    double *t = malloc(n * sizeof(double));
    double te = 1e3;
    if (t && taper_theory_compute(chain, NULL, NULL, NULL, t, NULL) == TAPER_OK && isfinite(t[n - 2]))
        te = t[n - 2] * 1.5;
    free(t);
    if (t_end) *t_end = te;
    return te / dt * (double)n;
}

static int run_chain(study *s, size_t ci)
{
    const chain_def *cd = &s->chains[ci];
    taper_chain *chain = make_chain(cd, 0);
    if (!chain) return -1;
    size_t n = taper_chain_size(chain);
    fprintf(stderr, "== %s N=%zu\n", chain_name(cd), n);

    /* references: pass times from taper-reference (long double, ~1e-16,
     * docs/design.md "Accuracy at tight tolerances") over granules 1..N-2;
     * peak velocities from CVODE Adams at rtol 1e-13, cross-checked with
     * rk8pd */
    run ref, ref2;
    long double *ld = malloc(n * sizeof *ld);
    double *ref_t = malloc(n * sizeof *ref_t);
    double t0 = wall_seconds();
    if (!ld || !ref_t || taper_reference_pass_times(chain, 1e-17L, ld) != 0 ||
        run_once(chain, M_ADAMS, 1e-13, 0, &ref) != TAPER_OK) {
        free(ld), free(ref_t);
        taper_chain_free(chain);
        return -1;
    }
    for (size_t k = 0; k < n; k++) ref_t[k] = k + 2 < n ? (double)ld[k] : NAN;
    free(ld);
    double t_ld = wall_seconds() - t0 - ref.seconds;
    /* run_once sets atol = 1e-3 rtol = 1e-16 */
    double t_ref = ref.seconds;
    taper_status st2 = run_once(chain, M_RK8PD, 1e-13, 0, &ref2);
    size_t miss_t = 0, miss_v = 0;
    s->ref_agree_t[ci] = st2 == TAPER_OK ? max_rel_err(ref2.t_pass, ref.t_pass, n, &miss_t) : NAN;
    s->ref_agree_v[ci] = st2 == TAPER_OK ? max_rel_err(ref2.v_peak, ref.v_peak, n, &miss_v) : NAN;
    s->ld_vs_adams[ci] = max_rel_err(ref.t_pass, ref_t, n, NULL);
    s->ld_vs_rk8pd[ci] = st2 == TAPER_OK ? max_rel_err(ref2.t_pass, ref_t, n, NULL) : NAN;
    fprintf(stderr, "   reference long double: %.2f s; adams 1e-13: %.2f s (t_pass %.2e off); rk8pd 1e-13:"
            " %.2f s (%.2e off); adams and rk8pd agree t_pass %.2e v_peak %.2e (missing %zu %zu)\n",
            t_ld, t_ref, s->ld_vs_adams[ci], ref2.seconds, s->ld_vs_rk8pd[ci], s->ref_agree_t[ci],
            s->ref_agree_v[ci], miss_t, miss_v);
    run_free(&ref2);

    for (int m = 0; m < N_METHODS; m++) {
        if (!(s->methods >> m & 1u)) continue;
        double tol[16];
        size_t nt = sweep(m, s->quick, chain, tol);
        for (size_t i = 0; i < nt; i++) {
            long max_steps = 0;
            if (m == M_VERLET) {
                double t_end, work = verlet_work(chain, tol[i], &t_end);
                if (work > (s->quick ? 3e7 : 4e8)) continue;
                max_steps = (long)(4.0 * t_end / tol[i]) + 1000;
            }
            if (m == M_BDF || m == M_ADAMS_NOWIN || m == M_RK8PD || is_erk(m)) {
                /* whole chain every step: skip what would take minutes */
                max_steps = 2000000;
            }
            run r;
            row w = {.chain = (int)ci, .method = m, .tol = tol[i]};
            taper_status status = run_median(chain, m, tol[i], max_steps, s->reps, &r, &w.t_min, &w.t_max);
            if (status != TAPER_OK && status != TAPER_ELIMIT) {
                run_free(&r);
                continue;
            }
            w.err_t = max_rel_err(r.t_pass, ref_t, n, &w.missing);
            w.err_v = max_rel_err(r.v_peak, ref.v_peak, n, &w.missing);
            w.drift = r.energy_drift;
            w.seconds = r.seconds;
            w.compile_seconds = r.compile_seconds;
            w.steps = r.steps, w.rhs = r.rhs_evals, w.roots = r.root_evals, w.jacs = r.jac_evals;
            w.complete = r.complete && w.missing == 0;
            fprintf(stderr, "   %-12s tol %-9.3g err_t %.2e err_v %.2e drift %.1e  %.4f s  steps %ld%s\n",
                    method_names[m], tol[i], w.err_t, w.err_v, w.drift, w.seconds, w.steps,
                    w.complete ? "" : "  (incomplete)");
            run_free(&r);
            if (add_row(s, &w) != 0) break;
        }
    }
    run_free(&ref);
    free(ref_t);
    taper_chain_free(chain);
    return 0;
}

/* ---- analysis ----------------------------------------------------------- */

/* Time for method m on chain ci to reach error `target` (err_t_pass), by
 * log-log interpolation between the bracketing runs of the sweep.  NaN if
 * no run reaches it; *lower then gets the time of the most accurate run. */
static double time_to_reach(const study *s, int ci, int m, double target, double *best_err,
                            double *best_time)
{
    double t_hit = NAN;
    *best_err = INFINITY, *best_time = NAN;
    const row *prev = NULL;
    for (size_t i = 0; i < s->n_rows; i++) {
        const row *r = &s->rows[i];
        if (r->chain != ci || r->method != m || !r->complete) continue;
        if (r->err_t < *best_err) *best_err = r->err_t, *best_time = r->seconds;
        if (r->err_t <= target && isnan(t_hit)) {
            if (prev && prev->err_t > target && r->err_t > 0) {
                double a = log(prev->err_t), b = log(r->err_t), u = (log(target) - a) / (b - a);
                t_hit = exp(log(prev->seconds) + u * (log(r->seconds) - log(prev->seconds)));
            } else
                t_hit = r->seconds;
        }
        prev = r;
    }
    return t_hit;
}

/* Least-squares slope of -log err against log steps over the runs whose
 * error lies in [floor, 1e-2]: the observed order per step. */
static double observed_order(const study *s, int ci, int m, double floor_err, int *npts)
{
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int k = 0;
    for (size_t i = 0; i < s->n_rows; i++) {
        const row *r = &s->rows[i];
        if (r->chain != ci || r->method != m || !r->complete) continue;
        if (!(r->err_t > floor_err && r->err_t < 1e-2) || r->steps <= 0) continue;
        double x = log((double)r->steps), y = -log(r->err_t);
        sx += x, sy += y, sxx += x * x, sxy += x * y, k++;
    }
    *npts = k;
    if (k < 2) return NAN;
    double d = k * sxx - sx * sx;
    return d > 0 ? (k * sxy - sx * sy) / d : NAN;
}

static FILE *open_out(const char *dir, const char *name)
{
    /* sized to the path: a long -o DIR is never cut */
    size_t size = strlen(dir) + 1 + strlen(name) + 1;
    char *path = malloc(size);
    if (!path) {
        fprintf(stderr, "taper-bench: cannot write %s/%s: out of memory\n", dir, name);
        return NULL;
    }
    snprintf(path, size, "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    if (!f) fprintf(stderr, "taper-bench: cannot write %s: %s\n", path, strerror(errno));
    free(path);
    return f;
}

/* The families of the leaders table: every CVODE setting of taper (the
 * window's Adams at any order, the default, the whole chain, BDF) is one
 * family, "cvode"; taper's rk8 is "rk8"; each peer is its own. */
static const char *family_name(int m)
{
    switch (m) {
    case M_ADAMS: case M_DEFAULT: case M_ADAMS_NOWIN: case M_ADAMS_Q4: case M_ADAMS_Q12: case M_BDF:
        return "cvode";
    default:
        return method_names[m];
    }
}

static int is_taper(int m) { return !strcmp(family_name(m), "cvode") || m == M_RK8; }

/* The fastest complete row of family `fam` on chain ci with err_t_pass at
 * or below `level` (NULL if none); *best_err: the family's smallest error. */
static const row *fastest_at(const study *s, int ci, const char *fam, double level, double *best_err)
{
    const row *best = NULL;
    *best_err = INFINITY;
    for (size_t i = 0; i < s->n_rows; i++) {
        const row *r = &s->rows[i];
        if (r->chain != ci || !r->complete || strcmp(family_name(r->method), fam)) continue;
        if (r->err_t < *best_err) *best_err = r->err_t;
        if (r->err_t <= level && (!best || r->seconds < best->seconds)) best = r;
    }
    return best;
}

/* leaders.tsv and leaders.md: for each chain and error level, each family's
 * fastest complete run at or below it, and its time over the fastest
 * family's.  A family "not reached" ran but never got that low. */
static int write_leaders(const study *s, const char *dir)
{
    static const double levels[] = {1e-6, 1e-8, 1e-9, 1e-10, 1e-12, 1e-14};
    const size_t n_levels = sizeof levels / sizeof *levels;
    const char *families[N_METHODS];
    size_t n_fam = 0;
    for (int m = 0; m < N_METHODS; m++) {
        if (!(s->methods >> m & 1u)) continue;
        const char *f = family_name(m);
        size_t j = 0;
        while (j < n_fam && strcmp(families[j], f)) j++;
        if (j == n_fam) families[n_fam++] = f;
    }
    FILE *tsv = open_out(dir, "leaders.tsv"), *md = tsv ? open_out(dir, "leaders.md") : NULL;
    if (!tsv || !md) {
        if (tsv) fclose(tsv);
        return -1;
    }
    fprintf(tsv, "chain\tn_granules\terror\tfamily\tmethod\ttol\terr_t_pass\tseconds\tover_leader\ttaper_leads\n");
    fprintf(md, "CPU seconds of the fastest run at or below each pass-time error; the others' time over the leader's"
                " (cvode: taper's CVODE settings; rk8: taper's method rk8; the rest are peers).\n\n| chain |");
    for (size_t l = 0; l < n_levels; l++) fprintf(md, " %.0e |", levels[l]);
    fprintf(md, "\n|---|");
    for (size_t l = 0; l < n_levels; l++) fprintf(md, "---|");
    fprintf(md, "\n");
    for (size_t c = 0; c < s->n_chains; c++) {
        fprintf(md, "| %s N=%zu |", chain_name(&s->chains[c]), s->chains[c].n);
        for (size_t l = 0; l < n_levels; l++) {
            const row *best[N_METHODS];
            double best_err[N_METHODS];
            const row *lead = NULL, *lead_taper = NULL, *lead_peer = NULL;
            for (size_t j = 0; j < n_fam; j++) {
                best[j] = fastest_at(s, (int)c, families[j], levels[l], &best_err[j]);
                if (!best[j]) continue;
                if (!lead || best[j]->seconds < lead->seconds) lead = best[j];
                const row **side = is_taper(best[j]->method) ? &lead_taper : &lead_peer;
                if (!*side || best[j]->seconds < (*side)->seconds) *side = best[j];
            }
            /* taper leads: its fastest family beats every peer that got there */
            const int taper_leads = lead_taper && (!lead_peer || lead_taper->seconds < lead_peer->seconds);
            int first = 1;
            if (lead) fprintf(md, " %s %.2g s;", family_name(lead->method), lead->seconds);
            for (size_t j = 0; j < n_fam; j++) {
                if (!best[j]) {
                    if (isfinite(best_err[j])) {
                        fprintf(tsv, "%s\t%zu\t%.0e\t%s\tnot reached\tnan\t%.3e\tnan\tnan\t%d\n",
                                chain_name(&s->chains[c]), s->chains[c].n, levels[l], families[j], best_err[j],
                                taper_leads);
                        fprintf(md, "%s %s not (%.1e)", first ? "" : ",", families[j],
                                best_err[j]);
                        first = 0;
                    }
                    continue;
                }
                const row *r = best[j];
                fprintf(tsv, "%s\t%zu\t%.0e\t%s\t%s\t%.3g\t%.3e\t%.6f\t%.3g\t%d\n", chain_name(&s->chains[c]),
                        s->chains[c].n, levels[l], families[j], method_names[r->method], r->tol, r->err_t, r->seconds,
                        r->seconds / lead->seconds, taper_leads);
                if (r == lead) continue;
                const double ratio = r->seconds / lead->seconds;
                fprintf(md, ratio < 100 ? "%s %s %.2gx" : "%s %s %.0fx", first ? "" : ",", families[j], ratio);
                first = 0;
            }
            if (!lead && first) fprintf(md, " none");
            fprintf(md, " |");
        }
        fprintf(md, "\n");
    }
    fclose(tsv);
    return fclose(md) == 0 ? 0 : -1;
}

static int write_results(const study *s, const char *dir)
{
    FILE *f = open_out(dir, "work-precision.tsv");
    if (!f) return -1;
    fprintf(f, "chain\tmethod\ttol\terr_t_pass\terr_v_peak\tenergy_drift\tseconds\tsteps\trhs_evals"
               "\troot_evals\tjac_evals\tn_granules\tseconds_min\tseconds_max\tmissing\tcomplete\tcompile_seconds\n");
    for (size_t i = 0; i < s->n_rows; i++) {
        const row *r = &s->rows[i];
        fprintf(f, "%s\t%s\t%.3g\t%.3e\t%.3e\t%.3e\t%.6f\t%ld\t%ld\t%ld\t%ld\t%zu\t%.6f\t%.6f\t%zu\t%d\t%.3f\n",
                chain_name(&s->chains[r->chain]), method_names[r->method], r->tol, r->err_t, r->err_v, r->drift,
                r->seconds, r->steps, r->rhs, r->roots, r->jacs, s->chains[r->chain].n, r->t_min,
                r->t_max, r->missing, r->complete, r->compile_seconds);
    }
    fclose(f);

    f = open_out(dir, "references.tsv");
    if (!f) return -1;
    fprintf(f, "chain\tn_granules\tagree_t_pass\tagree_v_peak\tadams_t_pass_error\trk8pd_t_pass_error\n");
    for (size_t c = 0; c < s->n_chains; c++)
        fprintf(f, "%s\t%zu\t%.3e\t%.3e\t%.3e\t%.3e\n", chain_name(&s->chains[c]), s->chains[c].n,
                s->ref_agree_t[c], s->ref_agree_v[c], s->ld_vs_adams[c], s->ld_vs_rk8pd[c]);
    fclose(f);

    f = open_out(dir, "orders.tsv");
    if (!f) return -1;
    fprintf(f, "chain\tmethod\torder_per_step\tpoints\n");
    for (size_t c = 0; c < s->n_chains; c++)
        for (int m = 0; m < N_METHODS; m++) {
            if (m == M_DEFAULT || !(s->methods >> m & 1u)) continue;
            int np;
            double floor_err = 1e-14; /* the long-double reference is good to ~1e-16 */
            double p = observed_order(s, (int)c, m, floor_err, &np);
            fprintf(f, "%s\t%s\t%.2f\t%d\n", chain_name(&s->chains[c]), method_names[m], p, np);
        }
    fclose(f);

    f = open_out(dir, "pareto.tsv");
    if (!f) return -1;
    fprintf(f, "chain\tmethod\ttol\terr_t_pass\tseconds\n");
    for (size_t c = 0; c < s->n_chains; c++) {
        /* sort this chain's complete rows by seconds, keep record-low errors */
        size_t cnt = 0;
        const row **p = malloc(s->n_rows * sizeof *p);
        if (!p) break;
        for (size_t i = 0; i < s->n_rows; i++)
            if (s->rows[i].chain == (int)c && s->rows[i].complete) p[cnt++] = &s->rows[i];
        for (size_t i = 1; i < cnt; i++)
            for (size_t j = i; j > 0 && p[j]->seconds < p[j - 1]->seconds; j--) {
                const row *t = p[j];
                p[j] = p[j - 1], p[j - 1] = t;
            }
        double best = INFINITY;
        for (size_t i = 0; i < cnt; i++)
            if (p[i]->err_t < best) {
                best = p[i]->err_t;
                fprintf(f, "%s\t%s\t%.3g\t%.3e\t%.6f\n", chain_name(&s->chains[c]), method_names[p[i]->method],
                        p[i]->tol, p[i]->err_t, p[i]->seconds);
            }
        free(p);
    }
    fclose(f);

    f = open_out(dir, "speed-ratios.tsv");
    if (!f) return -1;
    fprintf(f, "chain\ttarget\tadams_seconds\tmethod\tseconds\tratio\tnote\n");
    static const double targets[] = {1e-6, 1e-8, 1e-9, 1e-10, 1e-12};
    for (size_t c = 0; c < s->n_chains; c++)
        for (size_t ti = 0; ti < sizeof targets / sizeof *targets; ti++) {
            double be, bt;
            double ta = time_to_reach(s, (int)c, M_ADAMS, targets[ti], &be, &bt);
            for (int m = 0; m < N_METHODS; m++) {
                if (m == M_ADAMS || m == M_DEFAULT || !(s->methods >> m & 1u)) continue;
                double tm = time_to_reach(s, (int)c, m, targets[ti], &be, &bt);
                if (isnan(tm))
                    fprintf(f, "%s\t%.0e\t%.6f\t%s\t>%.6f\t>%.3g\tnot reached (best err %.2e)\n",
                            chain_name(&s->chains[c]), targets[ti], ta, method_names[m], bt, bt / ta, be);
                else
                    fprintf(f, "%s\t%.0e\t%.6f\t%s\t%.6f\t%.3g\t\n", chain_name(&s->chains[c]), targets[ti], ta,
                            method_names[m], tm, tm / ta);
            }
        }
    fclose(f);

    if (write_leaders(s, dir) != 0) return -1;

    f = open_out(dir, "work-precision.gp");
    if (!f) return -1;
    fprintf(f, "# gnuplot work-precision.gp  (run in this directory) -> work-precision.png\n"
               "set terminal pngcairo size 1500,%d font ',9'\n"
               "set output 'work-precision.png'\n"
               "set datafile separator '\\t'\n"
               "set logscale xy\n"
               "set format x '10^{%%T}'\nset format y '10^{%%T}'\n"
               "set xlabel 'CPU time [s] (median)'\nset ylabel 'max rel. error of t_{pass}'\n"
               "set key bottom left font ',8'\nset grid\n"
               "set multiplot layout %zu,3 title 'taper work-precision (pass-time error against CPU time)'\n",
            (int)(480 * ((s->n_chains + 2) / 3)), (s->n_chains + 2) / 3);
    static const char *styles[N_METHODS] = {"lc rgb '#1f77b4' pt 7", "lc rgb '#000000' pt 3 ps 2.5",
                                            "lc rgb '#17becf' pt 5", "lc rgb '#9467bd' pt 9",
                                            "lc rgb '#8c564b' pt 11", "lc rgb '#2ca02c' pt 13",
                                            "lc rgb '#ff7f0e' pt 4", "lc rgb '#d62728' pt 6",
                                            "lc rgb '#e377c2' pt 8", "lc rgb '#bcbd22' pt 10",
                                            "lc rgb '#7f7f7f' pt 12", "lc rgb '#ff7f0e' pt 5 dt 2",
                                            "lc rgb '#8b0000' pt 2"};
    for (size_t c = 0; c < s->n_chains; c++) {
        fprintf(f, "set title '%s N=%zu' noenhanced\nplot ", chain_name(&s->chains[c]), s->chains[c].n);
        for (int m = 0, first = 1; m < N_METHODS; m++) {
            if (!(s->methods >> m & 1u)) continue; /* not run (--methods) */
            fprintf(f, "%s'work-precision.tsv' using (strcol(1) eq '%s' && strcol(2) eq '%s' && $16 == 1 ? "
                       "$7 : NaN):4 with linespoints %s title '%s'",
                    first ? "" : ", \\\n     ", chain_name(&s->chains[c]), method_names[m], styles[m],
                    method_names[m]);
            first = 0;
        }
        fprintf(f, "\n");
    }
    fprintf(f, "unset multiplot\n");
    fclose(f);
    return 0;
}

/* ---- scaling ----------------------------------------------------------- */
static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Peak resident set of the process so far, in MB: the runs go in order of
 * increasing N, so after the largest run it is that run's peak. */
static double peak_rss_mb(void)
{
    struct rusage ru;
    return getrusage(RUSAGE_SELF, &ru) == 0 ? (double)ru.ru_maxrss / 1024.0 : NAN;
}

/* Time per granule against N: the three chains whose cost per
 * granule should be flat.  Wall and CPU time, medians of `reps` runs (runs
 * over 60 s: one).  The backward exponential chain stops where its masses
 * leave double precision (q = 0.05: granule 4490; the chain module says so). */
static int run_scaling(const char *dir, int reps, size_t n_max, int quick)
{
    FILE *f = open_out(dir, "scaling.tsv");
    if (!f) return -1;
    fprintf(f, "chain\tn_granules\tseconds\tseconds_per_granule\tcpu_seconds\tsteps\trhs_evals\t"
               "root_evals\tmax_window\tenergy_error\tpeak_rss_mb\n");
    const chain_def defs[] = {{TAPER_MONODISPERSE, 0, 0, 0},
                              {TAPER_BACKWARD_LINEAR, 0, 0.5, 0},
                              {TAPER_BACKWARD_EXPONENTIAL, 0, 0, 0.05}};
    static const size_t ns[] = {100, 316, 1000, 3162, 4400, 10000, 31623, 100000, 316228, 1000000};
    for (size_t c = 0; c < sizeof defs / sizeof *defs; c++)
        for (size_t i = 0; i < sizeof ns / sizeof *ns && ns[i] <= n_max; i++) {
            if (ns[i] == 4400 && defs[c].profile != TAPER_BACKWARD_EXPONENTIAL) continue;
            taper_chain *chain = make_chain(&defs[c], ns[i]);
            if (!chain) break; /* longer chains of this profile cannot exist either */
            double times[16], cpu[16];
            int r_use = quick ? 1 : reps;
            /* statistics of the last repetition */
            double steps = 0, rhs = 0, roots = 0, max_window = 0, energy_error = 0;
            int ok = 1;
            for (int r = 0; r < r_use && ok; r++) {
                taper_sim *sim = taper_sim_alloc(chain, NULL, NULL);
                double t0 = wall_seconds(), c0 = cpu_seconds();
                ok = sim && taper_sim_run(sim, NULL) == TAPER_OK;
                times[r] = wall_seconds() - t0;
                cpu[r] = cpu_seconds() - c0;
                if (sim) {
                    steps = taper_sim_statistic(sim, TAPER_STAT_STEPS);
                    rhs = taper_sim_statistic(sim, TAPER_STAT_RHS_EVALS);
                    roots = taper_sim_statistic(sim, TAPER_STAT_ROOT_EVALS);
                    max_window = taper_sim_statistic(sim, TAPER_STAT_MAX_WINDOW);
                    energy_error = taper_sim_statistic(sim, TAPER_STAT_ENERGY_ERROR);
                }
                taper_sim_free(sim);
                if (times[r] > 60.0) r_use = r + 1; /* long runs: one repetition */
            }
            taper_chain_free(chain);
            if (!ok) {
                fprintf(stderr, "   scaling %s N=%zu failed\n", chain_name(&defs[c]), ns[i]);
                continue;
            }
            qsort(times, (size_t)r_use, sizeof(double), cmp_double);
            qsort(cpu, (size_t)r_use, sizeof(double), cmp_double);
            /* ru_maxrss only grows: it measures a run of its own only for the
             * first chain (monodisperse, largest N last); NaN after that. */
            double t = times[r_use / 2], tc = cpu[r_use / 2], rss = c == 0 ? peak_rss_mb() : NAN;
            fprintf(f, "%s\t%zu\t%.6f\t%.3e\t%.6f\t%.0f\t%.0f\t%.0f\t%.0f\t%.3e\t%.1f\n",
                    chain_name(&defs[c]), ns[i], t, t / (double)ns[i], tc, steps, rhs, roots,
                    max_window, energy_error, rss);
            fflush(f);
            fprintf(stderr,
                    "   scaling %-20s N=%-7zu %.3f s (cpu %.3f)  %.2e s/granule  steps/granule %.1f  "
                    "max window %.0f  energy error %.1e  peak RSS %.0f MB\n",
                    chain_name(&defs[c]), ns[i], t, tc, t / (double)ns[i], steps / (double)ns[i],
                    max_window, energy_error, rss);
        }
    fclose(f);
    return 0;
}

/* ---- chains with options ------------------------------------------------- */
static const chain_def *find_chain(const chain_def *chains, size_t n_chains, const char *name);

/* An option of the study: a chain setting on top of the profile. */
typedef struct option_def {
    const char *name;
    double damping, drag, load;
    taper_boundary left, right;
} option_def;

static const option_def option_defs[] = {
    {"none", 0, 0, 0, TAPER_END_FREE, TAPER_END_FREE},
    {"damping=0.05", 0.05, 0, 0, TAPER_END_FREE, TAPER_END_FREE},
    {"drag=0.001", 0, 0.001, 0, TAPER_END_FREE, TAPER_END_FREE},
    {"load=1", 0, 0, 1.0, TAPER_END_FREE, TAPER_END_FREE},
    {"left_wall", 0, 0, 0, TAPER_END_WALL, TAPER_END_FREE},
    {"right_wall", 0, 0, 0, TAPER_END_FREE, TAPER_END_WALL},
};

/* The chain of c with n granules and option o; NULL after saying why. */
static taper_chain *make_option_chain(const chain_def *c, const option_def *o, size_t n)
{
    taper_error err;
    taper_chain *chain = NULL;
    taper_chain_spec *spec = taper_chain_spec_alloc(&err);
    if (spec && taper_chain_spec_set_profile(spec, c->profile, &err) == TAPER_OK &&
        taper_chain_spec_set_n_granules(spec, n, &err) == TAPER_OK &&
        taper_chain_spec_set_s(spec, c->s, &err) == TAPER_OK &&
        taper_chain_spec_set_q(spec, c->q, &err) == TAPER_OK &&
        taper_chain_spec_set_damping(spec, o->damping, &err) == TAPER_OK &&
        taper_chain_spec_set_drag(spec, o->drag, &err) == TAPER_OK &&
        taper_chain_spec_set_load(spec, o->load, &err) == TAPER_OK &&
        taper_chain_spec_set_end(spec, TAPER_LEFT, o->left, 0.0, &err) == TAPER_OK &&
        taper_chain_spec_set_end(spec, TAPER_RIGHT, o->right, 0.0, &err) == TAPER_OK)
        chain = taper_chain_alloc(spec, &err);
    taper_chain_spec_free(spec);
    if (!chain) fprintf(stderr, "taper-bench: %s %s N=%zu: %s\n", chain_name(c), o->name, n, err.message);
    return chain;
}

/* The monitor of an options run: the window's size weighted by the steps
 * taken at it (the cost of a step grows with the window), and the CPU
 * limit. */
typedef struct window_watch {
    double cpu_start, cpu_limit;
    double weighted;    /* sum of window size x steps                    */
    long steps;         /* steps at the last call                        */
    int stopped;        /* the CPU limit ended the run                   */
} window_watch;

static int watch_window(const taper_progress *p, void *user)
{
    window_watch *w = user;
    w->weighted += (double)(p->window_hi - p->window_lo + 1) * (double)(p->steps - w->steps);
    w->steps = p->steps;
    if (cpu_seconds() - w->cpu_start > w->cpu_limit) w->stopped = 1;
    return w->stopped;
}

/* One run of the chain at the default settings (window: 0 for the whole
 * chain); NULL when it could not start.  The caller frees the sim. */
static taper_sim *options_run(const taper_chain *chain, int window, window_watch *w, double *cpu)
{
    taper_error err;
    taper_solver_spec *spec = taper_solver_spec_alloc(&err);
    if (!spec || taper_solver_spec_set_window(spec, window, &err) != TAPER_OK) {
        fprintf(stderr, "taper-bench: %s\n", err.message);
        taper_solver_spec_free(spec);
        return NULL;
    }
    if (w) taper_solver_spec_set_monitor(spec, watch_window, w);
    taper_sim *sim = taper_sim_alloc(chain, spec, &err);
    taper_solver_spec_free(spec);
    if (!sim) {
        fprintf(stderr, "taper-bench: %s\n", err.message);
        return NULL;
    }
    const double c0 = cpu_seconds();
    if (w) w->cpu_start = c0;
    taper_status status = taper_sim_run(sim, &err);
    *cpu = cpu_seconds() - c0;
    if (status != TAPER_OK && !(w && w->stopped)) fprintf(stderr, "taper-bench: %s\n", err.message);
    return sim;
}

/* Largest relative difference of observable o between two runs, over the
 * granules where both are finite (NaN in one run only: counted in *odd). */
static double options_difference(const taper_sim *a, const taper_sim *b, taper_observable o, size_t n,
                                 size_t *odd)
{
    const double *x = taper_sim_observable(a, o), *y = taper_sim_observable(b, o);
    double e = 0.0;
    for (size_t k = 0; k < n; k++) {
        if (isnan(x[k]) != isnan(y[k])) ++*odd;
        if (!isfinite(x[k]) || !isfinite(y[k]) || y[k] == 0.0) continue;
        e = fmax(e, fabs(x[k] - y[k]) / fabs(y[k]));
    }
    return e;
}

static int run_options(const char *dir, const char *only, size_t n_max, double cpu_limit, const size_t *sizes,
                       size_t n_sizes)
{
    const chain_def mono = {TAPER_MONODISPERSE, 0, 0, 0};
    const chain_def *c = only ? find_chain(full_chains, sizeof full_chains / sizeof *full_chains, only) : &mono;
    if (!c) {
        fprintf(stderr, "taper-bench: no chain %s in this set\n", only);
        return 2;
    }
    FILE *f = open_out(dir, "options.tsv");
    if (!f) return 1;
    fprintf(f, "chain\toption\tn_granules\tgranules_crossed\tcomplete\tcpu_seconds\tcpu_per_granule\t"
               "steps_per_granule\tmean_window\tmax_window\tenergy_error\n");
    static const size_t default_sizes[] = {2000, 16000, 100000};
    const size_t *ns = n_sizes ? sizes : default_sizes;
    const size_t n_ns = n_sizes ? n_sizes : sizeof default_sizes / sizeof *default_sizes;
    const size_t n_options = sizeof option_defs / sizeof *option_defs;
    for (size_t o = 0; o < n_options; o++)
        for (size_t i = 0; i < n_ns && ns[i] <= n_max; i++) {
            taper_chain *chain = make_option_chain(c, &option_defs[o], ns[i]);
            if (!chain) continue;
            window_watch w = {.cpu_limit = cpu_limit};
            double cpu = 0.0;
            taper_sim *sim = options_run(chain, 1, &w, &cpu);
            taper_chain_free(chain);
            if (!sim) continue;
            const double crossed = taper_sim_statistic(sim, TAPER_STAT_GRANULE_REACHED);
            const double steps = taper_sim_statistic(sim, TAPER_STAT_STEPS);
            const int complete = taper_sim_statistic(sim, TAPER_STAT_COMPLETE) != 0.0;
            /* over the steps up to the last pass (the monitor's calls) */
            const double mean_window = w.steps > 0 ? w.weighted / (double)w.steps : NAN;
            fprintf(f, "%s\t%s\t%zu\t%.0f\t%d\t%.3f\t%.3e\t%.1f\t%.1f\t%.0f\t%.2e\n", chain_name(c),
                    option_defs[o].name, ns[i], crossed, complete, cpu, cpu / fmax(crossed, 1.0),
                    steps / fmax(crossed, 1.0), mean_window, taper_sim_statistic(sim, TAPER_STAT_MAX_WINDOW),
                    taper_sim_statistic(sim, TAPER_STAT_ENERGY_ERROR));
            fflush(f);
            fprintf(stderr, "   options %-13s N=%-6zu %s%8.2f s cpu  %.2e s/granule  %.1f steps/granule  "
                            "window mean %.1f max %.0f  energy error %.1e\n",
                    option_defs[o].name, ns[i], w.stopped ? "STOPPED " : complete ? "" : "partial ", cpu,
                    cpu / fmax(crossed, 1.0), steps / fmax(crossed, 1.0), mean_window,
                    taper_sim_statistic(sim, TAPER_STAT_MAX_WINDOW), taper_sim_statistic(sim, TAPER_STAT_ENERGY_ERROR));
            taper_sim_free(sim);
        }
    fclose(f);
    /* The accuracy contract: window against whole chain at N = 500. */
    f = open_out(dir, "options-agreement.tsv");
    if (!f) return 1;
    fprintf(f, "chain\toption\tn_granules\tt_pass_difference\tv_peak_difference\tnan_in_one_run\t"
               "energy_error_window\tenergy_error_whole\n");
    const size_t n = 500;
    for (size_t o = 0; o < n_options; o++) {
        taper_chain *chain = make_option_chain(c, &option_defs[o], n);
        if (!chain) continue;
        double cpu;
        taper_sim *a = options_run(chain, 1, NULL, &cpu), *b = options_run(chain, 0, NULL, &cpu);
        taper_chain_free(chain);
        if (a && b) {
            size_t odd = 0;
            const double dt = options_difference(a, b, TAPER_T_PASS, n, &odd);
            const double dv = options_difference(a, b, TAPER_V_PEAK, n, &odd);
            fprintf(f, "%s\t%s\t%zu\t%.2e\t%.2e\t%zu\t%.2e\t%.2e\n", chain_name(c), option_defs[o].name, n,
                    dt, dv, odd, taper_sim_statistic(a, TAPER_STAT_ENERGY_ERROR),
                    taper_sim_statistic(b, TAPER_STAT_ENERGY_ERROR));
            fprintf(stderr, "   agreement %-13s N=%zu  t_pass %.1e  v_peak %.1e  (nan in one run: %zu)  "
                            "energy error window %.1e, whole chain %.1e\n",
                    option_defs[o].name, n, dt, dv, odd, taper_sim_statistic(a, TAPER_STAT_ENERGY_ERROR),
                    taper_sim_statistic(b, TAPER_STAT_ENERGY_ERROR));
        }
        taper_sim_free(a);
        taper_sim_free(b);
    }
    fclose(f);
    return 0;
}

/* ---- the speed goal (--goal) ----------------------------------------------- */
#ifndef TAPER_BENCH_DRIVER
#define TAPER_BENCH_DRIVER "taper"
#endif

/* One run of a taper driver on a scene: what the goal reports. */
typedef struct goal_run {
    double cpu;                 /* user + system seconds of the process      */
    double steps, rhs, energy_error, reached;
    int status;                 /* the driver's exit status (-1: not run)    */
} goal_run;

/* The 1-minute load average (Linux's /proc/loadavg), NaN elsewhere. */
static double load_average(void)
{
    double load = NAN;
    FILE *f = fopen("/proc/loadavg", "r");
    if (f) {
        if (fscanf(f, "%lf", &load) != 1) load = NAN;
        fclose(f);
    }
    return load;
}

/* The scene of the goal: monodisperse N, the defaults, `method` unless
 * NULL, every 1000th granule's row written (the header's statistics are
 * the run's either way). */
static int goal_scene(const char *path, size_t n, const char *method)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "taper-bench: cannot write %s: %s\n", path, strerror(errno));
        return -1;
    }
    fprintf(f, "&chain profile = 'monodisperse', n_granules = %zu /\n", n);
    if (method) fprintf(f, "&solver method = '%s' /\n", method);
    fprintf(f, "&output progress = .false., every = %d /\n", n >= 10000 ? 1000 : 1);
    return fclose(f) == 0 ? 0 : -1;
}

/* dir/name into buf; 0, or -1 (after saying so) when it does not fit. */
static int goal_path(char *buf, size_t size, const char *dir, const char *name)
{
    const int len = snprintf(buf, size, "%s/%s", dir, name);
    if (len >= 0 && (size_t)len < size) return 0;
    fprintf(stderr, "taper-bench: path too long: %s/%s\n", dir, name);
    return -1;
}

/* "# name = value" of a granules.tsv header (NaN if absent). */
static double header_value(const char *path, const char *name)
{
    FILE *f = fopen(path, "r");
    double value = NAN;
    char line[512];
    const size_t len = strlen(name);
    for (int row = 0; f && fgets(line, sizeof line, f); row++) {
        if (line[0] != '#' && row > 0) break; /* the column names, the header, then the rows */
        if (!strncmp(line, "# ", 2) && !strncmp(line + 2, name, len) && !strncmp(line + 2 + len, " = ", 3)) {
            value = strtod(line + 5 + len, NULL);
            break;
        }
    }
    if (f) fclose(f);
    return value;
}

/* Runs `driver scene -o outdir` (its output to log), its CPU time from the
 * children's resource usage before and after. */
static goal_run goal_execute(const char *driver, const char *scene, const char *outdir, const char *log)
{
    goal_run r = {.cpu = NAN, .steps = NAN, .rhs = NAN, .energy_error = NAN, .reached = NAN, .status = -1};
    struct rusage before, after;
    getrusage(RUSAGE_CHILDREN, &before);
    pid_t pid = fork();
    if (pid < 0) {
        fprintf(stderr, "taper-bench: fork: %s\n", strerror(errno));
        return r;
    }
    if (pid == 0) {
        int fd = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0666);
        if (fd >= 0) {
            dup2(fd, STDOUT_FILENO);
            dup2(fd, STDERR_FILENO);
            close(fd);
        }
        execl(driver, driver, scene, "-o", outdir, (char *)NULL);
        fprintf(stderr, "taper-bench: cannot run %s: %s\n", driver, strerror(errno));
        _exit(127);
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
    getrusage(RUSAGE_CHILDREN, &after);
    r.cpu = (double)(after.ru_utime.tv_sec - before.ru_utime.tv_sec) +
            1e-6 * (double)(after.ru_utime.tv_usec - before.ru_utime.tv_usec) +
            (double)(after.ru_stime.tv_sec - before.ru_stime.tv_sec) +
            1e-6 * (double)(after.ru_stime.tv_usec - before.ru_stime.tv_usec);
    r.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
    char path[4096];
    if (goal_path(path, sizeof path, outdir, "granules.tsv") != 0) return r;
    r.steps = header_value(path, "steps");
    r.rhs = header_value(path, "rhs_evals");
    r.energy_error = header_value(path, "energy_error");
    r.reached = header_value(path, "granule_reached");
    return r;
}

/* Largest relative difference of t_pass between the rows two runs wrote
 * (the same granules: the same scene). */
static double goal_t_pass_difference(const char *dir_a, const char *dir_b)
{
    char pa[4096], pb[4096], la[4096], lb[4096];
    if (goal_path(pa, sizeof pa, dir_a, "granules.tsv") != 0 || goal_path(pb, sizeof pb, dir_b, "granules.tsv") != 0)
        return NAN;
    FILE *a = fopen(pa, "r"), *b = fopen(pb, "r");
    double worst = NAN;
    int column = -1;
    while (a && b) {
        char *ra = fgets(la, sizeof la, a), *rb = fgets(lb, sizeof lb, b);
        if (!ra || !rb) break;
        if (la[0] == '#' || lb[0] == '#') continue;
        if (column < 0) { /* the column names: t_pass's place */
            int c = 0;
            for (char *tok = strtok(la, "\t\n"); tok; tok = strtok(NULL, "\t\n"), c++)
                if (!strcmp(tok, "t_pass")) column = c;
            if (column < 0) break;
            worst = 0.0;
            continue;
        }
        double x = NAN, y = NAN;
        int c = 0;
        for (char *tok = strtok(la, "\t\n"); tok; tok = strtok(NULL, "\t\n"), c++)
            if (c == column) x = strtod(tok, NULL);
        c = 0;
        for (char *tok = strtok(lb, "\t\n"); tok; tok = strtok(NULL, "\t\n"), c++)
            if (c == column) y = strtod(tok, NULL);
        if (isfinite(x) && isfinite(y) && y != 0.0) worst = fmax(worst, fabs(x - y) / fabs(y));
    }
    if (a) fclose(a);
    if (b) fclose(b);
    return worst;
}

static int compare_doubles(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* "median (min-max)" of n values (sorted in place). */
static void print_spread(FILE *out, double *v, size_t n, const char *format)
{
    qsort(v, n, sizeof *v, compare_doubles);
    const double median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
    fprintf(out, format, median);
    if (n > 1) {
        fputs(" (", out);
        fprintf(out, format, v[0]);
        fputs("-", out);
        fprintf(out, format, v[n - 1]);
        fputs(")", out);
    }
}

static int run_goal(const char *dir, const char *driver, const char *baseline, size_t n, int reps)
{
    static const char *const methods[] = {NULL, "rk8"}; /* NULL: the defaults */
    enum { N_GOAL_METHODS = 2 };
    const int builds = baseline ? 2 : 1;
    const char *binaries[2] = {driver, baseline};
    goal_run *runs = calloc((size_t)reps * N_GOAL_METHODS * 2, sizeof *runs);
    FILE *tsv = open_out(dir, "goal.tsv");
    if (!runs || !tsv) {
        free(runs);
        if (tsv) fclose(tsv);
        return 1;
    }
    char scene[N_GOAL_METHODS][4096];
    for (int m = 0; m < N_GOAL_METHODS; m++) {
        snprintf(scene[m], sizeof scene[m], "%s/goal-%s.nml", dir, methods[m] ? methods[m] : "default");
        if (goal_scene(scene[m], n, methods[m]) != 0) {
            free(runs);
            fclose(tsv);
            return 1;
        }
    }
    fprintf(tsv, "round\tmethod\tbuild\tbinary\tstatus\tcpu_seconds\tsteps_per_granule\trhs_per_granule\t"
                 "energy_error\tgranule_reached\tload_average\n");
    const double load_start = load_average();
    printf("# taper-bench --goal: monodisperse N = %zu, %d round%s, load average %.2f at the start\n", n, reps,
           reps > 1 ? "s" : "", load_start);
    printf("#   this:     %s\n", driver);
    if (baseline) printf("#   baseline: %s\n", baseline);
    fflush(stdout);
    for (int r = 0; r < reps; r++)
        for (int m = 0; m < N_GOAL_METHODS; m++)
            for (int i = 0; i < builds; i++) {
                const int b = builds == 2 && (r % 2) ? 1 - i : i; /* the first of a pair alternates */
                char outdir[4096], log[4096];
                const char *name = methods[m] ? methods[m] : "default";
                snprintf(outdir, sizeof outdir, "%s/goal-%s-%s", dir, name, b ? "baseline" : "this");
                snprintf(log, sizeof log, "%s/goal-%s-%s.log", dir, name, b ? "baseline" : "this");
                goal_run *g = &runs[((size_t)r * N_GOAL_METHODS + (size_t)m) * 2 + (size_t)b];
                *g = goal_execute(binaries[b], scene[m], outdir, log);
                fprintf(tsv, "%d\t%s\t%s\t%s\t%d\t%.3f\t%.2f\t%.2f\t%.3e\t%.0f\t%.2f\n", r + 1, name,
                        b ? "baseline" : "this", binaries[b], g->status, g->cpu, g->steps / (double)n,
                        g->rhs / (double)n, g->energy_error, g->reached, load_average());
                fflush(tsv);
                fprintf(stderr, "   goal round %d %-7s %-8s %8.2f s cpu  %s\n", r + 1, name,
                        b ? "baseline" : "this", g->cpu, g->status ? "FAILED (see the log)" : "");
                if (g->status)
                    fprintf(stderr, "taper-bench: %s %s exited with %d: %s\n", binaries[b], scene[m], g->status, log);
            }
    fclose(tsv);
    printf("\n| method | build | CPU s, median (min-max) | steps/granule | RHS/granule | energy error |\n");
    printf("|---|---|---|---|---|---|\n");
    double *v = malloc((size_t)reps * sizeof *v);
    if (!v) {
        free(runs);
        return 1;
    }
    int failed = 0;
    for (int m = 0; m < N_GOAL_METHODS; m++)
        for (int b = 0; b < builds; b++) {
            const goal_run *last = &runs[((size_t)(reps - 1) * N_GOAL_METHODS + (size_t)m) * 2 + (size_t)b];
            for (int r = 0; r < reps; r++) v[r] = runs[((size_t)r * N_GOAL_METHODS + (size_t)m) * 2 + (size_t)b].cpu;
            printf("| %s | %s | ", methods[m] ? methods[m] : "default", b ? "baseline" : "this");
            print_spread(stdout, v, (size_t)reps, "%.2f");
            printf(" | %.2f | %.2f | %.2e |%s\n", last->steps / (double)n, last->rhs / (double)n,
                   last->energy_error, last->status ? " (failed)" : "");
            failed |= last->status != 0;
        }
    if (baseline) {
        printf("\nthis / baseline, CPU per round, median (min-max):\n");
        for (int m = 0; m < N_GOAL_METHODS; m++) {
            for (int r = 0; r < reps; r++) {
                const goal_run *g = &runs[((size_t)r * N_GOAL_METHODS + (size_t)m) * 2];
                v[r] = g[0].cpu / g[1].cpu;
            }
            const char *name = methods[m] ? methods[m] : "default";
            printf("  %-8s ", name);
            print_spread(stdout, v, (size_t)reps, "%.3f");
            char a[4096], b[4096];
            snprintf(a, sizeof a, "%s/goal-%s-this", dir, name);
            snprintf(b, sizeof b, "%s/goal-%s-baseline", dir, name);
            printf("   t_pass: largest relative difference %.1e (%s)\n", goal_t_pass_difference(a, b),
                   n >= 10000 ? "every 1000th granule" : "every granule");
        }
    }
    printf("\nload average %.2f at the start, %.2f at the end; every run in %s/goal.tsv\n", load_start,
           load_average(), dir);
    free(v);
    free(runs);
    return failed;
}

/* ---- main ------------------------------------------------------------- */
static void usage(FILE *out)
{
    fputs("usage: taper-bench [--quick] [-o DIR] [--reps R] [--chain NAME] [--no-scaling | --scaling-only]\n"
          "                   [--scaling-max N] [--methods NAME,NAME,...] [--heyoka-python PATH]\n"
          "       taper-bench [--heyoka-python PATH] --single CHAIN METHOD TOL [N [REF]]\n"
          "       taper-bench --write-chain CHAIN N FILE   (masses and contacts for peers/peer_heyoka.py)\n"
          "       taper-bench --options [-o DIR] [--chain NAME] [--options-max N] [--options-sizes N,N,...]\n"
          "                   [--options-limit S]\n"
          "       taper-bench --goal [--baseline BIN] [--driver BIN] [--goal-n N] [--reps R] [-o DIR]\n"
          "       taper-bench --choosing [--chain TEXT] [--reps R] [--options-limit S] [-o DIR]\n"
          "Work-precision study (see docs/benchmarks.md).  DIR defaults to bench-out.\n"
          "Methods:",
          out);
    for (int m = 0; m < N_METHODS; m++) fprintf(out, " %s", method_names[m]);
    fputs("\n         (erk-*: ARKODE ERKStep)\nChains:", out);
    for (size_t c = 0; c < sizeof full_chains / sizeof *full_chains; c++)
        fprintf(out, " %s", chain_name(&full_chains[c]));
    fputs("\n", out);
}

/* The chain of the set named `name` (a profile name, any case); NULL if none. */
static const chain_def *find_chain(const chain_def *chains, size_t n_chains, const char *name)
{
    taper_profile profile;
    if (taper_profile_from_name(name, &profile, NULL) != TAPER_OK) return NULL;
    for (size_t c = 0; c < n_chains; c++)
        if (chains[c].profile == profile) return &chains[c];
    return NULL;
}

static int single(int argc, char **argv, int i)
{
    if (i + 3 > argc) {
        usage(stderr);
        return 2;
    }
    const chain_def *cd = find_chain(full_chains, sizeof full_chains / sizeof *full_chains, argv[i]);
    int m = -1;
    for (int k = 0; k < N_METHODS; k++)
        if (!strcmp(argv[i + 1], method_names[k])) m = k;
    if (!cd || m < 0) {
        usage(stderr);
        return 2;
    }
    double tol = atof(argv[i + 2]);
    size_t n = i + 3 < argc ? (size_t)atol(argv[i + 3]) : 0;
    const char *ref_path = i + 4 < argc ? argv[i + 4] : NULL;
    if (m == M_HEYOKA && !heyoka_available()) return 77;
    taper_chain *chain = make_chain(cd, n);
    if (!chain) return 1;
    n = taper_chain_size(chain);
    /* REF: taper-reference's output for this chain, "k t_pass" per line */
    double *ref = NULL;
    if (ref_path) {
        FILE *f = fopen(ref_path, "r");
        ref = malloc(n * sizeof *ref);
        if (!f || !ref) {
            fprintf(stderr, "taper-bench: cannot read %s: %s\n", ref_path, f ? "out of memory" : strerror(errno));
            if (f) fclose(f);
            free(ref);
            taper_chain_free(chain);
            return 2;
        }
        for (size_t k = 0; k < n; k++) ref[k] = NAN;
        size_t k, line = 0, got = 0;
        double t;
        char text[256];
        int bad = 0;
        while (!bad && fgets(text, sizeof text, f)) {
            line++;
            if (text[0] == '#') continue; /* the header of tests/unit/reference/ files */
            bad = sscanf(text, "%zu %lf", &k, &t) != 2 || k < 1 || k + 1 > n;
            if (!bad) ref[k - 1] = k + 1 < n ? t : NAN, got++; /* granules 1..N-2, as the study */
        }
        fclose(f);
        if (bad || got != n - 1) {
            fprintf(stderr, "taper-bench: %s:%zu: not taper-reference's output for N = %zu\n", ref_path,
                    bad ? line : line + 1, n);
            free(ref);
            taper_chain_free(chain);
            return 2;
        }
    }
    run r;
    taper_status status = run_once(chain, m, tol, 0, &r);
    printf("%s N=%zu %s tol %g: %.4f s cpu %.4f s steps %ld rhs %ld roots %ld jac %ld drift %.2e t_pass(N-1) %.15g",
           chain_name(cd), n, method_names[m], tol, r.seconds, r.cpu, r.steps, r.rhs_evals, r.root_evals,
           r.jac_evals, r.energy_drift, r.t_pass[n - 2]);
    if (m == M_HEYOKA) printf(" compile %.3f s", r.compile_seconds);
    if (ref) {
        size_t missing = 0;
        printf(" err_t %.3e missing %zu", max_rel_err(r.t_pass, ref, n, &missing), missing);
    }
    printf("%s\n", r.complete ? "" : " (incomplete)");
    free(ref);
    run_free(&r);
    taper_chain_free(chain);
    return status == TAPER_OK ? 0 : 1;
}

int main(int argc, char **argv)
{
    const char *dir = "bench-out";
    int quick = 0, reps = 3, scaling = 1;
    const char *only = NULL; /* --chain NAME: just that chain of the set */
    unsigned methods = (1u << N_METHODS) - 1;
    size_t scaling_max = 10000, options_max = 100000;
    size_t options_sizes[16], n_options_sizes = 0; /* --options-sizes N,N,...: instead of 2000, 16000, 1e5 */
    int options = 0, goal = 0, choosing = 0, reps_given = 0;
    double options_limit = 120.0;
    int options_limit_given = 0;
    const char *baseline = NULL, *driver = TAPER_BENCH_DRIVER;
    size_t goal_n = 1000000;
    gsl_set_error_handler_off();
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--quick")) quick = 1;
        else if (!strcmp(argv[i], "-o") && i + 1 < argc) dir = argv[++i];
        else if (!strcmp(argv[i], "--reps") && i + 1 < argc) reps = atoi(argv[++i]), reps_given = 1;
        else if (!strcmp(argv[i], "--no-scaling")) scaling = 0;
        else if (!strcmp(argv[i], "--scaling-only")) scaling = 2;
        else if (!strcmp(argv[i], "--chain") && i + 1 < argc) only = argv[++i];
        else if (!strcmp(argv[i], "--scaling-max") && i + 1 < argc) scaling_max = (size_t)atol(argv[++i]);
        else if (!strcmp(argv[i], "--single")) return single(argc, argv, i + 1);
        else if (!strcmp(argv[i], "--heyoka-python") && i + 1 < argc) heyoka_python = argv[++i];
        else if (!strcmp(argv[i], "--write-chain") && i + 3 < argc) {
            const chain_def *cd = find_chain(full_chains, sizeof full_chains / sizeof *full_chains, argv[i + 1]);
            if (!cd) {
                usage(stderr);
                return 2;
            }
            taper_chain *chain = make_chain(cd, (size_t)atol(argv[i + 2]));
            FILE *f = chain ? fopen(argv[i + 3], "w") : NULL;
            if (chain && !f) fprintf(stderr, "taper-bench: cannot write %s: %s\n", argv[i + 3], strerror(errno));
            int bad = !f || write_chain_file(chain, f, argv[i + 3]) != 0;
            if (f && fclose(f) != 0) bad = 1;
            taper_chain_free(chain);
            return bad;
        }
        else if (!strcmp(argv[i], "--methods") && i + 1 < argc) {
            methods = 0;
            for (char *list = argv[++i], *name; (name = strtok(list, ",")); list = NULL) {
                int m = 0;
                while (m < N_METHODS && strcmp(name, method_names[m])) m++;
                if (m == N_METHODS) {
                    fprintf(stderr, "taper-bench: no method %s\n", name);
                    return 2;
                }
                methods |= 1u << m;
            }
        }
        else if (!strcmp(argv[i], "--options")) options = 1;
        else if (!strcmp(argv[i], "--goal")) goal = 1;
        else if (!strcmp(argv[i], "--choosing")) choosing = 1;
        else if (!strcmp(argv[i], "--baseline") && i + 1 < argc) baseline = argv[++i];
        else if (!strcmp(argv[i], "--driver") && i + 1 < argc) driver = argv[++i];
        else if (!strcmp(argv[i], "--goal-n") && i + 1 < argc) goal_n = (size_t)atol(argv[++i]);
        else if (!strcmp(argv[i], "--options-max") && i + 1 < argc) options_max = (size_t)atol(argv[++i]);
        else if (!strcmp(argv[i], "--options-sizes") && i + 1 < argc) {
            n_options_sizes = 0;
            for (char *list = argv[++i], *item; (item = strtok(list, ",")) && n_options_sizes < 16; list = NULL)
                if ((options_sizes[n_options_sizes++] = (size_t)atol(item)) < 3) {
                    fprintf(stderr, "taper-bench: --options-sizes: %s is not a chain of 3 or more granules\n", item);
                    return 2;
                }
        }
        else if (!strcmp(argv[i], "--options-limit") && i + 1 < argc)
            options_limit = atof(argv[++i]), options_limit_given = 1;
        else {
            usage(!strcmp(argv[i], "--help") ? stdout : stderr);
            return !strcmp(argv[i], "--help") ? 0 : 2;
        }
    }
    if (reps < 1) reps = 1;
    if (mkdir(dir, 0777) != 0 && errno != EEXIST) {
        fprintf(stderr, "taper-bench: cannot create %s: %s\n", dir, strerror(errno));
        return 2;
    }
    if (goal) {
        if (goal_n < 3) {
            fprintf(stderr, "taper-bench: --goal-n needs at least 3 granules\n");
            return 2;
        }
        return run_goal(dir, driver, baseline, goal_n, reps_given ? reps : 1);
    }
    if (choosing) /* a run over half a minute is off any front: 30 s unless --options-limit */
        return taper_bench_choosing(dir, only, reps, options_limit_given ? options_limit : 30.0);
    if ((methods >> M_HEYOKA & 1u) && !heyoka_available()) methods &= ~(1u << M_HEYOKA);
    if (options) {
        double t0 = wall_seconds();
        int status = run_options(dir, only, options_max, options_limit, options_sizes, n_options_sizes);
        if (!status) fprintf(stderr, "taper-bench: %.1f s; results in %s/options.tsv, options-agreement.tsv\n",
                             wall_seconds() - t0, dir);
        return status;
    }
    study s = {.quick = quick, .reps = reps, .methods = methods};
    s.chains = quick ? quick_chains : full_chains;
    s.n_chains = quick ? sizeof quick_chains / sizeof *quick_chains : sizeof full_chains / sizeof *full_chains;
    if (only) {
        const chain_def *c = find_chain(s.chains, s.n_chains, only);
        if (!c) {
            fprintf(stderr, "taper-bench: no chain %s in this set\n", only);
            return 2;
        }
        s.chains = c, s.n_chains = 1;
    }
    double t0 = wall_seconds();
    size_t n_chains = s.n_chains;
    for (size_t c = 0; c < n_chains && scaling != 2; c++) {
        s.n_chains = c + 1; /* the files describe the chains done so far */
        run_chain(&s, c);
        if (write_results(&s, dir) != 0) return 1; /* after every chain: partial results survive */
    }
    if (scaling) run_scaling(dir, reps, quick ? 1000 : scaling_max, quick);
    free(s.rows);
    fprintf(stderr, "taper-bench: %.1f s; results in %s/ (gnuplot work-precision.gp there)\n",
            wall_seconds() - t0, dir);
    return 0;
}
