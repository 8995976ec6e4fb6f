/*
 * header_alone.c -- taper.h compiles on its own, first and alone, as
 * strict C99 (-std=c99 -Wall -Wextra -pedantic -Werror) and, through
 * header_alone.cpp, as C++.  Uses each public type once so that a
 * declaration the other language rejects cannot hide; links against
 * libtaper.so to prove the C linkage (no C++ name mangling).
 */
#include "taper.h"
#include "taper.h" /* the include guard works */

int main(void)
{
    taper_chain_spec chain_spec;
    taper_solver_spec solver_spec;
    taper_error err;
    taper_stats stats;
    taper_progress progress;
    taper_fit_spec fit_spec;
    taper_fit_result fit_result;
    taper_chain *chain;
    taper_monitor_fn monitor = 0;
    taper_log_fn log_fn = 0;
    taper_status status = TAPER_OK;
    taper_profile profile = TAPER_BACKWARD_LINEAR;
    taper_method method = TAPER_ADAMS;
    taper_observable observable = TAPER_T_PASS;
    taper_law law = TAPER_LAW_V_OF_K;
    taper_fit_model model = TAPER_FIT_POWER;

    (void)stats, (void)progress, (void)fit_spec, (void)fit_result, (void)model;
    (void)monitor, (void)log_fn, (void)method, (void)observable, (void)law;
    err.status = TAPER_OK;
    err.message[0] = '\0';
    taper_chain_spec_init(&chain_spec);
    taper_solver_spec_init(&solver_spec);
    chain_spec.profile = profile;
    chain_spec.n_granules = 4;
    chain_spec.s = 0.5;
    chain = taper_chain_alloc(&chain_spec, &err);
    if (!chain) return 1;
    if (taper_chain_size(chain) != 4) status = TAPER_EINVAL;
    taper_chain_free(chain);
    return status == TAPER_OK && sizeof(err.message) == TAPER_MESSAGE_SIZE ? 0 : 1;
}
