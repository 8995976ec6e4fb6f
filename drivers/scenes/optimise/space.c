/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * space.c -- the free settings of a calibration or a design and the scene
 * at a point of their space (space.h).
 */
#include "optimise/space.h"

#include "util/text.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The groups whose variables describe the run: the ones a free setting may
 * name.  &solver's too: a study of how the tolerance moves an optimum. */
static const char *const run_groups[] = {"chain", "ends", "striker", "losses", "material", "solver"};

#define MAX_FREE 32

void opt_error_clear(opt_error *e)
{
    free(e->message);
    e->message = NULL;
    e->keyword = NULL;
}

static void set_error(opt_error *e, const char *keyword, const char *fmt, ...) TEXT_PRINTF(3, 4);
static void set_error(opt_error *e, const char *keyword, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    char *m = text_vprintf(fmt, ap);
    va_end(ap);
    free(e->message);
    e->message = m ? m : text_dup("out of memory");
    e->keyword = keyword;
}

void opt_error_print(const scene *sc, const opt_error *e, FILE *fp)
{
    const char *message = e->message ? e->message : "out of memory";
    int row = e->keyword ? scene_var_keyword(e->keyword) : -1;
    if (row < 0) {
        fprintf(fp, "%s: %s\n", scene_path(sc), message);
        return;
    }
    int line = scene_line_of(sc, e->keyword);
    fprintf(fp, "%s:", scene_path(sc));
    if (line > 0) fprintf(fp, "%d:", line);
    fprintf(fp, " &%s %s: %s\n", scene_var_group((size_t)row), scene_var_name((size_t)row),
            message);
}

/* ---- the scene's own echo, without the optimiser's groups ------------------------- */

/* The echo as text, the lines of &calibrate and &design left out (a line
 * "&group" to the line "/": the echo writes every group so, and a value
 * never spans lines' ends inside a string). */
static char *base_text(const scene *sc, size_t *len)
{
    char *echo = NULL, *out = NULL;
    size_t n = 0, m = 0;
    FILE *fp = open_memstream(&echo, &n);
    if (!fp) return NULL;
    scene_write(sc, fp, 0);
    if (fclose(fp) != 0 || !echo) {
        free(echo);
        return NULL;
    }
    FILE *o = open_memstream(&out, &m);
    if (!o) {
        free(echo);
        return NULL;
    }
    int skipping = 0;
    for (char *line = echo; *line;) {
        char *nl = strchr(line, '\n');
        size_t l = nl ? (size_t)(nl - line) + 1 : strlen(line);
        if (!skipping && (strncmp(line, "&calibrate", 10) == 0 || strncmp(line, "&design", 7) == 0))
            skipping = 1;
        if (!skipping) fwrite(line, 1, l, o);
        else if (l >= 1 && line[0] == '/' && (l == 1 || line[1] == '\n')) skipping = 0;
        line += l;
    }
    free(echo);
    if (fclose(o) != 0) {
        free(out);
        return NULL;
    }
    *len = m;
    return out;
}

/* ---- names ------------------------------------------------------------------------ */

/* The lower and upper end of a variable's range from its documented text
 * ("(0, inf)", "[0, 1000]", "each in [0, 1)"; "": none). */
static void range_of(size_t row, double *lo, double *hi)
{
    *lo = -INFINITY;
    *hi = INFINITY;
    char *text = scene_var_range(row);
    const char *p = text ? text : "";
    if (strncmp(p, "each in ", 8) == 0) p += 8;
    if (*p == '(' || *p == '[') {
        char *end;
        double a = strtod(p + 1, &end);
        if (end != p + 1 && strncmp(end, ", ", 2) == 0) {
            const char *q = end + 2;
            double b = strtod(q, &end);
            if (end != q) {
                *lo = a;
                *hi = b;
            }
        }
    }
    free(text);
}

static int in_group_list(const char *group)
{
    for (size_t i = 0; i < sizeof run_groups / sizeof run_groups[0]; i++)
        if (strcmp(run_groups[i], group) == 0) return 1;
    return 0;
}

/* One name of `free`: NAME, GROUP.KEY, either with (i). */
static int resolve(const scene *sc, const char *group, const char *token, opt_param *p,
                   opt_error *e, const char *key_free)
{
    char name[96];
    size_t len = strlen(token);
    if (len >= sizeof name) {
        set_error(e, key_free, "'%.40s...' is not a variable's name", token);
        return -1;
    }
    memcpy(name, token, len + 1);
    size_t index = 0;
    char *paren = strchr(name, '(');
    if (paren) {
        char *end;
        long i = strtol(paren + 1, &end, 10);
        if (end == paren + 1 || strcmp(end, ")") != 0 || i < 1) {
            set_error(e, key_free, "'%s': an element of a list is NAME(i), i = 1, 2, ...", token);
            return -1;
        }
        index = (size_t)i;
        *paren = '\0';
    }
    int row;
    char *dot = strchr(name, '.');
    if (dot) {
        *dot = '\0';
        row = scene_var_find(name, dot + 1);
    } else {
        row = scene_var_keyword(name);
        if (row < 0) row = scene_var_find(group, name);
    }
    if (row < 0) {
        const char *near = scene_nearest_keyword(dot ? dot + 1 : name);
        if (near)
            set_error(e, key_free, "'%s' is not a variable of the scene: did you mean %s?", token,
                      near);
        else
            set_error(e, key_free, "'%s' is not a variable of the scene (taper --defaults lists "
                      "them)", token);
        return -1;
    }
    const size_t r = (size_t)row;
    const char *keyword = scene_var_keyword_at(r);
    int log_radius = strcmp(group, "design") == 0 && strcmp(keyword, "design_log_radii") == 0;
    if (!log_radius && !in_group_list(scene_var_group(r))) {
        set_error(e, key_free, "'%s' is &%s's, which does not describe the run: free settings "
                  "are variables of &chain, &ends, &striker, &losses, &material, &solver",
                  token, scene_var_group(r));
        return -1;
    }
    scene_type type = scene_var_type(r);
    const scene_config *cfg = scene_cfg(sc);
    p->row = r;
    p->index = index;
    p->log_radius = log_radius;
    if (type == SCENE_REAL_LIST) {
        const double *v;
        size_t n = 0;
        if (log_radius) {
            v = cfg->design.log_radii.v;
            n = cfg->design.log_radii.n;
        } else {
            v = scene_var_reals(sc, r, &n);
        }
        if (!index) {
            set_error(e, key_free, "'%s' is a list: name one of its values, %s(i)", token, keyword);
            return -1;
        }
        if (index > n) {
            set_error(e, key_free, "'%s': %s has %zu value%s in the scene", token, keyword, n,
                      n == 1 ? "" : "s");
            return -1;
        }
        p->scene_value = v[index - 1];
    } else if (type == SCENE_REAL || type == SCENE_INTEGER) {
        if (index) {
            set_error(e, key_free, "'%s': %s is one value, not a list", token, keyword);
            return -1;
        }
        p->integer = type == SCENE_INTEGER;
        if (p->integer) {
            p->scene_value = (double)scene_var_integer(sc, r);
        } else {
            size_t n = 0;
            const double *v = scene_var_reals(sc, r, &n);
            p->scene_value = n ? v[0] : NAN;
        }
    } else {
        set_error(e, key_free, "'%s' is a %s, not a number a %s can vary", token,
                  type == SCENE_LOGICAL ? "logical" : "choice or string",
                  strcmp(group, "design") == 0 ? "design" : "calibration");
        return -1;
    }
    if (p->integer && strcmp(group, "calibrate") == 0) {
        set_error(e, key_free, "'%s' is an integer: a calibration fits real settings (a design "
                  "scans integers)", token);
        return -1;
    }
    p->name = text_dup(token);
    if (!p->name) {
        set_error(e, key_free, "out of memory");
        return -1;
    }
    range_of(r, &p->lower, &p->upper);
    if (log_radius) p->lower = -INFINITY, p->upper = INFINITY;
    scene_var_about about;
    scene_var_describe(r, &about);
    p->unit = cfg->material.on ? about.unit : NULL;
    return 0;
}

/* ---- building the scene at a point ------------------------------------------------ */

static int set_reals(scene *sc, size_t row, const double *v, size_t n)
{
    scene_value *vals = malloc((n ? n : 1) * sizeof *vals);
    if (!vals) return -1;
    for (size_t i = 0; i < n; i++) vals[i] = (scene_value){.kind = SCENE_VALUE_REAL, .x = v[i]};
    size_t errors = scene_set_values(sc, scene_var_keyword_at(row), vals, n);
    free(vals);
    return errors ? -1 : 0;
}

static int set_one(scene *sc, size_t row, double x, int integer)
{
    scene_value v = integer ? (scene_value){.kind = SCENE_VALUE_INTEGER, .i = (long long)llround(x)}
                            : (scene_value){.kind = SCENE_VALUE_REAL, .x = x};
    return scene_set_values(sc, scene_var_keyword_at(row), &v, 1) ? -1 : 0;
}

/* One element of a list variable of sc. */
static int set_element(scene *sc, size_t row, size_t index, double x)
{
    size_t n = 0;
    const double *v = scene_var_reals(sc, row, &n);
    if (index > n) return -1;
    double *copy = malloc(n * sizeof *copy);
    if (!copy) return -1;
    memcpy(copy, v, n * sizeof *copy);
    copy[index - 1] = x;
    int rc = set_reals(sc, row, copy, n);
    free(copy);
    return rc;
}

/* The lists given in metres with &material, whose first value is R_1. */
static int scale_list(scene *sc, const char *keyword, double ratio, double r1)
{
    int row = scene_var_keyword(keyword);
    size_t n = 0;
    const double *v = scene_var_reals(sc, (size_t)row, &n);
    if (n == 0) return 0;
    double *copy = malloc(n * sizeof *copy);
    if (!copy) return -1;
    for (size_t i = 0; i < n; i++) copy[i] = v[i] * ratio;
    copy[0] = r1; /* exactly: the scene requires it */
    int rc = set_reals(sc, (size_t)row, copy, n);
    free(copy);
    return rc;
}

/* The scene's diagnostics as "&group key: message" lines (the lines of
 * the echo they would name mean nothing to the user). */
static char *diagnostics(const scene *sc)
{
    char *text = NULL;
    size_t len = 0;
    FILE *fp = open_memstream(&text, &len);
    if (!fp) return NULL;
    for (size_t i = 0; i < scene_diag_count(sc); i++) {
        const scene_diag *d = scene_diag_at(sc, i);
        fprintf(fp, "%s", i ? "; " : "");
        if (d->group[0]) fprintf(fp, "&%s ", d->group);
        if (d->key[0]) fprintf(fp, "%s: ", d->key);
        fputs(d->message, fp);
    }
    if (scene_diag_count(sc) == 0) fputs("out of memory", fp);
    fclose(fp);
    return text;
}

static double material_radius(const scene *sc)
{
    size_t n = 0;
    const double *v = scene_var_reals(sc, (size_t)scene_var_find("material", "radius"), &n);
    return n ? v[0] : 1.0;
}

/* The scene at values with R_1 (and what is given in metres with it)
 * times r1_scale. */
static scene *build(const opt_space *s, const double *values, double r1_scale, char **msg)
{
    scene *sc = scene_new(s->path);
    *msg = NULL;
    if (!sc) return NULL;
    scene_keep_samples(sc); /* the calibration samples the run itself */
    int bad = scene_parse(sc, s->text, s->text_len) != 0;
    for (size_t i = 0; !bad && i < s->n; i++) {
        const opt_param *p = &s->p[i];
        if (p->log_radius) continue;
        bad = p->index ? set_element(sc, p->row, p->index, values[i])
                       : set_one(sc, p->row, values[i], p->integer);
    }
    if (!bad && r1_scale != 1.0) {
        int r = scene_var_find("material", "radius");
        double r1 = material_radius(sc) * r1_scale;
        bad = set_one(sc, (size_t)r, r1, 0) || scale_list(sc, "radii", r1_scale, r1) ||
              scale_list(sc, "pattern", r1_scale, r1);
    }
    if (!bad && s->log_radii) {
        double c[64];
        size_t nc = s->n_log_radii < 64 ? s->n_log_radii : 64;
        memcpy(c, s->log_radii, nc * sizeof *c);
        for (size_t i = 0; i < s->n; i++)
            if (s->p[i].log_radius) c[s->p[i].index - 1] = values[i];
        long long n = scene_var_integer(sc, (size_t)scene_var_keyword("n_granules"));
        double r1 = s->material ? material_radius(sc) : 1.0;
        double *radii = n >= 2 ? malloc((size_t)n * sizeof *radii) : NULL;
        if (!radii) {
            bad = 1;
        } else {
            for (long long k = 1; k <= n; k++) {
                double x = (double)(k - 1) / (double)(n - 1), y = 0, xj = 1;
                for (size_t j = 0; j < nc; j++) y += c[j] * (xj *= x);
                radii[k - 1] = r1 * exp(y);
            }
            radii[0] = r1;
            scene_value custom = {.kind = SCENE_VALUE_STRING, .s = "custom"};
            bad = scene_set_values(sc, "profile", &custom, 1) != 0 ||
                  set_reals(sc, (size_t)scene_var_keyword("radii"), radii, (size_t)n) != 0;
            free(radii);
        }
    }
    if (!bad) bad = scene_validate(sc) != 0;
    if (bad) {
        *msg = diagnostics(sc);
        scene_free(sc);
        return NULL;
    }
    return sc;
}

/* The chain's length (sum of diameters, m) or mass (kg) of a validated
 * scene with &material; NaN if the library refuses its chain. */
static double held_quantity(const scene *sc, int hold, char **msg)
{
    scene_config at;
    scene_config_at(scene_cfg(sc), 0, &at);
    taper_error err;
    taper_chain_spec *spec = scene_chain_spec(&at, 0, &err);
    taper_chain *chain = spec ? taper_chain_alloc(spec, &err) : NULL;
    taper_chain_spec_free(spec);
    if (!chain) {
        *msg = text_printf("%s", err.message);
        return NAN;
    }
    size_t n = taper_chain_size(chain);
    const double *x = hold == SCENE_HOLD_MASS ? taper_chain_mass(chain) : taper_chain_radius(chain);
    double sum = 0;
    for (size_t k = 0; k < n; k++) sum += x[k];
    taper_chain_free(chain);
    double r1 = at.material.radius;
    if (hold == SCENE_HOLD_LENGTH) return 2.0 * sum * r1;
    scene_material_props props;
    scene_material_resolve(&at, &props);
    const double pi = 3.14159265358979323846;
    return sum * props.density * (4.0 / 3.0) * pi * r1 * r1 * r1;
}

scene *opt_scene_at(const opt_space *s, const double *values, char **msg)
{
    scene *sc = build(s, values, 1.0, msg);
    if (!sc || s->hold == SCENE_HOLD_NONE) return sc;
    double q = held_quantity(sc, s->hold, msg);
    scene_free(sc);
    if (isnan(q)) return NULL;
    /* The length is R_1 times a sum the profile fixes; the mass R_1^3
     * times one: one scaling of R_1 holds either. */
    double ratio = s->hold == SCENE_HOLD_LENGTH ? s->hold_target / q : cbrt(s->hold_target / q);
    return build(s, values, ratio, msg);
}

void opt_space_scene_values(const opt_space *s, double *values)
{
    for (size_t i = 0; i < s->n; i++) values[i] = s->p[i].scene_value;
}

/* ---- the space ---------------------------------------------------------------------- */

void opt_space_free(opt_space *s)
{
    if (!s) return;
    for (size_t i = 0; i < s->n; i++) free(s->p[i].name);
    free(s->p);
    free(s->log_radii);
    free(s->text);
    free(s->path);
    free(s);
}

/* The lists of the group: start, lower, upper. */
typedef struct lists {
    const scene_reals *start, *lower, *upper;
    const char *free, *k_free, *k_start, *k_lower, *k_upper;
} lists;

static lists lists_of(const scene_config *cfg, const char *group)
{
    if (strcmp(group, "calibrate") == 0)
        return (lists){&cfg->calibrate.start, &cfg->calibrate.lower, &cfg->calibrate.upper,
                       cfg->calibrate.free, "calibrate_free", "calibrate_start",
                       "calibrate_lower", "calibrate_upper"};
    return (lists){&cfg->design.start, &cfg->design.lower, &cfg->design.upper, cfg->design.free,
                   "design_free", "design_start", "design_lower", "design_upper"};
}

static int parse_free(const scene *sc, const char *group, const lists *l, opt_space *s,
                      opt_error *e)
{
    const char *p = l->free;
    while (*p) {
        size_t len = strcspn(p, " ,\t");
        if (len == 0) {
            p++;
            continue;
        }
        if (s->n == MAX_FREE) {
            set_error(e, l->k_free, "more than %d free settings", MAX_FREE);
            return -1;
        }
        char *token = text_printf("%.*s", (int)len, p);
        if (!token) {
            set_error(e, l->k_free, "out of memory");
            return -1;
        }
        opt_param *q = &s->p[s->n];
        memset(q, 0, sizeof *q);
        int rc = resolve(sc, group, token, q, e, l->k_free);
        free(token);
        if (rc != 0) return -1;
        for (size_t i = 0; i < s->n; i++)
            if (s->p[i].row == q->row && s->p[i].index == q->index) {
                set_error(e, l->k_free, "'%s' is named twice", q->name);
                free(q->name);
                return -1;
            }
        s->n++;
        p += len;
    }
    if (s->n == 0) {
        set_error(e, l->k_free, "no free setting: name the settings to %s (e.g. free = "
                  "'young damping')", strcmp(group, "design") == 0 ? "vary" : "fit");
        return -1;
    }
    return 0;
}

static int lengths_match(const lists *l, size_t n, opt_error *e)
{
    const scene_reals *v[] = {l->start, l->lower, l->upper};
    const char *k[] = {l->k_start, l->k_lower, l->k_upper};
    for (int i = 0; i < 3; i++)
        if (v[i]->n && v[i]->n != n) {
            set_error(e, k[i], "%zu values for %zu free settings: give one per setting, in the "
                      "order of free", v[i]->n, n);
            return -1;
        }
    return 0;
}

static int check_bounds(opt_space *s, const lists *l, int design, opt_error *e)
{
    for (size_t i = 0; i < s->n; i++) {
        opt_param *p = &s->p[i];
        if (l->lower->n) p->lower = l->lower->v[i];
        if (l->upper->n) p->upper = l->upper->v[i];
        p->start = l->start->n ? l->start->v[i] : p->scene_value;
        if (isnan(p->start)) {
            set_error(e, l->k_start, "%s has no value in the scene: give it, or its start", p->name);
            return -1;
        }
        if (design && !(isfinite(p->lower) && isfinite(p->upper))) {
            set_error(e, isfinite(p->lower) ? l->k_upper : l->k_lower, "%s: a design needs "
                      "finite bounds (they set the optimiser's scale and the figure's range): "
                      "give lower and upper", p->name);
            return -1;
        }
        if (!(p->lower < p->upper)) {
            set_error(e, l->lower->n ? l->k_lower : l->k_upper, "%s: lower = %g is not below "
                      "upper = %g", p->name, p->lower, p->upper);
            return -1;
        }
        if (!(p->start >= p->lower && p->start <= p->upper)) {
            set_error(e, l->start->n ? l->k_start : l->k_free, "%s: the start %.17g is outside "
                      "[%g, %g]", p->name, p->start, p->lower, p->upper);
            return -1;
        }
        if (p->integer && (p->lower != floor(p->lower) || p->upper != floor(p->upper) ||
                           p->upper - p->lower > 1000)) {
            set_error(e, l->k_lower, "%s is an integer, scanned from lower to upper: give whole "
                      "numbers at most 1000 apart", p->name);
            return -1;
        }
    }
    return 0;
}

opt_space *opt_space_new(const scene *sc, const char *group, opt_error *e)
{
    const scene_config *cfg = scene_cfg(sc);
    const int design = strcmp(group, "design") == 0;
    lists l = lists_of(cfg, group);
    e->message = NULL;
    e->keyword = NULL;
    opt_space *s = calloc(1, sizeof *s);
    if (!s || !(s->p = calloc(MAX_FREE, sizeof *s->p)) || !(s->path = text_dup(scene_path(sc))) ||
        !(s->text = base_text(sc, &s->text_len))) {
        set_error(e, NULL, "out of memory");
        goto fail;
    }
    s->material = cfg->material.on;
    if (cfg->runs.swept) {
        set_error(e, design ? "design_objective" : "calibrate_data", "a %s runs one chain at "
                  "each point it tries: give %s one value (a list sweeps it)",
                  design ? "design" : "calibration", scene_swept_name(cfg, 0));
        goto fail;
    }
    if (parse_free(sc, group, &l, s, e) != 0 || lengths_match(&l, s->n, e) != 0 ||
        check_bounds(s, &l, design, e) != 0)
        goto fail;
    if (design && cfg->design.log_radii.n) {
        s->n_log_radii = cfg->design.log_radii.n;
        if (s->n_log_radii > 64) {
            set_error(e, "design_log_radii", "at most 64 coefficients");
            goto fail;
        }
        if (!(s->log_radii = malloc(s->n_log_radii * sizeof *s->log_radii))) goto fail;
        memcpy(s->log_radii, cfg->design.log_radii.v, s->n_log_radii * sizeof *s->log_radii);
        taper_profile profile = (taper_profile)scene_setting(cfg, "profile");
        if (profile != TAPER_MONODISPERSE) {
            set_error(e, "design_log_radii", "log_radii make the chain's radii: give the scene "
                      "profile = 'monodisperse' (its n_granules the chain's length), not '%s'",
                      taper_profile_name(profile));
            goto fail;
        }
    }
    if (design && cfg->design.hold != SCENE_HOLD_NONE) {
        s->hold = cfg->design.hold;
        if (!cfg->material.on) {
            set_error(e, "design_hold", "holding the chain's length or mass scales R_1, which "
                      "needs real units: give &material (in rescaled units R_1 is the unit)");
            goto fail;
        }
        if (cfg->chain.radii_file[0]) {
            set_error(e, "design_hold", "the radii of radii_file cannot be scaled: give them "
                      "inline (radii), or hold = 'none'");
            goto fail;
        }
        for (size_t i = 0; i < s->n; i++)
            if (strcmp(scene_var_keyword_at(s->p[i].row), "radius") == 0) {
                set_error(e, "design_hold", "&material radius is free and hold scales it: hold "
                          "= 'none', or another free setting");
                goto fail;
            }
    }
    /* The point the scene describes: the held quantity's value, and a
     * scene that runs. */
    double values[MAX_FREE];
    opt_space_scene_values(s, values);
    char *msg = NULL;
    int hold = s->hold;
    s->hold = SCENE_HOLD_NONE;
    scene *at = build(s, values, 1.0, &msg);
    if (at && hold != SCENE_HOLD_NONE) s->hold_target = held_quantity(at, hold, &msg);
    scene_free(at);
    s->hold = hold;
    if (!at || (hold != SCENE_HOLD_NONE && isnan(s->hold_target))) {
        set_error(e, l.k_free, "the scene at its own values of the free settings is refused: %s",
                  msg ? msg : "out of memory");
        free(msg);
        goto fail;
    }
    free(msg);
    for (size_t i = 0; i < s->n; i++) values[i] = s->p[i].start;
    if (!(at = opt_scene_at(s, values, &msg))) {
        set_error(e, l.start->n ? l.k_start : l.k_free, "the scene at the start is refused: %s",
                  msg ? msg : "out of memory");
        free(msg);
        goto fail;
    }
    scene_free(at);
    return s;
fail:
    opt_space_free(s);
    if (!e->message) set_error(e, NULL, "out of memory");
    return NULL;
}
