/*
 * sundials_compat.c -- SUNDIALS-version-specific calls (see the header).
 *   6.x: SUNContext_Create(void *comm, ...), CVodeSetErrHandlerFn.
 *   7.x: SUNContext_Create(SUN_COMM_NULL, ...), SUNContext_PushErrHandler.
 */
#include "sundials_compat.h"

#include <cvode/cvode.h>
#include <sundials/sundials_version.h>

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
    /* solve.c asks for a bounded number of steps per CVode call, to call the
     * progress monitor in between: "mxstep steps taken" is the normal end of
     * such a call, not something to warn a user about. */
    if (code == CV_TOO_MUCH_WORK) return;
    const taper_solver_messages *sink = data;
    sink->fn(msg, function, code, sink->user);
}

int taper_sundials_capture_errors(void *cvode_mem, taper_solver_messages *sink)
{
    return CVodeSetErrHandlerFn(cvode_mem, forward_error, sink);
}
