/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * test_scene_physics.c -- the scene side of the models beyond the paper: the new variables
 * stay out of the echo of a scene that does not give them (the paper's
 * scenes echo as before) and read back from the echo of one that does;
 * &material's relative densities, compliances and unit scales against the
 * formulas written out here; radii files and their errors at FILE:LINE;
 * the scene's own refusals at their keys; sweeps of the new variables.
 */
#include "scene/scene.h"
#include "test_util.h"
#include "util/text.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static scene *load_at(const char *path, const char *text)
{
    scene *sc = scene_new(path);
    assert_non_null(sc);
    if (scene_parse(sc, text, strlen(text)) == 0) scene_validate(sc);
    return sc;
}

static scene *load(const char *text) { return load_at("dir/test.nml", text); }

static scene *load_ok(const char *text)
{
    scene *sc = load(text);
    if (scene_error_count(sc)) {
        scene_print_diags(sc, stderr);
        fail_msg("unexpected errors for:\n%s", text);
    }
    return sc;
}

/* The echo (scene_write) as a string, malloc'd. */
static char *echo_of(const scene *sc)
{
    char *text = NULL;
    size_t len = 0;
    FILE *fp = open_memstream(&text, &len);
    assert_non_null(fp);
    scene_write(sc, fp, 0);
    fclose(fp);
    return text;
}

/* The first diagnostic is at group/key, its message containing `words`. */
static void assert_refused(const char *text, const char *group, const char *key,
                           const char *words)
{
    scene *sc = load(text);
    if (scene_diag_count(sc) == 0) fail_msg("accepted:\n%s", text);
    const scene_diag *d = scene_diag_at(sc, 0);
    if (strcmp(d->group, group) != 0 || strcmp(d->key, key) != 0 || !strstr(d->message, words))
        fail_msg("&%s %s: %s\nwanted &%s %s: ...%s... for:\n%s", d->group, d->key, d->message,
                 group, key, words, text);
    scene_free(sc);
}

/* ---- the echo -------------------------------------------------------------------- */

static void test_echo_leaves_out_what_is_not_given(void **state)
{
    (void)state;
    scene *sc = load_ok("&chain profile = 'backward_linear', s = 0.1 /\n");
    char *echo = echo_of(sc);
    static const char *const absent[] = {"&ends", "&striker", "&losses", "&material", "&sensors",
                                         "load", "pattern", "disorder", "seed", "radii_file",
                                         "t_end", "units"};
    for (size_t i = 0; i < sizeof absent / sizeof absent[0]; i++)
        if (strstr(echo, absent[i])) fail_msg("the echo of a paper scene has '%s':\n%s", absent[i], echo);
    free(echo);
    scene_free(sc);

    /* Given: the group, with only what was given. */
    sc = load_ok("&chain n_granules = 20 /\n&ends right = 'wall' /\n");
    echo = echo_of(sc);
    assert_non_null(strstr(echo, "&ends\n  right = 'wall'\n/\n"));
    assert_null(strstr(echo, "left"));
    assert_null(strstr(echo, "&striker"));
    free(echo);
    scene_free(sc);
}

/* Every new group given: the echo parses to the same configuration. */
static void test_echo_reads_back(void **state)
{
    (void)state;
    const char *text =
        "&chain profile = 'monodisperse', n_granules = 30, load = 0.25,\n"
        "  disorder = 'mass', disorder_amplitude = 0.05, seed = 12345678901 /\n"
        "&ends right = 'wall' /\n"
        "&striker radius = 1.5 /\n"
        "&losses damping = 0.01, drag = 0.002 /\n"
        "&material young = 193e9, poisson = 0.3, density = 8000, radius = 4.76e-3,\n"
        "  velocity = 0.5, other_young = 110e9, other_poisson = 0.34, other_density = 8500,\n"
        "  sequence = 1, 1, 2, wall = 2, striker = 2 /\n"
        "&solver t_end = 80 /\n"
        "&sensors interval = 0.5, granules = 3, 17, spacetime = .true.,\n"
        "  spacetime_granules = 10, spacetime_times = 40 /\n"
        "&output units = 'si' /\n";
    scene *a = load_ok(text);
    char *echo = echo_of(a);
    scene *b = load_ok(echo);
    const scene_config *x = scene_cfg(a), *y = scene_cfg(b);
    assert_double_rel(scene_setting(y, "load"), 0.25, 0);
    assert_int_equal(scene_setting(y, "disorder"), TAPER_DISORDER_MASS);
    assert_double_rel(scene_setting(y, "disorder_amplitude"), scene_setting(x, "disorder_amplitude"), 0);
    assert_true(scene_setting(y, "seed") == 12345678901.0);
    assert_int_equal(scene_setting(y, "left"), TAPER_END_FREE);
    assert_int_equal(scene_setting(y, "right"), TAPER_END_WALL);
    assert_double_rel(scene_setting(y, "striker_radius"), 1.5, 0);
    assert_double_rel(scene_setting(y, "damping"), 0.01, 0);
    assert_double_rel(scene_setting(y, "drag"), 0.002, 0);
    assert_true(y->material.on);
    assert_double_rel(y->material.young, 193e9, 0);
    assert_double_rel(y->material.radius, 4.76e-3, 0);
    assert_int_equal(y->material.sequence.n, 3);
    assert_double_rel(y->material.sequence.v[2], 2, 0);
    assert_int_equal(y->material.wall, 2);
    assert_double_rel(scene_setting(y, "t_end"), 80, 0);
    assert_double_rel(y->sensors.interval, 0.5, 0);
    assert_int_equal(y->sensors.granules.n, 2);
    assert_true(y->sensors.spacetime);
    assert_int_equal(y->sensors.spacetime_times, 40);
    assert_int_equal(y->output.units, SCENE_UNITS_SI);
    char *again = echo_of(b);
    assert_string_equal(echo, again);
    free(again);
    free(echo);
    scene_free(a);
    scene_free(b);
}

/* ---- materials and units ------------------------------------------------------------ */

static double compliance(double e, double nu) { return (1 - nu * nu) / e; }

static void test_material_props(void **state)
{
    (void)state;
    scene *sc = load_ok("&chain n_granules = 5 /\n&ends right = 'wall' /\n&striker radius = 2 /\n"
                        "&material young = 193e9, poisson = 0.3, density = 8000,\n"
                        "  radius = 4.76e-3, velocity = 0.5, other_young = 110e9, 70e9,\n"
                        "  other_poisson = 0.34, 0.33, other_density = 8500, 2700,\n"
                        "  sequence = 1, 2, wall = 3, striker = 2 /\n");
    const scene_config *c = scene_cfg(sc);
    scene_material_props p;
    assert_int_equal(scene_material_resolve(c, &p), 0);
    double c1 = compliance(193e9, 0.3);
    assert_double_rel(p.wall_compliance, compliance(70e9, 0.33) / c1, 1e-15);
    assert_double_rel(p.striker_compliance, compliance(110e9, 0.34) / c1, 1e-15);
    assert_double_rel(p.striker_density, 8500.0 / 8000.0, 1e-15);
    assert_true(p.mixed);
    double *rho, *cc;
    assert_int_equal(scene_material_arrays(c, 5, &rho, &cc), 0);
    static const double want_rho[5] = {8000, 8500, 8000, 8500, 8000};
    for (int k = 0; k < 5; k++) {
        assert_double_rel(rho[k], want_rho[k], 0);
        assert_double_rel(cc[k], k % 2 ? compliance(110e9, 0.34) : c1, 1e-15);
    }
    free(rho);
    free(cc);
    /* SI in, SI out: with &material the results are in SI unless the scene
     * asks for 'rescaled'. */
    assert_int_equal(c->output.units, SCENE_UNITS_SI);
    assert_string_equal(scene_unit_suffix(c, TAPER_DIM_TIME), "s");
    scene_free(sc);
    sc = load_ok("&chain n_granules = 5 /\n"
                 "&material young = 193e9, poisson = 0.3, density = 8000, radius = 2e-3,\n"
                 "  velocity = 0.7 /\n&output units = 'rescaled' /\n");
    assert_double_rel(scene_unit(scene_cfg(sc), TAPER_DIM_TIME), 1, 0);
    assert_null(scene_unit_suffix(scene_cfg(sc), TAPER_DIM_TIME));
    scene_free(sc);
}

/* In SI the scales are the library's for granule 1's material: here
 * material 2 (the sequence starts with it). */
static void test_units_of_granule_one(void **state)
{
    (void)state;
    scene *sc = load_ok("&chain n_granules = 4 /\n"
                        "&material young = 193e9, poisson = 0.3, density = 8000,\n"
                        "  radius = 2e-3, velocity = 0.7, other_young = 100e9,\n"
                        "  other_poisson = 0.25, other_density = 4000, sequence = 2, 1 /\n"
                        "&output units = 'si' /\n");
    const scene_config *c = scene_cfg(sc);
    for (int d = 0; d < TAPER_N_DIMENSIONS; d++) {
        double want = taper_unit_scale((taper_dimension)d, 100e9, 0.25, 4000, 2e-3, 0.7);
        assert_true(isfinite(want) && want > 0);
        assert_double_rel(scene_unit(c, (taper_dimension)d), want, 0);
        assert_string_equal(scene_unit_suffix(c, (taper_dimension)d),
                            taper_dimension_unit((taper_dimension)d));
    }
    /* The velocity unit is the impact velocity itself (eq. (5)). */
    assert_double_rel(scene_unit(c, TAPER_DIM_VELOCITY), 0.7, 1e-15);
    scene_free(sc);
}

/* One material throughout: no per-granule materials for the library
 * (exactly its single-material chain). */
static void test_one_material_is_not_mixed(void **state)
{
    (void)state;
    scene *sc = load_ok("&material young = 193e9, poisson = 0.3, density = 8000,\n"
                        "  radius = 4.76e-3, velocity = 0.5, sequence = 1, 1 /\n");
    scene_material_props p;
    scene_material_resolve(scene_cfg(sc), &p);
    assert_false(p.mixed);
    taper_chain_spec *spec = scene_chain_spec(scene_cfg(sc), 0, NULL);
    assert_non_null(spec);
    const double *rho;
    assert_int_equal(taper_chain_spec_materials(spec, &rho, NULL), 0);
    taper_chain_spec_free(spec);
    scene_free(sc);
}

/* ---- the scene's own refusals -------------------------------------------------------- */

static void test_refusals(void **state)
{
    (void)state;
    assert_refused("&chain exponent = 3 /\n&material young = 1e9, poisson = 0.3, density = 1000,"
                   " radius = 1e-3, velocity = 1 /\n",
                   "chain", "exponent", "Hertz");
    assert_refused("&output units = 'si' /\n", "output", "units", "&material");
    assert_refused("&material young = 1e9, poisson = 0.3, density = 1000, radius = 1e-3 /\n",
                   "material", "velocity", "needs velocity");
    assert_refused("&material young = 1e9, poisson = 0.5, density = 1000, radius = 1e-3,"
                   " velocity = 1 /\n",
                   "material", "poisson", "out of range");
    assert_refused("&material young = 1e9, poisson = 0.3, density = 1000, radius = 1e-3,"
                   " velocity = 1, other_young = 2e9 /\n",
                   "material", "other_poisson", "one per other material");
    assert_refused("&material young = 1e9, poisson = 0.3, density = 1000, radius = 1e-3,"
                   " velocity = 1, sequence = 1, 2 /\n",
                   "material", "sequence", "numbered 1 to 1");
    assert_refused("&ends right = 'wall', right_compliance = 1 /\n&material young = 1e9,"
                   " poisson = 0.3, density = 1000, radius = 1e-3, velocity = 1 /\n",
                   "ends", "right_compliance", "&material wall");
    assert_refused("&material sequence = 1, 2 /\n", "material", "sequence", "material 1");
    assert_refused("&chain n_granules = 10 /\n&sensors granules = 3 /\n", "sensors", "granules",
                   "interval > 0");
    assert_refused("&chain n_granules = 10 /\n&sensors interval = 1, granules = 2.5 /\n",
                   "sensors", "granules", "granules(1) = 2.5");
    assert_refused("&solver numerics = .false. /\n&sensors interval = 1 /\n", "sensors",
                   "interval", "numerics");
    assert_refused("&sensors interval = 1 /\n", "sensors", "interval", "nowhere");
    assert_refused("&chain seed = -1 /\n", "chain", "seed", ">= 0");
    /* The library's, at the scene's key. */
    assert_refused("&losses drag = -1 /\n", "losses", "drag", "drag");
    assert_refused("&ends left = 'wall' /\n&striker radius = 1 /\n", "ends", "left", "striker");
    assert_refused("&striker density = 2 /\n", "striker", "radius", "without a striker");
    assert_refused("&ends left_compliance = 1 /\n", "ends", "left_compliance", "wall");
    assert_refused("&chain profile = 'monodisperse', pattern = 1, 0.5 /\n", "chain", "pattern",
                   "decorated");
}

/* ---- radii files ------------------------------------------------------------------------ */

static char dir[] = "/tmp/taper_scene_physics.XXXXXX";

static void write_file(const char *name, const char *text)
{
    char *path = text_printf("%s/%s", dir, name);
    assert_non_null(path);
    FILE *fp = fopen(path, "w");
    assert_non_null(fp);
    fputs(text, fp);
    fclose(fp);
    free(path);
}

static void test_radii_file(void **state)
{
    (void)state;
    assert_non_null(mkdtemp(dir));
    write_file("r.txt", "# measured\n1\n  0.9  # a comment after the value\n\n0.8\n");
    write_file("bad.txt", "1\n0.9\n# fine\nnan\n");
    write_file("first.txt", "# R_1 must be 1\n2\n1\n");
    char *scene_path = text_printf("%s/s.nml", dir);
    assert_non_null(scene_path);

    scene *sc = load_at(scene_path, "&chain profile = 'custom', radii_file = 'r.txt' /\n");
    assert_int_equal(scene_error_count(sc), 0);
    const scene_config *c = scene_cfg(sc);
    assert_int_equal(scene_setting(c, "n_granules"), 3);
    assert_int_equal(c->chain.file_radii.n, 3);
    assert_double_rel(c->chain.file_radii.v[1], 0.9, 0);
    assert_double_rel(c->chain.file_radii.v[2], 0.8, 0);
    /* resolved against the scene's folder, absolute for the echo */
    assert_true(c->chain.radii_file[0] == '/');
    assert_non_null(strstr(c->chain.radii_file, "/r.txt"));
    taper_chain_spec *spec = scene_chain_spec(c, 0, NULL);
    size_t n;
    assert_non_null(spec);
    assert_non_null(taper_chain_spec_radii(spec, &n));
    assert_int_equal(n, 3);
    taper_chain_spec_free(spec);
    scene_free(sc);

    sc = load_at(scene_path, "&chain profile = 'custom',\n  radii_file = 'bad.txt' /\n");
    assert_int_equal(scene_diag_count(sc), 1);
    const scene_diag *d = scene_diag_at(sc, 0);
    assert_int_equal(d->line, 2);
    assert_string_equal(d->key, "radii_file");
    assert_non_null(strstr(d->message, "bad.txt:4: radius nan"));
    scene_free(sc);

    sc = load_at(scene_path, "&chain profile = 'custom', radii_file = 'first.txt' /\n");
    assert_non_null(strstr(scene_diag_at(sc, 0)->message, "first.txt:2: the first radius is 2"));
    scene_free(sc);

    sc = load_at(scene_path, "&chain profile = 'custom', radii_file = 'none.txt' /\n");
    assert_non_null(strstr(scene_diag_at(sc, 0)->message, "cannot open"));
    scene_free(sc);

    /* a device never ends: refused before reading */
    sc = load_at(scene_path, "&chain profile = 'custom', radii_file = '/dev/zero' /\n");
    assert_non_null(strstr(scene_diag_at(sc, 0)->message, "not a regular file"));
    scene_free(sc);

    /* a NUL byte cuts no line silently: the file and its line are named */
    char *nul = text_printf("%s/nul.txt", dir);
    FILE *f = nul ? fopen(nul, "wb") : NULL;
    assert_non_null(f);
    fwrite("1\n1.5\0junk\n2\n", 1, 13, f);
    fclose(f);
    free(nul);
    sc = load_at(scene_path, "&chain profile = 'custom', radii_file = 'nul.txt' /\n");
    assert_int_equal(scene_error_count(sc), 1);
    assert_non_null(strstr(scene_diag_at(sc, 0)->message, "nul.txt:2: a NUL byte"));
    scene_free(sc);

    sc = load_at(scene_path, "&chain profile = 'monodisperse', radii_file = 'r.txt' /\n");
    assert_non_null(strstr(scene_diag_at(sc, 0)->message, "profile = 'custom'"));
    scene_free(sc);

    static const char *const names[] = {"r.txt", "bad.txt", "first.txt", "nul.txt"};
    for (size_t i = 0; i < 4; i++) {
        char *p = text_printf("%s/%s", dir, names[i]);
        assert_non_null(p);
        unlink(p);
        free(p);
    }
    rmdir(dir);
    free(scene_path);
}

/* ---- sweeps ---------------------------------------------------------------------------------- */

static void test_sweeps_of_new_variables(void **state)
{
    (void)state;
    scene *sc = load_ok("&chain n_granules = 20, disorder_amplitude = 0.1, seed = 1, 2, 3 /\n");
    const scene_config *c = scene_cfg(sc);
    assert_int_equal(c->runs.n, 3);
    char *name = scene_point_name(c, 1);
    assert_string_equal(name, "seed=2");
    free(name);
    scene_config at;
    scene_config_at(c, 2, &at);
    assert_true(scene_setting(&at, "seed") == 3);
    scene_free(sc);

    sc = load_ok("&chain n_granules = 20, load = 0, 0.5 /\n&losses damping = 0, 0.1 /\n"
                 "&ends right = 'wall' /\n&sensors interval = 0.5, 1 /\n");
    c = scene_cfg(sc);
    assert_int_equal(c->runs.n, 8);
    name = scene_point_name(c, 7);
    assert_string_equal(name, "load=0.5,damping=0.1,interval=1");
    free(name);
    scene_free(sc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_echo_leaves_out_what_is_not_given),
        cmocka_unit_test(test_echo_reads_back),
        cmocka_unit_test(test_material_props),
        cmocka_unit_test(test_units_of_granule_one),
        cmocka_unit_test(test_one_material_is_not_mixed),
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_radii_file),
        cmocka_unit_test(test_sweeps_of_new_variables),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
