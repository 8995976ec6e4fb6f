/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * measurements.h -- a table of measurements for a calibration (&calibrate
 * data): what the experimenter's instruments read, in the form of taper's
 * own result files, so that a run's files are data too:
 *
 *   sensors   t, granule and one or more of x, v, f_left, f_right, force
 *             (sensors.tsv: granule k's displacement, velocity and contact
 *             forces at time t)
 *   walls     t and one or both of force_left, force_right (walls.tsv)
 *   granules  k and one or more of t_pass, T_res, v_peak, t_peak, X_pass
 *             (granules.tsv: per-granule observables of the pulse; its
 *             columns R, m, X0 and theory_* are the chain's and the
 *             theory's, not measurements, and are skipped)
 *
 * The first line that is not blank or a '#' comment names the columns,
 * each with its unit in brackets as taper writes it with &material
 * (t[s], x[m], v[m/s], force[N]) or without one (the rescaled units of
 * eq. (5)), every measured column alike; then one row per measurement,
 * values separated by tabs, blanks or commas; '#' starts a comment.  Any
 * subset of a file's rows and columns is a table.
 *
 * Every problem is an error naming FILE:LINE:COLUMN: an unknown column, a
 * unit that is not taper's for that column, a value that is not a finite
 * number (nan is not a measurement), a granule that is not a whole number
 * >= 1, a negative time, rows of the wrong length.  What needs the chain
 * (a granule beyond it, a wall it does not have, a time beyond the run) is
 * checked against the scene by meas_check.
 *
 * Not part of libtaper: the library never reads files.
 */
#ifndef TAPER_MEASUREMENTS_H
#define TAPER_MEASUREMENTS_H

#include "taper.h"

#include <stddef.h>

/* What a measured value is. */
typedef enum meas_quantity {
    MEAS_X = 0,      /* sensors: displacement of the granule from rest     */
    MEAS_V,          /* sensors: its velocity                              */
    MEAS_F_LEFT,     /* sensors: the force of its contact with k - 1       */
    MEAS_F_RIGHT,    /* sensors: ... with k + 1                            */
    MEAS_FORCE,      /* sensors: the mean of the two                       */
    MEAS_WALL_LEFT,  /* walls: the force on the left wall                  */
    MEAS_WALL_RIGHT, /* walls: ... on the right wall                       */
    MEAS_T_PASS,     /* granules: the observables of granules.tsv, in the  */
    MEAS_T_RES,      /*   order of taper_observable                        */
    MEAS_V_PEAK,
    MEAS_T_PEAK,
    MEAS_X_PASS,
    MEAS_N_QUANTITIES
} meas_quantity;

/* The column name of a quantity as taper writes it ("force", "t_pass"). */
const char *meas_quantity_name(meas_quantity q);
/* Its dimension (its unit with &material). */
taper_dimension meas_quantity_dimension(meas_quantity q);
/* The observable of a per-granule quantity (MEAS_T_PASS ...); -1 for the
 * others. */
int meas_quantity_observable(meas_quantity q);

typedef enum meas_form { MEAS_SENSORS = 0, MEAS_WALLS = 1, MEAS_GRANULES = 2 } meas_form;

/* One measured value. */
typedef struct meas_point {
    double t;           /* its time (sensors, walls); NaN for granules      */
    size_t granule;     /* sensors, granules: the granule (1-based); walls: 0 */
    meas_quantity q;
    double value;
    int line;           /* where it is in the file                          */
    int column;         /* 1-based                                          */
} meas_point;

typedef struct measurements {
    char *path;
    meas_form form;
    int si;                 /* 1: the columns carry SI units; 0: rescaled    */
    size_t n_quantities;    /* the quantities fitted, in the file's order    */
    meas_quantity quantity[MEAS_N_QUANTITIES];
    int quantity_column[MEAS_N_QUANTITIES]; /* their columns (1-based)       */
    int time_column;        /* t's or k's column                             */
    int granule_column;     /* sensors: granule's column; 0 otherwise        */
    meas_point *points;     /* in the file's order                           */
    size_t n;
    double peak[MEAS_N_QUANTITIES]; /* the largest |value| of each quantity  */
} measurements;

/* Reads the table at path.  columns: the quantities to fit, names
 * separated by blanks or commas ("force"); NULL or "": every measured
 * column of the file.  NULL on any problem, with *msg (malloc'd) naming
 * FILE:LINE:COLUMN. */
measurements *meas_read(const char *path, const char *columns, char **msg);
void meas_free(measurements *m);

/* What a table needs of the run it is compared with. */
typedef struct meas_run_limits {
    size_t n_granules;
    int wall_left, wall_right;  /* 1: that end is a wall                    */
    double t_end;               /* the scene's t_end in the table's units
                                   (SI or rescaled); 0: none given          */
    double t_max;               /* its t_max; 0: none                        */
} meas_run_limits;

/* Granules within the chain, walls the chain has, times within the run
 * (at most t_end when given, below t_max when given).  0, or -1 with *msg
 * (malloc'd) naming FILE:LINE:COLUMN. */
int meas_check(const measurements *m, const meas_run_limits *limits, char **msg);

/* The last time of a sensors or walls table (0 for granules). */
double meas_last_time(const measurements *m);

#endif
