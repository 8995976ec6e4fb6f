/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * peer_arkode.c -- the ARKODE ERKStep baseline of peers.h: an explicit
 * Runge-Kutta table of ARKODE (Verner 6(5), Fehlberg 8(7) or Dormand-Prince
 * 5(4); ARKODE names a table NAME_stages_embedding_order) on the
 * whole chain, events located by ARKODE's own root finder.
 *
 * The state is taper_dynamics' whole-chain state (v_k, z_k interleaved) in
 * a serial N_Vector, the RHS is taper_dynamics_rhs itself, error control
 * ERKStepSStolerances(rtol, atol) (WRMS norm, unlike rk8pd's max norm).
 * Root functions as taper_sim's (src/sim/events.c): a ring of
 * TAPER_PEER_SLOTS pass slots g = v_{k+1} - v_k (direction +1) and as many
 * peak slots g = taper_dynamics_peak_function (direction -1) that follow
 * the lowest unknown pass and peak.  A slot is armed only while its granule
 * moves (peer_common.c), otherwise it returns -1 (pass) or +1 (peak):
 * SUNDIALS 6.4.1 tests sign changes with glo*ghi < 0, which underflows on
 * precursor values ~1e-300.  ARKODE locates the roots on its dense output
 * (Hermite, default degree), so t_pass and v_peak carry the interpolant's
 * error as well as the step's.
 *
 * Every SUNDIALS-version-specific call is in sundials_compat_arkode.c
 * (context, error handler); the ERKStep calls used here exist unchanged in
 * SUNDIALS 6 and 7.
 */
#include "peers.h"
#include "sundials_compat_arkode.h"

#include <arkode/arkode_erkstep.h>
#include <nvector/nvector_serial.h>

#include <math.h>
#include <string.h>

#define RING TAPER_PEER_SLOTS
#define N_ROOTS (2 * RING)

typedef struct erk_ctx {
    taper_dynamics *dyn;
    taper_peer_events ev;
    long rhs_evals;
    char message[TAPER_MESSAGE_SIZE]; /* ARKODE's last error ("..." if cut) */
} erk_ctx;

static int rhs(sunrealtype t, N_Vector y, N_Vector ydot, void *user)
{
    (void)t;
    erk_ctx *c = user;
    c->rhs_evals++;
    taper_dynamics_rhs(c->dyn, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
    return 0;
}

/* Granule followed by ring slot `slot` when `first` is the lowest unknown
 * (as events.c: a granule keeps its slot while the ring advances). */
static size_t slot_granule(size_t first, size_t slot)
{
    size_t first_slot = (first - 1) % RING;
    return first + (slot + RING - first_slot) % RING;
}

static double pass_g(const erk_ctx *c, const double *y, size_t k)
{
    const taper_peer_events *ev = &c->ev;
    if (k > ev->pass_limit || !isnan(ev->r->t_pass[k - 1])) return -1.0;
    double v = taper_peer_v(y, k);
    if (!taper_peer_pass_armed(ev, k, v)) return -1.0;
    return taper_peer_v(y, k + 1) - v;
}

static double peak_g(const erk_ctx *c, const double *y, size_t k)
{
    const taper_peer_events *ev = &c->ev;
    if (k > ev->n || !isnan(ev->r->t_peak[k - 1])) return 1.0;
    if (!taper_peer_peak_armed(ev, taper_peer_v(y, k))) return 1.0;
    return taper_dynamics_peak_function(c->dyn, y, k);
}

static int roots(sunrealtype t, N_Vector yv, sunrealtype *g, void *user)
{
    (void)t;
    const erk_ctx *c = user;
    const double *y = N_VGetArrayPointer(yv);
    for (size_t i = 0; i < RING; i++) {
        g[i] = pass_g(c, y, slot_granule(c->ev.next_pass, i));
        g[RING + i] = peak_g(c, y, slot_granule(c->ev.next_peak, i));
    }
    return 0;
}

/* Events found at a root return, granules in increasing order, mapped with
 * the ring as it was when ARKODE evaluated the slots. */
static void record(erk_ctx *c, const int *found, double t, const double *y)
{
    taper_peer_events *ev = &c->ev;
    size_t first = ev->next_pass;
    for (size_t k = first; k < first + RING && k <= ev->pass_limit; k++)
        if (found[(k - 1) % RING] > 0 && isnan(ev->r->t_pass[k - 1]))
            taper_peer_record_pass(ev, k, t, taper_peer_v(y, k + 1));
    first = ev->next_peak;
    for (size_t k = first; k < first + RING && k <= ev->n; k++)
        if (found[RING + (k - 1) % RING] < 0 && isnan(ev->r->t_peak[k - 1]))
            taper_peer_record_peak(ev, k, t, taper_peer_v(y, k));
}

static void keep_message(const char *message, const char *function, int code, void *user)
{
    erk_ctx *c = user;
    taper_peer_format(c->message, sizeof c->message, "%s (ARKODE %s, flag %d)", message, function,
                      code);
}

taper_status taper_peer_arkode(const taper_chain *chain, taper_peer_erk_table table,
                               double rtol, double atol, long max_steps, taper_peer_result *r,
                               taper_error *err)
{
    if (!chain || !r) return taper_peer_fail(err, TAPER_EINVAL, "taper_peer_arkode: NULL argument");
    if (!(rtol > 0.0 && rtol < 1.0) || !(atol > 0.0 && atol < 1.0))
        return taper_peer_fail(err, TAPER_EINVAL, "arkode: rtol = %g, atol = %g must lie in (0, 1)", rtol,
                          atol);
    ARKODE_ERKTableID id;
    switch (table) {
    case TAPER_PEER_ERK_VERNER6: id = ARKODE_VERNER_8_5_6; break;
    case TAPER_PEER_ERK_FEHLBERG8: id = ARKODE_FEHLBERG_13_7_8; break;
    case TAPER_PEER_ERK_DP5: id = ARKODE_DORMAND_PRINCE_7_4_5; break;
    default: return taper_peer_fail(err, TAPER_EINVAL, "arkode: unknown table %d", (int)table);
    }
    size_t n = taper_chain_size(chain);
    erk_ctx c;
    memset(&c, 0, sizeof c);
    if (taper_peer_result_init(r, n) != 0) return taper_peer_fail(err, TAPER_ENOMEM, "arkode: out of memory");
    SUNContext ctx = NULL;
    N_Vector y = NULL;
    void *mem = NULL;
    taper_peer_messages sink = {keep_message, &c};
    taper_status status = TAPER_OK;
    if (!(c.dyn = taper_dynamics_alloc(chain, NULL)) ||
        taper_peer_sundials_context_new(&ctx) != 0 ||
        !(y = N_VNew_Serial((sunindextype)(2 * n), ctx))) {
        status = taper_peer_fail(err, TAPER_ENOMEM, "arkode: out of memory");
        goto done;
    }
    taper_peer_events_init(&c.ev, r);
    N_VConst(0.0, y);
    double *yd = N_VGetArrayPointer(y);
    yd[0] = 1.0; /* the impulse */
    double e0, p0, e1, p1;
    taper_dynamics_energy_momentum(c.dyn, yd, &e0, &p0);

    int directions[N_ROOTS];
    for (size_t i = 0; i < RING; i++) directions[i] = 1, directions[RING + i] = -1;
    mem = ERKStepCreate(rhs, 0.0, y, ctx);
    if (!mem || taper_peer_capture_erk_errors(mem, &sink) != ARK_SUCCESS ||
        ERKStepSetTableNum(mem, id) != ARK_SUCCESS ||
        ERKStepSStolerances(mem, rtol, atol) != ARK_SUCCESS ||
        /* ARKODE's own first-step estimate sees f'' = 0 at the impulse and
         * jumps to ~1e133; the first step of rk8pd instead */
        ERKStepSetInitStep(mem, 1e-4) != ARK_SUCCESS ||
        ERKStepSetUserData(mem, &c) != ARK_SUCCESS ||
        ERKStepRootInit(mem, N_ROOTS, roots) != ARK_SUCCESS ||
        ERKStepSetRootDirection(mem, directions) != ARK_SUCCESS) {
        status = taper_peer_fail(err, TAPER_ESOLVER, "arkode: set-up failed: %s",
                            c.message[0] ? c.message : "out of memory");
        goto done;
    }
    double t = 0.0;
    int stop_set = 0;
    long steps = 0;
    while (!taper_peer_events_done(&c.ev, t)) {
        if (max_steps > 0 && steps >= max_steps) {
            status = taper_peer_fail(err, TAPER_ELIMIT, "arkode: max_steps reached at t = %g", t);
            break;
        }
        if (!stop_set && isfinite(c.ev.t_end)) {
            /* passes complete: stop exactly at the grace end (solve.c's rule) */
            if (ERKStepSetStopTime(mem, c.ev.t_end) != ARK_SUCCESS) {
                status = taper_peer_fail(err, TAPER_ESOLVER, "arkode: %s", c.message);
                break;
            }
            stop_set = 1;
        }
        sunrealtype tret;
        int flag = ERKStepEvolve(mem, isfinite(c.ev.t_end) ? c.ev.t_end : 1e300, y, &tret, ARK_ONE_STEP);
        if (flag < 0) {
            status = taper_peer_fail(err, TAPER_ESOLVER, "arkode: flag %d at t = %g: %s", flag, t, c.message);
            break;
        }
        t = tret;
        if (flag == ARK_ROOT_RETURN) {
            int found[N_ROOTS];
            ERKStepGetRootInfo(mem, found);
            record(&c, found, t, yd);
        }
        ERKStepGetNumSteps(mem, &steps);
    }
    long fails = 0, gevals = 0;
    ERKStepGetNumSteps(mem, &steps);
    ERKStepGetNumErrTestFails(mem, &fails);
    ERKStepGetNumGEvals(mem, &gevals);
    r->steps = steps;
    r->failed_steps = fails;
    r->rhs_evals = c.rhs_evals;
    r->event_evals = gevals;
    r->t_final = t;
    taper_dynamics_energy_momentum(c.dyn, yd, &e1, &p1);
    r->energy_drift = fabs(e1 - e0) / e0;
    r->complete = c.ev.next_pass > c.ev.pass_limit;
done:
    if (mem) ERKStepFree(&mem);
    if (y) N_VDestroy(y);
    taper_peer_sundials_context_free(&ctx);
    taper_dynamics_free(c.dyn);
    if (status != TAPER_OK && status != TAPER_ELIMIT) taper_peer_result_free(r);
    if (status == TAPER_OK) taper_peer_ok(err);
    return status;
}
