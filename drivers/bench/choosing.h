/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * choosing.h -- taper-bench --choosing: the measurements behind
 * docs/choosing.md (choosing.c).
 */
#ifndef TAPER_BENCH_CHOOSING_H
#define TAPER_BENCH_CHOOSING_H

#include <stddef.h>

/* For each family of chains of docs/choosing.md (the paper's profiles, a
 * long chain, dimers and decorated chains, n < 2, chains with damping,
 * drag, a load, walls, stiff drag): each method at rtol 1e-6, 1e-8, 1e-10
 * and 1e-12 (atol 1e-3 rtol), its pass-time error against a reference, its
 * energy error and its CPU time.  Writes DIR/choosing.tsv and prints a
 * table; `only` (NULL: all) runs the cases whose name contains it; a run
 * stops after cpu_limit seconds of CPU and says how far it got.  0, or 1
 * after a message (2: `only` matches no case). */
int taper_bench_choosing(const char *dir, const char *only, int reps, double cpu_limit);

#endif
