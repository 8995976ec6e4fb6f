/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sundials_compat_arkode.c -- every SUNDIALS-version-specific call of the
 * ERK peer of taper-bench (peer_arkode.c), linked only into taper-bench and
 * the peers test, so that libtaper does not depend on libsundials_arkode.
 * Self-contained: src/sim/sundials_compat.c is the library's own glue for
 * CVODE (hidden in libtaper.so), and the bench does not reach into it.
 *   6.x: SUNContext_Create(void *comm, ...), ERKStepSetErrHandlerFn.
 *   7.x: SUNContext_Create(SUN_COMM_NULL, ...), SUNContext_PushErrHandler
 *        on the context instead.
 */
#include "sundials_compat_arkode.h"

#include <arkode/arkode_erkstep.h>
#include <sundials/sundials_version.h>

#if SUNDIALS_VERSION_MAJOR >= 7
#error "taper: port drivers/bench/peers/sundials_compat_arkode.c to SUNDIALS 7 (SUN_COMM_NULL, SUNContext_PushErrHandler)"
#endif

int taper_peer_sundials_context_new(SUNContext *ctx) { return SUNContext_Create(NULL, ctx); }

void taper_peer_sundials_context_free(SUNContext *ctx)
{
    if (ctx && *ctx) SUNContext_Free(ctx);
}

static void forward_error(int code, const char *module, const char *function, char *msg,
                          void *data)
{
    (void)module;
    const taper_peer_messages *sink = data;
    sink->fn(msg, function, code, sink->user);
}

int taper_peer_capture_erk_errors(void *erk_mem, taper_peer_messages *sink)
{
    return ERKStepSetErrHandlerFn(erk_mem, forward_error, sink);
}
