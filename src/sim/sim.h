/*
 * sim.h -- the simulation object shared by solve.c (CVODE set-up and the
 * run loop), events.c (root functions: pulse events and window edges) and
 * window.c (moving the active window).
 */
#ifndef TAPER_SIM_H
#define TAPER_SIM_H

#include "dynamics.h"
#include "nvector_window.h"
#include "sundials_compat.h"
#include "core/taper_internal.h"

#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nonlinearsolver.h>

/* Root-function slots: a ring of pass slots and of peak slots that follow
 * the front, one slot for growing the window, one for the gap behind it. */
#define TAPER_PASS_SLOTS 3
#define TAPER_PEAK_SLOTS 3
#define TAPER_SLOT_GROW (TAPER_PASS_SLOTS + TAPER_PEAK_SLOTS)
#define TAPER_SLOT_GAP (TAPER_SLOT_GROW + 1)
#define TAPER_N_SLOTS (TAPER_SLOT_GAP + 1)

struct taper_sim {
    const taper_chain *chain;
    taper_solver_spec spec;
    taper_dyn dyn;
    size_t target;          /* last granule requested                       */
    size_t pass_limit;      /* last granule with a pass time: min(target, N-1) */
    double *obs[TAPER_N_OBSERVABLES];

    /* pulse-event bookkeeping */
    size_t next_pass;       /* lowest granule whose t_pass is unknown       */
    size_t next_peak;       /* lowest granule whose peak is unknown         */
    double v_ref;           /* pulse velocity at the last pass event        */
    double z_ref;           /* compression z_k at the last pass event of k:
                               the pair's largest compression (dz_k/dt =
                               v_k - v_{k+1} = 0 there)                     */
    double *grow_z;         /* grow_z[k-1]: z_k above which granule k+1 joins
                               the window (k = hi)                           */
    unsigned char *events;  /* per granule: TAPER_EV_* bits                  */
    size_t untimed_passes, untimed_peaks;

    /* granules that left the window: x_j(t) = x_free[j] + v_free[j] t;
     * gap_watch[j]: compression of the gap z_j above which granule j is taken
     * back while it is the last granule out (0: it left in exact free flight,
     * > 0: it left at rest within the tolerance, see window.c) */
    double *x_free, *v_free, *gap_watch;
    double energy_free, momentum_free;

    /* Absolute-tolerance scale of each granule's velocity and compression:
     * the binary collision values v_k and z_max(k), so that atol is relative
     * to the pulse wherever it is (it decays by 1e-60 over a strongly
     * tapered backward chain). */
    double *v_scale, *z_scale;

    /* CVODE */
    SUNContext ctx;
    void *cvode;
    N_Vector y;
    taper_window *window;   /* NULL: plain serial vector, whole chain       */
    SUNMatrix band;
    SUNLinearSolver linear;
    SUNNonlinearSolver nonlinear;
    taper_solver_messages messages;
    char solver_message[400];

    double t;               /* time of the current state                    */
    int ran;
    int stop_reason;        /* status the run ends with                     */
    taper_stats stats;
    long counters_before_restart[6]; /* CVODE counters reset by CVodeReInit */
    long left_resting;      /* granules that left at rest within tolerance  */
};

/* Event bits of a granule: known (timed, or found to have happened before
 * its root function could see it, "untimed": its value stays NaN). */
#define TAPER_EV_PASS 1u
#define TAPER_EV_PEAK 2u

/* Pointer to the entry at absolute index taper_dyn_begin() of a state vector. */
double *taper_sim_data(const taper_sim *sim, N_Vector v);

/* events.c */
int taper_events_root_function(double t, N_Vector y, double *g, void *user);
void taper_events_directions(int *directions);
/* Records the events of one CVODE root return; sets *window_event when the
 * window must grow (1) or take back the granule behind it (-1). */
void taper_events_record(taper_sim *sim, const int *roots_found, int *grow, int *gap_closed);
int taper_events_complete(const taper_sim *sim);
int taper_events_passes_complete(const taper_sim *sim);

/* solve.c: hand a message to the caller's taper_log_fn, if any
 * (level 0: information, 1: warning). */
void taper_sim_log(const taper_sim *sim, int level, const char *fmt, ...) TAPER_PRINTF(3, 4);

/* solve.c: re-initialise CVODE at the current state (counters are kept). */
int taper_solver_restart(taper_sim *sim, taper_error *err);

/* window.c */
int taper_window_grow(taper_sim *sim, taper_error *err);
int taper_window_take_back(taper_sim *sim, taper_error *err);
int taper_window_shrink(taper_sim *sim, taper_error *err);

#endif
