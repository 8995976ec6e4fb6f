/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * parallel.h -- the runs of a sweep computed at once on several threads.
 *
 * The library has no global mutable state, so independent chains can be
 * integrated concurrently; each run's numbers are bit-identical to a serial
 * run (tests/api/test_threads.c).  Not part of libtaper.
 */
#ifndef TAPER_PARALLEL_H
#define TAPER_PARALLEL_H

#include <stddef.h>

typedef void (*parallel_fn)(size_t index, void *data);

/* Calls fn(i, data) once for each i < n, on up to `threads` threads at a
 * time (0: one per online processor).  The calls must be independent.
 * Falls back to serial calls if no thread can be created.  Returns the
 * number of threads used. */
unsigned parallel_for(size_t n, unsigned threads, parallel_fn fn, void *data);

#endif
