/*
 * solver_spec.h -- the layout behind taper_solver_spec.  Private to
 * src/sim: callers read and write it through the setters of taper.h.
 */
#ifndef TAPER_SOLVER_SPEC_H
#define TAPER_SOLVER_SPEC_H

#include "core/taper_internal.h"

/* How a chain is integrated; every value in its range (the setters see to
 * it).  taper_sim_alloc copies it and checks what depends on the chain. */
struct taper_solver_spec {
    taper_method method;
    double rtol;            /* relative tolerance                              */
    double atol;            /* in units of each granule's binary-collision
                               scale (taper.h)                                 */
    size_t last_granule;    /* 0: the whole chain                              */
    int window;             /* 1: the active window, 0: the whole chain        */
    int max_order;          /* 0: the measured default of the method           */
    double t_max;           /* 0: no limit                                     */
    long max_steps;         /* 0: no limit                                     */
    double t_end;           /* 0: end once the observables are known           */
    double sample_interval; /* > 0 with sample_fn                              */
    taper_sample_fn sample_fn; /* NULL: no sampler                            */
    void *sample_data;
    taper_monitor_fn monitor;
    void *monitor_data;
    taper_log_fn log;
    void *log_data;
};

/* Fills *spec with the defaults of taper_solver_spec_alloc. */
void taper_solver_spec_defaults(struct taper_solver_spec *spec);

/* The highest order CVODE allows for `method`. */
int taper_method_max_order(taper_method method);

#endif
