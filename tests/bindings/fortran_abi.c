/*
 * fortran_abi.c -- the C side of test_fortran_abi.f90: sizes and field
 * offsets of the structs of taper.h, which the bind(C) derived types of
 * share/fortran/taper.f90 must reproduce exactly.
 */
#include "taper.h"

#include <stddef.h>

#define N_FIELDS 16

/* layout[type][0] = sizeof, layout[type][1 + i] = offset of field i. */
static const size_t layout[][N_FIELDS] = {
    {sizeof(taper_error), offsetof(taper_error, status), offsetof(taper_error, message)},
    {sizeof(taper_chain_spec), offsetof(taper_chain_spec, profile),
     offsetof(taper_chain_spec, n_granules), offsetof(taper_chain_spec, s),
     offsetof(taper_chain_spec, q), offsetof(taper_chain_spec, exponent),
     offsetof(taper_chain_spec, radii)},
    {sizeof(taper_solver_spec), offsetof(taper_solver_spec, method),
     offsetof(taper_solver_spec, rtol), offsetof(taper_solver_spec, atol),
     offsetof(taper_solver_spec, last_granule), offsetof(taper_solver_spec, window),
     offsetof(taper_solver_spec, max_order), offsetof(taper_solver_spec, t_max),
     offsetof(taper_solver_spec, max_steps), offsetof(taper_solver_spec, monitor),
     offsetof(taper_solver_spec, monitor_data), offsetof(taper_solver_spec, log),
     offsetof(taper_solver_spec, log_data)},
    {sizeof(taper_stats), offsetof(taper_stats, steps), offsetof(taper_stats, rhs_evals),
     offsetof(taper_stats, root_evals), offsetof(taper_stats, jac_evals),
     offsetof(taper_stats, nonlin_iters), offsetof(taper_stats, err_test_fails),
     offsetof(taper_stats, window_changes), offsetof(taper_stats, restarts),
     offsetof(taper_stats, max_window), offsetof(taper_stats, granule_reached),
     offsetof(taper_stats, t_final), offsetof(taper_stats, energy_error),
     offsetof(taper_stats, momentum_error), offsetof(taper_stats, complete)},
    {sizeof(taper_progress), offsetof(taper_progress, granule), offsetof(taper_progress, target),
     offsetof(taper_progress, t), offsetof(taper_progress, steps),
     offsetof(taper_progress, window_lo), offsetof(taper_progress, window_hi)},
    {sizeof(taper_fit_spec), offsetof(taper_fit_spec, model), offsetof(taper_fit_spec, p),
     offsetof(taper_fit_spec, index_begin), offsetof(taper_fit_spec, index_end),
     offsetof(taper_fit_spec, x_min), offsetof(taper_fit_spec, x_max),
     offsetof(taper_fit_spec, skip_invalid), offsetof(taper_fit_spec, max_iter),
     offsetof(taper_fit_spec, xtol)},
    {sizeof(taper_fit_result), offsetof(taper_fit_result, model),
     offsetof(taper_fit_result, n_params), offsetof(taper_fit_result, param),
     offsetof(taper_fit_result, param_err), offsetof(taper_fit_result, n_points),
     offsetof(taper_fit_result, n_skipped), offsetof(taper_fit_result, chi2),
     offsetof(taper_fit_result, iterations)},
};

/* field 0: sizeof; field i >= 1: offset of the i-th member. */
size_t taper_test_layout(int type, int field);
size_t taper_test_layout(int type, int field)
{
    if (type < 0 || type >= (int)(sizeof layout / sizeof layout[0]) || field < 0 || field >= N_FIELDS)
        return (size_t)-1;
    return layout[type][field];
}
