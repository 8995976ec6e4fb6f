/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * scene_new.c -- the scene object: a new scene holds the defaults (the
 * table's: for the library's settings, the library's table of settings;
 * the output directory derived from the file name); its lifetime; -o DIR.
 */
#include "scene_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

void scene_free(scene *sc)
{
    if (!sc) return;
    for (size_t i = 0; i < scene_var_count(); i++) scene_field_clear(&sc->cfg, scene_var_at(i));
    free(sc->cfg.sweep.lists);
    free(sc->cfg.chain.file_radii.v);
    for (size_t i = 0; i < sc->n_diags; i++) {
        free(sc->diags[i].group);
        free(sc->diags[i].key);
        free(sc->diags[i].message);
    }
    free(sc->diags);
    free(sc->origin);
    free(sc->path);
    free(sc);
}

/* A library row's default: the library's table says it. */
static void set_library_default(const scene_var *var, scene_config *cfg)
{
    void *f = scene_field(cfg, var);
    double d = var->setting->default_value;
    switch (var->type) {
    case SCENE_REAL: memcpy(f, &d, sizeof d); break;
    case SCENE_INTEGER: {
        long long x = (long long)d;
        memcpy(f, &x, sizeof x);
        break;
    }
    case SCENE_LOGICAL:
    case SCENE_CHOICE: {
        int x = (int)d;
        memcpy(f, &x, sizeof x);
        break;
    }
    default: break; /* a list: empty */
    }
}

/* Table default text -> value.  The table's defaults are a fixed, tested
 * subset of the syntax, so this needs no error reporting beyond memory. */
static int set_table_default(const scene_var *var, scene_config *cfg)
{
    void *f = scene_field(cfg, var);
    if (var->setting) {
        set_library_default(var, cfg);
        return 0;
    }
    if (var->type == SCENE_REAL) {
        double x = var->def ? strtod(var->def, NULL) : NAN; /* NaN: none */
        memcpy(f, &x, sizeof x);
        return 0;
    }
    if (!var->def) return 0;
    switch (var->type) {
    case SCENE_STRING: {
        size_t n = strlen(var->def);
        char *s = malloc(n - 1);
        if (!s) return -1;
        memcpy(s, var->def + 1, n - 2); /* strip the quotes */
        s[n - 2] = '\0';
        *(char **)f = s;
        return 0;
    }
    case SCENE_CHOICE: {
        char name[64];
        size_t n = strlen(var->def);
        if (n - 2 >= sizeof name) return -1;
        memcpy(name, var->def + 1, n - 2);
        name[n - 2] = '\0';
        int v = 0;
        if (scene_choice_find(var, name, &v) != 0) return -1;
        memcpy(f, &v, sizeof v);
        return 0;
    }
    case SCENE_INTEGER: {
        long long x = strtoll(var->def, NULL, 10);
        memcpy(f, &x, sizeof x);
        return 0;
    }
    case SCENE_LOGICAL: {
        int b = strcasecmp(var->def, ".true.") == 0;
        memcpy(f, &b, sizeof b);
        return 0;
    }
    default: return 0;
    }
}

/* out/NAME for scene file .../NAME.nml. */
static char *derived_dir(const char *path)
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    size_t n = strlen(base);
    if (n > 4 && strcasecmp(base + n - 4, ".nml") == 0) n -= 4;
    if (n == 0) base = "scene", n = 5;
    return text_printf("out/%.*s", (int)n, base);
}

scene *scene_new(const char *path)
{
    scene *sc = calloc(1, sizeof *sc);
    if (!sc) return NULL;
    sc->from_stdin = path && strcmp(path, "-") == 0;
    sc->path = text_dup(sc->from_stdin ? "stdin" : path ? path : "<scene>");
    sc->origin = calloc(scene_var_count(), sizeof *sc->origin);
    sc->cfg.sweep.lists = calloc(scene_var_count(), sizeof *sc->cfg.sweep.lists);
    if (!sc->path || !sc->origin || !sc->cfg.sweep.lists) goto fail;
    sc->cfg.fit.model = SCENE_FIT_NONE;
    for (size_t i = 0; i < scene_var_count(); i++)
        if (set_table_default(scene_var_at(i), &sc->cfg) != 0) goto fail;
    for (size_t i = 0; i < scene_var_count(); i++) {
        if (!(scene_var_at(i)->flags & SCENE_FROM_PATH)) continue;
        char **s = scene_field(&sc->cfg, scene_var_at(i));
        free(*s);
        if (!(*s = derived_dir(sc->path))) goto fail;
    }
    sc->cfg.runs.n = 1;
    return sc;
fail:
    scene_free(sc);
    return NULL;
}

const char *scene_path(const scene *sc) { return sc->path; }
const scene_config *scene_cfg(const scene *sc) { return &sc->cfg; }

int scene_set_output_dir(scene *sc, const char *dir)
{
    char *s = text_dup(dir);
    if (!s) return -1;
    free(sc->cfg.output.dir);
    sc->cfg.output.dir = s;
    int i = scene_var_keyword("dir");
    scene_mark_given(sc, (size_t)i, 0); /* no longer from the file: messages name no line */
    return 0;
}
