"""The compiled shot: the DOP853 integrator with event location, and all three stages, in numba.

The physics is not here: the equations, the stages' right-hand sides and
events and the limits are the model's (``analytic.eom``, ``analytic.stages``,
``analytic.limits``), compiled from the same source the reference path runs
(``analytic.compiled``). What this module adds is the machinery of a whole
shot at compiled speed: an embedded Dormand-Prince 8(5,3) pair with its
7th-order dense output (the algorithm of ``scipy.integrate.DOP853``, whose
published coefficient arrays it is handed at run time), Brent's root finder
on the dense output, and the three stages in sequence (``shot``), for a
range of design rows (``shots``, the one compiled entry point, which
``analytic.fast`` runs on several threads at once).

The entry point is compiled with ``cache=True`` (``analytic.compiled.CALLABLE``):
the first call in a fresh checkout compiles it, with everything it calls,
and writes the machine code to ``__pycache__``; later processes load it from
there. The other functions here are ``analytic.compiled.internal``: compiled
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

import numba
import numpy as np
from numba.np.unsafe.ndarray import to_fixed_tuple

from analytic import limits, peaks, sequence, stages
from analytic.compiled import CALLABLE, internal
from analytic.limits import STAGE_STEP_LIMITS
from analytic.parameters import N_PARAMS, Params
from analytic.sequence import (FAILED, FINISHED, NEVER_FIRES, NEVER_LIFTS_OFF, NEXT_STAGE, OK, OUT_OF_STEPS,
                               REACHED_END, STEP_FAILED, SWITCH_MODE)
from analytic.stages import (FLIGHT, LOAD_NAMES, ROOT_RELATIVE_TOLERANCE, ROOT_TIME_TOLERANCE, SLIDE, SWING,
                             ZERO_START_PROBES)

stages_, limits_, peaks_, sequence_ = stages, limits, peaks, sequence
# The model's functions (compiled where the kernel calls them: ``analytic.compiled.register_model``).
derivative = stages_.derivative
event_value = stages_.event_value
event_direction = stages_.event_direction
event_terminal = stages_.event_terminal
event_armed = stages_.event_armed
event_count = stages_.event_count
first_event = stages_.first_event
fires = stages_.fires
swing_start = stages_.swing_start
slide_start = stages_.slide_start
state_size = stages_.state_size
switch_mode = stages_.switch_mode
flight_start = stages_.flight_start
frame_state = stages_.frame_state
loads_at = stages_.loads_at
loads_after_step = stages_.loads_after_step
search_golden, search_from, search_next, search_update = (peaks_.search_golden, peaks_.search_from,
                                                          peaks_.search_next, peaks_.search_update)
flight_time_limit = limits_.flight_time_limit
stretch_end, counted_crossing, past_root = sequence_.stretch_end, sequence_.counted_crossing, sequence_.past_root
leaves_zero, probe_time, probe_update, probe_bracket = (sequence_.leaves_zero, sequence_.probe_time,
                                                        sequence_.probe_update, sequence_.probe_bracket)


# Layout of a result row.
(STATUS, DETAIL, LIFTOFF_T, RELEASE_T, RELEASE_X, RELEASE_Y, RELEASE_VX, RELEASE_VY,
 LANDING_T, LANDING_X, APEX, END_T, VALUE, STEPS, EVALS, FRAME_X, FRAME_V) = range(17)
#: Where the peak loads start: value then time of each of ``stages.LOAD_NAMES`` in order.
PEAKS = 17
N_LOADS = len(LOAD_NAMES)
N_RESULT = PEAKS + 2 * N_LOADS
# STATUS holds ``Status.code``; DETAIL, for NEVER_LIFTS_OFF, a ``LiftoffFailure``
# and for STEP_FAILED the stage; VALUE, for NEVER_FIRES, the arm's acceleration at rest,
# and for STEP_FAILED 1 if the stage ran out of steps (``STAGE_STEP_LIMITS``);
# FRAME_X, FRAME_V the frame's displacement and velocity at release (0 when fixed);
# PEAKS + 2 i and PEAKS + 2 i + 1 the largest load i over stages 1-2 and its time
# (NaN for a machine that never fires, or a step failure).


# DOP853 step-size control (Hairer, Norsett & Wanner, "Solving Ordinary
# Differential Equations I", 2nd ed., II.4 and II.10; the values scipy uses).
_SAFETY, _MIN_FACTOR, _MAX_FACTOR = 0.9, 0.2, 10.0
_ERROR_ORDER = 7
_N_STAGES = 12


# --------------------------------------------------------------------------- #
# DOP853 with dense output, events located by Brent's method
# --------------------------------------------------------------------------- #
# ``coef`` is ``(A, B, C, E3, E5, D, A_EXTRA, C_EXTRA)``, scipy's DOP853 class
# arrays: stages 0-11 of the 8th-order step, the 5th- and 3rd-order error
# estimators, and the dense output's three extra stages and its 4 x 16 matrix.

@internal
def _rk_step(stage, t, y, f, h, coef, K, y_new, f_new, tmp, p, table):
    """One DOP853 step of size h from (t, y) with y'(t) = f; fills K[0:13].

    The right-hand side is called at two sites, the 11 stages' and the step's
    end (LLVM inlines it at each, ``analytic.compiled.INLINE``): one site in
    the loop for both, through an array chosen at run time, made every shot
    1.1-1.6x as long (the batch of the benchmark's designs on one thread,
    interleaved runs) for a smaller function.
    """
    A, B = coef[0], coef[1]
    n = y.shape[0]
    for j in range(n):
        K[0, j] = f[j]
    for s in range(1, _N_STAGES):
        for j in range(n):
            acc = 0.0
            for q in range(s):
                acc += K[q, j] * A[s, q]
            tmp[j] = y[j] + acc * h
        derivative(stage, tmp, p, table, K[s])
    for j in range(n):
        acc = 0.0
        for q in range(_N_STAGES):
            acc += K[q, j] * B[q]
        y_new[j] = y[j] + h * acc
    derivative(stage, y_new, p, table, f_new)
    for j in range(n):
        K[_N_STAGES, j] = f_new[j]


@internal
def _error_norm(h, y, y_new, K, coef, rtol, atol):
    """DOP853's blended 5th/3rd-order error estimate, scaled by the tolerances (< 1: accept)."""
    E3, E5 = coef[3], coef[4]
    n = y.shape[0]
    err5, err3 = 0.0, 0.0
    for j in range(n):
        scale = atol + max(abs(y[j]), abs(y_new[j])) * rtol
        e5, e3 = 0.0, 0.0
        for q in range(_N_STAGES + 1):
            e5 += K[q, j] * E5[q]
            e3 += K[q, j] * E3[q]
        err5 += (e5 / scale) ** 2
        err3 += (e3 / scale) ** 2
    if err5 == 0.0 and err3 == 0.0:
        return 0.0
    return abs(h) * err5 / math.sqrt((err5 + 0.01 * err3) * n)


@internal
def _rms(x, scale):
    total = 0.0
    for j in range(x.shape[0]):
        total += (x[j] / scale[j]) ** 2
    return math.sqrt(total / x.shape[0])


@internal
def _initial_step(stage, t0, y0, f0, t_bound, rtol, atol, p, table):
    """Starting step: Hairer, Norsett & Wanner (1993), II.4, as in scipy's ``select_initial_step``."""
    interval = abs(t_bound - t0)
    if interval == 0.0:
        return 0.0
    n = y0.shape[0]
    scale, y1, f1 = np.empty(n), np.empty(n), np.empty(n)
    for j in range(n):
        scale[j] = atol + abs(y0[j]) * rtol
    d0, d1 = _rms(y0, scale), _rms(f0, scale)
    h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    h0 = min(h0, interval)
    for j in range(n):
        y1[j] = y0[j] + h0 * f0[j]
    derivative(stage, y1, p, table, f1)
    for j in range(n):
        f1[j] -= f0[j]
    d2 = _rms(f1, scale) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / (_ERROR_ORDER + 1))
    return min(100.0 * h0, h1, interval)


@internal
def _dense_prepare(stage, t_old, h, y_old, y_new, f_new, coef, K, F, tmp, p, table):
    """The step's 7th-order interpolant: three more stages into K, then F (7, n)."""
    D, AX = coef[5], coef[6]
    n = y_old.shape[0]
    for e in range(3):
        s = _N_STAGES + 1 + e
        for j in range(n):
            acc = 0.0
            for q in range(s):
                acc += K[q, j] * AX[e, q]
            tmp[j] = y_old[j] + acc * h
        derivative(stage, tmp, p, table, K[s])  # autonomous: the stage's node C_EXTRA[e] is not needed
    for j in range(n):
        dy = y_new[j] - y_old[j]
        F[0, j] = dy
        F[1, j] = h * K[0, j] - dy
        F[2, j] = 2.0 * dy - h * (f_new[j] + K[0, j])
        for i in range(4):
            acc = 0.0
            for q in range(_N_STAGES + 4):
                acc += D[i, q] * K[q, j]
            F[3 + i, j] = h * acc


@internal
def _dense_eval(t, t_old, h, y_old, F, out):
    """The interpolant at t (Horner-like in x and 1 - x, highest term first)."""
    x = (t - t_old) / h
    n = y_old.shape[0]
    for j in range(n):
        out[j] = 0.0
    for i in range(7):
        row = 6 - i
        factor = x if i % 2 == 0 else 1.0 - x
        for j in range(n):
            out[j] = (out[j] + F[row, j]) * factor
    for j in range(n):
        out[j] += y_old[j]


@internal
def _event_at(t, stage, k, t_old, h, y_old, F, tmp, p):
    _dense_eval(t, t_old, h, y_old, F, tmp)
    return event_value(stage, k, tmp, p)


@internal
def _brent(stage, k, xa, xb, fa, fb, t_old, h, y_old, F, tmp, p):
    """Root of the event between xa and xb (values fa, fb of opposite sign): Brent (1973).

    Stops when the bracket is within ``ROOT_TIME_TOLERANCE + 4 eps |t|``,
    as ``scipy.optimize.brentq`` with the reference path's tolerances.
    """
    xtol, rtol = ROOT_TIME_TOLERANCE, ROOT_RELATIVE_TOLERANCE
    xpre, xcur, fpre, fcur = xa, xb, fa, fb
    if fpre == 0.0:
        return xpre
    if fcur == 0.0:
        return xcur
    xblk, fblk, spre, scur = 0.0, 0.0, 0.0, 0.0
    for _ in range(100):
        if fpre != 0.0 and fcur != 0.0 and (fpre < 0.0) != (fcur < 0.0):
            xblk, fblk = xpre, fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):
            xpre, xcur, xblk = xcur, xblk, xcur
            fpre, fcur, fblk = fcur, fblk, fcur
        delta = (xtol + rtol * abs(xcur)) / 2.0
        sbis = (xblk - xcur) / 2.0
        if fcur == 0.0 or abs(sbis) < delta:
            return xcur
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:   # secant
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:              # inverse quadratic
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            if 2.0 * abs(stry) < min(abs(spre), 3.0 * abs(sbis) - delta):
                spre, scur = scur, stry
            else:
                spre = scur = sbis
        else:
            spre = scur = sbis
        xpre, fpre = xcur, fcur
        if abs(scur) > delta:
            xcur += scur
        else:
            xcur += delta if sbis > 0.0 else -delta
        fcur = _event_at(xcur, stage, k, t_old, h, y_old, F, tmp, p)
    return xcur


# --------------------------------------------------------------------------- #
# Peak loads: sampled at every step's end, located around the largest sample
# --------------------------------------------------------------------------- #
# Per load k (``stages.LOAD_NAMES``): ``samples[k]`` holds the largest sample
# ``(t, value)`` at 2, 3 and the samples before and after it at 0, 1 and 4, 5
# (NaN times: none); ``sides[k]`` the steps on either side of it: the step ending
# at the sample (0) and the step after it (1), -1 for none; ``pending[k]``: side
# 1 is the next step. ``last`` holds the previous sample's values, then its time.
#
# A step is its stages K[0:13], its start and full end ``(y, y_new)`` and
# ``(t_start, h, t_end)``, t_end where the stretch stopped within it. The
# integrator keeps its last two steps in two buffers, alternately (``LIVE + b``
# for buffer b); a step that a load still needs when its buffer is about to be
# taken again is saved, once, in a slot of the pool (0 to ``POOL_SLOTS - 1``).
# While a load rises, each step replaces the last and nothing is copied; the
# interpolants are built at the end, for the few steps around a peak.
POOL_SLOTS = 2 * N_LOADS
LIVE = POOL_SLOTS


@internal
def _save_step(buffer, sides, K2, live_y, live_t, pool_k, pool_y, pool_t):
    """Move every load's reference to live ``buffer`` into a free pool slot, copying the step once."""
    slot = -1
    for k in range(N_LOADS):
        for side in range(2):
            if sides[k, side] == LIVE + buffer:
                if slot < 0:
                    slot = 0
                    taken = True
                    while taken:
                        taken = False
                        for j in range(N_LOADS):
                            if sides[j, 0] == slot or sides[j, 1] == slot:
                                taken = True
                        if taken:
                            slot += 1
                    n = live_y.shape[2]
                    for q in range(_N_STAGES + 1):
                        for i in range(n):   # loops: a slice copy costs 4 s of compile (its error message)
                            pool_k[slot, q, i] = K2[buffer, q, i]
                    for i in range(n):
                        pool_y[slot, 0, i], pool_y[slot, 1, i] = live_y[buffer, 0, i], live_y[buffer, 1, i]
                    for j in range(3):
                        pool_t[slot, j] = live_t[buffer, j]
                sides[k, side] = slot


@internal
def _sample_loads(t, values, buffer, samples, sides, pending, last, ended):
    """Take the loads ``values`` at ``t``, where the step in live ``buffer`` stopped (-1: the
    stretch's first sample, no step). ``ended``: no step follows."""
    here = LIVE + buffer if buffer >= 0 else -1
    for k in range(N_LOADS):
        if pending[k]:
            sides[k, 1] = here
            samples[k, 4], samples[k, 5] = t, values[k]
            pending[k] = False
        if values[k] > samples[k, 3]:
            samples[k, 0], samples[k, 1] = last[N_LOADS], last[k]
            samples[k, 2], samples[k, 3] = t, values[k]
            samples[k, 4] = math.nan
            sides[k, 0], sides[k, 1] = here, -1
            pending[k] = not ended
        last[k] = values[k]
    last[N_LOADS] = t


@internal
def _finish_peaks(stage, samples, sides, K2, live_y, live_t, pool_k, pool_y, pool_t, peaks, coef, p, table,
                  counts):
    """Locate each load's largest value around its largest sample (``analytic.peaks``' search on
    its steps' interpolants) and keep it in ``peaks`` (N_LOADS, 2) where it beats it."""
    n = pool_y.shape[2]
    F = np.empty((POOL_SLOTS + 2, 7, n))
    built = np.empty(POOL_SLOTS + 2, dtype=np.bool_)
    for ref in range(POOL_SLOTS + 2):
        built[ref] = False
    K = np.empty((_N_STAGES + 4, n))
    tmp = np.empty(n)
    starts, ends = np.empty(2), np.empty(2)
    for k in range(N_LOADS):
        if not samples[k, 3] > -math.inf:
            continue
        for side in range(2):
            ref = sides[k, side]
            starts[side], ends[side] = math.nan, math.nan
            if ref < 0:
                continue
            live = ref >= LIVE
            t_start = live_t[ref - LIVE, 0] if live else pool_t[ref, 0]
            h = live_t[ref - LIVE, 1] if live else pool_t[ref, 1]
            starts[side], ends[side] = t_start, live_t[ref - LIVE, 2] if live else pool_t[ref, 2]
            if not built[ref]:
                for q in range(_N_STAGES + 1):
                    for i in range(n):
                        K[q, i] = K2[ref - LIVE, q, i] if live else pool_k[ref, q, i]
                y_old = live_y[ref - LIVE, 0] if live else pool_y[ref, 0]
                y_end = live_y[ref - LIVE, 1] if live else pool_y[ref, 1]
                _dense_prepare(stage, t_start, h, y_old, y_end, K[_N_STAGES], coef, K, F[ref], tmp, p, table)
                counts[1] += 3
                built[ref] = True
        t_peak, value = samples[k, 2], samples[k, 3]
        for side in range(2):   # each step beside the sample on its own, as scipy's bounded search
            ref = sides[k, side]
            if not ends[side] > starts[side]:
                continue
            live = ref >= LIVE
            h = live_t[ref - LIVE, 1] if live else pool_t[ref, 1]
            y_old = live_y[ref - LIVE, 0] if live else pool_y[ref, 0]
            u = search_golden(starts[side], ends[side])
            _dense_eval(u, starts[side], h, y_old, F[ref], tmp)
            search = search_from(starts[side], ends[side], u, -loads_at(stage, tmp, p)[k])
            counts[1] += 1   # each load is one evaluation of the accelerations
            while True:
                done, u, search = search_next(search)
                if done:
                    break
                _dense_eval(u, starts[side], h, y_old, F[ref], tmp)
                counts[1] += 1
                search = search_update(search, u, -loads_at(stage, tmp, p)[k])
            if -search.fx > value:
                t_peak, value = search.x, -search.fx
        if value > peaks[k, 0]:
            peaks[k, 0], peaks[k, 1] = value, t_peak


@internal
def _keep_step(buffer, t_start, h, t_end, y, y_new, live_y, live_t):
    """Record the step just taken (its stages are in ``K2[buffer]``): its ends and times."""
    for i in range(y.shape[0]):
        live_y[buffer, 0, i], live_y[buffer, 1, i] = y[i], y_new[i]
    live_t[buffer, 0], live_t[buffer, 1], live_t[buffer, 2] = t_start, h, t_end


@internal
def integrate(stage, t0, y0, t_bound, coef, rtol, atol, p, table, counts, peaks, track_loads):
    """Integrate ``stage`` from (t0, y0) until a terminal event or ``t_bound``.

    Returns ``(code, t_end, y_end, apex)``: code is the index of the terminal
    event that ended it, ``REACHED_END``, ``FAILED`` (step size underflow
    or a non-finite state) or ``OUT_OF_STEPS`` (the stage's ``STAGE_STEP_LIMITS``
    accepted steps without reaching ``t_bound``); apex is the largest y[1] at a counted apex root
    (flight only; -inf if none). ``counts`` accumulates [steps, evaluations].
    In stages 1 and 2 with ``track_loads``, ``peaks`` (N_LOADS, 2) gets the
    largest of each load (``stages.loads_at``) and its time, where this stretch
    beats it: sampled at every step's end and refined on the interpolants
    beside the largest sample, as ``analytic.reference`` does.
    """
    n = y0.shape[0]
    ne = event_count(stage, p)
    K2 = np.empty((2, _N_STAGES + 4, n))   # the last two steps' stages, alternately
    K = K2[0]
    F = np.empty((7, n))
    y, y_new = np.empty(n), np.empty(n)
    for j in range(n):
        y[j] = y0[j]
    f, f_new = np.empty(n), np.empty(n)
    tmp, y_root = np.empty(n), np.empty(n)
    previous = np.empty(ne)
    derivative(stage, y, p, table, f)
    for k in range(ne):
        previous[k] = event_value(stage, k, y, p)
    t = t0
    h_abs = _initial_step(stage, t0, y, f, t_bound, rtol, atol, p, table)
    counts[1] += 2
    if not math.isfinite(h_abs):
        # A non-finite start or derivative: a NaN step would be shrunk forever.
        return FAILED, t, y, -math.inf
    apex = -math.inf
    apex_t, apex_y = np.empty(4), np.empty(4)   # counted apex roots within one step
    track = track_loads and stage != FLIGHT
    # Filled by loops: numba compiles np.full and np.zeros into a function per
    # shape and type (about a second of a cold compile in all, measured).
    samples, sides = np.empty((N_LOADS, 6)), np.empty((N_LOADS, 2), dtype=np.int64)
    pending = np.empty(N_LOADS, dtype=np.bool_)
    last = np.empty(N_LOADS + 1)
    slots = POOL_SLOTS if track else 0
    pool_k, pool_y, pool_t = np.empty((slots, _N_STAGES + 1, n)), np.empty((slots, 2, n)), np.empty((slots, 3))
    live_y, live_t = np.empty((2, 2, n)), np.empty((2, 3))
    for k in range(N_LOADS):
        pending[k] = False
        samples[k, 3] = -math.inf
        for j in range(0, 6, 2):
            samples[k, j] = math.nan
        sides[k, 0], sides[k, 1] = -1, -1
    if track:
        last[N_LOADS] = math.nan
        _sample_loads(t0, loads_at(stage, y, p), -1, samples, sides, pending, last, False)
        counts[1] += 1
    exponent = -1.0 / (_ERROR_ORDER + 1)
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
            _rk_step(stage, t, y, f, h, coef, K, y_new, f_new, tmp, p, table)
            counts[1] += _N_STAGES
            error = _error_norm(h, y, y_new, K, coef, rtol, atol)
            if error < 1.0:
                factor = _MAX_FACTOR if error == 0.0 else min(_MAX_FACTOR, _SAFETY * error ** exponent)
                if rejected:
                    factor = min(1.0, factor)
                h_abs *= factor
                break
            if math.isfinite(error):
                h_abs *= max(_MIN_FACTOR, _SAFETY * error ** exponent)
            else:   # a non-finite trial stage (e.g. past the sling's reach): shrink hard
                h_abs *= _MIN_FACTOR
            rejected = True
        counts[0] += 1
        steps += 1
        for j in range(n):
            if not math.isfinite(y_new[j]):
                return FAILED, t_new, y_new, apex
        t_old = t

        # Events on the accepted step [t_old, t_new].
        dense_ready = False
        hit_t, hit_k = math.inf, -1
        n_apex = 0
        for k in range(ne):
            after = event_value(stage, k, y_new, p)
            direction = event_direction(stage, k)
            before = previous[k]
            previous[k] = after
            start, v_start, end, v_end = t_old, before, t_new, after
            if leaves_zero(before, after):
                # Left zero at the step's start: did it come back within the step?
                if not dense_ready:
                    _dense_prepare(stage, t_old, h, y, y_new, f_new, coef, K, F, tmp, p, table)
                    counts[1] += 3
                    dense_ready = True
                i, low, v_low, high, v_high = 1, -1, math.nan, -1, math.nan
                while i < ZERO_START_PROBES:
                    v_probe = _event_at(probe_time(t_old, t_new, i), stage, k, t_old, h, y, F, tmp, p)
                    counts[1] += 1
                    i, low, v_low, high, v_high = probe_update(i, v_probe, after, low, v_low, high, v_high)
                start, v_start, end, v_end = probe_bracket(t_old, t_new, before, after, low, v_low, high, v_high)
            while counted_crossing(v_start, v_end, direction):
                if not dense_ready:
                    _dense_prepare(stage, t_old, h, y, y_new, f_new, coef, K, F, tmp, p, table)
                    counts[1] += 3
                    dense_ready = True
                if v_end == 0.0:
                    t_root = end
                else:
                    t_root = _brent(stage, k, start, end, v_start, v_end, t_old, h, y, F, tmp, p)
                _dense_eval(t_root, t_old, h, y, F, y_root)
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
                v_start = _event_at(start, stage, k, t_old, h, y, F, tmp, p)
                end, v_end = t_new, after
        for i in range(n_apex):
            if apex_t[i] <= hit_t:
                apex = max(apex, apex_y[i])
        if hit_k >= 0:
            y_hit = np.empty(n)
            _dense_eval(hit_t, t_old, h, y, F, y_hit)
            if track:
                _keep_step(buffer, t_old, h, hit_t, y, y_new, live_y, live_t)
                _sample_loads(hit_t, loads_at(stage, y_hit, p), buffer, samples, sides, pending, last, True)
                counts[1] += 1
                _finish_peaks(stage, samples, sides, K2, live_y, live_t, pool_k, pool_y, pool_t, peaks, coef, p,
                              table, counts)
            return hit_k, hit_t, y_hit, apex
        if track:   # at the step's end the derivative is known (f_new): stage 2 reads the accelerations
            _keep_step(buffer, t_old, h, t_new, y, y_new, live_y, live_t)
            _sample_loads(t_new, loads_after_step(stage, y_new, f_new, p), buffer, samples, sides, pending, last,
                          False)
            _save_step(1 - buffer, sides, K2, live_y, live_t, pool_k, pool_y, pool_t)   # the next step takes it
            counts[1] += 1 if stage == SLIDE else 0
        t = t_new
        for j in range(n):
            y[j] = y_new[j]
            f[j] = f_new[j]
    if track:
        _finish_peaks(stage, samples, sides, K2, live_y, live_t, pool_k, pool_y, pool_t, peaks, coef, p, table,
                      counts)
    return REACHED_END, t, y, apex


# --------------------------------------------------------------------------- #
# A whole shot
# --------------------------------------------------------------------------- #

@internal
def params(P):
    """The ``Params`` of a design row."""
    return Params(*to_fixed_tuple(P, N_PARAMS))


@internal
def _step_failed(out, code, stage):
    """Record a stage whose integration failed (``code``: ``FAILED`` or ``OUT_OF_STEPS``)."""
    out[STATUS], out[DETAIL] = STEP_FAILED, stage
    out[VALUE] = 1.0 if code == OUT_OF_STEPS else 0.0


@internal
def _run_stage(stage, t, y, switches, coef, rtol, atol, p, table, counts, peaks, track_loads, out):
    """Integrate ``stage`` from (t, y) in stretches, switching the friction modes between them,
    until ``analytic.sequence.stretch_end`` says the stage is over.

    Returns ``(action, status, detail, switches, t, y)`` at its end (``out[END_T]``); a step
    failure is recorded in ``out`` (``_step_failed``).
    """
    while True:
        code, t, y, _ = integrate(stage, t, y, p.t_limit, coef, rtol, atol, p, table, counts, peaks, track_loads)
        action, status, detail = stretch_end(stage, code, switches)
        if action != SWITCH_MODE:
            break
        switches += 1
        switch_mode(stage, code, y, p)
    out[END_T] = t
    if status == STEP_FAILED:
        _step_failed(out, code, stage)
    return action, status, detail, switches, t, y


@internal(inline="always")
def shot(P, table, coef, rtol, atol, track_loads, out):
    """Simulate the design row ``P`` through all three stages into the result row ``out``.

    Not compiled by itself: ``shots`` is the one entry point, and this is
    inlined into it, which spares a second optimisation of the whole shot.

    The stages and their ends are those of ``analytic.reference.simulate``;
    ``out[STATUS]`` names how it ended and the other entries hold what was
    reached (NaN otherwise). ``track_loads`` False leaves the peak loads NaN
    (the benchmark measures what finding them costs).
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
    if normal0 > 0.0:   # else the sling already pulls harder than the projectile's weight
        action, status, detail, switches, t1, y1 = _run_stage(SLIDE, 0.0, y1, switches, coef, rtol, atol, p, table,
                                                              counts, peaks, track_loads, out)
    if action == NEXT_STAGE:
        out[LIFTOFF_T] = t1
        y2 = np.empty(state_size(SWING, p))
        swing_start(y1, p, y2)
        action, status, detail, switches, t2, y2 = _run_stage(SWING, t1, y2, switches, coef, rtol, atol, p, table,
                                                              counts, peaks, track_loads, out)
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
    code, t3, y3, apex = integrate(FLIGHT, t2, y_release, t_max, coef, rtol, atol,
                                   p, table, counts, peaks, False)
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


@numba.njit(**CALLABLE)
def shots(designs, start, stop, table, coef, rtol, atol, track_loads, out):
    """``shot`` for rows ``start:stop`` of ``designs`` (S, N_PARAMS) into those of ``out`` (S, N_RESULT).

    The one compiled entry point. It releases the GIL (``nogil``), so
    ``analytic.fast`` runs several calls at once on Python threads, each on
    its own rows. ``track_loads`` False leaves the peak loads NaN.
    """
    for i in range(start, stop):
        shot(designs[i], table, coef, rtol, atol, track_loads, out[i])
