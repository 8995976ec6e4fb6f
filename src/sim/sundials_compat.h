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

#endif
