/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sensors.h -- what an experimenter's instruments read during a run
 * (&sensors): time series recorded by the library's sampler
 * (taper_solver_spec_set_sampler) and written after the run:
 *
 *   DIR/sensors.tsv    t, granule, x, v, f_left, f_right, force of every
 *                      chosen granule at every sample (tidy: one row per
 *                      granule and time)
 *   DIR/walls.tsv      t and the force on each wall, with the peak force,
 *                      its time and the impulse in the header
 *   DIR/spacetime.tsv  v(k, t) on a grid thinned to at most
 *                      spacetime_granules x spacetime_times points, and
 *   DIR/spacetime.gp   its gnuplot script -> DIR/spacetime.png
 *
 * Every file starts with its column names (units in SI), then '#' lines.
 * Recording happens inside taper_sim_run (a compute thread): it prints
 * nothing; writing happens afterwards, in the order of the sweep.
 *
 * Not part of libtaper.
 */
#ifndef TAPER_SENSORS_H
#define TAPER_SENSORS_H

#include "scene/scene.h"
#include "taper.h"

#include <stdio.h>

typedef struct sensors sensors;

/* The recorder of a run at configuration `at` (a point of the sweep) of
 * `chain`, or NULL when the scene samples nothing (interval 0) -- also
 * NULL out of memory, with *failed set. */
sensors *sensors_new(const scene_config *at, const taper_chain *chain, int *failed);
void sensors_free(sensors *s);
/* About how many bytes one sample adds to the files the sensors write and
 * to the memory they keep until then (the guard of &output max_output). */
double sensors_bytes_per_sample(const sensors *s);

/* The taper_sample_fn: records one sample.  Never stops the run (a
 * recording that runs out of memory is reported by sensors_write). */
int sensors_sample(const taper_sim *sim, void *user);

/* Writes the files the scene asks for and says so on `out` ("! wrote
 * ..."), renders spacetime.png when gnuplot is there (a note on `out`
 * otherwise).  `sim` gives the wall statistics; `partial` (NULL for a
 * complete run) why the run ended early, said in each file's header (its
 * samples end there).  0, or -1 with *msg (malloc'd). */
int sensors_write(const sensors *s, const taper_sim *sim, const char *partial, const char *dir,
                  FILE *out, char **msg);

#endif
