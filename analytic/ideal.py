"""The ideal release: the instant of the free swing that throws farthest, written once for both paths.

``machine.release_rule = "ideal"`` releases the projectile when the arm, swinging
forward, passes the arm angle ``theta*`` whose release gives the longest range
(``docs/derivation.md``, the release section). The rule's event is
``geometry.ideal_release``: the arm passing ``Params.alpha`` (the arm angle, not
a release angle), or stopping. Each analytic path finds ``theta*`` in the
same three steps, with its own shots:

1. the search pass: the swing with ``alpha = SEARCH_ANGLE`` (``-inf``), which
   runs from lift-off to the end of the candidates, the arm's stop (or an
   earlier end: the projectile reaching the base, the swing's time limit); it
   gives the window of arm angles ``(theta at lift-off, theta at the end]``;
2. ``CANDIDATES`` arm angles evenly spaced over that window, each a whole shot
   released there (the path's own slide, swing and flight, landing where the
   flight's landing event says), and the one that throws farthest;
3. Brent's bounded search between that candidate's neighbours, to
   ``ANGLE_TOLERANCE``.

The arm angle falls monotonically from lift-off to the arm's stop, so it
names each instant of the window once, and the release it asks for is an
event of the state that both paths locate as they locate any other. The
global maximum over the window is taken, not the first local one: a sling
that whirls round more than once passes a good launch direction once per turn,
and the rule is the longest range the swing offers.
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np
from scipy.optimize import minimize_scalar

#: ``Params.alpha`` of the search pass: the arm never passes it, so the swing runs to its stop.
SEARCH_ANGLE = -math.inf
#: Candidate arm angles over the window, evenly spaced: enough that a sling whirling twice round
#: in the window (a launch direction a candidate every 11 deg of whirl) has each of its turns'
#: maxima bracketed by its neighbours.
CANDIDATES = 64
#: Brent's search stops when the bracket of the arm angle is this narrow, rad. The range is flat
#: at its maximum (``R(theta* + d) = R* - c d^2``), so this settles the range to round-off and
#: the angle to what round-off of the range lets it be (``crosscheck.sensitivity``).
ANGLE_TOLERANCE = 1e-9


def candidates(start: float, end: float) -> np.ndarray:
    """The candidate arm angles, rad, (CANDIDATES,): the window from ``start`` (lift-off,
    not itself a candidate: the release cannot fall on the swing's first instant) to
    ``end`` (the arm's stop, or the search pass's other end), evenly spaced."""
    return start + (end - start) * np.arange(1, CANDIDATES + 1) / CANDIDATES


def best_arm_angle(ranges: Callable[[np.ndarray], np.ndarray], start: float, end: float) -> float:
    """The arm angle of the longest range over the window ``(start, end]``, rad.

    Parameters
    ----------
    ranges : arm angles (n,) -> the ranges of the shots released there (n,), m; NaN
        where a shot does not land.
    start, end : the arm's angle at lift-off and at the search pass's end, rad.

    Returns
    -------
    The best arm angle; ``SEARCH_ANGLE`` when no candidate lands (the shot then
    ends as the search pass does).
    """
    angles = candidates(start, end)
    values = _landed(ranges(angles))
    if not np.isfinite(values).any():
        return SEARCH_ANGLE
    i = int(np.argmax(values))   # the first of equals
    low = angles[i - 1] if i > 0 else start
    high = angles[i + 1] if i + 1 < len(angles) else end
    worst = float(np.min(values[np.isfinite(values)]))

    def shortfall(angle: float) -> float:   # Brent minimises; a shot that does not land is the worst
        value = float(_landed(ranges(np.array([angle])))[0])
        return -value if math.isfinite(value) else -worst + abs(worst) + 1.0

    found = minimize_scalar(shortfall, bounds=tuple(sorted((low, high))), method="bounded",
                            options={"xatol": ANGLE_TOLERANCE})
    return float(found.x) if -found.fun > values[i] else float(angles[i])


def _landed(values: np.ndarray) -> np.ndarray:
    """Ranges with the shots that did not land (NaN) as ``-inf``."""
    values = np.asarray(values, dtype=float)
    return np.where(np.isnan(values), -math.inf, values)
