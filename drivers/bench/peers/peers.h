/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * peers.h -- baseline integrators for taper-bench (not part of libtaper).
 *
 * They use libtaper's public API only (taper.h): the chain's getters, and
 * taper_dynamics for the whole-chain right-hand side, energy and peak
 * function, so that they integrate exactly the equations taper_sim does.
 *
 * Three honest peers that measure the same observables as taper_sim_run
 * (t_pass and v_peak per granule, the energy drift) on the whole chain:
 *
 *  - taper_peer_verlet: textbook velocity Verlet in displacements x_k with a
 *    fixed step dt, what most granular-chain papers use.  Pass times by
 *    linear interpolation of v_{k+1} - v_k between steps; the peak time by
 *    linear interpolation of the acceleration a_k and the peak value from
 *    the parabola v(t) that this linear a(t) integrates to.
 *  - taper_peer_arkode: an ARKODE ERKStep explicit Runge-Kutta table
 *    (Verner 6(5), Fehlberg 8(7) or Dormand-Prince 5(4); ARKODE's names are
 *    NAME_stages_embedding_order), adaptive, WRMS error control (rtol,
 *    atol), on taper_dynamics_rhs; events by ARKODE's root finder on its
 *    dense output, a ring of TAPER_PEER_SLOTS pass and peak slots as in
 *    taper_sim (src/sim/events.c).  Not in libtaper (which does not link
 *    ARKODE): link taper_peer_arkode_dep.
 *  - taper_peer_rk8pd: GSL odeiv2 rk8pd (Prince-Dormand 8(7)), adaptive,
 *    control_y_new(atol, rtol) (max norm), on taper_dynamics_rhs (state:
 *    v_k at 2(k-1), z_k at 2(k-1)+1).  rk8pd has no dense output, so events
 *    are located by sign changes of taper_sim's root functions between
 *    accepted steps, then refined by the Illinois method on the step size
 *    theta: g(theta) is evaluated on one fresh rk8pd step of size theta from
 *    the start of the accepted step (order-8 accurate, costs 12 RHS
 *    evaluations per evaluation of g, counted in rhs_evals).
 *
 * Event arming is taper_sim's: pass(k) is looked for only while k is the
 * next granule to be passed or v_k > 1e-6 v_ref, peak(k) only while
 * v_k > 1e-6 v_ref; a ring of TAPER_PEER_SLOTS granules follows the front.
 * A run ends when every pass time and peak is known, or (missing peaks)
 * 20 residence times after the last pass, as taper_sim's does.
 */
#ifndef TAPER_PEERS_H
#define TAPER_PEERS_H

#include "taper.h"

#include <stddef.h>

#define TAPER_PEER_SLOTS 4

typedef struct taper_peer_result {
    size_t n;
    double *t_pass;      /* length N, NaN where unknown ([N-1] always NaN) */
    double *v_peak;      /* length N, v_peak[0] = 1 (the impulse)          */
    double *t_peak;
    long steps;          /* accepted steps                                 */
    long failed_steps;   /* rejected steps (rk8pd)                         */
    long rhs_evals;      /* full-chain force evaluations                   */
    long event_evals;    /* evaluations of the state for event location    */
    double t_final;
    double energy_drift; /* |E(t_final) - E(0)| / E(0)                     */
    int complete;        /* every pass time known                          */
} taper_peer_result;

/* Records a failure in err (if non-NULL) as libtaper does: status, field
 * NULL, the formatted message, ending in "..." when cut at the buffer's
 * end; returns status. */
#if defined(__GNUC__) || defined(__clang__)
__attribute__((format(printf, 3, 4)))
#endif
taper_status taper_peer_fail(taper_error *err, taper_status status, const char *fmt, ...);
/* snprintf into buf[size] (size >= 4) that ends a cut text in "...". */
#if defined(__GNUC__) || defined(__clang__)
__attribute__((format(printf, 3, 4)))
#endif
void taper_peer_format(char *buf, size_t size, const char *fmt, ...);
/* Clears err to TAPER_OK, field NULL, empty message; returns TAPER_OK. */
taper_status taper_peer_ok(taper_error *err);

/* Velocity v_k of the whole-chain state y (1 <= k <= N). */
static inline double taper_peer_v(const double *y, size_t k) { return y[2 * (k - 1)]; }

/* Allocates the arrays for a chain of n granules (NaN-filled); 0 or -1. */
int taper_peer_result_init(taper_peer_result *r, size_t n);
void taper_peer_result_free(taper_peer_result *r);

/* Fixed step dt > 0.  max_steps > 0 stops the run early (complete = 0).
 * Returns TAPER_OK, TAPER_EINVAL, TAPER_ENOMEM or TAPER_ELIMIT. */
taper_status taper_peer_verlet(const taper_chain *chain, double dt, long max_steps,
                               taper_peer_result *r, taper_error *err);

/* Adaptive rk8pd with tolerances rtol, atol.  Returns TAPER_OK, TAPER_EINVAL,
 * TAPER_ENOMEM, TAPER_ESOLVER (GSL failed) or TAPER_ELIMIT. */
taper_status taper_peer_rk8pd(const taper_chain *chain, double rtol, double atol,
                              long max_steps, taper_peer_result *r, taper_error *err);

/* Adaptive ARKODE ERKStep with the given table, tolerances rtol, atol.
 * Returns TAPER_OK, TAPER_EINVAL, TAPER_ENOMEM, TAPER_ESOLVER (ARKODE failed)
 * or TAPER_ELIMIT. */
typedef enum taper_peer_erk_table {
    TAPER_PEER_ERK_VERNER6,   /* ARKODE_VERNER_8_5_6: order 6(5), 8 stages    */
    TAPER_PEER_ERK_FEHLBERG8, /* ARKODE_FEHLBERG_13_7_8: order 8(7), 13 stages */
    TAPER_PEER_ERK_DP5        /* ARKODE_DORMAND_PRINCE_7_4_5: 5(4), 7 stages   */
} taper_peer_erk_table;
taper_status taper_peer_arkode(const taper_chain *chain, taper_peer_erk_table table,
                               double rtol, double atol, long max_steps, taper_peer_result *r,
                               taper_error *err);

/* ---- shared event bookkeeping (peer_common.c) ---- */
typedef struct taper_peer_events {
    taper_peer_result *r;
    size_t n, pass_limit;    /* pass times for k = 1..N-1             */
    size_t next_pass, next_peak;
    double v_ref;            /* pulse velocity at the last pass         */
    double t_end;            /* grace end once passes are complete      */
} taper_peer_events;

void taper_peer_events_init(taper_peer_events *ev, taper_peer_result *r);
int taper_peer_pass_armed(const taper_peer_events *ev, size_t k, double v_k);
int taper_peer_peak_armed(const taper_peer_events *ev, double v_k);
void taper_peer_record_pass(taper_peer_events *ev, size_t k, double t, double v_next);
void taper_peer_record_peak(taper_peer_events *ev, size_t k, double t, double v);
/* 1 when the run may stop at time t. */
int taper_peer_events_done(const taper_peer_events *ev, double t);

#endif
