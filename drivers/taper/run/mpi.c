/*
 * mpi.c -- the runs of a sweep on MPI ranks (mpi.h).
 *
 * Protocol (MPI_COMM_WORLD, rank 0 the master):
 *   worker -> 0  TAG_REQUEST  a thread of the worker is idle
 *   0 -> worker  TAG_RUN      int64: the run to compute, or -1: stop
 *   worker -> 0  TAG_RESULT   int64 run, int32 status, int32 + int32 text
 *                             lengths, then the run's stdout and stderr text
 *   worker -> 0  TAG_BYE      all its threads have stopped: done with this
 *                             scene (every rank reads the scenes of the
 *                             command line in turn, one goodbye each)
 * Rank 0 serves these from its main thread without blocking (sweep.c polls
 * it every millisecond) while its own threads compute runs; it hands runs
 * out in the order of sweep_next, the dearest first, so a slow run starts
 * early wherever a thread is free.  A worker's threads share its MPI calls
 * under a mutex (MPI_THREAD_SERIALIZED): a request and its answer are one
 * locked exchange.  Results reach rank 0 as files in the shared output
 * directory (granules.tsv, scene.hash) and as the text the run printed; a
 * rank that dies loses its runs in progress, which the same command
 * redoes (resume).
 */
#include "run/mpi.h"

#include "run/run.h"
#include "run/sweep.h"

#include <mpi.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

enum { TAG_REQUEST = 1, TAG_RUN = 2, TAG_RESULT = 3, TAG_BYE = 4 };

static int rank, size = 1, active, finished;
static unsigned threads_per_rank = 1;
static int byes; /* rank 0: workers that said goodbye to this scene */

/* Launched by an MPI launcher: Open MPI, MPICH/Hydra, PMIx, Slurm's PMI. */
static int launched(void)
{
    static const char *const vars[] = {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK",
                                       "MPI_LOCALNRANKS", "PMI_RANK"};
    for (size_t i = 0; i < sizeof vars / sizeof vars[0]; i++)
        if (getenv(vars[i])) return 1;
    return 0;
}

int mpi_rank(void) { return rank; }

/* ---- rank 0 ------------------------------------------------------------------ */

static void send_run(int dest, long long i)
{
    int64_t v = i;
    MPI_Send(&v, 1, MPI_INT64_T, dest, TAG_RUN, MPI_COMM_WORLD);
}

/* Unpacks a result message into an outcome (texts malloc'd). */
static long long unpack(const unsigned char *buf, int len, run_outcome *o)
{
    int64_t i;
    int32_t rc, n_out, n_log;
    const size_t head = sizeof i + 3 * sizeof rc;
    memset(o, 0, sizeof *o);
    if (len < (int)head) return -1;
    memcpy(&i, buf, sizeof i);
    memcpy(&rc, buf + 8, sizeof rc);
    memcpy(&n_out, buf + 12, sizeof n_out);
    memcpy(&n_log, buf + 16, sizeof n_log);
    if (n_out < 0 || n_log < 0 || (size_t)len != head + (size_t)n_out + (size_t)n_log) return -1;
    o->rc = rc;
    if (n_out && (o->out = malloc((size_t)n_out + 1))) {
        memcpy(o->out, buf + head, (size_t)n_out);
        o->out[n_out] = '\0';
    }
    if (n_log && (o->log = malloc((size_t)n_log + 1))) {
        memcpy(o->log, buf + head + n_out, (size_t)n_log);
        o->log[n_log] = '\0';
    }
    return i;
}

/* One message from a worker (probed: st). */
static void handle(sweep *sw, const MPI_Status *st)
{
    int len = 0;
    MPI_Get_count(st, MPI_BYTE, &len);
    unsigned char *buf = malloc(len > 0 ? (size_t)len : 1);
    if (!buf) MPI_Abort(MPI_COMM_WORLD, RUN_FAILED);
    MPI_Recv(buf, len, MPI_BYTE, st->MPI_SOURCE, st->MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (st->MPI_TAG == TAG_REQUEST) {
        size_t i = sw ? sweep_next(sw) : SIZE_MAX;
        send_run(st->MPI_SOURCE, i == SIZE_MAX ? -1 : (long long)i);
    } else if (st->MPI_TAG == TAG_RESULT) {
        run_outcome o;
        long long i = unpack(buf, len, &o);
        if (sw && i >= 0 && (size_t)i < sweep_size(sw))
            sweep_done(sw, (size_t)i, &o);
        else
            run_outcome_free(&o);
    } else if (st->MPI_TAG == TAG_BYE) {
        byes++;
    }
    free(buf);
}

static void serve(sweep *sw, void *ctx)
{
    (void)ctx;
    for (;;) {
        int flag = 0;
        MPI_Status st;
        MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st);
        if (!flag) return;
        handle(sw, &st);
    }
}

/* Nothing more to hand out: every request is answered "stop" until every
 * worker has said goodbye. */
static void finish(sweep *sw, void *ctx)
{
    (void)ctx;
    finished = 1;
    while (byes < size - 1) {
        MPI_Status st;
        MPI_Probe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &st);
        handle(sw, &st);
    }
}

static sweep_remote remote = {.serve = serve, .finish = finish};

/* ---- the other ranks ------------------------------------------------------------ */

typedef struct worker_ctx {
    sweep *sw;
    pthread_mutex_t lock; /* one MPI exchange at a time */
} worker_ctx;

static void send_result(worker_ctx *w, size_t i, const run_outcome *o)
{
    int32_t rc = o->rc, n_out = o->out ? (int32_t)strlen(o->out) : 0,
            n_log = o->log ? (int32_t)strlen(o->log) : 0;
    int64_t idx = (int64_t)i;
    size_t len = sizeof idx + 3 * sizeof rc + (size_t)n_out + (size_t)n_log;
    unsigned char *buf = malloc(len);
    if (!buf) MPI_Abort(MPI_COMM_WORLD, RUN_FAILED);
    memcpy(buf, &idx, sizeof idx);
    memcpy(buf + 8, &rc, sizeof rc);
    memcpy(buf + 12, &n_out, sizeof n_out);
    memcpy(buf + 16, &n_log, sizeof n_log);
    if (n_out) memcpy(buf + 20, o->out, (size_t)n_out);
    if (n_log) memcpy(buf + 20 + n_out, o->log, (size_t)n_log);
    pthread_mutex_lock(&w->lock);
    MPI_Send(buf, (int)len, MPI_BYTE, 0, TAG_RESULT, MPI_COMM_WORLD);
    pthread_mutex_unlock(&w->lock);
    free(buf);
}

static void *worker_thread(void *arg)
{
    worker_ctx *w = arg;
    for (;;) {
        int64_t i = -1;
        char none = 0;
        pthread_mutex_lock(&w->lock);
        MPI_Send(&none, 0, MPI_BYTE, 0, TAG_REQUEST, MPI_COMM_WORLD);
        MPI_Recv(&i, 1, MPI_INT64_T, 0, TAG_RUN, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        pthread_mutex_unlock(&w->lock);
        if (i < 0) return NULL;
        run_outcome o;
        sweep_compute(w->sw, (size_t)i, &o);
        send_result(w, (size_t)i, &o);
        run_outcome_free(&o);
    }
}

int mpi_worker(const scene *sc)
{
    int rc = RUN_COMPLETE;
    if (sc && scene_cfg(sc)->runs.swept) {
        worker_ctx w = {.sw = sweep_open(sc)};
        if (!w.sw) MPI_Abort(MPI_COMM_WORLD, RUN_FAILED);
        pthread_mutex_init(&w.lock, NULL);
        long long t = scene_cfg(sc)->output.threads;
        unsigned n = t > 0 ? (unsigned)(t < 256 ? t : 256) : threads_per_rank;
        pthread_t tid[256];
        unsigned started = 0;
        for (; started < n; started++)
            if (pthread_create(&tid[started], NULL, worker_thread, &w) != 0) break;
        if (started == 0) worker_thread(&w);
        for (unsigned k = 0; k < started; k++) pthread_join(tid[k], NULL);
        pthread_mutex_destroy(&w.lock);
        sweep_close(w.sw);
    } else if (!sc) {
        rc = RUN_INPUT;
    }
    char none = 0;
    MPI_Send(&none, 0, MPI_BYTE, 0, TAG_BYE, MPI_COMM_WORLD);
    return rc;
}

/* ---- start and stop --------------------------------------------------------------- */

int mpi_start(int *argc, char ***argv)
{
    if (!launched()) return 0;
    int provided = 0;
    if (MPI_Init_thread(argc, argv, MPI_THREAD_SERIALIZED, &provided) != MPI_SUCCESS) return 0;
    active = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    if (provided < MPI_THREAD_SERIALIZED && size > 1) {
        if (rank == 0)
            fprintf(stderr, "taper: this MPI cannot serve threads (MPI_THREAD_SERIALIZED): "
                    "one thread per rank\n");
    }
    /* &output threads = 0: the cores of the node shared by its ranks. */
    MPI_Comm node;
    int local = 1;
    if (MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank, MPI_INFO_NULL, &node) ==
        MPI_SUCCESS) {
        MPI_Comm_size(node, &local);
        MPI_Comm_free(&node);
    }
    long cpus = sysconf(_SC_NPROCESSORS_ONLN);
    threads_per_rank = cpus > local ? (unsigned)(cpus / local) : 1u;
    if (provided < MPI_THREAD_SERIALIZED) threads_per_rank = 1;
    if (size > 1 && rank == 0) {
        remote.ranks = (unsigned)size;
        remote.threads = threads_per_rank;
        sweep_set_remote(&remote);
    }
    if (rank > 0) {
        /* Rank 0 speaks for the sweep. */
        if (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr)) {
            /* keep going: at worst a worker's text shows twice */
        }
    }
    return rank;
}

void mpi_scene_end(void)
{
    if (!active || rank != 0 || size < 2) return;
    if (!finished) finish(NULL, NULL); /* not a sweep: the workers' goodbyes */
    finished = 0;
    byes = 0;
}

int mpi_stop(int rc)
{
    if (!active) return rc;
    sweep_set_remote(NULL);
    MPI_Finalize();
    return rc;
}
