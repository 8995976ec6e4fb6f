/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * nvector_window.h -- an N_Vector whose active part is a sliding window of
 * the chain's state.
 *
 * Why: at any moment only a few granules near the pulse front move; the
 * granules ahead are exactly at rest and the ones behind fly freely.  CVODE
 * cannot change its problem size, but it touches state only through vector
 * operations.  All vectors cloned from one window share a descriptor of the
 * active index range [begin, end) (absolute indices into the full 2N state);
 * every operation, norm included, runs over that range only, so a step costs
 * O(window), not O(N).  Storage is a buffer of `capacity` entries starting at
 * absolute index `base`; moving the window repositions all buffers at once
 * (amortised O(1) per granule).
 *
 * Exactness: the Nordsieck history is component-wise, so dropping components
 * leaves the others untouched, and components entering on the right hold
 * zero in every vector (a granule at rest has zero state and derivatives).
 * Invariant maintained here: in every vector, entries at absolute index
 * >= end + tail are zero.
 */
#ifndef TAPER_NVECTOR_WINDOW_H
#define TAPER_NVECTOR_WINDOW_H

#include <sundials/sundials_nvector.h>

typedef struct taper_window {
    size_t begin, end;   /* active absolute index range                     */
    size_t tail;         /* entries after end that travel with it (the
                            sim's quadratures): every operation covers
                            [begin, end + tail)                             */
    size_t base;         /* absolute index of buffer element 0              */
    size_t capacity;     /* buffer length of every registered vector        */
    N_Vector *vectors;   /* every live vector of this window                */
    size_t n_vectors, vectors_cap;
} taper_window;

/* Pointer to the entry with absolute index `begin` of v, and the length
 * (end - begin + tail). */
double *taper_window_data(N_Vector v);
size_t taper_window_length(N_Vector v);

/* Creates a window with active range [begin, end) and buffers of at least
 * `capacity` entries; NULL on allocation failure.  The caller owns it and
 * frees it after every vector of the window has been destroyed. */
taper_window *taper_window_alloc(size_t begin, size_t end, size_t capacity);
/* The same with `tail` (at most TAPER_WINDOW_TAIL_MAX) entries after end in
 * every vector, which move with end when the range changes: values that
 * belong to no granule (integrals over the motion) ride along with the
 * window.  Entries between the old and the new end are zero, as ever. */
#define TAPER_WINDOW_TAIL_MAX 8
taper_window *taper_window_alloc_tail(size_t begin, size_t end, size_t capacity, size_t tail);
void taper_window_free(taper_window *w);
N_Vector taper_window_vector_new(taper_window *w, SUNContext ctx);

/* Moves the active range to [begin, end), repositioning the buffers of every
 * vector if the range is no longer covered.  Entries newly covered are zero.
 * Returns 0, or -1 on allocation failure (the window is then unchanged). */
int taper_window_set_range(taper_window *w, size_t begin, size_t end);

#endif
