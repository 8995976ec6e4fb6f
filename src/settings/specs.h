/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * specs.h -- the layouts behind taper_chain_spec and taper_solver_spec, and
 * what the other parts of the library need of them.  Not installed: callers
 * read and write specs through taper.h, whose setters and getters are
 * driven by the table of settings (table.c).  src/chain builds a chain from
 * a taper_chain_spec, src/sim copies a taper_solver_spec into each sim.
 * Every value is in its range: the setters see to it.
 */
#ifndef TAPER_SETTINGS_SPECS_H
#define TAPER_SETTINGS_SPECS_H

#include "core/taper_internal.h"

/* Settings of a chain.  The options after n_radii are beyond the paper
 * (taper.h, "Beyond the paper"); each default is the paper's idealisation. */
struct taper_chain_spec {
    taper_profile profile;
    size_t n_granules;  /* N                                             */
    double s, q;        /* tapering parameters                            */
    double exponent;    /* contact exponent n                             */
    double *radii;      /* owned copy, n_radii of them; NULL: none        */
    size_t n_radii;
    double *pattern;    /* decorated profile: one period; NULL: none      */
    size_t n_pattern;
    taper_disorder disorder;      /* what the disorder multiplies         */
    double disorder_amplitude;    /* 0 <= a < 1; 0: none                  */
    uint64_t disorder_seed;
    double *density;    /* mixed chains, relative to granule 1's          */
    size_t n_density;   /* (divided by the first entry); NULL: one        */
    double *compliance; /* material                                       */
    size_t n_compliance;
    taper_boundary end[TAPER_N_ENDS];
    double end_compliance[TAPER_N_ENDS]; /* of a wall, relative to c_1    */
    double striker_radius;        /* 0: no striker, the impulse v_1 = 1   */
    double striker_density, striker_compliance;
    double load;        /* static force F0                                */
    double damping;     /* Kuwabara-Kono time                             */
    double drag;        /* hydrodynamic friction coefficient              */
    double piston_duration;   /* 0: no piston; INFINITY: a steady push    */
    double piston_compliance; /* of the piston's face, relative to c_1    */
};

/* How a chain is integrated.  taper_sim_alloc copies it and checks what
 * depends on the chain. */
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
    double sample_interval; /* > 0 with sample_fn, unless sample_times         */
    const double *sample_times; /* the caller's: times of the samples instead
                               of j * interval (NULL: the grid)              */
    size_t n_sample_times;
    taper_sample_fn sample_fn; /* NULL: no sampler                            */
    void *sample_data;
    taper_monitor_fn monitor;
    void *monitor_data;
    taper_log_fn log;
    void *log_data;
};

/* Fills *spec with the defaults of taper_*_spec_alloc (the table's). */
void taper_chain_spec_defaults(struct taper_chain_spec *spec);
void taper_solver_spec_defaults(struct taper_solver_spec *spec);

/* The highest order CVODE allows for `method`. */
int taper_method_max_order(taper_method method);

#endif
