/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * analysis.h -- the scene's &fit applied to one run: to the numerics and to
 * the exact binary-collision theory alike, and the closed-form theory value
 * a table may show instead (&fit theory).
 *
 * Not part of libtaper.
 */
#ifndef TAPER_ANALYSIS_H
#define TAPER_ANALYSIS_H

#include "results/series.h"
#include "scene/scene.h"
#include "taper.h"

typedef struct analysis_fit {
    int ok;                     /* 1: fitted                                    */
    double value, error;        /* factor * reported parameter, standard error  */
    taper_fit_result *result;   /* every parameter of the fit (NULL if !ok)     */
    char *message;              /* why not, when !ok (malloc'd)                 */
} analysis_fit;

/* One run of a scene seen by the reports (tables, figures). */
typedef struct report_point {
    double param;               /* the tabulated parameter's value (s or q)   */
    const taper_chain_spec *spec; /* the run's chain                          */
    series_source src;
    analysis_fit fit[2];        /* [SERIES_THEORY], [SERIES_NUMERICS]         */
    double theory;              /* theory column: the closed form of &fit
                                   theory, or fit[SERIES_THEORY].value        */
} report_point;

/* Every run of a scene, in the order of the sweep. */
typedef struct report {
    const scene_config *cfg;
    const char *scene_path;     /* named in the figure script                 */
    const char *dir;
    const char *param_name;     /* "s" or "q"                                 */
    size_t n;
    report_point *points;
} report;

/* Fills points[i].fit and .theory from .src and .spec (when &fit is on). */
void analysis_apply(report *r);
/* Frees what analysis_apply allocated. */
void analysis_free(report *r);

/* Fits &fit y against &fit x over granules k_min..k_max of one side
 * (SERIES_THEORY, SERIES_NUMERICS) of a run.  Never fails loudly: out->ok
 * says whether it worked, out->message why not. */
void analysis_fit_side(const scene_config *cfg, const series_source *src, int side,
                       analysis_fit *out);

/* The closed form named by &fit theory ('rate', 'f', 'b') for the chain;
 * NaN for 'fit' (the fit of the theory is used). */
double analysis_closed_theory(const scene_config *cfg, const taper_chain_spec *spec);

/* Name of the tabulated value: &fit label, or the parameter's name. */
const char *analysis_label(const scene_config *cfg);

#endif
