/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sweep.c -- the runs of a sweep (sweep.h): the order of the steps.
 *
 * Each run is prepared, computed and written on its own (sweep_compute) by
 * a worker thread or an MPI rank, so that a sweep of thousands of long
 * chains holds one chain per worker in memory.  The main thread prints
 * each run's messages in the order of the sweep as soon as the runs before
 * it are done (run/sweep_print.c), sleeping in between until a run is done;
 * other ranks are served by a thread of their own (drivers/taper/sweep_mpi.c).  At the end
 * sweep.tsv and the reports are built from the runs' files
 * (run/sweep_report.c), so that the results do not depend on where a run
 * was computed, or when.
 */
#include "run/sweep.h"

#include "run/interrupt.h"
#include "run/outdir.h"
#include "run/sweep_print.h"
#include "run/sweep_report.h"
#include "run/sweep_resume.h"

#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <unistd.h>

enum { MAX_THREADS = 256 };

/* Seconds the main thread sleeps at most between looks at the sweep: a
 * signal cannot wake it, and the progress line is due every 0.25 s on a
 * terminal. */
static const double LOOK_EVERY = 0.2;

static void *worker(void *arg)
{
    sweep *sw = arg;
    for (size_t i; (i = sweep_next(sw)) != SIZE_MAX;) {
        run_outcome o;
        sweep_compute(sw, i, &o);
        sweep_done(sw, i, &o);
    }
    return NULL;
}

typedef struct server {
    const sweep_remote *remote;
    sweep *sw;
} server;

static void *serve(void *arg)
{
    const server *s = arg;
    s->remote->serve(s->sw, s->remote->ctx);
    return NULL;
}

static unsigned online_cpus(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (unsigned)n : 1u;
}

/* The output directory locked and cleared of other sweeps' files, the runs
 * listed, this part's dealt, and those already on disk found. */
static int prepare(sweep *sw, const sweep_options *opt)
{
    const scene *sc = sw->sc;
    const scene_config *cfg = sw->cfg;
    /* Created and locked: parts of one sweep share the lock (--part). */
    if (outdir_lock(sc, cfg->output.dir, opt->parts > 1) != 0) return RUN_INPUT;
    int rc = sweep_remove_others(sw);
    if (rc != RUN_COMPLETE) return rc;
    for (size_t i = 0; i < sw->n; i++) {
        if (cfg->runs.n_swept == 1) {
            char num[SCENE_REAL_TEXT];
            scene_swept_text(cfg, i, 0, num);
            printf("! sweep %s = %s -> %s\n", scene_swept_name(cfg, 0), num, sw->items[i].dir);
        } else {
            printf("! sweep %s -> %s\n", sw->items[i].name, sw->items[i].dir);
        }
    }
    sweep_deal(sw, opt->part, opt->parts);
    /* The temporaries a killed taper left: in the directory itself when this
     * process holds it alone (parts share it; only the merge writes there),
     * and in the directories of this part's runs. */
    size_t removed = opt->parts > 1 ? 0 : outdir_remove_temporaries(cfg->output.dir);
    removed += sweep_find_reusable(sw);
    if (removed)
        printf("! removed %zu temporary file%s a killed taper left in %s\n", removed,
               removed == 1 ? "" : "s", cfg->output.dir);
    size_t mine = sw->n;
    for (size_t i = 0; i < sw->n; i++) mine -= sw->items[i].elsewhere;
    if (opt->parts > 1)
        printf("! part %zu/%zu: %zu of the %zu runs\n", opt->part, opt->parts, mine, sw->n);
    if (sw->reused)
        printf("! resuming: %zu of %zu runs reused (their results are on disk, from the same "
               "scene), %zu to compute\n", sw->reused, mine, mine - sw->reused);
    fflush(stdout);
    return RUN_COMPLETE;
}

/* Interrupted: what was done is kept for the next attempt. */
static int interrupted(const sweep *sw, const sweep_printer *p)
{
    sweep_print_rest(p, sw);
    size_t complete = 0;
    for (size_t i = 0; i < sw->n; i++)
        complete += sw->items[i].state == SWEEP_DONE && sweep_has_rows(sw->items[i].outcome.rc);
    fprintf(stderr, "%s: interrupted: %zu of %zu runs complete; run the same command to "
            "resume (complete runs are reused)\n", scene_path(sw->sc), complete, sw->n);
    return RUN_PARTIAL;
}

/* A part of a job array: its runs' directories, no sweep.tsv. */
static int part_done(const sweep *sw, const sweep_options *opt)
{
    size_t complete = 0, mine = 0;
    for (size_t i = 0; i < sw->n; i++) {
        if (sw->items[i].elsewhere) continue;
        mine++;
        complete += sweep_has_rows(sw->items[i].outcome.rc);
    }
    printf("! part %zu/%zu done: %zu of its %zu runs complete; once every part is done, "
           "`taper %s` (without --part) merges them: it reuses their runs and writes "
           "sweep.tsv\n", opt->part, opt->parts, complete, mine, scene_path(sw->sc));
    return complete == mine ? RUN_COMPLETE : RUN_SOME_FAILED;
}

static int results(sweep *sw)
{
    int rc = sweep_write_results(sw);
    if (rc == RUN_COMPLETE && sw->failed) {
        fprintf(stderr, "%s: %zu of %zu runs failed (sweep.tsv and runs.tsv name them)\n",
                scene_path(sw->sc), sw->failed, sw->n);
        rc = RUN_SOME_FAILED;
    } else if (rc == RUN_COMPLETE && sw->untrusted) {
        rc = RUN_UNTRUSTED; /* each run's granules.tsv and message say why */
    }
    return rc;
}

int sweep_run(const scene *sc, const sweep_options *opt)
{
    const scene_config *cfg = scene_cfg(sc);
    const sweep_remote *remote = opt->remote;
    sweep *sw = sweep_open(sc);
    int rc = sw ? prepare(sw, opt) : RUN_FAILED;
    if (rc != RUN_COMPLETE) {
        if (!sw) fprintf(stderr, "%s: out of memory\n", scene_path(sc));
        if (remote) remote->serve(NULL, remote->ctx); /* nothing to hand out */
        sweep_close(sw);
        return rc;
    }

    unsigned threads = (unsigned)cfg->output.threads;
    if (threads == 0) threads = remote ? remote->threads : online_cpus();
    if (threads > MAX_THREADS) threads = MAX_THREADS;
    size_t todo = sw->n - sw->reused;
    if (!remote && threads > todo) threads = todo ? (unsigned)todo : 1;
    sweep_printer p;
    sweep_print_start(&p, cfg->output.progress, remote != NULL, remote ? remote->ranks : 1,
                      threads);
    pthread_t tid[MAX_THREADS], server_tid;
    unsigned started = 0;
    for (; started < threads; started++)
        if (pthread_create(&tid[started], NULL, worker, sw) != 0) break;
    server srv = {.remote = remote, .sw = sw};
    int serving = remote && !remote->main_thread &&
                  pthread_create(&server_tid, NULL, serve, &srv) == 0;
    if (remote && !serving) serve(&srv); /* no thread: the other ranks first */
    if (started == 0) worker(sw);        /* no thread: here */

    /* Print runs in order as they finish. */
    do {
        sweep_print_ready(&p, sw);
        sweep_print_progress(&p, sw, 0);
    } while (!sweep_wait(sw, LOOK_EVERY));
    for (unsigned t = 0; t < started; t++) pthread_join(tid[t], NULL);
    if (serving) pthread_join(server_tid, NULL);
    sweep_print_ready(&p, sw);
    sweep_print_progress(&p, sw, 1);
    sweep_print_clear(&p);

    if (sw->done < sw->n || interrupt_signal())
        rc = interrupted(sw, &p);
    else if (opt->parts > 1)
        rc = part_done(sw, opt);
    else
        rc = results(sw);
    sweep_close(sw);
    return rc;
}
