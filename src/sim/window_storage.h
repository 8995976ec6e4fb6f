/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * window_storage.h -- the storage of a state whose active part is a sliding
 * window of the chain's state: buffers that hold the absolute index range
 * [begin, end) of the full 2N state, all repositioned together when the
 * range moves.  A leaf of src/sim, in plain C: every stepper keeps its
 * state here (CVODE's vectors through nvector_window.c, rk8's entries
 * directly), and the sim moves the range (taper_sim_move_window).
 *
 * Why: at any moment only a few granules near the pulse front move; the
 * granules ahead are exactly at rest and the ones behind fly freely.  An
 * integrator cannot change its problem size, but it touches state only
 * through its buffers: every buffer registered with one window shares the
 * active range, so a step costs O(window), not O(N).  Each buffer has
 * `capacity` entries, its entry 0 at absolute index `base`; moving the
 * window repositions every buffer at once (amortised O(1) per granule).
 *
 * Exactness: entries entering on the right hold zero in every buffer (a
 * granule at rest has zero state and derivatives), and a multistep
 * history is component-wise, so dropping components leaves the others
 * untouched.  Invariant maintained here: in every buffer, entries at
 * absolute index >= end + tail are zero.
 */
#ifndef TAPER_WINDOW_STORAGE_H
#define TAPER_WINDOW_STORAGE_H

#include <stddef.h>

typedef struct taper_window {
    size_t begin, end;   /* active absolute index range                     */
    size_t tail;         /* entries after end that travel with it (the
                            sim's quadratures): every buffer's active part
                            is [begin, end + tail)                          */
    size_t base;         /* absolute index of every buffer's entry 0        */
    size_t capacity;     /* entries of every registered buffer              */
    double ***buffers;   /* where each registered buffer's pointer is kept  */
    size_t n_buffers, buffers_cap;
} taper_window;

/* Creates a window with active range [begin, end) and buffers of at least
 * `capacity` entries; NULL on allocation failure.  The caller owns it and
 * frees it after every buffer of the window has been detached. */
taper_window *taper_window_alloc(size_t begin, size_t end, size_t capacity);
/* The same with `tail` (at most TAPER_WINDOW_TAIL_MAX) entries after end in
 * every buffer, which move with end when the range changes: values that
 * belong to no granule (integrals over the motion) ride along with the
 * window.  Entries between the old and the new end are zero, as ever. */
#define TAPER_WINDOW_TAIL_MAX 8
taper_window *taper_window_alloc_tail(size_t begin, size_t end, size_t capacity, size_t tail);
void taper_window_free(taper_window *w);

/* Allocates a buffer of the window's capacity, zero, into *buffer and
 * registers it: the window repositions it (and updates *buffer) whenever
 * the range moves, so *buffer must stay where it is until it is detached.
 * 0, or -1 on allocation failure (*buffer is then NULL). */
int taper_window_attach(taper_window *w, double **buffer);
/* Frees a registered buffer and forgets it (*buffer becomes NULL). */
void taper_window_detach(taper_window *w, double **buffer);

/* The entry at absolute index begin of a registered buffer, and the
 * entries from there on: end - begin + tail. */
static inline double *taper_window_entries(const taper_window *w, double *buffer)
{
    return buffer + (w->begin - w->base);
}
static inline size_t taper_window_size(const taper_window *w) { return w->end - w->begin + w->tail; }

/* Moves the active range to [begin, end), repositioning every buffer if
 * the range is no longer covered.  Entries newly covered are zero.
 * Returns 0, or -1 on allocation failure (the window is then unchanged). */
int taper_window_set_range(taper_window *w, size_t begin, size_t end);

#endif
