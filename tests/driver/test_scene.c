/*
 * test_scene.c -- the scene parser, validation, writer and the atomic
 * output files.  Errors are checked for their line, group, key and the
 * substance of the message, since that is what a user acts on.
 */
#include "results/output.h"
#include "scene/scene.h"
#include "test_util.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Library defaults as a test fixture: the scene module must not care where
 * they come from, and distinctive values show that they are used. */
static taper_solver_spec lib_defaults(void)
{
    taper_solver_spec lib;
    memset(&lib, 0, sizeof lib);
    lib.method = TAPER_BDF;
    lib.rtol = 3e-9;
    lib.atol = 7e-13;
    lib.window = 1;
    return lib;
}

static scene *new_scene(void)
{
    taper_solver_spec lib = lib_defaults();
    scene *sc = scene_new("dir/test.nml", &lib);
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
    if (sc->n_errors) {
        scene_print_diags(sc, stderr);
        fail_msg("unexpected errors for:\n%s", text);
    }
    return sc;
}

/* ---- syntax ------------------------------------------------------------ */

static void test_basic_values(void **state)
{
    (void)state;
    scene *sc = load_ok("! a comment\n"
                        "&chain profile = 'backward_linear', s = 0.5, n_granules = 200,\n"
                        "       exponent = 2.5 /\n"
                        "&solver rtol = 1d-10, atol = 1.5e-13 method='adams' /\n"
                        "&output dir = 'out/demo' /\n");
    assert_string_equal(scene_str(sc, "chain", "profile"), "backward_linear");
    assert_double_rel(scene_real(sc, "chain", "s"), 0.5, 0);
    assert_int_equal(scene_int(sc, "chain", "n_granules"), 200);
    assert_double_rel(scene_real(sc, "solver", "rtol"), 1e-10, 0);
    assert_double_rel(scene_real(sc, "solver", "atol"), 1.5e-13, 0);
    assert_string_equal(scene_str(sc, "solver", "method"), "adams");
    assert_string_equal(scene_str(sc, "output", "dir"), "out/demo");
    assert_int_equal(scene_get(sc, "chain", "s")->line, 2);
    assert_int_equal(scene_get(sc, "chain", "exponent")->line, 3);
    scene_free(sc);
}

static void test_case_insensitive_names(void **state)
{
    (void)state;
    scene *sc = load_ok("&CHAIN PROFILE = 'Backward_Linear' S = 0.25 N_Granules = 7 /\n"
                        "&Solver METHOD = \"BDF\" /");
    /* names and allowed strings fold case; the allowed string is stored
     * in its canonical spelling */
    assert_string_equal(scene_str(sc, "chain", "profile"), "backward_linear");
    assert_string_equal(scene_str(sc, "solver", "method"), "bdf");
    assert_int_equal(scene_int(sc, "chain", "n_granules"), 7);
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
        assert_int_equal(scene_bool(sc, "solver", "numerics"), 0);
        assert_int_equal(scene_bool(sc, "output", "progress"), 1);
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
        assert_int_equal(sc->n_errors, 0);
        assert_double_rel(scene_real(sc, "solver", "t_max"), cases[i].value, 0);
        scene_free(sc);
    }
}

static void test_strings(void **state)
{
    (void)state;
    scene *sc = load_ok("&output dir = 'it''s here' /");
    assert_string_equal(scene_str(sc, "output", "dir"), "it's here");
    scene_free(sc);
    sc = load_ok("&output dir = \"a \"\"b\"\" 'c'\" /");
    assert_string_equal(scene_str(sc, "output", "dir"), "a \"b\" 'c'");
    scene_free(sc);
    sc = load_ok("&output dir = 'has ! no comment, / or = inside' /");
    assert_string_equal(scene_str(sc, "output", "dir"), "has ! no comment, / or = inside");
    scene_free(sc);
}

static void test_lists_and_continuation(void **state)
{
    (void)state;
    scene *sc = load_ok("&chain profile = 'custom'\n"
                        "  radii = 1.0, 1.2 1.5,   ! comment inside a list\n"
                        "          3*2.0,\n"
                        "          2*0.5 /\n");
    const scene_value *r = scene_get(sc, "chain", "radii");
    static const double want[] = {1.0, 1.2, 1.5, 2.0, 2.0, 2.0, 0.5, 0.5};
    assert_int_equal(r->count, 8);
    for (size_t i = 0; i < 8; i++) assert_double_rel(r->list[i], want[i], 0);
    assert_int_equal(r->line, 2);
    /* custom: n_granules follows the radii */
    assert_int_equal(scene_int(sc, "chain", "n_granules"), 8);
    taper_chain_spec spec;
    scene_chain_spec(sc, 0, &spec);
    assert_int_equal(spec.profile, TAPER_CUSTOM);
    assert_int_equal(spec.n_granules, 8);
    assert_ptr_equal(spec.radii, r->list);
    scene_free(sc);
}

static void test_separators(void **state)
{
    (void)state;
    /* commas between assignments, a trailing comma, values on the next line,
     * several groups on one line */
    scene *sc = load_ok("&chain profile='backward_linear', s=\n0.5, n_granules=\n 12, / &solver /");
    assert_double_rel(scene_real(sc, "chain", "s"), 0.5, 0);
    assert_int_equal(scene_int(sc, "chain", "n_granules"), 12);
    scene_free(sc);
}

static void test_sweep(void **state)
{
    (void)state;
    scene *sc = load_ok("&chain profile = 'backward_exponential', q = 0.1, 0.2 0.3 /");
    int sv = scene_sweep_var(sc);
    assert_int_equal(sv, scene_var_find("chain", "q"));
    taper_chain_spec spec;
    scene_chain_spec(sc, 2, &spec);
    assert_double_rel(spec.q, 0.3, 0);
    scene_chain_spec(sc, 0, &spec);
    assert_double_rel(spec.q, 0.1, 0);
    scene_free(sc);
    sc = load_ok("&chain profile = 'backward_linear', s = 0.1 /");
    assert_int_equal(scene_sweep_var(sc), -1);
    scene_free(sc);
}

/* ---- defaults ------------------------------------------------------------ */

static void test_defaults(void **state)
{
    (void)state;
    scene *sc = new_scene();
    taper_chain_spec want, got;
    taper_chain_spec_init(&want);
    scene_chain_spec(sc, 0, &got);
    /* the table's chain defaults are the library's */
    assert_int_equal(got.profile, want.profile);
    assert_int_equal(got.n_granules, want.n_granules);
    assert_double_rel(got.exponent, want.exponent, 0);
    assert_true(got.s == want.s && got.q == want.q && got.radii == NULL);
    /* solver defaults come from the library spec given to scene_new */
    taper_solver_spec s;
    memset(&s, 0, sizeof s);
    scene_solver_spec(sc, &s);
    assert_int_equal(s.method, TAPER_BDF);
    assert_double_rel(s.rtol, 3e-9, 0);
    assert_double_rel(s.atol, 7e-13, 0);
    assert_int_equal(s.window, 1);
    assert_int_equal(s.last_granule, 0);
    assert_int_equal(s.max_steps, 0);
    assert_true(scene_bool(sc, "solver", "numerics"));
    /* output dir derives from the file name */
    assert_string_equal(scene_str(sc, "output", "dir"), "out/test");
    assert_int_equal(scene_validate(sc), 0);
    scene_free(sc);
}

static void test_library_defaults_real(void **state)
{
    (void)state;
    taper_solver_spec lib;
    taper_solver_spec_init(&lib);
    scene *sc = scene_new("x.nml", &lib);
    assert_non_null(sc);
    assert_double_rel(scene_real(sc, "solver", "rtol"), lib.rtol, 0);
    assert_double_rel(scene_real(sc, "solver", "atol"), lib.atol, 0);
    assert_int_equal(scene_bool(sc, "solver", "window"), lib.window != 0);
    assert_string_equal(scene_str(sc, "solver", "method"), lib.method == TAPER_BDF ? "bdf" : "adams");
    assert_int_equal(scene_validate(sc), 0);
    scene_free(sc);
}

/* Every value of a and b equal (after a write/parse round trip). */
static void assert_same_values(const scene *a, const scene *b)
{
    for (size_t i = 0; i < scene_var_count(); i++) {
        const scene_var *var = scene_var_at(i);
        const scene_value *x = &a->values[i], *y = &b->values[i];
        if (var->type == SCENE_STRING) {
            assert_string_equal(x->str, y->str);
        } else if (var->type == SCENE_INTEGER) {
            assert_int_equal(x->ival, y->ival);
        } else if (var->type == SCENE_LOGICAL) {
            assert_int_equal(x->bval, y->bval);
        } else {
            assert_int_equal(x->count, y->count);
            for (size_t k = 0; k < x->count; k++) assert_true(x->list[k] == y->list[k]);
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
    for (size_t i = 0; i < scene_var_count(); i++)
        assert_non_null(strstr(text, scene_var_at(i)->name));
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
    {"&chain /\n&nope x = 1 /", 2, "nope", "", "unknown group"},
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
    {"&chain exponent = 2, 3 /", 1, "chain", "exponent", "one value"},
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
    {"&chain exponent = 1 /", 1, "chain", "exponent", "(1, 20]"},
    {"&chain\n profile = 'backward_linear'\n s = -0.5 /", 3, "chain", "s", "out of range"},
    {"&chain profile='backward_linear' s = 0.1, 1e9 /", 1, "chain", "s", "1e+09 is out of range"},
    {"&solver rtol = 1 /", 1, "solver", "rtol", "out of range"},
    {"&solver atol = 0 /", 1, "solver", "atol", "(0, 0.1]"},
    {"&solver t_max = -1 /", 1, "solver", "t_max", "out of range"},
    {"&chain profile = 'conical' /", 1, "chain", "profile", "'backward_linear'"},
    {"&solver method = 'rk4' /", 1, "solver", "method", "'adams', 'bdf'"},
    {"&chain profile='custom' radii = 1, 0.5, -1 /", 1, "chain", "radii", "element 3"},
    {"&output dir = '' /", 1, "output", "dir", "empty"},
    /* validation: relations */
    {"&chain profile = 'forward_linear'\n s = 0.5\n n_granules = 200 /", 2, "chain", "s",
     "n_granules < 1 + 1/s = 3"},
    {"&chain profile = 'forward_linear', n_granules = 3, s = 0.5 /", 1, "chain", "s", "<= 0"},
    {"&chain profile = 'backward_exponential', q = 1 /", 1, "chain", "q", "q < 1"},
    {"&chain profile = 'backward_linear', q = 0.1 /", 1, "chain", "q", "no effect"},
    {"&chain profile = 'forward_exponential', s = 0.1 /", 1, "chain", "s", "no effect"},
    {"&chain\n s = 0.1 /", 2, "chain", "s", "no effect"},
    {"&chain profile = 'backward_linear'\n radii = 1, 2 /", 2, "chain", "radii", "only used"},
    {"&chain profile = 'custom' /", 1, "chain", "profile", "needs radii"},
    {"&chain profile = 'custom', radii = 1 /", 1, "chain", "radii", "at least 2"},
    {"&chain profile = 'custom', radii = 2, 1 /", 1, "chain", "radii", "must be 1"},
    {"&chain profile = 'custom'\n radii = 1, 2, 3\n n_granules = 4 /", 3, "chain", "n_granules",
     "3 radii"},
    {"&chain n_granules = 10 /\n&solver last_granule = 11 /", 2, "solver", "last_granule",
     "beyond the chain"},
    {"&chain profile = 'backward_linear', s = 0.1, 0.2 /\n&chain /", 2, "chain", "", "twice"},
};

static void check_bad(const bad_case *c)
{
    scene *sc = load(c->text);
    if (sc->n_diags == 0) fail_msg("no error for: %s", c->text);
    const scene_diag *d = &sc->diags[0];
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
    assert_int_equal(sc->n_errors, 1);
    assert_int_equal(sc->diags[0].line, 2);
    assert_non_null(strstr(sc->diags[0].message, "longer than"));
    scene_free(sc);
    free(text);
}

static void test_validation_reports_all(void **state)
{
    (void)state;
    /* one pass reports every out-of-range value, each at its own line */
    scene *sc = load("&chain n_granules = 1\n exponent = 0.5 /\n&solver rtol = 2 /");
    assert_int_equal(sc->n_errors, 3);
    assert_int_equal(sc->diags[0].line, 1);
    assert_int_equal(sc->diags[1].line, 2);
    assert_int_equal(sc->diags[2].line, 3);
    scene_free(sc);
}

static void test_two_sweeps_rejected(void **state)
{
    (void)state;
    /* only the exponential profiles use q, so give both on a profile where
     * the only remaining complaint can be the double sweep */
    scene *sc = load("&chain profile='backward_linear', s = 0.1, 0.2 /");
    assert_int_equal(sc->n_errors, 0);
    scene_free(sc);
    sc = load("&chain profile='monodisperse'\n s = 0, 0\n q = 0, 0 /");
    assert_int_equal(sc->n_errors, 1);
    assert_int_equal(sc->diags[0].line, 3);
    assert_string_equal(sc->diags[0].key, "q");
    assert_non_null(strstr(sc->diags[0].message, "one variable"));
    scene_free(sc);
}

static void test_missing_file(void **state)
{
    (void)state;
    taper_solver_spec lib = lib_defaults();
    scene *sc = scene_new("/nonexistent/dir/scene.nml", &lib);
    assert_non_null(sc);
    assert_int_equal(scene_load(sc), 1);
    assert_int_equal(sc->diags[0].line, 0);
    assert_non_null(strstr(sc->diags[0].message, "cannot open"));
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
        if (sc->n_diags > 0 && !(sc->diags[0].line >= 0 && sc->diags[0].line <= lines))
            fail_msg("cut at %zu: error at line %d of %d", len, sc->diags[0].line, lines);
        scene_free(sc);
    }
    scene *sc = load_ok(text); /* and uncut it is fine */
    assert_int_equal(scene_int(sc, "chain", "n_granules"), 4);
    scene_free(sc);
}

/* ---- output ------------------------------------------------------------- */

static void test_output_atomic(void **state)
{
    (void)state;
    char dir[] = "/tmp/taper_test_out_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char sub[128], final[160], msg[256];
    snprintf(sub, sizeof sub, "%s/a/b/c", dir);
    assert_int_equal(out_mkdir_p(sub, msg, sizeof msg), 0);
    assert_int_equal(out_mkdir_p(sub, msg, sizeof msg), 0); /* exists: fine */
    snprintf(final, sizeof final, "%s/r.tsv", sub);

    out_file *f = out_open(sub, "r.tsv", msg, sizeof msg);
    assert_non_null(f);
    out_cell(f->fp, 1.5, 0);
    out_cell(f->fp, NAN, 1);
    assert_int_equal(access(final, F_OK), -1); /* nothing before commit */
    assert_int_equal(out_commit(f, msg, sizeof msg), 0);
    FILE *fp = fopen(final, "r");
    assert_non_null(fp);
    char line[64];
    assert_non_null(fgets(line, sizeof line, fp));
    fclose(fp);
    assert_string_equal(line, "1.5\tnan\n");

    f = out_open(sub, "s.tsv", msg, sizeof msg);
    assert_non_null(f);
    char tmp[256];
    snprintf(tmp, sizeof tmp, "%s", f->tmp_path);
    out_discard(f); /* leaves nothing behind */
    assert_int_equal(access(tmp, F_OK), -1);

    assert_int_equal(out_remove(sub, "r.tsv", msg, sizeof msg), 0);
    assert_int_equal(access(final, F_OK), -1);
    assert_int_equal(out_remove(sub, "r.tsv", msg, sizeof msg), 0); /* absent: fine */

    /* a directory below a regular file cannot exist (even for root) */
    fp = fopen(final, "w");
    fclose(fp);
    snprintf(sub, sizeof sub, "%s/a/b/c/r.tsv/x", dir);
    assert_int_equal(out_mkdir_p(sub, msg, sizeof msg), -1);
    assert_non_null(strstr(msg, "r.tsv"));
    assert_null(out_open(sub, "t.tsv", msg, sizeof msg));
    assert_non_null(strstr(msg, sub));
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
    out_write_table(fp, &cols);
    fclose(fp);
    assert_string_equal(text,
                        "k\tR\tm\tX0\tt_pass\tT_res\tv_peak\tt_peak\tX_pass\ttheory_v\ttheory_T\ttheory_t\n"
                        "1\t1\tnan\tnan\t0.10000000000000001\tnan\tnan\tnan\tnan\tnan\tnan\tnan\n"
                        "2\t2\tnan\tnan\tnan\tnan\tnan\tnan\tnan\tnan\tnan\tnan\n");
    free(text);
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
        cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_library_defaults_real),
        cmocka_unit_test(test_defaults_output_reparses),
        cmocka_unit_test(test_echo_reparses),
        cmocka_unit_test(test_bad_scenes),
        cmocka_unit_test(test_long_line),
        cmocka_unit_test(test_validation_reports_all),
        cmocka_unit_test(test_two_sweeps_rejected),
        cmocka_unit_test(test_missing_file),
        cmocka_unit_test(test_diag_format),
        cmocka_unit_test(test_garbage_never_crashes),
        cmocka_unit_test(test_every_truncation),
        cmocka_unit_test(test_output_atomic),
        cmocka_unit_test(test_table_output),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
