/*
 * sundials_compat_arkode.c -- the ARKODE part of sundials_compat.c, compiled
 * only into the ERK peer of taper-bench (drivers/bench/peers/peer_arkode.c), so that libtaper
 * does not depend on libsundials_arkode.
 *   6.x: ERKStepSetErrHandlerFn.
 *   7.x: SUNContext_PushErrHandler on the context instead.
 */
#include "sim/sundials_compat.h"

#include <arkode/arkode_erkstep.h>
#include <sundials/sundials_version.h>

#include <stdio.h>

#if SUNDIALS_VERSION_MAJOR >= 7
#error "taper: port drivers/bench/peers/sundials_compat_arkode.c to SUNDIALS 7 (SUNContext_PushErrHandler)"
#endif

static void forward_error(int code, const char *module, const char *function, char *msg,
                          void *data)
{
    (void)module;
    const taper_solver_messages *sink = data;
    char text[400];
    snprintf(text, sizeof text, "%s (ARKODE %s, flag %d)", msg, function, code);
    sink->fn(text, sink->user);
}

int taper_sundials_capture_erk_errors(void *erk_mem, taper_solver_messages *sink)
{
    return ERKStepSetErrHandlerFn(erk_mem, forward_error, sink);
}
