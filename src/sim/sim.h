/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sim.h -- the simulation object (struct taper_sim) and the interfaces of
 * the files of src/sim.  Private to src/sim and its unit tests.  Nothing
 * here names an integrator: the integrators are steppers (stepper.h), which
 * only solve.c and the stepper files see.
 *
 * Layering (a file calls only files below it; nothing calls upward):
 *
 *   solve.c        the run: the loop, which asks events.c what happened at
 *                  a root and window.c what the window must do, and applies
 *                  the answers (moving the window, restarting the stepper);
 *                  the statistics and the end of the run, taper_sim_run.
 *     v
 *   steppers.c     the steppers by method (one row each, stepper.h), and
 *                  the steppers: stepper_cvode.c (CVODE's Adams and BDF,
 *                  with stepper_cvode_clock.c: its clock and its roots
 *                  located again on its interpolant; nvector_window.c,
 *                  sundials_compat.c), stepper_rk8.c (GSL's rk8pd).  Each
 *                  integrates equations.c's right-hand side with events.c's
 *                  root functions armed.
 *     v
 *   events.c       pulse events: the root functions, and the recording of
 *                  a root return (observables, rings), which returns a
 *                  taper_root_report.
 *   window.c       the window policy, read-only on the sim: growth
 *                  thresholds, which granule may leave and how
 *                  (taper_departure), whether one must come back.
 *   sample.c       the sampler: the next sample time, the user's call.
 *   budget.c       the energy budget and the balances at the end.
 *   equations.c    the right-hand side and the error weights on the
 *                  state's entries, for every stepper.
 *     v
 *   window_flight.c the window's extent (taper_sim_move_window, the only
 *                  code that moves it) and the granules that leave it into
 *                  flight, free or under drag with the handover of their
 *                  drag loss, and come back.
 *     v
 *   sim.c          the state: allocation (with the bodies of extended.c),
 *                  free, the theory and tolerance scales, the results'
 *                  accessors (state, striker, forces, the closed-form
 *                  flight of a body out of the window), the log.
 *     v
 *   dynamics.c, dynamics_api.c, extended.c, window_storage.c (leaves: they
 *   call nothing else in src/sim).
 *
 * Who writes what after taper_sim_alloc:
 *   sim->pulse               events.c (taper_events_record, _arm)
 *   sim->dyn.lo/hi/v_left    window_flight.c, in taper_sim_move_window only
 *   sim->out, the state's entries of departing and returning granules
 *                            window_flight.c (release / recall)
 *   sim->state, sim->stepper the stepper (its storage; set up by solve.c)
 *   sim->t, t_low, stats     solve.c (the budget's statistics: budget.c)
 *   sim->walls               events.c
 *   sim->samples_taken       sample.c
 */
#ifndef TAPER_SIM_H
#define TAPER_SIM_H

#include "dynamics.h"
#include "extended.h"
#include "settings/specs.h"
#include "window_storage.h"

#include <math.h>

/* The events' rings: the granules whose pass and peak the root functions
 * watch follow the front (taper_pulse.pass_slots, .peak_slots; events.c,
 * which gives the stepper six root functions and one per wall, however
 * many granules the rings hold).  Rings start with TAPER_RING_SLOTS
 * granules each; where every root is armed from the start they grow to
 * cover every window granule whose event is unknown. */
#define TAPER_RING_SLOTS 3

/* A chain this long or longer is a long one: the monitor is asked between
 * the passes of the set-up and before the energy budget walks the whole
 * chain (sim.c, solve.c), as the theory asks it every 65536 granules; a
 * shorter chain's monitor sees the run's events alone. */
#define TAPER_LONG_CHAIN 65536

/* Event bits of a granule: known (timed, or found to have happened before
 * its root function could see it, "untimed": its value stays NaN). */
#define TAPER_EV_PASS 1u
#define TAPER_EV_PEAK 2u

/* The stepper's counters over the whole run (taper.h, TAPER_STAT_STEPS to
 * _ERR_TEST_FAILS: what each counts for each method). */
typedef struct taper_step_counters {
    long steps;
    long rhs_evals;
    long root_evals;
    long jac_evals;
    long nonlin_iters;
    long err_test_fails;
} taper_step_counters;

/* The statistics of a run (taper_sim_statistic reads them by
 * TAPER_STAT_*). */
typedef struct taper_run_statistics {
    taper_step_counters counters;
    long window_changes;
    long restarts;
    size_t max_window;
    size_t granule_reached;
    double t_final;
    double energy_error;
    double momentum_error;
    int complete;
    /* the energy budget at t_final (budget.c) */
    double energy_initial, energy_dissipated, energy_transmitted, energy_reflected,
        energy_in_chain;
    double wall_impulse[TAPER_N_ENDS]; /* NaN: no wall                     */
    double piston_work;     /* W(t_final); NaN: no piston                  */
} taper_run_statistics;

/* The largest force of each wall and its time (events.c; NaN: no wall). */
typedef struct taper_walls {
    double peak_force[TAPER_N_ENDS], peak_time[TAPER_N_ENDS];
} taper_walls;

/* Quadratures (equations.c): the wall impulses and the dissipated energy, the
 * last entries of the whole-chain state, after the 2 bodies entries. */
#define TAPER_QUAD_WALL_LEFT 0
#define TAPER_QUAD_WALL_RIGHT 1
#define TAPER_QUAD_DISSIPATED 2
#define TAPER_N_QUADRATURES 3

/* Pulse-event bookkeeping and the observables (written by events.c). */
typedef struct taper_pulse {
    double *obs[TAPER_N_OBSERVABLES];
    size_t next_pass;       /* lowest granule whose t_pass is unknown       */
    size_t next_peak;       /* lowest granule whose peak is unknown         */
    double v_ref;           /* pulse velocity at the last pass event        */
    double z_ref;           /* compression z_k at the last pass event of k:
                               the pair's largest compression (dz_k/dt =
                               v_k - v_{k+1} = 0 there)                     */
    unsigned char *events;  /* per granule: TAPER_EV_* bits                  */
    size_t untimed_passes, untimed_peaks;
    /* The rings: granules next_pass .. next_pass + pass_slots - 1 and
     * next_peak .. next_peak + peak_slots - 1 are watched (events.c,
     * "the stepper's root functions").  arm_all: every pending event of
     * the window is armed (a root finder that compares signs:
     * taper_events_arm);
     * otherwise fixed rings of TAPER_RING_SLOTS armed near the front. */
    size_t pass_slots, peak_slots;
    int arm_all;
    /* Below n = 2 (with a root finder that compares signs): the pass of k
     * is k+1 overtaking k while k is the fastest of the window's granules
     * up to k (events.c, "leading passes"); the pass ring covers every
     * window granule whose pass is unknown. */
    int lead;
} taper_pulse;

/* Granules that left the window fly freely: x_j(t) = x_free[j] +
 * v_free[j] t.  Under drag (t_free != NULL) they fly as m dv/dt = -drag v
 * has it, from x_free[j] (the position then) at velocity v_free[j] at time
 * t_free[j]: v_j(t) = v_free e^(-s / tau), x_j(t) = x_free + v_free tau
 * (1 - e^(-s / tau)), s = t - t_free, tau = m_j / drag (taper_sim_flight).
 * gap_watch[j]: compression of the gap z_j above which granule j is taken
 * back while it is the last granule out (0: it left in exact free flight,
 * > 0: it left at rest within the tolerance, see window.c). */
typedef struct taper_out {
    double *x_free, *v_free, *gap_watch;
    double *t_free;         /* departure times (drag only, else NULL)       */
    /* Drag only: the dissipation quadrature hands a departed granule's
     * drag loss over to its flight's closed form smoothly, from
     * hand_start[j] (the end of the step it left in) over
     * hand_length[j] (window_flight.c, "handover"); handing: the granules whose
     * handover is under way, n_handing of them (room for handing_size). */
    double *hand_start, *hand_length;
    size_t *handing, n_handing, handing_size;
    double energy_free, momentum_free; /* at departure                      */
    double dissipated_recalled; /* drag's work on granules out of the window
                               that the quadrature does not hold, for those
                               taken back since (taper_sim_dissipated_out)  */
    double quiet_after;     /* drag: from this time on every granule out
                               moves slower than the absorbed pulse's bound
                               (solve.c, absorbed_by_drag)                   */
    long left_resting;      /* granules that left at rest within tolerance  */
} taper_out;

/* The state the stepper integrates: its entries from absolute index
 * taper_dyn_begin (the window's, or the whole chain's from 0), then the
 * quadratures (TAPER_N_QUADRATURES of them with walls or losses).  The
 * stepper keeps it (set up by solve.c): in the window's buffers
 * (window_storage.h) where the run has a window, else in an array of the
 * whole chain's 2 n entries and the quadratures. */
typedef struct taper_state {
    taper_window *window;   /* NULL: the whole chain                        */
    double **buffer;        /* where the storage's pointer is kept: a buffer
                               of the window (its entry 0 at absolute index
                               window->base, moved with the window) or the
                               whole chain's entries; NULL: none yet        */
} taper_state;

/* The run's stepper, opaque below solve.c (stepper.h); release: how sim.c
 * frees it (the stepper's own free, set by solve.c). */
struct taper_stepper;
typedef struct taper_run_stepper {
    struct taper_stepper *memory;
    void (*release)(struct taper_stepper *s);
} taper_run_stepper;

struct taper_sim {
    /* read-only after taper_sim_alloc */
    const taper_chain *chain;
    taper_model model;      /* bodies: the granules and the ends' bodies    */
    size_t n;               /* bodies (N for the paper's chain)             */
    double exponent;        /* n of the contact law                         */
    const double *mass, *contact, *rest; /* the chain's arrays (getters)    */
    taper_solver_spec spec;
    size_t target;          /* body of the last granule requested           */
    size_t pass_limit;      /* last body with a pass time: min(target, N-1) + off */
    double *theory[TAPER_N_THEORY_QUANTITIES]; /* taper_theory_compute's columns */
    /* Absolute-tolerance scale of each granule's velocity and compression:
     * the binary collision values v_k and z_max(k), so that atol is relative
     * to the pulse wherever it is (it decays by 1e-60 over a strongly
     * tapered backward chain). */
    double *v_scale, *z_scale;
    double *grow_z;         /* grow_z[k-1]: z_k above which granule k+1 joins
                               the window (k = hi); window.c's thresholds    */

    taper_dyn dyn;          /* the equations on the window lo..hi           */
    taper_pulse pulse;
    taper_walls walls;
    size_t samples_taken;   /* sampler calls so far (sample.c)              */
    taper_out out;
    taper_state state;
    taper_run_stepper stepper;
    double t;               /* time of the current state, on the stepper's
                               clock                                        */
    double t_low;           /* that clock's low part: the true time is
                               t + t_low (stepper.h, taper_step)            */
    int piston_moving;      /* the piston has not stopped yet (solve.c)     */
    double phase_stop;      /* stop time of the run's phase (solve.c)       */
    double piston_work;     /* W at the stop: the impulse J(duration)       */
    int ran;
    taper_run_statistics stats;
};

/* ---- the state's entries and time ------------------------------------------ */
/* The state's entries from absolute index taper_dyn_begin (taper_state);
 * NULL before the run has made the state. */
static inline double *taper_sim_entries(const taper_sim *sim)
{
    const taper_state *s = &sim->state;
    if (!s->buffer) return NULL;
    return s->window ? taper_window_entries(s->window, *s->buffer) : *s->buffer;
}

/* The quadratures' entries (after the window's; NULL before the run). */
static inline double *taper_sim_quadratures(const taper_sim *sim)
{
    double *y = taper_sim_entries(sim);
    return y ? y + (taper_dyn_end(&sim->dyn) - taper_dyn_begin(&sim->dyn)) : NULL;
}

/* The drag's relaxation time m_j / drag of body j (INFINITY: no drag, or a
 * wall). */
static inline double taper_sim_drag_time(const taper_sim *sim, size_t j)
{
    const double rate = sim->model.drag * sim->dyn.inv_mass[j - 1];
    return rate > 0.0 ? 1.0 / rate : INFINITY;
}

/* The true time of time t on the stepper's clock: t plus the clock's low
 * part as of the last advance (CVODE's rounding drift summed exactly, rk8's
 * compensated sum; stepper.h). */
static inline double taper_sim_true_time(const taper_sim *sim, double t) { return t + sim->t_low; }

/* ---- sim.c: the state and its readers ---------------------------------------- */
/* Hands a message to the caller's taper_log_fn, if any (level 0:
 * information, 1: warning).  Never cut: a long message is formatted into
 * an allocated buffer. */
void taper_sim_log(const taper_sim *sim, int level, const char *fmt, ...) TAPER_PRINTF(3, 4);

/* The state of every body at sim->t (caller-owned arrays of sim->n, either
 * may be NULL): the window, free flight behind it, rest ahead of it. */
void taper_sim_bodies(const taper_sim *sim, double *x, double *v);

/* Position and velocity at time t of body j < lo, out of the window (see
 * taper_out); either pointer may be NULL. */
void taper_sim_flight(const taper_sim *sim, size_t j, double t, double *x, double *v);

/* ---- window_flight.c: the window's extent and the granules out of it ---------- */
/* The one place the window's extent changes: granules lo..hi are
 * integrated, v_left is the frozen velocity of granule lo-1.  Moves the
 * window's range (entries newly covered on the right are zero).  0, or -1
 * when the window cannot grow (nothing changed then). */
int taper_sim_move_window(taper_sim *sim, size_t lo, size_t hi, double v_left);

/* Granule lo leaves the window, flying freely at its velocity from now on;
 * `watch` is the gap compression that takes it back (window.c).  t_step:
 * the stepper's time reached, the end of the step that held the root (>=
 * sim->t), up to which the quadratures hold the granule's drag loss; h_step:
 * that step's size (the handover's time scale).  0, or -1 when out of
 * memory (the granule stays in the window then). */
int taper_sim_release_granule(taper_sim *sim, double watch, int at_rest, double t_step, double h_step);

/* The part of the drag loss of departed granules that the dissipation
 * quadrature still integrates at time t (the handover, window_flight.c):
 * the right-hand side's extra term, 0 without drag. */
double taper_sim_handover_power(const taper_sim *sim, double t);

/* Granule lo-1 returns with its ballistic state (its gap closed).  A
 * multistep history is then wrong for that component: the caller restarts
 * the stepper.  0, or -1 when the window cannot grow. */
int taper_sim_recall_granule(taper_sim *sim);

/* Energy the drag has taken from the bodies while they were out of the
 * window, up to sim->t (0 without drag).  O(N): for the end of the run. */
double taper_sim_dissipated_out(const taper_sim *sim);

/* ---- equations.c: what every stepper integrates -------------------------------- */
/* The right-hand side f = y' and the error weights w on the state's entries
 * (from absolute index taper_dyn_begin; the quadratures after the window's
 * entries). */
void taper_equations_rhs(const taper_sim *sim, double t, const double *y, double *f);
void taper_equations_weights(const taper_sim *sim, const double *y, double *w);

/* ---- sample.c: the sampler ---------------------------------------------------- */
/* The next sample time, INFINITY without a sampler. */
double taper_sample_next(const taper_sim *sim);
/* Calls the sampler at sim->t (the next sample time); non-zero: it asked
 * to stop. */
int taper_sample_call(taper_sim *sim);

/* ---- budget.c: the energy budget and the balances at the end ------------------ */
/* Fills the budget statistics and, for chains with options, the energy and
 * momentum errors from the state at sim->t and the quadratures q (NULL:
 * none). */
void taper_budget_compute(taper_sim *sim, const double *q);
/* The piston's work W(sim->t) from the quadratures q (NaN: no piston). */
double taper_budget_piston_work(const taper_sim *sim, const double *q);

/* ---- events.c: pulse events -------------------------------------------------- */
/* What a root return asks of the window. */
typedef struct taper_root_report {
    int grow;        /* the front reached the growth threshold of hi         */
    int gap_closed;  /* the gap behind the window closed                     */
    int passed;      /* a pass event moved next_pass: the back may leave     */
} taper_root_report;

/* A root function's value for granule k at the state y (events.c). */
typedef double (*taper_root_value)(const taper_sim *sim, const double *y, size_t k);

/* Where an event lies, as the stepper that returned it can say: its
 * refine_root (stepper.h), handed to events.c by the loop so that events.c
 * never sees a stepper.  It returns the zero's time on the stepper's clock
 * and points *y at the state there, or returns sim->t and leaves *y. */
typedef struct taper_root_locator {
    double (*refine)(struct taper_stepper *s, taper_root_value g, size_t k, const double **y);
    struct taper_stepper *stepper;
} taper_root_locator;

/* Chooses how the root functions are armed for the run (pulse.arm_all,
 * pulse.lead), before the stepper first evaluates them:
 * sees_tiny_sign_changes says whether the stepper's root finder sees a
 * sign change between two tiny values whose product underflows. */
void taper_events_arm(taper_sim *sim, int sees_tiny_sign_changes);
/* The root functions' values at the state's entries y (taper_events_slots
 * of them). */
void taper_events_root_values(const taper_sim *sim, const double *y, double *g);
/* Root functions in all: the rings' (four, events.c), grow and gap, and
 * the walls'. */
size_t taper_events_slots(const taper_sim *sim);
/* The slot of the window's growth (its root need not be located: the
 * window grows where the stepper's step ends, solve.c). */
size_t taper_events_grow_slot(const taper_sim *sim);
/* The direction of each slot's crossing (+1: from below, -1: from above),
 * for taper_events_slots(sim) slots. */
void taper_events_directions(const taper_sim *sim, int *directions);
/* Where every root is armed: enlarges the rings to cover every window
 * granule whose event is unknown, after a root return (the stepper then
 * re-evaluates every root function before it looks for the next root, so
 * the functions' granules may change).  1 if the number of root functions
 * changed (the caller arms the stepper's roots again), else 0. */
int taper_events_fit_rings(taper_sim *sim);
/* Records the events of one root return at the current state: roots_found
 * holds each slot's crossing (+1 up, -1 down, 0 none); each event's time
 * and state are those `where` locates. */
taper_root_report taper_events_record(taper_sim *sim, const int *roots_found, taper_root_locator where);
int taper_events_complete(const taper_sim *sim);
/* A right wall's first contact is over: its force has peaked and the
 * contact opened (under a load: fallen below half its rise); 1 without a
 * right wall. */
int taper_events_walls_settled(const taper_sim *sim);
/* At the piston's stop (solve.c, before v_1 is set to 0): the jump of
 * dz_1/dt from v_1 - v_2 to -v_2 is a maximum of the piston's compression
 * and force that no root function sees (the stepper restarts there); the
 * piston's pass, if still unknown, and its force are recorded here. */
void taper_events_piston_stopped(taper_sim *sim);
int taper_events_passes_complete(const taper_sim *sim);

/* ---- window.c: the window policy (decisions only) ---------------------------- */
/* How granule lo may leave the window (criteria 1 and 2 of window.c). */
typedef enum taper_departure_kind {
    TAPER_STAYS = 0,
    TAPER_LEAVES_FREE = 1,    /* exact free flight                            */
    TAPER_LEAVES_AT_REST = 2  /* at rest within the tolerance                 */
} taper_departure_kind;

typedef struct taper_departure {
    taper_departure_kind kind;
    double watch;             /* gap_watch for the granule leaving            */
} taper_departure;

/* What the window must do after a root return, in this order: take granule
 * lo-1 back, grow by granule hi+1, then let granules leave while
 * taper_window_departure says so. */
typedef struct taper_window_plan {
    int take_back;
    int grow;
    int shrink;
} taper_window_plan;

/* grow_z[k-1] for k = 1..N (INFINITY for k = N). */
void taper_window_growth_thresholds(const taper_sim *sim, double *grow_z);
taper_window_plan taper_window_plan_for(const taper_sim *sim, taper_root_report report);
taper_departure taper_window_departure(const taper_sim *sim);

#endif
