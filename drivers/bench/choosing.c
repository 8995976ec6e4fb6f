/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * choosing.c -- taper-bench --choosing: each method and tolerance on each
 * family of chains of docs/choosing.md, its error and its cost.
 *
 * A case is a chain and the methods worth running on it.  Its reference
 * pass times: taper-reference's long-double integration (reference.h,
 * ~1e-16) where that applies (no options), else the run of the case's
 * reference method at rtol 1e-13, atol 1e-16, cross-checked against the
 * other explicit method at the same tolerances: their difference is the
 * resolution of the errors printed for that case.  Each run: the largest
 * relative pass-time error over granules 1..N-2, the energy error the
 * library reports (the balance E + D = E(0) with damping or drag), the CPU
 * seconds of the run (the median of `reps` where a run takes under a
 * second), steps and right-hand sides.  A run is stopped after cpu_limit
 * seconds of CPU (checked at pulse events) and says how far it got; the
 * reference run gets 5 times that, its cross-check twice.
 */
#include "choosing.h"

#include "reference.h"
#include "taper.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct choosing_case {
    const char *name;   /* the chain, as docs/choosing.md's table names it */
    taper_profile profile;
    size_t n;
    double s, q, exponent;
    double pattern2;    /* decorated: the period (1, pattern2); 0: none  */
    double damping, drag, load;
    int left_wall, right_wall;
    unsigned methods;   /* bit TAPER_ADAMS, TAPER_BDF, TAPER_RK8        */
    int long_double_reference;
    taper_method reference; /* otherwise: this method at rtol 1e-13     */
} choosing_case;

#define M(x) (1u << (x))
#define EXPLICIT (M(TAPER_ADAMS) | M(TAPER_RK8))

static const choosing_case cases[] = {
    {"backward_linear S=0.5 N=400", TAPER_BACKWARD_LINEAR, 400, 0.5, 0, 2.5, 0, 0, 0, 0, 0, 0, EXPLICIT, 1, TAPER_RK8},
    {"backward_exponential q=0.05 N=200", TAPER_BACKWARD_EXPONENTIAL, 200, 0, 0.05, 2.5, 0, 0, 0, 0, 0, 0, EXPLICIT, 1,
     TAPER_RK8},
    {"forward_linear S=0.009 N=100", TAPER_FORWARD_LINEAR, 100, 0.009, 0, 2.5, 0, 0, 0, 0, 0, 0, EXPLICIT, 1, TAPER_RK8},
    {"forward_exponential q=0.05 N=100", TAPER_FORWARD_EXPONENTIAL, 100, 0, 0.05, 2.5, 0, 0, 0, 0, 0, 0, EXPLICIT, 1,
     TAPER_RK8},
    {"monodisperse N=10000", TAPER_MONODISPERSE, 10000, 0, 0, 2.5, 0, 0, 0, 0, 0, 0, EXPLICIT, 1, TAPER_RK8},
    {"monodisperse N=100000", TAPER_MONODISPERSE, 100000, 0, 0, 2.5, 0, 0, 0, 0, 0, 0, EXPLICIT, 0, TAPER_RK8},
    {"dimer 1,0.7 N=1000", TAPER_DECORATED, 1000, 0, 0, 2.5, 0.7, 0, 0, 0, 0, 0, EXPLICIT, 0, TAPER_RK8},
    {"decorated 1,0.1 N=100", TAPER_DECORATED, 100, 0, 0, 2.5, 0.1, 0, 0, 0, 0, 0, EXPLICIT, 0, TAPER_RK8},
    {"monodisperse n=1.5 N=100", TAPER_MONODISPERSE, 100, 0, 0, 1.5, 0, 0, 0, 0, 0, 0, EXPLICIT, 0, TAPER_RK8},
    {"forward_exponential q=0.1 n=1.75 N=80", TAPER_FORWARD_EXPONENTIAL, 80, 0, 0.1, 1.75, 0, 0, 0, 0, 0, 0, EXPLICIT,
     0, TAPER_ADAMS},
    {"monodisperse damping=0.05 N=500", TAPER_MONODISPERSE, 500, 0, 0, 2.5, 0, 0.05, 0, 0, 0, 0, EXPLICIT, 0,
     TAPER_RK8},
    {"monodisperse drag=0.001 N=500", TAPER_MONODISPERSE, 500, 0, 0, 2.5, 0, 0, 0.001, 0, 0, 0, EXPLICIT, 0, TAPER_RK8},
    {"monodisperse load=1 N=500", TAPER_MONODISPERSE, 500, 0, 0, 2.5, 0, 0, 0, 1.0, 0, 0, EXPLICIT, 0, TAPER_RK8},
    {"monodisperse left wall N=500", TAPER_MONODISPERSE, 500, 0, 0, 2.5, 0, 0, 0, 0, 1, 0, EXPLICIT, 0, TAPER_RK8},
    {"monodisperse right wall N=500", TAPER_MONODISPERSE, 500, 0, 0, 2.5, 0, 0, 0, 0, 0, 1, EXPLICIT, 0, TAPER_RK8},
    {"monodisperse drag=100 N=100 (stiff)", TAPER_MONODISPERSE, 100, 0, 0, 2.5, 0, 0, 100, 0, 0, 0,
     EXPLICIT | M(TAPER_BDF), 0, TAPER_BDF},
};

static const double rtols[] = {1e-6, 1e-8, 1e-10, 1e-12};

static double process_cpu(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static taper_chain *case_chain(const choosing_case *c)
{
    taper_error err;
    taper_chain *chain = NULL;
    taper_chain_spec *spec = taper_chain_spec_alloc(&err);
    const double pattern[2] = {1.0, c->pattern2};
    int ok = spec && taper_chain_spec_set_profile(spec, c->profile, &err) == TAPER_OK &&
             taper_chain_spec_set_n_granules(spec, c->n, &err) == TAPER_OK &&
             taper_chain_spec_set_s(spec, c->s, &err) == TAPER_OK &&
             taper_chain_spec_set_q(spec, c->q, &err) == TAPER_OK &&
             taper_chain_spec_set_exponent(spec, c->exponent, &err) == TAPER_OK &&
             (c->pattern2 <= 0 || taper_chain_spec_set_pattern(spec, pattern, 2, &err) == TAPER_OK) &&
             taper_chain_spec_set_damping(spec, c->damping, &err) == TAPER_OK &&
             taper_chain_spec_set_drag(spec, c->drag, &err) == TAPER_OK &&
             taper_chain_spec_set_load(spec, c->load, &err) == TAPER_OK &&
             (!c->left_wall || taper_chain_spec_set_end(spec, TAPER_LEFT, TAPER_END_WALL, 0.0, &err) == TAPER_OK) &&
             (!c->right_wall || taper_chain_spec_set_end(spec, TAPER_RIGHT, TAPER_END_WALL, 0.0, &err) == TAPER_OK);
    if (ok) chain = taper_chain_alloc(spec, &err);
    taper_chain_spec_free(spec);
    if (!chain) fprintf(stderr, "taper-bench: %s: %s\n", c->name, err.message);
    return chain;
}

/* The CPU limit, checked by the monitor at every pulse event. */
typedef struct limit {
    double start, seconds;
    int stopped;
} limit;

static int watch_limit(const taper_progress *p, void *user)
{
    (void)p;
    limit *l = user;
    if (process_cpu() - l->start > l->seconds) l->stopped = 1;
    return l->stopped;
}

typedef struct result {
    double *t_pass;
    double cpu, energy_error, steps, rhs, reached;
    int complete, stopped, failed;
} result;

/* One run of method m at rtol (atol 1e-3 rtol; the library's defaults
 * where rtol is 1e-10: its default atol is 1e-13 too). */
static result run(const taper_chain *chain, taper_method m, double rtol, double cpu_limit)
{
    result r = {.cpu = NAN, .energy_error = NAN, .failed = 1};
    const size_t n = taper_chain_size(chain);
    taper_error err;
    limit l = {.seconds = cpu_limit};
    taper_solver_spec *spec = taper_solver_spec_alloc(&err);
    taper_sim *sim = NULL;
    if (spec && taper_solver_spec_set_method(spec, m, &err) == TAPER_OK &&
        taper_solver_spec_set_rtol(spec, rtol, &err) == TAPER_OK &&
        taper_solver_spec_set_atol(spec, 1e-3 * rtol, &err) == TAPER_OK) {
        taper_solver_spec_set_monitor(spec, watch_limit, &l);
        l.start = process_cpu(); /* the monitor is called from taper_sim_alloc too (the theory of a long chain) */
        sim = taper_sim_alloc(chain, spec, &err);
    }
    taper_solver_spec_free(spec);
    r.t_pass = malloc(n * sizeof *r.t_pass);
    if (!sim || !r.t_pass) {
        fprintf(stderr, "taper-bench: %s\n", sim ? "out of memory" : err.message);
        taper_sim_free(sim);
        return r;
    }
    const taper_status status = taper_sim_run(sim, &err);
    r.cpu = process_cpu() - l.start; /* taper_sim_alloc (the chain's theory) and the run */
    r.stopped = l.stopped;
    r.failed = status != TAPER_OK && !l.stopped;
    if (r.failed) fprintf(stderr, "taper-bench: %s rtol %g: %s\n", taper_method_name(m), rtol, err.message);
    memcpy(r.t_pass, taper_sim_observable(sim, TAPER_T_PASS), n * sizeof *r.t_pass);
    r.energy_error = taper_sim_statistic(sim, TAPER_STAT_ENERGY_ERROR);
    r.steps = taper_sim_statistic(sim, TAPER_STAT_STEPS);
    r.rhs = taper_sim_statistic(sim, TAPER_STAT_RHS_EVALS);
    r.reached = taper_sim_statistic(sim, TAPER_STAT_GRANULE_REACHED);
    r.complete = taper_sim_statistic(sim, TAPER_STAT_COMPLETE) != 0.0;
    taper_sim_free(sim);
    return r;
}

/* Largest relative difference over granules 1..N-2 where both are finite;
 * *missing: granules the reference has and the run lacks. */
static double t_pass_error(const double *x, const double *ref, size_t n, size_t *missing)
{
    double e = 0.0;
    *missing = 0;
    for (size_t k = 0; k + 2 < n; k++) {
        if (!isfinite(ref[k]) || ref[k] == 0.0) continue;
        if (!isfinite(x[k])) {
            ++*missing;
            continue;
        }
        e = fmax(e, fabs(x[k] - ref[k]) / fabs(ref[k]));
    }
    return e;
}

static int cmp(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int taper_bench_choosing(const char *dir, const char *only, int reps, double cpu_limit)
{
    int matched = 0;
    for (size_t ci = 0; ci < sizeof cases / sizeof *cases; ci++) matched += !only || strstr(cases[ci].name, only);
    if (!matched) {
        fprintf(stderr, "taper-bench: --choosing --chain %s: no chain of the set contains it; the set:\n", only);
        for (size_t ci = 0; ci < sizeof cases / sizeof *cases; ci++) fprintf(stderr, "  %s\n", cases[ci].name);
        return 2;
    }
    char path[4096];
    snprintf(path, sizeof path, "%s/choosing.tsv", dir);
    FILE *tsv = fopen(path, "w");
    if (!tsv) {
        fprintf(stderr, "taper-bench: cannot write %s\n", path);
        return 1;
    }
    fprintf(tsv, "chain\treference\treference_resolution\tmethod\trtol\tt_pass_error\tmissing\tenergy_error\t"
                 "cpu_seconds\tsteps\trhs_evals\tgranule_reached\tcomplete\tstopped\n");
    printf("| chain | reference (resolution) | method | rtol | t_pass error | energy error | CPU s | steps | note |\n");
    printf("|---|---|---|---|---|---|---|---|---|\n");
    fflush(stdout);
    int failed = 0;
    for (size_t ci = 0; ci < sizeof cases / sizeof *cases; ci++) {
        const choosing_case *c = &cases[ci];
        if (only && !strstr(c->name, only)) continue;
        taper_chain *chain = case_chain(c);
        if (!chain) {
            failed = 1;
            continue;
        }
        const size_t n = taper_chain_size(chain);
        double *ref = malloc(n * sizeof *ref);
        double resolution = NAN;
        char ref_name[64];
        int ok = ref != NULL;
        if (ok && c->long_double_reference) {
            long double *ld = malloc(n * sizeof *ld);
            ok = ld && taper_reference_pass_times(chain, 1e-17L, ld) == 0;
            for (size_t k = 0; ok && k < n; k++) ref[k] = k + 2 < n ? (double)ld[k] : NAN;
            free(ld);
            snprintf(ref_name, sizeof ref_name, "long double");
        } else if (ok) {
            /* the reference method at 1e-13, and the other explicit one
             * beside it: their difference bounds what is resolved */
            result a = run(chain, c->reference, 1e-13, 5 * cpu_limit);
            const taper_method other = c->reference == TAPER_RK8 ? TAPER_ADAMS : TAPER_RK8;
            ok = !a.failed && a.complete && !a.stopped;
            if (ok) {
                memcpy(ref, a.t_pass, n * sizeof *ref);
                if (c->reference != TAPER_BDF) {
                    result b = run(chain, other, 1e-13, 2 * cpu_limit);
                    size_t miss;
                    if (!b.failed && !b.stopped && b.complete) {
                        resolution = t_pass_error(b.t_pass, ref, n, &miss);
                        if (miss) resolution = NAN; /* not the same events: no resolution */
                    }
                    free(b.t_pass);
                }
            }
            free(a.t_pass);
            snprintf(ref_name, sizeof ref_name, "%s 1e-13", taper_method_name(c->reference));
        }
        if (!ok) {
            fprintf(stderr, "taper-bench: %s: no reference\n", c->name);
            free(ref);
            taper_chain_free(chain);
            failed = 1;
            continue;
        }
        for (int m = 0; m < 3; m++) {
            const taper_method method = m == 0 ? TAPER_ADAMS : m == 1 ? TAPER_RK8 : TAPER_BDF;
            if (!(c->methods & M(method))) continue;
            for (size_t ti = 0; ti < sizeof rtols / sizeof *rtols; ti++) {
                result r = run(chain, method, rtols[ti], cpu_limit);
                double cpu[16] = {r.cpu};
                int runs = 1;
                while (!r.failed && !r.stopped && r.cpu < 1.0 && runs < reps && runs < 16) {
                    result again = run(chain, method, rtols[ti], cpu_limit);
                    cpu[runs++] = again.cpu;
                    free(again.t_pass);
                }
                qsort(cpu, (size_t)runs, sizeof *cpu, cmp);
                const double median = cpu[runs / 2];
                size_t missing = 0;
                const double err = r.failed ? NAN : t_pass_error(r.t_pass, ref, n, &missing);
                char note[160] = "";
                if (r.failed) snprintf(note, sizeof note, "failed");
                else if (r.stopped)
                    snprintf(note, sizeof note, "stopped at %.0f s of CPU, granule %.0f", r.cpu, r.reached);
                else if (missing) snprintf(note, sizeof note, "%zu pass times missing", missing);
                if (!r.stopped && !r.failed && isfinite(resolution) && err < resolution)
                    snprintf(note + strlen(note), sizeof note - strlen(note), "%sbelow the resolution",
                             *note ? "; " : "");
                fprintf(tsv, "%s\t%s\t%.2e\t%s\t%g\t%.2e\t%zu\t%.2e\t%.4f\t%.0f\t%.0f\t%.0f\t%d\t%d\n", c->name,
                        ref_name, resolution, taper_method_name(method), rtols[ti], err, missing, r.energy_error,
                        median, r.steps, r.rhs, r.reached, r.complete, r.stopped);
                fflush(tsv);
                char res[32] = "";
                if (isfinite(resolution)) snprintf(res, sizeof res, " (%.1e)", resolution);
                else if (!c->long_double_reference) snprintf(res, sizeof res, " (no cross-check)");
                printf("| %s | %s%s | %s | %g | %.1e | %.1e | %.3g | %.0f | %s |\n", c->name, ref_name, res,
                       taper_method_name(method), rtols[ti], err, r.energy_error, median, r.steps, note);
                fflush(stdout);
                free(r.t_pass);
            }
        }
        free(ref);
        taper_chain_free(chain);
    }
    fclose(tsv);
    return failed;
}
