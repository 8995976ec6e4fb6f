/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sundials_compat_arkode.h -- the SUNDIALS-version-specific calls of the
 * ERK peer (peer_arkode.c).  The bench's own glue, self-contained: libtaper
 * keeps its CVODE glue private (src/sim/sundials_compat.c is the library's,
 * not exported), and the bench uses libtaper's public API only.
 */
#ifndef TAPER_PEER_SUNDIALS_COMPAT_ARKODE_H
#define TAPER_PEER_SUNDIALS_COMPAT_ARKODE_H

#include <sundials/sundials_context.h>

/* Where ARKODE's error text goes instead of stderr.  The caller owns the
 * sink and keeps it alive as long as the ERKStep memory. */
typedef struct taper_peer_messages {
    /* ARKODE's message, the function that failed and its flag, as given
     * (the receiver formats them, so nothing is cut on the way) */
    void (*fn)(const char *message, const char *function, int code, void *user);
    void *user;
} taper_peer_messages;

int taper_peer_sundials_context_new(SUNContext *ctx); /* 0 on success */
void taper_peer_sundials_context_free(SUNContext *ctx);
/* ARKODE_SUCCESS or ARKODE's flag. */
int taper_peer_capture_erk_errors(void *erk_mem, taper_peer_messages *sink);

#endif
