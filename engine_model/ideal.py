"""The ideal release in the engine: the arm angle whose release throws farthest, from its own swing and flights.

The engine finds it as the analytic model defines it (``docs/derivation.md``,
the release section), with nothing of the analytic model's but the rule's
event (``analytic.geometry.ideal_release``): its search pass steps the swing
from lift-off to the arm's stop (the machine's ``release_angle`` None), every
step after lift-off is a candidate, and each candidate's range is the
engine's own flight (``engine_model.flight.fly``) from that step's state.
The steps where the arm passes ``CANDIDATES`` arm angles evenly spaced over the
window are flown first (the analytic model's candidates), then a golden-section
search over the steps between the best one's neighbours; a parabola through the
best step's range and its neighbours' gives the arm angle between steps. ``engine_model.shot`` then
steps the machine again, with that arm angle as its release angle: the same
steps up to there (the rule's value changes nothing of the motion), released
where the arm passes it.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from analytic.design import Design
from engine_model import kinematics as kin
from engine_model.budget import flight_step_base
from engine_model.events import interpolate
from engine_model.flight import fly
from engine_model.stepping import Run

#: Arm angles flown first, evenly spaced over the window: as many as ``analytic.ideal.CANDIDATES``, at
#: the steps where the arm passes them. Evenly in angle, not in time: the arm turns fastest at the end
#: of its swing, where a short sling whips round and its best throw can lie between two candidates
#: evenly spaced in time (32 steps of 14 ms each bracketed two maxima 10 ms apart on a light arm
#: whose sling whips, and the golden-section search found the lower one).
CANDIDATES = 64
#: The golden ratio: the bracket of steps narrows by it with each flight (``_golden_steps``).
_GOLDEN = 0.5 * (1.0 + math.sqrt(5.0))


def searching(design: Design) -> Design:
    """``design`` as the search pass steps it: the ideal rule without a release angle (the arm's stop)."""
    return dataclasses.replace(design, machine=dataclasses.replace(design.machine, release_angle=None))


def released_at(design: Design, arm_angle: float | None) -> Design:
    """``design`` as the release pass steps it: the ideal rule released where the arm passes ``arm_angle``
    (rad; None: at its stop, as the search pass)."""
    return dataclasses.replace(design, machine=dataclasses.replace(design.machine, release_angle=arm_angle))


def best_arm_angle(design: Design, run: Run, dt: float, budget: bool) -> float | None:
    """The arm angle of the longest throw over the search pass ``run`` (stepped at ``dt``), rad; None
    where it never lifted off or no candidate lands (the shot then ends as the search pass did)."""
    if run.liftoff_time is None or len(run.raw) < 3:
        return None
    sync = kin.synchronise(np.array(run.raw), kin.origin_carried(design))
    times = dt * np.arange(len(sync))
    arm = kin.column(sync, kin.ARM, kin.ANGLE)
    spin = kin.column(sync, kin.ARM, kin.W)
    # Lift-off to the arm's stop: the steps off the base (not the lift-off's own, still on it, where the
    # release pass cannot release: its rule's crossing is looked for only after it).
    off_base = ~np.asarray(run.on_base, dtype=bool)
    free = np.flatnonzero(off_base & (spin < 0.0))
    if len(free) == 0:
        return None
    ranges = np.full(len(sync), np.nan)

    def flown(k: int) -> float:
        if np.isnan(ranges[k]):
            position = kin.position(sync[k:k + 1], kin.PROJECTILE)[0]
            velocity = kin.velocity(sync[k:k + 1], kin.PROJECTILE)[0]
            flight = fly(design, float(times[k]), position, velocity,
                         flight_step_base(design, position, velocity) if budget else dt)
            ranges[k] = flight.landing_position[0] if flight.landed else -math.inf
        return ranges[k]

    best = _golden_steps(flown, *_bracket(flown, _candidate_steps(arm, free), free))
    if not math.isfinite(flown(best)):
        return None
    edge = _edge(design, sync, times, dt, budget, flown, best, free)
    if edge is not None:
        return edge
    if best - 1 not in free or best + 1 not in free:
        return float(arm[best])
    below, at, above = flown(best - 1), flown(best), flown(best + 1)
    curvature = below - 2.0 * at + above
    if not (math.isfinite(below) and math.isfinite(above) and curvature < 0.0):
        return float(arm[best])
    offset = 0.5 * (below - above) / curvature   # the parabola's vertex, in steps from the best, within +-1/2
    neighbour = best + 1 if offset > 0.0 else best - 1
    return float(arm[best] + abs(offset) * (arm[neighbour] - arm[best]))


#: The edge's bisection (``_edge``) stops when its bracket is this fraction of a step: a throw whose apex
#: just reaches the target lands where the range's slope in the release is infinite (it falls as the
#: square root of the apex's excess), and a step's millionth leaves a range within a few parts in 1e5.
EDGE_TOLERANCE = 1e-6


def _edge(design: Design, sync: np.ndarray, times: np.ndarray, dt: float, budget: bool, flown, best: int,
          free: np.ndarray) -> float | None:
    """The arm angle of the longest throw where it lies at the edge of the releases that land, between
    the best step and a neighbour that does not land (a throw landing behind the pivot, least far
    when its apex just reaches a raised target), rad; None where it does not (the best step's
    neighbours land, or the edge throws no farther than the best step).

    The releases between the two steps are flown from the state the release pass would release at
    (``events.interpolate``: the parabola through three rows, as ``shot._cut_at_release``), the edge
    bracketed by bisection to ``EDGE_TOLERANCE`` of a step, and the release put one bracket's width
    inside it, on the side that lands.
    """
    for neighbour in (best + 1, best - 1):
        if neighbour not in free or math.isfinite(flown(neighbour)):
            continue
        k = max(best, neighbour)   # the interval from step k - 1 to k, through rows k - 2 .. k
        if k < 2:
            continue

        def flown_at(fraction: float) -> float:
            state = interpolate(sync[k - 2:k + 1], fraction)
            position = kin.position(state[None, :], kin.PROJECTILE)[0]
            velocity = kin.velocity(state[None, :], kin.PROJECTILE)[0]
            flight = fly(design, float(times[k - 1] + fraction * dt), position, velocity,
                         flight_step_base(design, position, velocity) if budget else dt)
            return flight.landing_position[0] if flight.landed else -math.inf

        lands, short = (1.0, 0.0) if neighbour < best else (0.0, 1.0)
        while abs(short - lands) > EDGE_TOLERANCE:
            middle = 0.5 * (lands + short)
            if math.isfinite(flown_at(middle)):
                lands = middle
            else:
                short = middle
        fraction = min(max(lands + (lands - short), 0.0), 1.0)   # a bracket's width inside the edge
        if flown_at(fraction) > flown(best):
            return float(interpolate(kin.column(sync[k - 2:k + 1], kin.ARM, kin.ANGLE), fraction))
    return None


def _candidate_steps(arm: np.ndarray, free: np.ndarray) -> np.ndarray:
    """The steps of the window ``free`` (ascending) where the arm, turning forward (its angle ``arm``
    falling), first reaches each of ``CANDIDATES`` angles evenly spaced from its angle at the window's
    first step (excluded, as the analytic model's lift-off) to its last (included); ascending, each once."""
    start, end = arm[free[0]], arm[free[-1]]
    angles = start + (end - start) * np.arange(1, CANDIDATES + 1) / CANDIDATES
    # The arm's angle over the window, made monotonic (a step's own jitter cannot pass an angle twice).
    passed = np.minimum.accumulate(arm[free])
    index = np.minimum(np.searchsorted(-passed, -angles, side="left"), len(free) - 1)
    return np.unique(free[index])


def _bracket(flown, steps: np.ndarray, free: np.ndarray) -> tuple[int, int]:
    """The candidates either side of the one of ``steps`` that throws farthest (the first of equals),
    or the window ``free``'s end beyond the first and the last."""
    i = max(range(len(steps)), key=lambda j: flown(int(steps[j])))
    return (int(steps[i - 1]) if i > 0 else int(free[0]),
            int(steps[i + 1]) if i + 1 < len(steps) else int(free[-1]))


def _golden_steps(flown, low: int, high: int) -> int:
    """The step of the longest range in ``[low, high]`` (``flown(k)``: step k's range, kept once
    flown), by golden-section search over whole steps: a few flights, not one a step."""
    inner_low, inner_high = high - round((high - low) / _GOLDEN), low + round((high - low) / _GOLDEN)
    while high - low > 4 and inner_low < inner_high:
        if flown(inner_low) >= flown(inner_high):
            high, inner_high = inner_high, inner_low
            inner_low = high - round((high - low) / _GOLDEN)
        else:
            low, inner_low = inner_low, inner_high
            inner_high = low + round((high - low) / _GOLDEN)
    return max(range(low, high + 1), key=flown)
