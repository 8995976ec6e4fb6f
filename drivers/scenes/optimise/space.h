/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * space.h -- the settings a calibration or a design varies (&calibrate
 * free, &design free), their start and bounds, and the scene at any point
 * of that space.
 *
 * A free setting is any real or integer variable of the scene's table that
 * describes the chain (&chain, &ends, &striker, &losses, &material; &solver
 * too, for studies of the tolerance), named by its one name or GROUP.KEY,
 * or an element of a real list as NAME(i) (pattern(2): a decorated chain's
 * small radius), or a coefficient of &design log_radii (a smooth custom
 * chain, design only).  Values are as a scene file gives them: SI with
 * &material.  Bounds left out are the variable's range (docs/scene.md,
 * "allowed").
 *
 * The scene at a point is made as a file's is: the scene's echo (without
 * &calibrate and &design) read again, the free settings set to the
 * point's values with scene_set_values, then validated; so a value the
 * library refuses there (an s beyond 1/(N - 1) for a forward chain) is
 * refused as in a file, and the optimum's scene, written out, reproduces
 * its run.  &design hold keeps the chain's length or mass by scaling
 * &material radius (and custom radii or a pattern with it) after the rest
 * is set.
 *
 * Not part of libtaper.
 */
#ifndef TAPER_OPT_SPACE_H
#define TAPER_OPT_SPACE_H

#include "scene/scene.h"

#include <stddef.h>

/* What a problem of the space is about, for messages that name a key of
 * the scene: the keyword of the variable at fault (calibrate_free, ...). */
typedef struct opt_error {
    char *message;          /* malloc'd                                       */
    const char *keyword;    /* the scene variable at fault, or NULL            */
} opt_error;
void opt_error_clear(opt_error *e);
/* Prints e as the scene's diagnostics are: FILE:LINE: &group key: message
 * (FILE: message without a key). */
void opt_error_print(const scene *sc, const opt_error *e, FILE *fp);

typedef struct opt_param {
    char *name;             /* as the scene names it: "young", "pattern(2)"   */
    size_t row;             /* its variable's row in the scene's table        */
    size_t index;           /* 1-based element of a list; 0: a scalar         */
    int integer;            /* an integer variable (a design scans it)       */
    int log_radius;         /* a coefficient of &design log_radii             */
    double scene_value;     /* the value the scene gives it                   */
    double start, lower, upper;
    const char *unit;       /* its SI unit with &material ("Pa"), or NULL     */
} opt_param;

typedef struct opt_space {
    char *path;             /* the scene's: messages, relative paths          */
    char *text;             /* the scene's echo without &calibrate, &design   */
    size_t text_len;
    opt_param *p;
    size_t n;
    int hold;               /* scene_design_hold                              */
    double hold_target;     /* the length (m) or mass (kg) held               */
    double *log_radii;      /* &design log_radii (NULL: none), and their number */
    size_t n_log_radii;
    int material;           /* &material is on: values in SI                  */
} opt_space;

/* The space of the group ("calibrate" or "design") of a validated scene.
 * NULL with *e on a problem of the scene's &calibrate or &design keys (an
 * unknown name, a list of the wrong length, a start outside its bounds, a
 * start the scene cannot run). */
opt_space *opt_space_new(const scene *sc, const char *group, opt_error *e);
void opt_space_free(opt_space *s);

/* The scene at values[0..n) (the free settings' values, in their order),
 * validated.  NULL with *msg (malloc'd: the scene reader's diagnostics)
 * when the scene or the library refuses the point. */
scene *opt_scene_at(const opt_space *s, const double *values, char **msg);

/* The scene's value of every free setting, in order. */
void opt_space_scene_values(const opt_space *s, double *values);

#endif
