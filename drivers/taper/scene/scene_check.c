/*
 * scene_check.c -- validation of a parsed scene: each value against its
 * table range or allowed strings, then the relations between variables.
 * Runs after parsing so that every problem is reported at once, each with
 * the line of the key and what to change.
 */
#include "scene_impl.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static int in_range(const scene_var *var, double x)
{
    int lo_ok = (var->flags & SCENE_LO_OPEN) ? x > var->lo : x >= var->lo;
    int hi_ok = (var->flags & SCENE_HI_OPEN) ? x < var->hi : x <= var->hi;
    return lo_ok && hi_ok;
}

static void range_error(scene *sc, const scene_var *var, const scene_value *v, double x)
{
    char range[96], xs[40];
    scene_range_text(var, range, sizeof range);
    scene_format_real(x, xs, sizeof xs);
    scene_error(sc, v->line, var->group, var->name, "%s is out of range: give a value in %s", xs,
                range);
}

/* Canonical lower-case spelling of an allowed string, or an error. */
static void check_choice(scene *sc, const scene_var *var, scene_value *v)
{
    for (const char *const *c = var->choices; *c; c++) {
        if (strcasecmp(*c, v->str) == 0) {
            memcpy(v->str, *c, strlen(*c) + 1); /* same length: fits */
            return;
        }
    }
    /* shown: at most 31 bytes, each up to 4 characters once scene_error
     * writes non-ASCII as \xNN, so that the list of allowed values fits. */
    char allowed[256], shown[32];
    scene_range_text(var, allowed, sizeof allowed);
    if (snprintf(shown, sizeof shown, "%s", v->str) >= (int)sizeof shown)
        memcpy(shown + sizeof shown - 4, "...", 4);
    scene_error(sc, v->line, var->group, var->name, "'%s' is not allowed: use one of %s", shown,
                allowed);
}

static void check_one(scene *sc, const scene_var *var, scene_value *v)
{
    switch (var->type) {
    case SCENE_STRING:
        if (var->choices && v->str) check_choice(sc, var, v);
        break;
    case SCENE_INTEGER:
        if (!in_range(var, (double)v->ival)) range_error(sc, var, v, (double)v->ival);
        break;
    case SCENE_REAL:
        for (size_t i = 0; i < v->count; i++)
            if (!in_range(var, v->list[i])) {
                range_error(sc, var, v, v->list[i]);
                break;
            }
        break;
    case SCENE_REAL_LIST:
        for (size_t i = 0; i < v->count; i++)
            if ((var->flags & SCENE_POSITIVE) && !(v->list[i] > 0.0)) {
                char xs[40];
                scene_format_real(v->list[i], xs, sizeof xs);
                scene_error(sc, v->line, var->group, var->name,
                            "element %zu is %s: every value must be > 0", i + 1, xs);
                break;
            }
        break;
    default:
        break;
    }
}

static scene_value *val(scene *sc, const char *group, const char *name)
{
    return &sc->values[scene_var_find(group, name)];
}

static int any_nonzero(const scene_value *v)
{
    for (size_t i = 0; i < v->count; i++)
        if (v->list[i] != 0.0) return 1;
    return 0;
}

/* s only means something for the linear profiles, q for the exponential
 * ones, radii for custom: a value given to the wrong profile is a mistake. */
static void check_unused(scene *sc, const char *profile)
{
    int linear = strstr(profile, "linear") != NULL;
    int expo = strstr(profile, "exponential") != NULL;
    scene_value *s = val(sc, "chain", "s"), *q = val(sc, "chain", "q");
    scene_value *r = val(sc, "chain", "radii");
    if (!linear && any_nonzero(s))
        scene_error(sc, s->line, "chain", "s",
                    "s has no effect with profile = '%s' (only the linear profiles use it): "
                    "remove s or change the profile", profile);
    if (!expo && any_nonzero(q))
        scene_error(sc, q->line, "chain", "q",
                    "q has no effect with profile = '%s' (only the exponential profiles use it): "
                    "remove q or change the profile", profile);
    if (strcmp(profile, "custom") != 0 && r->given)
        scene_error(sc, r->line, "chain", "radii",
                    "radii are only used with profile = 'custom': remove them or set the profile");
}

static void check_custom(scene *sc)
{
    scene_value *r = val(sc, "chain", "radii"), *n = val(sc, "chain", "n_granules");
    scene_value *p = val(sc, "chain", "profile");
    if (!r->given) {
        scene_error(sc, p->line, "chain", "profile",
                    "profile = 'custom' needs radii = R_1, R_2, ..., R_N (R_1 = 1)");
        return;
    }
    if (r->count < 2)
        scene_error(sc, r->line, "chain", "radii", "a chain needs at least 2 radii, got %zu", r->count);
    if (n->given && (size_t)n->ival != r->count)
        scene_error(sc, n->line, "chain", "n_granules",
                    "n_granules = %lld but %zu radii are given (line %d): give N radii or drop "
                    "n_granules", n->ival, r->count, r->line);
    else
        n->ival = (long long)r->count; /* resolved: N follows the radii */
    if (r->list[0] != 1.0) {
        char xs[40];
        scene_format_real(r->list[0], xs, sizeof xs);
        scene_error(sc, r->line, "chain", "radii",
                    "the first radius is the unit of length and must be 1, got %s: divide all "
                    "radii by it", xs);
    }
}

/* R_N = 1 - s (N-1) must stay positive: N < 1 + 1/s (paper, eq. r1-forw). */
static void check_forward_linear(scene *sc)
{
    scene_value *s = val(sc, "chain", "s");
    long long n = val(sc, "chain", "n_granules")->ival;
    for (size_t i = 0; i < s->count; i++) {
        double si = s->list[i];
        if (si > 0.0 && !((double)n < 1.0 + 1.0 / si)) {
            char xs[40];
            scene_format_real(si, xs, sizeof xs);
            scene_error(sc, s->line, "chain", "s",
                        "forward_linear with s = %s and n_granules = %lld gives R_N = 1 - s (N-1) "
                        "= %g <= 0: need n_granules < 1 + 1/s = %.6g or s < 1/(N-1) = %.6g",
                        xs, n, 1.0 - si * (double)(n - 1), 1.0 + 1.0 / si, 1.0 / (double)(n - 1));
            return;
        }
    }
}

static void check_backward_exponential(scene *sc)
{
    scene_value *q = val(sc, "chain", "q");
    for (size_t i = 0; i < q->count; i++) {
        if (!(q->list[i] < 1.0)) {
            char xs[40];
            scene_format_real(q->list[i], xs, sizeof xs);
            scene_error(sc, q->line, "chain", "q",
                        "backward_exponential needs q < 1 (R_k = (1-q)^(1-k)), got q = %s", xs);
            return;
        }
    }
}

static void check_optional(scene *sc, const char *profile, long long n);

static void check_relations(scene *sc)
{
    const char *profile = val(sc, "chain", "profile")->str;
    check_unused(sc, profile);
    if (strcmp(profile, "custom") == 0) check_custom(sc);
    if (strcmp(profile, "forward_linear") == 0) check_forward_linear(sc);
    if (strcmp(profile, "backward_exponential") == 0) check_backward_exponential(sc);

    scene_value *last = val(sc, "solver", "last_granule");
    long long n = val(sc, "chain", "n_granules")->ival;
    if (last->ival > n)
        scene_error(sc, last->line, "solver", "last_granule",
                    "last_granule = %lld is beyond the chain (n_granules = %lld): give 0..%lld",
                    last->ival, n, n);

    scene_value *s = val(sc, "chain", "s"), *q = val(sc, "chain", "q");
    if (s->count > 1 && q->count > 1)
        scene_error(sc, q->line, "chain", "q",
                    "only one variable may be swept at a time (s, line %d, is a list too)", s->line);
    check_optional(sc, profile, n);
    if (!val(sc, "output", "dir")->str[0])
        scene_error(sc, val(sc, "output", "dir")->line, "output", "dir",
                    "the output directory must not be empty");
}

/* The fit's tabulated parameter must be one the model has. */
static void check_fit_report(scene *sc)
{
    static const char *const params[][2] = {
        {"power", "ab"}, {"exponential", "ab"}, {"divergence_b", "abp"},
        {"divergence_c", "acp"}, {"divergence_m", "amf"},
    };
    const char *model = val(sc, "fit", "model")->str;
    scene_value *r = val(sc, "fit", "report");
    for (size_t i = 0; i < sizeof params / sizeof params[0]; i++) {
        if (strcmp(params[i][0], model) != 0) continue;
        if (!strchr(params[i][1], r->str[0]))
            scene_error(sc, r->line, "fit", "report",
                        "model '%s' has no parameter '%s': report one of %s", model, r->str,
                        params[i][1]);
    }
    scene_value *p = val(sc, "fit", "p");
    if (p->count > 0 && strcmp(model, "divergence_b") != 0 && strcmp(model, "divergence_c") != 0)
        scene_error(sc, p->line, "fit", "p",
                    "p is the fixed exponent of divergence_b and divergence_c, not of '%s': "
                    "remove it", model);
}

/* A closed-form theory column exists only for its profile. */
static void check_fit_theory(scene *sc, const char *profile)
{
    scene_value *t = val(sc, "fit", "theory");
    int expo = strstr(profile, "exponential") != NULL;
    if ((strcmp(t->str, "rate") == 0 || strcmp(t->str, "f") == 0) && !expo)
        scene_error(sc, t->line, "fit", "theory",
                    "theory = '%s' is a law of the exponential chains, not of '%s': use 'fit'",
                    t->str, profile);
    if (strcmp(t->str, "b") == 0 && strcmp(profile, "forward_linear") != 0)
        scene_error(sc, t->line, "fit", "theory",
                    "theory = 'b' (S/(1+S)) is a law of forward_linear chains: use 'fit'");
}

static void check_window(scene *sc, const char *group, const char *key, long long n)
{
    scene_value *k = val(sc, group, key);
    if (k->ival > n)
        scene_error(sc, k->line, group, key,
                    "%s = %lld is beyond the chain (n_granules = %lld)", key, k->ival, n);
}

static void check_fit(scene *sc, const char *profile, long long n)
{
    check_fit_report(sc);
    check_fit_theory(sc, profile);
    check_window(sc, "fit", "k_min", n);
    check_window(sc, "fit", "k_max", n);
    scene_value *lo = val(sc, "fit", "k_min"), *hi = val(sc, "fit", "k_max");
    if (hi->ival > 0 && hi->ival < lo->ival + 2)
        scene_error(sc, hi->line, "fit", "k_max",
                    "the window k_min = %lld .. k_max = %lld has fewer than 3 granules",
                    lo->ival, hi->ival);
}

/* Optional groups: what each needs from the others. */
static void check_optional(scene *sc, const char *profile, long long n)
{
    int fit = scene_group_active(sc, "fit");
    if (fit) check_fit(sc, profile, n);
    int sv = scene_sweep_var(sc);
    size_t points = sv < 0 ? 1 : sc->values[sv].count;
    if (scene_group_active(sc, "table")) {
        scene_value *name = val(sc, "table", "name");
        if (!fit)
            scene_error(sc, name->line, "table", "name",
                        "a table tabulates the fit: give &fit model (and x, y, window)");
        const char *lists[] = {"paper_theory", "paper_numerics"};
        for (int i = 0; i < 2; i++) {
            scene_value *l = val(sc, "table", lists[i]);
            if (l->given && l->count != points)
                scene_error(sc, l->line, "table", lists[i],
                            "%zu values for %zu runs: give one value per swept value", l->count,
                            points);
        }
    }
    if (scene_group_active(sc, "figure")) {
        check_window(sc, "figure", "k_max", n);
        scene_value *inset = val(sc, "figure", "inset");
        if (inset->bval && !fit)
            scene_error(sc, inset->line, "figure", "inset",
                        "the inset shows the fit: give &fit model (and x, y, window)");
    }
}

size_t scene_validate(scene *sc)
{
    size_t before = sc->n_errors;
    for (size_t i = 0; i < scene_var_count(); i++)
        check_one(sc, scene_var_at(i), &sc->values[i]);
    /* Relations assume each value is in range (e.g. a known profile). */
    if (sc->n_errors == before) check_relations(sc);
    return sc->n_errors - before;
}
