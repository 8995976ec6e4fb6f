/*
 * _scene.h -- the one place where the Python extension meets the driver's
 * scene reader (drivers/taper/scene, linked in from the static library
 * taper_app): taper.run_scene reads a scene exactly as `taper` does, and a
 * change of the scene module's API touches only _scene.c.
 */
#ifndef TAPER_PY_SCENE_H
#define TAPER_PY_SCENE_H

#include "taper.h"

#include <stddef.h>

typedef struct pyscene pyscene;

/* Reads and validates the scene at path.  0: *out holds it; -1: the scene
 * is invalid and *diag (malloc'd, the caller frees it) holds the reader's
 * diagnostics as the driver prints them; -2: out of memory.  Needs no GIL,
 * prints nothing. */
int pyscene_load(const char *path, pyscene **out, char **diag);
void pyscene_free(pyscene *sc);

/* The number of runs: the values of the swept variable, or 1. */
size_t pyscene_runs(const pyscene *sc);
/* 0 when the scene asks for the theory alone (&solver numerics = .false.). */
int pyscene_numerics(const pyscene *sc);
/* Fills the library's specs for run i, as the driver does. */
taper_status pyscene_specs(const pyscene *sc, size_t i, taper_chain_spec *chain,
                           taper_solver_spec *solver, taper_error *err);

#endif
