/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * illinois.h -- the Illinois method (regula falsi whose end that stays
 * put twice in a row has its value halved): a root finder that keeps its
 * bracket [a, b] and converges superlinearly.  Used where a root is
 * located again on CVODE's interpolant (stepper_cvode_clock.c) and where
 * rk8 locates its roots on its dense output (stepper_rk8.c).  A
 * leaf: header-only, nothing of the sim.
 */
#ifndef TAPER_ILLINOIS_H
#define TAPER_ILLINOIS_H

/* a < b; ga and gb on opposite sides of the root (b: the far side). */
typedef struct taper_bracket {
    double a, ga, b, gb;
    int side; /* the end moved last: 1 (b), -1 (a), 0 (none yet) */
} taper_bracket;

/* The next trial point: the secant's, or the middle where the secant
 * leaves the bracket. */
static inline double taper_bracket_point(const taper_bracket *br)
{
    double c = br->b - br->gb * (br->b - br->a) / (br->gb - br->ga);
    return c > br->a && c < br->b ? c : 0.5 * (br->a + br->b);
}

/* Moves the end on c's side to c (far: c is on b's side of the root). */
static inline void taper_bracket_move(taper_bracket *br, double c, double gc, int far)
{
    if (far) {
        br->b = c, br->gb = gc;
        if (br->side == 1) br->ga *= 0.5;
        br->side = 1;
    } else {
        br->a = c, br->ga = gc;
        if (br->side == -1) br->gb *= 0.5;
        br->side = -1;
    }
}

#endif
