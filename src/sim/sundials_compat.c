/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sundials_compat.c -- SUNDIALS-version-specific calls (see the header).
 *   6.x: SUNContext_Create(void *comm, ...), CVodeSetErrHandlerFn.
 *   7.x: SUNContext_Create(SUN_COMM_NULL, ...), SUNContext_PushErrHandler.
 */
#include "sundials_compat.h"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>
#include <sundials/sundials_math.h>
#include <sundials/sundials_version.h>

#include <math.h>
#include <stdatomic.h>

#if SUNDIALS_VERSION_MAJOR >= 7
#error "taper: port src/sim/sundials_compat.c to SUNDIALS 7 (SUN_COMM_NULL, SUNContext_PushErrHandler)"
#endif

int taper_sundials_context_new(SUNContext *ctx) { return SUNContext_Create(NULL, ctx); }

void taper_sundials_context_free(SUNContext *ctx)
{
    if (ctx && *ctx) SUNContext_Free(ctx);
}

static void forward_error(int code, const char *module, const char *function, char *msg,
                          void *data)
{
    (void)module;
    /* The CVODE stepper asks for a bounded number of steps per CVode call,
     * to call the progress monitor in between: "mxstep steps taken" is the
     * normal end of such a call, not something to warn a user about. */
    if (code == CV_TOO_MUCH_WORK) return;
    const taper_solver_messages *sink = data;
    sink->fn(msg, function, code, sink->user);
}

int taper_sundials_capture_errors(void *cvode_mem, taper_solver_messages *sink)
{
    return CVodeSetErrHandlerFn(cvode_mem, forward_error, sink);
}

/* ---- root finding on tiny values ---------------------------------------- */
#if defined(SUNRdifferentsign) || SUNDIALS_VERSION_MAJOR > 6 ||                                   \
    (SUNDIALS_VERSION_MAJOR == 6 && SUNDIALS_VERSION_MINOR >= 5)
#define TAPER_ROOTS_SEE_TINY_VALUES 1
#else
#define TAPER_ROOTS_SEE_TINY_VALUES 0
#endif

#if TAPER_ROOTS_SEE_TINY_VALUES
static int unit_rate(double t, N_Vector y, N_Vector ydot, void *user)
{
    (void)t, (void)y, (void)user;
    N_VConst(1.0, ydot);
    return 0;
}

/* 1e-200 (y - 0.5): -5e-201 at t = 0, +5e-201 at t = 1, whose product
 * underflows to -0. */
static int tiny_root(double t, N_Vector y, double *g, void *user)
{
    (void)t, (void)user;
    g[0] = 1e-200 * (N_VGetArrayPointer(y)[0] - 0.5);
    return 0;
}

static void silent(int code, const char *module, const char *function, char *msg, void *data)
{
    (void)code, (void)module, (void)function, (void)msg, (void)data;
}

/* Whether the loaded CVODE finds the root at t = 0.5 (a root finder that
 * multiplies runs to t = 1 without seeing it). */
static int probe_tiny_root(void)
{
    SUNContext ctx = NULL;
    if (taper_sundials_context_new(&ctx) != 0) return 0;
    int found = 0;
    N_Vector y = N_VNew_Serial(1, ctx);
    SUNNonlinearSolver fixed_point = y ? SUNNonlinSol_FixedPoint(y, 0, ctx) : NULL;
    void *mem = fixed_point ? CVodeCreate(CV_ADAMS, ctx) : NULL;
    if (mem) {
        N_VConst(0.0, y);
        double t = 0.0;
        if (CVodeSetErrHandlerFn(mem, silent, NULL) == CV_SUCCESS &&
            CVodeInit(mem, unit_rate, 0.0, y) == CV_SUCCESS && CVodeSStolerances(mem, 1e-8, 1e-8) == CV_SUCCESS &&
            CVodeSetNonlinearSolver(mem, fixed_point) == CV_SUCCESS &&
            CVodeRootInit(mem, 1, tiny_root) == CV_SUCCESS &&
            CVode(mem, 1.0, y, &t, CV_NORMAL) == CV_ROOT_RETURN)
            found = fabs(t - 0.5) < 1e-6;
        CVodeFree(&mem);
    }
    if (fixed_point) SUNNonlinSolFree(fixed_point);
    if (y) N_VDestroy(y);
    taper_sundials_context_free(&ctx);
    return found;
}
#endif

int taper_sundials_roots_see_tiny_values(void)
{
#if TAPER_ROOTS_SEE_TINY_VALUES
    /* 0: not probed yet, 1: yes, 2: no.  Two threads may both probe: they
     * find the same answer. */
    static atomic_int probed = 0;
    int answer = atomic_load(&probed);
    if (!answer) {
        answer = probe_tiny_root() ? 1 : 2;
        atomic_store(&probed, answer);
    }
    return answer == 1;
#else
    return 0;
#endif
}
