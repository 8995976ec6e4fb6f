/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_threads.c -- libtaper has no global mutable state: different chains
 * simulated in several threads at once give results bit-identical to the
 * same runs done one after another in a single thread.
 *
 * Each job is one chain and solver (every profile, both methods, windowed
 * and whole-chain integration); every thread runs a different job, several
 * rounds over, so that all code paths overlap in time.  Each run builds
 * its own settings objects from the job's plain description, so that the
 * setters run concurrently too.  Uses only the public API of the shared
 * library.
 */
#include "taper.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define N_JOBS 8
#define N_THREADS 8
#define ROUNDS 3

typedef struct job {
    taper_profile profile;
    size_t n;
    double s, q;
    taper_method method;
    int window;
    double t_max;
    const char *name;
} job;

typedef struct result {
    taper_status status;
    const char *field;
    size_t n;
    double *obs[TAPER_N_OBSERVABLES];
    double *theory_v, *theory_t;     /* taper_theory_compute  */
    double *sim_theory[TAPER_N_THEORY_QUANTITIES]; /* taper_sim_theory */
    double stats[TAPER_N_STATISTICS];
    char message[TAPER_MESSAGE_SIZE];
} result;

static double custom_radii[40];

static void make_jobs(job *jobs)
{
    static const job def[N_JOBS] = {
        {TAPER_MONODISPERSE, 60, 0, 0, TAPER_ADAMS, 1, 0, "monodisperse/adams/window"},
        {TAPER_BACKWARD_LINEAR, 80, 0.1, 0, TAPER_ADAMS, 1, 0, "backward_linear/adams/window"},
        {TAPER_BACKWARD_LINEAR, 50, 0.2, 0, TAPER_BDF, 0, 0, "backward_linear/bdf"},
        {TAPER_FORWARD_LINEAR, 60, 0.01, 0, TAPER_ADAMS, 0, 0, "forward_linear/adams/whole"},
        {TAPER_BACKWARD_EXPONENTIAL, 70, 0, 0.03, TAPER_ADAMS, 1, 0, "backward_exponential/adams"},
        {TAPER_FORWARD_EXPONENTIAL, 50, 0, 0.02, TAPER_BDF, 0, 0, "forward_exponential/bdf"},
        {TAPER_CUSTOM, 40, 0, 0, TAPER_ADAMS, 1, 0, "custom/adams"},
        /* ends early: the partial path too */
        {TAPER_MONODISPERSE, 30, 0, 0, TAPER_ADAMS, 1, 12.5, "monodisperse/t_max (partial)"},
    };
    for (size_t k = 0; k < 40; k++) custom_radii[k] = 1.0 + 0.3 * sin(0.4 * (double)k);
    custom_radii[0] = 1.0;
    memcpy(jobs, def, sizeof def);
}

static void keep_error(result *r, const taper_error *err)
{
    r->status = err->status;
    r->field = err->field;
    snprintf(r->message, sizeof r->message, "%s", err->message);
}

/* Runs one job from scratch: settings, chain, theory, sim; copies every
 * result. */
static void run_job(const job *j, result *r)
{
    taper_error err;
    memset(r, 0, sizeof *r);
    taper_chain_spec *cs = taper_chain_spec_alloc(&err);
    taper_solver_spec *ss = taper_solver_spec_alloc(&err);
    taper_chain *chain = NULL;
    taper_sim *sim = NULL;
    if (!cs || !ss || taper_chain_spec_set_profile(cs, j->profile, &err) != TAPER_OK ||
        taper_chain_spec_set_n_granules(cs, j->n, &err) != TAPER_OK ||
        taper_chain_spec_set_s(cs, j->s, &err) != TAPER_OK ||
        taper_chain_spec_set_q(cs, j->q, &err) != TAPER_OK ||
        (j->profile == TAPER_CUSTOM &&
         taper_chain_spec_set_radii(cs, custom_radii, j->n, &err) != TAPER_OK) ||
        taper_solver_spec_set_method(ss, j->method, &err) != TAPER_OK ||
        taper_solver_spec_set_window(ss, j->window, &err) != TAPER_OK ||
        taper_solver_spec_set_t_max(ss, j->t_max, &err) != TAPER_OK ||
        !(chain = taper_chain_alloc(cs, &err))) {
        keep_error(r, &err);
        goto done;
    }
    size_t n = r->n = taper_chain_size(chain);
    r->theory_v = malloc(n * sizeof(double));
    r->theory_t = malloc(n * sizeof(double));
    taper_theory_compute(chain, r->theory_v, NULL, NULL, r->theory_t, NULL);
    sim = taper_sim_alloc(chain, ss, &err);
    if (sim) {
        taper_sim_run(sim, &err);
        keep_error(r, &err);
        for (int o = 0; o < TAPER_N_OBSERVABLES; o++) {
            r->obs[o] = malloc(n * sizeof(double));
            memcpy(r->obs[o], taper_sim_observable(sim, (taper_observable)o), n * sizeof(double));
        }
        for (int q = 0; q < TAPER_N_THEORY_QUANTITIES; q++) {
            r->sim_theory[q] = malloc(n * sizeof(double));
            memcpy(r->sim_theory[q], taper_sim_theory(sim, (taper_theory_quantity)q),
                   n * sizeof(double));
        }
        for (int s = 0; s < TAPER_N_STATISTICS; s++)
            r->stats[s] = taper_sim_statistic(sim, (taper_statistic)s);
    } else
        keep_error(r, &err);
done:
    taper_sim_free(sim);
    taper_chain_free(chain);
    taper_solver_spec_free(ss);
    taper_chain_spec_free(cs);
}

static void free_result(result *r)
{
    for (int o = 0; o < TAPER_N_OBSERVABLES; o++) free(r->obs[o]);
    for (int q = 0; q < TAPER_N_THEORY_QUANTITIES; q++) free(r->sim_theory[q]);
    free(r->theory_v);
    free(r->theory_t);
}

static int same_array(const double *a, const double *b, size_t n)
{
    if (!a || !b) return a == b;
    return memcmp(a, b, n * sizeof(double)) == 0; /* bit for bit, NaN included */
}

/* 0 when r equals the reference bit for bit, else prints why. */
static int compare(const char *name, const result *ref, const result *r)
{
    static const char *const obs_names[] = {"t_pass", "t_res", "v_peak", "t_peak", "x_pass"};
    int bad = 0;
    if (r->status != ref->status || r->field != ref->field || r->n != ref->n ||
        strcmp(r->message, ref->message) != 0) {
        fprintf(stderr, "%s: status %d '%s' vs single-threaded %d '%s'\n", name, r->status,
                r->message, ref->status, ref->message);
        return 1;
    }
    for (int o = 0; o < TAPER_N_OBSERVABLES; o++)
        if (!same_array(ref->obs[o], r->obs[o], r->n)) {
            fprintf(stderr, "%s: %s differs from the single-threaded run\n", name, obs_names[o]);
            bad = 1;
        }
    if (!same_array(ref->theory_v, r->theory_v, r->n) || !same_array(ref->theory_t, r->theory_t, r->n)) {
        fprintf(stderr, "%s: theory differs\n", name);
        bad = 1;
    }
    for (int q = 0; q < TAPER_N_THEORY_QUANTITIES; q++)
        if (!same_array(ref->sim_theory[q], r->sim_theory[q], r->n)) {
            fprintf(stderr, "%s: taper_sim_theory column %d differs\n", name, q);
            bad = 1;
        }
    for (int s = 0; s < TAPER_N_STATISTICS; s++)
        if (memcmp(&ref->stats[s], &r->stats[s], sizeof r->stats[s]) != 0) {
            fprintf(stderr, "%s: statistic %s differs (%.17g vs %.17g)\n", name,
                    taper_statistic_name((taper_statistic)s), r->stats[s], ref->stats[s]);
            bad = 1;
        }
    return bad;
}

typedef struct worker {
    pthread_t thread;
    const job *jobs;
    int first;              /* job of round 0; round r runs (first + r) % N_JOBS */
    result results[ROUNDS];
} worker;

static pthread_barrier_t start_line;

static void *work(void *arg)
{
    worker *w = arg;
    pthread_barrier_wait(&start_line); /* all threads start together */
    for (int r = 0; r < ROUNDS; r++) run_job(&w->jobs[(w->first + r) % N_JOBS], &w->results[r]);
    return NULL;
}

int main(void)
{
    static job jobs[N_JOBS];
    static result ref[N_JOBS];
    static worker workers[N_THREADS];
    make_jobs(jobs);

    /* Reference: one after another, in this thread. */
    for (int i = 0; i < N_JOBS; i++) {
        run_job(&jobs[i], &ref[i]);
        taper_status expect = i == N_JOBS - 1 ? TAPER_ELIMIT : TAPER_OK;
        if (ref[i].status != expect) {
            fprintf(stderr, "%s: single-threaded run ended with %d (%s), expected %d\n",
                    jobs[i].name, ref[i].status, ref[i].message, expect);
            return 1;
        }
        /* the sim's own theory is taper_theory_compute's, computed once */
        if (!same_array(ref[i].sim_theory[TAPER_THEORY_V], ref[i].theory_v, ref[i].n) ||
            !same_array(ref[i].sim_theory[TAPER_THEORY_T], ref[i].theory_t, ref[i].n)) {
            fprintf(stderr, "%s: taper_sim_theory differs from taper_theory_compute\n",
                    jobs[i].name);
            return 1;
        }
    }

    pthread_barrier_init(&start_line, NULL, N_THREADS);
    for (int t = 0; t < N_THREADS; t++) {
        workers[t].jobs = jobs;
        workers[t].first = t % N_JOBS;
        if (pthread_create(&workers[t].thread, NULL, work, &workers[t]) != 0) {
            fprintf(stderr, "pthread_create failed\n");
            return 1;
        }
    }
    int fails = 0;
    for (int t = 0; t < N_THREADS; t++) {
        pthread_join(workers[t].thread, NULL);
        for (int r = 0; r < ROUNDS; r++) {
            int i = (workers[t].first + r) % N_JOBS;
            fails += compare(jobs[i].name, &ref[i], &workers[t].results[r]);
            free_result(&workers[t].results[r]);
        }
    }
    pthread_barrier_destroy(&start_line);
    for (int i = 0; i < N_JOBS; i++) free_result(&ref[i]);
    if (fails) {
        fprintf(stderr, "%d concurrent runs differ from the single-threaded ones\n", fails);
        return 1;
    }
    printf("%d threads x %d rounds over %d chains: every result bit-identical to the serial run\n",
           N_THREADS, ROUNDS, N_JOBS);
    return 0;
}
