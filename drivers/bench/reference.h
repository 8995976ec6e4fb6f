/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * reference.h -- converged pass times without CVODE (reference.c), for
 * taper-reference and taper-bench.
 */
#ifndef TAPER_BENCH_REFERENCE_H
#define TAPER_BENCH_REFERENCE_H

#include "taper.h"

/* Pass times t_pass[k-1], k = 1..N-1 ([N-1] NaN), of the paper's chain
 * (no options) by extrapolated modified midpoint steps in long double with
 * local error tol (1e-17: ~1e-16 of t, docs/design.md "Accuracy at tight
 * tolerances").  0, or -1 after a message on stderr. */
int taper_reference_pass_times(const taper_chain *chain, long double tol, long double *t_pass);

#endif
