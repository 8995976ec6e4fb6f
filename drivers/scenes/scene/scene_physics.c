/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * scene_physics.c -- the scene's own rules for the variables beyond the
 * paper: the radii file of a measured chain, &material (real
 * units, mixed chains), &sensors and &output units.  The library's
 * settings among them (ends, striker, load, losses, disorder, pattern) are
 * checked by the library's setters (scene_lib.c); what is here only the
 * scene knows: files, material indices, granule numbers against the chain,
 * and which groups go together.
 */
#include "scene_impl.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Bytes in a radii file: 10^7 radii (TAPER_N_GRANULES_MAX) of a few tens
 * of characters each, with comments. */
#define RADII_FILE_MAX (1l << 30)

static int row(const char *group, const char *name) { return scene_var_find(group, name); }

static int given(const scene *sc, const char *group, const char *name)
{
    return sc->origin[row(group, name)].given;
}

/* ---- the radii file ------------------------------------------------------------ */

/* path as the scene means it: relative to the scene file's folder (the
 * working directory for a scene read from stdin), made absolute
 * so that the echo of the scene runs from anywhere.  malloc'd. */
static char *resolve_path(const scene *sc, const char *path)
{
    char *joined;
    const char *slash = strrchr(sc->path, '/');
    if (path[0] == '/' || sc->from_stdin || !slash)
        joined = text_dup(path);
    else
        joined = text_printf("%.*s/%s", (int)(slash - sc->path), sc->path, path);
    if (!joined || joined[0] == '/') return joined;
    char cwd[4096];
    if (!getcwd(cwd, sizeof cwd)) return joined;
    char *abs = text_printf("%s/%s", cwd, joined);
    free(joined);
    return abs;
}

/* One radius per line; blank lines and '#' comments (whole lines or after
 * the value) are skipped.  Every radius finite and > 0, the first 1 (the
 * unit of length, as the library requires of a custom chain), each error
 * naming FILE:LINE of the radii file. */
static void read_radii_file(scene *sc)
{
    scene_chain_config *c = &sc->cfg.chain;
    size_t r = (size_t)row("chain", "radii_file");
    char *path = resolve_path(sc, c->radii_file);
    if (!path) {
        scene_var_error(sc, r, "out of memory");
        return;
    }
    free(c->radii_file);
    c->radii_file = path; /* the echo names the file this run read */
    /* A regular file of bounded size: a device or a FIFO named by mistake
     * (or by a fuzzer) would never end, or block the open itself. */
    int fd = open(path, O_RDONLY | O_NONBLOCK);
    struct stat st;
    if (fd < 0 || fstat(fd, &st) != 0) {
        scene_var_error(sc, r, "cannot open %s: %s", path, strerror(errno));
        if (fd >= 0) close(fd);
        return;
    }
    if (!S_ISREG(st.st_mode) || st.st_size > RADII_FILE_MAX) {
        scene_var_error(sc, r, "%s is %s: give a text file of radii", path,
                        S_ISREG(st.st_mode) ? "larger than 1 GB" : "not a regular file");
        close(fd);
        return;
    }
    FILE *fp = fdopen(fd, "r");
    if (!fp) {
        scene_var_error(sc, r, "cannot read %s: %s", path, strerror(errno));
        close(fd);
        return;
    }
    /* Radii are relative to R_1, or with &material in metres (R_1 then
     * is &material radius). */
    const double unit = given(sc, "material", "radius") ? sc->cfg.material.radius : 1.0;
    char *line = NULL;
    size_t cap = 0, alloc = 0;
    ssize_t len;
    int lineno = 0;
    while ((len = getline(&line, &cap, fp)) >= 0) {
        lineno++;
        if (len > SCENE_MAX_LINE) {
            scene_var_error(sc, r, "%s:%d: line longer than %d characters: one radius per line",
                            path, lineno, SCENE_MAX_LINE);
            break;
        }
        /* A NUL byte would end the line for strtod and cut it silently
         * ("1.5\0junk" read as 1.5): a binary file, or a corrupted one. */
        if (memchr(line, '\0', (size_t)len)) {
            scene_var_error(sc, r, "%s:%d: a NUL byte (byte %zu of the line): a text file of "
                            "radii has none", path, lineno,
                            (size_t)((char *)memchr(line, '\0', (size_t)len) - line) + 1);
            break;
        }
        if (c->file_radii.n == TAPER_N_GRANULES_MAX) {
            scene_var_error(sc, r, "%s:%d: more than %d radii (a chain has at most that many "
                            "granules)", path, lineno, TAPER_N_GRANULES_MAX);
            break;
        }
        char *hash = strchr(line, '#');
        if (hash) *hash = '\0';
        char *p = line, *end;
        while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n') p++;
        if (!*p) continue;
        errno = 0;
        double x = strtod(p, &end);
        while (*end == ' ' || *end == '\t' || *end == '\r' || *end == '\n') end++;
        if (end == p || *end) {
            scene_var_error(sc, r, "%s:%d: '%.40s' is not a number: one radius per line", path,
                            lineno, strtok(p, "\r\n"));
            break;
        }
        if (!isfinite(x) || x <= 0 || errno == ERANGE) {
            scene_var_error(sc, r, "%s:%d: radius %g: every radius must be finite and > 0", path,
                            lineno, x);
            break;
        }
        if (c->file_radii.n == 0 && x != unit) {
            if (unit == 1)
                scene_var_error(sc, r, "%s:%d: the first radius is %g: it must be 1 (R_1 is the "
                                "unit of length; divide the file by it)", path, lineno, x);
            else
                scene_var_error(sc, r, "%s:%d: the first radius is %g m: with &material it must "
                                "be &material radius = %g m (granule 1's radius is R_1)", path,
                                lineno, x, unit);
            break;
        }
        if (c->file_radii.n == alloc) {
            size_t grown_n = alloc ? 2 * alloc : 1024;
            double *grown = realloc(c->file_radii.v, grown_n * sizeof *grown);
            if (!grown) {
                scene_var_error(sc, r, "%s: out of memory", path);
                break;
            }
            c->file_radii.v = grown;
            alloc = grown_n;
        }
        c->file_radii.v[c->file_radii.n++] = x;
    }
    if (ferror(fp)) scene_var_error(sc, r, "cannot read %s: %s", path, strerror(errno));
    if (sc->n_errors == 0 && c->file_radii.n == 0)
        scene_var_error(sc, r, "%s holds no radius", path);
    free(line);
    fclose(fp);
}

void scene_read_radii(scene *sc)
{
    scene_chain_config *c = &sc->cfg.chain;
    if (!c->radii_file[0]) return;
    size_t r = (size_t)row("chain", "radii_file");
    if (SCENE_PROFILE(&sc->cfg) != TAPER_CUSTOM) {
        scene_var_error(sc, r, "radii_file is only used with profile = 'custom': remove it or "
                        "set the profile");
        return;
    }
    if (given(sc, "chain", "radii")) {
        scene_var_error(sc, r, "give the radii either inline (radii) or in a file (radii_file), "
                        "not both");
        return;
    }
    read_radii_file(sc);
}

/* ---- &material -------------------------------------------------------------------- */

/* The number of materials: 1 + the others; lists of the others must have
 * the same length. */
static size_t n_materials(const scene_material_config *m) { return 1 + m->other_young.n; }

static void check_material_lists(scene *sc)
{
    const scene_material_config *m = &sc->cfg.material;
    const char *names[] = {"other_poisson", "other_density"};
    const scene_reals *lists[] = {&m->other_poisson, &m->other_density};
    for (int i = 0; i < 2; i++)
        if (lists[i]->n != m->other_young.n)
            scene_var_error(sc, (size_t)row("material", names[i]),
                            "%zu values, but other_young has %zu: give one per other material",
                            lists[i]->n, m->other_young.n);
    size_t nm = n_materials(m);
    size_t s = (size_t)row("material", "sequence");
    for (size_t j = 0; j < m->sequence.n; j++) {
        double x = m->sequence.v[j];
        if (x != floor(x) || x < 1 || x > (double)nm) {
            scene_var_error(sc, s, "sequence(%zu) = %g: materials are numbered 1 to %zu (1: "
                            "young, poisson, density; then other_*)", j + 1, x, nm);
            return;
        }
    }
    if ((size_t)m->wall > nm)
        scene_var_error(sc, (size_t)row("material", "wall"),
                        "material %lld does not exist: 0 (rigid) or 1 to %zu", m->wall, nm);
    if ((size_t)m->striker > nm)
        scene_var_error(sc, (size_t)row("material", "striker"),
                        "material %lld does not exist: 1 to %zu", m->striker, nm);
}

/* Settings that &material computes cannot also be given. */
static void check_material_owns(scene *sc)
{
    static const char *const owned[][3] = {
        {"ends", "left_compliance", "wall"},
        {"ends", "right_compliance", "wall"},
        {"striker", "density", "striker"},
        {"striker", "compliance", "striker"},
        {"chain", "densities", "sequence"},
        {"chain", "compliances", "sequence"},
    };
    for (size_t i = 0; i < sizeof owned / sizeof owned[0]; i++)
        if (given(sc, owned[i][0], owned[i][1]))
            scene_var_error(sc, (size_t)row(owned[i][0], owned[i][1]),
                            "with &material this follows from &material %s: remove it (or "
                            "choose that material)", owned[i][2]);
}

/* Real units are those of Hertz contacts: the rescaling of eq. (5) with a
 * = sqrt(2) E / (3 (1 - nu^2)) holds for n = 5/2 only. */
static void check_hertz(scene *sc)
{
    size_t e = (size_t)row("chain", "exponent");
    for (size_t j = 0; j < scene_row_count(&sc->cfg, e); j++) {
        double n = scene_row_value(&sc->cfg, e, j);
        if (n != 2.5) {
            char t[SCENE_REAL_TEXT];
            scene_format_real(n, t);
            scene_var_error(sc, e, "exponent = %s, but &material gives real units, which are "
                            "those of Hertz contacts (n = 5/2, elastic spheres): set exponent = "
                            "2.5, or remove &material to stay in rescaled units", t);
            return;
        }
    }
}

/* With &material every size is in metres and granule 1's radius is R_1:
 * the first radius of a custom chain or a pattern is &material radius. */
static void check_first_radius(scene *sc, const char *keyword)
{
    const scene_reals *r = scene_setting_list(&sc->cfg, keyword);
    size_t rr = (size_t)row("material", "radius");
    for (size_t j = 0; r->n && j < scene_row_count(&sc->cfg, rr); j++) {
        double R1 = scene_row_value(&sc->cfg, rr, j);
        if (r->v[0] != R1) {
            char a[SCENE_REAL_TEXT], b[SCENE_REAL_TEXT];
            scene_format_real(r->v[0], a);
            scene_format_real(R1, b);
            scene_var_error(sc, (size_t)scene_var_keyword(keyword),
                            "%s(1) = %s m: with &material the sizes are in metres and granule "
                            "1's radius is &material radius = %s m (R_1): make them equal",
                            keyword, a, b);
            return;
        }
    }
}

static void check_material(scene *sc)
{
    scene_material_config *m = &sc->cfg.material;
    static const char *const needed[] = {"young", "poisson", "density", "radius", "velocity"};
    /* On when one of the five that set the units is given (`taper
     * --defaults` writes wall = 0 and striker = 1: those alone at their
     * defaults leave it off). */
    m->on = 0;
    for (size_t i = 0; i < sizeof needed / sizeof needed[0]; i++)
        if (given(sc, "material", needed[i])) m->on = 1;
    if (!m->on) {
        static const char *const others[] = {"other_young", "other_poisson", "other_density",
                                             "sequence"};
        for (size_t i = 0; i < sizeof others / sizeof others[0]; i++)
            if (given(sc, "material", others[i]))
                scene_var_error(sc, (size_t)row("material", others[i]),
                                "a mixed chain needs material 1: give &material young, poisson, "
                                "density, radius, velocity");
        if (m->wall != 0 || m->striker != 1)
            scene_var_error(sc, (size_t)row("material", m->wall != 0 ? "wall" : "striker"),
                            "materials need &material young, poisson, density, radius, velocity");
        return;
    }
    for (size_t i = 0; i < sizeof needed / sizeof needed[0]; i++)
        if (!given(sc, "material", needed[i]))
            scene_var_error(sc, (size_t)row("material", needed[i]),
                            "&material needs %s (young [Pa], poisson, density [kg/m^3], radius "
                            "[m] of granule 1, velocity [m/s])", needed[i]);
    check_material_lists(sc);
    check_material_owns(sc);
    check_hertz(sc);
    check_first_radius(sc, "radii");
    check_first_radius(sc, "pattern");
}

/* ---- &sensors and &output units --------------------------------------------------- */

/* The shortest chain of a sweep of n_granules. */
static long long shortest_chain(const scene *sc)
{
    size_t nr = (size_t)row("chain", "n_granules");
    long long n = SCENE_N_GRANULES(&sc->cfg);
    for (size_t j = 0; j < scene_row_count(&sc->cfg, nr); j++)
        if ((long long)scene_row_value(&sc->cfg, nr, j) < n)
            n = (long long)scene_row_value(&sc->cfg, nr, j);
    return n;
}

static void check_sensors(scene *sc)
{
    const scene_config *cfg = &sc->cfg;
    const scene_sensors_config *s = &cfg->sensors;
    size_t iv = (size_t)row("sensors", "interval");
    int sampling = 0;
    for (size_t j = 0; j < scene_row_count(cfg, iv); j++)
        if (scene_row_value(cfg, iv, j) > 0) sampling = 1;
    if (sampling && !cfg->solver.numerics)
        scene_var_error(sc, iv, "sensors sample the dynamics, and &solver numerics = .false.: "
                        "turn the numerics on or set interval = 0");
    int walls = scene_setting(cfg, "left") == TAPER_END_WALL ||
                scene_setting(cfg, "right") == TAPER_END_WALL;
    if (sampling && cfg->solver.numerics && s->granules.n == 0 && !s->spacetime && !walls &&
        !sc->samples_kept)
        scene_var_error(sc, iv, "the samples would go nowhere: give &sensors granules, "
                        "spacetime = .true., or a wall (&ends)");
    if (!sampling && s->granules.n > 0)
        scene_var_error(sc, (size_t)row("sensors", "granules"),
                        "sensors need a sampling interval: give &sensors interval > 0");
    if (!sampling && s->spacetime)
        scene_var_error(sc, (size_t)row("sensors", "spacetime"),
                        "the space-time picture is sampled: give &sensors interval > 0");
    long long n = shortest_chain(sc);
    size_t g = (size_t)row("sensors", "granules");
    for (size_t j = 0; j < s->granules.n; j++) {
        double k = s->granules.v[j];
        if (k != floor(k) || k < 1 || k > (double)n) {
            scene_var_error(sc, g, "granules(%zu) = %g: a sensor sits on a granule 1 to %lld "
                            "(n_granules)", j + 1, k, n);
            return;
        }
    }
}

/* With &material the results are in SI unless the scene asks for
 * 'rescaled': SI in, SI out. */
static void check_units(scene *sc)
{
    scene_config *cfg = &sc->cfg;
    if (cfg->material.on && !given(sc, "output", "units")) cfg->output.units = SCENE_UNITS_SI;
    if (cfg->output.units == SCENE_UNITS_SI && !cfg->material.on)
        scene_var_error(sc, (size_t)row("output", "units"),
                        "units = 'si' converts with the materials of &material: give &material "
                        "young, poisson, density, radius, velocity");
}

/* A seed is any non-negative integer below 2^53 (exact in a sweep's list). */
static void check_seed(scene *sc)
{
    size_t r = (size_t)row("chain", "seed");
    for (size_t j = 0; j < scene_row_count(&sc->cfg, r); j++)
        if (scene_row_value(&sc->cfg, r, j) < 0) {
            scene_var_error(sc, r, "%.0f is out of range: a seed is an integer >= 0",
                            scene_row_value(&sc->cfg, r, j));
            return;
        }
}

/* piston = 'push' needs its duration (the library takes 0 for no piston),
 * and only 'push' has one ('steady' is for ever). */
static void check_piston(scene *sc)
{
    const scene_striker_config *st = &sc->cfg.striker;
    size_t r = (size_t)row("striker", "piston_duration");
    for (size_t j = 0; j < scene_row_count(&sc->cfg, r); j++) {
        double T = scene_row_value(&sc->cfg, r, j);
        if (st->piston == SCENE_PISTON_PUSH && !(T > 0.0)) {
            scene_var_error(sc, r, "piston = 'push' pushes for piston_duration > 0 (%g given); "
                                   "piston = 'steady' pushes for ever", T);
            return;
        }
        if (st->piston != SCENE_PISTON_PUSH && T != 0.0) {
            scene_var_error(sc, r, "piston_duration = %g has no effect without piston = 'push' "
                                   "(a 'steady' piston pushes for ever): leave it at 0", T);
            return;
        }
    }
}

void scene_keep_samples(scene *sc) { sc->samples_kept = 1; }

void scene_check_physics(scene *sc)
{
    check_material(sc);
    check_sensors(sc);
    check_units(sc);
    check_seed(sc);
    check_piston(sc);
}

/* ---- what the library receives ------------------------------------------------- */

/* Material i (1-based): E, nu, rho. */
static void material_at(const scene_material_config *m, size_t i, double *e, double *nu,
                        double *rho)
{
    /* A material the lists do not have (a scene being validated, whose
     * errors are reported): NaN, which the library refuses too. */
    size_t j = i - 2;
    *e = i <= 1 ? m->young : j < m->other_young.n ? m->other_young.v[j] : NAN;
    *nu = i <= 1 ? m->poisson : j < m->other_poisson.n ? m->other_poisson.v[j] : NAN;
    *rho = i <= 1 ? m->density : j < m->other_density.n ? m->other_density.v[j] : NAN;
}

static double compliance(double e, double nu) { return (1 - nu * nu) / e; }

/* The material of granule k (1-based). */
static size_t material_of(const scene_material_config *m, size_t k)
{
    return m->sequence.n ? (size_t)m->sequence.v[(k - 1) % m->sequence.n] : 1;
}

int scene_material_resolve(const scene_config *cfg, scene_material_props *p)
{
    const scene_material_config *m = &cfg->material;
    memset(p, 0, sizeof *p);
    if (!m->on) return 0;
    double e1, nu1, rho1;
    material_at(m, material_of(m, 1), &e1, &nu1, &rho1);
    double c1 = compliance(e1, nu1);
    p->young = e1;
    p->poisson = nu1;
    p->density = rho1;
    p->wall_compliance = 0; /* rigid */
    if (m->wall > 0) {
        double e, nu, rho;
        material_at(m, (size_t)m->wall, &e, &nu, &rho);
        p->wall_compliance = compliance(e, nu) / c1;
    }
    double e, nu, rho;
    material_at(m, (size_t)m->striker, &e, &nu, &rho);
    p->striker_density = rho / rho1;
    p->striker_compliance = compliance(e, nu) / c1;
    /* One material throughout: the library's single-material chain, exactly. */
    int mixed = 0;
    for (size_t j = 0; j < m->sequence.n; j++)
        if ((size_t)m->sequence.v[j] != material_of(m, 1)) mixed = 1;
    p->mixed = mixed;
    return 0;
}

int scene_material_arrays(const scene_config *cfg, size_t n, double **density,
                          double **compliance_out)
{
    const scene_material_config *m = &cfg->material;
    *density = malloc(n * sizeof **density);
    *compliance_out = malloc(n * sizeof **compliance_out);
    if (!*density || !*compliance_out) {
        free(*density);
        free(*compliance_out);
        *density = *compliance_out = NULL;
        return -1;
    }
    for (size_t k = 1; k <= n; k++) {
        double e, nu, rho;
        material_at(m, material_of(m, k), &e, &nu, &rho);
        (*density)[k - 1] = rho;
        (*compliance_out)[k - 1] = compliance(e, nu);
    }
    return 0;
}

double scene_unit(const scene_config *cfg, taper_dimension dim)
{
    if (cfg->output.units != SCENE_UNITS_SI || !cfg->material.on) return 1.0;
    scene_material_props p;
    scene_material_resolve(cfg, &p);
    return taper_unit_scale(dim, p.young, p.poisson, p.density, cfg->material.radius,
                            cfg->material.velocity);
}

const char *scene_unit_suffix(const scene_config *cfg, taper_dimension dim)
{
    if (cfg->output.units != SCENE_UNITS_SI || !cfg->material.on) return NULL;
    return taper_dimension_unit(dim);
}

taper_dimension scene_column_dimension(scene_column c)
{
    static const taper_dimension dims[SCENE_N_COLUMNS] = {
        [SCENE_COL_K] = TAPER_DIM_NUMBER,
        [SCENE_COL_R] = TAPER_DIM_SIZE,
        [SCENE_COL_M] = TAPER_DIM_MASS,
        [SCENE_COL_X0] = TAPER_DIM_SIZE,
        [SCENE_COL_T_PASS] = TAPER_DIM_TIME, /* the observables and the theory: */
        [SCENE_COL_T_RES] = TAPER_DIM_TIME,  /* the library's dimensions, checked */
        [SCENE_COL_V_PEAK] = TAPER_DIM_VELOCITY, /* in tests/driver/test_scene.c */
        [SCENE_COL_T_PEAK] = TAPER_DIM_TIME,
        [SCENE_COL_X_PASS] = TAPER_DIM_LENGTH,
        [SCENE_COL_THEORY_V] = TAPER_DIM_VELOCITY,
        [SCENE_COL_THEORY_T] = TAPER_DIM_TIME,
        [SCENE_COL_THEORY_CUM_T] = TAPER_DIM_TIME,
    };
    return (unsigned)c < SCENE_N_COLUMNS ? dims[c] : TAPER_DIM_NUMBER;
}

void scene_column_convert(const scene_config *cfg, scene_column c, double *values,
                          const double *rest, size_t n)
{
    if (!scene_unit_suffix(cfg, TAPER_DIM_LENGTH) || c == SCENE_COL_K) return;
    double scale = scene_unit(cfg, scene_column_dimension(c));
    if (c == SCENE_COL_X_PASS) {
        const double radius = cfg->material.radius;
        for (size_t k = 0; k < n; k++) values[k] = rest[k] * radius + (values[k] - rest[k]) * scale;
        return;
    }
    for (size_t k = 0; k < n; k++) values[k] *= scale;
}
