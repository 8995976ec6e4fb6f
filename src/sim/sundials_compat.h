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
 * and keeps it alive as long as the CVODE memory. */
typedef struct taper_solver_messages {
    void (*fn)(const char *message, void *user);
    void *user;
} taper_solver_messages;

int taper_sundials_context_new(SUNContext *ctx);          /* 0 on success */
void taper_sundials_context_free(SUNContext *ctx);
int taper_sundials_capture_errors(void *cvode_mem, taper_solver_messages *sink);
/* The same for ARKODE's ERKStep memory; in sundials_compat_arkode.c, linked
 * only into taper-bench and the peers test (not into libtaper). */
int taper_sundials_capture_erk_errors(void *erk_mem, taper_solver_messages *sink);
/* Library version as "6.4.1". */
const char *taper_sundials_version(void);

#endif
