/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * window_storage.c -- the window's buffers and their range (see
 * window_storage.h).  A leaf: nothing of the sim, nothing of SUNDIALS.
 */
#include "window_storage.h"

#include <stdlib.h>
#include <string.h>

taper_window *taper_window_alloc_tail(size_t begin, size_t end, size_t capacity, size_t tail)
{
    if (tail > TAPER_WINDOW_TAIL_MAX) return NULL;
    taper_window *w = calloc(1, sizeof *w);
    if (!w) return NULL;
    w->begin = begin;
    w->end = end;
    w->tail = tail;
    w->base = begin;
    w->capacity = capacity > end - begin + tail ? capacity : end - begin + tail;
    return w;
}

taper_window *taper_window_alloc(size_t begin, size_t end, size_t capacity)
{
    return taper_window_alloc_tail(begin, end, capacity, 0);
}

void taper_window_free(taper_window *w)
{
    if (!w) return;
    free(w->buffers);
    free(w);
}

/* ---- registry ------------------------------------------------------- */
int taper_window_attach(taper_window *w, double **buffer)
{
    *buffer = NULL;
    if (w->n_buffers == w->buffers_cap) {
        size_t cap = w->buffers_cap ? 2 * w->buffers_cap : 32;
        double ***grown = realloc(w->buffers, cap * sizeof *grown);
        if (!grown) return -1;
        w->buffers = grown;
        w->buffers_cap = cap;
    }
    *buffer = calloc(w->capacity, sizeof(double));
    if (!*buffer) return -1;
    w->buffers[w->n_buffers++] = buffer;
    return 0;
}

void taper_window_detach(taper_window *w, double **buffer)
{
    for (size_t i = 0; i < w->n_buffers; i++) {
        if (w->buffers[i] == buffer) {
            w->buffers[i] = w->buffers[--w->n_buffers];
            break;
        }
    }
    free(*buffer);
    *buffer = NULL;
}

/* ---- the range ------------------------------------------------------ */
/* Copies what old buffers hold of [begin, end) into fresh buffers based at
 * `base`, and the tail from the old end to the new; everything else in the
 * new buffers is zero. */
static int reposition(taper_window *w, size_t base, size_t capacity, size_t begin, size_t end)
{
    size_t n = w->n_buffers;
    double **fresh = calloc(n ? n : 1, sizeof *fresh);
    if (!fresh) return -1;
    for (size_t j = 0; j < n; j++) {
        fresh[j] = calloc(capacity, sizeof(double));
        if (!fresh[j]) {
            for (size_t i = 0; i < j; i++) free(fresh[i]);
            free(fresh);
            return -1;
        }
    }
    size_t lo = begin > w->base ? begin : w->base;
    /* Beyond the old end the old buffers hold the tail, then zeros. */
    size_t hi = end < w->end ? end : w->end;
    for (size_t j = 0; j < n; j++) {
        double **buf = w->buffers[j];
        if (hi > lo) memcpy(fresh[j] + (lo - base), *buf + (lo - w->base), (hi - lo) * sizeof(double));
        if (w->tail)
            memcpy(fresh[j] + (end - base), *buf + (w->end - w->base), w->tail * sizeof(double));
        free(*buf);
        *buf = fresh[j];
    }
    free(fresh);
    w->base = base;
    w->capacity = capacity;
    return 0;
}

/* Moves the tail of every buffer from the old end to `end`, zeroing where
 * it was (in place: the buffers cover both). */
static void move_tail(taper_window *w, size_t end)
{
    const size_t t = w->tail;
    if (!t || end == w->end) return;
    double saved[TAPER_WINDOW_TAIL_MAX];
    for (size_t j = 0; j < w->n_buffers; j++) {
        double *b = *w->buffers[j];
        memcpy(saved, b + (w->end - w->base), t * sizeof(double));
        memset(b + (w->end - w->base), 0, t * sizeof(double));
        memcpy(b + (end - w->base), saved, t * sizeof(double));
    }
}

int taper_window_set_range(taper_window *w, size_t begin, size_t end)
{
    if (begin >= w->base && end + w->tail <= w->base + w->capacity) {
        /* Keep the zero invariant when the right edge retreats (never in
         * normal use, but cheap to honour). */
        for (size_t j = 0; end < w->end && j < w->n_buffers; j++)
            memset(*w->buffers[j] + (end - w->base), 0, (w->end - end) * sizeof(double));
        move_tail(w, end);
        w->begin = begin;
        w->end = end;
        return 0;
    }
    size_t need = end - begin + w->tail;
    size_t capacity = w->capacity > 2 * need ? w->capacity : 2 * need + 64;
    if (reposition(w, begin, capacity, begin, end) != 0) return -1;
    w->begin = begin;
    w->end = end;
    return 0;
}
