/*
 * scene.c -- the table of scene variables, the scene object (typed values
 * and where they came from), diagnostics, and typed access to a row's
 * field.
 *
 * The table below is the only place a variable is declared: the parser
 * (scene_parse.c), the validation (scene_check.c, scene_lib.c), the echo,
 * --defaults, --doc and --get (scene_write.c) all walk it.  Each row names
 * the field of scene_config it fills, so that resolving is generic.
 */
#include "scene_impl.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* Choice fields are enums written through int: they must be int-sized. */
_Static_assert(sizeof(taper_profile) == sizeof(int), "enum size");
_Static_assert(sizeof(taper_method) == sizeof(int), "enum size");
_Static_assert(sizeof(scene_quantity) == sizeof(int), "enum size");
_Static_assert(sizeof(scene_fit_report) == sizeof(int), "enum size");
_Static_assert(sizeof(scene_fit_theory) == sizeof(int), "enum size");
_Static_assert(sizeof(scene_curves) == sizeof(int), "enum size");
_Static_assert(sizeof(taper_boundary) == sizeof(int), "enum size");
_Static_assert(sizeof(taper_disorder) == sizeof(int), "enum size");
_Static_assert(sizeof(scene_units) == sizeof(int), "enum size");
/* No field is larger than a list (scene_set moves fields through one). */
_Static_assert(sizeof(scene_reals) >= sizeof(double) && sizeof(scene_reals) >= sizeof(long long) &&
               sizeof(scene_reals) >= sizeof(char *), "field size");

/* ---- names of the choices -------------------------------------------------- */

/* Library choices: the library's one list of names. */
static const char *profile_choice(int i) { return taper_profile_name((taper_profile)i); }
static const char *method_choice(int i) { return taper_method_name((taper_method)i); }
static const char *fit_model_choice(int i) { return scene_fit_model_name(i); }
static const char *boundary_choice(int i) { return taper_boundary_name((taper_boundary)i); }
static const char *const pistons[] = {"none", "push", "steady", NULL};
static const char *piston_choice(int i) { return i >= 0 && i < 3 ? pistons[i] : NULL; }
static const char *disorder_choice(int i) { return taper_disorder_name((taper_disorder)i); }

/* The scene's own choices. */
#define NAME_AT(list, i) \
    ((i) >= 0 && (size_t)(i) < sizeof(list) / sizeof(list[0]) ? list[i] : NULL)
static const char *const quantities[] = {"k", "v", "T_res", "t", "t_reach", "t_peak"};
static const char *const fit_reports[] = {"a", "b", "c", "m", "p", "f"};
static const char *const fit_theories[] = {"fit", "rate", "f", "b"};
static const char *const curves[] = {"both", "theory", "numerics"};
static const char *const chain_params[] = {"s", "q"};
static const char *const sweep_modes[] = {"grid", "zip"};
static const char *const units[] = {"rescaled", "si"};
static const char *const columns[SCENE_N_COLUMNS] = {
    "k", "R", "m", "X0", "t_pass", "T_res", "v_peak", "t_peak", "X_pass",
    "theory_v", "theory_T", "theory_t"};

const char *scene_column_name(scene_column c) { return NAME_AT(columns, (int)c); }
int scene_column_numerics(scene_column c) { return c >= SCENE_COL_T_PASS && c <= SCENE_COL_X_PASS; }

const char *scene_quantity_name(scene_quantity q) { return NAME_AT(quantities, (int)q); }
const char *scene_fit_report_name(scene_fit_report r) { return NAME_AT(fit_reports, (int)r); }
const char *scene_fit_theory_name(scene_fit_theory t) { return NAME_AT(fit_theories, (int)t); }
const char *scene_chain_param_name(scene_chain_param p) { return NAME_AT(chain_params, (int)p); }
const char *scene_fit_model_name(int model)
{
    return model == SCENE_FIT_NONE ? "none" : taper_fit_model_name((taper_fit_model)model);
}

static const char *quantity_choice(int i) { return NAME_AT(quantities, i); }
static const char *report_choice(int i) { return NAME_AT(fit_reports, i); }
static const char *theory_choice(int i) { return NAME_AT(fit_theories, i); }
static const char *curves_choice(int i) { return NAME_AT(curves, i); }
static const char *sweep_mode_choice(int i) { return NAME_AT(sweep_modes, i); }
static const char *units_choice(int i) { return NAME_AT(units, i); }
const char *scene_units_name(scene_units u) { return NAME_AT(units, (int)u); }

/* ---- groups ------------------------------------------------------------------ */

/* The groups, in the order they are written and documented. */
static const char *const groups[SCENE_N_GROUPS][2] = {
    {"chain", "the granular chain: radius profile, size, contact law, disorder, static load"},
    {"ends", "what holds the chain at each end: nothing (free) or a wall"},
    {"striker", "a striker (granule 0) hitting granule 1, or a piston pushing it, instead of "
                "the paper's impulse"},
    {"losses", "dissipation: viscoelastic contacts and drag"},
    {"material", "real units (Hertz contacts, n = 5/2): materials, R_1 and the impact velocity"},
    {"solver", "the integration of the equations of motion (CVODE)"},
    {"sensors", "time series sampled during the run: chosen granules, wall forces, v(k, t)"},
    {"output", "where and how results are written"},
    {"fit", "a fit applied to every run of the scene, to numerics and theory alike"},
    {"table", "a table of the fitted parameter over the sweep, next to the paper's values"},
    {"figure", "a figure: per-granule data of every run, and the fit as an inset"},
    {"sweep", "how the lists of several swept variables combine into runs"},
};

const char *scene_group_name(size_t i) { return i < SCENE_N_GROUPS ? groups[i][0] : NULL; }
const char *scene_group_doc(size_t i) { return i < SCENE_N_GROUPS ? groups[i][1] : NULL; }

int scene_group_index(const char *name)
{
    for (size_t i = 0; i < SCENE_N_GROUPS; i++)
        if (strcmp(groups[i][0], name) == 0) return (int)i;
    return -1;
}

/* ---- the table ----------------------------------------------------------------- */

#define AT(field) offsetof(scene_config, field)
#define CHOICE(fn, first) fn, first
#define NO_CHOICE NULL, 0

/* The scene's own bounds are generous but finite: a number outside them is
 * a typo, not a physics question.  The library's settings carry taper.h's
 * ranges for the documentation only: the library's setters check them. */
static const scene_var table[] = {
    {"chain", "profile", SCENE_CHOICE, 0, AT(chain.profile), NULL, SCENE_LIB_CHAIN, NULL, 0, 0,
     CHOICE(profile_choice, 0),
     "radius profile R_k: monodisperse (1), backward_linear (1+s(k-1)), forward_linear "
     "(1-s(k-1)), backward_exponential ((1-q)^(1-k)), forward_exponential ((1+q)^(1-k)), "
     "custom (radii or radii_file), decorated (pattern repeated)"},
    {"chain", "n_granules", SCENE_INTEGER, SCENE_COUNT | SCENE_SWEEP, AT(chain.n_granules), NULL,
     SCENE_LIB_CHAIN, NULL, TAPER_N_GRANULES_MIN, TAPER_N_GRANULES_MAX, NO_CHOICE,
     "number of granules N (custom profile: may be left out, then N = number of radii)"},
    {"chain", "s", SCENE_REAL, SCENE_SWEEP | SCENE_LIST_FIELD, AT(chain.s), NULL, SCENE_LIB_CHAIN, NULL, 0,
     TAPER_S_MAX, NO_CHOICE,
     "linear tapering S (backward_linear, forward_linear: N < 1 + 1/S); a list of values "
     "sweeps it"},
    {"chain", "q", SCENE_REAL, SCENE_SWEEP | SCENE_LIST_FIELD, AT(chain.q), NULL, SCENE_LIB_CHAIN, NULL, 0,
     TAPER_Q_MAX, NO_CHOICE,
     "exponential tapering q (backward_exponential needs q < 1); a list of values sweeps it"},
    {"chain", "exponent", SCENE_REAL, SCENE_SWEEP, AT(chain.exponent), NULL, SCENE_LIB_CHAIN,
     NULL, TAPER_EXPONENT_MIN, TAPER_EXPONENT_MAX, NO_CHOICE,
     "contact exponent n: force ~ overlap^(n-1); 2.5 is Hertz"},
    {"chain", "radii", SCENE_REAL_LIST, SCENE_LO_OPEN, AT(chain.radii), NULL, SCENE_LIB_CHAIN,
     NULL, 0, INFINITY, NO_CHOICE,
     "custom profile only: the radii R_1, ..., R_N (R_1 = 1 is the unit of length)"},
    {"chain", "radii_file", SCENE_STRING, SCENE_EXTRA, AT(chain.radii_file), "''", SCENE_OWN,
     NULL, 0, 0, NO_CHOICE,
     "custom profile only, instead of radii: a text file with one radius per line ('#' starts "
     "a comment), its path relative to the scene file; any number of granules"},
    {"chain", "pattern", SCENE_REAL_LIST, SCENE_LO_OPEN | SCENE_EXTRA, AT(chain.pattern), NULL,
     SCENE_LIB_CHAIN, NULL, 0, INFINITY, NO_CHOICE,
     "decorated profile only: the radii of one period, starting with 1 (R_1); granule k has "
     "radius pattern((k-1) mod P + 1), e.g. 1, 0.5 for a large and a small granule"},
    {"chain", "disorder", SCENE_CHOICE, SCENE_EXTRA, AT(chain.disorder), NULL, SCENE_LIB_CHAIN,
     NULL, 0, 0, CHOICE(disorder_choice, 0),
     "what a random disorder perturbs: the 'radius' or the 'mass' of every granule k >= 2, "
     "by a factor 1 + disorder_amplitude u_k, u_k uniform in [-1, 1)"},
    {"chain", "disorder_amplitude", SCENE_REAL, SCENE_HI_OPEN | SCENE_SWEEP | SCENE_EXTRA,
     AT(chain.disorder_amplitude), NULL, SCENE_LIB_CHAIN, NULL, 0, 1, NO_CHOICE,
     "amplitude of the disorder, below 1; 0: none"},
    {"chain", "seed", SCENE_INTEGER, SCENE_SWEEP | SCENE_EXTRA, AT(chain.seed), NULL,
     SCENE_LIB_CHAIN, NULL, 0, 9007199254740992.0, NO_CHOICE,
     "seed of the disorder: u_k depends on (seed, k) alone, the same on every machine and for "
     "every N; a list of seeds runs an ensemble"},
    {"chain", "load", SCENE_REAL, SCENE_SWEEP | SCENE_EXTRA, AT(chain.load), NULL,
     SCENE_LIB_CHAIN, NULL, 0, INFINITY, NO_CHOICE,
     "static compressive force F0 through the chain (precompression; rescaled force of eq. "
     "(5)): every contact starts at its static overlap; 0: the paper's just-touching chain"},

    {"ends", "left", SCENE_CHOICE, SCENE_EXTRA, AT(ends.left), NULL, SCENE_LIB_CHAIN, NULL, 0, 0,
     CHOICE(boundary_choice, 0),
     "granule 1's end: 'free', or 'wall' (a fixed flat wall touching granule 1; not with a "
     "striker)"},
    {"ends", "right", SCENE_CHOICE, SCENE_EXTRA, AT(ends.right), NULL, SCENE_LIB_CHAIN, NULL, 0,
     0, CHOICE(boundary_choice, 0),
     "granule N's end: 'free', or 'wall' (the pulse reflects from it; its force is a sensor's "
     "reading)"},
    {"ends", "left_compliance", SCENE_REAL, SCENE_SWEEP | SCENE_EXTRA, AT(ends.left_compliance),
     NULL, SCENE_LIB_CHAIN, NULL, 0, INFINITY, NO_CHOICE,
     "compliance (1 - nu^2)/E of the left wall relative to granule 1's: 0 rigid, 1 granule 1's "
     "material (with &material: from &material wall)"},
    {"ends", "right_compliance", SCENE_REAL, SCENE_SWEEP | SCENE_EXTRA,
     AT(ends.right_compliance), NULL, SCENE_LIB_CHAIN, NULL, 0, INFINITY, NO_CHOICE,
     "compliance of the right wall relative to granule 1's (as left_compliance)"},

    {"striker", "radius", SCENE_REAL, SCENE_SWEEP | SCENE_EXTRA, AT(striker.radius), NULL,
     SCENE_LIB_CHAIN, "striker_radius", 0, INFINITY, NO_CHOICE,
     "radius of a striker relative to R_1, hitting granule 1 (at rest) with unit velocity; 0: "
     "no striker, the impulse v_1 = 1 of the paper"},
    {"striker", "density", SCENE_REAL, SCENE_LO_OPEN | SCENE_SWEEP | SCENE_EXTRA,
     AT(striker.density), NULL, SCENE_LIB_CHAIN, "striker_density", 0, INFINITY, NO_CHOICE,
     "the striker's density relative to granule 1's: its mass is density radius^3 (with "
     "&material: from &material striker)"},
    {"striker", "compliance", SCENE_REAL, SCENE_SWEEP | SCENE_EXTRA, AT(striker.compliance), NULL,
     SCENE_LIB_CHAIN, "striker_compliance", 0, INFINITY, NO_CHOICE,
     "the striker's compliance (1 - nu^2)/E relative to granule 1's (with &material: from "
     "&material striker)"},
    {"striker", "piston", SCENE_CHOICE, SCENE_EXTRA, AT(striker.piston), NULL, SCENE_LIB_CHAIN,
     NULL, 0, 0, CHOICE(piston_choice, 0),
     "'none', or a piston touching granule 1 (at rest) that moves at unit velocity: 'push' for "
     "piston_duration, then stops; 'steady' for ever (not with a striker, a left wall or a "
     "load).  The energy budget adds up to its work (docs/physics.md, \"Piston\")"},
    {"striker", "piston_duration", SCENE_REAL, SCENE_SWEEP | SCENE_EXTRA,
     AT(striker.piston_duration), NULL, SCENE_LIB_CHAIN, "piston_duration", 0, INFINITY,
     NO_CHOICE, "how long piston = 'push' pushes (rescaled time, > 0); 0 otherwise"},
    {"striker", "piston_compliance", SCENE_REAL, SCENE_SWEEP | SCENE_EXTRA,
     AT(striker.piston_compliance), NULL, SCENE_LIB_CHAIN, "piston_compliance", 0, INFINITY,
     NO_CHOICE, "compliance of the piston's face relative to granule 1's (as a wall's: 0 rigid)"},

    {"losses", "damping", SCENE_REAL, SCENE_SWEEP | SCENE_EXTRA, AT(losses.damping), NULL,
     SCENE_LIB_CHAIN, NULL, 0, INFINITY, NO_CHOICE,
     "viscoelastic contacts (Kuwabara-Kono): each contact pushes with r_k (z^(n-1) + damping "
     "d(z^(n-1))/dt), never pulls; a (rescaled) time; 0: elastic"},
    {"losses", "drag", SCENE_REAL, SCENE_SWEEP | SCENE_EXTRA, AT(losses.drag), NULL,
     SCENE_LIB_CHAIN, NULL, 0, INFINITY, NO_CHOICE,
     "hydrodynamic friction: a force -drag v_k on every granule (and the striker); 0: none"},

    {"material", "young", SCENE_REAL, SCENE_LO_OPEN | SCENE_SWEEP | SCENE_EXTRA,
     AT(material.young), NULL, SCENE_OWN, NULL, 0, INFINITY, NO_CHOICE,
     "Young's modulus E of material 1 [Pa] (e.g. 193e9, stainless steel); the group needs "
     "young, poisson, density, radius, velocity"},
    {"material", "poisson", SCENE_REAL, SCENE_LO_OPEN | SCENE_HI_OPEN | SCENE_SWEEP | SCENE_EXTRA,
     AT(material.poisson), NULL, SCENE_OWN, NULL, -1, 0.5, NO_CHOICE,
     "Poisson ratio nu of material 1"},
    {"material", "density", SCENE_REAL, SCENE_LO_OPEN | SCENE_SWEEP | SCENE_EXTRA,
     AT(material.density), NULL, SCENE_OWN, NULL, 0, INFINITY, NO_CHOICE,
     "density of material 1 [kg/m^3]"},
    {"material", "radius", SCENE_REAL, SCENE_LO_OPEN | SCENE_SWEEP | SCENE_EXTRA,
     AT(material.radius), NULL, SCENE_OWN, NULL, 0, INFINITY, NO_CHOICE,
     "radius R_1 of granule 1 [m] (every length of the scene is relative to it)"},
    {"material", "velocity", SCENE_REAL, SCENE_LO_OPEN | SCENE_SWEEP | SCENE_EXTRA,
     AT(material.velocity), NULL, SCENE_OWN, NULL, 0, INFINITY, NO_CHOICE,
     "velocity of the impulse given to granule 1, or of the striker [m/s]"},
    {"material", "other_young", SCENE_REAL_LIST, SCENE_LO_OPEN | SCENE_EXTRA,
     AT(material.other_young), NULL, SCENE_OWN, NULL, 0, INFINITY, NO_CHOICE,
     "mixed chains: Young's moduli of materials 2, 3, ... [Pa]"},
    {"material", "other_poisson", SCENE_REAL_LIST, SCENE_LO_OPEN | SCENE_HI_OPEN | SCENE_EXTRA,
     AT(material.other_poisson), NULL, SCENE_OWN, NULL, -1, 0.5, NO_CHOICE,
     "Poisson ratios of materials 2, 3, ..."},
    {"material", "other_density", SCENE_REAL_LIST, SCENE_LO_OPEN | SCENE_EXTRA,
     AT(material.other_density), NULL, SCENE_OWN, NULL, 0, INFINITY, NO_CHOICE,
     "densities of materials 2, 3, ... [kg/m^3]"},
    {"material", "sequence", SCENE_REAL_LIST, SCENE_EXTRA, AT(material.sequence), NULL,
     SCENE_OWN, NULL, 1, 1000, NO_CHOICE,
     "the material of granules 1, 2, ..., repeated along the chain (e.g. 1, 2: alternating); "
     "left out: material 1 throughout"},
    {"material", "wall", SCENE_INTEGER, SCENE_EXTRA, AT(material.wall), "0", SCENE_OWN, NULL, 0,
     1000, NO_CHOICE, "the walls' material (&ends); 0: rigid"},
    {"material", "striker", SCENE_INTEGER, SCENE_EXTRA, AT(material.striker), "1", SCENE_OWN,
     NULL, 1, 1000, NO_CHOICE, "the striker's material (&striker)"},

    {"solver", "method", SCENE_CHOICE, 0, AT(solver.method), NULL, SCENE_LIB_SOLVER, NULL, 0, 0,
     CHOICE(method_choice, 0),
     "integrator: 'adams' (Adams-Moulton, fixed point) or 'bdf' (BDF, banded Jacobian)"},
    {"solver", "rtol", SCENE_REAL, SCENE_SWEEP, AT(solver.rtol), NULL, SCENE_LIB_SOLVER, NULL,
     TAPER_RTOL_MIN, TAPER_RTOL_MAX, NO_CHOICE,
     "relative tolerance of the integrator (below 1e-14 double precision cannot follow)"},
    {"solver", "atol", SCENE_REAL, SCENE_LO_OPEN | SCENE_SWEEP, AT(solver.atol), NULL, SCENE_LIB_SOLVER, NULL,
     0, TAPER_ATOL_MAX, NO_CHOICE,
     "absolute tolerance, in units of each granule's binary-collision velocity and maximum "
     "compression (relative to the pulse wherever it is)"},
    {"solver", "window", SCENE_LOGICAL, 0, AT(solver.window), NULL, SCENE_LIB_SOLVER, NULL, 0,
     0, NO_CHOICE,
     "integrate only the granules that can move (exact and faster); .false.: the whole chain"},
    {"solver", "last_granule", SCENE_INTEGER, SCENE_COUNT | SCENE_SWEEP, AT(solver.last_granule),
     NULL, SCENE_LIB_SOLVER, NULL, 0, TAPER_N_GRANULES_MAX, NO_CHOICE,
     "stop once the pulse has passed this granule (at most n_granules); 0: the whole chain"},
    {"solver", "t_max", SCENE_REAL, SCENE_SWEEP, AT(solver.t_max), NULL, SCENE_LIB_SOLVER, NULL, 0,
     INFINITY, NO_CHOICE, "stop at this time with a partial result; 0: no limit"},
    {"solver", "max_steps", SCENE_INTEGER, SCENE_SWEEP, AT(solver.max_steps), NULL, SCENE_LIB_SOLVER, NULL,
     0, INFINITY, NO_CHOICE,
     "stop after this many internal steps with a partial result; 0: no limit"},
    {"solver", "t_end", SCENE_REAL, SCENE_SWEEP | SCENE_EXTRA, AT(solver.t_end), NULL,
     SCENE_LIB_SOLVER, NULL, 0, INFINITY, NO_CHOICE,
     "integrate until this time even after the pulse has passed every granule (to follow "
     "reflections, and the sensors); 0: stop once the pulse has passed"},
    {"solver", "numerics", SCENE_LOGICAL, 0, AT(solver.numerics), ".true.", SCENE_OWN, NULL, 0,
     0, NO_CHOICE, "integrate the dynamics; .false.: binary-collision theory only (fast)"},

    {"sensors", "interval", SCENE_REAL, SCENE_SWEEP | SCENE_EXTRA, AT(sensors.interval), "0",
     SCENE_OWN, NULL, 0, INFINITY, NO_CHOICE,
     "sampling interval (rescaled time) of the sensors (DIR/sensors.tsv), the wall forces "
     "(DIR/walls.tsv) and the space-time picture; 0: no sampling"},
    {"sensors", "granules", SCENE_REAL_LIST, SCENE_EXTRA, AT(sensors.granules), NULL, SCENE_OWN,
     NULL, 1, TAPER_N_GRANULES_MAX, NO_CHOICE,
     "granules whose displacement x, velocity v and contact forces are written to "
     "DIR/sensors.tsv at every sample"},
    {"sensors", "spacetime", SCENE_LOGICAL, SCENE_EXTRA, AT(sensors.spacetime), ".false.",
     SCENE_OWN, NULL, 0, 0, NO_CHOICE,
     "the space-time picture of v(k, t): DIR/spacetime.tsv and DIR/spacetime.png (gnuplot)"},
    {"sensors", "spacetime_granules", SCENE_INTEGER, SCENE_EXTRA, AT(sensors.spacetime_granules),
     "200", SCENE_OWN, NULL, 2, 100000, NO_CHOICE,
     "at most this many granules across the picture: every ceil(N / this)-th granule"},
    {"sensors", "spacetime_times", SCENE_INTEGER, SCENE_EXTRA, AT(sensors.spacetime_times), "500",
     SCENE_OWN, NULL, 2, 1000000, NO_CHOICE,
     "at most this many times down the picture: whenever more samples come, every other row "
     "is dropped (the picture's interval doubles)"},

    {"output", "dir", SCENE_STRING, SCENE_FROM_PATH, AT(output.dir), NULL, SCENE_OWN, NULL, 0, 0,
     NO_CHOICE,
     "output directory, created if missing (default out/NAME for scene NAME.nml; -o overrides)"},
    {"output", "progress", SCENE_LOGICAL, 0, AT(output.progress), ".true.", SCENE_OWN, NULL, 0,
     0, NO_CHOICE, "show a progress line on stderr when it is a terminal"},
    {"output", "threads", SCENE_INTEGER, 0, AT(output.threads), "0", SCENE_OWN, NULL, 0, 256,
     NO_CHOICE,
     "runs of a sweep computed at once (results identical to one at a time); 0: one per core"},
    {"output", "columns", SCENE_STRING, 0, AT(output.columns), "''", SCENE_OWN, NULL, 0, 0,
     NO_CHOICE,
     "columns of granules.tsv and sweep.tsv, names separated by blanks or commas, written in "
     "the file's order with k always first (e.g. 'v_peak theory_v'); empty: every column the "
     "run has (without numerics: k R m X0 theory_v theory_T theory_t)"},
    {"output", "every", SCENE_INTEGER, 0, AT(output.every), "1", SCENE_OWN, NULL, 1, 1e7,
     NO_CHOICE, "write the rows of granules k = 1, 1 + every, 1 + 2 every, ... and the last"},
    {"output", "max_energy_error", SCENE_REAL, SCENE_LO_OPEN, AT(output.max_energy_error),
     "1e-3", SCENE_OWN, NULL, 0, 1e300, NO_CHOICE,
     "a run whose relative energy error exceeds this is UNTRUSTED: its granules.tsv says so "
     "and taper exits with status 4"},
    {"output", "max_momentum_error", SCENE_REAL, SCENE_LO_OPEN, AT(output.max_momentum_error),
     "1e-3", SCENE_OWN, NULL, 0, 1e300, NO_CHOICE,
     "the same bound on the relative momentum error"},
    {"output", "units", SCENE_CHOICE, SCENE_EXTRA, AT(output.units), "'rescaled'", SCENE_OWN,
     NULL, 0, 0, CHOICE(units_choice, 0),
     "units of the result files: 'rescaled' (eq. (5) of arXiv:0905.4512), or 'si' (needs "
     "&material; each column's unit in its header, e.g. t_pass[s])"},

    {"fit", "model", SCENE_CHOICE, 0, AT(fit.model), "'none'", SCENE_LIB_FIT, NULL, 0, 0,
     CHOICE(fit_model_choice, SCENE_FIT_NONE),
     "'none' (no fit), or y = 'power' a x^b, 'exponential' a e^(b x), 'divergence_b' "
     "a (1 - b x)^-p, 'divergence_c' a (1 - x/C)^-p, 'divergence_m' a (1 + x/M)^-f; fitted "
     "to ln y; writes DIR/fits.tsv"},
    {"fit", "x", SCENE_CHOICE, 0, AT(fit.x), "'k'", SCENE_OWN, NULL, 0, 0,
     CHOICE(quantity_choice, 0),
     "abscissa: k (granule), v (numerics: v_peak; theory: v_k, eq. (9)), T_res (T_res; T_k), "
     "t (pulse passes k: t_pass; eq. (19)), t_reach (pulse reaches k: t of k-1), "
     "t_peak (time of v_peak; theory: t_reach, when k leaves its collision with k-1)"},
    {"fit", "y", SCENE_CHOICE, 0, AT(fit.y), "'v'", SCENE_OWN, NULL, 0, 0,
     CHOICE(quantity_choice, 0), "ordinate, one of the quantities of x"},
    {"fit", "k_min", SCENE_INTEGER, 0, AT(fit.k_min), "1", SCENE_OWN, NULL, 1, 1e7, NO_CHOICE,
     "first granule of the fit window"},
    {"fit", "k_max", SCENE_INTEGER, 0, AT(fit.k_max), "0", SCENE_OWN, NULL, 0, 1e7, NO_CHOICE,
     "last granule of the fit window; 0: the last granule with a value"},
    {"fit", "p", SCENE_REAL, SCENE_LO_OPEN, AT(fit.p), NULL, SCENE_LIB_FIT, "exponent", 0,
     INFINITY, NO_CHOICE,
     "fixed exponent p of divergence_b and divergence_c; left out: 3/2 (divergence_b), "
     "fitted (divergence_c)"},
    {"fit", "report", SCENE_CHOICE, 0, AT(fit.report), "'b'", SCENE_OWN, NULL, 0, 0,
     CHOICE(report_choice, 0),
     "the parameter tabulated: a or b (power, exponential, divergence_b), p (divergence_b, "
     "_c), c (divergence_c), m or f (divergence_m)"},
    {"fit", "factor", SCENE_REAL, 0, AT(fit.factor), "1", SCENE_OWN, NULL, -1e3, 1e3, NO_CHOICE,
     "the tabulated value is factor * parameter (e.g. -1: a decay rate from b < 0)"},
    {"fit", "label", SCENE_STRING, 0, AT(fit.label), "''", SCENE_OWN, NULL, 0, 0, NO_CHOICE,
     "name of the tabulated value in tables and plots; empty: the parameter's name"},
    {"fit", "theory", SCENE_CHOICE, 0, AT(fit.theory), "'fit'", SCENE_OWN, NULL, 0, 0,
     CHOICE(theory_choice, 0),
     "theory column: 'fit' (the same fit of the exact binary-collision theory), or the "
     "closed form: 'rate' |ln A(q)|, 'f' f(q) (q -> -q for forward chains), 'b' S/(1+S)"},

    {"table", "name", SCENE_STRING, 0, AT(table.name), "''", SCENE_OWN, NULL, 0, 0, NO_CHOICE,
     "table label (e.g. 'Table I'); non-empty: write DIR/table.tsv and print the table"},
    {"table", "caption", SCENE_STRING, 0, AT(table.caption), "''", SCENE_OWN, NULL, 0, 0,
     NO_CHOICE, "one line printed above the table"},
    {"table", "digits", SCENE_INTEGER, 0, AT(table.digits), "4", SCENE_OWN, NULL, 1, 12,
     NO_CHOICE, "decimals printed on stdout (table.tsv has every digit)"},
    {"table", "paper_theory", SCENE_REAL_LIST, 0, AT(table.paper_theory), NULL, SCENE_OWN, NULL,
     0, 0, NO_CHOICE, "the paper's theory column, one value per swept value"},
    {"table", "paper_numerics", SCENE_REAL_LIST, 0, AT(table.paper_numerics), NULL, SCENE_OWN,
     NULL, 0, 0, NO_CHOICE, "the paper's numerics column, one value per swept value"},

    {"figure", "name", SCENE_STRING, 0, AT(figure.name), "''", SCENE_OWN, NULL, 0, 0, NO_CHOICE,
     "figure label (e.g. 'Fig. 1'); non-empty: write DIR/figure.gp, its data, and "
     "DIR/figure.png when gnuplot is installed"},
    {"figure", "title", SCENE_STRING, 0, AT(figure.title), "''", SCENE_OWN, NULL, 0, 0,
     NO_CHOICE, "title line of the plot"},
    {"figure", "x", SCENE_CHOICE, 0, AT(figure.x), "'k'", SCENE_OWN, NULL, 0, 0,
     CHOICE(quantity_choice, 0), "abscissa of the main panel (quantities as for &fit x)"},
    {"figure", "y", SCENE_CHOICE, 0, AT(figure.y), "'v'", SCENE_OWN, NULL, 0, 0,
     CHOICE(quantity_choice, 0), "ordinate of the main panel"},
    {"figure", "curves", SCENE_CHOICE, 0, AT(figure.curves), "'both'", SCENE_OWN, NULL, 0, 0,
     CHOICE(curves_choice, 0),
     "series drawn: theory (open circles), numerics (filled circles), or both"},
    {"figure", "log_x", SCENE_LOGICAL, 0, AT(figure.log_x), ".false.", SCENE_OWN, NULL, 0, 0,
     NO_CHOICE, "logarithmic x axis"},
    {"figure", "log_y", SCENE_LOGICAL, 0, AT(figure.log_y), ".false.", SCENE_OWN, NULL, 0, 0,
     NO_CHOICE, "logarithmic y axis"},
    {"figure", "every", SCENE_INTEGER, 0, AT(figure.every), "1", SCENE_OWN, NULL, 1, 1e6,
     NO_CHOICE, "draw every n-th granule (the first and every n-th after it)"},
    {"figure", "k_max", SCENE_INTEGER, 0, AT(figure.k_max), "0", SCENE_OWN, NULL, 0, 1e7,
     NO_CHOICE, "last granule drawn; 0: the whole chain"},
    {"figure", "x_label", SCENE_STRING, 0, AT(figure.x_label), "''", SCENE_OWN, NULL, 0, 0,
     NO_CHOICE, "x axis label; empty: from x"},
    {"figure", "y_label", SCENE_STRING, 0, AT(figure.y_label), "''", SCENE_OWN, NULL, 0, 0,
     NO_CHOICE, "y axis label; empty: from y"},
    {"figure", "inset", SCENE_LOGICAL, 0, AT(figure.inset), ".false.", SCENE_OWN, NULL, 0, 0,
     NO_CHOICE, "an inset inside the main panel (as the paper's Figs. 1, 2, 9): the &fit value of theory and numerics against the swept variable"},
    {"figure", "inset_reference", SCENE_REAL, 0, AT(figure.inset_reference), NULL, SCENE_OWN,
     NULL, -1e3, 1e3, NO_CHOICE,
     "a horizontal line in the inset (e.g. an asymptotic exponent); left out: none"},

    {"sweep", "mode", SCENE_CHOICE, 0, AT(sweep.mode), "'grid'", SCENE_OWN, NULL, 0, 0,
     CHOICE(sweep_mode_choice, 0),
     "several variables given lists: 'grid' runs every combination (the variable later in "
     "this table varies fastest), 'zip' the i-th values together (lists of equal length)"},
};
#define N_VARS (sizeof table / sizeof table[0])

/* Every validated scene's echo must read back (docs/robustness.md, finding
 * B).  The echo writes a list value in at most 32 bytes (24 for %.17g of a
 * double, then ',' and at most a line break and 6 spaces); all lists of
 * more than one value hold at most SCENE_MAX_LIST values together
 * (scene_parse.c); every other variable is one line of at most
 * SCENE_MAX_LINE characters (a string echoes as long as it was written)
 * plus its name. */
_Static_assert(32ull * SCENE_MAX_LIST + N_VARS * (SCENE_MAX_LINE + 128ull) <= SCENE_MAX_FILE,
               "the echo of a valid scene may exceed SCENE_MAX_FILE");

size_t scene_var_count(void) { return N_VARS; }
const scene_var *scene_var_at(size_t i) { return i < N_VARS ? &table[i] : NULL; }
const char *scene_var_group(size_t i) { return i < N_VARS ? table[i].group : NULL; }
const char *scene_var_name(size_t i) { return i < N_VARS ? table[i].name : NULL; }
scene_type scene_var_type(size_t i) { return i < N_VARS ? table[i].type : SCENE_STRING; }
int scene_var_sweeps(size_t i) { return i < N_VARS && (table[i].flags & SCENE_LIST_FIELD) != 0; }
int scene_var_takes_list(size_t i) { return i < N_VARS && (table[i].flags & SCENE_SWEEP) != 0; }
size_t scene_var_index(const scene_var *var) { return (size_t)(var - table); }

int scene_var_find(const char *group, const char *name)
{
    if (!group || !name) return -1;
    for (size_t i = 0; i < N_VARS; i++)
        if (strcasecmp(table[i].group, group) == 0 && strcasecmp(table[i].name, name) == 0)
            return (int)i;
    return -1;
}

int scene_var_of_field(scene_lib lib, const char *field)
{
    if (lib == SCENE_OWN || !field) return -1;
    for (size_t i = 0; i < N_VARS; i++) {
        const char *name = table[i].lib_field ? table[i].lib_field : table[i].name;
        if (table[i].lib == lib && strcmp(name, field) == 0) return (int)i;
    }
    return -1;
}

const char *scene_type_name(const scene_var *var)
{
    static const char *const names[] = {"string", "real", "integer", "logical", "real list",
                                        "string"};
    if (var->type == SCENE_REAL && (var->flags & SCENE_SWEEP)) return "real (list: sweep)";
    if (var->type == SCENE_INTEGER && (var->flags & SCENE_SWEEP)) return "integer (list: sweep)";
    return names[var->type];
}

/* ---- typed fields ------------------------------------------------------------- */

void *scene_field(scene_config *cfg, const scene_var *var) { return (char *)cfg + var->offset; }

const void *scene_cfield(const scene_config *cfg, const scene_var *var)
{
    return (const char *)cfg + var->offset;
}

int scene_var_is_list(const scene_var *var)
{
    return var->type == SCENE_REAL_LIST || (var->flags & SCENE_LIST_FIELD);
}

size_t scene_field_size(const scene_var *var)
{
    if (scene_var_is_list(var)) return sizeof(scene_reals);
    switch (var->type) {
    case SCENE_STRING: return sizeof(char *);
    case SCENE_REAL: return sizeof(double);
    case SCENE_INTEGER: return sizeof(long long);
    default: return sizeof(int); /* LOGICAL, CHOICE */
    }
}

void scene_field_clear(scene_config *cfg, const scene_var *var)
{
    void *f = scene_field(cfg, var);
    if (cfg->sweep.lists) {
        scene_reals *l = &cfg->sweep.lists[scene_var_index(var)];
        free(l->v);
        l->v = NULL;
        l->n = 0;
    }
    if (scene_var_is_list(var)) {
        scene_reals *r = f;
        free(r->v);
        r->v = NULL;
        r->n = 0;
    } else if (var->type == SCENE_STRING) {
        char **s = f;
        free(*s);
        *s = NULL;
    }
}

int scene_choice_find(const scene_var *var, const char *name, int *value)
{
    for (int v = var->choice_first; var->choice(v); v++) {
        if (strcasecmp(var->choice(v), name) == 0) {
            *value = v;
            return 0;
        }
    }
    return -1;
}

const char *scene_var_text(const scene *sc, size_t i)
{
    if (i >= N_VARS) return "";
    const scene_var *var = &table[i];
    const void *f = scene_cfield(&sc->cfg, var);
    if (var->type == SCENE_STRING) {
        char *const *s = f;
        return *s ? *s : "";
    }
    if (var->type == SCENE_CHOICE) {
        int v;
        memcpy(&v, f, sizeof v);
        const char *name = var->choice(v);
        return name ? name : "";
    }
    return "";
}

long long scene_var_integer(const scene *sc, size_t i)
{
    if (i >= N_VARS) return 0;
    const void *f = scene_cfield(&sc->cfg, &table[i]);
    if (table[i].type == SCENE_INTEGER) {
        long long x;
        memcpy(&x, f, sizeof x);
        return x;
    }
    if (table[i].type == SCENE_LOGICAL || table[i].type == SCENE_CHOICE) {
        int x;
        memcpy(&x, f, sizeof x);
        return x;
    }
    return 0;
}

const double *scene_var_reals(const scene *sc, size_t i, size_t *n)
{
    *n = 0;
    if (i >= N_VARS) return NULL;
    const scene_var *var = &table[i];
    const void *f = scene_cfield(&sc->cfg, var);
    if (scene_var_is_list(var)) {
        const scene_reals *r = f;
        *n = r->n;
        return r->v;
    }
    if (var->type == SCENE_REAL) {
        if (sc->cfg.sweep.lists && sc->cfg.sweep.lists[i].n > 1) {
            *n = sc->cfg.sweep.lists[i].n;
            return sc->cfg.sweep.lists[i].v;
        }
        const double *x = f;
        *n = isnan(*x) ? 0 : 1; /* NaN: a real without default, left out */
        return x;
    }
    return NULL;
}

size_t scene_row_count(const scene_config *cfg, size_t i)
{
    const scene_var *var = &table[i];
    if (scene_var_is_list(var)) return ((const scene_reals *)scene_cfield(cfg, var))->n;
    if (cfg->sweep.lists && cfg->sweep.lists[i].n > 1) return cfg->sweep.lists[i].n;
    return 1;
}

double scene_row_value(const scene_config *cfg, size_t i, size_t j)
{
    const scene_var *var = &table[i];
    const void *f = scene_cfield(cfg, var);
    if (scene_var_is_list(var)) {
        const scene_reals *r = f;
        return j < r->n ? r->v[j] : NAN;
    }
    if (cfg->sweep.lists && cfg->sweep.lists[i].n > 1)
        return j < cfg->sweep.lists[i].n ? cfg->sweep.lists[i].v[j] : NAN;
    if (var->type == SCENE_INTEGER) {
        long long x;
        memcpy(&x, f, sizeof x);
        return (double)x;
    }
    double x;
    memcpy(&x, f, sizeof x);
    return x;
}

/* ---- numbers as scene text ------------------------------------------------- */

void scene_format_real(double x, char buf[SCENE_REAL_TEXT])
{
    /* Shortest representation that reads back exactly: tidy scenes, and
     * the echo re-parses to the same doubles.  At most 24 characters
     * (%.17g of a double), so buf cannot overflow. */
    const size_t size = SCENE_REAL_TEXT;
    int prec = 15;
    snprintf(buf, size, "%.*g", prec, x);
    if (strtod(buf, NULL) == x) {
        /* 15 digits suffice: the shortest from 1 up (tidy values are short) */
        for (prec = 1; prec < 15; prec++) {
            snprintf(buf, size, "%.*g", prec, x);
            if (strtod(buf, NULL) == x) break;
        }
    } else {
        /* a value with 16 or 17 significant digits (most computed ones):
         * two tries rather than 17, so that long lists echo quickly */
        for (prec = 16; prec < 17; prec++) {
            snprintf(buf, size, "%.*g", prec, x);
            if (strtod(buf, NULL) == x) break;
        }
    }
    /* %g switches to an exponent once it has fewer digits than the integer
     * part: print 20 rather than 2e+01, keep 1e+06 and beyond short. */
    double mag = fabs(x);
    if (mag >= 1.0 && mag < 1e6) {
        int digits = (int)floor(log10(mag)) + 1;
        if (digits > prec) prec = digits;
    }
    snprintf(buf, size, "%.*g", prec, x);
}

/* ---- diagnostics -------------------------------------------------------------- */

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
    int g = scene_group_index(table[i].group);
    return g < 0 ? 0 : sc->group_line[g];
}

void scene_var_error(scene *sc, size_t i, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    char *raw = text_vprintf(fmt, ap);
    va_end(ap);
    record(sc, var_line(sc, i), table[i].group, table[i].name, raw);
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

int scene_line(const scene *sc, size_t offset)
{
    for (size_t i = 0; i < N_VARS; i++)
        if (table[i].offset == offset) return sc->origin[i].line;
    return 0;
}

/* The row a library error is reported against: n_granules resolved from
 * the radii is the radii's fault. */
int scene_error_row(const scene *sc, scene_lib lib, const char *field)
{
    int i = scene_var_of_field(lib, field);
    /* taper_sim_alloc checks the chain with the solver: its fields name
     * either's settings (damping with n < 2, n_granules beyond the
     * resolution of time). */
    if (i < 0 && lib == SCENE_LIB_SOLVER) i = scene_var_of_field(SCENE_LIB_CHAIN, field);
    int from_file = sc->cfg.chain.file_radii.n > 0;
    if (i >= 0 && sc->n_from_radii && table[i].offset == offsetof(scene_config, chain.n_granules))
        i = scene_var_find("chain", from_file ? "radii_file" : "radii");
    /* The radii of a file are the file's. */
    if (i >= 0 && from_file && table[i].offset == offsetof(scene_config, chain.radii))
        i = scene_var_find("chain", "radii_file");
    return i;
}

void scene_print_library_error(const scene *sc, scene_lib lib, const taper_error *err, FILE *fp)
{
    int i = scene_error_row(sc, lib, err->field);
    if (i < 0)
        fprintf(fp, "%s: %s\n", sc->path, err->message);
    else
        print_diag(sc->path, var_line(sc, (size_t)i), table[i].group, table[i].name, err->message,
                   fp);
}

void scene_print_output_error(const scene *sc, const char *message, FILE *fp)
{
    int i = scene_var_find("output", "dir");
    int line = sc->origin[i].line;
    print_diag(sc->path, line, "output", "dir", message, fp);
}
