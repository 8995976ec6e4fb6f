/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sweep_mpi.c -- the runs of a sweep on MPI ranks (sweep_mpi.h).
 *
 * Protocol (MPI_COMM_WORLD, rank 0 the master):
 *   worker -> 0  TAG_REQUEST  a thread of the worker is idle
 *   0 -> worker  TAG_RUN      int64: the run to compute, or -1: stop
 *   worker -> 0  TAG_RESULT   int64 run, int32 status, int32 signal, int32
 *                             + int32 text lengths, then the run's stdout
 *                             and stderr text
 *   worker -> 0  TAG_BYE      int32 signal: all its threads have stopped,
 *                             done with this scene (every rank walks the
 *                             scenes of the command line in step, one
 *                             goodbye each, interrupted or not)
 * `signal` is the stop signal the worker received (interrupt_signal), or 0:
 * a signal to any rank stops the whole sweep, as it stops a serial one.
 *
 * Rank 0 serves these on a thread of its own (sweep_remote.serve), the
 * only one of rank 0 to call MPI while a sweep runs, while its other
 * threads compute runs; it hands runs out in the order of sweep_next, the
 * dearest first, so a slow run starts early wherever a thread is free.  A
 * worker's threads share its MPI calls under a mutex
 * (MPI_THREAD_SERIALIZED): a request and its answer are one locked
 * exchange.
 *
 * Waiting: MPI has no call that sleeps until a message comes (Open MPI's
 * blocking calls spin), so each worker rings rank 0's bell (bell.h)
 * before each message it sends, and rank 0's server sleeps in poll() until
 * one rings.  Rank 0 counts the rings and the messages of each rank: a
 * message rung for but not yet arrived is waited for in short naps.
 * Workers without a bell (no TCP route to rank 0) are polled every
 * millisecond instead; all of them with a bell, rank 0 still looks once a
 * second, a safety net that costs nothing.  The other way, rank 0 rings
 * after each answer, and a worker waits for its answer, and at the end for
 * rank 0 to be done, asleep too. 
 *
 * Results reach rank 0 as files in the shared output directory
 * (granules.tsv, scene.hash) and as the text the run printed; a rank that
 * dies loses its runs in progress, which the same command redoes (resume).
 */
#include "sweep_mpi.h"

#include "bell.h"
#include "run/interrupt.h"
#include "run/run.h"
#include "run/sweep.h"
#include "run/sweep_resume.h"

#include <mpi.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

enum { TAG_REQUEST = 1, TAG_RUN = 2, TAG_RESULT = 3, TAG_BYE = 4 };
enum { MAX_THREADS = 256 };

static int rank, size = 1, active, served;
static int serialized;   /* MPI_THREAD_SERIALIZED or better: threads may call MPI */
static unsigned threads_per_rank = 1;
static int byes;         /* rank 0: workers that said goodbye to this scene */

/* The bells: rank 0 holds bell[r] for each worker r (-1: none), rung[r]
 * its rings, got[r] the messages it sent; a worker holds bell[0]. */
static int *bell;
static unsigned long *rung, *got;
static int bells;        /* rank 0: workers with a bell */

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

/* A result: the run's index (8 bytes), rc, the worker's signal, the
 * lengths of stdout and stderr text (4 each), its CPU seconds (a double),
 * then the texts. */
enum { RESULT_HEAD = 8 + 4 * 4 + 8 };

/* Unpacks a result message into an outcome (texts malloc'd) and the
 * worker's signal. */
static long long unpack(const unsigned char *buf, int len, run_outcome *o, int32_t *sig)
{
    int64_t i;
    int32_t rc, n_out, n_log;
    memset(o, 0, sizeof *o);
    *sig = 0;
    if (len < RESULT_HEAD) return -1;
    memcpy(&i, buf, sizeof i);
    memcpy(&rc, buf + 8, sizeof rc);
    memcpy(sig, buf + 12, sizeof *sig);
    memcpy(&n_out, buf + 16, sizeof n_out);
    memcpy(&n_log, buf + 20, sizeof n_log);
    memcpy(&o->cpu_seconds, buf + 24, sizeof o->cpu_seconds);
    if (n_out < 0 || n_log < 0 || (size_t)len != RESULT_HEAD + (size_t)n_out + (size_t)n_log)
        return -1;
    o->rc = rc;
    if (n_out && (o->out = malloc((size_t)n_out + 1))) {
        memcpy(o->out, buf + RESULT_HEAD, (size_t)n_out);
        o->out[n_out] = '\0';
    }
    if (n_log && (o->log = malloc((size_t)n_log + 1))) {
        memcpy(o->log, buf + RESULT_HEAD + n_out, (size_t)n_log);
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
    got[st->MPI_SOURCE]++;
    int32_t sig = 0;
    if (st->MPI_TAG == TAG_REQUEST) {
        size_t i = sw ? sweep_next(sw) : SIZE_MAX;
        send_run(st->MPI_SOURCE, i == SIZE_MAX ? -1 : (long long)i);
        bell_ring(bell[st->MPI_SOURCE], BELL_MESSAGE);
    } else if (st->MPI_TAG == TAG_RESULT) {
        run_outcome o;
        long long i = unpack(buf, len, &o, &sig);
        if (sw && i >= 0 && (size_t)i < sweep_size(sw))
            sweep_done(sw, (size_t)i, &o);
        else
            run_outcome_free(&o);
    } else if (st->MPI_TAG == TAG_BYE) {
        if (len == (int)sizeof sig) memcpy(&sig, buf, sizeof sig);
        byes++;
    }
    if (sig > 0) interrupt_from_rank(sig, st->MPI_SOURCE);
    free(buf);
}

/* Every message that has come, handled.  1 if one was. */
static int drain(sweep *sw)
{
    int any = 0;
    for (;;) {
        int flag = 0;
        MPI_Status st;
        MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st);
        if (!flag) return any;
        handle(sw, &st);
        any = 1;
    }
}

/* A worker has rung for a message that has not come yet. */
static int owed(void)
{
    for (int r = 1; r < size; r++)
        if (bell[r] >= 0 && rung[r] > got[r]) return 1;
    return 0;
}

static void nap(long ns)
{
    struct timespec t = {0, ns};
    nanosleep(&t, NULL);
}

/* Hands out runs and takes results until every worker has said goodbye
 * to this scene (sw NULL: every request is answered "stop"). */
static void serve(sweep *sw, void *ctx)
{
    (void)ctx;
    served = 1;
    while (byes < size - 1) {
        if (drain(sw)) continue;
        if (owed()) {
            nap(20000); /* on its way: a message follows its ring at once */
        } else {
            /* Some workers without a bell: polled every millisecond. */
            bell_wait(bell, size, bells == size - 1 ? 1000 : 1, rung);
            bells = 0;
            for (int r = 1; r < size; r++) bells += bell[r] >= 0;
        }
    }
}

static sweep_remote remote = {.serve = serve};

const sweep_remote *mpi_remote(void) { return active && size > 1 && rank == 0 ? &remote : NULL; }

void mpi_scene_end(void)
{
    if (!active || rank != 0 || size < 2) return;
    if (!served) serve(NULL, NULL); /* not a sweep, or skipped: the workers' goodbyes */
    served = 0;
    byes = 0;
}

/* ---- the other ranks ------------------------------------------------------------ */

typedef struct worker_ctx {
    sweep *sw;
    pthread_mutex_t lock; /* one MPI exchange at a time */
} worker_ctx;

/* Rings rank 0's bell, then sends (under the worker's lock). */
static void send_to_0(const void *buf, int len, int tag)
{
    bell_ring(bell[0], BELL_MESSAGE);
    MPI_Send(buf, len, MPI_BYTE, 0, tag, MPI_COMM_WORLD);
}

static void drop_bell(void)
{
    close(bell[0]);
    bell[0] = -1;
}

/* Rank 0's answer to this worker's request: asleep until rank 0 rings for
 * it (once per answer, after sending it), then the answer, which follows
 * at once.  Rank 0 may be busy for long (preparing the output directory,
 * writing sweep.tsv before the next scene); a blocking MPI_Recv would spin
 * all that time. */
static int64_t answer(void)
{
    while (bell[0] >= 0) {
        int ring = bell_await(bell[0], 1000);
        if (ring == BELL_MESSAGE) break;
        if (ring < 0) {
            drop_bell();
            break;
        }
        int flag = 0; /* a second without a ring: look all the same */
        MPI_Iprobe(0, TAG_RUN, MPI_COMM_WORLD, &flag, MPI_STATUS_IGNORE);
        if (flag) break;
    }
    int64_t i = -1;
    MPI_Recv(&i, 1, MPI_INT64_T, 0, TAG_RUN, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    return i;
}

static void send_result(worker_ctx *w, size_t i, const run_outcome *o)
{
    int32_t rc = o->rc, sig = interrupt_signal(), n_out = o->out ? (int32_t)strlen(o->out) : 0,
            n_log = o->log ? (int32_t)strlen(o->log) : 0;
    int64_t idx = (int64_t)i;
    size_t len = RESULT_HEAD + (size_t)n_out + (size_t)n_log;
    unsigned char *buf = malloc(len);
    if (!buf) MPI_Abort(MPI_COMM_WORLD, RUN_FAILED);
    memcpy(buf, &idx, sizeof idx);
    memcpy(buf + 8, &rc, sizeof rc);
    memcpy(buf + 12, &sig, sizeof sig);
    memcpy(buf + 16, &n_out, sizeof n_out);
    memcpy(buf + 20, &n_log, sizeof n_log);
    memcpy(buf + 24, &o->cpu_seconds, sizeof o->cpu_seconds);
    if (n_out) memcpy(buf + RESULT_HEAD, o->out, (size_t)n_out);
    if (n_log) memcpy(buf + RESULT_HEAD + n_out, o->log, (size_t)n_log);
    pthread_mutex_lock(&w->lock);
    send_to_0(buf, (int)len, TAG_RESULT);
    pthread_mutex_unlock(&w->lock);
    free(buf);
}

static void *worker_thread(void *arg)
{
    worker_ctx *w = arg;
    /* Interrupted: no more runs asked for (rank 0 hears of the signal
     * with this thread's last result, or with the goodbye). */
    while (!interrupt_signal()) {
        pthread_mutex_lock(&w->lock);
        send_to_0(NULL, 0, TAG_REQUEST);
        int64_t i = answer();
        pthread_mutex_unlock(&w->lock);
        if (i < 0) break;
        run_outcome o;
        sweep_compute(w->sw, (size_t)i, &o);
        send_result(w, (size_t)i, &o);
        run_outcome_free(&o);
    }
    return NULL;
}

static void say_goodbye(void)
{
    int32_t sig = interrupt_signal();
    send_to_0(&sig, (int)sizeof sig, TAG_BYE);
}

int mpi_worker(const scene *sc)
{
    if (sc && scene_cfg(sc)->runs.swept && !interrupt_signal()) {
        worker_ctx w = {.sw = sweep_open(sc)};
        if (!w.sw) MPI_Abort(MPI_COMM_WORLD, RUN_FAILED);
        pthread_mutex_init(&w.lock, NULL);
        long long t = scene_cfg(sc)->output.threads;
        unsigned n = t > 0 ? (unsigned)(t < MAX_THREADS ? t : MAX_THREADS) : threads_per_rank;
        if (!serialized) n = 1; /* only the main thread may call MPI */
        pthread_t tid[MAX_THREADS];
        unsigned started = 0;
        for (; n > 1 && started < n; started++)
            if (pthread_create(&tid[started], NULL, worker_thread, &w) != 0) break;
        if (started == 0) worker_thread(&w);
        for (unsigned k = 0; k < started; k++) pthread_join(tid[k], NULL);
        pthread_mutex_destroy(&w.lock);
        sweep_close(w.sw);
    }
    say_goodbye();
    return interrupt_signal() ? RUN_PARTIAL : RUN_COMPLETE;
}

void mpi_scene_skip(void)
{
    if (!active || size < 2) return;
    if (rank == 0)
        mpi_scene_end();
    else
        say_goodbye();
}

/* ---- start and stop --------------------------------------------------------------- */

/* The name of process pid ("mpirun", "orted", "slurmstepd"), or "". */
static void process_name(long pid, char *name, size_t size_of_name)
{
    char path[64];
    snprintf(path, sizeof path, "/proc/%ld/comm", pid);
    FILE *fp = fopen(path, "r");
    name[0] = '\0';
    if (fp && fgets(name, (int)size_of_name, fp)) name[strcspn(name, "\n")] = '\0';
    if (fp) fclose(fp);
}

/* The bells, set up once for the whole command line: rank 0 listens and
 * broadcasts where, the workers connect; those that cannot are polled. */
static void set_up_bells(void)
{
    bell = malloc((size_t)size * sizeof *bell);
    rung = calloc((size_t)size, sizeof *rung);
    got = calloc((size_t)size, sizeof *got);
    if (!bell || !rung || !got) MPI_Abort(MPI_COMM_WORLD, RUN_FAILED);
    for (int r = 0; r < size; r++) bell[r] = -1;
    bell_address a;
    int listener = -1;
    if (rank == 0) listener = bell_listen(&a);
    int ok = listener >= 0;
    MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
    if (!ok) return;
    MPI_Bcast(&a, (int)sizeof a, MPI_BYTE, 0, MPI_COMM_WORLD);
    /* The workers wait for rank 0's answer longer than rank 0 accepts: a
     * worker answered is one that rings. */
    if (rank == 0)
        bells = bell_accept(listener, &a, size, 5.0, bell);
    else
        bell[0] = bell_connect(&a, rank, 6.0);
}

int mpi_start(int *argc, char ***argv)
{
    if (!launched()) return 0;
    int provided = 0;
    if (MPI_Init_thread(argc, argv, MPI_THREAD_SERIALIZED, &provided) != MPI_SUCCESS) return 0;
    active = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    serialized = provided >= MPI_THREAD_SERIALIZED;
    if (!serialized && size > 1 && rank == 0)
        fprintf(stderr, "taper: this MPI cannot serve threads (MPI_THREAD_SERIALIZED): "
                "one thread per rank\n");
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
    if (!serialized) threads_per_rank = 1;
    remote.ranks = (unsigned)size;
    remote.threads = threads_per_rank;
    remote.main_thread = !serialized;
    /* mpirun (or orted, srun's slurmstepd) stops the ranks with SIGTERM
     * whatever it was sent itself: say so when it comes from there. */
    char name[32];
    long parent = (long)getppid();
    process_name(parent, name, sizeof name);
    interrupt_set_launcher(parent, name[0] ? name : "the MPI launcher");
    if (size > 1) set_up_bells();
    if (rank > 0) {
        /* Rank 0 speaks for the sweep. */
        if (!freopen("/dev/null", "w", stdout) || !freopen("/dev/null", "w", stderr)) {
            /* keep going: at worst a worker's text shows twice */
        }
    }
    return rank;
}

static mpi_link link_state;

mpi_link *mpi_link_get(void)
{
    if (!active || size < 2 || !bell) return NULL;
    link_state = (mpi_link){.rank = rank, .size = size, .threads_per_rank = threads_per_rank,
                            .bell = bell, .rung = rung, .got = got};
    return &link_state;
}

int mpi_stop(int rc)
{
    if (!active) return rc;
    /* MPI_Finalize waits for every rank, polling (Open MPI: 10 000 times a
     * second): the workers wait asleep for rank 0 to be done instead. */
    if (rank == 0)
        for (int r = 1; bell && r < size; r++) bell_ring(bell[r], BELL_FAREWELL);
    else
        while (bell && bell[0] >= 0) {
            int ring = bell_await(bell[0], -1);
            if (ring == BELL_FAREWELL || ring < 0) break;
        }
    MPI_Finalize();
    return rc;
}
