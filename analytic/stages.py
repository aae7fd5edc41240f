"""The three stages of a shot: their states, right-hand sides and events, written once.

A stage is integrated from a start state until one of its terminal events
(or its time limit). Both analytic paths drive the same functions: the
reference path (``analytic.reference``) runs them under scipy's DOP853, the
compiled path (``analytic.kernel``) compiles the same source. Plain ``math``
on floats and indexing into ``y`` and ``out``, nothing else.

=====  ===========================================  ================================================
stage  state y                                      events (value; counted direction; ends stage?)
=====  ===========================================  ================================================
1      [theta, phi, theta', phi']                   under_tip (|sin beta| - limit; falling; yes),
       (psi from the base constraint)               liftoff (normal force; falling; yes),
                                                    arm_back (tip height above base; falling; yes)
2      [theta, phi, psi, theta', phi', psi']        release (the rule's value; rising; yes, only
                                                    when armed), hits_base (projectile height; falling; yes)
3      [x, y, vx, vy] from the pivot                landing (height above base; falling; yes),
                                                    apex (vy; falling; no: recorded)
=====  ===========================================  ================================================

In a tie between two terminal events in one step, the earlier-listed wins.
"""

from __future__ import annotations

import math

from analytic.aero import force_factor
from analytic.eom import slide_accelerations, slide_constraint, swing_accelerations
from analytic.geometry import projectile_state, release_at
from analytic.limits import SLING_VERTICAL_LIMIT
from analytic.outcome import Stage

SLIDE, SWING, FLIGHT = int(Stage.SLIDE), int(Stage.SWING), int(Stage.FLIGHT)
#: Length of the state of each stage (indexed by stage number).
STATE_SIZE = (0, 4, 6, 4)
#: Events of each stage, in their index order (indexed by stage number).
EVENT_NAMES = ((), ("under_tip", "liftoff", "arm_back"), ("release", "hits_base"), ("landing", "apex"))
#: Event roots are located to this absolute time tolerance, s (Brent's method on the dense output).
ROOT_TIME_TOLERANCE = 1e-14
#: A root that does not count is stepped past by at least this many units in the
#: last place of t before the search goes on: Brent's method stops within
#: ``ROOT_TIME_TOLERANCE + 4 eps |t|`` (up to 8 units), which past t = 64 s is more
#: than the ten tolerances stepped otherwise; past t = 450 s those are less than
#: one unit, and the search would find the same root again forever.
ROOT_NUDGE_ULPS = 8.0


def derivative(stage, y, p, table, out):
    """Write the state derivative of ``stage`` at ``y`` into ``out``.

    Stage 1 gives NaN past the sling's reach (``eom.slide_constraint``), so a
    step that gets there is rejected; flight has quadratic drag on the
    air-relative velocity, ``a = -g e_y - (rho A / 2 m) Cd(Re) |v - w| (v - w)``
    with ``w = (wind, 0)``; ``table`` is ``analytic.aero.DRAG_TABLE``.
    """
    if stage == SLIDE:
        ddtheta, ddphi, _ = slide_accelerations(y[0], y[1], y[2], y[3], p)
        out[0], out[1], out[2], out[3] = y[2], y[3], ddtheta, ddphi
    elif stage == SWING:
        a, b, c = swing_accelerations(y[0], y[1], y[2], y[3], y[4], y[5], p)
        out[0], out[1], out[2], out[3], out[4], out[5] = y[3], y[4], y[5], a, b, c
    else:
        vx_rel = y[2] - p.wind
        vy = y[3]
        # Not math.hypot: CPython's own algorithm and the C library's (which
        # compiled code calls) may differ in the last bit; sqrt is correctly rounded in both.
        speed = math.sqrt(vx_rel * vx_rel + vy * vy)
        k = p.rho * p.area / (2.0 * p.mP) * force_factor(int(p.drag), speed, p.diameter, p.rho, p.mu,
                                                         p.cd, table)
        out[0], out[1], out[2], out[3] = y[2], vy, -k * vx_rel, -p.g - k * vy


def sling_off_vertical(theta, p):
    """Stage 1: ``|sin beta| - SLING_VERTICAL_LIMIT`` from the constraint, defined (as
    ``-limit``) even beyond the sling's reach."""
    cos_beta = -(p.h + p.La * math.cos(theta)) / p.Ls
    return math.sqrt(max(0.0, 1.0 - cos_beta * cos_beta)) - SLING_VERTICAL_LIMIT


def event_value(stage, k, y, p):
    """Value of event ``k`` of ``stage`` at ``y`` (see the table above)."""
    if stage == SLIDE:
        off_vertical = sling_off_vertical(y[0], p)
        if k == 0:
            return off_vertical
        if k == 1:
            if off_vertical <= 0.0:
                return 1.0   # no lift-off under the tip: under_tip ends the stage there
            return slide_accelerations(y[0], y[1], y[2], y[3], p)[2]
        return p.La * math.cos(y[0]) + p.h
    if stage == SWING:
        if k == 0:
            _, _, vx, vy = projectile_state(y[0], y[2], y[3], y[5], p.La, p.Ls)
            return release_at(int(p.rule), p.alpha, y[0], y[2], vx, vy)[0]
        return p.La * math.cos(y[0]) + p.Ls * math.cos(y[0] + y[2]) + p.h
    if k == 0:
        return y[1] + p.h
    return y[3]


def event_direction(stage, k):
    """+1: only rising crossings count; -1: only falling ones."""
    return 1 if (stage == SWING and k == 0) else -1


def event_terminal(stage, k):
    """Whether a counted root of the event ends the stage (the apex is only recorded)."""
    return not (stage == FLIGHT and k == 1)


def event_armed(stage, k, y, p):
    """Whether a root of the event at ``y`` counts: only the release has a condition."""
    if stage == SWING and k == 0:
        _, _, vx, vy = projectile_state(y[0], y[2], y[3], y[5], p.La, p.Ls)
        return release_at(int(p.rule), p.alpha, y[0], y[2], vx, vy)[1]
    return True


def fires(p):
    """``(theta'', N)`` at rest: the machine fires when theta'' < 0, and the projectile
    starts on the base when N > 0 (otherwise stage 1 is skipped)."""
    ddtheta, _, normal = slide_accelerations(p.theta0, p.phi0, 0.0, 0.0, p)
    return ddtheta, normal


def swing_start(y, p):
    """The stage-2 start ``(theta, phi, psi, theta', phi', psi')`` from the stage-1 state at lift-off."""
    psi, dpsi, _, _, _ = slide_constraint(y[0], y[2], p)
    return y[0], y[1], psi, y[2], y[3], dpsi


def flight_start(y, p):
    """The flight start ``(x, y, vx, vy)`` from the stage-2 state at release."""
    return projectile_state(y[0], y[2], y[3], y[5], p.La, p.Ls)
