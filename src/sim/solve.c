/* SPDX-License-Identifier: GPL-3.0-or-later */
/*
 * solve.c -- the run: the loop that drives the method's stepper (stepper.h)
 * towards the next output, asks events.c what a root return means and
 * window.c what the window must do, and applies the answers (the window
 * moves in window_flight.c; the stepper is restarted here and nowhere
 * else).  Then the statistics and the end of the run.  It never asks which
 * method integrates.
 *
 * The run starts from the impulse (v_1 = 1, everything else at rest and just
 * touching; with a striker the striker moves, granule 1 rests) and ends by
 * itself as soon as every requested observable is known, never at a guessed
 * end time, unless the caller asks to go on to t_end.  A sampler is served
 * on the way (sample.c).
 */
#include "stepper.h"

#include <float.h>
#include <math.h>

/* Once every pass time is known, how long (in units of the longest
 * residence time) to wait for the remaining peaks before declaring them
 * absent. */
#define PEAK_GRACE 20.0
/* The end of time when no t_max is given (pass times of exponential chains
 * grow like e^{eta k}: 1e30 is reached within a few hundred granules). */
#define NO_TIME_LIMIT 1e300

/* The stepper of the run (set up by setup_stepper; its memory is
 * sim->stepper's). */
static const taper_stepper_type *stepper_type(const taper_sim *sim)
{
    return taper_stepper_of(sim->spec.method)->type;
}

static taper_stepper *stepper(const taper_sim *sim) { return sim->stepper.memory; }

/* The quadratures at sim->t: the state's last entries; NULL without. */
static const double *quadratures_now(const taper_sim *sim)
{
    return sim->model.quadratures ? taper_sim_quadratures(sim) : NULL;
}

/* ---- set-up ------------------------------------------------------------ */
/* The state, on the window where the method's stepper integrates on one and
 * the spec asks for it (the quadratures ride along as its tail), else the
 * whole chain.  The body with the impulse and the next one are in the
 * window from the start (with a left wall, the wall behind them too): their
 * contact closes at t = 0+ in every chain, so holding it out would only
 * delay it.  A growth root is acted on at the end of the stepper's step,
 * not at the root (the new granule's state and history are zero at the
 * step's end): a first contact joining at its growth root lost the impulse
 * r h^n / n of the whole first step (h = 1e-4), an energy error of 1.3e-6
 * for n = 3/2 and 1.2e-8 for n = 2 at any rtol (the whole chain: 2.5e-9 and
 * 1.6e-9 at rtol 1e-12).  Under a load the same holds for the linear
 * K h^2 / 2. */
static taper_status setup_stepper(taper_sim *sim, taper_error *err)
{
    const taper_stepper_row *row = taper_stepper_of(sim->spec.method);
    if (!row)
        return taper_fail_field(err, TAPER_EINVAL, "method", "no stepper integrates method %d",
                                (int)sim->spec.method);
    taper_window_growth_thresholds(sim, sim->grow_z);
    const size_t extra = sim->model.quadratures ? TAPER_N_QUADRATURES : 0;
    const int windowed = sim->spec.window && row->on_window;
    if (windowed && !(sim->state.window = taper_window_alloc_tail(0, 2, 64, extra)))
        return taper_fail(err, TAPER_ENOMEM, "cannot allocate the state");
    sim->stepper.memory = row->type->alloc(sim, err);
    if (!sim->stepper.memory) return TAPER_ENOMEM;
    sim->stepper.release = row->type->free;
    const size_t i0 = sim->model.impulse;
    const size_t hi = !windowed ? sim->n : i0 < sim->n ? i0 + 1 : i0;
    if (taper_sim_move_window(sim, 1, hi, 0.0) != 0) return taper_fail(err, TAPER_ENOMEM, "cannot allocate the state");
    sim->stats.max_window = sim->dyn.hi - sim->dyn.lo + 1;
    /* v_1 = 1: the impulse (on the striker, or on granule 1 before a wall) */
    taper_sim_entries(sim)[taper_idx_v(sim->model.impulse)] = 1.0;
    taper_events_arm(sim, row->type->sees_tiny_sign_changes(sim->stepper.memory));
    return row->type->start(sim->stepper.memory, err);
}

/* The run's counters so far (none before the stepper). */
static taper_step_counters counters_now(const taper_sim *sim)
{
    return stepper(sim) ? stepper_type(sim)->counters(stepper(sim)) : (taper_step_counters){0};
}

/* ---- why a run stops early -------------------------------------------------- */
typedef enum stop_reason {
    STOP_INTERRUPTED,    /* the monitor asked                                */
    STOP_MAX_STEPS,      /* spec max_steps                                    */
    STOP_T_MAX,          /* spec t_max                                        */
    STOP_END_OF_TIME,    /* NO_TIME_LIMIT without a t_max                     */
    STOP_SOLVER,         /* the stepper failed                                */
    STOP_WINDOW_MEMORY   /* the window could not grow                         */
} stop_reason;

static taper_status stop_status(stop_reason why)
{
    switch (why) {
    case STOP_INTERRUPTED: return TAPER_EINTERRUPTED;
    case STOP_MAX_STEPS:
    case STOP_T_MAX:
    case STOP_END_OF_TIME: return TAPER_ELIMIT;
    case STOP_WINDOW_MEMORY: return TAPER_ENOMEM;
    case STOP_SOLVER: break;
    }
    return TAPER_ESOLVER;
}

/* What a user can change when a run stops early. */
static const char *advice(stop_reason why)
{
    switch (why) {
    case STOP_INTERRUPTED: return "";
    case STOP_MAX_STEPS: return "; raise max_steps (0: no limit)";
    case STOP_END_OF_TIME:
        return "; the pulse cannot cross this chain in finite double-precision time: fewer "
               "granules or a weaker taper";
    case STOP_T_MAX: return "; raise t_max (0: no limit)";
    default: break;
    }
    return "; try a looser rtol, method 'bdf' (strongly forward-tapered chains, whose lightest "
           "granules collide on tiny time scales), or fewer granules";
}

/* The granule that body k is (0 for a body before granule 1). */
static size_t granule_of(const taper_sim *sim, size_t k)
{
    return k > sim->model.off ? k - sim->model.off : 0;
}

/* Ends the run early: the reason (STOP_SOLVER: the stepper's own words),
 * where the pulse was, what to change. */
static taper_status stop(const taper_sim *sim, taper_error *err, stop_reason why)
{
    const taper_status status = stop_status(why);
    switch (why) {
    case STOP_WINDOW_MEMORY:
        /* not a stop of the integration: nothing to keep or advise */
        return taper_fail(err, status, "cannot enlarge the active window to %zu granules",
                          sim->dyn.hi - sim->dyn.lo + 2);
    case STOP_INTERRUPTED: taper_fail(err, status, "interrupted"); break;
    case STOP_MAX_STEPS: taper_fail(err, status, "max_steps reached"); break;
    case STOP_T_MAX: taper_fail(err, status, "t_max reached"); break;
    case STOP_END_OF_TIME: taper_fail(err, status, "time 1e300 reached (no t_max given)"); break;
    case STOP_SOLVER: stepper_type(sim)->describe_failure(stepper(sim), err, status); break;
    }
    taper_fail_append(err, " at t = %.17g with the pulse past granule %zu of %zu "
                           "(observables found so far are kept)%s",
                      sim->t, granule_of(sim, sim->pulse.next_pass - 1),
                      granule_of(sim, sim->pass_limit), advice(why));
    return status;
}

/* ---- applying the window's decisions ------------------------------------------ */
static void window_changed(taper_sim *sim)
{
    sim->stats.window_changes++;
    size_t size = sim->dyn.hi - sim->dyn.lo + 1;
    if (size > sim->stats.max_window) sim->stats.max_window = size;
}

/* The stepper goes on from the state the loop changed at sim->t. */
static taper_status restart(taper_sim *sim, taper_error *err)
{
    taper_status status = stepper_type(sim)->restart(stepper(sim), err);
    if (status == TAPER_OK) sim->stats.restarts++;
    return status;
}

/* Whether the gap slot's gap, z_{lo-1}, is already at its watch: the root
 * that watches it needs a sign change, and after a take-back starts from
 * the state the stepper has then. */
static int gap_already_closed(const taper_sim *sim)
{
    const size_t lo = sim->dyn.lo;
    if (lo <= 1) return 0;
    const double *y = taper_sim_entries(sim);
    return y[0] - sim->out.gap_watch[lo - 2] >= 0.0;
}

/* Granule lo-1 returns; and so does every one behind whose gap has closed
 * too by then.  A take-back comes at the end of the step holding its root,
 * and within that step the returning granule may already have closed the
 * next gap: at n = 12 behind a rigid wall the reflected pulse comes back
 * as a Newton's cradle, one granule flying at -1 at a time, and granule 775
 * of 1000, back in the window with its gap to 774 already closed, flew
 * through the resting 774 unseen (a compression of 2157 by t = 3649,
 * energy error 1.7e39). */
static taper_status take_back(taper_sim *sim, taper_error *err)
{
    do {
        if (taper_sim_recall_granule(sim) != 0) return stop(sim, err, STOP_WINDOW_MEMORY);
        window_changed(sim);
        taper_sim_log(sim, 0, "granule %zu rejoins the window at t = %.17g (its gap closed)",
                      granule_of(sim, sim->dyn.lo), sim->t);
    } while (gap_already_closed(sim));
    return restart(sim, err);
}

static taper_status grow(taper_sim *sim, taper_error *err)
{
    const taper_dyn *d = &sim->dyn;
    if (taper_sim_move_window(sim, d->lo, d->hi + 1, d->v_left) != 0)
        return stop(sim, err, STOP_WINDOW_MEMORY);
    window_changed(sim);
    return TAPER_OK;
}

static taper_status shrink(taper_sim *sim, taper_error *err)
{
    const size_t lo = sim->dyn.lo;
    const double tn = stepper_type(sim)->reached(stepper(sim)), h = stepper_type(sim)->last_step(stepper(sim));
    taper_status status = TAPER_OK;
    for (taper_departure d; !status && (d = taper_window_departure(sim)).kind != TAPER_STAYS;)
        if (taper_sim_release_granule(sim, d.watch, d.kind == TAPER_LEAVES_AT_REST, tn, h) != 0)
            status = taper_fail(err, TAPER_ENOMEM, "cannot allocate the drag's handovers");
    if (sim->dyn.lo != lo) window_changed(sim);
    return status;
}

/* ---- the piston's stop ------------------------------------------------------ */
/* The piston's velocity jumps from 1 to 0 at t = duration: a discontinuity
 * of the right-hand side that no step may straddle (the error control would
 * smear it over the steps around it).  The stepper stops there exactly (its
 * stop time), the piston's velocity is set to 0 in the state, and the
 * stepper restarts from that state (a multistep method with a fresh
 * history).  The piston never
 * leaves the window while it moves (window.c), so its velocity is always
 * the state's. */
static int piston_stop_pending(const taper_sim *sim)
{
    return sim->piston_moving && isfinite(sim->model.piston_duration);
}

/* The stop time a phase of the run asked for (grace, t_end): kept, so that
 * it can be set again after the piston's stop replaced it. */
static void set_stop_time(taper_sim *sim, double t)
{
    sim->phase_stop = t;
    if (!piston_stop_pending(sim)) stepper_type(sim)->set_stop(stepper(sim), t);
}

static taper_status stop_piston(taper_sim *sim, taper_error *err)
{
    double *y = taper_sim_entries(sim);
    sim->piston_work = taper_sim_quadratures(sim)[TAPER_QUAD_WALL_LEFT];
    taper_events_piston_stopped(sim);
    y[taper_idx_v(1) - taper_dyn_begin(&sim->dyn)] = 0.0; /* lo == 1 (window.c) */
    sim->piston_moving = 0;
    taper_sim_log(sim, 0, "the piston stops at t = %.17g (work done: %.17g)", sim->t,
                  sim->piston_work);
    taper_status status = restart(sim, err);
    /* The phase's stop, or none: the stop just reached is no stop any more
     * (a stepper may keep it through its restart and then refuse to start
     * from it: CVODE 6.4, flag -22). */
    if (!status) stepper_type(sim)->set_stop(stepper(sim), sim->phase_stop > sim->t ? sim->phase_stop : NO_TIME_LIMIT);
    return status;
}

/* ---- the run -------------------------------------------------------------- */
static int call_monitor(const taper_sim *sim)
{
    if (!sim->spec.monitor) return 0;
    const size_t N = sim->model.granules;
    const size_t lo = granule_of(sim, sim->dyn.lo), hi = granule_of(sim, sim->dyn.hi);
    taper_progress p = {
        .granule = granule_of(sim, sim->pulse.next_pass - 1),
        .target = granule_of(sim, sim->pass_limit), .t = sim->t,
        .steps = counters_now(sim).steps, .window_lo = lo ? lo : 1,
        .window_hi = hi > N ? N : hi ? hi : 1,
    };
    return sim->spec.monitor(&p, sim->spec.monitor_data);
}

static taper_status handle_roots(taper_sim *sim, const int *found, taper_error *err)
{
    const taper_root_locator where = {stepper_type(sim)->refine_root, stepper(sim)};
    const taper_root_report report = taper_events_record(sim, found, where);
    const taper_window_plan plan = taper_window_plan_for(sim, report);
    taper_status status = TAPER_OK;
    if (plan.take_back) status = take_back(sim, err);
    if (!status && plan.grow) status = grow(sim, err);
    if (!status && taper_events_fit_rings(sim)) status = stepper_type(sim)->arm_roots(stepper(sim), err);
    if (!status && report.passed) {
        if (plan.shrink) status = shrink(sim, err);
        if (!status && call_monitor(sim)) status = stop(sim, err, STOP_INTERRUPTED);
    }
    return status;
}

/* The time after which missing peaks are declared absent. */
/* The longest residence time so far is the scale: in forward chains the
 * last granules are tiny and passed in 1e-3 time units (even out of order),
 * while the train behind keeps pushing them for times of order the first
 * residence times.  Called once per run: O(N) is fine. */
static double grace_time(const taper_sim *sim)
{
    const double *tp = sim->pulse.obs[TAPER_T_PASS];
    double longest = 0.0;
    for (size_t k = 1; k <= sim->pass_limit; k++)
        longest = fmax(longest, tp[k - 1] - (k > 1 ? tp[k - 2] : 0.0));
    return sim->t + PEAK_GRACE * fmax(longest, 1e-3);
}

/* One advance of the stepper towards tout, stopping on the way at the next
 * sample time (sample.c) and calling the sampler there.  *reached: the
 * stepper got to tout (or its stop time) itself.  Without a sampler this
 * is the plain advance. */
static taper_status advance(taper_sim *sim, double tout, int *reached, taper_error *err)
{
    const taper_stepper_type *type = stepper_type(sim);
    const double t_sample = taper_sample_next(sim);
    double target = t_sample < tout ? t_sample : tout;
    const int piston_first = piston_stop_pending(sim) && sim->model.piston_duration <= target;
    if (piston_first) target = sim->model.piston_duration;
    if (piston_stop_pending(sim)) { /* the stop: the piston's or the phase's, the first */
        double stop_at = sim->model.piston_duration;
        const double tn = type->reached(stepper(sim));
        if (sim->phase_stop > tn && sim->phase_stop < stop_at) stop_at = sim->phase_stop;
        type->set_stop(stepper(sim), stop_at);
    }
    taper_step step;
    const taper_step_outcome outcome = type->advance(stepper(sim), target, tout, &step);
    const double t = step.t;
    sim->t = t;
    sim->t_low = step.t_low;
    *reached = 0;
    if (piston_first && outcome == TAPER_STEP_REACHED && t >= target) {
        taper_status status = stop_piston(sim, err);
        /* a sample or tout at the stop time: served below, from the
         * stopped state (a stepper may refuse an output time that is its
         * own time now) */
        if (status != TAPER_OK || (t < t_sample && t < tout)) return status;
    }
    switch (outcome) {
    case TAPER_STEP_ROOT: return handle_roots(sim, step.found, err);
    case TAPER_STEP_WORK:
        if (call_monitor(sim)) return stop(sim, err, STOP_INTERRUPTED);
        return TAPER_OK;
    case TAPER_STEP_REACHED:
        /* after a sample the monitor too: a sampled run past the pulse has
         * no events, and its advances end at samples, not at the steps'
         * limit */
        if (t >= t_sample && (taper_sample_call(sim) || call_monitor(sim)))
            return stop(sim, err, STOP_INTERRUPTED);
        *reached = t >= tout; /* a stop time of an earlier phase is no arrival */
        return TAPER_OK;
    case TAPER_STEP_FAILED: break;
    }
    return stop(sim, err, STOP_SOLVER);
}

static taper_status step_once(taper_sim *sim, double tout, int grace, taper_error *err)
{
    int reached;
    taper_status status = advance(sim, tout, &reached, err);
    if (status != TAPER_OK || !reached) return status;
    if (grace) return TAPER_OK; /* remaining peaks do not exist */
    return stop(sim, err, sim->spec.t_max > 0.0 ? STOP_T_MAX : STOP_END_OF_TIME);
}

/* After the observables: on to t_end (taper_solver_spec_set_t_end), within
 * t_max. */
static taper_status continue_to_end(taper_sim *sim, taper_error *err)
{
    const double t_end = sim->spec.t_end;
    if (!(t_end > sim->t)) return TAPER_OK;
    const double limit = sim->spec.t_max > 0.0 ? sim->spec.t_max : NO_TIME_LIMIT;
    const double tout = t_end < limit ? t_end : limit;
    /* The stepper may have stepped past tout already (the last root lay
     * inside its step): it then interpolates, and a stop time behind it
     * would be refused. */
    if (tout > stepper_type(sim)->reached(stepper(sim))) set_stop_time(sim, tout);
    for (int reached = 0; !reached;) {
        if (sim->spec.max_steps > 0 && counters_now(sim).steps >= sim->spec.max_steps)
            return stop(sim, err, STOP_MAX_STEPS);
        taper_status status = advance(sim, tout, &reached, err);
        if (status != TAPER_OK) return status;
    }
    return tout < t_end ? stop(sim, err, STOP_T_MAX) : TAPER_OK;
}

/* Drag takes momentum out of the chain (contact forces and damping only
 * move it along), so a pulse under strong drag dies into an overdamped
 * front that creeps on ever slower, and the passes still to come come ever
 * later, of motion below what the tolerance resolves (a monodisperse chain
 * of 100 at drag 100: every granule at rest within rtol by t = 1.85e6,
 * 28 passed; the front, followed on with BDF, passed granule 99 at
 * t = 4.1e7; Adams had passed 11 by t = 1.2e5 after 1.6e7 steps).  The
 * pulse is absorbed once every body moves slower than one unit of the
 * tolerance at the impulse's velocity, rtol v_1 + atol v_scale (v_1 = 1,
 * the impulse, striker or piston velocity of eq. (5)'s units): the run
 * ends there, complete, the passes it never reached NaN, and the log says
 * so.  Bodies ahead of the window never moved; those behind it fly under
 * drag and slow down on their own, and sim.c keeps the time after which
 * every one of them is that slow (quiet_after). */
static int absorbed_by_drag(const taper_sim *sim)
{
    if (!(sim->model.drag > 0.0) || sim->piston_moving || sim->t < sim->out.quiet_after) return 0;
    const taper_dyn *d = &sim->dyn;
    const double *y = taper_sim_entries(sim);
    /* from the front, where the pulse is: a moving run answers at once */
    for (size_t k = d->hi; k >= d->lo; k--)
        if (fabs(taper_dyn_v(d, y, k)) > sim->spec.rtol + sim->spec.atol * sim->v_scale[k - 1]) return 0;
    return 1;
}

/* The longest residence time so far (at least 1e-3): the time scale on
 * which the pulse makes progress. */
/* A pulse can leave the chain before it has passed every granule: a heavy
 * granule sends it back, or damping absorbs it, and the passes still to
 * come are of motion below what the tolerance resolves (a chain of radii 1,
 * 1e-3, 1e3, 1e-3, 1e3, 1 reflects all but 2e-9 of the energy at granule
 * 3, then the light granule 4 rattles between the heavy ones for ever).
 * The budget's "in chain" is the energy that can still be exchanged
 * (budget.c): once it is below rtol E(0), nothing the run resolves is left
 * to happen.  Checked only when the run has stalled, PEAK_GRACE longest
 * residence times without a pass: the budget walks the whole chain. */
typedef struct progress_watch {
    size_t next_pass;  /* passes seen so far                          */
    double longest;    /* the longest residence time among them       */
    double since, interval;
} progress_watch;

/* The longest residence time so far, kept as a running maximum over the
 * passes found since the last look (a rescan of every pass at each new one
 * would cost O(N^2) on a long chain). */
static void watch_passes(const taper_sim *sim, progress_watch *w)
{
    const double *tp = sim->pulse.obs[TAPER_T_PASS];
    for (size_t k = w->next_pass > 1 ? w->next_pass : 1;
         k < sim->pulse.next_pass && k <= sim->pass_limit; k++)
        if (isfinite(tp[k - 1]))
            w->longest = fmax(w->longest,
                              tp[k - 1] - (k > 1 && isfinite(tp[k - 2]) ? tp[k - 2] : 0.0));
    w->next_pass = sim->pulse.next_pass;
    w->since = sim->t;
    w->interval = PEAK_GRACE * w->longest;
}

/* 1: the pulse has left; 0: not; -1: the monitor, asked before the budget
 * walks the whole of a long chain (10^6 granules: tens of milliseconds,
 * and before the first pass it is looked at after every event), said
 * stop. */
static int pulse_has_left(taper_sim *sim, progress_watch *w)
{
    if (sim->pulse.next_pass != w->next_pass) {
        watch_passes(sim, w);
        return 0;
    }
    if (sim->t - w->since < w->interval) return 0;
    w->since = sim->t; /* the next look after another interval */
    if (sim->n >= TAPER_LONG_CHAIN && call_monitor(sim)) return -1;
    taper_budget_compute(sim, quadratures_now(sim));
    const double left = sim->stats.energy_in_chain, e0 = sim->stats.energy_initial;
    return isfinite(left) && left <= sim->spec.rtol * e0;
}

static taper_status integrate(taper_sim *sim, taper_error *err)
{
    double tout = sim->spec.t_max > 0.0 ? sim->spec.t_max : NO_TIME_LIMIT;
    int grace = 0, absorbed = 0, left = 0;
    progress_watch watch = {.next_pass = 0, .longest = 1e-3};
    watch_passes(sim, &watch);
    while (!taper_events_complete(sim) || !taper_events_walls_settled(sim)) {
        if (sim->spec.max_steps > 0 && counters_now(sim).steps >= sim->spec.max_steps)
            return stop(sim, err, STOP_MAX_STEPS);
        if (!grace && taper_events_passes_complete(sim)) {
            grace = 1;
            double tg = grace_time(sim);
            if (tg < tout) tout = tg;
            set_stop_time(sim, tout);
        }
        double t_before = sim->t;
        taper_status status = step_once(sim, tout, grace, err);
        if (status != TAPER_OK) return status;
        if (grace && sim->t >= tout && sim->t > t_before) break;
        if ((absorbed = absorbed_by_drag(sim))) break;
        if ((left = pulse_has_left(sim, &watch)) < 0) return stop(sim, err, STOP_INTERRUPTED);
        if (left) break;
    }
    const size_t next_peak = sim->pulse.next_peak;
    if (!taper_events_walls_settled(sim)) /* the grace time ended it (a steady piston) */
        taper_sim_log(sim, 1,
                      "the right wall still pushes at t = %.6g, %g times the longest residence "
                      "time after the last pass: its peak force, time and impulse are those of "
                      "the run so far, not of its whole contact",
                      sim->t, PEAK_GRACE);
    if (left) {
        const size_t next_pass = sim->pulse.next_pass;
        taper_sim_log(sim, 1,
                      "the pulse has left the chain: at t = %.6g the energy that can still be "
                      "exchanged is %.2g of the initial, below rtol (%.1e): reflected %.6g, "
                      "transmitted %.6g; from granule %zu on no pass and from granule %zu on "
                      "no velocity maximum (nan)",
                      sim->t, sim->stats.energy_in_chain / sim->stats.energy_initial,
                      sim->spec.rtol, sim->stats.energy_reflected, sim->stats.energy_transmitted,
                      granule_of(sim, next_pass <= sim->pass_limit ? next_pass : sim->pass_limit + 1),
                      granule_of(sim, next_peak));
    } else if (absorbed) {
        const size_t next_pass = sim->pulse.next_pass;
        taper_sim_log(sim, 1,
                      "the pulse was absorbed by drag: at t = %.6g every granule moves slower than "
                      "rtol + atol v_scale (%.1e of the impulse's velocity); from granule %zu on "
                      "no pass and from granule %zu on no velocity maximum (nan)",
                      sim->t, sim->spec.rtol,
                      granule_of(sim, next_pass <= sim->pass_limit ? next_pass : sim->pass_limit + 1),
                      granule_of(sim, next_peak));
    } else if (next_peak <= sim->target) {
        size_t missing = 0;
        for (size_t k = next_peak; k <= sim->target; k++)
            missing += isnan(sim->pulse.obs[TAPER_T_PEAK][k - 1]);
        taper_sim_log(sim, 1,
                      "%zu of granules %zu..%zu reached no forward velocity maximum within %g "
                      "times the longest residence time after the last pass (the run ended at "
                      "t = %.6g): their v_peak is nan",
                      missing, granule_of(sim, next_peak), granule_of(sim, sim->target),
                      PEAK_GRACE, sim->t);
    }
    taper_status status = continue_to_end(sim, err);
    /* A wall the pulse never reached has no peak: said, never 0. */
    static const char *const sides[TAPER_N_ENDS] = {"left", "right"};
    for (int e = 0; status == TAPER_OK && e < TAPER_N_ENDS; e++) {
        const int wall = e == TAPER_LEFT ? sim->model.wall_left && !sim->model.piston
                                         : sim->model.wall_right;
        if (wall && isnan(sim->walls.peak_force[e]))
            taper_sim_log(sim, 1,
                          "the %s wall felt no force before the run ended at t = %.6g: its peak "
                          "force and time are nan (give t_end to follow the pulse there)",
                          sides[e], sim->t);
    }
    return status;
}

/* Smallest residence time, relative to t_pass, that the pass times resolve.
 * CVODE locates a root to within 100 uround (|t| + |h|) (cvRootfind's
 * ttol), whatever rtol, so a difference of two pass times carries up to
 * 200 uround t_pass of root-finding error; T_res is kept while that is
 * below 1 % of it.  The integration error of T_res is relative to T_res
 * itself, not to t_pass: both pass times share the error accumulated
 * before them (docs/design.md, "Pulse events").  Measured: forward exponential q = 0.05,
 * N = 1000, against rtol 1e-13, the T_res error is ~1e-14 t_pass / T_res
 * (7e-4 at T_res ~ 1e-12 t_pass); monodisperse at rtol 1e-6 to N = 20000,
 * T_res ~ 6e-5 t_pass is good to 7e-5 (twice the t_pass error). */
#define PASS_TIME_RESOLUTION (2e4 * DBL_EPSILON)

/* Residence times T_res(k) = t_pass(k) - t_pass(k-1), NaN where they are
 * not a residence: below the pass times' resolution (the last, tiny
 * granules of forward chains are passed within 1e-15 t of each other: a
 * difference that is noise), or negative, where
 * granule k is passed before granule k-1 (below n = 2 the precursor moves
 * the chain's end as a block and its last granule may be passed first; the
 * light end of a steep forward taper, small granules of decorated and mixed
 * chains too).  A negative "residence" would
 * read as a measurement (it did, in a partial file).  The counts
 * go to the log (report_untimed). */
typedef struct residence_report {
    size_t unresolved, out_of_order;
    size_t first_out_of_order;  /* granule, 0: none */
} residence_report;

static residence_report residence_times(taper_sim *sim)
{
    /* granule k of the chain: t_pass(0) = 0 even after a striker */
    const double *tp = sim->pulse.obs[TAPER_T_PASS] + sim->model.off;
    double *tr = sim->pulse.obs[TAPER_T_RES] + sim->model.off;
    residence_report r = {0, 0, 0};
    for (size_t k = 1; k <= sim->model.granules; k++) {
        double before = k > 1 ? tp[k - 2] : 0.0, T = tp[k - 1] - before;
        if (fabs(T) < PASS_TIME_RESOLUTION * fabs(tp[k - 1])) {
            T = NAN;
            r.unresolved++;
        } else if (T < 0.0) {
            T = NAN;
            if (!r.out_of_order++) r.first_out_of_order = k;
        }
        tr[k - 1] = T;
    }
    return r;
}

/* What the caller's log should know about values left NaN on purpose. */
static void report_untimed(const taper_sim *sim, residence_report residences)
{
    const size_t passes = sim->pulse.untimed_passes, peaks = sim->pulse.untimed_peaks;
    if (passes || peaks)
        taper_sim_log(sim, 1,
                      "%zu pass time%s and %zu peak%s happened before their root functions "
                      "were armed (light granules overtaking in the precursor of a steeply "
                      "tapered chain): written as nan, not guessed",
                      passes, passes == 1 ? "" : "s", peaks, peaks == 1 ? "" : "s");
    if (residences.unresolved)
        taper_sim_log(sim, 1,
                      "%zu residence time%s below the resolution of the pass times "
                      "(%.1e t, set by CVODE's root finder): written as nan",
                      residences.unresolved, residences.unresolved == 1 ? " is" : "s are",
                      PASS_TIME_RESOLUTION);
    if (residences.out_of_order)
        taper_sim_log(sim, 1,
                      "%zu granule%s passed before the granule ahead of %s (first: "
                      "granule %zu): the pulse is no longer a sequence of passes there "
                      "(light granules overtaken within the pulse: small granules of a "
                      "decorated or mixed chain, the precursor below n = 2, the light end of "
                      "a steep forward taper); their residence times are written as nan, "
                      "their pass times kept",
                      residences.out_of_order, residences.out_of_order == 1 ? " was" : "s were",
                      residences.out_of_order == 1 ? "it" : "them", residences.first_out_of_order);
}

/* Energy error beyond which the caller is told that the far end of the
 * chain is not what the tolerance suggests.  The error of a long run is a
 * drift, not noise: the energy error grows with the granules crossed, and
 * the pulse's amplitude and speed follow it (monodisperse, 10^6 granules:
 * v_peak off by half the energy error at the end, t_pass by a twentieth;
 * docs/benchmarks.md, "Long chains at looser tolerances"). */
#define ENERGY_DRIFT_WARNING 1e-3

static void warn_of_drift(const taper_sim *sim)
{
    const double e = sim->stats.energy_error;
    if (e > ENERGY_DRIFT_WARNING)
        taper_sim_log(sim, 1,
                      "energy error %.1e at t = %.6g: the integration has drifted, and values far "
                      "along the chain carry errors up to that size (v_peak about half of it); "
                      "a smaller rtol reduces it",
                      e, sim->stats.t_final);
}

static void finish(taper_sim *sim, taper_status status)
{
    report_untimed(sim, residence_times(sim));
    taper_run_statistics *s = &sim->stats;
    s->counters = counters_now(sim);
    s->granule_reached = granule_of(sim, sim->pulse.next_pass - 1); /* a granule, not a body */
    s->t_final = sim->t;
    s->complete = status == TAPER_OK;
    const taper_dyn *d = &sim->dyn;
    const double *y = taper_sim_entries(sim);
    double e = 0.0, p = 0.0, p_abs = 0.0;
    if (y) taper_dyn_energy_momentum(d, y, &e, &p);
    e += sim->out.energy_free;
    p += sim->out.momentum_free;
    for (size_t k = 1; y && k <= sim->n; k++) {
        double v = 0.0;
        if (k < d->lo) taper_sim_flight(sim, k, sim->t, NULL, &v);
        else if (k <= d->hi) v = taper_dyn_v(d, y, k);
        p_abs += sim->mass[k - 1] * fabs(v);
    }
    /* (a piston's run: budget.c replaces both with the work's balance) */
    const double m0 = sim->mass[sim->model.impulse - 1], e0 = 0.5 * m0, p0 = m0;
    s->energy_error = fabs(e - e0) / e0;
    /* Relative to the momentum in motion: in backward chains granules carry
     * momenta far above P0 in opposite directions. */
    s->momentum_error = fabs(p - p0) / fmax(p0, p_abs);
    taper_budget_compute(sim, quadratures_now(sim));
    warn_of_drift(sim);
}

taper_status taper_sim_run(taper_sim *sim, taper_error *err)
{
    if (!sim) return taper_fail(err, TAPER_EINVAL, "taper_sim_run: sim is NULL");
    if (sim->ran) return taper_fail(err, TAPER_EINVAL, "taper_sim_run: this sim has already run");
    sim->ran = 1;
    sim->piston_moving = sim->model.piston;
    sim->phase_stop = 0.0;
    taper_status status = setup_stepper(sim, err);
    /* the sampler's first call: the initial state, t = 0 */
    if (status == TAPER_OK && taper_sample_next(sim) == 0.0 && taper_sample_call(sim))
        status = stop(sim, err, STOP_INTERRUPTED);
    if (status == TAPER_OK) status = integrate(sim, err);
    finish(sim, status);
    if (status == TAPER_OK) taper_ok(err);
    return status;
}
