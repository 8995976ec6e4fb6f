/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * sundials_compat.h -- the only place that knows which SUNDIALS version we
 * build against.  Debian 12 ships 6.4.1; the 7.x equivalents are noted so a
 * port touches this file only.
 */
#ifndef TAPER_SUNDIALS_COMPAT_H
#define TAPER_SUNDIALS_COMPAT_H

#include <sundials/sundials_context.h>
#include <sundials/sundials_nvector.h>

/* Where CVODE's error text goes instead of stderr.  The caller owns the sink
 * and keeps it alive as long as the CVODE memory.  The message, the CVODE
 * function that raised it and its flag arrive as given: the receiver
 * formats them, so nothing is cut on the way. */
typedef struct taper_solver_messages {
    void (*fn)(const char *message, const char *function, int code, void *user);
    void *user;
} taper_solver_messages;

int taper_sundials_context_new(SUNContext *ctx);          /* 0 on success */
void taper_sundials_context_free(SUNContext *ctx);
int taper_sundials_capture_errors(void *cvode_mem, taper_solver_messages *sink);

/* 1 if CVODE's root finder sees a sign change between two tiny values whose
 * product underflows: SUNDIALS >= 6.5.0, or the bundled 6.4.1 with our
 * backport of that fix (its sundials_math.h defines SUNRdifferentsign).
 * Then every root function may be armed from the start (events.c); 6.4.1
 * without the fix tests glo*ghi < 0 and misses such roots, so roots are
 * armed only near the pulse.  Decided at compile time and confirmed once
 * per process on the library actually loaded (a bundled build's libtaper
 * installed without its rpath loads the system's 6.4.1): one tiny CVODE
 * problem, y' = 1, root of 1e-200 (y - 0.5), about 10 us. */
int taper_sundials_roots_see_tiny_values(void);

#endif
