"""The compiled shot: a stage integrated with event location, and the whole shot, in numba.

The physics is not here: the equations, the stages' right-hand sides and
events and the limits are the model's (``analytic.eom``, ``analytic.stages``,
``analytic.limits``), and what each stage's end means is ``analytic.sequence``,
compiled from the same source the reference path runs (``analytic.fast.compiled``).
The integrator's parts are ``analytic.fast.dop853`` (scipy's DOP853, step for step)
and the peak loads' ``analytic.fast.kernel_loads``. This module drives them:
``integrate`` takes a stage's steps and finds its events, ``shot`` runs the
stages in sequence, and ``shots`` (the one compiled entry point, which
``analytic.fast`` runs on several threads at once) a range of design rows.

The entry point is compiled with ``cache=True`` (``analytic.fast.compiled.CALLABLE``):
the first call in a fresh checkout compiles it, with everything it calls,
and writes the machine code to ``__pycache__``; later processes load it from
there. The other functions here are ``analytic.fast.compiled.internal``: compiled
once per argument type (a stage or a flag passed as a constant does not get
its own copy), for compiled callers only. Numbers that come from outside the
model's source (the DOP853 coefficients, the drag table) are arguments, never
globals a stale cache could freeze.

Designs arrive as rows laid out as ``analytic.parameters.Params`` and read as
records (``params``); results leave as records of ``RESULT_DTYPE``, field by
field (``analytic.fast`` reads them by name).
"""

from __future__ import annotations

import math

import numpy as np

from analytic.fast.marks import entry, internal
from analytic.fast.dop853 import (ERROR_ORDER, MAX_FACTOR, MIN_FACTOR, N_STAGES, SAFETY, brent, dense_eval, dense_prepare,
                             derivative_call, error_norm, event_at, initial_step, rk_step)
from analytic.fast.kernel_loads import N_LOADS, finish_peaks, keep_step, sample_loads, start_peaks
from analytic.limits import STAGE_STEP_LIMITS, flight_time_limit
from analytic.parameters import PARAMS_DTYPE
from analytic.scope import FRICTION, LOADS, RECORDING   # what this copy handles (analytic.scope)
from analytic.sequence import (FAILED, FINISHED, NEVER_FIRES, NEVER_LIFTS_OFF, NEXT_STAGE, OK, OUT_OF_STEPS,
                               REACHED_END, SHORT_OF_TARGET, STEP_FAILED, SWITCH_MODE, counted_crossing, event_rate,
                               lands_at_release, leaves_zero, past_root, probe_bracket, probe_time, probe_update,
                               rate_offset, short_of_target, stretch_end, tangent_state, turn_bracket, turn_first,
                               turn_next, turn_search, turn_update, turns_back)
from analytic.stages import (ZERO_START_PROBES, event_armed, event_count, event_direction, event_terminal,
                             event_turns, event_value, fires, first_event, flight_start, frame_state, loads_after_step,
                             loads_at, slide_start, swing_start)
from analytic.states import (FLIGHT, FLIGHT_LANDING, FLIGHT_VX, FLIGHT_VY, FLIGHT_X, FLIGHT_Y, SLIDE, SWING, state_size,
                             switch_mode)


#: A result row, field by field (``analytic.fast`` reads them by name; NaN: not reached):
#:
#: * ``status``: ``Status.code``; ``detail``: for NEVER_LIFTS_OFF a ``LiftoffFailure``, for
#:   STEP_FAILED the stage, else 0; ``out_of_steps``: a STEP_FAILED stage took its
#:   ``STAGE_STEP_LIMITS`` steps; ``rest_acceleration``: for NEVER_FIRES, the arm's at rest;
#: * ``steps``, ``evaluations``: the integrator's accepted steps and the model's evaluations,
#:   counted as the shot goes;
#: * the instants the shot reached and where: lift-off, release (the projectile's position and
#:   velocity on the ground, the frame's displacement and velocity: 0 when fixed), landing
#:   (``landing_x``, its range; ``apex_height``, the flight's highest point above the base);
#:   ``end_time``, where the shot ended;
#: * ``peaks[i]``: the largest load i (``stages.LOAD_NAMES``) over stages 1-2 and its time (NaN for
#:   a machine that never fires, or a step failure).
#:
#: Aligned (``align=True``): each field on its own boundary, as numba's records read them.
RESULT_DTYPE = np.dtype([
    ("status", np.int64), ("detail", np.int64), ("steps", np.int64), ("evaluations", np.int64),
    ("liftoff_time", np.float64), ("release_time", np.float64),
    ("release_position", np.float64, (2,)), ("release_velocity", np.float64, (2,)),
    ("frame_release_displacement", np.float64), ("frame_release_velocity", np.float64),
    ("landing_time", np.float64), ("landing_x", np.float64), ("apex_height", np.float64),
    ("end_time", np.float64), ("rest_acceleration", np.float64), ("peaks", np.float64, (N_LOADS, 2)),
    ("out_of_steps", np.bool_)], align=True)

#: The state of a recording (``shots``' motion), one record: the next sample's time, the spacing of
#: stages 1-2's and of the flight's samples, the most samples a flight gets (its spacing widens to
#: keep within them), the rows written so far, and whether the buffer ran out (the recording lost).
RECORDING_DTYPE = np.dtype([
    ("next_sample", np.float64), ("spacing", np.float64), ("flight_spacing", np.float64),
    ("sample_limit", np.int64), ("rows", np.int64), ("ran_out", np.bool_)], align=True)
#: The longest state a sample holds (stage 2 with friction, a floating arm's with the base's work).
MAX_STATE = 13
#: A recorded sample: its time, its stage, and the stage's state (NaN past its length).
SAMPLE_DTYPE = np.dtype([("t", np.float64), ("stage", np.int64), ("state", np.float64, (MAX_STATE,))],
                        align=True)


@internal
def record_row(t, stage, y, rec, motion):
    """Append the sample (t, stage, y) to ``motion``; past its end mark the recording lost (``ran_out``)."""
    recording = rec[0]
    if recording.ran_out:
        return
    row = recording.rows
    if row >= motion.shape[0] or y.shape[0] > MAX_STATE:
        recording.ran_out = True
        return
    sample = motion[row]
    sample.t, sample.stage = t, stage
    state = sample.state
    for j in range(y.shape[0]):
        state[j] = y[j]
    for j in range(y.shape[0], MAX_STATE):
        state[j] = math.nan
    recording.rows = row + 1


@internal
def record_step(stage, t_end, t_old, h, y_old, F, tmp, rec, motion):
    """Record the samples of the grid (``next_sample``, spaced by the stage's spacing) up to ``t_end``
    on the step's interpolant (``F``, prepared)."""
    recording = rec[0]
    spacing = recording.flight_spacing if stage == FLIGHT else recording.spacing
    while recording.next_sample <= t_end:
        dense_eval(recording.next_sample, t_old, h, y_old, F, tmp)
        record_row(recording.next_sample, stage, tmp, rec, motion)
        recording.next_sample += spacing


@internal
def record_last(t, stage, y, rec, motion):
    """Record the state ``y`` at ``t`` where a stage ended, unless its grid's last sample fell there."""
    recording = rec[0]
    if recording.rows > 0 and motion[recording.rows - 1].t < t:
        record_row(t, stage, y, rec, motion)


#: Rows of ``integrate``'s ``work``, the states and derivatives of ``_integrate_steps``: the state at a
#: step's start (``STATE``), at its end (``TRIAL``) and at the root that ended the stretch (``ROOT``),
#: the derivative at a step's start and end, scratch, a root's state, and the state behind a step's end.
STATE, TRIAL, ROOT = 0, 1, 2
WORK_ROWS = 8


@internal(allocates=True)
def integrate(stage, t0, y0, t_bound, coef, rtol, atol, p, table, out, peaks, track_loads, rec, motion):
    """Integrate ``stage`` from (t0, y0) until a terminal event or ``t_bound``, each event's roots found
    from its values and rates at each step's ends (``analytic.sequence``).

    Returns ``(code, t_end, y_end, apex)``: code is the index of the terminal
    event that ended it, ``REACHED_END``, ``FAILED`` (step size underflow
    or a non-finite state) or ``OUT_OF_STEPS`` (the stage's ``STAGE_STEP_LIMITS``
    accepted steps without reaching ``t_bound``); apex is the largest y at a counted apex root
    (flight only; -inf if none). ``out`` (a ``RESULT_DTYPE`` record) counts the steps and evaluations.
    A non-empty ``rec`` records the motion into ``motion``: the start, then a grid from it,
    each sample read off its step's interpolant (``record_step``; the stage's last is
    ``shot``'s). The grids are ``analytic.reference``'s: each stretch starts its own.
    In stages 1 and 2 with ``track_loads``, ``peaks`` (N_LOADS, 2) gets the
    largest of each load (``stages.loads_at``) and its time, where this stretch
    beats it: sampled at every step's end and refined on the interpolants
    beside each local maximum of the samples, as ``analytic.reference`` does.

    This function allocates the stretch's arrays and ``_integrate_steps`` steps through it: that
    one counts no references (``analytic.fast.marks.internal``), so the helpers numba inlines into
    its loop take their arrays at no cost per step.
    """
    n = y0.shape[0]
    ne = event_count(stage, p)
    if RECORDING and rec.shape[0] > 0:   # (a stage's first stretch after another stage: lift-off again, which the reader drops)
        record_row(t0, stage, y0, rec, motion)
        rec[0].next_sample = t0 + (rec[0].flight_spacing if stage == FLIGHT else rec[0].spacing)
    K2 = np.empty((2, N_STAGES + 4, n))   # the last two steps' stages, alternately
    F = np.empty((7, n))
    # One array each for the states and derivatives (``_integrate_steps`` names its rows), the events'
    # values and rates at a step's start, and the apex roots within one step (times, heights): each
    # array is one more argument of ``_integrate_steps``, passed at every stretch.
    work = np.empty((WORK_ROWS, n))
    for j in range(n):
        work[0, j] = y0[j]
    events = np.empty((2, ne))
    apexes = np.empty((2, 4))
    track = track_loads and stage != FLIGHT
    # The peak loads' state (``analytic.fast.kernel_loads``): the last two samples, the stretch's
    # largest, and the last two steps with their interpolants. Filled by loops (``start_peaks``):
    # numba compiles np.full and np.zeros into a function per shape and type (about a second of a
    # cold compile in all).
    buffers = 2 if LOADS and track else 0
    recent, best = np.empty((2, N_LOADS + 1)), np.empty((N_LOADS, 2))
    live_y, live_t = np.empty((buffers, 2, n)), np.empty((buffers, 3))
    dense, built, load_tmp = np.empty((buffers, 7, n)), np.empty(buffers, dtype=np.bool_), np.empty(n)
    code, t_end, apex, end = _integrate_steps(stage, ne, t0, t_bound, coef, rtol, atol, p, table, out, peaks, track,
                                              rec, motion, K2, F, work, events, apexes, recent, best, live_y, live_t,
                                              dense, built, load_tmp)
    return code, t_end, work[end], apex


@internal
def _integrate_steps(stage, ne, t0, t_bound, coef, rtol, atol, p, table, out, peaks, track, rec, motion, K2, F, work,
                     events, apexes, recent, best, live_y, live_t, dense, built, load_tmp):
    """``integrate``'s stretch, on its arrays (``work[STATE]`` holding the start): step after step (``_step``),
    each searched for the events' roots (``_locate_events``), until an event ends it or ``t_bound``.

    Returns ``(code, t_end, apex, end)`` as ``integrate`` does, with the end state in ``work[end]``.

    numba inlines the helpers every step runs (``_step``, ``_locate_events``, ``_stop_at``,
    ``_after_step``: ``inline="always"``, each at its one call site), so this compiles as the one
    function it was. The helpers that run only where a step holds an event's root
    (``_probe_zero_start``, ``_search_turn``, ``_roots``, ``_ensure_dense``) are calls: inlined at
    their call sites too, they lengthened a cold compile (``compile_scopes_s``) for no faster shot.
    """
    y, y_new, y_end = work[STATE], work[TRIAL], work[ROOT]
    f, f_new, tmp, y_root, behind = work[3], work[4], work[5], work[6], work[7]
    previous, rates = events[0], events[1]   # each event's value and rate at the step's start
    apex_t, apex_y = apexes[0], apexes[1]   # the counted apex roots within one step
    n = y.shape[0]
    derivative_call(stage, y, p, table, f)
    for k in range(ne):
        previous[k] = event_value(stage, k, y, p)
        rates[k] = math.nan   # none at the stretch's start: its first step is not searched for turns (sequence)
    t = t0
    h_abs = initial_step(stage, t0, y, f, t_bound, rtol, atol, p, table)
    out.evaluations += 2
    if not math.isfinite(h_abs):
        # A non-finite start or derivative: a NaN step would be shrunk forever.
        return FAILED, t, -math.inf, STATE
    apex = -math.inf
    if LOADS and track:
        start_peaks(recent, best, built)
        sample_loads(t0, loads_at(stage, y, p), -1, recent, best, stage, K2, live_y, live_t, dense, built, load_tmp,
                     coef, p, table, out)
        out.evaluations += 1
    steps = 0
    while t < t_bound:
        if steps == STAGE_STEP_LIMITS[stage]:
            return OUT_OF_STEPS, t, apex, STATE
        buffer = steps % 2
        K = K2[buffer]
        accepted, t_new, h, h_abs = _step(stage, t, y, f, h_abs, t_bound, coef, rtol, atol, K, y_new, f_new, tmp, p,
                                          table, out)
        if not accepted:
            return FAILED, t, apex, STATE
        out.steps += 1
        steps += 1
        for j in range(n):
            if not math.isfinite(y_new[j]):
                return FAILED, t_new, apex, TRIAL
        t_old = t
        hit_t, hit_k, n_apex, dense_ready = _locate_events(stage, ne, t_old, t_new, h, y, y_new, f_new, previous,
                                                           rates, behind, coef, K, F, tmp, y_root, apex_t, apex_y,
                                                           p, table, out)
        for i in range(n_apex):
            if apex_t[i] <= hit_t:
                apex = max(apex, apex_y[i])
        if hit_k >= 0:
            dense_eval(hit_t, t_old, h, y, F, y_end)
            _stop_at(stage, hit_t, t_old, h, buffer, y, y_new, y_end, F, tmp, coef, p, table, out, peaks, track, rec,
                     motion, K2, recent, best, live_y, live_t, dense, built, load_tmp)
            return hit_k, hit_t, apex, ROOT
        _after_step(stage, t_old, t_new, h, buffer, dense_ready, y, y_new, f_new, K, F, tmp, coef, p, table, out,
                    track, rec, motion, K2, recent, best, live_y, live_t, dense, built, load_tmp)
        t = t_new
        for j in range(n):
            y[j] = y_new[j]
            f[j] = f_new[j]
    if LOADS and track:
        finish_peaks((steps - 1) % 2 if steps > 0 else -1, recent, best, peaks, stage, K2, live_y, live_t, dense,
                     built, load_tmp, coef, p, table, out)
    return REACHED_END, t, apex, STATE


@internal(inline="always")
def _stop_at(stage, hit_t, t_old, h, buffer, y, y_new, y_end, F, tmp, coef, p, table, out, peaks, track, rec, motion,
             K2, recent, best, live_y, live_t, dense, built, load_tmp):
    """The stretch ends at an event's root ``hit_t`` within the step from ``t_old`` (its state ``y_end``,
    on the step's dense output): the recording's samples up to it, and the peak loads' last sample
    there and their search (``kernel_loads.finish_peaks``)."""
    if RECORDING and rec.shape[0] > 0:
        record_step(stage, hit_t, t_old, h, y, F, tmp, rec, motion)
    if LOADS and track:
        keep_step(buffer, t_old, h, hit_t, y, y_new, live_y, live_t, built)
        out.evaluations += 1
        sample_loads(hit_t, loads_at(stage, y_end, p), buffer, recent, best, stage, K2, live_y, live_t, dense, built,
                     load_tmp, coef, p, table, out)
        finish_peaks(buffer, recent, best, peaks, stage, K2, live_y, live_t, dense, built, load_tmp, coef, p, table,
                     out)


@internal(inline="always")
def _after_step(stage, t_old, t_new, h, buffer, dense_ready, y, y_new, f_new, K, F, tmp, coef, p, table, out, track,
                rec, motion, K2, recent, best, live_y, live_t, dense, built, load_tmp):
    """What the stretch keeps of an accepted step that no event ended: the recording's samples in it (on its
    dense output, built if it was not), and each load at its end, searched around the sample before it
    where that one is a local maximum (``kernel_loads.sample_loads``: at the step's end the derivative is
    known, ``f_new``, and stage 2 reads the accelerations from it); the step in ``buffer`` stays for the
    next step, which takes the other."""
    if RECORDING and rec.shape[0] > 0 and rec[0].next_sample <= t_new:
        _ensure_dense(dense_ready, stage, t_old, h, y, y_new, f_new, coef, K, F, tmp, p, table, out)
        record_step(stage, t_new, t_old, h, y, F, tmp, rec, motion)
    if LOADS and track:
        keep_step(buffer, t_old, h, t_new, y, y_new, live_y, live_t, built)
        out.evaluations += 1 if stage == SLIDE else 0
        sample_loads(t_new, loads_after_step(stage, y_new, f_new, p), buffer, recent, best, stage, K2, live_y, live_t,
                     dense, built, load_tmp, coef, p, table, out)


@internal(inline="always")
def _step(stage, t, y, f, h_abs, t_bound, coef, rtol, atol, K, y_new, f_new, tmp, p, table, out):
    """One accepted DOP853 step from (t, y), y' = f, trying ``h_abs`` first: its stages in ``K``, its end
    in ``y_new`` and ``f_new``.

    scipy's step-size control: a step whose error norm exceeds 1 is taken again smaller (a step
    with a non-finite trial stage, five times smaller), and an accepted one sets the next size
    from its error, no larger after a rejection. Returns ``(accepted, t_new, h, h_abs)``: the step
    taken and the size to try next; not accepted when the size fell below the resolution of t
    (the stretch ``FAILED``).
    """
    exponent = -1.0 / (ERROR_ORDER + 1)
    min_step = 10.0 * abs(np.nextafter(t, math.inf) - t)
    if h_abs < min_step:
        h_abs = min_step
    rejected = False
    while True:
        if h_abs < min_step:
            return False, t, 0.0, h_abs
        t_new = t + h_abs
        if t_new > t_bound:
            t_new = t_bound
        h = t_new - t
        h_abs = abs(h)
        rk_step(stage, t, y, f, h, coef, K, y_new, f_new, tmp, p, table)
        out.evaluations += N_STAGES
        error = error_norm(h, y, y_new, K, coef, rtol, atol)
        if error < 1.0:
            factor = MAX_FACTOR if error == 0.0 else min(MAX_FACTOR, SAFETY * error ** exponent)
            if rejected:
                factor = min(1.0, factor)
            return True, t_new, h, h_abs * factor
        if math.isfinite(error):
            h_abs *= max(MIN_FACTOR, SAFETY * error ** exponent)
        else:   # a non-finite trial stage (e.g. past the sling's reach): shrink hard
            h_abs *= MIN_FACTOR
        rejected = True


@internal
def _ensure_dense(dense_ready, stage, t_old, h, y, y_new, f_new, coef, K, F, tmp, p, table, out):
    """The step's dense output in ``F``, built on first need (three more evaluations); returns True."""
    if not dense_ready:
        dense_prepare(stage, t_old, h, y, y_new, f_new, coef, K, F, tmp, p, table)
        out.evaluations += 3
    return True


@internal(inline="always")
def _locate_events(stage, ne, t_old, t_new, h, y, y_new, f_new, previous, rates, behind, coef, K, F, tmp, y_root,
                   apex_t, apex_y, p, table, out):
    """The events' counted roots on the accepted step [t_old, t_new], from each event's values and rates
    at its ends (``previous`` and ``rates``: at its start; updated to its end).

    Returns ``(hit_t, hit_k, n_apex, dense_ready)``: the terminal root that ends the step and its event
    (``stages.first_event``; -1: none), the counted apex roots written into ``apex_t``, ``apex_y``, and
    whether the step's dense output was built (``_ensure_dense``).
    """
    dense_ready = False
    hit_t, hit_k = math.inf, -1
    n_apex = 0
    offset = rate_offset(h)
    tangent_state(y_new, f_new, offset, behind)
    for k in range(ne):
        after = event_value(stage, k, y_new, p)
        direction = event_direction(stage, k)
        before, rate_before = previous[k], rates[k]
        rate_after = (event_rate(after, event_value(stage, k, behind, p), offset) if event_turns(stage, k)
                      else math.nan)   # (a rate only where turns are searched)
        previous[k], rates[k] = after, rate_after
        start, v_start, end, v_end = t_old, before, t_new, after
        if leaves_zero(before, after):
            dense_ready = _ensure_dense(dense_ready, stage, t_old, h, y, y_new, f_new, coef, K, F, tmp, p, table, out)
            start, v_start, end, v_end = _probe_zero_start(stage, k, t_old, t_new, h, before, after, y, F, tmp, p,
                                                           out)
        elif turns_back(before, after, rate_before, rate_after):
            dense_ready = _ensure_dense(dense_ready, stage, t_old, h, y, y_new, f_new, coef, K, F, tmp, p, table, out)
            start, v_start, end, v_end = _search_turn(stage, k, t_old, t_new, h, before, after, rate_before,
                                                      rate_after, direction, y, F, tmp, p, out)
        if counted_crossing(v_start, v_end, direction):
            dense_ready = _ensure_dense(dense_ready, stage, t_old, h, y, y_new, f_new, coef, K, F, tmp, p, table, out)
            hit_t, hit_k, n_apex = _roots(stage, k, start, v_start, end, v_end, direction, after, t_old, t_new, h,
                                          hit_t, hit_k, n_apex, y, F, tmp, y_root, apex_t, apex_y, p)
    return hit_t, hit_k, n_apex, dense_ready


@internal
def _probe_zero_start(stage, k, t_old, t_new, h, before, after, y, F, tmp, p, out):
    """The bracket ``(start, v_start, end, v_end)`` of event ``k``, which left exactly zero at the step's
    start: did it come back within the step? Its dense output probed (``sequence.probe_update``)."""
    i, low, v_low, high, v_high = 1, -1, math.nan, -1, math.nan
    while i < ZERO_START_PROBES:
        v_probe = event_at(probe_time(t_old, t_new, i), stage, k, t_old, h, y, F, tmp, p)
        out.evaluations += 1
        i, low, v_low, high, v_high = probe_update(i, v_probe, after, low, v_low, high, v_high)
    return probe_bracket(t_old, t_new, before, after, low, v_low, high, v_high)


@internal
def _search_turn(stage, k, t_old, t_new, h, before, after, rate_before, rate_after, direction, y, F, tmp, p, out):
    """The bracket ``(start, v_start, end, v_end)`` of event ``k``, whose value turned back within the
    step: its extremum searched for a value across zero (``sequence.turn_search`` and the rest)."""
    u = turn_first(t_old, t_new, rate_before, rate_after)
    v = event_at(u, stage, k, t_old, h, y, F, tmp, p)
    out.evaluations += 1
    search = turn_search(t_old, t_new, before, after, u, v)
    while True:
        done, u_next, search = turn_next(search, before, v)
        if done:
            break
        u = u_next
        v = event_at(u, stage, k, t_old, h, y, F, tmp, p)
        out.evaluations += 1
        search = turn_update(search, before, u, v)
    return turn_bracket(t_old, t_new, before, after, u, v, direction)


@internal
def _roots(stage, k, start, v_start, end, v_end, direction, after, t_old, t_new, h, hit_t, hit_k, n_apex, y, F, tmp,
           y_root, apex_t, apex_y, p):
    """Event ``k``'s counted roots in the bracket ``[start, end]`` of the step, by Brent's method on its
    dense output (built): a terminal one that counts ends the step (``stages.first_event`` against the
    ``(hit_t, hit_k)`` so far); an apex is kept (``apex_t``, ``apex_y``: at most four a step); a root
    that does not count is stepped past and the rest of the step searched again.

    Returns ``(hit_t, hit_k, n_apex)``.
    """
    while counted_crossing(v_start, v_end, direction):
        if v_end == 0.0:
            t_root = end
        else:
            t_root = brent(stage, k, start, end, v_start, v_end, t_old, h, y, F, tmp, p)
        dense_eval(t_root, t_old, h, y, F, y_root)
        if event_armed(stage, k, y_root, p):
            if event_terminal(stage, k):
                hit_t, hit_k = first_event(t_root, k, hit_t, hit_k)
                return hit_t, hit_k, n_apex
            if n_apex < 4:
                apex_t[n_apex], apex_y[n_apex] = t_root, y_root[FLIGHT_Y]
                n_apex += 1
        # Not counted: look for a later root in the same step, past this one.
        start = past_root(t_root, t_new)
        if start >= t_new:
            break
        v_start = event_at(start, stage, k, t_old, h, y, F, tmp, p)
        end, v_end = t_new, after
    return hit_t, hit_k, n_apex


# --------------------------------------------------------------------------- #
# A whole shot
# --------------------------------------------------------------------------- #

@internal
def params(P):
    """The ``Params`` of a design row, as a record over the row itself (``parameters.PARAMS_DTYPE``):
    read in place, and passed to each function as one pointer."""
    return P.view(PARAMS_DTYPE)[0]


@internal
def _step_failed(out, code, stage):
    """Record a stage whose integration failed (``code``: ``FAILED`` or ``OUT_OF_STEPS``)."""
    out.status, out.detail = STEP_FAILED, stage
    out.out_of_steps = code == OUT_OF_STEPS


@internal(allocates=True)
def _run_stage(stage, t, y, switches, coef, rtol, atol, p, table, peaks, track_loads, out, rec, motion):
    """Integrate ``stage`` from (t, y) in stretches, switching the friction modes between them,
    until ``analytic.sequence.stretch_end`` says the stage is over.

    Returns ``(action, status, detail, switches, t, y)`` at its end (``out.end_time``); a step
    failure is recorded in ``out`` (``_step_failed``). A recording (``rec``) gets each
    stretch's samples (``integrate``) and the stage's last.
    """
    while True:
        code, t, y, _ = integrate(stage, t, y, p.t_limit, coef, rtol, atol, p, table, out, peaks, track_loads,
                                  rec, motion)
        action, status, detail = stretch_end(stage, code, switches)
        if not FRICTION or action != SWITCH_MODE:   # (only friction's events switch modes)
            break
        switches += 1
        switch_mode(stage, code, y, p)
    out.end_time = t
    if RECORDING and rec.shape[0] > 0:
        record_last(t, stage, y, rec, motion)
    if status == STEP_FAILED:
        _step_failed(out, code, stage)
    return action, status, detail, switches, t, y


@internal(inline="always")
def _clear(out):
    """A result record before the shot: nothing reached (NaN), nothing counted."""
    out.status, out.detail, out.steps, out.evaluations = 0, 0, 0, 0
    out.liftoff_time, out.release_time = math.nan, math.nan
    position, velocity = out.release_position, out.release_velocity
    position[0], position[1], velocity[0], velocity[1] = math.nan, math.nan, math.nan, math.nan
    out.frame_release_displacement, out.frame_release_velocity = math.nan, math.nan
    out.landing_time, out.landing_x, out.apex_height = math.nan, math.nan, math.nan
    out.end_time, out.rest_acceleration = math.nan, math.nan
    out.out_of_steps = False
    peaks = out.peaks
    for k in range(N_LOADS):
        peaks[k, 0], peaks[k, 1] = math.nan, math.nan


@internal(inline="always", allocates=True)
def shot(P, table, coef, rtol, atol, track_loads, out, rec, motion):
    """Simulate the design row ``P`` through all three stages into the result record ``out``
    (``RESULT_DTYPE``).

    Not compiled by itself: ``shots`` is the one entry point, and this is
    inlined into it, which spares a second optimisation of the whole shot.

    The stages and their ends are those of ``analytic.reference.simulate``;
    ``out.status`` names how it ended and the other fields hold what was
    reached (NaN otherwise). ``track_loads`` False leaves the peak loads NaN
    (the benchmark measures what finding them costs). A non-empty ``rec`` records the
    motion into ``motion`` (``integrate``; ``analytic.fast.motion.simulate_motion`` reads it).
    """
    _clear(out)
    p = params(P)
    ddtheta0, normal0 = fires(p)
    if not (math.isfinite(ddtheta0) and math.isfinite(normal0)):
        # The equations cannot be evaluated even at rest (``analytic.reference.simulate``).
        out.end_time, out.evaluations = 0.0, 1
        _step_failed(out, FAILED, SLIDE)
        return
    if not ddtheta0 < 0.0:
        out.status, out.rest_acceleration, out.end_time = NEVER_FIRES, ddtheta0, 0.0
        out.evaluations = 1
        return
    peaks = np.empty((N_LOADS, 2))
    for k in range(N_LOADS):
        peaks[k, 0], peaks[k, 1] = -math.inf, -math.inf
    action, status, detail, switches, t2, y2 = _slide_and_swing(normal0, p, table, coef, rtol, atol, peaks,
                                                                track_loads, out, rec, motion)
    if action == FINISHED:
        if status != STEP_FAILED:   # (a step failure is recorded by _run_stage)
            out.status = status
            if status == NEVER_LIFTS_OFF:
                out.detail = detail
            _write_peaks(peaks, out)
        return
    x, y, vx, vy = flight_start(y2, p)
    if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(vx) and math.isfinite(vy)):
        _step_failed(out, FAILED, FLIGHT)
        return
    out.release_time = t2
    position, velocity = out.release_position, out.release_velocity
    position[0], position[1], velocity[0], velocity[1] = x, y, vx, vy
    out.frame_release_displacement, out.frame_release_velocity = frame_state(y2, p)
    _write_peaks(peaks, out)
    _flight(t2, x, y, vx, vy, switches, p, table, coef, rtol, atol, peaks, out, rec, motion)


@internal(inline="always", allocates=True)
def _slide_and_swing(normal0, p, table, coef, rtol, atol, peaks, track_loads, out, rec, motion):
    """Stage 1, the slide on the base until the normal force vanishes (none where the base's push at
    rest, ``normal0``, is not positive), and stage 2, the free swing until release
    (``analytic.sequence``: what each stretch's end means, for both paths).

    Returns ``_run_stage``'s ``(action, status, detail, switches, t, y)`` of the last stage run;
    ``out`` gets the lift-off and the counts.
    """
    y1 = np.empty(state_size(SLIDE, p))
    slide_start(p, y1)
    switches, action, status, detail, t1, t2, y2 = 0, NEXT_STAGE, 0, 0, 0.0, 0.0, y1
    if normal0 <= 0.0 and RECORDING and rec.shape[0] > 0:   # the sling already pulls harder than the projectile's weight
        record_row(0.0, SLIDE, y1, rec, motion)
    if normal0 > 0.0:   # else the sling already pulls harder than the projectile's weight
        action, status, detail, switches, t1, y1 = _run_stage(SLIDE, 0.0, y1, switches, coef, rtol, atol, p, table,
                                                              peaks, track_loads, out, rec, motion)
    if action == NEXT_STAGE:
        out.liftoff_time = t1
        y2 = np.empty(state_size(SWING, p))
        swing_start(y1, p, y2)
        action, status, detail, switches, t2, y2 = _run_stage(SWING, t1, y2, switches, coef, rtol, atol, p, table,
                                                              peaks, track_loads, out, rec, motion)
    return action, status, detail, switches, t2, y2


@internal(inline="always", allocates=True)
def _flight(t2, x, y, vx, vy, switches, p, table, coef, rtol, atol, peaks, out, rec, motion):
    """Stage 3: the flight from its release at ``t2`` (the projectile at (x, y), moving at (vx, vy))
    until it lands or its time runs out (``limits.flight_time_limit``); ``out`` gets how it ended."""
    t_max = t2 + flight_time_limit(y + p.h - p.yt, vy, p.g)   # (the height above the target)
    y_release = np.empty(4)
    y_release[FLIGHT_X], y_release[FLIGHT_Y], y_release[FLIGHT_VX], y_release[FLIGHT_VY] = x, y, vx, vy
    if RECORDING and rec.shape[0] > 0:
        rec[0].flight_spacing = max(rec[0].flight_spacing, (t_max - t2) / rec[0].sample_limit)
    if lands_at_release(y + p.h - p.yt, vy):
        code, t3, y3, apex = FLIGHT_LANDING, t2, y_release, -math.inf
    else:
        code, t3, y3, apex = integrate(FLIGHT, t2, y_release, t_max, coef, rtol, atol, p, table, out, peaks, False,
                                       rec, motion)
    if RECORDING and rec.shape[0] > 0:
        record_last(t3, FLIGHT, y3, rec, motion)
    out.end_time = t3
    _, status, _ = stretch_end(FLIGHT, code, switches)
    if status == STEP_FAILED:
        _step_failed(out, code, FLIGHT)
        return
    if status != OK:
        out.status = status
        return
    apex_height = max(y, apex) + p.h
    if short_of_target(apex_height, p.yt):   # its end is its apex, to the root
        out.status, out.apex_height = SHORT_OF_TARGET, max(apex_height, y3[FLIGHT_Y] + p.h)
        return
    out.status = status
    out.landing_time, out.landing_x, out.apex_height = t3, y3[FLIGHT_X], apex_height


@internal
def _write_peaks(peaks, out):
    """The peak loads found (``peaks``, (N_LOADS, 2)) into the result record."""
    found = out.peaks
    for k in range(N_LOADS):
        found[k, 0], found[k, 1] = peaks[k, 0], peaks[k, 1]


@entry
def shots(designs, start, stop, table, coef, rtol, atol, track_loads, out, rec, motion):
    """``shot`` for rows ``start:stop`` of ``designs`` (S, N_PARAMS) into those of ``out`` (S,) of
    ``RESULT_DTYPE``.

    The one compiled entry point. It releases the GIL (``nogil``), so
    ``analytic.fast`` runs several calls at once on Python threads, each on
    its own rows. ``track_loads`` False leaves the peak loads NaN. ``rec`` (``RECORDING_DTYPE``)
    and ``motion`` (``SAMPLE_DTYPE``) record one shot's motion (``shot``; empty: none).
    """
    for i in range(start, stop):
        shot(designs[i], table, coef, rtol, atol, track_loads, out[i], rec, motion)
