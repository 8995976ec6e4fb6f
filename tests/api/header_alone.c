/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * header_alone.c -- taper.h compiles on its own, first and alone, as
 * strict C99 (-std=c99 -Wall -Wextra -pedantic -Werror) and, through
 * header_alone.cpp, as C++.  Uses each public type once so that a
 * declaration the other language rejects cannot hide (in C++ an int is no
 * enum: every enum-typed parameter is passed its enum); links against
 * libtaper.so to prove the C linkage (no C++ name mangling).
 */
#include "taper.h"
#include "taper.h" /* the include guard works */

static int monitor(const taper_progress *progress, void *user)
{
    (void)user;
    return progress->granule > progress->target;
}

static void log_fn(int level, const char *message, void *user)
{
    (void)level, (void)message, (void)user;
}

int main(void)
{
    taper_error err;
    taper_progress progress;
    taper_chain_spec *chain_spec = taper_chain_spec_alloc(&err);
    taper_solver_spec *solver_spec = taper_solver_spec_alloc(&err);
    taper_fit_spec *fit_spec = taper_fit_spec_alloc(TAPER_FIT_POWER, &err);
    taper_fit_result *fit_result = 0;
    taper_chain *chain = 0;
    taper_sim *sim = 0;
    taper_dynamics *dyn = 0;
    taper_monitor_fn monitor_fn = monitor;
    taper_status status = TAPER_OK;
    taper_profile profile = TAPER_BACKWARD_LINEAR;
    taper_method method = TAPER_ADAMS;
    taper_observable observable = TAPER_T_PASS;
    taper_statistic statistic = TAPER_STAT_STEPS;
    taper_theory_quantity quantity = TAPER_THEORY_V;
    taper_law law = TAPER_LAW_V_OF_K;
    taper_fit_model model = TAPER_FIT_POWER;

    progress.granule = 0;
    progress.target = 1;
    if (monitor_fn(&progress, 0)) status = TAPER_EINVAL;
    if (!chain_spec || !solver_spec || !fit_spec) return 1;
    if (taper_chain_spec_set_profile(chain_spec, profile, &err) != TAPER_OK ||
        taper_chain_spec_set_n_granules(chain_spec, 4, &err) != TAPER_OK ||
        taper_chain_spec_set_s(chain_spec, 0.5, &err) != TAPER_OK ||
        taper_solver_spec_set_method(solver_spec, method, &err) != TAPER_OK)
        return 1;
    taper_solver_spec_set_monitor(solver_spec, monitor_fn, 0);
    taper_solver_spec_set_log(solver_spec, log_fn, 0);
    chain = taper_chain_alloc(chain_spec, &err);
    if (!chain) return 1;
    if (taper_chain_size(chain) != 4 || taper_chain_profile(chain) != profile) status = TAPER_EINVAL;
    dyn = taper_dynamics_alloc(chain, &err);
    sim = taper_sim_alloc(chain, solver_spec, &err);
    if (!dyn || !sim || taper_sim_run(sim, &err) != TAPER_OK) status = TAPER_ESOLVER;
    if (!taper_sim_observable(sim, observable) || !taper_sim_theory(sim, quantity) ||
        !(taper_sim_statistic(sim, statistic) > 0) || !taper_statistic_name(statistic) ||
        !taper_method_name(method) || !taper_profile_name(profile) ||
        !taper_fit_model_name(model) || !(taper_asymptotic_exponent(law, 2.5) < 0))
        status = TAPER_EINVAL;
    {
        const double x[3] = {1.0, 2.0, 4.0}, y[3] = {1.0, 0.5, 0.25};
        fit_result = taper_fit(fit_spec, x, y, 3, &err);
        if (!fit_result || taper_fit_result_model(fit_result) != model) status = TAPER_EINVAL;
    }
    taper_fit_result_free(fit_result);
    taper_fit_spec_free(fit_spec);
    taper_sim_free(sim);
    taper_dynamics_free(dyn);
    taper_chain_free(chain);
    taper_solver_spec_free(solver_spec);
    taper_chain_spec_free(chain_spec);
    return status == TAPER_OK && sizeof(err.message) == TAPER_MESSAGE_SIZE ? 0 : 1;
}
