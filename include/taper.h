/*
 * taper.h -- pulse propagation in tapered granular chains.
 *
 * The one public header of libtaper.  It models the rescaled equations of
 * motion of Harbola, Rosas, Esposito and Lindenberg, "Pulse propagation in
 * tapered granular chains: an analytic study" (eq. motion_rescaled):
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
 *    status and a message the caller can show.  err may always be NULL.
 *    After a successful call err holds TAPER_OK and an empty message.
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
#define TAPER_VERSION_MAJOR 0
#define TAPER_VERSION_MINOR 1
#define TAPER_VERSION_PATCH 0
#define TAPER_VERSION_STRING "0.1.0"

/* The version of the library actually loaded (may differ from the macros
 * the caller was compiled with). */
TAPER_API const char *taper_version(void);

/* ------------------------------------------------------------------ */
/* Errors                                                             */
/* ------------------------------------------------------------------ */
typedef enum taper_status {
    TAPER_OK = 0,
    TAPER_EINVAL = 1,        /* invalid argument or parameter             */
    TAPER_ENOMEM = 2,        /* allocation failed                          */
    TAPER_ERANGE = 3,        /* a value overflows double precision         */
    TAPER_ESOLVER = 4,       /* the integrator failed; partial results kept */
    TAPER_EINTERRUPTED = 5,  /* the monitor asked to stop; partial results kept */
    TAPER_ELIMIT = 6,        /* t_max or max_steps reached; partial results kept */
    TAPER_EIO = 7            /* file input/output (driver level)           */
} taper_status;

#define TAPER_MESSAGE_SIZE 512

/* Filled by failing calls.  status repeats the return value. */
typedef struct taper_error {
    int status;
    char message[TAPER_MESSAGE_SIZE];
} taper_error;

/* A short constant description of a status code ("invalid argument", ...);
 * "unknown status" for other values.  Never NULL; static storage. */
TAPER_API const char *taper_strerror(int status);

/* ------------------------------------------------------------------ */
/* Chain geometry                                                      */
/* ------------------------------------------------------------------ */
typedef enum taper_profile {
    TAPER_MONODISPERSE = 0,          /* R_k = 1                                  */
    TAPER_BACKWARD_LINEAR = 1,       /* R_k = 1 + S (k-1),  S > 0                */
    TAPER_FORWARD_LINEAR = 2,        /* R_k = 1 - S (k-1),  S > 0, N < 1 + 1/S   */
    TAPER_BACKWARD_EXPONENTIAL = 3,  /* R_k = (1-q)^(1-k),  0 < q < 1            */
    TAPER_FORWARD_EXPONENTIAL = 4,   /* R_k = (1+q)^(1-k),  q > 0                */
    TAPER_CUSTOM = 5                 /* R_k given; R_1 should be 1 (the unit)    */
} taper_profile;

/* "monodisperse", "backward_linear", ... ; NULL for an unknown value. */
TAPER_API const char *taper_profile_name(int profile);
/* Case-insensitive inverse of taper_profile_name.  TAPER_EINVAL if unknown. */
TAPER_API int taper_profile_from_name(const char *name, int *profile);

/* What the caller fills to describe a chain.  Plain data: start from
 * taper_chain_spec_init() so that fields added later get their defaults. */
typedef struct taper_chain_spec {
    int profile;            /* taper_profile                                   */
    size_t n_granules;      /* N >= 2                                          */
    double s;               /* linear tapering S                               */
    double q;               /* exponential tapering q                          */
    double exponent;        /* contact exponent n > 1 (5/2: Hertz)             */
    const double *radii;    /* TAPER_CUSTOM: n_granules radii (copied)         */
} taper_chain_spec;

/* Defaults: monodisperse, N = 100, S = q = 0, n = 5/2, radii = NULL. */
TAPER_API void taper_chain_spec_init(taper_chain_spec *spec);

typedef struct taper_chain taper_chain;

/* Builds the chain: radii, masses, contact factors, rest positions.  The
 * spec (and spec->radii) is copied: the caller may free it afterwards.
 * Returns a chain the caller owns (release with taper_chain_free), or NULL:
 * TAPER_EINVAL for invalid parameters (NULL spec, N < 2, S or q out of
 * range, forward_linear with N >= 1 + 1/S, custom without radii or with a
 * radius <= 0, n <= 1), TAPER_ERANGE for chains whose masses overflow or
 * underflow double precision (naming the granule), TAPER_ENOMEM. */
TAPER_API taper_chain *taper_chain_alloc(const taper_chain_spec *spec, taper_error *err);
/* Releases the chain and its arrays.  Every sim of it must be freed first. */
TAPER_API void taper_chain_free(taper_chain *chain);

TAPER_API size_t taper_chain_size(const taper_chain *chain);       /* N */
TAPER_API double taper_chain_exponent(const taper_chain *chain);   /* n */
TAPER_API int taper_chain_profile(const taper_chain *chain);
/* Arrays of length N owned by the chain, valid until taper_chain_free. */
TAPER_API const double *taper_chain_radius(const taper_chain *chain);   /* R_k          */
TAPER_API const double *taper_chain_mass(const taper_chain *chain);     /* m_k = R_k^3  */
TAPER_API const double *taper_chain_contact(const taper_chain *chain);  /* r_k, [N-1] = NaN */
/* Centre of granule k in the uncompressed chain, X0(1) = 0,
 * X0(k) = sum_{j<k} (R_j + R_{j+1})  (the paper's X_0 for every profile). */
TAPER_API const double *taper_chain_rest_position(const taper_chain *chain);

/* ------------------------------------------------------------------ */
/* Binary collision approximation (paper, Sec. II)                    */
/* ------------------------------------------------------------------ */

/* Residence time of one binary collision, eq. (compress-time):
 * T = sqrt(pi) (n mu / (2 r))^(1/n) zdot0^(2/n - 1) Gamma(1+1/n) / Gamma(1/n+1/2).
 * NaN for invalid arguments (mu, r, zdot0 <= 0 or n <= 1). */
TAPER_API double taper_theory_collision_time(double mu, double r, double zdot0, double n);

/* Fills caller-owned arrays, each optional (NULL to skip), of length N:
 *   v[k-1]  = v_k, eq. (recv), the velocity granule k leaves its collision with;
 *   mu[k-1] = mu_k = m_k m_{k+1} / (m_k + m_{k+1}),  k = 1..N-1;
 *   T[k-1]  = T_k, eq. (compress-time) with zdot0 = v_k, k = 1..N-1;
 *   t[k-1]  = sum_{j<=k} T_j, eq. (totaltime), k = 1..N-1.
 * Entries that do not exist are NaN.  TAPER_EINVAL for a NULL chain;
 * TAPER_ERANGE if a time overflows (the arrays are then filled up to the
 * granule named in the message). */
TAPER_API int taper_theory_compute(const taper_chain *chain, double *v, double *mu,
                                   double *T, double *t, taper_error *err);

/* ------------------------------------------------------------------ */
/* Full dynamics                                                       */
/* ------------------------------------------------------------------ */
typedef enum taper_method {
    TAPER_ADAMS = 0,  /* CVODE Adams-Moulton, fixed-point iteration (non-stiff) */
    TAPER_BDF = 1     /* CVODE BDF, Newton with the banded analytic Jacobian    */
} taper_method;

/* Given to the monitor after each pulse event. */
typedef struct taper_progress {
    size_t granule;     /* highest k whose t_pass is known (0: none yet)      */
    size_t target;      /* the run ends once the pulse passed this granule    */
    double t;           /* time of the event                                  */
    long steps;         /* internal steps so far                              */
    size_t window_lo;   /* active window: granules window_lo..window_hi move  */
    size_t window_hi;
} taper_progress;

/* Return non-zero to stop the run (it then ends with TAPER_EINTERRUPTED,
 * keeping what was found).  Called from the thread running the simulation. */
typedef int (*taper_monitor_fn)(const taper_progress *progress, void *user);

/* Diagnostics the library would otherwise have printed, called from the
 * thread running the simulation: level 1 (warning) for CVODE's own messages
 * and for peaks declared absent, level 0 (information) for window restarts.
 * Optional: failures are reported through taper_error in any case. */
typedef void (*taper_log_fn)(int level, const char *message, void *user);

typedef struct taper_solver_spec {
    int method;             /* taper_method                                    */
    double rtol;            /* relative tolerance                              */
    double atol;            /* absolute tolerance, in units of each granule's
                               binary-collision scale (its velocity v_k and
                               maximum compression): relative to the pulse
                               wherever it is, however strong the taper       */
    size_t last_granule;    /* stop once every observable of granules
                               1..last_granule is known; 0: the whole chain   */
    int window;             /* non-zero: integrate only the granules that can
                               move (exact); zero: the whole chain every step */
    int max_order;          /* highest method order; 0: the measured default */
    double t_max;           /* stop at this time; 0: no limit                  */
    long max_steps;         /* stop after this many internal steps; 0: none    */
    taper_monitor_fn monitor;
    void *monitor_data;
    taper_log_fn log;
    void *log_data;
} taper_solver_spec;

/* Defaults (the measured Pareto choice, see docs/benchmarks.md). */
TAPER_API void taper_solver_spec_init(taper_solver_spec *spec);

/* Per-granule observables of a run (arrays of length N, NaN where unknown). */
typedef enum taper_observable {
    TAPER_T_PASS = 0,   /* first time v_{k+1} overtakes v_k (pulse passes k)    */
    TAPER_T_RES = 1,    /* t_pass(k) - t_pass(k-1), t_pass(0) = 0               */
    TAPER_V_PEAK = 2,   /* first maximum of v_k (v_peak(1) = 1 at t = 0)        */
    TAPER_T_PEAK = 3,   /* its time                                             */
    TAPER_X_PASS = 4    /* X0(k) + x_k(t_pass(k)): pulse position               */
} taper_observable;
#define TAPER_N_OBSERVABLES 5

typedef struct taper_stats {
    long steps;             /* internal CVODE steps                           */
    long rhs_evals;         /* right-hand side evaluations                    */
    long root_evals;        /* root function evaluations                      */
    long jac_evals;         /* Jacobian evaluations (BDF)                     */
    long nonlin_iters;      /* nonlinear solver iterations                    */
    long err_test_fails;    /* local error test failures                      */
    long window_changes;    /* times the active window grew or shrank         */
    long restarts;          /* solver re-initialisations                      */
    size_t max_window;      /* largest number of granules integrated at once  */
    size_t granule_reached; /* highest k with t_pass(k) known                 */
    double t_final;         /* time the run ended                             */
    double energy_error;    /* |E(t_final) - E(0)| / E(0)                     */
    double momentum_error;  /* |P(t_final) - P(0)| / max(P(0), sum m_k |v_k|):
                               relative to the momentum in motion            */
    int complete;           /* 1 when every requested observable is known     */
} taper_stats;

typedef struct taper_sim taper_sim;

/* Prepares a run of `chain` (which must outlive the sim).  Copies spec;
 * NULL spec: the defaults of taper_solver_spec_init.  Returns a sim the
 * caller owns (release with taper_sim_free), or NULL: TAPER_EINVAL for a
 * NULL chain or invalid settings (method, rtol outside [10 eps, 1), atol
 * outside (0, 1), last_granule > N, max_order beyond CVODE's limit,
 * negative t_max or max_steps), TAPER_ENOMEM.  Cheap: CVODE is set up by
 * taper_sim_run. */
TAPER_API taper_sim *taper_sim_alloc(const taper_chain *chain, const taper_solver_spec *spec,
                                     taper_error *err);
TAPER_API void taper_sim_free(taper_sim *sim);

/* Integrates from the impulse until every requested observable is known.
 * Returns TAPER_OK, or TAPER_ESOLVER / TAPER_EINTERRUPTED / TAPER_ELIMIT
 * with the observables found so far kept (stats.complete == 0) and a message
 * naming the granule the pulse had reached and the time (for ESOLVER it
 * includes CVODE's own message, which SUNDIALS would otherwise print).
 * A sim runs once: a second call is TAPER_EINVAL.  NULL sim: TAPER_EINVAL. */
TAPER_API int taper_sim_run(taper_sim *sim, taper_error *err);

/* Array of length N owned by the sim (valid until taper_sim_free), NaN
 * where not (yet) known; NULL for an unknown observable or a NULL sim.
 * Readable after a partial run too. */
TAPER_API const double *taper_sim_observable(const taper_sim *sim, int which);
/* Copies the statistics of the run into *stats (zeros before the run).
 * Does nothing if either pointer is NULL. */
TAPER_API void taper_sim_stats(const taper_sim *sim, taper_stats *stats);

/* Displacements x_k and velocities v_k (caller-owned arrays of length N,
 * either may be NULL) of every granule at stats.t_final.  TAPER_EINVAL for
 * a NULL sim or one that has not run. */
TAPER_API int taper_sim_state(const taper_sim *sim, double *x, double *v, taper_error *err);

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
typedef enum taper_law {
    TAPER_LAW_V_OF_K = 0,     /* v_k ~ k^-3/2, eq. (vel-ampl-lin-large)       -3/2   */
    TAPER_LAW_T_RES_OF_K = 1, /* T_k ~ k^beta, eq. (rel-t-k)                   13/10 */
    TAPER_LAW_T_OF_K = 2,     /* t_k ~ k^(beta+1), eq. (time-with-k-binary)    23/10 */
    TAPER_LAW_K_OF_T = 3,     /* k ~ t^(1/(beta+1)), Table I                   10/23 */
    TAPER_LAW_V_OF_T = 4,     /* v ~ t^(-3/2/(beta+1)), eq. (ampl-timelinear) -15/23 */
    TAPER_LAW_X_OF_T = 5,     /* X ~ t^(2/(beta+1)), eq. (positiont)           20/23 */
    TAPER_LAW_C_OF_T = 6,     /* c = dX/dt ~ t^(2/(beta+1) - 1), eq. (speed)  -3/23
                                 (the paper prints -3/20: wrong)                       */
    /* Forward linear (R_k = 1 - S(k-1) = (1+S)(1 - b k), b = S/(1+S)): the
     * divergence laws of Sec. IV A as powers of (1 - b k) or (1 - t/C). */
    TAPER_LAW_FWD_V_OF_K = 7,  /* v_k ~ (1 - b k)^-3/2, eq. (vk-forw)          -3/2   */
    TAPER_LAW_FWD_T_OF_K = 8,  /* C - t_k ~ (1 - b k)^(beta+1), eq. (t-forw)   23/10 */
    TAPER_LAW_FWD_V_OF_T = 9   /* v ~ (1 - t/C)^(-3/2/(beta+1)), eq. (v-t-forw) -15/23 */
} taper_law;

/* The exponent p of `law` (a taper_law) for contact exponent n. */
TAPER_API double taper_asymptotic_exponent(int law, double n);

/* A(q) = [1 + (1-q)^-3] / 2, eq. (eq:Adef): v_{k+1} = v_k / A, so
 * v_k = A^(1-k) = A e^(-k ln A), eq. (eq:vgeometric).  Domain q < 1. */
TAPER_API double taper_asymptotic_A(double q);
/* ln A(q), accurate for small |q|: the decay rate of v_k in k (Table II);
 * a forward chain's growth rate is -ln A(-q) (Table IV).  Domain q < 1. */
TAPER_API double taper_asymptotic_lnA(double q);
/* eta(q) = ln(T_{k+1} / T_k) = (1 - 2/n) ln A - (5/(2n)) ln(1-q), exact for
 * every k; n = 5/2 gives eq. (Bq), ln(A^(1/5) / (1-q)).  t ~ e^(eta k),
 * eq. (time-k-binary).  Domain q < 1, n > 1. */
TAPER_API double taper_asymptotic_eta(double q, double n);
/* f(q) = ln A / eta, eq. (bq-geometric): v ~ t^-f (backward, Table III) and
 * v ~ (1 + t/M)^-f(-q) (forward, Table V).  Domain q < 1, q != 0, n > 1. */
TAPER_API double taper_asymptotic_f(double q, double n);
/* Backward exponential chains, 0 < q < 1: X ~ t^p with
 * p = -ln(1-q) / eta, which is 1 - f/5 for n = 5/2, eq. (position-pulse-binary). */
TAPER_API double taper_asymptotic_position_exponent(double q, double n);
/* c = dX/dt ~ t^(p - 1), -f/5 for n = 5/2, eq. (pulse-velocity-bianry).
 * Domain 0 < q < 1. */
TAPER_API double taper_asymptotic_speed_exponent(double q, double n);
/* Time scale tau(q) = T_1 / (e^eta - 1), T_1 the first residence time
 * (eq. compress-time with v = 1, mu_1 = 1/(1 + (1-q)^3),
 * r_1 = (1 - q/2)^(-1/2)).  The exact theory obeys, for every k,
 *   t_k = tau (e^(k eta) - 1)  and  v_k = (1 + t_{k-1}/tau)^(-f)   (t_0 = 0),
 * i.e. v(t) of eqs. (vel-t-binary) and (geo-vt-forw) with t the time the
 * pulse reaches granule k.  tau > 0 for backward chains (q > 0); tau < 0
 * for forward ones (q < 0), whose pulse passes the whole infinite chain by
 * t = -tau.  Domain q < 1, q != 0, n > 1. */
TAPER_API double taper_asymptotic_timescale(double q, double n);
/* M(q) of eq. (mq) for a forward exponential chain of parameter q > 0:
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
 *                          too when spec.p is NaN (e.g. 15/23 expected)
 *   TAPER_FIT_DIVERGENCE_M y = a (1 + x/M)^-f: a, M, f
 *
 * The divergence forms are solved with gsl_multifit_nlinear (trust region,
 * Levenberg-Marquardt, analytic Jacobian), started from the linearisation
 * y^(-1/p) = a^(-1/p) (1 - x/C), which is exact for exact data (with a scan
 * over p when p is fitted).  Results: param[] in the order listed
 * (param[2] is the exponent p or f, fixed or fitted), param_err[] their
 * standard errors from the covariance (J^T J)^-1 scaled by the residual
 * variance chi2 / (n_points - n_params) (a's error by the delta method from
 * ln a; a fixed p has error 0), chi2 = sum of squared ln-residuals.
 *
 * Window: the points with index_begin <= i < index_end (index_end = 0: to the
 * end) and x_min <= x <= x_max.  Points in the window whose x or y is not
 * finite, whose y <= 0, or (power law) whose x <= 0 are skipped and counted
 * in n_skipped when skip_invalid is non-zero (the default); otherwise the
 * first such point is an error.  TAPER_EINVAL (with a message) for bad
 * arguments or fewer than n_params + 1 usable points or x values that cannot
 * determine the fit; TAPER_ESOLVER if the nonlinear fit does not converge.
 * On failure result->param and param_err are NaN.  GSL's error handler is
 * never reached (inputs are validated first), so nothing prints or aborts.
 */
typedef enum taper_fit_model {
    TAPER_FIT_POWER = 0,
    TAPER_FIT_EXPONENTIAL = 1,
    TAPER_FIT_DIVERGENCE_B = 2,
    TAPER_FIT_DIVERGENCE_C = 3,
    TAPER_FIT_DIVERGENCE_M = 4
} taper_fit_model;

typedef struct taper_fit_spec {
    int model;            /* taper_fit_model                                 */
    double p;             /* exponent of DIVERGENCE_B/_C; NaN: fit it (_C)   */
    size_t index_begin;   /* window in indices [begin, end); end 0: all      */
    size_t index_end;
    double x_min, x_max;  /* window in x (inclusive); -inf, +inf: all        */
    int skip_invalid;     /* 1: skip unusable points; 0: they are an error   */
    size_t max_iter;      /* nonlinear iterations (default 200)              */
    double xtol;          /* step tolerance (default 1e-12)                  */
} taper_fit_spec;

typedef struct taper_fit_result {
    int model;
    size_t n_params;      /* parameters fitted: 2 or 3                       */
    double param[3];      /* (a, b) | (a, b, p) | (a, C, p) | (a, M, f)       */
    double param_err[3];  /* standard errors                                 */
    size_t n_points;      /* points used                                     */
    size_t n_skipped;     /* points in the window skipped as unusable        */
    double chi2;          /* sum of squared residuals of ln y                */
    size_t iterations;    /* nonlinear iterations (0 for linear fits)        */
} taper_fit_result;

/* Defaults for `model`: whole range, p = 3/2 (DIVERGENCE_B), NaN (fit p,
 * DIVERGENCE_C), skip_invalid = 1, max_iter = 200, xtol = 1e-12. */
TAPER_API void taper_fit_spec_init(taper_fit_spec *spec, int model);
/* Fits y[i] against x[i], i < n, per spec (see above). */
TAPER_API int taper_fit(const taper_fit_spec *spec, const double *x, const double *y, size_t n,
                        taper_fit_result *result, taper_error *err);
/* --- end fits --- */

#ifdef __cplusplus
}
#endif

#endif /* TAPER_H */
