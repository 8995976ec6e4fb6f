/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * fortran_abi.c -- the C side of test_fortran_abi.f90: sizes and field
 * offsets of the three structs of taper.h that the Fortran module declares
 * as bind(C) derived types, taper_error and taper_progress (the library
 * fills them) and taper_setting (a row of the table of settings, read
 * through a pointer); the library only ever appends fields to them.  Every
 * other object is opaque and reached through functions, so it has no
 * layout to agree on.
 */
#include "taper.h"

#include <stddef.h>

#define N_FIELDS 16

/* layout[type][0] = sizeof, layout[type][1 + i] = offset of field i. */
static const size_t layout[][N_FIELDS] = {
    {sizeof(taper_error), offsetof(taper_error, status), offsetof(taper_error, field),
     offsetof(taper_error, message)},
    {sizeof(taper_progress), offsetof(taper_progress, granule), offsetof(taper_progress, target),
     offsetof(taper_progress, t), offsetof(taper_progress, steps),
     offsetof(taper_progress, window_lo), offsetof(taper_progress, window_hi)},
    {sizeof(taper_setting), offsetof(taper_setting, name), offsetof(taper_setting, group),
     offsetof(taper_setting, object), offsetof(taper_setting, type),
     offsetof(taper_setting, dimension), offsetof(taper_setting, min),
     offsetof(taper_setting, max), offsetof(taper_setting, min_open),
     offsetof(taper_setting, max_open), offsetof(taper_setting, default_value),
     offsetof(taper_setting, choices), offsetof(taper_setting, beyond_paper),
     offsetof(taper_setting, description), offsetof(taper_setting, bounds_reason)},
};

/* field 0: sizeof; field i >= 1: offset of the i-th member. */
size_t taper_test_layout(int type, int field);
size_t taper_test_layout(int type, int field)
{
    if (type < 0 || type >= (int)(sizeof layout / sizeof layout[0]) || field < 0 || field >= N_FIELDS)
        return (size_t)-1;
    return layout[type][field];
}

/* The enum values and counts of taper.h, in the order of ENUMS in
 * test_fortran_abi.f90, which compares its module's constants with them:
 * a header that renumbers or grows an enum fails there until the module
 * follows. */
static const long enums[] = {
    TAPER_MONODISPERSE, TAPER_BACKWARD_LINEAR, TAPER_FORWARD_LINEAR, TAPER_BACKWARD_EXPONENTIAL,
    TAPER_FORWARD_EXPONENTIAL, TAPER_CUSTOM, TAPER_DECORATED, TAPER_N_PROFILES,
    TAPER_DISORDER_RADIUS, TAPER_DISORDER_MASS, TAPER_N_DISORDERS,
    TAPER_LEFT, TAPER_RIGHT, TAPER_N_ENDS, TAPER_END_FREE, TAPER_END_WALL, TAPER_N_BOUNDARIES,
    TAPER_DIM_LENGTH, TAPER_DIM_TIME, TAPER_DIM_VELOCITY, TAPER_DIM_MASS, TAPER_DIM_FORCE,
    TAPER_DIM_ENERGY, TAPER_DIM_IMPULSE, TAPER_N_DIMENSIONS,
    TAPER_ADAMS, TAPER_BDF, TAPER_N_METHODS,
    TAPER_T_PASS, TAPER_T_RES, TAPER_V_PEAK, TAPER_T_PEAK, TAPER_X_PASS, TAPER_N_OBSERVABLES,
    TAPER_THEORY_V, TAPER_THEORY_MU, TAPER_THEORY_T_RES, TAPER_THEORY_T,
    TAPER_N_THEORY_QUANTITIES,
    TAPER_STAT_STEPS, TAPER_STAT_RHS_EVALS, TAPER_STAT_ROOT_EVALS, TAPER_STAT_JAC_EVALS,
    TAPER_STAT_NONLIN_ITERS, TAPER_STAT_ERR_TEST_FAILS, TAPER_STAT_WINDOW_CHANGES,
    TAPER_STAT_RESTARTS, TAPER_STAT_MAX_WINDOW, TAPER_STAT_GRANULE_REACHED, TAPER_STAT_T_FINAL,
    TAPER_STAT_ENERGY_ERROR, TAPER_STAT_MOMENTUM_ERROR, TAPER_STAT_COMPLETE,
    TAPER_STAT_ENERGY_INITIAL, TAPER_STAT_ENERGY_DISSIPATED, TAPER_STAT_ENERGY_TRANSMITTED,
    TAPER_STAT_ENERGY_REFLECTED, TAPER_STAT_ENERGY_IN_CHAIN, TAPER_STAT_WALL_PEAK_FORCE_LEFT,
    TAPER_STAT_WALL_PEAK_TIME_LEFT, TAPER_STAT_WALL_IMPULSE_LEFT,
    TAPER_STAT_WALL_PEAK_FORCE_RIGHT, TAPER_STAT_WALL_PEAK_TIME_RIGHT,
    TAPER_STAT_WALL_IMPULSE_RIGHT, TAPER_N_STATISTICS,
    TAPER_FIT_POWER, TAPER_FIT_EXPONENTIAL, TAPER_FIT_DIVERGENCE_B, TAPER_FIT_DIVERGENCE_C,
    TAPER_FIT_DIVERGENCE_M, TAPER_N_FIT_MODELS,
    TAPER_OK, TAPER_EINVAL, TAPER_ENOMEM, TAPER_ERANGE, TAPER_ESOLVER, TAPER_EINTERRUPTED,
    TAPER_ELIMIT, TAPER_MESSAGE_SIZE, TAPER_N_GRANULES_MIN, TAPER_N_GRANULES_MAX,
    TAPER_MAX_ORDER_ADAMS, TAPER_MAX_ORDER_BDF, TAPER_N_LAWS,
    TAPER_SETTING_REAL, TAPER_SETTING_INTEGER, TAPER_SETTING_BOOLEAN, TAPER_SETTING_CHOICE,
    TAPER_SETTING_LIST, TAPER_SETTING_CHAIN, TAPER_SETTING_SOLVER,
};

/* Entry i (0-based) of the list above; -1 past its end. */
long taper_test_enum(int i);
long taper_test_enum(int i)
{
    return i >= 0 && i < (int)(sizeof enums / sizeof enums[0]) ? enums[i] : -1;
}

/* How many entries the list has. */
int taper_test_n_enums(void);
int taper_test_n_enums(void)
{
    return (int)(sizeof enums / sizeof enums[0]);
}
