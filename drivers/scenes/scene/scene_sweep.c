/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * scene_sweep.c -- the points of a sweep.  Any variable of the table with
 * the SCENE_SWEEP flag (reals and integers of &chain and &solver) takes a
 * list of values; several lists combine as a grid (every combination, the
 * variable later in the table fastest, like nested loops written in table
 * order) or zipped (&sweep mode = 'zip': the i-th values together).  A run
 * is one point; its configuration is the scene's with every swept variable
 * at that point's value (scene_config_at), its name NAME=VALUE[,NAME=VALUE]
 * (the run's directory).
 */
#include "scene_impl.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* At most this many runs in one scene (a grid multiplies quickly). */
#define SCENE_MAX_RUNS 10000000u

void scene_resolve_sweep(scene *sc)
{
    scene_config *cfg = &sc->cfg;
    scene_runs *runs = &cfg->runs;
    runs->n = 1;
    runs->swept = 0;
    runs->sweep = SCENE_PARAM_S;
    runs->n_swept = 0;
    size_t first = 0; /* a zipped list to compare lengths with */
    for (size_t i = 0; i < scene_var_count(); i++) {
        const scene_var *var = scene_var_at(i);
        if (!(var->flags & SCENE_SWEEP)) continue;
        size_t n = scene_row_count(cfg, i);
        if (n < 2) continue;
        if (runs->n_swept == SCENE_MAX_SWEPT) {
            scene_var_error(sc, i, "at most %d variables may be swept at once", SCENE_MAX_SWEPT);
            return;
        }
        size_t k = runs->n_swept++;
        runs->swept_row[k] = i;
        runs->swept_len[k] = n;
        if (cfg->sweep.mode == SCENE_SWEEP_ZIP) {
            if (k == 0) {
                first = i;
                runs->n = n;
            } else if (n != runs->n) {
                scene_var_error(sc, i,
                                "%zu values, but %s has %zu: zipped lists (&sweep mode = 'zip') "
                                "need the same length (or mode = 'grid': every combination)",
                                n, scene_var_at(first)->name, runs->n);
                return;
            }
        } else {
            if (runs->n > SCENE_MAX_RUNS / n) {
                scene_var_error(sc, i, "the grid has more than %u runs: split the sweep",
                                SCENE_MAX_RUNS);
                return;
            }
            runs->n *= n;
        }
    }
    runs->swept = runs->n_swept > 0;
    if (runs->n_swept == 1) {
        const char *name = scene_var_at(runs->swept_row[0])->name;
        if (strcmp(name, "q") == 0) runs->sweep = SCENE_PARAM_Q;
    }
}

size_t scene_point_index(const scene_config *cfg, size_t point, size_t k)
{
    const scene_runs *runs = &cfg->runs;
    if (k >= runs->n_swept) return 0;
    if (cfg->sweep.mode == SCENE_SWEEP_ZIP) return point < runs->swept_len[k] ? point : 0;
    size_t stride = 1;
    for (size_t j = k + 1; j < runs->n_swept; j++) stride *= runs->swept_len[j];
    return (point / stride) % runs->swept_len[k];
}

double scene_param_value(const scene_config *cfg, scene_chain_param p, size_t point)
{
    size_t row = (size_t)scene_var_keyword(p == SCENE_PARAM_Q ? "q" : "s");
    for (size_t k = 0; k < cfg->runs.n_swept; k++)
        if (cfg->runs.swept_row[k] == row)
            return scene_row_value(cfg, row, scene_point_index(cfg, point, k));
    /* Not resolved yet (before scene_validate): the list by point. */
    size_t n = scene_row_count(cfg, row);
    return scene_row_value(cfg, row, n > 1 && point < n ? point : 0);
}

double scene_swept_value(const scene_config *cfg, size_t point, size_t k)
{
    if (k >= cfg->runs.n_swept) return NAN;
    return scene_row_value(cfg, cfg->runs.swept_row[k], scene_point_index(cfg, point, k));
}

const char *scene_swept_name(const scene_config *cfg, size_t k)
{
    return k < cfg->runs.n_swept ? scene_var_at(cfg->runs.swept_row[k])->name : "";
}

int scene_swept_integer(const scene_config *cfg, size_t k)
{
    return k < cfg->runs.n_swept && scene_var_at(cfg->runs.swept_row[k])->type == SCENE_INTEGER;
}

void scene_swept_text(const scene_config *cfg, size_t point, size_t k,
                      char buf[SCENE_REAL_TEXT])
{
    double x = scene_swept_value(cfg, point, k);
    if (scene_swept_integer(cfg, k))
        snprintf(buf, SCENE_REAL_TEXT, "%lld", (long long)x);
    else
        scene_format_real(x, buf);
}

char *scene_point_name(const scene_config *cfg, size_t point)
{
    char *text = NULL;
    size_t len = 0;
    FILE *fp = open_memstream(&text, &len);
    if (!fp) return NULL;
    for (size_t k = 0; k < cfg->runs.n_swept; k++) {
        char num[SCENE_REAL_TEXT];
        scene_swept_text(cfg, point, k, num);
        fprintf(fp, "%s%s=%s", k ? "," : "", scene_swept_name(cfg, k), num);
    }
    if (fclose(fp) != 0) {
        free(text);
        return NULL;
    }
    return text;
}

void scene_config_at(const scene_config *cfg, size_t point, scene_config *at)
{
    *at = *cfg;
    for (size_t k = 0; k < cfg->runs.n_swept; k++) {
        const scene_var *var = scene_var_at(cfg->runs.swept_row[k]);
        size_t j = scene_point_index(cfg, point, k);
        void *f = scene_field(at, var);
        if (scene_var_is_list(var)) {
            scene_reals *r = f;
            r->v += j; /* a view of one value */
            r->n = 1;
        } else if (var->type == SCENE_INTEGER) {
            long long x = (long long)scene_row_value(cfg, cfg->runs.swept_row[k], j);
            memcpy(f, &x, sizeof x);
        } else {
            double x = scene_row_value(cfg, cfg->runs.swept_row[k], j);
            memcpy(f, &x, sizeof x);
        }
    }
    at->sweep.lists = NULL;
    at->runs.n = 1;
    at->runs.swept = 0;
    at->runs.n_swept = 0;
}

size_t scene_sweep_point_of(const scene_config *cfg, size_t k, size_t j)
{
    const scene_runs *runs = &cfg->runs;
    if (cfg->sweep.mode == SCENE_SWEEP_ZIP) return j;
    size_t stride = 1;
    for (size_t i = k + 1; i < runs->n_swept; i++) stride *= runs->swept_len[i];
    return j * stride;
}
