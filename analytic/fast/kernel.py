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

Designs arrive as rows laid out as ``analytic.parameters.Params``; results
leave as rows laid out by the index constants below (``analytic.fast`` reads
them).
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
                               REACHED_END, STEP_FAILED, SWITCH_MODE, counted_crossing, event_rate, lands_at_release,
                               leaves_zero, past_root, probe_bracket, probe_time, probe_update, rate_offset,
                               stretch_end, tangent_state, turn_bracket, turn_first, turn_next, turn_search,
                               turn_update, turns_back)
from analytic.stages import (FLIGHT, SLIDE, SWING, ZERO_START_PROBES, event_armed, event_count,
                             event_direction, event_terminal, event_turns, event_value, fires, first_event,
                             flight_start, frame_state, loads_after_step, loads_at, slide_start, state_size, swing_start,
                             switch_mode)


# Layout of a result row.
(STATUS, DETAIL, LIFTOFF_T, RELEASE_T, RELEASE_X, RELEASE_Y, RELEASE_VX, RELEASE_VY,
 LANDING_T, LANDING_X, APEX, END_T, VALUE, STEPS, EVALS, FRAME_X, FRAME_V) = range(17)
#: Where the peak loads start: value then time of each of ``stages.LOAD_NAMES`` in order.
PEAKS = 17
N_RESULT = PEAKS + 2 * N_LOADS
# STATUS holds ``Status.code``; DETAIL, for NEVER_LIFTS_OFF, a ``LiftoffFailure``
# and for STEP_FAILED the stage; VALUE, for NEVER_FIRES, the arm's acceleration at rest,
# and for STEP_FAILED 1 if the stage ran out of steps (``STAGE_STEP_LIMITS``);
# FRAME_X, FRAME_V the frame's displacement and velocity at release (0 when fixed);
# PEAKS + 2 i and PEAKS + 2 i + 1 the largest load i over stages 1-2 and its time
# (NaN for a machine that never fires, or a step failure).


# Layout of ``rec``, the state of a recording (``shots``' motion): the next sample's time, the
# rows written so far (-1: the buffer ran out), the spacing of stages 1-2's and the flight's
# samples, and the most samples a flight gets (its spacing widens to keep within them). A row
# of ``motion`` is the time, the stage, then the stage's state (``MAX_STATE``).
NEXT_SAMPLE, ROWS, SPACING, FLIGHT_SPACING, SAMPLE_LIMIT = range(5)
#: Columns of a recorded sample: time, stage, and the longest state (stage 2 with friction).
MAX_STATE = 12
SAMPLE_WIDTH = 2 + MAX_STATE


@internal
def record_row(t, stage, y, rec, motion):
    """Append the sample (t, stage, y) to ``motion``; past its end mark the recording lost (ROWS -1)."""
    row = int(rec[ROWS])
    if row < 0:
        return
    if row >= motion.shape[0] or y.shape[0] > MAX_STATE:
        rec[ROWS] = -1.0
        return
    motion[row, 0], motion[row, 1] = t, stage
    for j in range(y.shape[0]):
        motion[row, 2 + j] = y[j]
    for j in range(y.shape[0], MAX_STATE):
        motion[row, 2 + j] = math.nan
    rec[ROWS] = row + 1.0


@internal
def record_step(stage, t_end, t_old, h, y_old, F, tmp, rec, motion):
    """Record the samples of the grid (``rec[NEXT_SAMPLE]``, spaced by the stage's spacing) up to
    ``t_end`` on the step's interpolant (``F``, prepared)."""
    spacing = rec[FLIGHT_SPACING] if stage == FLIGHT else rec[SPACING]
    while rec[NEXT_SAMPLE] <= t_end:
        dense_eval(rec[NEXT_SAMPLE], t_old, h, y_old, F, tmp)
        record_row(rec[NEXT_SAMPLE], stage, tmp, rec, motion)
        rec[NEXT_SAMPLE] += spacing


@internal(allocates=True)
def integrate(stage, t0, y0, t_bound, coef, rtol, atol, p, table, counts, peaks, track_loads, rec, motion):
    """Integrate ``stage`` from (t0, y0) until a terminal event or ``t_bound``, each event's roots found
    from its values and rates at each step's ends (``analytic.sequence``).

    Returns ``(code, t_end, y_end, apex)``: code is the index of the terminal
    event that ended it, ``REACHED_END``, ``FAILED`` (step size underflow
    or a non-finite state) or ``OUT_OF_STEPS`` (the stage's ``STAGE_STEP_LIMITS``
    accepted steps without reaching ``t_bound``); apex is the largest y[1] at a counted apex root
    (flight only; -inf if none). ``counts`` accumulates [steps, evaluations].
    A non-empty ``rec`` records the motion into ``motion``: the start, then a grid from it,
    each sample read off its step's interpolant (``record_step``; the stage's last is
    ``shot``'s). The grids are ``analytic.reference``'s: each stretch starts its own.
    In stages 1 and 2 with ``track_loads``, ``peaks`` (N_LOADS, 2) gets the
    largest of each load (``stages.loads_at``) and its time, where this stretch
    beats it: sampled at every step's end and refined on the interpolants
    beside each local maximum of the samples, as ``analytic.reference`` does.
    """
    n = y0.shape[0]
    ne = event_count(stage, p)
    if RECORDING and rec.shape[0] > 0:   # (a stage's first stretch after another stage: lift-off again, which the reader drops)
        record_row(t0, stage, y0, rec, motion)
        rec[NEXT_SAMPLE] = t0 + (rec[FLIGHT_SPACING] if stage == FLIGHT else rec[SPACING])
    K2 = np.empty((2, N_STAGES + 4, n))   # the last two steps' stages, alternately
    K = K2[0]
    F = np.empty((7, n))
    y, y_new = np.empty(n), np.empty(n)
    for j in range(n):
        y[j] = y0[j]
    f, f_new = np.empty(n), np.empty(n)
    tmp, y_root, behind = np.empty(n), np.empty(n), np.empty(n)
    previous, rates = np.empty(ne), np.empty(ne)   # each event's value and rate at the step's start
    derivative_call(stage, y, p, table, f)
    for k in range(ne):
        previous[k] = event_value(stage, k, y, p)
        rates[k] = math.nan   # none at the stretch's start: its first step is not searched for turns (sequence)
    t = t0
    h_abs = initial_step(stage, t0, y, f, t_bound, rtol, atol, p, table)
    counts[1] += 2
    if not math.isfinite(h_abs):
        # A non-finite start or derivative: a NaN step would be shrunk forever.
        return FAILED, t, y, -math.inf
    apex = -math.inf
    apex_t, apex_y = np.empty(4), np.empty(4)   # counted apex roots within one step
    track = track_loads and stage != FLIGHT
    # Filled by loops: numba compiles np.full and np.zeros into a function per
    # shape and type (about a second of a cold compile in all, measured).
    # The peak loads' state (``analytic.fast.kernel_loads``): the last two samples, the stretch's
    # largest, and the last two steps with their interpolants.
    buffers = 2 if LOADS and track else 0
    recent, best = np.empty((2, N_LOADS + 1)), np.empty((N_LOADS, 2))
    live_y, live_t = np.empty((buffers, 2, n)), np.empty((buffers, 3))
    dense, built, load_tmp = np.empty((buffers, 7, n)), np.empty(buffers, dtype=np.bool_), np.empty(n)
    if LOADS and track:
        start_peaks(recent, best, built)
        sample_loads(t0, loads_at(stage, y, p), -1, recent, best, stage, K2, live_y, live_t, dense, built, load_tmp,
                     coef, p, table, counts)
        counts[1] += 1
    exponent = -1.0 / (ERROR_ORDER + 1)
    steps = 0
    while t < t_bound:
        if steps == STAGE_STEP_LIMITS[stage]:
            return OUT_OF_STEPS, t, y, apex
        buffer = steps % 2
        K = K2[buffer]
        min_step = 10.0 * abs(np.nextafter(t, math.inf) - t)
        if h_abs < min_step:
            h_abs = min_step
        rejected = False
        while True:
            if h_abs < min_step:
                return FAILED, t, y, apex
            t_new = t + h_abs
            if t_new > t_bound:
                t_new = t_bound
            h = t_new - t
            h_abs = abs(h)
            rk_step(stage, t, y, f, h, coef, K, y_new, f_new, tmp, p, table)
            counts[1] += N_STAGES
            error = error_norm(h, y, y_new, K, coef, rtol, atol)
            if error < 1.0:
                factor = MAX_FACTOR if error == 0.0 else min(MAX_FACTOR, SAFETY * error ** exponent)
                if rejected:
                    factor = min(1.0, factor)
                h_abs *= factor
                break
            if math.isfinite(error):
                h_abs *= max(MIN_FACTOR, SAFETY * error ** exponent)
            else:   # a non-finite trial stage (e.g. past the sling's reach): shrink hard
                h_abs *= MIN_FACTOR
            rejected = True
        counts[0] += 1
        steps += 1
        for j in range(n):
            if not math.isfinite(y_new[j]):
                return FAILED, t_new, y_new, apex
        t_old = t

        # Events on the accepted step [t_old, t_new], from their values and rates at its ends.
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
                # Left zero at the step's start: did it come back within the step?
                if not dense_ready:
                    dense_prepare(stage, t_old, h, y, y_new, f_new, coef, K, F, tmp, p, table)
                    counts[1] += 3
                    dense_ready = True
                i, low, v_low, high, v_high = 1, -1, math.nan, -1, math.nan
                while i < ZERO_START_PROBES:
                    v_probe = event_at(probe_time(t_old, t_new, i), stage, k, t_old, h, y, F, tmp, p)
                    counts[1] += 1
                    i, low, v_low, high, v_high = probe_update(i, v_probe, after, low, v_low, high, v_high)
                start, v_start, end, v_end = probe_bracket(t_old, t_new, before, after, low, v_low, high, v_high)
            elif turns_back(before, after, rate_before, rate_after):
                # Turned back within the step: search its extremum for a value across zero.
                if not dense_ready:
                    dense_prepare(stage, t_old, h, y, y_new, f_new, coef, K, F, tmp, p, table)
                    counts[1] += 3
                    dense_ready = True
                u = turn_first(t_old, t_new, rate_before, rate_after)
                v = event_at(u, stage, k, t_old, h, y, F, tmp, p)
                counts[1] += 1
                search = turn_search(t_old, t_new, before, after, u, v)
                while True:
                    done, u_next, search = turn_next(search, before, v)
                    if done:
                        break
                    u = u_next
                    v = event_at(u, stage, k, t_old, h, y, F, tmp, p)
                    counts[1] += 1
                    search = turn_update(search, before, u, v)
                start, v_start, end, v_end = turn_bracket(t_old, t_new, before, after, u, v, direction)
            while counted_crossing(v_start, v_end, direction):
                if not dense_ready:
                    dense_prepare(stage, t_old, h, y, y_new, f_new, coef, K, F, tmp, p, table)
                    counts[1] += 3
                    dense_ready = True
                if v_end == 0.0:
                    t_root = end
                else:
                    t_root = brent(stage, k, start, end, v_start, v_end, t_old, h, y, F, tmp, p)
                dense_eval(t_root, t_old, h, y, F, y_root)
                if event_armed(stage, k, y_root, p):
                    if event_terminal(stage, k):
                        hit_t, hit_k = first_event(t_root, k, hit_t, hit_k)
                        break
                    if n_apex < 4:
                        apex_t[n_apex], apex_y[n_apex] = t_root, y_root[1]
                        n_apex += 1
                # Not counted: look for a later root in the same step, past this one.
                start = past_root(t_root, t_new)
                if start >= t_new:
                    break
                v_start = event_at(start, stage, k, t_old, h, y, F, tmp, p)
                end, v_end = t_new, after
        for i in range(n_apex):
            if apex_t[i] <= hit_t:
                apex = max(apex, apex_y[i])
        if hit_k >= 0:
            y_hit = np.empty(n)
            dense_eval(hit_t, t_old, h, y, F, y_hit)
            if RECORDING and rec.shape[0] > 0:
                record_step(stage, hit_t, t_old, h, y, F, tmp, rec, motion)
            if LOADS and track:
                keep_step(buffer, t_old, h, hit_t, y, y_new, live_y, live_t, built)
                counts[1] += 1
                sample_loads(hit_t, loads_at(stage, y_hit, p), buffer, recent, best, stage, K2, live_y, live_t, dense,
                             built, load_tmp, coef, p, table, counts)
                finish_peaks(buffer, recent, best, peaks, stage, K2, live_y, live_t, dense, built, load_tmp, coef, p,
                             table, counts)
            return hit_k, hit_t, y_hit, apex
        if RECORDING and rec.shape[0] > 0 and rec[NEXT_SAMPLE] <= t_new:
            if not dense_ready:
                dense_prepare(stage, t_old, h, y, y_new, f_new, coef, K, F, tmp, p, table)
                counts[1] += 3
            record_step(stage, t_new, t_old, h, y, F, tmp, rec, motion)
        if LOADS and track:   # at the step's end the derivative is known (f_new): stage 2 reads the accelerations
            keep_step(buffer, t_old, h, t_new, y, y_new, live_y, live_t, built)
            counts[1] += 1 if stage == SLIDE else 0
            sample_loads(t_new, loads_after_step(stage, y_new, f_new, p), buffer, recent, best, stage, K2, live_y,
                         live_t, dense, built, load_tmp, coef, p, table, counts)
        t = t_new
        for j in range(n):
            y[j] = y_new[j]
            f[j] = f_new[j]
    if LOADS and track:
        finish_peaks((steps - 1) % 2 if steps > 0 else -1, recent, best, peaks, stage, K2, live_y, live_t, dense,
                     built, load_tmp, coef, p, table, counts)
    return REACHED_END, t, y, apex


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
    out[STATUS], out[DETAIL] = STEP_FAILED, stage
    out[VALUE] = 1.0 if code == OUT_OF_STEPS else 0.0


@internal(allocates=True)
def _run_stage(stage, t, y, switches, coef, rtol, atol, p, table, counts, peaks, track_loads, out, rec, motion):
    """Integrate ``stage`` from (t, y) in stretches, switching the friction modes between them,
    until ``analytic.sequence.stretch_end`` says the stage is over.

    Returns ``(action, status, detail, switches, t, y)`` at its end (``out[END_T]``); a step
    failure is recorded in ``out`` (``_step_failed``). A recording (``rec``) gets each
    stretch's samples (``integrate``) and the stage's last.
    """
    while True:
        code, t, y, _ = integrate(stage, t, y, p.t_limit, coef, rtol, atol, p, table, counts, peaks, track_loads,
                                  rec, motion)
        action, status, detail = stretch_end(stage, code, switches)
        if not FRICTION or action != SWITCH_MODE:   # (only friction's events switch modes)
            break
        switches += 1
        switch_mode(stage, code, y, p)
    out[END_T] = t
    if RECORDING and rec.shape[0] > 0 and rec[ROWS] > 0 and motion[int(rec[ROWS]) - 1, 0] < t:
        record_row(t, stage, y, rec, motion)
    if status == STEP_FAILED:
        _step_failed(out, code, stage)
    return action, status, detail, switches, t, y


@internal(inline="always", allocates=True)
def shot(P, table, coef, rtol, atol, track_loads, out, rec, motion):
    """Simulate the design row ``P`` through all three stages into the result row ``out``.

    Not compiled by itself: ``shots`` is the one entry point, and this is
    inlined into it, which spares a second optimisation of the whole shot.

    The stages and their ends are those of ``analytic.reference.simulate``;
    ``out[STATUS]`` names how it ended and the other entries hold what was
    reached (NaN otherwise). ``track_loads`` False leaves the peak loads NaN
    (the benchmark measures what finding them costs). A non-empty ``rec`` records the
    motion into ``motion`` (``integrate``; ``analytic.fast.motion.simulate_motion`` reads it).
    """
    for i in range(N_RESULT):
        out[i] = math.nan
    counts = np.empty(2)
    counts[0], counts[1] = 0.0, 0.0
    p = params(P)
    ddtheta0, normal0 = fires(p)
    if not (math.isfinite(ddtheta0) and math.isfinite(normal0)):
        # The equations cannot be evaluated even at rest (``analytic.reference.simulate``).
        out[END_T], out[STEPS], out[EVALS] = 0.0, 0.0, 1.0
        _step_failed(out, FAILED, SLIDE)
        return
    if not ddtheta0 < 0.0:
        out[STATUS], out[VALUE], out[END_T] = NEVER_FIRES, ddtheta0, 0.0
        out[STEPS], out[EVALS] = 0.0, 1.0
        return

    # Stage 1: slide on the base until the normal force vanishes; stage 2: free swing until
    # release (``analytic.sequence``: what each stretch's end means, for both paths).
    peaks = np.empty((N_LOADS, 2))
    for k in range(N_LOADS):
        peaks[k, 0], peaks[k, 1] = -math.inf, -math.inf
    y1 = np.empty(state_size(SLIDE, p))
    slide_start(p, y1)
    switches, action, status, detail, t1, t2, y2 = 0, NEXT_STAGE, 0, 0, 0.0, 0.0, y1
    if normal0 <= 0.0 and RECORDING and rec.shape[0] > 0:   # the sling already pulls harder than the projectile's weight
        record_row(0.0, SLIDE, y1, rec, motion)
    if normal0 > 0.0:   # else the sling already pulls harder than the projectile's weight
        action, status, detail, switches, t1, y1 = _run_stage(SLIDE, 0.0, y1, switches, coef, rtol, atol, p, table,
                                                              counts, peaks, track_loads, out, rec,
                                                              motion)
    if action == NEXT_STAGE:
        out[LIFTOFF_T] = t1
        y2 = np.empty(state_size(SWING, p))
        swing_start(y1, p, y2)
        action, status, detail, switches, t2, y2 = _run_stage(SWING, t1, y2, switches, coef, rtol, atol, p, table,
                                                              counts, peaks, track_loads, out, rec,
                                                              motion)
    out[STEPS], out[EVALS] = counts[0], counts[1]
    if action == FINISHED:
        if status != STEP_FAILED:   # (a step failure is recorded by _run_stage)
            out[STATUS] = status
            if status == NEVER_LIFTS_OFF:
                out[DETAIL] = detail
            _write_peaks(peaks, out)
        return
    x, y, vx, vy = flight_start(y2, p)
    if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(vx) and math.isfinite(vy)):
        _step_failed(out, FAILED, FLIGHT)
        return
    out[RELEASE_T], out[RELEASE_X], out[RELEASE_Y], out[RELEASE_VX], out[RELEASE_VY] = t2, x, y, vx, vy
    out[FRAME_X], out[FRAME_V] = frame_state(y2, p)
    _write_peaks(peaks, out)

    # Stage 3: flight.
    t_max = t2 + flight_time_limit(y + p.h, vy, p.g)
    y_release = np.empty(4)
    y_release[0], y_release[1], y_release[2], y_release[3] = x, y, vx, vy
    if RECORDING and rec.shape[0] > 0:
        rec[FLIGHT_SPACING] = max(rec[FLIGHT_SPACING], (t_max - t2) / rec[SAMPLE_LIMIT])
    if lands_at_release(y + p.h, vy):
        code, t3, y3, apex = 0, t2, y_release, -math.inf   # (0: the landing event)
    else:
        code, t3, y3, apex = integrate(FLIGHT, t2, y_release, t_max, coef, rtol, atol,
                                       p, table, counts, peaks, False, rec, motion)
    if RECORDING and rec.shape[0] > 0 and rec[ROWS] > 0 and motion[int(rec[ROWS]) - 1, 0] < t3:
        record_row(t3, FLIGHT, y3, rec, motion)
    out[STEPS], out[EVALS], out[END_T] = counts[0], counts[1], t3
    _, status, _ = stretch_end(FLIGHT, code, switches)
    if status == STEP_FAILED:
        _step_failed(out, code, FLIGHT)
        return
    out[STATUS] = status
    if status != OK:
        return
    out[LANDING_T], out[LANDING_X], out[APEX] = t3, y3[0], max(y, apex) + p.h


@internal
def _write_peaks(peaks, out):
    for k in range(N_LOADS):
        out[PEAKS + 2 * k], out[PEAKS + 2 * k + 1] = peaks[k, 0], peaks[k, 1]


@entry
def shots(designs, start, stop, table, coef, rtol, atol, track_loads, out, rec, motion):
    """``shot`` for rows ``start:stop`` of ``designs`` (S, N_PARAMS) into those of ``out`` (S, N_RESULT).

    The one compiled entry point. It releases the GIL (``nogil``), so
    ``analytic.fast`` runs several calls at once on Python threads, each on
    its own rows. ``track_loads`` False leaves the peak loads NaN. ``rec`` and
    ``motion`` record one shot's motion (``shot``; empty: none).
    """
    for i in range(start, stop):
        shot(designs[i], table, coef, rtol, atol, track_loads, out[i], rec, motion)
