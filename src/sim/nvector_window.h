/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * nvector_window.h -- an N_Vector whose active part is a sliding window of
 * the chain's state (window_storage.h): CVODE's vectors for the CVODE
 * stepper (stepper_cvode.c).  Every vector cloned from one keeps its
 * buffer in the same window, so all of them follow the active range
 * [begin, end) together, and every operation, norm included, runs over
 * that range only.
 */
#ifndef TAPER_NVECTOR_WINDOW_H
#define TAPER_NVECTOR_WINDOW_H

#include "window_storage.h"

#include <sundials/sundials_nvector.h>

/* Pointer to the entry with absolute index `begin` of v, and the length
 * (end - begin + tail). */
double *taper_window_data(N_Vector v);
size_t taper_window_length(N_Vector v);

/* A vector of the window (zero); its clones are of the window too.  NULL
 * on allocation failure.  Every vector of a window is destroyed before the
 * window is freed. */
N_Vector taper_window_vector_new(taper_window *w, SUNContext ctx);
/* Where v keeps its buffer's pointer (the window updates it): the state's
 * storage for the sim (taper_state.buffer). */
double **taper_window_vector_buffer(N_Vector v);

#endif
