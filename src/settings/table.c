/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * table.c -- the one table of settings (taper.h, "Settings by name"): a row
 * per setting of taper_chain_spec and taper_solver_spec, with its name,
 * the group scene files put it in, its type, physical dimension, range,
 * default, one-line description and the reason for its bounds, and where
 * it lives in its spec.  The typed setters of taper.h, the by-name setters,
 * the getters and the defaults all read it; so do the driver's scene
 * variables, `taper --doc`, and the Python and Fortran bindings.  Adding a
 * setting is a row here (appended to its object's rows) plus what the
 * library does with it.
 */
#include "settings/settings.h"

#include <math.h>
#include <stddef.h>

#define CHAIN_AT(field) .info.object = TAPER_SETTING_CHAIN, \
                        .offset = offsetof(struct taper_chain_spec, field)
#define SOLVER_AT(field) .info.object = TAPER_SETTING_SOLVER, \
                         .offset = offsetof(struct taper_solver_spec, field)
#define LIST_AT(field, count) CHAIN_AT(field), .storage = STORE_LIST, \
                              .count_offset = offsetof(struct taper_chain_spec, count), \
                              .info.type = TAPER_SETTING_LIST
#define REAL .info.type = TAPER_SETTING_REAL, .storage = STORE_DOUBLE
#define CHOICE(names) .info.type = TAPER_SETTING_CHOICE, .storage = STORE_INT, \
                      .info.choices = (names)
#define RANGE(lo, hi) .info.min = (lo), .info.max = (hi)
#define DIM(d) .info.dimension = TAPER_DIM_##d
/* Finite and >= 0: [0, inf). */
#define NONNEGATIVE RANGE(0.0, INFINITY), .info.max_open = 1
/* Finite and > 0: (0, inf). */
#define POSITIVE RANGE(0.0, INFINITY), .info.min_open = 1, .info.max_open = 1
/* A whole number a double holds exactly: scene files, Python and Fortran
 * pass every number as one. */
#define EXACT_INTEGER 9007199254740992.0

const setting_row taper_setting_rows[] = {
    /* ---- the chain: the paper's model ---------------------------------- */
    {.info.name = "profile", .info.group = "chain", DIM(NUMBER),
              .info.default_value = TAPER_MONODISPERSE,
              .info.description = "radius profile R_k: monodisperse (1), backward_linear "
                                  "(1+s(k-1)), forward_linear (1-s(k-1)), backward_exponential "
                                  "((1-q)^(1-k)), forward_exponential ((1+q)^(1-k)), custom "
                                  "(radii), decorated (pattern repeated)",
              .info.bounds_reason = "",
     CHOICE(taper_profile_names), CHAIN_AT(profile)},
    {.info.name = "n_granules", .info.group = "chain", .info.type = TAPER_SETTING_INTEGER, DIM(NUMBER),
              RANGE(TAPER_N_GRANULES_MIN, TAPER_N_GRANULES_MAX), .info.default_value = 100,
              .info.description = "number of granules N",
              .info.bounds_reason = "a chain needs two granules for one contact; 1e7 granules "
                                    "already take about 2 GB",
     .storage = STORE_SIZE, CHAIN_AT(n_granules)},
    {.info.name = "s", .info.group = "chain", DIM(NUMBER), RANGE(0.0, TAPER_S_MAX),
              .info.description = "linear tapering S (backward_linear, forward_linear: "
                                  "N < 1 + 1/S)",
              .info.bounds_reason = "the profile gives the sign, so S >= 0; beyond 1e3 the "
                                    "second granule would be a thousand times the first",
     REAL, CHAIN_AT(s)},
    {.info.name = "q", .info.group = "chain", DIM(NUMBER), RANGE(0.0, TAPER_Q_MAX),
              .info.description = "exponential tapering q (backward_exponential needs q < 1)",
              .info.bounds_reason = "the profile gives the sign, so q >= 0; beyond 1e3 the "
                                    "radii change a thousandfold from one granule to the next",
     REAL, CHAIN_AT(q)},
    {.info.name = "exponent", .info.group = "chain", DIM(NUMBER),
              RANGE(TAPER_EXPONENT_MIN, TAPER_EXPONENT_MAX), .info.default_value = 2.5,
              .info.description = "contact exponent n: force ~ overlap^(n-1); 2.5 is Hertz",
              .info.bounds_reason = "below 3/2 the force's slope (n-1) z^(n-2) is unbounded at "
                                    "contact onset and the integration stalls; 20 is the "
                                    "stiffest contact law tested",
     REAL, CHAIN_AT(exponent)},
    {.info.name = "radii", .info.group = "chain", DIM(SIZE), POSITIVE,
              .info.description = "custom profile only: the radii R_1, ..., R_N (R_1 = 1 is the "
                                  "unit of length)",
              .info.bounds_reason = "a radius is finite and > 0",
     LIST_AT(radii, n_radii)},

    /* ---- the chain beyond the paper ------------------------------------ */
    {.info.name = "pattern", .info.group = "chain", DIM(SIZE), POSITIVE, .info.beyond_paper = 1,
              .info.description = "decorated profile only: the radii of one period, starting "
                                  "with R_1 = 1; granule k has radius pattern((k-1) mod P + 1), "
                                  "e.g. 1, 0.5 for a large and a small granule",
              .info.bounds_reason = "a radius is finite and > 0",
     LIST_AT(pattern, n_pattern)},
    {.info.name = "disorder", .info.group = "chain", DIM(NUMBER), .info.beyond_paper = 1,
              .info.default_value = TAPER_DISORDER_RADIUS,
              .info.description = "what a random disorder perturbs: the 'radius' or the 'mass' of "
                                  "every granule k >= 2, by a factor 1 + disorder_amplitude u_k, "
                                  "u_k uniform in [-1, 1)",
              .info.bounds_reason = "",
     CHOICE(taper_disorder_names), CHAIN_AT(disorder)},
    {.info.name = "disorder_amplitude", .info.group = "chain", DIM(NUMBER), RANGE(0.0, 1.0),
              .info.max_open = 1, .info.beyond_paper = 1,
              .info.description = "amplitude of the disorder; 0: none",
              .info.bounds_reason = "every factor 1 + amplitude u_k, u_k in [-1, 1), must stay "
                                    "> 0",
     REAL, CHAIN_AT(disorder_amplitude)},
    {.info.name = "seed", .info.group = "chain", .info.type = TAPER_SETTING_INTEGER, DIM(NUMBER),
              RANGE(0.0, EXACT_INTEGER), .info.beyond_paper = 1,
              .info.description = "seed of the disorder: u_k depends on (seed, k) alone, the same "
                                  "on every machine and for every N",
              .info.bounds_reason = "a whole number >= 0 that a double holds exactly (scene files "
                                    "and the bindings pass it as one)",
     .storage = STORE_U64, CHAIN_AT(disorder_seed)},
    {.info.name = "load", .info.group = "chain", DIM(FORCE), NONNEGATIVE, .info.beyond_paper = 1,
              .info.description = "static compressive force F0 through the chain "
                                  "(precompression): every contact starts at its static overlap; "
                                  "0: the paper's just-touching chain",
              .info.bounds_reason = "a compressive force is finite and >= 0",
     REAL, CHAIN_AT(load)},
    {.info.name = "densities", .info.group = "chain", DIM(DENSITY), POSITIVE, .info.beyond_paper = 1,
              .info.description = "mixed chains: each granule's density, relative to granule 1's "
                                  "(divided by the first entry); one per granule, with compliances",
              .info.bounds_reason = "a density is finite and > 0",
     LIST_AT(density, n_density), .relative = 1},
    {.info.name = "compliances", .info.group = "chain", DIM(COMPLIANCE), POSITIVE,
              .info.beyond_paper = 1,
              .info.description = "mixed chains: each granule's contact compliance (1 - nu^2)/E, "
                                  "relative to granule 1's; one per granule, with densities",
              .info.bounds_reason = "a compliance is finite and > 0",
     LIST_AT(compliance, n_compliance), .relative = 1},

    {.info.name = "left", .info.group = "ends", DIM(NUMBER), .info.beyond_paper = 1,
              .info.default_value = TAPER_END_FREE,
              .info.description = "granule 1's end: 'free', or 'wall' (a fixed flat wall touching "
                                  "granule 1; not with a striker)",
              .info.bounds_reason = "",
     CHOICE(taper_boundary_names), CHAIN_AT(end[TAPER_LEFT])},
    {.info.name = "right", .info.group = "ends", DIM(NUMBER), .info.beyond_paper = 1,
              .info.default_value = TAPER_END_FREE,
              .info.description = "granule N's end: 'free', or 'wall' (the pulse reflects from it)",
              .info.bounds_reason = "",
     CHOICE(taper_boundary_names), CHAIN_AT(end[TAPER_RIGHT])},
    {.info.name = "left_compliance", .info.group = "ends", DIM(COMPLIANCE), NONNEGATIVE,
              .info.beyond_paper = 1,
              .info.description = "compliance (1 - nu^2)/E of the left wall relative to granule "
                                  "1's: 0 rigid, 1 granule 1's material",
              .info.bounds_reason = "0 is a rigid wall, and no material has a negative or an "
                                    "infinite compliance",
     REAL, CHAIN_AT(end_compliance[TAPER_LEFT])},
    {.info.name = "right_compliance", .info.group = "ends", DIM(COMPLIANCE), NONNEGATIVE,
              .info.beyond_paper = 1,
              .info.description = "compliance of the right wall relative to granule 1's (as "
                                  "left_compliance)",
              .info.bounds_reason = "0 is a rigid wall, and no material has a negative or an "
                                    "infinite compliance",
     REAL, CHAIN_AT(end_compliance[TAPER_RIGHT])},

    {.info.name = "striker_radius", .info.group = "striker", DIM(SIZE), RANGE(0.0, 1e100),
              .info.beyond_paper = 1,
              .info.description = "radius of a striker hitting granule 1 (at rest) with the "
                                  "impulse's velocity; 0: no striker, the impulse v_1 = 1 of the "
                                  "paper",
              .info.bounds_reason = "0 is no striker; up to 1e100 its mass radius^3 stays "
                                    "finite",
     REAL, CHAIN_AT(striker_radius)},
    {.info.name = "striker_density", .info.group = "striker", DIM(DENSITY), POSITIVE,
              .info.default_value = 1.0, .info.beyond_paper = 1,
              .info.description = "the striker's density relative to granule 1's: its mass is "
                                  "density radius^3",
              .info.bounds_reason = "a density is finite and > 0",
     REAL, CHAIN_AT(striker_density)},
    {.info.name = "striker_compliance", .info.group = "striker", DIM(COMPLIANCE), NONNEGATIVE,
              .info.default_value = 1.0, .info.beyond_paper = 1,
              .info.description = "the striker's compliance (1 - nu^2)/E relative to granule 1's",
              .info.bounds_reason = "0 is a rigid striker, and no material has a negative or an "
                                    "infinite compliance",
     REAL, CHAIN_AT(striker_compliance)},
    {.info.name = "piston_duration", .info.group = "striker", DIM(TIME), RANGE(0.0, INFINITY),
              .info.beyond_paper = 1,
              .info.description = "how long a piston touching granule 1 (at rest) pushes it at the "
                                  "impulse's velocity; 0: no piston; infinite: for ever (not with "
                                  "a striker, a left wall or a load)",
              .info.bounds_reason = "0 is no piston, infinite a push for ever; a duration "
                                   "cannot be negative",
     REAL, CHAIN_AT(piston_duration)},
    {.info.name = "piston_compliance", .info.group = "striker", DIM(COMPLIANCE), NONNEGATIVE,
              .info.beyond_paper = 1,
              .info.description = "compliance of the piston's face relative to granule 1's (as a "
                                  "wall's: 0 rigid)",
              .info.bounds_reason = "0 is a rigid face, and no material has a negative or an "
                                    "infinite compliance",
     REAL, CHAIN_AT(piston_compliance)},

    {.info.name = "damping", .info.group = "losses", DIM(TIME), NONNEGATIVE, .info.beyond_paper = 1,
              .info.description = "viscoelastic contacts (Kuwabara-Kono): each contact pushes with "
                                  "r_k (z^(n-1) + damping d(z^(n-1))/dt), never pulls; 0: elastic",
              .info.bounds_reason = "a relaxation time is finite and >= 0",
     REAL, CHAIN_AT(damping)},
    {.info.name = "drag", .info.group = "losses", DIM(DRAG), NONNEGATIVE, .info.beyond_paper = 1,
              .info.description = "hydrodynamic friction: a force -drag v_k on every granule (and "
                                  "the striker); 0: none",
              .info.bounds_reason = "a friction coefficient is finite and >= 0",
     REAL, CHAIN_AT(drag)},

    /* ---- the solver ----------------------------------------------------- */
    {.info.name = "method", .info.group = "solver", DIM(NUMBER), .info.default_value = TAPER_ADAMS,
              .info.description = "integrator: 'adams' (CVODE Adams-Moulton, fixed point; the "
                                  "default, the faster where light granules chatter), 'bdf' (CVODE "
                                  "BDF, banded Jacobian: stiff drag) or 'rk8' (Prince-Dormand 8(7), "
                                  "single-step: the choice for smooth, long chains and tight "
                                  "tolerances); which one for which chain, with measured errors "
                                  "and costs: docs/choosing.md",
              .info.bounds_reason = "",
     CHOICE(taper_method_names), SOLVER_AT(method)},
    {.info.name = "rtol", .info.group = "solver", DIM(NUMBER),
              RANGE(TAPER_RTOL_MIN, TAPER_RTOL_MAX), .info.default_value = 1e-10,
              .info.description = "relative tolerance of the integrator; the pass-time error "
                                  "and the cost each rtol gives, by method and family of chains: "
                                  "docs/choosing.md",
              .info.bounds_reason = "below 3e-16 (1.35 rounding units of double precision) "
                                    "CVODE's error test cannot be met; above 0.1 no digit of a "
                                    "result would be right",
     REAL, SOLVER_AT(rtol)},
    {.info.name = "atol", .info.group = "solver", DIM(NUMBER), RANGE(0.0, TAPER_ATOL_MAX),
              .info.min_open = 1, .info.default_value = 1e-13,
              .info.description = "absolute tolerance, in units of each granule's binary-collision "
                                  "velocity and maximum compression (relative to the pulse "
                                  "wherever it is)",
              .info.bounds_reason = "CVODE needs a floor > 0; above 0.1 of the pulse's own scale "
                                    "no digit of a result would be right",
     REAL, SOLVER_AT(atol)},
    {.info.name = "window", .info.group = "solver", .info.type = TAPER_SETTING_BOOLEAN, DIM(NUMBER),
              RANGE(0.0, 1.0), .info.default_value = 1,
              .info.description = "integrate only the granules that can move (exact and faster); "
                                  "0: the whole chain",
              .info.bounds_reason = "",
     .storage = STORE_INT, SOLVER_AT(window)},
    {.info.name = "last_granule", .info.group = "solver", .info.type = TAPER_SETTING_INTEGER,
              DIM(NUMBER), RANGE(0.0, TAPER_N_GRANULES_MAX),
              .info.description = "stop once the pulse has passed this granule (at most "
                                  "n_granules); 0: the whole chain",
              .info.bounds_reason = "no chain has more than 1e7 granules",
     .storage = STORE_SIZE, SOLVER_AT(last_granule)},
    {.info.name = "max_order", .info.group = "solver", .info.type = TAPER_SETTING_INTEGER,
              DIM(NUMBER), RANGE(0.0, TAPER_MAX_ORDER_ADAMS), .info.beyond_paper = 1,
              .info.description = "highest order of the integrator: 1 to 12 (adams) or 1 to 5 "
                                  "(bdf); 0: the measured default (rk8: 0 only, its order is 8)",
              .info.bounds_reason = "CVODE's Adams methods go to order 12, its BDF to 5",
     .storage = STORE_INT, SOLVER_AT(max_order)},
    {.info.name = "t_max", .info.group = "solver", DIM(TIME), NONNEGATIVE,
              .info.description = "stop at this time with a partial result; 0: no limit",
              .info.bounds_reason = "a time is finite and >= 0",
     REAL, SOLVER_AT(t_max)},
    {.info.name = "max_steps", .info.group = "solver", .info.type = TAPER_SETTING_INTEGER,
              DIM(NUMBER), RANGE(0.0, EXACT_INTEGER),
              .info.description = "stop after this many internal steps with a partial result; 0: "
                                  "no limit",
              .info.bounds_reason = "a count >= 0 that a double holds exactly",
     .storage = STORE_LONG, SOLVER_AT(max_steps)},
    {.info.name = "t_end", .info.group = "solver", DIM(TIME), NONNEGATIVE, .info.beyond_paper = 1,
              .info.description = "integrate until this time even after the pulse has passed "
                                  "every granule (to follow reflections, and the samples); 0: stop "
                                  "once the observables are known",
              .info.bounds_reason = "a time is finite and >= 0",
     REAL, SOLVER_AT(t_end)},
};

#define N_ROWS (sizeof taper_setting_rows / sizeof taper_setting_rows[0])
_Static_assert(N_ROWS <= SETTING_MAX_ROWS, "raise SETTING_MAX_ROWS");
const size_t taper_setting_n_rows = N_ROWS;
