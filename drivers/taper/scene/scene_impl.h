/*
 * scene_impl.h -- what the scene_*.c files share and nobody else needs.
 */
#ifndef TAPER_SCENE_IMPL_H
#define TAPER_SCENE_IMPL_H

#include "scene.h"

#if defined(__GNUC__) || defined(__clang__)
#define SCENE_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define SCENE_PRINTF(a, b)
#endif

/* Limits that keep every buffer bounded whatever the input. */
#define SCENE_MAX_FILE (8u << 20)      /* bytes in a scene file                */
#define SCENE_MAX_LINE 4096            /* characters in one line               */
/* Values in one list, and in all lists of more than one value together
 * (custom radii, sweeps, table values): small enough that the echo of any
 * valid scene, up to 32 bytes a value, fits SCENE_MAX_FILE and reads back
 * (checked at compile time in scene.c). */
#define SCENE_MAX_LIST 250000

/* Records one error (line 0 / group or key NULL when unknown). */
void scene_error(scene *sc, int line, const char *group, const char *key,
                 const char *fmt, ...) SCENE_PRINTF(5, 6);

/* Frees what a value holds and zeroes it. */
void scene_value_clear(scene_value *v);

/* "string", "real", ... */
const char *scene_type_name(const scene_var *var);

/* Allowed values of var as text ("[0, 1000]", "(1, 20]", "'adams', 'bdf'"),
 * empty when anything goes. */
void scene_range_text(const scene_var *var, char *buf, size_t size);

/* Writes the value of var as namelist value text (no key). */
void scene_value_text(const scene_var *var, const scene_value *v, char *buf, size_t size);

#endif
