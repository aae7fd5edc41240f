"""The shot's sequence, written once for both paths: what each stretch's end means, and where roots count.

A shot is stage 1 (the slide), stage 2 (the swing) and stage 3 (the flight);
in a design with friction a stage is integrated in stretches, one per set of
joint modes, each ended by an event (``states.EVENT_NAMES``). Both paths
integrate a stretch with their own integrator (``analytic.reference.ode`` with
scipy's DOP853 on the reference path, ``analytic.fast.kernel`` compiled) and then
ask ``stretch_end`` what follows: a switch of the friction modes and another
stretch of the same stage, the next stage, or the end of the shot with its
status. This module is plain Python on numbers, which the reference path runs
as it is and ``analytic.fast.compiled`` compiles for the kernel, like the model.

The event-root policy is here too: which sign changes of an event's value
count (``counted_crossing``), where the search for a later root goes on after
a root that does not count (``past_root``), how a step is probed for the
other side of an event that starts it at exactly zero (``probe_time``,
``probe_update``, ``probe_bracket``), and how a step is searched whose
event value turns back within it (``turns_back`` and the ``turn_*`` functions).

**A value that crosses zero and back within one step.** Each path checks an
event's value at the ends of each accepted step; a step that holds two roots
of it shows no sign change between its ends. At a release the projectile's
velocity may turn past the release angle and back within one step (the
cross-check's ``sample-7-001-light-fixed``: 13 ms apart, in a step of 15 ms),
and the shot would swing on to a later crossing. So each path also knows the
value's time derivative, its rate, at each step's end (``event_rate``): where
the values at a step's two ends have one sign and the rates say that the value
heads for zero at the start and away from it at the end (``turns_back``), the
value turns within the step, at an extremum between the ends; the extremum is
located on the step's dense output (``analytic.peaks``' Brent search, from
where a rate linear in time would vanish, ``turn_first``), and the search
stops as soon as a value lies across zero (``turn_next``): the two roots lie
on either side of that point, one rising and one falling, and the one the
event counts is bracketed (``turn_bracket``) and located as any other. A turn
that stays short of zero costs the search and changes nothing.

Why the rate, rather than more samples of the value: a two-root step is one
whose value turns back, and the sign of the rate at the ends tells exactly
that for a value with one extremum in the step (a DOP853 step resolves the
motion, so an event of the motion has few); probes at fixed fractions of every
step would cost a dense output a step (three more evaluations of the equations)
and still miss a hump narrower than their spacing. The rate is the backward
difference of the value along the state's tangent at the step's end, over
``RATE_OFFSET`` of the step (``rate_offset``, ``tangent_state``): it needs no
derivative of each event written out (the friction events' are implicit),
costs one evaluation of the event a step, the state's derivative there being
the integrator's own (DOP853 evaluates it at every step's end), and a rate
computed at a step's end is the next step's rate at its start. Its error is
the value's curvature over the offset, so a rate's sign is wrong only within
about that offset of the value's extremum, where the value is within round-off
of the end's own. A step whose value turns twice (three roots) is not looked
into: its rates head one way at both ends.

Only the release's turns are searched (``stages.event_turns``). Its value is
the one that sweeps back and forth through a swing (the velocity's direction,
or the sling's angle, as the sling whips), and a release missed for a turn moves
the whole shot. The rate costs an evaluation of the event at every step of its
stage, which for the release is a few trigonometric functions, for the lift-off
a solve of the slide's equations and for a friction event one of the
friction's: a cost on every shot, against turns of those values (a projectile
that touches the base and leaves it again within one step) that none of the
cross-check's and the benchmark's designs makes (every terminal event watched,
the release's was the only turn across zero found). The other events are
checked between a step's ends, as is the apex, which only records.

A stretch's first step is checked between its ends only: it has no rate at its
start. A stretch starts at the root of the event that ended the last one, and
the events tied to that root start at zero to round-off with a rate of zero to
round-off (at lift-off the projectile leaves the base horizontally: its height,
and the release's value for a level release angle), so the sign of a rate there
is round-off's, and a search of the turn it suggests finds round-off's roots
(measured with the height watched: the projectile "back on the base" a
microsecond after lift-off, on 11 of the default cross-check's 99 designs on
the reference path, 17 on the fast path).
"""

from __future__ import annotations

import math

import numpy as np

from analytic.outcome import LiftoffFailure, Status
from analytic.peaks import search_around, search_from, search_next, search_update
from analytic.stages import ROOT_NUDGE_ULPS, ROOT_TIME_TOLERANCE, ZERO_START_PROBES
from analytic.states import (FIRST_SWITCH, FLIGHT, FLIGHT_LANDING, MODE_SWITCH_LIMIT, SLIDE, SLIDE_ARM_BACK,
                             SLIDE_ARM_STALLS, SLIDE_LIFTOFF, SLIDE_UNDER_TIP, SWING, SWING_HITS_BASE, SWING_RELEASE)

#: How a stretch ended, besides the index of the terminal event that ended it: it
#: reached the end of its time, the integrator failed (a step size underflow or a
#: non-finite state), or it took the stage's ``limits.STAGE_STEP_LIMITS`` steps.
REACHED_END, FAILED, OUT_OF_STEPS = -1, -2, -3
#: What follows a stretch (``stretch_end``).
SWITCH_MODE, NEXT_STAGE, FINISHED = 0, 1, 2

OK, NEVER_FIRES, NEVER_LIFTS_OFF, HITS_BASE, NEVER_RELEASES, NO_LANDING, STEP_FAILED, SHORT_OF_TARGET = (
    Status.OK.code, Status.NEVER_FIRES.code, Status.NEVER_LIFTS_OFF.code,
    Status.HITS_BASE_BEFORE_RELEASE.code, Status.NEVER_RELEASES.code, Status.NO_LANDING.code,
    Status.STEP_FAILED.code, Status.SHORT_OF_TARGET.code)
UNDER_TIP, ARM_BACK, TIME_LIMIT, STALLED = (int(LiftoffFailure.UNDER_TIP), int(LiftoffFailure.ARM_BACK),
                                            int(LiftoffFailure.TIME_LIMIT), int(LiftoffFailure.STALLED))
#: An event's rate at a state is the backward difference of its value along the state's tangent over
#: this fraction of the step (``rate_offset``; a power of two, so the offset is the step scaled
#: exactly). The difference's error is of the order of the value's curvature times the offset, so a
#: rate's sign is wrong only within about the offset (1.5e-5 of the step) of the value's extremum;
#: and along the offset the state moves by 1.5e-5 of what it moves in a step, orders of magnitude
#: above its round-off, so the difference is not the value's noise.
RATE_OFFSET = 2.0**-16


def stretch_end(stage, code, switches):
    """What follows a stretch of ``stage`` that ended with ``code`` (an event's index, or
    ``REACHED_END``, ``FAILED``, ``OUT_OF_STEPS``), after ``switches`` mode switches in the shot.

    Returns ``(action, status, detail)``: ``SWITCH_MODE`` (``states.switch_mode``, then
    the stage goes on), ``NEXT_STAGE``, or ``FINISHED`` with the shot's ``Status.code``
    and its detail: a ``LiftoffFailure`` for ``NEVER_LIFTS_OFF``, the stage for
    ``STEP_FAILED``, else 0. The machine after release (stage 4) finishes ``OK`` at the
    end of its time.
    """
    if code == FAILED or code == OUT_OF_STEPS:
        return FINISHED, STEP_FAILED, stage
    if code >= FIRST_SWITCH[stage] and stage != FLIGHT:
        if switches >= MODE_SWITCH_LIMIT:   # stick and slip chattering without end
            return FINISHED, STEP_FAILED, stage
        return SWITCH_MODE, 0, 0
    if stage == SLIDE:
        if code == SLIDE_LIFTOFF:
            return NEXT_STAGE, 0, 0
        if code == SLIDE_UNDER_TIP:
            return FINISHED, NEVER_LIFTS_OFF, UNDER_TIP
        if code == SLIDE_ARM_BACK:
            return FINISHED, NEVER_LIFTS_OFF, ARM_BACK
        return FINISHED, NEVER_LIFTS_OFF, STALLED if code == SLIDE_ARM_STALLS else TIME_LIMIT
    if stage == SWING:
        if code == SWING_RELEASE:
            return NEXT_STAGE, 0, 0
        return FINISHED, HITS_BASE if code == SWING_HITS_BASE else NEVER_RELEASES, 0
    if stage == FLIGHT:
        return FINISHED, OK if code == FLIGHT_LANDING else NO_LANDING, 0
    return FINISHED, OK, 0


def lands_at_release(height, vertical_velocity):
    """Whether a flight that starts ``height`` (m) above the target (``Params.yt``; the base for the
    default target) with upward speed ``vertical_velocity`` (m/s) has ended at its start: at or
    below the target and not rising. Below a raised target that is short of it
    (``short_of_target``: its highest point is its start).

    The swing ends a shot whose projectile falls through the base (``hits_base``), so a
    release below it is a rounding apart from one on it: the two paths give such a release
    heights of either sign (-1.7e-10 m and +5.8e-11 m on a machine 3e5 m high, found by
    ``tests/test_fuzz.py``). Falling from above the base, the landing event finds the root
    at once; from below it, no root is left to find and the shot would wrongly not land. Both
    paths land such a flight at its start, so the outcome does not turn on the last bit.
    """
    return height <= 0.0 and vertical_velocity <= 0.0


def short_of_target(apex_height, target_height):
    """Whether a flight that ended by its landing event (``stages.landing_value``) with its highest
    point ``apex_height`` (m above the base: the release's height, or the highest apex root) never
    reached the target ``target_height`` (m above the base): a raised target above its apex.

    A landing at or below the base's level cannot be short: the swing ends a shot whose projectile
    falls through the base (``hits_base``), so its flight starts at or above it (to rounding,
    ``lands_at_release``).
    """
    return target_height > 0.0 and apex_height < target_height


def counted_crossing(v_start, v_end, direction):
    """Whether an event's value going from ``v_start`` to ``v_end`` crosses zero in its counted
    ``direction`` (+1 rising, -1 falling, 0 either); reaching zero counts, leaving it does not."""
    rising = v_start < 0.0 <= v_end
    falling = v_start > 0.0 >= v_end
    return (rising and direction >= 0) or (falling and direction <= 0)


def past_root(t_root, t_new):
    """Where the search for a later root of the step ending at ``t_new`` goes on after the root
    at ``t_root`` that did not count (``stages.ROOT_NUDGE_ULPS``); at or past ``t_new``: none."""
    ulp = np.nextafter(abs(t_root), math.inf) - abs(t_root)
    return t_root + max(ROOT_TIME_TOLERANCE * 10.0, (t_new - t_root) * 1e-9, ROOT_NUDGE_ULPS * ulp)


def probe_time(t_old, t_new, i):
    """The ``i``-th of ``stages.ZERO_START_PROBES`` equal divisions of the step ``[t_old, t_new]``."""
    return t_old + (t_new - t_old) * i / ZERO_START_PROBES


def leaves_zero(before, after):
    """Whether an event whose value is ``before`` at a step's start and ``after`` at its end
    left exactly zero at the start: it may have come back within the step (probe it)."""
    return before == 0.0 and after != 0.0


def probe_update(i, v, after, low, v_low, high, v_high):
    """Take the event's value ``v`` at probe ``i`` of a step whose value at its end is ``after``.

    The probes look first for a value on the other side of zero from ``after``
    (``low``, ``v_low``: its probe and value, -1 until found), then for the next
    probe back on ``after``'s side or at zero (``high``, ``v_high``). Returns the
    next probe to take (``ZERO_START_PROBES``: done) and the four updated.
    """
    if low < 0:
        if v != 0.0 and (v > 0.0) != (after > 0.0):
            return i + 1, i, v, high, v_high
        return i + 1, low, v_low, high, v_high
    if (v > 0.0) != (v_low > 0.0) or v == 0.0:
        return ZERO_START_PROBES, low, v_low, i, v
    return i + 1, low, v_low, high, v_high


def probe_bracket(t_old, t_new, before, after, low, v_low, high, v_high):
    """The bracket ``(start, v_start, end, v_end)`` to search for a root after the probes
    (``probe_update``): the whole step if none was on the other side."""
    start, v_start = (probe_time(t_old, t_new, low), v_low) if low >= 0 else (t_old, before)
    end, v_end = (probe_time(t_old, t_new, high), v_high) if high >= 0 else (t_new, after)
    return start, v_start, end, v_end


def rate_offset(h):
    """The time offset, s, of the backward difference that gives an event's rate at the end of a step of size
    ``h`` (``RATE_OFFSET`` of it)."""
    return h * RATE_OFFSET


def tangent_state(y, f, offset, out):
    """Write into ``out`` the state ``offset`` back along the tangent at ``y``, whose derivative is ``f``:
    ``y - offset f``, where an event's value gives its rate at ``y`` (``event_rate``)."""
    for j in range(len(y)):
        out[j] = y[j] - offset * f[j]


def event_rate(value, behind, offset):
    """An event's rate (its value's time derivative), 1/s times its unit: ``value`` at a state, ``behind``
    at its ``tangent_state`` ``offset`` s back."""
    return (value - behind) / offset


def turns_back(before, after, rate_before, rate_after):
    """Whether an event's value turns back within a step: strictly on one side of zero at both ends
    (``before``, ``after``), it heads for zero at the start (``rate_before``) and away from it at the end
    (``rate_after``). Then it has an extremum inside, which may lie across zero: two roots, one
    rising and one falling (``turn_first`` and the rest search for it). A rate that is NaN (none at
    a stretch's start, or a value that cannot be evaluated) tells no turn."""
    if before < 0.0 and after < 0.0:
        return rate_before > 0.0 and rate_after < 0.0
    if before > 0.0 and after > 0.0:
        return rate_before < 0.0 and rate_after > 0.0
    return False


def turn_first(t_old, t_new, rate_before, rate_after):
    """Where the search of a step ``[t_old, t_new]`` whose value ``turns_back`` evaluates it first: where
    the rate, taken as linear in time between its values at the ends, vanishes (the extremum of a
    quadratic value). Strictly inside the step."""
    fraction = rate_before / (rate_before - rate_after)
    t = t_old + (t_new - t_old) * fraction
    return t if t_old < t < t_new else 0.5 * (t_old + t_new)


def crossed(before, v):
    """Whether the value ``v`` inside a step lies across zero from ``before``, its value at the start (or at zero)."""
    return v == 0.0 or (v > 0.0) != (before > 0.0)


def turn_search(t_old, t_new, before, after, u, v):
    """The search (an ``analytic.peaks.Search``) of a step whose value ``turns_back``, for its extremum,
    after the first evaluation, ``v`` at ``u`` (``turn_first``).

    The search minimises the value's distance from zero on its side (the value itself on the
    positive side, minus it on the negative); from three points when ``u`` is the nearest to zero of
    it and the two ends (its first step the vertex of the parabola through them), else from ``u``.
    """
    side = 1.0 if before > 0.0 else -1.0
    if side * v < side * before and side * v < side * after:
        return search_around(t_old, -side * before, u, -side * v, t_new, -side * after)
    return search_from(t_old, t_new, u, side * v)


def turn_next(s, before, v):
    """``(done, u, s)``: the next time ``u`` at which the search ``s`` of a turning step evaluates its value,
    or done: ``v``, the value the last evaluation gave, lies across zero from ``before`` (``crossed``), or
    the search has found the extremum short of zero (``analytic.peaks.search_next``)."""
    if crossed(before, v):
        return True, math.nan, s
    return search_next(s)


def turn_update(s, before, u, v):
    """The search ``s`` of a turning step after the value ``v`` at ``u`` (``turn_next``)."""
    return search_update(s, u, v if before > 0.0 else -v)


def turn_bracket(t_old, t_new, before, after, u, v, direction):
    """The bracket ``(start, v_start, end, v_end)`` of a turning step ``[t_old, t_new]``'s counted root, after
    its search: ``u`` the last time evaluated, ``v`` the value there. Across zero: the first root lies
    between the start and ``u``, the second between ``u`` and the end; the first if it is counted
    (``direction``), else the second. Otherwise the step's ends, which hold no counted crossing."""
    if not crossed(before, v):
        return t_old, before, t_new, after
    if counted_crossing(before, v, direction):
        return t_old, before, u, v
    return u, v, t_new, after
