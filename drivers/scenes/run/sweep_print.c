/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sweep_print.c -- what a sweep prints while it runs (sweep_print.h).
 */
#include "run/sweep_print.h"

#include <math.h>
#include <stdio.h>
#include <time.h>
#include <unistd.h>

static double wall_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void sweep_print_start(sweep_printer *p, int progress, int remote, unsigned ranks,
                       unsigned threads)
{
    int tty = isatty(STDERR_FILENO);
    *p = (sweep_printer){.show = progress && (tty || remote), .every = tty ? 0.25 : 10,
                         .start = wall_seconds(), .ranks = ranks, .threads = threads};
    p->last = tty ? 0 : p->start;
}

void sweep_print_clear(sweep_printer *p)
{
    if (p->on_screen) fputs("\r\033[K", stderr);
    p->on_screen = 0;
}

void sweep_print_progress(sweep_printer *p, sweep *sw, int force)
{
    if (!p->show) return;
    double now = wall_seconds();
    if (!force && now - p->last < p->every) return;
    p->last = now;
    pthread_mutex_lock(&sw->lock);
    size_t done = sw->done, reused = sw->reused, failed = sw->failed, computed = sw->computed;
    double cost_done = sw->cost_done, cost_todo = sw->cost_todo;
    pthread_mutex_unlock(&sw->lock);
    double elapsed = now - p->start;
    double rate = computed ? (double)computed / fmax(elapsed, 1e-9) : 0;
    fprintf(stderr, "%staper: runs %zu/%zu", p->every > 1 ? "" : "\r\033[K", done, sw->n);
    if (reused) fprintf(stderr, " (%zu reused)", reused);
    if (failed) fprintf(stderr, " %zu failed", failed);
    if (computed) {
        /* Time left from the estimated costs of what is left. */
        double left = cost_done > 0 ? elapsed * (cost_todo - cost_done) / cost_done : NAN;
        fprintf(stderr, "  %.3g runs/s", rate);
        if (isfinite(left)) fprintf(stderr, "  %.0f s left", fmax(left, 0));
    }
    fprintf(stderr, "  [%u rank%s x %u thread%s]", p->ranks, p->ranks == 1 ? "" : "s", p->threads,
            p->threads == 1 ? "" : "s");
    if (p->every > 1) {
        fputc('\n', stderr); /* a log line */
    } else {
        p->on_screen = 1;
    }
    fflush(stderr);
}

void sweep_print_ready(sweep_printer *p, sweep *sw)
{
    for (;;) {
        pthread_mutex_lock(&sw->lock);
        int ready = p->committed < sw->n && sw->items[p->committed].state == SWEEP_DONE;
        pthread_mutex_unlock(&sw->lock);
        if (!ready) return;
        const sweep_item *it = &sw->items[p->committed++];
        sweep_print_clear(p);
        if (it->outcome.log) fputs(it->outcome.log, stderr);
        if (it->outcome.out) fputs(it->outcome.out, stdout);
        if (it->reused) printf("! reused %s/granules.tsv\n", it->dir);
        if (it->elsewhere) continue;
        fflush(stdout);
        fflush(stderr);
    }
}

void sweep_print_rest(const sweep_printer *p, const sweep *sw)
{
    for (size_t i = p->committed; i < sw->n; i++) {
        const sweep_item *it = &sw->items[i];
        if (it->state != SWEEP_DONE) continue;
        if (it->outcome.log) fputs(it->outcome.log, stderr);
        if (it->outcome.out) fputs(it->outcome.out, stdout);
    }
    fflush(stdout);
}
