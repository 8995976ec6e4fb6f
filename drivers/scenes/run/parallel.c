/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * parallel.c -- a minimal parallel for: workers take the next index under a
 * mutex until none is left.  Which thread computes which run does not
 * matter: the runs are independent and deterministic.
 */
#include "run/parallel.h"

#include <pthread.h>
#include <unistd.h>

typedef struct pool {
    pthread_mutex_t lock;
    size_t next, n;
    parallel_fn fn;
    void *data;
} pool;

static void *worker(void *arg)
{
    pool *p = arg;
    for (;;) {
        pthread_mutex_lock(&p->lock);
        size_t i = p->next < p->n ? p->next++ : p->n;
        pthread_mutex_unlock(&p->lock);
        if (i >= p->n) return NULL;
        p->fn(i, p->data);
    }
}

static unsigned online_cpus(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (unsigned)n : 1u;
}

unsigned parallel_for(size_t n, unsigned threads, parallel_fn fn, void *data)
{
    enum { MAX_THREADS = 256 };
    if (threads == 0) threads = online_cpus();
    if (threads > n) threads = (unsigned)n;
    if (threads > MAX_THREADS) threads = MAX_THREADS;
    pool p = {.next = 0, .n = n, .fn = fn, .data = data};
    pthread_t tid[MAX_THREADS];
    unsigned started = 0;
    if (threads > 1 && pthread_mutex_init(&p.lock, NULL) == 0) {
        for (; started < threads; started++)
            if (pthread_create(&tid[started], NULL, worker, &p) != 0) break;
        for (unsigned t = 0; t < started; t++) pthread_join(tid[t], NULL);
        pthread_mutex_destroy(&p.lock);
    }
    /* Whatever no thread took (none started, or threads = 1) runs here. */
    for (size_t i = p.next; i < n; i++) fn(i, data);
    return started > 0 ? started : 1u;
}
