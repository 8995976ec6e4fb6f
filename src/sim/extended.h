/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * extended.h -- the chain the sim integrates: the chain's granules and the
 * bodies the options put at its ends (extended.c, a leaf of src/sim).
 */
#ifndef TAPER_EXTENDED_H
#define TAPER_EXTENDED_H

#include "dynamics.h"
#include "settings/specs.h"

/* The chain the sim integrates (extended.c): bodies 1..bodies, granule k
 * of the chain being body k + off.  A striker or a left wall is body 1
 * (off = 1), a right wall body `bodies`; walls have mass 0.  Every array of
 * the sim indexed by granule (observables, scales, events, the window) is
 * indexed by body; the public readers add off. */
typedef struct taper_model {
    size_t granules;        /* N                                            */
    size_t off;             /* bodies before granule 1 (0 or 1)             */
    size_t bodies;          /* off + N + (1 with a right wall)              */
    int striker, wall_left, wall_right;
    /* A piston is a left wall (wall_left is set: body 1, inverse mass 0,
     * its force and impulse the left wall's) that moves at velocity 1 until
     * t = piston_duration (INFINITY: never stops), then rests; the body
     * with the impulse is the piston itself (impulse = 1), granule 1
     * rests.  docs/physics.md, "Piston". */
    int piston;
    double piston_duration;
    size_t impulse;         /* the body moving at t = 0 (velocity 1)        */
    double scale_mass;      /* its mass, granule 1's behind a piston: the
                               scale of energies and impulses              */
    double load, damping, drag;
    int options;            /* any option: the general right-hand side      */
    int free_flight;        /* no load, no drag: bodies that leave the
                               window fly freely (window.c)                 */
    int quadratures;        /* walls or losses: the stepper integrates the
                               wall impulses and the dissipated energy      */
    double *mass, *contact, *rest; /* per body (contact: with the next)     */
    double *delta;          /* static overlaps (NULL without a load)        */
} taper_model;

/* 0, or -1 when out of memory (taper_model_release frees what was made). */
int taper_model_init(taper_model *m, const taper_chain *chain);
void taper_model_release(taper_model *m);
/* Copies the options into the equations (dynamics.h). */
void taper_model_configure(const taper_model *m, taper_dyn *d);

#endif
