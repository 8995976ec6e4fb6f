/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * scene_diag.c -- what is said about a scene: its errors (each with the
 * file, the line, the group and the key), printed as FILE:LINE: &group
 * key: message, and the nearest names for "did you mean" -- for a file,
 * the command line and a program (the Python package) alike.  The table
 * of variables is scene.c's; this file only reads it.
 */
#include "scene_impl.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* ---- did you mean ----------------------------------------------------------- */

/* The names of the rows that match `group` (NULL: every row's keyword),
 * for taper_nearest_name (at most two edits). */
static const char *nearest(const char *group, const char *name)
{
    const size_t count = scene_var_count();
    const char **names = malloc((count ? count : 1) * sizeof *names);
    if (!names) return NULL;
    size_t n = 0;
    for (size_t i = 0; i < count; i++) {
        const scene_var *var = scene_var_at(i);
        if (!group) names[n++] = var->keyword;
        else if (strcasecmp(var->group, group) == 0) names[n++] = var->name;
    }
    const char *close = taper_nearest_name(name, names, n);
    free(names);
    return close;
}

const char *scene_nearest_key(const char *group, const char *key) { return nearest(group, key); }
const char *scene_nearest_keyword(const char *keyword) { return nearest(NULL, keyword); }

const char *scene_nearest_group(const char *group)
{
    const char *names[SCENE_N_GROUPS];
    for (size_t g = 0; g < SCENE_N_GROUPS; g++) names[g] = scene_group_name(g);
    return taper_nearest_name(group, names, SCENE_N_GROUPS);
}

/* "&chain, &ends, ..., &sweep": every group, from the list scene.c keeps. */
static char *group_list(void)
{
    size_t len = 1;
    for (size_t g = 0; g < SCENE_N_GROUPS; g++) len += strlen(scene_group_name(g)) + 3;
    char *text = malloc(len), *o = text;
    if (!text) return NULL;
    for (size_t g = 0; g < SCENE_N_GROUPS; g++)
        o += sprintf(o, "%s&%s", g ? ", " : "", scene_group_name(g));
    return text;
}

void scene_unknown_group(scene *sc, int line, const char *group)
{
    const char *close = scene_nearest_group(group);
    char *all = group_list();
    if (close)
        scene_error(sc, line, group, NULL, "unknown group: did you mean &%s? (groups: %s)", close,
                    all ? all : "out of memory");
    else
        scene_error(sc, line, group, NULL, "unknown group (groups: %s)", all ? all : "out of memory");
    free(all);
}

/* ---- errors ------------------------------------------------------------------ */

/* src with every byte that is not printable ASCII (control bytes, UTF-8,
 * Latin-1, ...) shown as \xNN, so that a message says exactly which bytes
 * the file has.  malloc'd. */
static char *escaped(const char *src)
{
    size_t n = 0;
    for (const unsigned char *c = (const unsigned char *)src; *c; c++)
        n += (*c >= 0x20 && *c < 0x7f) ? 1 : 4;
    char *dst = malloc(n + 1), *o = dst;
    if (!dst) return NULL;
    for (const unsigned char *c = (const unsigned char *)src; *c; c++) {
        if (*c >= 0x20 && *c < 0x7f)
            *o++ = (char)*c;
        else
            o += sprintf(o, "\\x%02x", *c);
    }
    *o = '\0';
    return dst;
}

static void record(scene *sc, int line, const char *group, const char *key, const char *raw)
{
    sc->n_errors++;
    if (sc->n_diags >= SCENE_MAX_DIAGS) return;
    if (!sc->diags && !(sc->diags = calloc(SCENE_MAX_DIAGS, sizeof *sc->diags))) return;
    scene_diag d = {.line = line};
    d.group = escaped(group ? group : "");
    d.key = escaped(key ? key : "");
    d.message = escaped(raw ? raw : "out of memory");
    if (!d.group || !d.key || !d.message) {
        free(d.group);
        free(d.key);
        free(d.message);
        return; /* counted in n_errors: the caller still fails */
    }
    sc->diags[sc->n_diags++] = d;
}

void scene_error(scene *sc, int line, const char *group, const char *key, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    char *raw = text_vprintf(fmt, ap);
    va_end(ap);
    record(sc, line, group, key, raw);
    free(raw);
}

/* The line to name for row i: its key's, or for a value the file left
 * out, the line its group opens (where the user would add it). */
static int var_line(const scene *sc, size_t i)
{
    if (sc->origin[i].given) return sc->origin[i].line;
    int g = scene_group_index(scene_var_at(i)->group);
    return g < 0 ? 0 : sc->group_line[g];
}

void scene_var_error(scene *sc, size_t i, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    char *raw = text_vprintf(fmt, ap);
    va_end(ap);
    record(sc, var_line(sc, i), scene_var_at(i)->group, scene_var_at(i)->name, raw);
    free(raw);
}

size_t scene_error_count(const scene *sc) { return sc->n_errors; }
size_t scene_diag_count(const scene *sc) { return sc->n_diags; }
const scene_diag *scene_diag_at(const scene *sc, size_t i)
{
    return i < sc->n_diags ? &sc->diags[i] : NULL;
}

static void print_diag(const char *path, int line, const char *group, const char *key,
                       const char *message, FILE *fp)
{
    fprintf(fp, "%s:", path);
    if (line > 0) fprintf(fp, "%d:", line);
    if (group[0]) fprintf(fp, " &%s", group);
    if (key[0]) fprintf(fp, " %s", key);
    fprintf(fp, "%s %s\n", group[0] || key[0] ? ":" : "", message);
}

void scene_print_diags(const scene *sc, FILE *fp)
{
    for (size_t i = 0; i < sc->n_diags; i++) {
        const scene_diag *d = &sc->diags[i];
        print_diag(sc->path, d->line, d->group, d->key, d->message, fp);
    }
    if (sc->n_errors > sc->n_diags)
        fprintf(fp, "%s: %zu more errors not shown\n", sc->path, sc->n_errors - sc->n_diags);
}

/* The row a library error is reported against: n_granules resolved from
 * the radii is the radii's fault. */
int scene_error_row(const scene *sc, scene_lib lib, const char *field)
{
    int i = scene_var_of_field(lib, field);
    int from_file = sc->cfg.chain.file_radii.n > 0;
    if (i >= 0 && sc->n_from_radii && strcmp(scene_var_at((size_t)i)->keyword, "n_granules") == 0)
        i = scene_var_keyword(from_file ? "radii_file" : "radii");
    /* The radii of a file are the file's. */
    if (i >= 0 && from_file && strcmp(scene_var_at((size_t)i)->keyword, "radii") == 0)
        i = scene_var_keyword("radii_file");
    return i;
}

void scene_print_library_error(const scene *sc, scene_lib lib, const taper_error *err, FILE *fp)
{
    int i = scene_error_row(sc, lib, err->field);
    if (i < 0)
        fprintf(fp, "%s: %s\n", sc->path, err->message);
    else
        print_diag(sc->path, var_line(sc, (size_t)i), scene_var_at((size_t)i)->group,
                   scene_var_at((size_t)i)->name, err->message, fp);
}

void scene_print_output_error(const scene *sc, const char *message, FILE *fp)
{
    int i = scene_var_find("output", "dir");
    int line = sc->origin[i].line;
    print_diag(sc->path, line, "output", "dir", message, fp);
}
