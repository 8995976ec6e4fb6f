/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * steppers.c -- the steppers by method: one row per method of
 * TAPER_METHOD_LIST (taper.h), the only place that ties a method to the
 * file that integrates it (stepper.h).
 */
#include "stepper.h"

static const taper_stepper_row rows[TAPER_N_METHODS] = {
    [TAPER_ADAMS] = {&taper_stepper_cvode, 1},
    /* Newton's iteration on the band Jacobian of the whole chain */
    [TAPER_BDF] = {&taper_stepper_cvode, 0},
    [TAPER_RK8] = {&taper_stepper_rk8, 1},
};

const taper_stepper_row *taper_stepper_of(taper_method method)
{
    return (unsigned)method < TAPER_N_METHODS && rows[method].type ? &rows[method] : NULL;
}
