/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sweep_queue.c -- the runs of a sweep and who computes which
 * (sweep_queue.h).
 */
#include "run/sweep_queue.h"

#include "run/interrupt.h"
#include "util/text.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* The granules the pulse crosses: the cost of a run grows with them (a
 * theory-only run costs next to nothing). */
static double estimate(const scene_config *cfg, size_t point)
{
    scene_config at;
    scene_config_at(cfg, point, &at);
    double n = scene_setting(&at, "n_granules"), last = scene_setting(&at, "last_granule");
    if (last > 0 && last < n) n = last;
    return at.solver.numerics ? n : 1e-3 * n;
}

typedef struct ranked {
    double cost;
    size_t i;
} ranked;

/* The dearest first; equal costs in the order of the sweep. */
static int dearest_first(const void *a, const void *b)
{
    const ranked *x = a, *y = b;
    if (x->cost != y->cost) return x->cost > y->cost ? -1 : 1;
    return x->i < y->i ? -1 : x->i > y->i;
}

static int order_by_cost(sweep *sw)
{
    ranked *r = malloc((sw->n ? sw->n : 1) * sizeof *r);
    if (!r) return -1;
    for (size_t i = 0; i < sw->n; i++) r[i] = (ranked){.cost = sw->items[i].cost, .i = i};
    qsort(r, sw->n, sizeof *r, dearest_first);
    for (size_t k = 0; k < sw->n; k++) sw->order[k] = r[k].i;
    free(r);
    return 0;
}

sweep *sweep_open(const scene *sc)
{
    const scene_config *cfg = scene_cfg(sc);
    sweep *sw = calloc(1, sizeof *sw);
    if (!sw) return NULL;
    sw->sc = sc;
    sw->cfg = cfg;
    sw->n = cfg->runs.n;
    sw->items = calloc(sw->n, sizeof *sw->items);
    sw->order = calloc(sw->n, sizeof *sw->order);
    if (!sw->items || !sw->order) goto fail;
    pthread_mutex_init(&sw->lock, NULL);
    pthread_cond_init(&sw->cond, NULL);
    for (size_t i = 0; i < sw->n; i++) {
        sweep_item *it = &sw->items[i];
        if (!(it->name = scene_point_name(cfg, i))) goto fail;
        if (!(it->dir = text_printf("%s/%s", cfg->output.dir, it->name))) goto fail;
        it->cost = estimate(cfg, i);
        it->outcome.cpu_seconds = NAN; /* until it is computed or reused */
        sw->cost_todo += it->cost;
    }
    if (order_by_cost(sw) != 0) goto fail;
    return sw;
fail:
    sweep_close(sw);
    return NULL;
}

void sweep_close(sweep *sw)
{
    if (!sw) return;
    for (size_t i = 0; sw->items && i < sw->n; i++) {
        free(sw->items[i].name);
        free(sw->items[i].dir);
        run_outcome_free(&sw->items[i].outcome);
    }
    if (sw->items && sw->order) {
        pthread_mutex_destroy(&sw->lock);
        pthread_cond_destroy(&sw->cond);
    }
    free(sw->items);
    free(sw->order);
    free(sw);
}

size_t sweep_size(const sweep *sw) { return sw->n; }

/* Run i leaves the runs to compute, done already (here or elsewhere). */
static void set_done_before(sweep *sw, size_t i)
{
    sw->items[i].state = SWEEP_DONE;
    sw->done++;
    sw->cost_todo -= sw->items[i].cost;
}

void sweep_deal(sweep *sw, size_t part, size_t parts)
{
    if (parts < 2) return;
    pthread_mutex_lock(&sw->lock);
    for (size_t pos = 0; pos < sw->n; pos++) {
        if (pos % parts == part - 1) continue;
        size_t i = sw->order[pos];
        sw->items[i].elsewhere = 1;
        set_done_before(sw, i);
    }
    pthread_mutex_unlock(&sw->lock);
}

void sweep_reuse(sweep *sw, size_t i, int rc, double cpu_seconds)
{
    pthread_mutex_lock(&sw->lock);
    sweep_item *it = &sw->items[i];
    it->reused = 1;
    it->outcome.rc = rc;
    it->outcome.cpu_seconds = cpu_seconds;
    sw->untrusted += rc == RUN_UNTRUSTED;
    sw->reused++;
    set_done_before(sw, i);
    pthread_mutex_unlock(&sw->lock);
}

size_t sweep_next(sweep *sw)
{
    size_t i = SIZE_MAX;
    pthread_mutex_lock(&sw->lock);
    while (!interrupt_signal() && sw->next < sw->n) {
        size_t j = sw->order[sw->next++];
        if (sw->items[j].state != SWEEP_TODO) continue; /* reused, or another part's */
        sw->items[j].state = SWEEP_RUNNING;
        sw->running++;
        i = j;
        break;
    }
    pthread_mutex_unlock(&sw->lock);
    return i;
}

void sweep_done(sweep *sw, size_t i, run_outcome *o)
{
    pthread_mutex_lock(&sw->lock);
    sweep_item *it = &sw->items[i];
    run_outcome_free(&it->outcome);
    it->outcome = *o;
    memset(o, 0, sizeof *o);
    if (it->state == SWEEP_RUNNING) sw->running--;
    it->state = SWEEP_DONE;
    sw->done++;
    sw->computed++;
    sw->cost_done += it->cost;
    if (!sweep_has_rows(it->outcome.rc)) sw->failed++;
    if (it->outcome.rc == RUN_UNTRUSTED) sw->untrusted++;
    pthread_cond_broadcast(&sw->cond);
    pthread_mutex_unlock(&sw->lock);
}

int sweep_wait(sweep *sw, double seconds)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    double whole = floor(seconds);
    ts.tv_sec += (time_t)whole;
    ts.tv_nsec += (long)((seconds - whole) * 1e9);
    if (ts.tv_nsec >= 1000000000L) {
        ts.tv_sec++;
        ts.tv_nsec -= 1000000000L;
    }
    pthread_mutex_lock(&sw->lock);
    int finished = sw->done == sw->n ||
                   ((interrupt_signal() || sw->next >= sw->n) && sw->running == 0);
    if (!finished) pthread_cond_timedwait(&sw->cond, &sw->lock, &ts);
    pthread_mutex_unlock(&sw->lock);
    return finished;
}
