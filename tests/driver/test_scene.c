/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_scene.c -- the scene parser, validation (the scene's own rules and
 * the library's, each reported at its key), the typed configuration, the
 * writer and the atomic output files.  Errors are checked for their line,
 * group, key and the substance of the message, since that is what a user
 * acts on.
 */
#include "results/output.h"
#include "scene/scene.h"
#include "test_util.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static scene *new_scene(void)
{
    scene *sc = scene_new("dir/test.nml");
    assert_non_null(sc);
    return sc;
}

/* Parses and, if that worked, validates: the driver's sequence. */
static scene *load(const char *text)
{
    scene *sc = new_scene();
    if (scene_parse(sc, text, strlen(text)) == 0) scene_validate(sc);
    return sc;
}

static scene *load_ok(const char *text)
{
    scene *sc = load(text);
    if (scene_error_count(sc)) {
        scene_print_diags(sc, stderr);
        fail_msg("unexpected errors for:\n%s", text);
    }
    return sc;
}

static const scene_config *cfg_of(const scene *sc) { return scene_cfg(sc); }

/* ---- syntax ------------------------------------------------------------ */

static void test_basic_values(void **state)
{
    (void)state;
    scene *sc = load_ok("! a comment\n"
                        "&chain profile = 'backward_linear', s = 0.5, n_granules = 200,\n"
                        "       exponent = 2.5 /\n"
                        "&solver rtol = 1d-10, atol = 1.5e-13 method='adams' /\n"
                        "&output dir = 'out/demo' /\n");
    const scene_config *c = cfg_of(sc);
    assert_int_equal((taper_profile)scene_setting(c, "profile"), TAPER_BACKWARD_LINEAR);
    size_t n_s = 0;
    scene_var_reals(sc, (size_t)scene_var_keyword("s"), &n_s);
    assert_int_equal(n_s, 1);
    assert_double_rel(scene_setting(c, "s"), 0.5, 0);
    assert_int_equal((long long)scene_setting(c, "n_granules"), 200);
    assert_double_rel(scene_setting(c, "rtol"), 1e-10, 0);
    assert_double_rel(scene_setting(c, "atol"), 1.5e-13, 0);
    assert_int_equal((taper_method)scene_setting(c, "method"), TAPER_ADAMS);
    assert_string_equal(c->output.dir, "out/demo");
    assert_int_equal(scene_line_of(sc, "s"), 2);
    assert_int_equal(scene_line_of(sc, "exponent"), 3);
    assert_int_equal(scene_line_of(sc, "numerics"), 0);
    assert_int_equal(c->runs.n, 1);
    assert_int_equal(c->runs.swept, 0);
    assert_int_equal(c->runs.param, SCENE_PARAM_S);
    assert_false(c->runs.fit || c->runs.table || c->runs.figure);
    scene_free(sc);
}

static void test_case_insensitive_names(void **state)
{
    (void)state;
    scene *sc = load_ok("&CHAIN PROFILE = 'Backward_Linear' S = 0.25 N_Granules = 7 /\n"
                        "&Solver METHOD = \"BDF\" /");
    /* names and choices fold case; a choice is stored as its enum */
    assert_int_equal((taper_profile)scene_setting(cfg_of(sc), "profile"), TAPER_BACKWARD_LINEAR);
    assert_int_equal((taper_method)scene_setting(cfg_of(sc), "method"), TAPER_BDF);
    assert_int_equal((long long)scene_setting(cfg_of(sc), "n_granules"), 7);
    scene_free(sc);
}

static void test_logical_forms(void **state)
{
    (void)state;
    const char *yes[] = {"T", "t", ".t.", ".T", ".true.", ".TRUE.", "true"};
    const char *no[] = {"F", "f", ".f.", ".F", ".false.", ".False.", "false"};
    char text[128];
    for (size_t i = 0; i < sizeof yes / sizeof yes[0]; i++) {
        snprintf(text, sizeof text, "&solver numerics = %s /&output progress = %s /", no[i], yes[i]);
        scene *sc = load_ok(text);
        assert_int_equal(cfg_of(sc)->solver.numerics, 0);
        assert_int_equal(cfg_of(sc)->output.progress, 1);
        scene_free(sc);
    }
}

static void test_real_forms(void **state)
{
    (void)state;
    static const struct { const char *text; double value; } cases[] = {
        {"2", 2.0},        {"1.5e3", 1500.0}, {"1d-10", 1e-10}, {"1.5D+2", 150.0},
        {"-0", 0.0},       {"7E+250", 7e250},
        {".5", 0.5},       {"3.", 3.0},       {"+4.25", 4.25},  {"2.5E0", 2.5},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char text[128];
        snprintf(text, sizeof text, "&solver t_max = %s /", cases[i].text);
        scene *sc = load(text);
        /* every form is a valid time (-0 == 0 is in range) */
        assert_int_equal(scene_error_count(sc), 0);
        assert_double_rel(scene_setting(cfg_of(sc), "t_max"), cases[i].value, 0);
        scene_free(sc);
    }
}

static void test_strings(void **state)
{
    (void)state;
    scene *sc = load_ok("&output dir = 'it''s here' /");
    assert_string_equal(cfg_of(sc)->output.dir, "it's here");
    scene_free(sc);
    sc = load_ok("&output dir = \"a \"\"b\"\" 'c'\" /");
    assert_string_equal(cfg_of(sc)->output.dir, "a \"b\" 'c'");
    scene_free(sc);
    sc = load_ok("&output dir = 'has ! no comment, / or = inside' /");
    assert_string_equal(cfg_of(sc)->output.dir, "has ! no comment, / or = inside");
    scene_free(sc);
    /* A row of names takes a list of strings, as a Fortran namelist gives
     * a character array, and reads it as the one string of names. */
    sc = load_ok("&output columns = 'v_peak', 'theory_v' /");
    assert_string_equal(cfg_of(sc)->output.columns, "v_peak, theory_v");
    assert_int_equal(cfg_of(sc)->output.column_set, 1u << 0 | 1u << 6 | 1u << 9);
    scene_free(sc);
    sc = load_ok("&calibrate data = 'x.tsv', free = 'material.young',\n 'losses.damping' /");
    assert_string_equal(cfg_of(sc)->calibrate.free, "material.young, losses.damping");
    scene_free(sc);
    /* (A string that is one value, a path, takes one: bad_cases.) */
}

static void test_lists_and_continuation(void **state)
{
    (void)state;
    scene *sc = load_ok("&chain profile = 'custom'\n"
                        "  radii = 1.0, 1.2 1.5,   ! comment inside a list\n"
                        "          3*2.0,\n"
                        "          2*0.5 /\n");
    const scene_reals *r = scene_setting_list(cfg_of(sc), "radii");
    static const double want[] = {1.0, 1.2, 1.5, 2.0, 2.0, 2.0, 0.5, 0.5};
    assert_int_equal(r->n, 8);
    for (size_t i = 0; i < 8; i++) assert_double_rel(r->v[i], want[i], 0);
    assert_int_equal(scene_line_of(sc, "radii"), 2);
    /* custom: n_granules follows the radii */
    assert_int_equal((long long)scene_setting(cfg_of(sc), "n_granules"), 8);
    taper_error err;
    taper_chain_spec *spec = scene_chain_spec(cfg_of(sc), 0, &err);
    assert_non_null(spec);
    assert_int_equal(taper_chain_spec_profile(spec), TAPER_CUSTOM);
    assert_int_equal(taper_chain_spec_n_granules(spec), 8);
    size_t n = 0;
    const double *radii = taper_chain_spec_radii(spec, &n);
    assert_int_equal(n, 8);
    for (size_t i = 0; i < 8; i++) assert_true(radii[i] == want[i]);
    taper_chain_spec_free(spec);
    scene_free(sc);
}

static void test_separators(void **state)
{
    (void)state;
    /* commas between assignments, a trailing comma, values on the next line,
     * several groups on one line */
    scene *sc = load_ok("&chain profile='backward_linear', s=\n0.5, n_granules=\n 12, / &solver /");
    assert_double_rel(scene_setting(cfg_of(sc), "s"), 0.5, 0);
    assert_int_equal((long long)scene_setting(cfg_of(sc), "n_granules"), 12);
    scene_free(sc);
}

static void test_sweep(void **state)
{
    (void)state;
    scene *sc = load_ok("&chain profile = 'backward_exponential', q = 0.1, 0.2 0.3 /");
    const scene_config *c = cfg_of(sc);
    assert_int_equal(c->runs.swept, 1);
    assert_int_equal(c->runs.sweep, SCENE_PARAM_Q);
    assert_int_equal(c->runs.param, SCENE_PARAM_Q);
    assert_int_equal(c->runs.n, 3);
    assert_string_equal(scene_chain_param_name(c->runs.sweep), "q");
    taper_chain_spec *spec = scene_chain_spec(c, 2, NULL);
    assert_double_rel(taper_chain_spec_q(spec), 0.3, 0);
    taper_chain_spec_free(spec);
    spec = scene_chain_spec(c, 0, NULL);
    assert_double_rel(taper_chain_spec_q(spec), 0.1, 0);
    taper_chain_spec_free(spec);
    assert_double_rel(scene_param_value(c, SCENE_PARAM_Q, 1), 0.2, 0);
    scene_free(sc);
    sc = load_ok("&chain profile = 'backward_linear', s = 0.1 /");
    assert_int_equal(cfg_of(sc)->runs.swept, 0);
    assert_int_equal(cfg_of(sc)->runs.n, 1);
    scene_free(sc);
}

static void test_optional_groups(void **state)
{
    (void)state;
    scene *sc = load_ok("&chain profile = 'forward_linear', n_granules = 50, s = 0.01, 0.02 /\n"
                        "&fit model = 'divergence_b', x = 'k', y = 'v', k_min = 2, k_max = 40,\n"
                        "     report = 'b', theory = 'b', p = 1.5 /\n"
                        "&table name = 'T', paper_theory = 0.1, 0.2 /\n"
                        "&figure name = 'F', curves = 'theory', inset = T /");
    const scene_config *c = cfg_of(sc);
    assert_true(c->runs.fit && c->runs.table && c->runs.figure);
    assert_int_equal(c->fit.model, TAPER_FIT_DIVERGENCE_B);
    assert_int_equal(c->fit.y, SCENE_Q_V);
    assert_int_equal(c->fit.report, SCENE_REPORT_B);
    assert_int_equal(c->fit.theory, SCENE_THEORY_B);
    assert_int_equal(c->figure.curves, SCENE_CURVES_THEORY);
    assert_true(isnan(c->figure.inset_reference));
    assert_int_equal(c->table.paper_theory.n, 2);
    taper_error err;
    taper_fit_spec *fit = scene_fit_spec(c, &err);
    assert_non_null(fit);
    assert_int_equal(taper_fit_spec_model(fit), TAPER_FIT_DIVERGENCE_B);
    assert_double_rel(taper_fit_spec_exponent(fit), 1.5, 0);
    taper_fit_spec_free(fit);
    scene_free(sc);
}

/* ---- defaults ------------------------------------------------------------ */

static void test_defaults(void **state)
{
    (void)state;
    scene *sc = new_scene();
    const scene_config *c = cfg_of(sc);
    /* the chain and solver defaults are the library's own */
    taper_chain_spec *want = taper_chain_spec_alloc(NULL);
    taper_chain_spec *got = scene_chain_spec(c, 0, NULL);
    assert_non_null(got);
    assert_int_equal(taper_chain_spec_profile(got), taper_chain_spec_profile(want));
    assert_int_equal(taper_chain_spec_n_granules(got), taper_chain_spec_n_granules(want));
    assert_true(taper_chain_spec_exponent(got) == taper_chain_spec_exponent(want));
    assert_true(taper_chain_spec_s(got) == taper_chain_spec_s(want));
    assert_true(taper_chain_spec_q(got) == taper_chain_spec_q(want));
    size_t n = 1;
    assert_null(taper_chain_spec_radii(got, &n));
    assert_int_equal(n, 0);
    taper_chain_spec_free(want);
    taper_chain_spec_free(got);
    taper_solver_spec *lib = taper_solver_spec_alloc(NULL);
    taper_solver_spec *s = scene_solver_spec(c, NULL);
    assert_non_null(s);
    assert_int_equal(taper_solver_spec_method(s), taper_solver_spec_method(lib));
    assert_true(taper_solver_spec_rtol(s) == taper_solver_spec_rtol(lib));
    assert_true(taper_solver_spec_atol(s) == taper_solver_spec_atol(lib));
    assert_int_equal(taper_solver_spec_window(s), taper_solver_spec_window(lib));
    assert_int_equal(taper_solver_spec_last_granule(s), taper_solver_spec_last_granule(lib));
    assert_true(taper_solver_spec_t_max(s) == taper_solver_spec_t_max(lib));
    assert_int_equal(taper_solver_spec_max_steps(s), taper_solver_spec_max_steps(lib));
    taper_solver_spec_free(lib);
    taper_solver_spec_free(s);
    assert_true(c->solver.numerics);
    assert_int_equal(c->fit.model, SCENE_FIT_NONE);
    assert_true(isnan(c->fit.p));
    /* output dir derives from the file name */
    assert_string_equal(c->output.dir, "out/test");
    assert_int_equal(scene_validate(sc), 0);
    scene_free(sc);
}

/* Every value of a and b equal (after a write/parse round trip), through
 * the generic walk of the table. */
static void assert_same_values(const scene *a, const scene *b)
{
    for (size_t i = 0; i < scene_var_count(); i++) {
        scene_type t = scene_var_type(i);
        if (t == SCENE_STRING || t == SCENE_CHOICE) {
            assert_string_equal(scene_var_text(a, i), scene_var_text(b, i));
        } else if (t == SCENE_INTEGER || t == SCENE_LOGICAL) {
            assert_int_equal(scene_var_integer(a, i), scene_var_integer(b, i));
        } else {
            size_t na, nb;
            const double *x = scene_var_reals(a, i, &na), *y = scene_var_reals(b, i, &nb);
            assert_int_equal(na, nb);
            for (size_t k = 0; k < na; k++) assert_true(x[k] == y[k]);
        }
    }
}

static char *write_to_string(const scene *sc, int doc)
{
    char *text = NULL;
    size_t len = 0;
    FILE *fp = open_memstream(&text, &len);
    assert_non_null(fp);
    scene_write(sc, fp, doc);
    fclose(fp);
    return text;
}

static void test_defaults_output_reparses(void **state)
{
    (void)state;
    scene *def = new_scene();
    char *text = write_to_string(def, 1);
    /* documented: every variable appears (set or as a comment) */
    for (size_t i = 0; i < scene_var_count(); i++) assert_non_null(strstr(text, scene_var_name(i)));
    scene *again = load_ok(text);
    assert_same_values(def, again);
    free(text);
    scene_free(def);
    scene_free(again);
}

static void test_echo_reparses(void **state)
{
    (void)state;
    scene *sc = load_ok("&chain profile='custom', radii = 1, 0.1, 0.30000000000000004, 7*2.5 /\n"
                        "&solver rtol = 1.234567890123e-11, numerics = F, max_steps = 123456789012 /\n"
                        "&output dir = 'a''b c' /");
    char *text = write_to_string(sc, 0);
    scene *again = load_ok(text);
    assert_same_values(sc, again);
    free(text);
    scene_free(again);
    scene_free(sc);
}

/* A directory of 3000 characters (15 nested folders) echoes whole and
 * reads back: no buffer cuts it (it used to be cut at 1020). */
static void test_long_dir_echo(void **state)
{
    (void)state;
    char dir[3001];
    size_t o = 0;
    for (int f = 0; f < 15; f++) {
        size_t len = f < 14 ? 199 : 200; /* 14 * 199 + 200 + 14 slashes = 3000 */
        if (f) dir[o++] = '/';
        for (size_t i = 0; i < len; i++) dir[o++] = (char)('a' + (f + (int)i) % 26);
    }
    dir[o] = '\0';
    assert_int_equal(strlen(dir), 3000);
    char *text = NULL;
    size_t len = 0;
    FILE *fp = open_memstream(&text, &len);
    fprintf(fp, "&output dir = '%s' /\n", dir);
    fclose(fp);
    scene *sc = load_ok(text);
    assert_string_equal(cfg_of(sc)->output.dir, dir);
    char *echo = write_to_string(sc, 0);
    assert_non_null(strstr(echo, dir));
    scene *again = load_ok(echo);
    assert_string_equal(cfg_of(again)->output.dir, dir);
    assert_same_values(sc, again);
    free(echo);
    free(text);
    scene_free(again);
    scene_free(sc);
}

/* --set overrides one variable after the file, as if the file said so. */
static void test_set(void **state)
{
    (void)state;
    scene *sc = new_scene();
    const char *text = "&chain profile = 'backward_linear', s = 0.5 /\n&fit model = 'power' /";
    assert_int_equal(scene_parse(sc, text, strlen(text)), 0);
    assert_int_equal(scene_set(sc, "chain.s=0.1, 0.2"), 0);
    assert_int_equal(scene_set(sc, "solver.method='bdf'"), 0);
    assert_int_equal(scene_set(sc, "FIT.K_MIN=3"), 0);
    assert_int_equal(scene_validate(sc), 0);
    const scene_config *c = cfg_of(sc);
    size_t n_s = 0;
    scene_var_reals(sc, (size_t)scene_var_keyword("s"), &n_s);
    assert_int_equal(n_s, 2);
    assert_int_equal(c->runs.n, 2);
    assert_int_equal((taper_method)scene_setting(c, "method"), TAPER_BDF);
    assert_int_equal(c->fit.k_min, 3);
    assert_int_equal(scene_line_of(sc, "s"), 0); /* not from the file any more */
    char *out = NULL;
    size_t len = 0;
    FILE *fp = open_memstream(&out, &len);
    assert_int_equal(scene_print_value(sc, "fit.k_min", fp), 0);
    assert_int_equal(scene_print_value(sc, "solver.method", fp), 0);
    assert_int_equal(scene_print_value(sc, "chain.s", fp), 0);
    assert_int_equal(scene_print_value(sc, "chain.nope", fp), -1);
    assert_int_equal(scene_print_value(sc, "nogroup", fp), -1);
    fclose(fp);
    assert_string_equal(out, "3\n'bdf'\n0.1, 0.2\n");
    free(out);
    scene_free(sc);

    static const struct { const char *set, *key, *needle; } bad[] = {
        {"chain.nope=1", "nope", "no such variable"},
        {"chain.n_granules=1.5", "n_granules", "integer"},
        {"solver.method='rk4'", "method", "not allowed"},
        {"fit.k_min=3 / &chain s = 1", "k_min", "one variable"},
        {"k_min=3", "", "GROUP.KEY=VALUE"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        sc = new_scene();
        assert_true(scene_set(sc, bad[i].set) > 0);
        const scene_diag *d = scene_diag_at(sc, 0);
        assert_int_equal(d->line, 0);
        assert_string_equal(d->key, bad[i].key);
        if (!strstr(d->message, bad[i].needle))
            fail_msg("--set %s: '%s' lacks '%s'", bad[i].set, d->message, bad[i].needle);
        scene_free(sc);
    }
}

/* ---- errors ------------------------------------------------------------- */

typedef struct bad_case {
    const char *text;
    int line;
    const char *group;   /* "" when none */
    const char *key;     /* "" when none */
    const char *message; /* a substring of the message */
} bad_case;

static const bad_case bad_cases[] = {
    /* syntax */
    {"&chain /\n&nope x = 1 /", 2, "nope", "", "unknown group (groups: &chain, &ends, &striker, "
     "&losses, &material, &solver, &sensors, &output, &fit, &table, &figure, &sweep, &calibrate, &design)"},
    {"&sensor interval = 1 /", 1, "sensor", "", "unknown group: did you mean &sensors?"},
    {"&chain\n  prfile = 'x' /", 2, "chain", "prfile", "did you mean profile"},
    {"&solver\n\n  zzz = 1 /", 3, "solver", "zzz", "unknown key"},
    {"&chain n_granules 5 /", 1, "chain", "n_granules", "expected '='"},
    {"&chain\n n_granules = 5\n", 1, "chain", "", "not closed"},
    {"&chain profile = 'abc /", 1, "", "", "not closed"},
    {"&chain n_granules = , /", 1, "chain", "n_granules", "empty value"},
    {"&chain profile='custom' radii = 1,,2 /", 1, "chain", "radii", "empty value"},
    {"&chain n_granules = /", 1, "chain", "n_granules", "no value"},
    {"&chain\n&solver /", 2, "chain", "", "before &chain"},
    {"&chain / &chain /", 1, "chain", "", "given twice"},
    {"hello &chain /", 1, "", "", "expected a group"},
    {"&chain / trailing", 1, "", "", "expected a group"},
    {"&chain 'x' /", 1, "chain", "", "expected a key"},
    {"& /", 1, "", "", "group name"},
    {"&chain radii(2) = 1 /", 1, "chain", "radii(2)", "not supported"},
    {"", 0, "", "", "empty scene"},
    {"! only a comment\n\n", 0, "", "", "empty scene"},
    {"&chain /\x01\x02", 1, "", "", "binary"},
    {"&chain\n / \n\x7f", 3, "", "", "binary"},
    /* types */
    {"&chain n_granules = 1.5 /", 1, "chain", "n_granules", "integer"},
    {"&chain n_granules = 1e3 /", 1, "chain", "n_granules", "integer"},
    {"&chain n_granules = 'ten' /", 1, "chain", "n_granules", "got a string"},
    {"&chain n_granules = .true. /", 1, "chain", "n_granules", "integer"},
    {"&chain s = 'a' /", 1, "chain", "s", "real"},
    {"&chain profile = 3 /", 1, "chain", "profile", "string"},
    {"&chain profile = backward_linear /", 1, "chain", "profile", "quotes"},
    {"&output progress = 1 /", 1, "output", "progress", "logical"},
    {"&output progress = yes /", 1, "output", "progress", "not a value"},
    {"&solver window = .true., .false. /", 1, "solver", "window", "one value"},
    {"&output dir = 'a', 'b' /", 1, "output", "dir", "one value"},
    {"&chain exponent = 2, 3, 4\n n_granules = 10, 20 /\n&sweep mode = 'zip' /", 1, "chain",
     "exponent", "same length"},
    {"&chain\n\n n_granules = 10,\n n_granules = 3 /", 4, "chain", "n_granules", "line 3"},
    /* numbers */
    {"&chain s = nan /", 1, "chain", "s", "finite"},
    {"&chain s = -Inf /", 1, "chain", "s", "finite"},
    {"&chain s = Infinity /", 1, "chain", "s", "finite"},
    {"&chain exponent = 1d999 /", 1, "chain", "exponent", "range of double"},
    {"&chain exponent = 1e-999 /", 1, "chain", "exponent", "range of double"},
    {"&chain n_granules = 99999999999999999999 /", 1, "chain", "n_granules", "integer"},
    {"&chain s = 1.2.3 /", 1, "chain", "s", "not a value"},
    {"&chain s = 0x10 /", 1, "chain", "s", "not a value"},
    {"&chain s = 1e /", 1, "chain", "s", "not a value"},
    {"&chain profile='custom' radii = 0*1.0 /", 1, "chain", "radii", "repeat count 0: it must be at least 1"},
    {"&chain profile='custom' radii = 3* /", 1, "chain", "radii", "repeat"},
    {"&chain profile='custom' radii = x*1 /", 1, "chain", "radii", "repeat"},
    {"&chain profile='custom' radii = 99999999999*1 /", 1, "chain", "radii", "longer than"},
    {"&chain profile='custom' radii = 250001*1 /", 1, "chain", "radii", "longer than 250000"},
    /* all lists together: the echo of a valid scene must fit the file limit */
    {"&chain profile='custom' radii = 1, 199999*1.5\n s = 50001*0 /", 2, "chain", "s",
     "200000 in other lists: a scene's lists hold at most 250000 values in all"},
    /* validation: ranges and allowed values */
    {"&chain n_granules = 1 /", 1, "chain", "n_granules", "[2, 1e+07]"},
    {"&chain n_granules = -5 /", 1, "chain", "n_granules", "out of range"},
    {"&chain n_granules = 0 /", 1, "chain", "n_granules", "out of range"},
    {"&chain exponent = 1 /", 1, "chain", "exponent", "[1.5, 20]"},
    {"&chain\n profile = 'backward_linear'\n s = -0.5 /", 3, "chain", "s", "out of range"},
    {"&chain profile='backward_linear' s = 0.1, 1e9 /", 1, "chain", "s", "1e+09 is out of range"},
    {"&solver rtol = 1 /", 1, "solver", "rtol", "rtol = 1 is out of range [3e-16, 0.1]: below 3e-16 (1.35 rounding units of double precision) CVODE's error test cannot be met; above 0.1"},
    {"&solver atol = 0 /", 1, "solver", "atol", "(0, 0.1]"},
    {"&solver t_max = -1 /", 1, "solver", "t_max", ">= 0"},
    {"&chain profile = 'conical' /", 1, "chain", "profile", "'backward_linear'"},
    {"&solver method = 'rk4' /", 1, "solver", "method", "'adams', 'bdf'"},
    {"&chain profile='custom' radii = 1, 0.5, -1 /", 1, "chain", "radii", "radii(3) = -1"},
    {"&output dir = '' /", 1, "output", "dir", "empty"},
    /* validation: relations */
    {"&chain profile = 'forward_linear'\n s = 0.5\n n_granules = 200 /", 3, "chain", "n_granules",
     "n_granules < 1 + 1/s = 3"},
    {"&chain profile = 'forward_linear', n_granules = 3, s = 0.5 /", 1, "chain", "n_granules",
     "not positive"},
    /* a key the file leaves out: the line its group opens */
    {"&solver /\n&chain\n profile = 'forward_linear'\n s = 0.5 /", 2, "chain", "n_granules",
     "n_granules < 1 + 1/s = 3"},
    {"&chain profile = 'backward_exponential', q = 1 /", 1, "chain", "q", "q < 1"},
    {"&chain profile = 'backward_linear', q = 0.1 /", 1, "chain", "q", "no effect"},
    {"&chain profile = 'forward_exponential', s = 0.1 /", 1, "chain", "s", "no effect"},
    {"&chain\n s = 0.1 /", 2, "chain", "s", "no effect"},
    {"&chain profile = 'backward_linear'\n radii = 1, 2 /", 2, "chain", "radii", "only used"},
    {"&chain profile = 'custom' /", 1, "chain", "radii", "needs radii"},
    {"&chain profile = 'custom', radii = 1 /", 1, "chain", "radii", "a chain needs two granules"},
    {"&chain profile = 'custom', radii = 2, 1 /", 1, "chain", "radii", "must be 1"},
    {"&chain profile = 'custom'\n radii = 1, 2, 3\n n_granules = 4 /", 2, "chain", "radii",
     "3 radii but n_granules = 4"},
    /* the library's refusals, each at its key */
    {"&solver\n rtol = 1e-20 /", 2, "solver", "rtol", "1e-20"},
    {"&chain\n\n exponent = 25 /", 3, "chain", "exponent", "[1.5, 20]"},
    {"&chain profile = 'backward_exponential'\n q = 1.5 /", 2, "chain", "q", "q < 1"},
    {"&chain profile = 'backward_exponential'\n q = 1.5, 2 /", 2, "chain", "q", "q = 1.5"},
    /* a sweep whose every point breaks a relation (one bad point among
     * good ones fails that run alone: tests/sweeps/faults.sh) */
    {"&chain profile = 'forward_linear', n_granules = 50\n s = 0.5, 0.6 /", 1, "chain",
     "n_granules", "s = 0.5"},
    {"&solver method = 'bdf'\n max_steps = -3 /", 2, "solver", "max_steps", ">= 0"},
    {"&fit model = 'divergence_c', y = 'v', report = 'c'\n p = -1 /", 2, "fit", "p", "> 0"},
    {"&chain profile = 'backward_linear', s = 0.1, 0.2 /\n&chain /", 2, "chain", "", "twice"},
    /* a figure of the dynamics without them: refused before the run */
    {"&solver numerics = .false. /\n&figure name = 'f'\n curves = 'numerics' /", 3, "figure",
     "curves", "turn the numerics on"},
    /* a tapered profile whose s (q) was never given */
    {"&chain\n profile = 'forward_linear' /", 1, "chain", "s", "needs its tapering s"},
};

static void check_bad(const bad_case *c)
{
    scene *sc = load(c->text);
    if (scene_diag_count(sc) == 0) fail_msg("no error for: %s", c->text);
    const scene_diag *d = scene_diag_at(sc, 0);
    if (d->line != c->line || strcmp(d->group, c->group) != 0 || strcmp(d->key, c->key) != 0 ||
        !strstr(d->message, c->message)) {
        scene_print_diags(sc, stderr);
        fail_msg("for %s\nwanted line %d &%s %s: ...%s...", c->text, c->line, c->group, c->key,
                 c->message);
    }
    scene_free(sc);
}

static void test_bad_scenes(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof bad_cases / sizeof bad_cases[0]; i++) check_bad(&bad_cases[i]);
}

/* What the library can only check with the chain built (taper_chain_alloc,
 * taper_sim_alloc) is reported the same way, by the field it names. */
static char *library_refusal(const char *text, int sim)
{
    scene *sc = load_ok(text);
    const scene_config *c = cfg_of(sc);
    taper_error err;
    taper_chain_spec *cs = scene_chain_spec(c, 0, &err);
    assert_non_null(cs);
    taper_chain *chain = taper_chain_alloc(cs, &err);
    scene_lib lib = SCENE_LIB_CHAIN;
    if (chain && sim) {
        taper_solver_spec *ss = scene_solver_spec(c, &err);
        assert_non_null(ss);
        taper_sim *s = taper_sim_alloc(chain, ss, &err);
        assert_null(s);
        taper_solver_spec_free(ss);
        lib = SCENE_LIB_SOLVER;
    } else {
        assert_null(chain);
    }
    char *out = NULL;
    size_t len = 0;
    FILE *fp = open_memstream(&out, &len);
    scene_print_library_error(sc, lib, &err, fp);
    fclose(fp);
    taper_chain_free(chain);
    taper_chain_spec_free(cs);
    scene_free(sc);
    return out;
}

static int starts_with(const char *s, const char *prefix)
{
    return strncmp(s, prefix, strlen(prefix)) == 0;
}

static void test_library_refusals(void **state)
{
    (void)state;
    char *out = library_refusal("&chain n_granules = 10 /\n&solver\n last_granule = 11 /", 1);
    if (!starts_with(out, "dir/test.nml:3: &solver last_granule: ")) fail_msg("got: %s", out);
    free(out);
    out = library_refusal("&chain profile = 'forward_exponential'\n q = 0.5\n n_granules = 2000 /",
                          0);
    if (!starts_with(out, "dir/test.nml:3: &chain n_granules: ") ||
        !strstr(out, "at most 568 granules"))
        fail_msg("got: %s", out);
    free(out);
    /* last_granule beyond the default N = 100 */
    out = library_refusal("\n&chain profile = 'forward_exponential'\n q = 0.5 /\n"
                          "&solver last_granule = 101 /", 1);
    if (!starts_with(out, "dir/test.nml:4: &solver last_granule: ")) fail_msg("got: %s", out);
    free(out);
    /* a chain that is too long for double precision, n_granules left out of
     * a custom chain: the radii are at fault */
    out = library_refusal("&chain profile = 'custom'\n radii = 1, 1e-150 /", 0);
    if (!starts_with(out, "dir/test.nml:2: &chain radii: ")) fail_msg("got: %s", out);
    free(out);
}

/* A field the scene does not have, or none: the message alone. */
/* A program's values (the Python package) go through the same checks. */
static void test_set_values(void **state)
{
    (void)state;
    scene *sc = new_scene();
    scene_value profile = {.kind = SCENE_VALUE_STRING, .s = "Backward_Linear"};
    scene_value n = {.kind = SCENE_VALUE_INTEGER, .i = 40};
    scene_value s2[2] = {{.kind = SCENE_VALUE_REAL, .x = 0.25}, {.kind = SCENE_VALUE_REAL, .x = 0.5}};
    scene_value radius = {.kind = SCENE_VALUE_REAL, .x = 1.5};
    assert_int_equal(scene_set_values(sc, "profile", &profile, 1), 0);
    assert_int_equal(scene_set_values(sc, "n_granules", &n, 1), 0);
    assert_int_equal(scene_set_values(sc, "s", s2, 2), 0);
    assert_int_equal(scene_set_values(sc, "striker_radius", &radius, 1), 0);
    assert_int_equal(scene_validate(sc), 0);
    const scene_config *c = cfg_of(sc);
    assert_int_equal(c->runs.n, 2);
    assert_int_equal(scene_setting(c, "profile"), TAPER_BACKWARD_LINEAR);
    assert_int_equal(scene_setting(c, "n_granules"), 40);
    assert_true(scene_setting(c, "striker_radius") == 1.5);
    scene_free(sc);
    /* the scene's checks: a real for an integer, a number for a choice, an
     * unknown name, a non-finite number */
    sc = new_scene();
    scene_value half = {.kind = SCENE_VALUE_REAL, .x = 2.5};
    scene_value inf = {.kind = SCENE_VALUE_REAL, .x = INFINITY};
    assert_int_equal(scene_set_values(sc, "n_granules", &half, 1), 1);
    assert_int_equal(scene_set_values(sc, "profile", &half, 1), 1);
    assert_int_equal(scene_set_values(sc, "n_granule", &n, 1), 1);
    assert_int_equal(scene_set_values(sc, "t_end", &inf, 1), 1);
    assert_non_null(strstr(scene_diag_at(sc, 0)->message, "2.5"));
    assert_string_equal(scene_diag_at(sc, 1)->key, "profile");
    assert_non_null(strstr(scene_diag_at(sc, 3)->message, "not a finite number"));
    scene_free(sc);
}

static void test_library_error_without_key(void **state)
{
    (void)state;
    scene *sc = load_ok("&chain /");
    taper_error err = {.status = TAPER_ESOLVER, .field = NULL, .message = "CVODE failed"};
    char *out = NULL;
    size_t len = 0;
    FILE *fp = open_memstream(&out, &len);
    scene_print_library_error(sc, SCENE_LIB_SOLVER, &err, fp);
    err.field = "sample_interval"; /* a setting no scene variable is */
    scene_print_library_error(sc, SCENE_LIB_SOLVER, &err, fp);
    /* Every setting of the library's table is a variable, found whichever
     * spec reported it (taper_sim_alloc checks the chain with the solver). */
    err.field = "max_order";
    scene_print_library_error(sc, SCENE_LIB_SOLVER, &err, fp);
    err.field = "rtol";
    scene_print_library_error(sc, SCENE_LIB_CHAIN, &err, fp);
    fclose(fp);
    assert_string_equal(out, "dir/test.nml: CVODE failed\ndir/test.nml: CVODE failed\n"
                             "dir/test.nml: &solver max_order: CVODE failed\n"
                             "dir/test.nml: &solver rtol: CVODE failed\n");
    free(out);
    scene_free(sc);
}

static void test_long_line(void **state)
{
    (void)state;
    size_t n = 100000;
    char *text = malloc(n + 32);
    assert_non_null(text);
    strcpy(text, "&chain\n s = 0.1 ");
    memset(text + strlen(text), ' ', n);
    strcpy(text + n, "/\n");
    scene *sc = load(text);
    assert_int_equal(scene_error_count(sc), 1);
    assert_int_equal(scene_diag_at(sc, 0)->line, 2);
    assert_non_null(strstr(scene_diag_at(sc, 0)->message, "longer than"));
    scene_free(sc);
    free(text);
}

static void test_validation_reports_all(void **state)
{
    (void)state;
    /* one pass reports every refused value, each at its own line */
    scene *sc = load("&chain n_granules = 1\n exponent = 0.5 /\n&solver rtol = 2 /");
    assert_int_equal(scene_error_count(sc), 3);
    assert_int_equal(scene_diag_at(sc, 0)->line, 1);
    assert_int_equal(scene_diag_at(sc, 1)->line, 2);
    assert_int_equal(scene_diag_at(sc, 2)->line, 3);
    scene_free(sc);
    /* a sweep value the library refuses is reported once, at the sweep */
    sc = load("&chain profile = 'backward_linear'\n s = 0.1, -1, 2000, 0.2 /");
    assert_int_equal(scene_error_count(sc), 1);
    assert_int_equal(scene_diag_at(sc, 0)->line, 2);
    assert_non_null(strstr(scene_diag_at(sc, 0)->message, "s = -1"));
    scene_free(sc);
}

/* Lists of several variables make a grid (or zipped runs);
 * zipped lists of unequal lengths are refused at the later one. */
static void test_two_sweeps_rejected(void **state)
{
    (void)state;
    scene *sc = load("&chain profile='backward_linear', s = 0.1, 0.2 /");
    assert_int_equal(scene_error_count(sc), 0);
    scene_free(sc);
    sc = load("&chain profile='monodisperse'\n s = 0, 0\n q = 0, 0, 0 /");
    assert_int_equal(scene_error_count(sc), 0);
    assert_int_equal(cfg_of(sc)->runs.n, 6);
    scene_free(sc);
    sc = load("&chain profile='monodisperse'\n s = 0, 0\n q = 0, 0, 0 /\n&sweep mode='zip' /");
    assert_int_equal(scene_error_count(sc), 1);
    assert_int_equal(scene_diag_at(sc, 0)->line, 3);
    assert_string_equal(scene_diag_at(sc, 0)->key, "q");
    assert_non_null(strstr(scene_diag_at(sc, 0)->message, "same length"));
    scene_free(sc);
}

static void test_missing_file(void **state)
{
    (void)state;
    scene *sc = scene_new("/nonexistent/dir/scene.nml");
    assert_non_null(sc);
    assert_int_equal(scene_load(sc), 1);
    assert_int_equal(scene_diag_at(sc, 0)->line, 0);
    assert_non_null(strstr(scene_diag_at(sc, 0)->message, "cannot open"));
    char *text = NULL;
    size_t len = 0;
    FILE *fp = open_memstream(&text, &len);
    scene_print_diags(sc, fp);
    fclose(fp);
    assert_string_equal(text, "/nonexistent/dir/scene.nml: cannot open: No such file or directory\n");
    free(text);
    scene_free(sc);
}

static void test_diag_format(void **state)
{
    (void)state;
    scene *sc = load("&chain\n s = nan /");
    char *text = NULL;
    size_t len = 0;
    FILE *fp = open_memstream(&text, &len);
    scene_print_diags(sc, fp);
    fclose(fp);
    assert_string_equal(text, "dir/test.nml:2: &chain s: 'nan' is not a finite number\n");
    free(text);
    scene_free(sc);
}

/* Messages are as long as they need to be: a long unknown string is shown
 * cut with "..." (a mark, not a silent cut), the list of choices whole. */
static void test_long_messages(void **state)
{
    (void)state;
    char text[600];
    snprintf(text, sizeof text, "&figure name = 'x', curves = '%0300d' /", 7);
    scene *sc = load(text);
    const scene_diag *d = scene_diag_at(sc, 0);
    assert_non_null(d);
    assert_non_null(strstr(d->message, "...' is not allowed"));
    assert_non_null(strstr(d->message, "'both', 'theory', 'numerics'"));
    scene_free(sc);
    sc = load("&figure\n nme = 'x' /");
    d = scene_diag_at(sc, 0);
    /* every key of &figure is listed */
    assert_non_null(strstr(d->message, "inset_reference"));
    scene_free(sc);
}

/* Whatever the bytes, parsing and validation return (ASan/valgrind turn
 * any out-of-bounds access here into a failure). */
static void test_garbage_never_crashes(void **state)
{
    (void)state;
    static const char seed[] = "&chain profile='custom', radii = 1, 2*1.5 3, n_granules=4 /\n"
                               "&solver rtol=1d-10, window=.t., method=\"bdf\" /\n"
                               "&output dir='o''k' progress=F /\n";
    static const char alphabet[] = "&/=,'\"!*.-+de0123456789 \n\tabcTF()";
    uint64_t x = 88172645463325252ull;
    char buf[sizeof seed + 16];
    for (int iter = 0; iter < 20000; iter++) {
        memcpy(buf, seed, sizeof seed);
        size_t len = sizeof seed - 1;
        for (int m = 0; m < 1 + iter % 6 && len > 0; m++) {
            x ^= x << 13, x ^= x >> 7, x ^= x << 17; /* xorshift64 */
            size_t at = (size_t)(x % len);
            if (iter % 3 == 0)
                buf[at] = (char)(x >> 32); /* any byte */
            else if (iter % 3 == 1)
                buf[at] = alphabet[(x >> 24) % (sizeof alphabet - 1)];
            else
                len = at; /* truncate */
        }
        scene *sc = new_scene();
        if (scene_parse(sc, buf, len) == 0) scene_validate(sc);
        scene_free(sc);
    }
}

/* A scene cut at every byte: either it still parses, or the first error
 * names a line that exists. */
static void test_every_truncation(void **state)
{
    (void)state;
    static const char text[] = "! demo\n&chain profile = 'custom',\n  radii = 1, 2*1.5,\n  0.5 /\n"
                               "&solver rtol = 1d-9, window = .false. /\n&output dir = \"o\" /\n";
    for (size_t len = 0; len < sizeof text; len++) {
        int lines = 1;
        for (size_t i = 0; i < len; i++) lines += text[i] == '\n';
        scene *sc = new_scene();
        if (scene_parse(sc, text, len) == 0) scene_validate(sc);
        const scene_diag *d = scene_diag_at(sc, 0);
        if (d && !(d->line >= 0 && d->line <= lines))
            fail_msg("cut at %zu: error at line %d of %d", len, d->line, lines);
        scene_free(sc);
    }
    scene *sc = load_ok(text); /* and uncut it is fine */
    assert_int_equal((long long)scene_setting(cfg_of(sc), "n_granules"), 4);
    scene_free(sc);
}

/* ---- output ------------------------------------------------------------- */

static void test_output_atomic(void **state)
{
    (void)state;
    char dir[] = "/tmp/taper_test_out_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char sub[128], final[160];
    char *msg = NULL;
    snprintf(sub, sizeof sub, "%s/a/b/c", dir);
    assert_int_equal(out_mkdir_p(sub, &msg), 0);
    assert_int_equal(out_mkdir_p(sub, &msg), 0); /* exists: fine */
    snprintf(final, sizeof final, "%s/r.tsv", sub);

    out_file *f = out_open(sub, "r.tsv", &msg);
    assert_non_null(f);
    out_cell(f->fp, 1.5, 0);
    out_cell(f->fp, NAN, 1);
    assert_int_equal(access(final, F_OK), -1); /* nothing before commit */
    assert_int_equal(out_commit(f, &msg), 0);
    FILE *fp = fopen(final, "r");
    assert_non_null(fp);
    char line[64];
    assert_non_null(fgets(line, sizeof line, fp));
    fclose(fp);
    assert_string_equal(line, "1.5\tnan\n");

    f = out_open(sub, "s.tsv", &msg);
    assert_non_null(f);
    char tmp[256];
    snprintf(tmp, sizeof tmp, "%s", f->tmp_path);
    out_discard(f); /* leaves nothing behind */
    assert_int_equal(access(tmp, F_OK), -1);

    assert_int_equal(out_remove(sub, "r.tsv", &msg), 0);
    assert_int_equal(access(final, F_OK), -1);
    assert_int_equal(out_remove(sub, "r.tsv", &msg), 0); /* absent: fine */

    /* a directory below a regular file cannot exist (even for root) */
    fp = fopen(final, "w");
    fclose(fp);
    snprintf(sub, sizeof sub, "%s/a/b/c/r.tsv/x", dir);
    assert_int_equal(out_mkdir_p(sub, &msg), -1);
    assert_non_null(strstr(msg, "r.tsv"));
    free(msg);
    assert_null(out_open(sub, "t.tsv", &msg));
    assert_non_null(strstr(msg, sub));
    free(msg);
    char cmd[200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    assert_int_equal(system(cmd), 0);
}

static void test_table_output(void **state)
{
    (void)state;
    double a[] = {1, 2}, b[] = {0.1, NAN};
    out_columns cols = {.n = 2};
    cols.col[1] = a;
    cols.col[4] = b;
    char *text = NULL;
    size_t len = 0;
    FILE *fp = open_memstream(&text, &len);
    out_file mem = {.fp = fp, .slot = -1}; /* not stoppable: no signal check */
    out_write_header(fp, &cols, NULL);
    out_write_rows(&mem, &cols, NULL, 0);
    fclose(fp);
    assert_string_equal(text,
                        "k\tR\tm\tX0\tt_pass\tT_res\tv_peak\tt_peak\tX_pass\ttheory_v\ttheory_T\ttheory_t\n"
                        "1\t1\tnan\tnan\t0.1\tnan\tnan\tnan\tnan\tnan\tnan\tnan\n"
                        "2\t2\tnan\tnan\tnan\tnan\tnan\tnan\tnan\tnan\tnan\tnan\n");
    free(text);
}

/* &output columns and every: the chosen columns (k always), rows 1, 1 +
 * every, ... and the last. */
static void test_table_columns_every(void **state)
{
    (void)state;
    double a[] = {1, 2, 3, 4, 5, 6}, b[] = {10, 20, 30, 40, 50, 60};
    out_columns cols = {.n = 6, .every = 4};
    cols.col[1] = a;
    cols.col[6] = b;
    cols.set = 1u << 0 | 1u << 6;
    char *text = NULL;
    size_t len = 0;
    FILE *fp = open_memstream(&text, &len);
    out_file mem = {.fp = fp, .slot = -1};
    out_write_header(fp, &cols, "s");
    out_write_rows(&mem, &cols, "s", 0.5);
    fclose(fp);
    assert_string_equal(text, "s\tk\tv_peak\n0.5\t1\t10\n0.5\t5\t50\n0.5\t6\t60\n");
    free(text);

    scene *sc = load_ok("&output columns = 'v_peak, theory_v' every = 10 /");
    assert_int_equal(cfg_of(sc)->output.column_set, 1u << 0 | 1u << 6 | 1u << 9);
    assert_int_equal(cfg_of(sc)->output.every, 10);
    scene_free(sc);
    sc = load_ok("&solver numerics = .false. /");
    assert_int_equal(cfg_of(sc)->output.column_set, 0xfu | 0xeu << 8);
    scene_free(sc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_basic_values),
        cmocka_unit_test(test_case_insensitive_names),
        cmocka_unit_test(test_logical_forms),
        cmocka_unit_test(test_real_forms),
        cmocka_unit_test(test_strings),
        cmocka_unit_test(test_lists_and_continuation),
        cmocka_unit_test(test_separators),
        cmocka_unit_test(test_sweep),
        cmocka_unit_test(test_optional_groups),
        cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_defaults_output_reparses),
        cmocka_unit_test(test_echo_reparses),
        cmocka_unit_test(test_long_dir_echo),
        cmocka_unit_test(test_set),
        cmocka_unit_test(test_bad_scenes),
        cmocka_unit_test(test_library_refusals),
        cmocka_unit_test(test_set_values),
        cmocka_unit_test(test_library_error_without_key),
        cmocka_unit_test(test_long_line),
        cmocka_unit_test(test_table_columns_every),
        cmocka_unit_test(test_validation_reports_all),
        cmocka_unit_test(test_two_sweeps_rejected),
        cmocka_unit_test(test_missing_file),
        cmocka_unit_test(test_diag_format),
        cmocka_unit_test(test_long_messages),
        cmocka_unit_test(test_garbage_never_crashes),
        cmocka_unit_test(test_every_truncation),
        cmocka_unit_test(test_output_atomic),
        cmocka_unit_test(test_table_output),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
