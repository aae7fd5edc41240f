"""The shot's sequence, written once for both paths: what each stretch's end means, and where roots count.

A shot is stage 1 (the slide), stage 2 (the swing) and stage 3 (the flight);
in a design with friction a stage is integrated in stretches, one per set of
joint modes, each ended by an event (``stages.EVENT_NAMES``). Both paths
integrate a stretch with their own integrator (``analytic.reference.ode`` with
scipy's DOP853 on the reference path, ``analytic.fast.kernel`` compiled) and then
ask ``stretch_end`` what follows: a switch of the friction modes and another
stretch of the same stage, the next stage, or the end of the shot with its
status. This module is plain Python on numbers, which the reference path runs
as it is and ``analytic.fast.compiled`` compiles for the kernel, like the model.

The event-root policy is here too: which sign changes of an event's value
count (``counted_crossing``), where the search for a later root goes on after
a root that does not count (``past_root``), and how a step is probed for the
other side of an event that starts it at exactly zero (``probe_time``,
``probe_update``, ``probe_bracket``).
"""

from __future__ import annotations

import math

import numpy as np

from analytic.outcome import LiftoffFailure, Status
from analytic.stages import (ARM_STALLS, FIRST_SWITCH, FLIGHT, MODE_SWITCH_LIMIT, ROOT_NUDGE_ULPS,
                             ROOT_TIME_TOLERANCE, SLIDE, SWING, ZERO_START_PROBES)

#: How a stretch ended, besides the index of the terminal event that ended it: it
#: reached the end of its time, the integrator failed (a step size underflow or a
#: non-finite state), or it took the stage's ``limits.STAGE_STEP_LIMITS`` steps.
REACHED_END, FAILED, OUT_OF_STEPS = -1, -2, -3
#: What follows a stretch (``stretch_end``).
SWITCH_MODE, NEXT_STAGE, FINISHED = 0, 1, 2

OK, NEVER_FIRES, NEVER_LIFTS_OFF, HITS_BASE, NEVER_RELEASES, NO_LANDING, STEP_FAILED = (
    Status.OK.code, Status.NEVER_FIRES.code, Status.NEVER_LIFTS_OFF.code,
    Status.HITS_BASE_BEFORE_RELEASE.code, Status.NEVER_RELEASES.code, Status.NO_LANDING.code,
    Status.STEP_FAILED.code)
UNDER_TIP, ARM_BACK, TIME_LIMIT, STALLED = (int(LiftoffFailure.UNDER_TIP), int(LiftoffFailure.ARM_BACK),
                                            int(LiftoffFailure.TIME_LIMIT), int(LiftoffFailure.STALLED))


def stretch_end(stage, code, switches):
    """What follows a stretch of ``stage`` that ended with ``code`` (an event's index, or
    ``REACHED_END``, ``FAILED``, ``OUT_OF_STEPS``), after ``switches`` mode switches in the shot.

    Returns ``(action, status, detail)``: ``SWITCH_MODE`` (``stages.switch_mode``, then
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
        if code == 1:
            return NEXT_STAGE, 0, 0
        if code == 0:
            return FINISHED, NEVER_LIFTS_OFF, UNDER_TIP
        if code == 2:
            return FINISHED, NEVER_LIFTS_OFF, ARM_BACK
        return FINISHED, NEVER_LIFTS_OFF, STALLED if code == ARM_STALLS else TIME_LIMIT
    if stage == SWING:
        if code == 0:
            return NEXT_STAGE, 0, 0
        return FINISHED, HITS_BASE if code == 1 else NEVER_RELEASES, 0
    if stage == FLIGHT:
        return FINISHED, OK if code == 0 else NO_LANDING, 0
    return FINISHED, OK, 0


def lands_at_release(height, vertical_velocity):
    """Whether a flight that starts ``height`` (m) above the base with upward speed
    ``vertical_velocity`` (m/s) has landed at its start: at or below the base and not rising.

    The swing ends a shot whose projectile falls through the base (``hits_base``), so a
    release below it is a rounding apart from one on it: the two paths give such a release
    heights of either sign (-1.7e-10 m and +5.8e-11 m on a machine 3e5 m high, found by
    ``tests/test_fuzz.py``). Falling from above the base, the landing event finds the root
    at once; from below it, no root is left to find and the shot would wrongly not land. Both
    paths land such a flight at its start, so the outcome does not turn on the last bit.
    """
    return height <= 0.0 and vertical_velocity <= 0.0


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
