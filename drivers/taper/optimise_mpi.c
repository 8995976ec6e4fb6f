/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * optimise_mpi.c -- the runs of a calibration or a design on MPI ranks
 * (optimise_mpi.h).
 *
 * Protocol (MPI_COMM_WORLD, rank 0 the optimiser; tags apart from the
 * sweep's, sweep_mpi.c):
 *   worker -> 0  TAG_READY   int32: the threads it computes on (0: it could
 *                            not build the problem), once per scene
 *   0 -> worker  TAG_POINT   int64 index in the batch, then the point's
 *                            values (doubles)
 *   worker -> 0  TAG_RESULT  int64 index, int32 status, int32 signal, int32
 *                            simulated values, int32 message length, double
 *                            objective, then the values and the message
 *   0 -> worker  TAG_END     the scene is over (then the sweep's goodbye)
 * Rank 0 keeps at most as many points at a worker as it has threads, and
 * hands out the next point of the batch as a result comes back, while its
 * own threads take points from the same batch; a batch ends when every
 * point handed out is back, so the optimiser sees the batch as it would
 * without MPI.  A worker's `signal` (interrupt_signal) stops rank 0 too.
 *
 * Only the main thread of a rank calls MPI (rank 0's is the optimiser's, in
 * opt_evaluate_batch; a worker's serves its computing threads), so this
 * needs no more than MPI_THREAD_FUNNELED.  Waiting is asleep, as in a
 * sweep: each message is announced by a ring of the bells (bell.h), and a
 * rank's computing threads wake its main thread through a pipe put in the
 * rank's own slot of the bells, so one poll() waits for both.
 */
#include "optimise_mpi.h"

#include "bell.h"
#include "optimise/evaluate.h"
#include "optimise/optimise.h"
#include "run/interrupt.h"
#include "run/run.h"
#include "sweep_mpi.h"

#include <fcntl.h>
#include <math.h>
#include <mpi.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

enum { TAG_READY = 21, TAG_POINT = 22, TAG_RESULT = 23, TAG_END = 24 };
enum { MAX_THREADS = 256 };
/* A ring whose message has not come after this long was not for us (a
 * ring left over by another exchange): stop waiting for it. */
#define OWED_NS 50000000L

static void nap(long ns)
{
    struct timespec t = {0, ns};
    nanosleep(&t, NULL);
}

static double seconds_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* A pipe to wake this rank's main thread: its read end in the rank's own
 * slot of the bells while it waits.  0, or -1. */
static int wake_open(int fd[2])
{
    if (pipe(fd) != 0) return -1;
    for (int k = 0; k < 2; k++) {
        fcntl(fd[k], F_SETFL, fcntl(fd[k], F_GETFL) | O_NONBLOCK);
        fcntl(fd[k], F_SETFD, FD_CLOEXEC);
    }
    return 0;
}

static void wake(int fd)
{
    char c = 1;
    (void)!write(fd, &c, 1); /* a full pipe wakes the reader all the same */
}

/* ---- results as bytes ------------------------------------------------------------- */

enum { RESULT_HEAD = 8 + 4 * 4 + 8 };

static unsigned char *pack_result(int64_t i, const opt_result *r, int *len)
{
    int32_t status = r->status, sig = interrupt_signal(), n_model = (int32_t)r->n_model,
            n_msg = r->message ? (int32_t)strlen(r->message) : 0;
    size_t size = RESULT_HEAD + (size_t)n_model * sizeof(double) + (size_t)n_msg;
    unsigned char *buf = malloc(size);
    if (!buf) return NULL;
    memcpy(buf, &i, 8);
    memcpy(buf + 8, &status, 4);
    memcpy(buf + 12, &sig, 4);
    memcpy(buf + 16, &n_model, 4);
    memcpy(buf + 20, &n_msg, 4);
    memcpy(buf + 24, &r->objective, 8);
    if (n_model) memcpy(buf + RESULT_HEAD, r->model, (size_t)n_model * sizeof(double));
    if (n_msg) memcpy(buf + RESULT_HEAD + (size_t)n_model * sizeof(double), r->message, (size_t)n_msg);
    *len = (int)size;
    return buf;
}

/* The index of the result in buf (-1: malformed), into *r and the
 * worker's signal. */
static int64_t unpack_result(const unsigned char *buf, int len, opt_result *r, int32_t *sig)
{
    int64_t i;
    int32_t status, n_model, n_msg;
    memset(r, 0, sizeof *r);
    *sig = 0;
    if (len < RESULT_HEAD) return -1;
    memcpy(&i, buf, 8);
    memcpy(&status, buf + 8, 4);
    memcpy(sig, buf + 12, 4);
    memcpy(&n_model, buf + 16, 4);
    memcpy(&n_msg, buf + 20, 4);
    memcpy(&r->objective, buf + 24, 8);
    if (n_model < 0 || n_msg < 0 ||
        (size_t)len != RESULT_HEAD + (size_t)n_model * sizeof(double) + (size_t)n_msg)
        return -1;
    r->status = status;
    if (n_model) {
        if (!(r->model = malloc((size_t)n_model * sizeof *r->model))) MPI_Abort(MPI_COMM_WORLD, RUN_FAILED);
        memcpy(r->model, buf + RESULT_HEAD, (size_t)n_model * sizeof(double));
        r->n_model = (size_t)n_model;
    }
    if (n_msg) {
        if (!(r->message = malloc((size_t)n_msg + 1))) MPI_Abort(MPI_COMM_WORLD, RUN_FAILED);
        memcpy(r->message, buf + RESULT_HEAD + (size_t)n_model * sizeof(double), (size_t)n_msg);
        r->message[n_msg] = '\0';
    }
    return i;
}

/* A point not run: the optimisation was stopped before it was handed out
 * (as opt_evaluate says of a run stopped at once). */
static void not_run(opt_result *r)
{
    memset(r, 0, sizeof *r);
    r->status = OPT_RUN_INTERRUPTED;
    r->objective = NAN;
    r->message = malloc(sizeof "interrupted");
    if (r->message) memcpy(r->message, "interrupted", sizeof "interrupted");
}

/* ---- rank 0 --------------------------------------------------------------------------- */

static int *slots;           /* per worker: threads it announced (this scene) */
static size_t *runs_on;      /* per rank: runs it made (this scene)           */

typedef struct batch0 {
    const opt_problem *pb;
    size_t n, p;
    const double *values;
    opt_result *r;
    pthread_mutex_t lock;
    size_t next;             /* the next point to hand out                    */
    size_t done;             /* points handed out and back                    */
    int wake;                /* the pipe's write end                          */
} batch0;

static int stopping(const opt_problem *pb) { return pb->stop && pb->stop(pb->stop_user); }

/* The next point to hand out, or SIZE_MAX (none, or stopped). */
static size_t take(batch0 *b)
{
    size_t i = SIZE_MAX;
    pthread_mutex_lock(&b->lock);
    if (b->next < b->n && !stopping(b->pb)) i = b->next++;
    pthread_mutex_unlock(&b->lock);
    return i;
}

static void *local_thread(void *arg)
{
    batch0 *b = arg;
    size_t i;
    while ((i = take(b)) != SIZE_MAX) {
        opt_evaluate(b->pb, b->values + i * b->p, &b->r[i]);
        pthread_mutex_lock(&b->lock);
        b->done++;
        runs_on[0]++;
        pthread_mutex_unlock(&b->lock);
        wake(b->wake);
    }
    return NULL;
}

/* One message from a worker (probed: st). */
static void handle(batch0 *b, const mpi_link *L, int *sent, const MPI_Status *st)
{
    int len = 0, src = st->MPI_SOURCE;
    MPI_Get_count(st, MPI_BYTE, &len);
    unsigned char *buf = malloc(len > 0 ? (size_t)len : 1);
    if (!buf) MPI_Abort(MPI_COMM_WORLD, RUN_FAILED);
    MPI_Recv(buf, len, MPI_BYTE, src, st->MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    L->got[src]++;
    if (st->MPI_TAG == TAG_READY) {
        int32_t threads = 0;
        if (len == (int)sizeof threads) memcpy(&threads, buf, sizeof threads);
        slots[src] = threads > 0 ? threads : 0;
    } else if (b) {
        opt_result r;
        int32_t sig = 0;
        int64_t i = unpack_result(buf, len, &r, &sig);
        if (i >= 0 && (size_t)i < b->n) {
            b->r[i] = r;
            pthread_mutex_lock(&b->lock);
            b->done++;
            pthread_mutex_unlock(&b->lock);
            sent[src]--;
            runs_on[src]++;
        } else {
            opt_result_free(&r);
        }
        if (sig > 0) interrupt_from_rank(sig, src);
    }
    free(buf);
}

/* Every message of ours that has come, handled (a sweep's goodbye, from a
 * rank that skipped this scene after a signal, is left to mpi_scene_end). */
static int drain(batch0 *b, const mpi_link *L, int *sent)
{
    static const int tags[] = {TAG_READY, TAG_RESULT};
    int any = 0;
    for (int again = 1; again;) {
        again = 0;
        for (size_t t = 0; t < sizeof tags / sizeof tags[0]; t++) {
            int flag = 0;
            MPI_Status st;
            MPI_Iprobe(MPI_ANY_SOURCE, tags[t], MPI_COMM_WORLD, &flag, &st);
            if (!flag) continue;
            handle(b, L, sent, &st);
            any = again = 1;
        }
    }
    return any;
}

static void send_point(batch0 *b, const mpi_link *L, int dest, size_t i)
{
    size_t len = 8 + b->p * sizeof(double);
    unsigned char *buf = malloc(len);
    if (!buf) MPI_Abort(MPI_COMM_WORLD, RUN_FAILED);
    int64_t idx = (int64_t)i;
    memcpy(buf, &idx, 8);
    memcpy(buf + 8, b->values + i * b->p, b->p * sizeof(double));
    MPI_Send(buf, (int)len, MPI_BYTE, dest, TAG_POINT, MPI_COMM_WORLD);
    bell_ring(L->bell[dest], BELL_MESSAGE);
    free(buf);
}

/* A worker has rung for a message that has not come yet. */
static int owed(const mpi_link *L)
{
    for (int r = 1; r < L->size; r++)
        if (L->bell[r] >= 0 && L->rung[r] > L->got[r]) return 1;
    return 0;
}

static void run_batch(const opt_problem *pb, size_t n, const double *values, opt_result *r,
                      void *user)
{
    mpi_link *L = user;
    batch0 b = {.pb = pb, .n = n, .p = pb->space->n, .values = values, .r = r, .wake = -1};
    int fd[2] = {-1, -1};
    int *sent = calloc((size_t)L->size, sizeof *sent);
    if (!sent) MPI_Abort(MPI_COMM_WORLD, RUN_FAILED);
    pthread_mutex_init(&b.lock, NULL);
    if (wake_open(fd) == 0) {
        b.wake = fd[1];
        L->bell[0] = fd[0]; /* rank 0's own slot: its threads' wake-up */
    }
    unsigned want = pb->threads ? pb->threads : L->threads_per_rank;
    if (want > MAX_THREADS) want = MAX_THREADS;
    if (want > n) want = (unsigned)n;
    pthread_t tid[MAX_THREADS];
    unsigned started = 0;
    for (; started < want; started++)
        if (pthread_create(&tid[started], NULL, local_thread, &b) != 0) break;
    double owed_since = -1;
    for (;;) {
        if (drain(&b, L, sent)) owed_since = -1;
        int workers = 0;
        for (int w = 1; w < L->size; w++) {
            workers += slots[w] > 0;
            while (sent[w] < slots[w]) {
                size_t i = take(&b);
                if (i == SIZE_MAX) break;
                send_point(&b, L, w, i);
                sent[w]++;
            }
        }
        pthread_mutex_lock(&b.lock);
        int over = b.done == b.next && (b.next == b.n || stopping(pb));
        pthread_mutex_unlock(&b.lock);
        if (over) break;
        if (started == 0 && !workers) { /* no thread, no worker yet: compute here */
            size_t i = take(&b);
            if (i != SIZE_MAX) {
                opt_evaluate(pb, values + i * b.p, &r[i]);
                pthread_mutex_lock(&b.lock);
                b.done++;
                runs_on[0]++;
                pthread_mutex_unlock(&b.lock);
            }
            continue;
        }
        if (owed(L) && (owed_since < 0 || seconds_now() - owed_since < 1e-9 * OWED_NS)) {
            if (owed_since < 0) owed_since = seconds_now();
            nap(20000); /* on its way: a message follows its ring at once */
            continue;
        }
        int bells = 1;
        for (int w = 1; w < L->size; w++) bells &= L->bell[w] >= 0;
        bell_wait(L->bell, L->size, bells && b.wake >= 0 ? 1000 : 1, L->rung);
        if (owed_since >= 0 && !owed(L)) owed_since = -1;
    }
    for (unsigned k = 0; k < started; k++) pthread_join(tid[k], NULL);
    for (size_t i = b.next; i < n; i++) not_run(&r[i]);
    L->bell[0] = -1;
    if (fd[0] >= 0) {
        close(fd[0]);
        close(fd[1]);
    }
    pthread_mutex_destroy(&b.lock);
    free(sent);
}

static opt_runner runner;

const opt_runner *optimise_mpi_runner(void)
{
    mpi_link *L = mpi_link_get();
    if (!L || L->rank != 0) return NULL;
    if (!slots) {
        slots = calloc((size_t)L->size, sizeof *slots);
        runs_on = calloc((size_t)L->size, sizeof *runs_on);
        if (!slots || !runs_on) MPI_Abort(MPI_COMM_WORLD, RUN_FAILED);
    }
    runner = (opt_runner){.run = run_batch, .user = L};
    return &runner;
}

void optimise_mpi_scene_end(void)
{
    mpi_link *L = mpi_link_get();
    if (!L || L->rank != 0 || !slots) return;
    size_t total = 0;
    for (int r = 0; r < L->size; r++) total += runs_on[r];
    if (total) {
        printf("! runs on %d ranks:", L->size);
        for (int r = 0; r < L->size; r++)
            printf("%s %zu on rank %d", r ? "," : "", runs_on[r], r);
        printf("\n");
        fflush(stdout);
    }
    for (int r = 1; r < L->size; r++) {
        MPI_Send(NULL, 0, MPI_BYTE, r, TAG_END, MPI_COMM_WORLD);
        bell_ring(L->bell[r], BELL_MESSAGE);
    }
    /* A worker's announcement not yet received is mpi_scene_end's to take
     * (with its goodbye, which follows it). */
    memset(slots, 0, (size_t)L->size * sizeof *slots);
    memset(runs_on, 0, (size_t)L->size * sizeof *runs_on);
}

/* ---- the other ranks -------------------------------------------------------------------- */

typedef struct job {
    int64_t index;
    double *values;          /* a point; NULL once computed                   */
    opt_result r;
    struct job *next;
} job;

typedef struct worker {
    const optimise_remote *w;
    pthread_mutex_t lock;
    pthread_cond_t more;
    job *todo, *todo_tail;   /* points to compute, in order received          */
    job *done;               /* results to send                               */
    size_t busy;             /* points received and not yet sent back          */
    int ending;
    int wake;
} worker;

/* Computes the next point; 0 when there is none (and ending: stop). */
static int compute_one(worker *k, int block)
{
    pthread_mutex_lock(&k->lock);
    while (!k->todo && !k->ending && block) pthread_cond_wait(&k->more, &k->lock);
    job *j = k->todo;
    if (j) {
        k->todo = j->next;
        if (!k->todo) k->todo_tail = NULL;
    }
    pthread_mutex_unlock(&k->lock);
    if (!j) return 0;
    optimise_remote_evaluate(k->w, j->values, &j->r);
    free(j->values);
    j->values = NULL;
    pthread_mutex_lock(&k->lock);
    j->next = k->done;
    k->done = j;
    pthread_mutex_unlock(&k->lock);
    if (k->wake >= 0) wake(k->wake);
    return 1;
}

static void *worker_thread(void *arg)
{
    while (compute_one(arg, 1)) {
    }
    return NULL;
}

/* Rings rank 0's bell, then sends. */
static void send_to_0(const mpi_link *L, const void *buf, int len, int tag)
{
    bell_ring(L->bell[0], BELL_MESSAGE);
    MPI_Send(buf, len, MPI_BYTE, 0, tag, MPI_COMM_WORLD);
}

/* Rank 0's messages that have come.  1 if one did. */
static int receive(worker *k, mpi_link *L)
{
    size_t p = k->w ? optimise_remote_size(k->w) : 0;
    int any = 0;
    for (;;) {
        int flag = 0, len = 0;
        MPI_Status st;
        MPI_Iprobe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st);
        if (!flag) return any;
        any = 1;
        MPI_Get_count(&st, MPI_BYTE, &len);
        unsigned char *buf = malloc(len > 0 ? (size_t)len : 1);
        if (!buf) MPI_Abort(MPI_COMM_WORLD, RUN_FAILED);
        MPI_Recv(buf, len, MPI_BYTE, 0, st.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        L->got[0]++;
        if (st.MPI_TAG == TAG_END) {
            pthread_mutex_lock(&k->lock);
            k->ending = 1;
            pthread_cond_broadcast(&k->more);
            pthread_mutex_unlock(&k->lock);
        } else if (st.MPI_TAG == TAG_POINT && k->w && (size_t)len == 8 + p * sizeof(double)) {
            job *j = calloc(1, sizeof *j);
            if (!j || !(j->values = malloc((p ? p : 1) * sizeof(double))))
                MPI_Abort(MPI_COMM_WORLD, RUN_FAILED);
            memcpy(&j->index, buf, 8);
            memcpy(j->values, buf + 8, p * sizeof(double));
            pthread_mutex_lock(&k->lock);
            if (k->todo_tail)
                k->todo_tail->next = j;
            else
                k->todo = j;
            k->todo_tail = j;
            k->busy++;
            pthread_cond_signal(&k->more);
            pthread_mutex_unlock(&k->lock);
        }
        free(buf);
    }
}

/* The results computed, sent to rank 0. */
static void send_results(worker *k, const mpi_link *L)
{
    pthread_mutex_lock(&k->lock);
    job *j = k->done;
    k->done = NULL;
    pthread_mutex_unlock(&k->lock);
    while (j) {
        job *next = j->next;
        int len = 0;
        unsigned char *buf = pack_result(j->index, &j->r, &len);
        if (!buf) MPI_Abort(MPI_COMM_WORLD, RUN_FAILED);
        send_to_0(L, buf, len, TAG_RESULT);
        free(buf);
        opt_result_free(&j->r);
        free(j);
        pthread_mutex_lock(&k->lock);
        k->busy--;
        pthread_mutex_unlock(&k->lock);
        j = next;
    }
}

void optimise_mpi_serve(const scene *sc)
{
    mpi_link *L = mpi_link_get();
    if (!L || L->rank == 0) return;
    worker k = {.w = optimise_remote_new(sc), .wake = -1};
    pthread_mutex_init(&k.lock, NULL);
    pthread_cond_init(&k.more, NULL);
    int fd[2] = {-1, -1};
    if (wake_open(fd) == 0) {
        k.wake = fd[1];
        L->bell[L->rank] = fd[0]; /* this rank's own slot: its threads' wake-up */
    }
    long long t = scene_cfg(sc)->output.threads;
    unsigned want = t > 0 ? (unsigned)(t < MAX_THREADS ? t : MAX_THREADS) : L->threads_per_rank;
    if (!k.w) want = 0;
    pthread_t tid[MAX_THREADS];
    unsigned started = 0;
    for (; started < want; started++)
        if (pthread_create(&tid[started], NULL, worker_thread, &k) != 0) break;
    int32_t announce = (int32_t)(started ? started : want ? 1 : 0); /* 1: on this thread */
    send_to_0(L, &announce, (int)sizeof announce, TAG_READY);
    L->got[0] = L->rung[0]; /* rings counted from here */
    double owed_since = -1;
    for (;;) {
        if (receive(&k, L)) owed_since = -1;
        if (started == 0)
            while (compute_one(&k, 0)) {
            }
        send_results(&k, L);
        pthread_mutex_lock(&k.lock);
        int over = k.ending && k.busy == 0;
        pthread_mutex_unlock(&k.lock);
        if (over) break;
        if (L->bell[0] >= 0 && L->rung[0] > L->got[0]) {
            if (owed_since < 0) owed_since = seconds_now();
            if (seconds_now() - owed_since < 1e-9 * OWED_NS) {
                nap(20000); /* on its way: a message follows its ring at once */
                continue;
            }
            L->got[0] = L->rung[0]; /* a stray ring: not ours */
        }
        owed_since = -1;
        bell_wait(L->bell, L->size, L->bell[0] >= 0 && k.wake >= 0 ? 1000 : 1, L->rung);
    }
    for (unsigned j = 0; j < started; j++) pthread_join(tid[j], NULL);
    L->bell[L->rank] = -1;
    if (fd[0] >= 0) {
        close(fd[0]);
        close(fd[1]);
    }
    pthread_cond_destroy(&k.more);
    pthread_mutex_destroy(&k.lock);
    optimise_remote_free((optimise_remote *)k.w);
}
