/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * taper.h -- pulse propagation in tapered granular chains.
 *
 * The one public header of libtaper.  It models the rescaled equations of
 * motion, eq. (6) of Harbola, Rosas, Esposito and Lindenberg, "Pulse
 * propagation in tapered granular chains: an analytic study",
 * arXiv:0905.4512:
 *
 *     m_k x_k'' = r_{k-1} (x_{k-1} - x_k)^{n-1} theta(x_{k-1} - x_k)
 *               - r_k     (x_k - x_{k+1})^{n-1} theta(x_k - x_{k+1}),
 *
 * with R_1 = 1, m_k = R_k^3, r_k = (2 R_k R_{k+1} / (R_k + R_{k+1}))^{1/2},
 * v_1(0) = 1 and every other granule at rest, just touching.
 *
 * Pipeline:  chain (geometry)  ->  sim (full dynamics, CVODE, exact pulse
 * events)  ->  theory (binary collision approximation)  ->  fits.
 *
 * Conventions
 *  - Granules are numbered k = 1..N as in the paper; arrays returned or
 *    filled by the library hold granule k at index k-1 and have length N.
 *    Quantities that belong to the pair (k, k+1) (r_k, mu_k, T_k, t_pass(k))
 *    sit at index k-1; the last entry of such an array is NaN.
 *  - Values that do not exist (not reached, not defined) are NaN.
 *  - Every function that can fail returns a taper_status (or NULL for the
 *    *_alloc functions) and, when given a non-NULL taper_error, writes the
 *    status, the name of the setting at fault and a message the caller can
 *    show.  err may always be NULL.  After a successful call err holds
 *    TAPER_OK, field NULL and an empty message.
 *  - Settings live in objects the library allocates (taper_chain_spec,
 *    taper_solver_spec, taper_fit_spec), read and written through
 *    functions, as CVODE's memory is: a later version adds settings without
 *    breaking programs compiled against this header (docs/api.md, "Why
 *    opaque objects").  A setter checks its value alone and refuses it
 *    (TAPER_EINVAL, the spec unchanged); the *_alloc that consumes a spec
 *    checks the relations between settings.  Every setting is a row of the
 *    table of settings ("Settings by name" below: its range, default,
 *    dimension and description); the ranges are the TAPER_*_MIN and _MAX
 *    constants below, stated once, here.
 *  - Getters never fail: a NULL object reads as a fresh one (a spec's
 *    getter returns the default), and an index or enum value out of range
 *    reads as NaN (a double), NULL (a pointer) or 0.
 *  - The library never prints, never calls exit() or abort(), and has no
 *    global mutable state: distinct objects may be used from distinct
 *    threads at once.  A chain is only read after taper_chain_alloc, so one
 *    chain may serve several sims running in different threads; a single
 *    sim must not be used from two threads at the same time.
 *  - Objects are created by *_alloc, owned by the caller and released by
 *    *_free (NULL is a no-op).  Arrays returned as `const double *` belong
 *    to the object that returned them and live as long as it does.
 *  - See docs/api.md for a complete walk-through.
 */
#ifndef TAPER_H
#define TAPER_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(TAPER_BUILDING_LIBRARY) && (defined(__GNUC__) || defined(__clang__))
#define TAPER_API __attribute__((visibility("default")))
#else
#define TAPER_API
#endif

/* ------------------------------------------------------------------ */
/* Version                                                            */
/* ------------------------------------------------------------------ */
/* TAPER_VERSION_MAJOR, _MINOR, _PATCH and TAPER_VERSION_STRING ("1.0.0"),
 * written by the build from meson.build's project version.  Programs built
 * against one major version run with any later library of that major version
 * (the soname is libtaper.so.MAJOR). */
#include "taper_version.h"

/* The version of the library actually loaded (may differ from the macros
 * the caller was compiled with). */
TAPER_API const char *taper_version(void);

/* ------------------------------------------------------------------ */
/* Enumerations and their names                                       */
/* ------------------------------------------------------------------ */
/* Every enum below and its names come from one list, as REBOUND's do: the
 * macro TAPER_<ENUM>_LIST(X) calls X(constant, "name") once per value, in
 * the order of the values (0, 1, ...).  The header expands it into the enum
 * and its count; the library expands it into the table its *_name and
 * *_from_name functions read, so a value and its name cannot drift apart.
 * Callers may expand a list too (a switch over every value, a table of
 * their own). */
#define TAPER_ENUM_CONSTANT(constant, name) constant,
#define TAPER_ENUM_COUNT(constant, name) +1
/* The lists of quantities (statistics, observables, the theory's columns)
 * have a third column, their dimension: X(constant, "name", TIME) means
 * TAPER_DIM_TIME (taper_dimension, below). */
#define TAPER_QUANTITY_CONSTANT(constant, name, dimension) constant,
#define TAPER_QUANTITY_COUNT(constant, name, dimension) +1

/* ------------------------------------------------------------------ */
/* Errors                                                             */
/* ------------------------------------------------------------------ */
/* X(constant, "name", "description"): the name is a short identifier (the
 * Python package's Result.status), the description taper_strerror's. */
#define TAPER_STATUS_LIST(X)                                                           \
    X(TAPER_OK, "ok", "success")                                                       \
    X(TAPER_EINVAL, "invalid", "invalid argument")   /* invalid argument or setting */ \
    X(TAPER_ENOMEM, "nomem", "out of memory")        /* allocation failed           */ \
    X(TAPER_ERANGE, "range", "value out of double-precision range")                    \
    X(TAPER_ESOLVER, "solver", "integrator failure") /* partial results kept        */ \
    X(TAPER_EINTERRUPTED, "interrupted", "interrupted") /* the monitor asked to stop;
                                                           partial results kept     */ \
    X(TAPER_ELIMIT, "limit", "time or step limit reached") /* t_max or max_steps;
                                                              partial results kept  */
#define TAPER_STATUS_CONSTANT(constant, name, description) constant,
typedef enum taper_status { TAPER_STATUS_LIST(TAPER_STATUS_CONSTANT) } taper_status;

#define TAPER_MESSAGE_SIZE 512

/* Filled by failing calls.  status repeats the return value.  field names
 * the setting at fault, spelt as its setter (and the scene variable) is:
 * "rtol" for taper_solver_spec_set_rtol, "n_granules", "radii", ...; NULL
 * when no single setting is (out of memory, a solver failure).  It points
 * to static storage.  A message longer than the buffer ends in "...". */
typedef struct taper_error {
    taper_status status;
    const char *field;
    char message[TAPER_MESSAGE_SIZE];
} taper_error;

/* A short constant description of a status code ("invalid argument", ...);
 * "unknown status" for other values.  Never NULL; static storage. */
TAPER_API const char *taper_strerror(taper_status status);
/* The status's identifier ("ok", "invalid", ...); NULL outside the enum. */
TAPER_API const char *taper_status_name(taper_status status);
/* The name of names[0..n) nearest to `name` (case-insensitive, at most two
 * edits away), for "did you mean" in messages; NULL if none is that near.
 * The library's own refusals of unknown names use it, and so can callers
 * with lists of their own. */
TAPER_API const char *taper_nearest_name(const char *name, const char *const *names, size_t n);

/* ------------------------------------------------------------------ */
/* Ranges of the settings (inclusive unless said otherwise)            */
/* ------------------------------------------------------------------ */
#define TAPER_N_GRANULES_MIN 2
#define TAPER_N_GRANULES_MAX 10000000      /* 1e7                              */
#define TAPER_S_MAX 1e3                    /* 0 <= s <= TAPER_S_MAX            */
#define TAPER_Q_MAX 1e3                    /* 0 <= q <= TAPER_Q_MAX (backward
                                              exponential: q < 1)              */
#define TAPER_EXPONENT_MIN 1.5             /* inclusive: n >= 3/2 (below, the
                                              force's unbounded slope at
                                              contact onset stalls CVODE:
                                              chain_spec.c)                    */
#define TAPER_EXPONENT_MAX 20.0
#define TAPER_RTOL_MIN 3e-16               /* 1.35 rounding units of double:
                                              CVODE's error test fails below   */
#define TAPER_RTOL_MAX 0.1
#define TAPER_ATOL_MAX 0.1                 /* 0 < atol <= TAPER_ATOL_MAX       */
#define TAPER_MAX_ORDER_ADAMS 12
#define TAPER_MAX_ORDER_BDF 5

/* ------------------------------------------------------------------ */
/* Chain geometry                                                      */
/* ------------------------------------------------------------------ */
#define TAPER_PROFILE_LIST(X)                                                          \
    X(TAPER_MONODISPERSE, "monodisperse")                 /* R_k = 1                */ \
    X(TAPER_BACKWARD_LINEAR, "backward_linear")           /* 1 + S (k-1), S > 0     */ \
    X(TAPER_FORWARD_LINEAR, "forward_linear")             /* 1 - S (k-1), S > 0,
                                                             N < 1 + 1/S            */ \
    X(TAPER_BACKWARD_EXPONENTIAL, "backward_exponential") /* (1-q)^(1-k), 0 < q < 1 */ \
    X(TAPER_FORWARD_EXPONENTIAL, "forward_exponential")   /* (1+q)^(1-k), q > 0     */ \
    X(TAPER_CUSTOM, "custom")         /* R_k given, R_1 = 1 (the unit of length)    */ \
    X(TAPER_DECORATED, "decorated")   /* R_k = pattern[(k-1) mod P], pattern[0] = 1:
                                         small granules between large ones          */
typedef enum taper_profile { TAPER_PROFILE_LIST(TAPER_ENUM_CONSTANT) } taper_profile;
#define TAPER_N_PROFILES (0 TAPER_PROFILE_LIST(TAPER_ENUM_COUNT))

/* The profile's name in the list above (scene files, bindings and the
 * bench all take it from here).  NULL for a value outside the enum, so that
 * `for (i = 0; taper_profile_name(i); i++)` walks them. */
TAPER_API const char *taper_profile_name(taper_profile profile);
/* Case-insensitive inverse of taper_profile_name.  TAPER_EINVAL if unknown
 * (field "profile"; the message lists the names and the nearest one). */
TAPER_API taper_status taper_profile_from_name(const char *name, taper_profile *profile,
                                               taper_error *err);

/* What describes a chain, before it is built.  Defaults: monodisperse,
 * N = 100, S = q = 0, n = 5/2, no radii. */
typedef struct taper_chain_spec taper_chain_spec;

TAPER_API taper_chain_spec *taper_chain_spec_alloc(taper_error *err);
TAPER_API void taper_chain_spec_free(taper_chain_spec *spec);

/* Each setter checks its value against the range above (field = the
 * setting's name).  Relations (S with a linear profile, N < 1 + 1/S for
 * forward_linear, q < 1 for backward_exponential, radii with custom) are
 * checked by taper_chain_spec_check and taper_chain_alloc. */
TAPER_API taper_status taper_chain_spec_set_profile(taper_chain_spec *spec, taper_profile profile,
                                                    taper_error *err);
TAPER_API taper_status taper_chain_spec_set_n_granules(taper_chain_spec *spec, size_t n,
                                                       taper_error *err);
TAPER_API taper_status taper_chain_spec_set_s(taper_chain_spec *spec, double s, taper_error *err);
TAPER_API taper_status taper_chain_spec_set_q(taper_chain_spec *spec, double q, taper_error *err);
TAPER_API taper_status taper_chain_spec_set_exponent(taper_chain_spec *spec, double exponent,
                                                     taper_error *err);
/* Copies n radii (every one finite and > 0); NULL, 0 removes them.  Does
 * not change n_granules: taper_chain_alloc requires n == n_granules for the
 * custom profile (field "radii"). */
TAPER_API taper_status taper_chain_spec_set_radii(taper_chain_spec *spec, const double *radii,
                                                  size_t n, taper_error *err);

TAPER_API taper_profile taper_chain_spec_profile(const taper_chain_spec *spec);
TAPER_API size_t taper_chain_spec_n_granules(const taper_chain_spec *spec);
TAPER_API double taper_chain_spec_s(const taper_chain_spec *spec);
TAPER_API double taper_chain_spec_q(const taper_chain_spec *spec);
TAPER_API double taper_chain_spec_exponent(const taper_chain_spec *spec);
/* The radii set (owned by the spec) and their number; NULL, 0 if none. */
TAPER_API const double *taper_chain_spec_radii(const taper_chain_spec *spec, size_t *n);

/* ---- Beyond the paper: ends, striker, static load, losses, materials ----
 *
 * Every setting below defaults to the paper's idealisation (free ends, the
 * impulse v_1 = 1, no load, no losses, one material); with all of them at
 * their defaults a chain is exactly the one above.  Physics and sources of
 * each model: docs/physics.md.  All values are in the rescaled units of
 * eq. (5) of arXiv:0905.4512 (lengths in R_1, velocities in the impulse or
 * striker velocity); taper_unit_scale converts them to SI. */

/* Decorated profile: the radii of one period, pattern[0] = 1 (the unit of
 * length), every one finite and > 0; P >= 1.  NULL, 0 removes it.  Used by
 * TAPER_DECORATED only (taper_chain_spec_check refuses it otherwise). */
TAPER_API taper_status taper_chain_spec_set_pattern(taper_chain_spec *spec, const double *pattern,
                                                    size_t p, taper_error *err);
TAPER_API const double *taper_chain_spec_pattern(const taper_chain_spec *spec, size_t *p);

/* Random perturbation of a chain, reproducible on every machine: the radius
 * (or the mass) of granule k >= 2 is multiplied by 1 + amplitude u_k with
 * u_k uniform in [-1, 1) drawn from (seed, k) alone, so that granule k gets
 * the same u_k whatever N and whichever profile.  Granule 1 stays the unit.
 * 0 <= amplitude < 1; amplitude 0 (the default) switches it off. */
#define TAPER_DISORDER_LIST(X)                                                         \
    X(TAPER_DISORDER_RADIUS, "radius")                                                 \
    X(TAPER_DISORDER_MASS, "mass")
typedef enum taper_disorder { TAPER_DISORDER_LIST(TAPER_ENUM_CONSTANT) } taper_disorder;
#define TAPER_N_DISORDERS (0 TAPER_DISORDER_LIST(TAPER_ENUM_COUNT))
/* "radius", "mass"; NULL outside the enum. */
TAPER_API const char *taper_disorder_name(taper_disorder kind);
TAPER_API taper_status taper_disorder_from_name(const char *name, taper_disorder *kind,
                                                taper_error *err);
TAPER_API taper_status taper_chain_spec_set_disorder(taper_chain_spec *spec, taper_disorder kind,
                                                     double amplitude, uint64_t seed,
                                                     taper_error *err);
TAPER_API taper_disorder taper_chain_spec_disorder(const taper_chain_spec *spec);
TAPER_API double taper_chain_spec_disorder_amplitude(const taper_chain_spec *spec);
TAPER_API uint64_t taper_chain_spec_disorder_seed(const taper_chain_spec *spec);

/* Mixed chains: per-granule density and contact compliance c = (1 - nu^2)/E,
 * each relative to granule 1's (both arrays are divided by their first
 * entry), n == n_granules, every entry finite and > 0.  Masses become
 * m_k = rho_k R_k^3 and contact factors r_k 2 c_1 / (c_k + c_{k+1}) (Hertz:
 * 1/E* = c_k + c_{k+1}).  NULL, 0 removes them (one material). */
TAPER_API taper_status taper_chain_spec_set_materials(taper_chain_spec *spec,
                                                      const double *density,
                                                      const double *compliance, size_t n,
                                                      taper_error *err);
/* The materials set (owned by the spec, already relative to granule 1's:
 * density[0] = compliance[0] = 1) and their number; NULL, NULL, 0 if none.
 * Either output may be NULL. */
TAPER_API size_t taper_chain_spec_materials(const taper_chain_spec *spec, const double **density,
                                            const double **compliance);

/* The ends of a chain. */
#define TAPER_END_LIST(X)                                                              \
    X(TAPER_LEFT, "left")     /* granule 1's end, where the pulse starts              */ \
    X(TAPER_RIGHT, "right")   /* granule N's end                                       */
typedef enum taper_end { TAPER_END_LIST(TAPER_ENUM_CONSTANT) } taper_end;
#define TAPER_N_ENDS (0 TAPER_END_LIST(TAPER_ENUM_COUNT))
#define TAPER_BOUNDARY_LIST(X)                                                         \
    X(TAPER_END_FREE, "free") /* nothing (under a static load: the load pushes it)  */ \
    X(TAPER_END_WALL, "wall") /* a fixed flat wall touching the end granule at rest */
typedef enum taper_boundary { TAPER_BOUNDARY_LIST(TAPER_ENUM_CONSTANT) } taper_boundary;
#define TAPER_N_BOUNDARIES (0 TAPER_BOUNDARY_LIST(TAPER_ENUM_COUNT))
/* "free", "wall"; NULL outside the enum. */
TAPER_API const char *taper_boundary_name(taper_boundary boundary);
TAPER_API taper_status taper_boundary_from_name(const char *name, taper_boundary *boundary,
                                                taper_error *err);
/* A wall is a Hertz contact with a half-space: eq. (7) with R_{k+1} -> oo
 * gives the factor sqrt(2 R_k), times 2 c_1 / (c_k + c_wall) for a wall of
 * compliance c_wall >= 0 relative to granule 1's (0: rigid; 1: the wall is
 * of granule 1's material).  A left wall and a striker exclude each other
 * (taper_chain_spec_check). */
TAPER_API taper_status taper_chain_spec_set_end(taper_chain_spec *spec, taper_end end,
                                                taper_boundary boundary, double compliance,
                                                taper_error *err);
TAPER_API taper_boundary taper_chain_spec_end(const taper_chain_spec *spec, taper_end end);
TAPER_API double taper_chain_spec_end_compliance(const taper_chain_spec *spec, taper_end end);

/* A striker (granule 0) of radius > 0 (relative to R_1), density and
 * compliance relative to granule 1's, hits granule 1 with unit velocity:
 * granule 1 starts at rest.  Its mass is density radius^3 and its contact
 * with granule 1 follows eq. (7) and the compliances.  radius 0 (the
 * default) removes it: the impulse v_1 = 1 of the paper. */
TAPER_API taper_status taper_chain_spec_set_striker(taper_chain_spec *spec, double radius,
                                                    double density, double compliance,
                                                    taper_error *err);
TAPER_API double taper_chain_spec_striker_radius(const taper_chain_spec *spec);
TAPER_API double taper_chain_spec_striker_density(const taper_chain_spec *spec);
TAPER_API double taper_chain_spec_striker_compliance(const taper_chain_spec *spec);

/* A piston: a body of infinite mass touching granule 1 (at rest, as the
 * whole chain) from the left, that moves at the unit velocity for
 * 0 <= t <= duration and stops there (position min(t, duration)); duration
 * may be INFINITY (a steady push).  Its face is a wall's of compliance >= 0
 * relative to granule 1's (taper_chain_spec_set_end).  It does the work
 * W(t) = J(min(t, duration)), J the impulse of its force
 * (taper_sim_piston_work).  duration 0 (the default) removes it.  A piston
 * excludes a striker, a left wall and a static load
 * (taper_chain_spec_check; docs/physics.md, "Piston"). */
TAPER_API taper_status taper_chain_spec_set_piston(taper_chain_spec *spec, double duration,
                                                   double compliance, taper_error *err);
TAPER_API double taper_chain_spec_piston_duration(const taper_chain_spec *spec);
TAPER_API double taper_chain_spec_piston_compliance(const taper_chain_spec *spec);

/* Precompression: a static compressive force F0 >= 0 through the chain
 * (rescaled force, eq. (5)).  Every contact starts at its static overlap
 * delta_k with r_k delta_k^(n-1) = F0; a free end is pushed by the constant
 * load F0, a wall holds its end by its own overlap.  The state integrated
 * is the displacement from that equilibrium, so granules ahead of the pulse
 * are exactly at rest.  0 (the default): the paper's just-touching chain. */
TAPER_API taper_status taper_chain_spec_set_load(taper_chain_spec *spec, double f0,
                                                 taper_error *err);
TAPER_API double taper_chain_spec_load(const taper_chain_spec *spec);

/* Viscoelastic contacts (Kuwabara-Kono; for n = 5/2 the damping force is
 * proportional to z^(1/2) dz/dt): every contact pushes with
 * r_k (z^(n-1) + damping d(z^(n-1))/dt) while that is > 0, never pulls.
 * damping >= 0 is a time (rescaled); 0: elastic. */
TAPER_API taper_status taper_chain_spec_set_damping(taper_chain_spec *spec, double damping,
                                                    taper_error *err);
TAPER_API double taper_chain_spec_damping(const taper_chain_spec *spec);
/* Hydrodynamic friction: a force -drag v_k on every granule (and the
 * striker); drag >= 0; 0: none. */
TAPER_API taper_status taper_chain_spec_set_drag(taper_chain_spec *spec, double drag,
                                                 taper_error *err);
TAPER_API double taper_chain_spec_drag(const taper_chain_spec *spec);

/* Checks the relations between the settings, without building the chain:
 * TAPER_OK, or TAPER_EINVAL naming the setting to change by its name in the
 * table of settings: "left", "right", "left_compliance", "right_compliance"
 * (set_end), "striker_radius", "striker_density", "striker_compliance",
 * "load", "damping", "drag", "densities", "compliances" (set_materials),
 * "pattern", "disorder", "disorder_amplitude", "seed", "piston_duration",
 * "piston_compliance".
 * Relations refused: a pattern without the decorated profile or the
 * reverse, pattern[0] != 1, materials for another number of granules than
 * n_granules, a wall compliance on a free end, striker density or
 * compliance without a striker, a striker with a left wall, a piston with
 * a striker, a left wall or a load, a piston compliance without a
 * piston. */
TAPER_API taper_status taper_chain_spec_check(const taper_chain_spec *spec, taper_error *err);

typedef struct taper_chain taper_chain;

/* Builds the chain: radii, masses, contact factors, rest positions.  The
 * spec is copied: the caller may free it afterwards.  Returns a chain the
 * caller owns (release with taper_chain_free), or NULL: TAPER_EINVAL as
 * taper_chain_spec_check, TAPER_ERANGE for chains whose masses overflow or
 * underflow double precision (naming the granule), TAPER_ENOMEM. */
TAPER_API taper_chain *taper_chain_alloc(const taper_chain_spec *spec, taper_error *err);
/* Releases the chain and its arrays.  Every sim of it must be freed first. */
TAPER_API void taper_chain_free(taper_chain *chain);

TAPER_API size_t taper_chain_size(const taper_chain *chain);       /* N */
TAPER_API double taper_chain_exponent(const taper_chain *chain);   /* n */
TAPER_API taper_profile taper_chain_profile(const taper_chain *chain);
/* Arrays of length N owned by the chain, valid until taper_chain_free. */
TAPER_API const double *taper_chain_radius(const taper_chain *chain);   /* R_k          */
TAPER_API const double *taper_chain_mass(const taper_chain *chain);     /* m_k = R_k^3  */
TAPER_API const double *taper_chain_contact(const taper_chain *chain);  /* r_k, [N-1] = NaN */
/* Centre of granule k in the uncompressed chain, X0(1) = 0,
 * X0(k) = sum_{j<k} (R_j + R_{j+1})  (the paper's X_0 for every profile). */
TAPER_API const double *taper_chain_rest_position(const taper_chain *chain);

/* What the options above made of the chain (NaN where absent). */
TAPER_API taper_boundary taper_chain_end(const taper_chain *chain, taper_end end);
/* Contact factor of the wall at `end` (NaN for a free end). */
TAPER_API double taper_chain_end_contact(const taper_chain *chain, taper_end end);
TAPER_API double taper_chain_striker_radius(const taper_chain *chain);
TAPER_API double taper_chain_striker_mass(const taper_chain *chain);
/* Contact factor of the pair (striker, granule 1). */
TAPER_API double taper_chain_striker_contact(const taper_chain *chain);
/* The piston's duration (0: none) and the contact factor of its face with
 * granule 1 (NaN: none). */
TAPER_API double taper_chain_piston_duration(const taper_chain *chain);
TAPER_API double taper_chain_piston_contact(const taper_chain *chain);
TAPER_API double taper_chain_load(const taper_chain *chain);      /* F0 (0: none)       */
TAPER_API double taper_chain_damping(const taper_chain *chain);   /* 0: elastic         */
TAPER_API double taper_chain_drag(const taper_chain *chain);      /* 0: none            */
/* NULL when the binary collision approximation (and so taper_theory_compute
 * and taper_sim_theory) describes this chain's first pass; otherwise why
 * not (for example "dissipation: the binary collision approximation of
 * arXiv:0905.4512 is elastic"), and the theory columns are NaN.  A striker,
 * mixed materials, disorder and walls keep the theory of the first pass; a
 * decorated chain uses the effective chain of docs/physics.md. */
TAPER_API const char *taper_chain_theory_note(const taper_chain *chain);

/* ------------------------------------------------------------------ */
/* Real units (Hertz contacts, n = 5/2)                               */
/* ------------------------------------------------------------------ */
/*
 * The rescaling of eq. (5): y = R_1 alpha^(1/n) x, tau = (R_1/V_1)
 * alpha^(1/n) t, with alpha of eq. (4) and a = sqrt(2) E / (3 (1 - nu^2))
 * (Hertz, same material: a r_k of eq. (7) is (4/3) E* sqrt(R*)).
 */
/* X(constant, "name", "SI unit"): the one list of dimensions and units. */
#define TAPER_DIMENSION_LIST(X)                                                        \
    X(TAPER_DIM_LENGTH, "length", "m")          /* R_1 alpha^(1/n), eq. (5)         */ \
    X(TAPER_DIM_TIME, "time", "s")              /* the length over V                 */ \
    X(TAPER_DIM_VELOCITY, "velocity", "m/s")    /* V, the impulse's                  */ \
    X(TAPER_DIM_MASS, "mass", "kg")             /* M_1 = (4/3) pi rho_1 R_1^3        */ \
    X(TAPER_DIM_FORCE, "force", "N")            /* M_1 V^2 / length                  */ \
    X(TAPER_DIM_ENERGY, "energy", "J")          /* M_1 V^2                           */ \
    X(TAPER_DIM_IMPULSE, "impulse", "N s")      /* M_1 V                             */ \
    X(TAPER_DIM_SIZE, "size", "m")              /* R_1: radii and rest positions      */ \
    X(TAPER_DIM_DENSITY, "density", "kg/m^3")   /* rho_1: densities are relative to
                                                   granule 1's                       */ \
    X(TAPER_DIM_COMPLIANCE, "compliance", "1/Pa") /* c_1 = (1 - nu_1^2)/E_1          */ \
    X(TAPER_DIM_DRAG, "drag", "kg/s")           /* a drag coefficient: mass / time   */ \
    X(TAPER_DIM_NUMBER, "number", "1")          /* dimensionless: scale 1            */
#define TAPER_DIMENSION_CONSTANT(constant, name, unit) constant,
#define TAPER_DIMENSION_COUNT(constant, name, unit) +1
typedef enum taper_dimension { TAPER_DIMENSION_LIST(TAPER_DIMENSION_CONSTANT) } taper_dimension;
#define TAPER_N_DIMENSIONS (0 TAPER_DIMENSION_LIST(TAPER_DIMENSION_COUNT))
/* "length", ...; and the SI unit "m", "s", "m/s", ... of the list above.
 * NULL outside the enum. */
TAPER_API const char *taper_dimension_name(taper_dimension dim);
TAPER_API const char *taper_dimension_unit(taper_dimension dim);
/* The SI value of one rescaled unit of `dim` for granule 1 of radius [m],
 * Young's modulus [Pa], Poisson ratio, density [kg/m^3] and impulse (or
 * striker) velocity [m/s].  NaN for an argument out of its physical range
 * (radius, young, density, velocity > 0, -1 < poisson < 1/2). */
TAPER_API double taper_unit_scale(taper_dimension dim, double young, double poisson,
                                  double density, double radius, double velocity);

/* ------------------------------------------------------------------ */
/* The equations of motion, for callers' own integrators               */
/* ------------------------------------------------------------------ */
/*
 * The right-hand side that taper_sim integrates, over the whole chain, so
 * that another integrator (the peers of taper-bench, a user's own) solves
 * exactly the same equations.  State y of length 2N in difference
 * variables, interleaved: v_k at y[2(k-1)], z_k = x_k - x_{k+1} at
 * y[2(k-1)+1], with x_{N+1} := 0 so that z_N = x_N (docs/design.md).
 */
typedef struct taper_dynamics taper_dynamics;

/* The chain must outlive the object.  NULL with TAPER_EINVAL / ENOMEM.
 * The paper's chain only: a chain with a wall, a striker, a load, damping
 * or drag is refused with TAPER_EINVAL, field naming the option ("end",
 * "striker_radius", "load", "damping", "drag"). */
TAPER_API taper_dynamics *taper_dynamics_alloc(const taper_chain *chain, taper_error *err);
TAPER_API void taper_dynamics_free(taper_dynamics *dyn);
/* ydot = f(y), both of length 2N.  NULL dyn or ydot: nothing is written;
 * NULL y: ydot is NaN. */
TAPER_API void taper_dynamics_rhs(const taper_dynamics *dyn, const double *y, double *ydot);
/* Kinetic plus contact energy and momentum of the state y (either output
 * may be NULL); NaN for a NULL dyn or y. */
TAPER_API void taper_dynamics_energy_momentum(const taper_dynamics *dyn, const double *y,
                                              double *energy, double *momentum);
/* A function with the sign of granule k's acceleration, never identically
 * zero while a contact of k is closed: its downward zero is k's velocity
 * peak (the root function taper_sim uses).  1 <= k <= N; NaN otherwise
 * and for a NULL dyn or y. */
TAPER_API double taper_dynamics_peak_function(const taper_dynamics *dyn, const double *y,
                                              size_t k);

/* ------------------------------------------------------------------ */
/* Binary collision approximation (paper, Sec. II)                    */
/* ------------------------------------------------------------------ */

/* Residence time of one binary collision, eq. (18):
 * T = sqrt(pi) (n mu / (2 r))^(1/n) zdot0^(2/n - 1) Gamma(1+1/n) / Gamma(1/n+1/2).
 * NaN for invalid arguments (mu, r, zdot0 <= 0 or n <= 1). */
TAPER_API double taper_theory_collision_time(double mu, double r, double zdot0, double n);

/* The columns of the theory of a chain. */
/* X(constant, "name", dimension). */
#define TAPER_THEORY_QUANTITY_LIST(X)                                                  \
    X(TAPER_THEORY_V, "v", VELOCITY) /* v_k, eq. (9): the velocity granule k leaves its
                                        collision with                               */ \
    X(TAPER_THEORY_MU, "mu", MASS)   /* mu_k = m_k m_{k+1} / (m_k + m_{k+1}), k = 1..N-1 */ \
    X(TAPER_THEORY_T_RES, "T", TIME) /* T_k, eq. (18) with zdot0 = v_k, k = 1..N-1   */ \
    X(TAPER_THEORY_T, "t", TIME)     /* t_k = sum_{j<=k} T_j, eq. (19), k = 1..N-1    */
typedef enum taper_theory_quantity {
    TAPER_THEORY_QUANTITY_LIST(TAPER_QUANTITY_CONSTANT)
} taper_theory_quantity;
#define TAPER_N_THEORY_QUANTITIES (0 TAPER_THEORY_QUANTITY_LIST(TAPER_QUANTITY_COUNT))

/* "v", "mu", "T", "t": the names of taper_theory_compute's arrays (the
 * spelling of the paper's symbols).  granules.tsv writes three of them as
 * the columns "theory_v", "theory_T", "theory_t" (mu has no column).  NULL
 * outside the enum, so that `for (i = 0; taper_theory_quantity_name(i); i++)`
 * walks them. */
TAPER_API const char *taper_theory_quantity_name(taper_theory_quantity which);
/* Its dimension; TAPER_DIM_NUMBER outside the enum. */
TAPER_API taper_dimension taper_theory_quantity_dimension(taper_theory_quantity which);

/* Fills caller-owned arrays of length N, each optional (NULL to skip), with
 * the columns above.  Entries that do not exist are NaN.  TAPER_EINVAL for
 * a NULL chain; TAPER_ERANGE if a time overflows (the arrays are then
 * filled up to the granule named in the message). */
TAPER_API taper_status taper_theory_compute(const taper_chain *chain, double *v, double *mu,
                                            double *T, double *t, taper_error *err);

/* ------------------------------------------------------------------ */
/* Full dynamics                                                       */
/* ------------------------------------------------------------------ */
#define TAPER_METHOD_LIST(X)                                                           \
    X(TAPER_ADAMS, "adams") /* CVODE Adams-Moulton, fixed-point iteration (non-stiff) */ \
    X(TAPER_BDF, "bdf")     /* CVODE BDF, Newton with the banded analytic Jacobian    */ \
    X(TAPER_RK8, "rk8")     /* Prince-Dormand 8(7) single-step (GSL rk8pd), rtol 1e-14 */
typedef enum taper_method { TAPER_METHOD_LIST(TAPER_ENUM_CONSTANT) } taper_method;
#define TAPER_N_METHODS (0 TAPER_METHOD_LIST(TAPER_ENUM_COUNT))

/* "adams", "bdf", "rk8"; NULL outside the enum. */
TAPER_API const char *taper_method_name(taper_method method);
/* Case-insensitive inverse; TAPER_EINVAL if unknown (field "method"). */
TAPER_API taper_status taper_method_from_name(const char *name, taper_method *method,
                                              taper_error *err);

/* Given to the monitor during a run: after each pulse event, after each
 * sample of a sampler, and at least every ~0.05 s of integration (every
 * 1e6 granule-steps of the active window, at most 20000 steps); and while
 * the binary-collision theory of a chain is computed (taper_sim_alloc,
 * taper_theory_compute_monitored), every 65536 granules, with window_lo =
 * window_hi = 0, granule the granule reached, target N, t its t_k and
 * steps 0; and so while a chain is built (taper_chain_alloc_monitored),
 * with t 0, and between taper_sim_alloc's other passes over the chain,
 * with granule 0.  Filled by the library: a later version may append
 * fields, never reorder them. */
typedef struct taper_progress {
    size_t granule;     /* highest k whose t_pass is known (0: none yet)      */
    size_t target;      /* the run ends once the pulse passed this granule    */
    double t;           /* time of the event                                  */
    long steps;         /* internal steps so far                              */
    size_t window_lo;   /* active window: granules window_lo..window_hi move  */
    size_t window_hi;   /* (0 and 0: the theory or the chain is being
                           computed)                                          */
} taper_progress;

/* Return non-zero to stop the run (it then ends with TAPER_EINTERRUPTED,
 * keeping what was found) or the theory (TAPER_EINTERRUPTED, nothing
 * kept).  Called from the thread running the simulation; a monitor that
 * reads a flag a signal handler sets (as the driver's and the Python
 * package's do) stops a run within a fraction of a second in every phase. */
typedef int (*taper_monitor_fn)(const taper_progress *progress, void *user);

/* taper_theory_compute, asking `monitor` (NULL: never) every 65536 granules
 * whether to go on (progress as above: window 0..0), so that the theory of
 * the longest chains stops at once.  A non-zero answer ends it with
 * TAPER_EINTERRUPTED naming the last granule K computed: the arrays hold
 * granules 1..K, NaN at K+1, and nothing is written after it (so that it
 * returns at once, whatever N). */
TAPER_API taper_status taper_theory_compute_monitored(const taper_chain *chain, double *v,
                                                      double *mu, double *T, double *t,
                                                      taper_monitor_fn monitor, void *user,
                                                      taper_error *err);

/* taper_chain_alloc, asking `monitor` (NULL: never) every 65536 granules
 * of each loop over the chain whether to go on (progress: granule the
 * loop's granule, target N, t 0, steps 0, window 0..0), so that building
 * the longest chains (10^7 granules: a fraction of a second) stops at
 * once.  A non-zero answer: NULL with TAPER_EINTERRUPTED, nothing kept. */
TAPER_API taper_chain *taper_chain_alloc_monitored(const taper_chain_spec *spec,
                                                   taper_monitor_fn monitor, void *user,
                                                   taper_error *err);

/* Diagnostics the library would otherwise have printed, called from the
 * thread running the simulation: level 1 (warning) for CVODE's own messages
 * and for peaks declared absent, level 0 (information) for window restarts.
 * Optional: failures are reported through taper_error in any case. */
typedef void (*taper_log_fn)(int level, const char *message, void *user);

/* How a chain is integrated.  Defaults: the measured Pareto choice
 * (docs/benchmarks.md): Adams, rtol 1e-10, atol 1e-13, the window on, the
 * whole chain, no limits, no monitor, no log. */
typedef struct taper_solver_spec taper_solver_spec;

TAPER_API taper_solver_spec *taper_solver_spec_alloc(taper_error *err);
TAPER_API void taper_solver_spec_free(taper_solver_spec *spec);

TAPER_API taper_status taper_solver_spec_set_method(taper_solver_spec *spec, taper_method method,
                                                    taper_error *err);
/* Relative tolerance, TAPER_RTOL_MIN..TAPER_RTOL_MAX. */
TAPER_API taper_status taper_solver_spec_set_rtol(taper_solver_spec *spec, double rtol,
                                                  taper_error *err);
/* Absolute tolerance, in units of each granule's binary-collision scale
 * (its velocity v_k and maximum compression): relative to the pulse
 * wherever it is, however strong the taper.  0 < atol <= TAPER_ATOL_MAX. */
TAPER_API taper_status taper_solver_spec_set_atol(taper_solver_spec *spec, double atol,
                                                  taper_error *err);
/* Stop once every observable of granules 1..last_granule is known; 0: the
 * whole chain.  Checked against N by taper_sim_alloc. */
TAPER_API taper_status taper_solver_spec_set_last_granule(taper_solver_spec *spec,
                                                          size_t last_granule, taper_error *err);
/* Non-zero: integrate only the granules that can move (exact); zero: the
 * whole chain every step.  Granules leave the window in free flight (with
 * damping too) or in the closed-form flight under drag; under a static load
 * none leaves.  Behind a pulse in a monodisperse chain with damping, drag or
 * a load the chain keeps moving, and the window spans it (docs/window.md). */
TAPER_API taper_status taper_solver_spec_set_window(taper_solver_spec *spec, int window,
                                                    taper_error *err);
/* Highest method order, 1..TAPER_MAX_ORDER_ADAMS (or _BDF, checked by
 * taper_sim_alloc against the method; rk8's order is fixed: 0 only); 0:
 * the measured default. */
TAPER_API taper_status taper_solver_spec_set_max_order(taper_solver_spec *spec, int max_order,
                                                       taper_error *err);
/* Stop at this time with a partial result; 0: no limit. */
TAPER_API taper_status taper_solver_spec_set_t_max(taper_solver_spec *spec, double t_max,
                                                   taper_error *err);
/* Stop after this many internal steps with a partial result; 0: no limit. */
TAPER_API taper_status taper_solver_spec_set_max_steps(taper_solver_spec *spec, long max_steps,
                                                       taper_error *err);
/* Integrate until t_end even after every observable is known (to follow a
 * reflection from a wall, or for the sampler); the run then ends with
 * TAPER_OK at t_end.  0 (the default): stop once the observables are
 * known.  The run lasts until both: observables still unknown at t_end are
 * waited for as without t_end (t_final > t_end then). */
TAPER_API taper_status taper_solver_spec_set_t_end(taper_solver_spec *spec, double t_end,
                                                   taper_error *err);
TAPER_API double taper_solver_spec_t_end(const taper_solver_spec *spec);

/* Called at t = 0, interval, 2 interval, ... while the run lasts, with the
 * sim positioned at that time: inside the call taper_sim_time,
 * taper_sim_state, taper_sim_striker_state and taper_sim_forces read the
 * state at the sample time (interpolated by CVODE to its own accuracy,
 * without stopping the integration; method rk8 by its dense output of
 * order 7, the step itself kept).  Return non-zero to stop the run
 * (TAPER_EINTERRUPTED). */
typedef struct taper_sim taper_sim;
typedef int (*taper_sample_fn)(const taper_sim *sim, void *user);
/* interval > 0 with a function, or fn NULL to remove the sampler. */
TAPER_API taper_status taper_solver_spec_set_sampler(taper_solver_spec *spec, double interval,
                                                     taper_sample_fn fn, void *user,
                                                     taper_error *err);
/* 0 when there is no sampler or it samples at given times. */
TAPER_API double taper_solver_spec_sample_interval(const taper_solver_spec *spec);
/* The sampler at n given times instead of a grid: fn is called at times[0],
 * times[1], ... (the sim positioned there as above) while the run lasts,
 * e.g. at the times of a measurement.  The times are finite, >= 0 and
 * strictly increasing (TAPER_EINVAL, field "sample_times", otherwise; n >=
 * 1).  The array is the caller's, not copied, as `user` is: it must stay
 * valid and unchanged while a sim made from this spec runs.  Replaces a
 * sampler set by taper_solver_spec_set_sampler, and the other way round;
 * fn NULL removes the sampler.  A run that ends before a time (give t_end,
 * taper_solver_spec_set_t_end, to reach it) does not call fn there. */
TAPER_API taper_status taper_solver_spec_set_sample_times(taper_solver_spec *spec,
                                                          const double *times, size_t n,
                                                          taper_sample_fn fn, void *user,
                                                          taper_error *err);
/* The times of taper_solver_spec_set_sample_times and their number (*n);
 * NULL and 0 without them (n may be NULL). */
TAPER_API const double *taper_solver_spec_sample_times(const taper_solver_spec *spec, size_t *n);

/* Either may be NULL (none). */
TAPER_API void taper_solver_spec_set_monitor(taper_solver_spec *spec, taper_monitor_fn monitor,
                                             void *user);
TAPER_API void taper_solver_spec_set_log(taper_solver_spec *spec, taper_log_fn log, void *user);

TAPER_API taper_method taper_solver_spec_method(const taper_solver_spec *spec);
TAPER_API double taper_solver_spec_rtol(const taper_solver_spec *spec);
TAPER_API double taper_solver_spec_atol(const taper_solver_spec *spec);
TAPER_API size_t taper_solver_spec_last_granule(const taper_solver_spec *spec);
TAPER_API int taper_solver_spec_window(const taper_solver_spec *spec);
TAPER_API int taper_solver_spec_max_order(const taper_solver_spec *spec);
TAPER_API double taper_solver_spec_t_max(const taper_solver_spec *spec);
TAPER_API long taper_solver_spec_max_steps(const taper_solver_spec *spec);

/* ------------------------------------------------------------------ */
/* Settings by name: the one table of settings                        */
/* ------------------------------------------------------------------ */
/*
 * Every setting of taper_chain_spec and taper_solver_spec is one row of one
 * table, in the spirit of SUNDIALS' name-to-setter tables: its name, type,
 * physical dimension, range, default, a one-line description and the
 * reason for its bounds.  The typed setters above and the by-name setters
 * below check a value against the same row, so a program, a scene file
 * and the bindings all see one range and one message.  The driver builds
 * its scene variables, `taper --defaults`, `taper --doc` and docs/scene.md
 * from this table; the Python and Fortran bindings their keywords.
 *
 * Names are unique over the table and are taper_error.field.  `group` is
 * where the driver's scene files put a setting ("chain", "ends",
 * "striker", "losses", "solver"); in a scene file the group's name is left
 * off the front of the setting's name: striker_radius is &striker radius.
 *
 * Values are in the rescaled units of eq. (5) of arXiv:0905.4512; a row's
 * dimension says which unit (taper_unit_scale converts to SI).
 */
typedef enum taper_setting_type {
    TAPER_SETTING_REAL = 0,     /* a double                                       */
    TAPER_SETTING_INTEGER = 1,  /* a whole number (exact in a double below 2^53)  */
    TAPER_SETTING_BOOLEAN = 2,  /* 0 or 1                                         */
    TAPER_SETTING_CHOICE = 3,   /* one of `choices`, set by name or by index      */
    TAPER_SETTING_LIST = 4      /* a list of reals, each within the range         */
} taper_setting_type;

typedef enum taper_setting_object {
    TAPER_SETTING_CHAIN = 0,    /* a taper_chain_spec's                           */
    TAPER_SETTING_SOLVER = 1    /* a taper_solver_spec's                          */
} taper_setting_object;

/* One row.  Static storage, read-only; a later version may append fields,
 * never reorder them, so never copy or allocate one: hold the pointer. */
typedef struct taper_setting {
    const char *name;              /* "n_granules", "striker_radius", ...        */
    const char *group;             /* "chain", "ends", "striker", "losses",
                                      "solver"                                   */
    taper_setting_object object;   /* the spec that holds it                     */
    taper_setting_type type;
    taper_dimension dimension;     /* TAPER_DIM_NUMBER: a pure number            */
    double min, max;               /* range (list: of each entry); a bound may
                                      be infinite                                */
    int min_open, max_open;        /* 1: that bound excluded                     */
    double default_value;          /* real, integer, boolean, or the choice's
                                      index; a list's default is empty           */
    const char *const *choices;    /* CHOICE: the names, NULL-terminated (the
                                      enum's list: taper_profile_name, ...)      */
    int beyond_paper;              /* 1: not part of the paper's model; its
                                      default is the paper's idealisation        */
    const char *description;       /* one line                                   */
    const char *bounds_reason;     /* why the range is what it is ("" if no
                                      bound needs a reason)                      */
} taper_setting;

/* The rows, i < taper_setting_count(), in a fixed order (chain settings
 * first; later versions append).  NULL past the end. */
TAPER_API size_t taper_setting_count(void);
TAPER_API const taper_setting *taper_setting_at(size_t i);
/* The row of `name` (case is ignored, as in scene files), or NULL with
 * TAPER_EINVAL naming the nearest name ("did you mean 'n_granules'?") when
 * err is given. */
TAPER_API const taper_setting *taper_setting_find(const char *name, taper_error *err);

/* Set a setting of either spec by name.  `value` is the real, the integer
 * (a whole number), the boolean (0 or 1) or the choice's index; _text takes
 * a choice by name (case-insensitive) and a number as text (strtod); _list
 * a list (n values; NULL, 0: none).  TAPER_EINVAL naming the setting for an
 * unknown name (with the nearest one), a setting of the other spec, a value
 * of the wrong type or out of range (the message states both bounds and
 * why); the spec is then unchanged.  Relations between settings are
 * checked later, as for the typed setters. */
TAPER_API taper_status taper_chain_spec_set_option(taper_chain_spec *spec, const char *name,
                                                   double value, taper_error *err);
TAPER_API taper_status taper_chain_spec_set_option_text(taper_chain_spec *spec, const char *name,
                                                        const char *value, taper_error *err);
TAPER_API taper_status taper_chain_spec_set_option_list(taper_chain_spec *spec, const char *name,
                                                        const double *values, size_t n,
                                                        taper_error *err);
TAPER_API taper_status taper_solver_spec_set_option(taper_solver_spec *spec, const char *name,
                                                    double value, taper_error *err);
TAPER_API taper_status taper_solver_spec_set_option_text(taper_solver_spec *spec,
                                                         const char *name, const char *value,
                                                         taper_error *err);
/* The value of a setting by name: the real, integer, boolean or choice
 * index; a list's values (owned by the spec) and their number.  A NULL spec
 * reads as a fresh one: the default (the rule of every getter in this
 * header).  NaN (list: NULL, 0) for an unknown name or a setting of the
 * other spec. */
TAPER_API double taper_chain_spec_option(const taper_chain_spec *spec, const char *name);
TAPER_API const double *taper_chain_spec_option_list(const taper_chain_spec *spec,
                                                     const char *name, size_t *n);
TAPER_API double taper_solver_spec_option(const taper_solver_spec *spec, const char *name);

/* Per-granule observables of a run (arrays of length N, NaN where unknown). */
/* X(constant, "name", dimension).  X_pass is a size X0 (in R_1) plus a
 * displacement x_k (in the unit of length): in SI, X0 R_1 + x_k L. */
#define TAPER_OBSERVABLE_LIST(X)                                                       \
    X(TAPER_T_PASS, "t_pass", TIME)   /* first time v_{k+1} overtakes v_k (pulse passes
                                         k)                                           */ \
    X(TAPER_T_RES, "T_res", TIME)     /* t_pass(k) - t_pass(k-1), t_pass(0) = 0; NaN
                                         where k is passed before k-1 (never negative) */ \
    X(TAPER_V_PEAK, "v_peak", VELOCITY) /* first maximum of v_k (v_peak(1) = 1 at t = 0;
                                         with a striker a maximum found like the others) */ \
    X(TAPER_T_PEAK, "t_peak", TIME)   /* its time                                     */ \
    X(TAPER_X_PASS, "X_pass", LENGTH) /* X0(k) + x_k(t_pass(k)): pulse position       */
typedef enum taper_observable {
    TAPER_OBSERVABLE_LIST(TAPER_QUANTITY_CONSTANT)
} taper_observable;
#define TAPER_N_OBSERVABLES (0 TAPER_OBSERVABLE_LIST(TAPER_QUANTITY_COUNT))

/* The names above are the column names of granules.tsv (the driver and the
 * bindings take them from here).  NULL
 * outside the enum, so that `for (i = 0; taper_observable_name(i); i++)`
 * walks them. */
TAPER_API const char *taper_observable_name(taper_observable which);
/* Its dimension; TAPER_DIM_NUMBER outside the enum. */
TAPER_API taper_dimension taper_observable_dimension(taper_observable which);

/* Statistics of a run, read one at a time with taper_sim_statistic (all
 * values are doubles; counts are exact integers). */
/* The energy budget (energy_initial ... energy_in_chain) is at t_final
 * (docs/physics.md): every granule carries its kinetic energy and half of
 * each closed contact's (a wall's contact: all of it); with a static load,
 * energies are measured from the precompressed equilibrium. */
#define TAPER_STATISTIC_LIST(X)                                                        \
    X(TAPER_STAT_STEPS, "steps", NUMBER)                   /* accepted steps (CVODE, rk8)   */ \
    X(TAPER_STAT_RHS_EVALS, "rhs_evals", NUMBER)           /* right-hand sides (rk8: with
                                                               its dense output's stages)   */ \
    X(TAPER_STAT_ROOT_EVALS, "root_evals", NUMBER)         /* root function evaluations     */ \
    X(TAPER_STAT_JAC_EVALS, "jac_evals", NUMBER)           /* Jacobian evaluations (BDF)    */ \
    X(TAPER_STAT_NONLIN_ITERS, "nonlin_iters", NUMBER)     /* nonlinear solver iterations   */ \
    X(TAPER_STAT_ERR_TEST_FAILS, "err_test_fails", NUMBER) /* local error test failures     */ \
    X(TAPER_STAT_WINDOW_CHANGES, "window_changes", NUMBER) /* times the active window grew
                                                      or shrank                     */ \
    X(TAPER_STAT_RESTARTS, "restarts", NUMBER)             /* solver re-initialisations     */ \
    X(TAPER_STAT_MAX_WINDOW, "max_window", NUMBER)         /* most granules integrated at
                                                      once                          */ \
    X(TAPER_STAT_GRANULE_REACHED, "granule_reached", NUMBER) /* highest k with t_pass(k)
                                                        known                       */ \
    X(TAPER_STAT_T_FINAL, "t_final", TIME)               /* time the run ended            */ \
    X(TAPER_STAT_ENERGY_ERROR, "energy_error", NUMBER)     /* |E(t_final) - E(0)| / E(0);
                                       with losses |E + D - E(0)| / E(0), D
                                       dissipated; under a load E from the
                                       equilibrium                                  */ \
    X(TAPER_STAT_MOMENTUM_ERROR, "momentum_error", NUMBER) /* |P(t_final) - P(0)| /
                                       max(P(0), sum m_k |v_k|): relative to the
                                       momentum in motion; with walls, a load or
                                       drag P(t) - P(0) is compared with the
                                       external impulses J_left - J_right + F0 t
                                       (free first body) - F0 t (free last body)
                                       - drag sum x_k                               */ \
    X(TAPER_STAT_COMPLETE, "complete", NUMBER)  /* 1 when the run ended by itself: every
                                       requested observable known, or NaN because
                                       it does not exist (a peak that never came;
                                       passes beyond a pulse that drag absorbed,
                                       said in the log)                             */ \
    X(TAPER_STAT_ENERGY_INITIAL, "energy_initial", ENERGY)       /* E(0)                    */ \
    X(TAPER_STAT_ENERGY_DISSIPATED, "energy_dissipated", ENERGY) /* by damping and drag
                                                            until t_final           */ \
    X(TAPER_STAT_ENERGY_TRANSMITTED, "energy_transmitted", ENERGY) /* left forward
                                       for good: the clusters (cut at open contacts)
                                       at the far end moving forward, none of
                                       which meets the rest again; 0 with a right
                                       wall                                         */ \
    X(TAPER_STAT_ENERGY_REFLECTED, "energy_reflected", ENERGY) /* left backward for
                                       good, likewise at the near end; 0 with a
                                       left wall or a piston                        */ \
    X(TAPER_STAT_ENERGY_IN_CHAIN, "energy_in_chain", ENERGY)   /* the rest                  */ \
    X(TAPER_STAT_WALL_PEAK_FORCE_LEFT, "wall_peak_force_left", FORCE) /* largest wall force
                                       over [0, t_final] (NaN: no wall); a run with a
                                       right wall lasts until that wall's first
                                       contact has opened (under a load: its force
                                       is back below half its rise), and to t_end
                                       if later                                     */ \
    X(TAPER_STAT_WALL_PEAK_TIME_LEFT, "wall_peak_time_left", TIME) /* its time (a root of
                                       the wall contact's rate: exact)              */ \
    X(TAPER_STAT_WALL_IMPULSE_LEFT, "wall_impulse_left", IMPULSE) /* integral of the wall
                                       force over [0, t_final]                      */ \
    X(TAPER_STAT_WALL_PEAK_FORCE_RIGHT, "wall_peak_force_right", FORCE)                      \
    X(TAPER_STAT_WALL_PEAK_TIME_RIGHT, "wall_peak_time_right", TIME)                        \
    X(TAPER_STAT_WALL_IMPULSE_RIGHT, "wall_impulse_right", IMPULSE)
typedef enum taper_statistic { TAPER_STATISTIC_LIST(TAPER_QUANTITY_CONSTANT) } taper_statistic;
#define TAPER_N_STATISTICS (0 TAPER_STATISTIC_LIST(TAPER_QUANTITY_COUNT))

/* The names above (those of granules.tsv's header); NULL outside the enum. */
TAPER_API const char *taper_statistic_name(taper_statistic which);
/* Its dimension (TAPER_DIM_NUMBER for counts and relative errors);
 * TAPER_DIM_NUMBER outside the enum. */
TAPER_API taper_dimension taper_statistic_dimension(taper_statistic which);

/* Prepares a run of `chain` (which must outlive the sim), and computes its
 * binary collision theory once (taper_sim_theory), asking the spec's
 * monitor as taper_theory_compute_monitored does, and between its other
 * passes over the chain (window 0..0 too).  Copies spec (NULL: the
 * defaults).  Returns a sim the caller owns (release with taper_sim_free),
 * or NULL: TAPER_EINVAL for a NULL chain or settings that do not fit it
 * (last_granule > N, max_order beyond the method's), TAPER_ERANGE from the
 * theory, TAPER_EINTERRUPTED when the monitor stopped the set-up,
 * TAPER_ENOMEM.  CVODE is set up by taper_sim_run. */
TAPER_API taper_sim *taper_sim_alloc(const taper_chain *chain, const taper_solver_spec *spec,
                                     taper_error *err);
TAPER_API void taper_sim_free(taper_sim *sim);

/* Integrates from the impulse until every requested observable is known.
 * Returns TAPER_OK, or TAPER_ESOLVER / TAPER_EINTERRUPTED / TAPER_ELIMIT
 * with the observables found so far kept (TAPER_STAT_COMPLETE 0) and a
 * message naming the granule the pulse had reached and the time (for
 * ESOLVER it includes CVODE's own message, which SUNDIALS would otherwise
 * print).  A sim runs once: a second call is TAPER_EINVAL.  NULL sim:
 * TAPER_EINVAL. */
TAPER_API taper_status taper_sim_run(taper_sim *sim, taper_error *err);

/* Array of length N owned by the sim (valid until taper_sim_free), NaN
 * where not (yet) known; NULL for an unknown observable or a NULL sim.
 * Readable after a partial run too. */
TAPER_API const double *taper_sim_observable(const taper_sim *sim, taper_observable which);
/* The binary collision theory of the sim's chain (taper_theory_compute's
 * columns), computed once by taper_sim_alloc; NULL for an unknown quantity
 * or a NULL sim. */
TAPER_API const double *taper_sim_theory(const taper_sim *sim, taper_theory_quantity which);
/* One statistic of the run (zero before the run); NaN for an unknown
 * statistic or a NULL sim. */
TAPER_API double taper_sim_statistic(const taper_sim *sim, taper_statistic which);

/* Displacements x_k and velocities v_k (caller-owned arrays of length N,
 * either may be NULL) of every granule at TAPER_STAT_T_FINAL.  TAPER_EINVAL
 * for a NULL sim or one that has not run. */
TAPER_API taper_status taper_sim_state(const taper_sim *sim, double *x, double *v,
                                       taper_error *err);
/* The time the state readers see: t_final after a run, the sample time
 * inside a sampler's call. */
TAPER_API double taper_sim_time(const taper_sim *sim);
/* The work the piston did until TAPER_STAT_T_FINAL, W = J(min(t_final,
 * duration)) (taper_chain_spec_set_piston): with a piston the energy
 * budget's parts add up to W, not to E(0) = 0, and TAPER_STAT_ENERGY_ERROR
 * is |E + D - W| / W.  NaN without a piston or before the run. */
TAPER_API double taper_sim_piston_work(const taper_sim *sim);
/* Displacement and velocity of the striker (TAPER_EINVAL if none). */
TAPER_API taper_status taper_sim_striker_state(const taper_sim *sim, double *x, double *v,
                                               taper_error *err);
/* Contact forces (caller-owned array of N + 1): force[k] of the contact
 * (k, k+1) for k = 1..N-1, force[0] that on granule 1 from the left (the
 * striker, a wall or the load; 0 when free), force[N] that on granule N from
 * the right (a wall or the load).  Damping included; never negative. */
TAPER_API taper_status taper_sim_forces(const taper_sim *sim, double *force, taper_error *err);


/* --- Asymptotic laws (paper Secs. III-IV) --- */
/*
 * Large-k laws of the binary collision approximation for the four tapering
 * protocols, for any contact exponent n > 1 (the paper: n = 5/2).  Each
 * was derived again and is checked in tests/test_asymptotic.c against the
 * exact sums and products of taper_theory_compute; where the paper's
 * printed formula is wrong the correct one is implemented and the
 * difference is recorded in docs/paper.md ("Discrepancies found in the
 * paper").  Every function returns NaN outside its domain (NaN arguments,
 * n <= 1 or infinite, q or S out of range); none fails otherwise.
 *
 * Exponential chains use the paper's signed q: q > 0 is the backward chain
 * R_k = (1-q)^(1-k) (Sec. III B); a forward chain R_k = (1+q)^(1-k) of
 * parameter q is evaluated at -q, exactly as the paper does in Sec. IV B.
 */

/* Power laws y ~ x^p of linear chains.  Backward linear (R_k = 1 + S(k-1),
 * S k >> 1, independent of S), with beta = 3/2 - 1/(2n):           n = 5/2 */
/* The last three are forward linear (R_k = 1 - S(k-1) = (1+S)(1 - b k),
 * b = S/(1+S)): the divergence laws of Sec. IV A as powers of (1 - b k) or
 * (1 - t/C). */
#define TAPER_LAW_LIST(X)                                                              \
    X(TAPER_LAW_V_OF_K, "v_of_k")         /* v_k ~ k^-3/2, eq. (22)          -3/2   */ \
    X(TAPER_LAW_T_RES_OF_K, "t_res_of_k") /* T_k ~ k^beta, eq. (25)          13/10  */ \
    X(TAPER_LAW_T_OF_K, "t_of_k")         /* t_k ~ k^(beta+1), eq. (26)      23/10  */ \
    X(TAPER_LAW_K_OF_T, "k_of_t")         /* k ~ t^(1/(beta+1)), Table I     10/23  */ \
    X(TAPER_LAW_V_OF_T, "v_of_t")         /* v ~ t^(-3/2/(beta+1)), eq. (27) -15/23 */ \
    X(TAPER_LAW_X_OF_T, "x_of_t")         /* X ~ t^(2/(beta+1)), eq. (30)    20/23  */ \
    X(TAPER_LAW_C_OF_T, "c_of_t")         /* c = dX/dt ~ t^(2/(beta+1) - 1), eq. (31)
                                             -3/23 (the paper prints -3/20: wrong)  */ \
    X(TAPER_LAW_FWD_V_OF_K, "fwd_v_of_k") /* v_k ~ (1 - b k)^-3/2, eq. (50)  -3/2   */ \
    X(TAPER_LAW_FWD_T_OF_K, "fwd_t_of_k") /* C - t_k ~ (1 - b k)^(beta+1), eq. (51)
                                             23/10                                  */ \
    X(TAPER_LAW_FWD_V_OF_T, "fwd_v_of_t") /* v ~ (1 - t/C)^(-3/2/(beta+1)), eq. (53)
                                             -15/23                                 */
typedef enum taper_law { TAPER_LAW_LIST(TAPER_ENUM_CONSTANT) } taper_law;
#define TAPER_N_LAWS (0 TAPER_LAW_LIST(TAPER_ENUM_COUNT))

/* The names above: each enum constant's suffix in lower case.  NULL
 * outside the enum, so that
 * `for (i = 0; taper_law_name(i); i++)` walks them. */
TAPER_API const char *taper_law_name(taper_law law);

/* The exponent p of `law` (a taper_law) for contact exponent n. */
TAPER_API double taper_asymptotic_exponent(taper_law law, double n);

/* A(q) = [1 + (1-q)^-3] / 2, eq. (35): v_{k+1} = v_k / A, so
 * v_k = A^(1-k) = A e^(-k ln A), eq. (34).  Domain q < 1. */
TAPER_API double taper_asymptotic_A(double q);
/* ln A(q), accurate for small |q|: the decay rate of v_k in k (Table II);
 * a forward chain's growth rate is -ln A(-q) (Table IV).  Domain q < 1. */
TAPER_API double taper_asymptotic_lnA(double q);
/* eta(q) = ln(T_{k+1} / T_k) = (1 - 2/n) ln A - (5/(2n)) ln(1-q), exact for
 * every k; n = 5/2 gives eq. (39), ln(A^(1/5) / (1-q)).  t ~ e^(eta k),
 * eq. (38).  Domain q < 1, n > 1. */
TAPER_API double taper_asymptotic_eta(double q, double n);
/* f(q) = ln A / eta, eq. (41): v ~ t^-f (backward, Table III) and
 * v ~ (1 + t/M)^-f(-q) (forward, Table V).  Domain q < 1, q != 0, n > 1. */
TAPER_API double taper_asymptotic_f(double q, double n);
/* Backward exponential chains, 0 < q < 1: X ~ t^p with
 * p = -ln(1-q) / eta, which is 1 - f/5 for n = 5/2, eq. (44). */
TAPER_API double taper_asymptotic_position_exponent(double q, double n);
/* c = dX/dt ~ t^(p - 1), -f/5 for n = 5/2, eq. (45).
 * Domain 0 < q < 1. */
TAPER_API double taper_asymptotic_speed_exponent(double q, double n);
/* Time scale tau(q) = T_1 / (e^eta - 1), T_1 the first residence time
 * (eq. (18) with v = 1, mu_1 = 1/(1 + (1-q)^3),
 * r_1 = (1 - q/2)^(-1/2)).  The exact theory obeys, for every k,
 *   t_k = tau (e^(k eta) - 1)  and  v_k = (1 + t_{k-1}/tau)^(-f)   (t_0 = 0),
 * i.e. v(t) of eqs. (40) and (56) with t the time the
 * pulse reaches granule k.  tau > 0 for backward chains (q > 0); tau < 0
 * for forward ones (q < 0), whose pulse passes the whole infinite chain by
 * t = -tau.  Domain q < 1, q != 0, n > 1. */
TAPER_API double taper_asymptotic_timescale(double q, double n);
/* M(q) of eq. (57) for a forward exponential chain of parameter q > 0:
 * taper_asymptotic_timescale(-q, n) < 0; v diverges as t -> -M.
 * The paper's printed M(q) is wrong (docs/paper.md). */
TAPER_API double taper_asymptotic_M(double q, double n);

/* Forward linear chains, 0 < S < 1: the divergence time C(S), where the
 * exact sum of T_k over the longest chain (N < 1 + 1/S) converges.
 * C0: leading order, sqrt(pi) Gamma(1+1/n)/Gamma(1/n+1/2) (n/4)^(1/n) /
 *     ((beta+1) S); for n = 5/2 it is the paper's C0(S) with 1/S in place
 *     of the paper's (1 + 1/S), which is not the correct O(S) term.
 * C:  C0 (1 + c1 S), c1 = 57/130 for n = 5/2 (general n: see asymptotic.c);
 *     relative error O(S^2). */
TAPER_API double taper_asymptotic_C0(double S, double n);
TAPER_API double taper_asymptotic_C(double S, double n);
/* b = S / (1 + S) = 1/(1 + 1/S): v_k ~ (1 - b k)^-3/2 diverges at k = 1/b
 * (Fig. 8 inset).  Domain 0 < S < 1. */
TAPER_API double taper_asymptotic_forward_linear_b(double S);
/* --- end asymptotic --- */
/* --- Fits --- */
/*
 * Least-squares fits of y(x) over a window, applied alike to numerics and to
 * the theory.  Every model is fitted to ln y (relative residuals, the right
 * weighting for data that span decades, and a > 0 by construction):
 *
 *   TAPER_FIT_POWER        y = a x^b          ln y = ln a + b ln x  (linear)
 *   TAPER_FIT_EXPONENTIAL  y = a e^(b x)      ln y = ln a + b x     (linear)
 *   TAPER_FIT_DIVERGENCE_B y = a (1 - b x)^-p, p given (e.g. 3/2): a, b
 *   TAPER_FIT_DIVERGENCE_C y = a (1 - x/C)^-p: a, C; p given, or fitted
 *                          too when the exponent is NaN (e.g. 15/23 expected)
 *   TAPER_FIT_DIVERGENCE_M y = a (1 + x/M)^-f: a, M, f
 *
 * The divergence forms are solved with gsl_multifit_nlinear (trust region,
 * Levenberg-Marquardt, analytic Jacobian), started from the linearisation
 * y^(-1/p) = a^(-1/p) (1 - x/C), which is exact for exact data (with a scan
 * over p when p is fitted).  Results: parameters in the order listed
 * (parameter 2 is the exponent p or f, fixed or fitted), their standard
 * errors from the covariance (J^T J)^-1 scaled by the residual variance
 * chi2 / (n_points - n_params) (a's error by the delta method from ln a; a
 * fixed p has error 0), chi2 = sum of squared ln-residuals.
 *
 * Window: the points with index_begin <= i < index_end (index_end = 0: to the
 * end) and x_min <= x <= x_max.  Points in the window whose x or y is not
 * finite, whose y <= 0, or (power law) whose x <= 0 are skipped and counted
 * in n_skipped when skip_invalid is non-zero (the default); otherwise the
 * first such point is an error.  TAPER_EINVAL (with a message) for bad
 * arguments or fewer than n_params + 1 usable points or x values that cannot
 * determine the fit; TAPER_ESOLVER if the nonlinear fit does not converge.
 * On failure the result's parameters and errors are NaN.  GSL's error
 * handler is never reached (inputs are validated first), so nothing prints
 * or aborts.
 */
#define TAPER_FIT_MODEL_LIST(X)                                                        \
    X(TAPER_FIT_POWER, "power")                                                        \
    X(TAPER_FIT_EXPONENTIAL, "exponential")                                            \
    X(TAPER_FIT_DIVERGENCE_B, "divergence_b")                                          \
    X(TAPER_FIT_DIVERGENCE_C, "divergence_c")                                          \
    X(TAPER_FIT_DIVERGENCE_M, "divergence_m")
typedef enum taper_fit_model { TAPER_FIT_MODEL_LIST(TAPER_ENUM_CONSTANT) } taper_fit_model;
#define TAPER_N_FIT_MODELS (0 TAPER_FIT_MODEL_LIST(TAPER_ENUM_COUNT))

/* The names above; NULL outside the enum. */
TAPER_API const char *taper_fit_model_name(taper_fit_model model);
/* Case-insensitive inverse; TAPER_EINVAL if unknown (field "model"). */
TAPER_API taper_status taper_fit_model_from_name(const char *name, taper_fit_model *model,
                                                 taper_error *err);

/* A fit's settings.  Defaults for `model`: the whole range, exponent 3/2
 * (DIVERGENCE_B) or NaN (fitted, DIVERGENCE_C), skip_invalid 1,
 * max_iter 200, xtol 1e-12.  NULL with TAPER_EINVAL for an unknown model. */
typedef struct taper_fit_spec taper_fit_spec;
TAPER_API taper_fit_spec *taper_fit_spec_alloc(taper_fit_model model, taper_error *err);
TAPER_API void taper_fit_spec_free(taper_fit_spec *spec);

/* The fixed exponent p of DIVERGENCE_B/_C (> 0), or NaN: fit it (_C only). */
TAPER_API taper_status taper_fit_spec_set_exponent(taper_fit_spec *spec, double p,
                                                   taper_error *err);
/* Points begin <= i < end (end 0: to the end of the data). */
TAPER_API taper_status taper_fit_spec_set_index_window(taper_fit_spec *spec, size_t begin,
                                                       size_t end, taper_error *err);
/* Points with x_min <= x <= x_max (-inf, +inf: all; x_min <= x_max). */
TAPER_API taper_status taper_fit_spec_set_x_window(taper_fit_spec *spec, double x_min,
                                                   double x_max, taper_error *err);
TAPER_API taper_status taper_fit_spec_set_skip_invalid(taper_fit_spec *spec, int skip,
                                                       taper_error *err);
TAPER_API taper_status taper_fit_spec_set_max_iter(taper_fit_spec *spec, size_t max_iter,
                                                   taper_error *err);
TAPER_API taper_status taper_fit_spec_set_xtol(taper_fit_spec *spec, double xtol,
                                               taper_error *err);
TAPER_API taper_fit_model taper_fit_spec_model(const taper_fit_spec *spec);
TAPER_API double taper_fit_spec_exponent(const taper_fit_spec *spec);

/* The outcome of a fit. */
typedef struct taper_fit_result taper_fit_result;

/* Fits y[i] against x[i], i < n, per spec (see above).  Returns a result the
 * caller owns (release with taper_fit_result_free), or NULL with the status
 * in err (TAPER_EINVAL, TAPER_ESOLVER, TAPER_ENOMEM). */
TAPER_API taper_fit_result *taper_fit(const taper_fit_spec *spec, const double *x,
                                      const double *y, size_t n, taper_error *err);
TAPER_API void taper_fit_result_free(taper_fit_result *result);

TAPER_API taper_fit_model taper_fit_result_model(const taper_fit_result *result);
TAPER_API size_t taper_fit_result_n_params(const taper_fit_result *result); /* 2 or 3 */
/* Parameter i (0: a; 1: b, C or M; 2: p or f) and its standard error; NaN
 * for i >= 3 (a fixed exponent is reported with error 0). */
TAPER_API double taper_fit_result_param(const taper_fit_result *result, size_t i);
TAPER_API double taper_fit_result_param_error(const taper_fit_result *result, size_t i);
TAPER_API size_t taper_fit_result_n_points(const taper_fit_result *result);  /* used     */
TAPER_API size_t taper_fit_result_n_skipped(const taper_fit_result *result); /* skipped  */
TAPER_API double taper_fit_result_chi2(const taper_fit_result *result);
TAPER_API size_t taper_fit_result_iterations(const taper_fit_result *result); /* 0: linear */
/* --- end fits --- */

#ifdef __cplusplus
}
#endif

#endif /* TAPER_H */
