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
from analytic.eom import (frame_coupling, frame_displacement, frame_velocity, horizontal_moment, loads,
                          slide_accelerations, slide_constraint, swing_accelerations, terms, total_mass)
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
            vx, vy = ground_velocity(y, p)
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
        vx, vy = ground_velocity(y, p)
        return release_at(int(p.rule), p.alpha, y[0], y[2], vx, vy)[1]
    return True


def ground_velocity(y, p):
    """The projectile's velocity on the ground ``(vx, vy)`` at the stage-2 state ``y``, m/s:
    relative to the pivot plus the frame's (0 for a fixed frame). The velocity
    release rule reads this one; the sling rule's angle is the same on either."""
    _, _, vx, vy = projectile_state(y[0], y[2], y[3], y[5], p.La, p.Ls)
    return vx + frame_velocity(y[0], y[1], y[2], y[3], y[4], y[5], p), vy


def frame_state(y, p):
    """The frame's ``(X, X')`` at the stage-2 state ``y`` (m, m/s; zeros for a fixed frame)."""
    return (frame_displacement(y[0], y[1], y[2], p),
            frame_velocity(y[0], y[1], y[2], y[3], y[4], y[5], p))


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
    """The flight start ``(x, y, vx, vy)`` on the ground from the stage-2 state at release:
    x from the pivot's place at rest (where a rolling frame's pivot stood)."""
    x, height, vx, vy = projectile_state(y[0], y[2], y[3], y[5], p.La, p.Ls)
    frame_x, frame_v = frame_state(y, p)
    return x + frame_x, height, vx + frame_v, vy


def machine_derivative(y, p, out):
    """After release: the arm and counterweight swing on alone, y = [theta, phi, theta', phi'].

    The stage-2 system without the projectile (mP = 0 drops its row and
    column). A rolling frame keeps the machine's momentum from release, which
    adds only a total derivative to the Lagrangian: the same reduced system
    as before, with the machine's mass alone (``machine_frame``).
    """
    m = p._replace(mP=0.0)
    m11, m12, _, m22, _, f1, f2, _ = terms(y[0], y[1], 0.0, y[2], y[3], 0.0, m)
    if p.rolling:
        b1, b2, _, c = frame_coupling(y[0], y[1], 0.0, y[2], y[3], 0.0, m)
        k = 1.0 / total_mass(m)
        m11, m12, m22 = m11 - k * b1 * b1, m12 - k * b1 * b2, m22 - k * b2 * b2
        f1, f2 = f1 + k * b1 * c, f2 + k * b2 * c
    det = m11 * m22 - m12 * m12
    out[0], out[1] = y[2], y[3]
    out[2], out[3] = (f1 * m22 - f2 * m12) / det, (f2 * m11 - f1 * m12) / det


def machine_frame(y, p, momentum, start_time, start_y, start_x, time):
    """The frame's ``(X, X')`` after release at ``time`` and machine state ``y`` (``machine_derivative``).

    ``momentum`` is the machine's horizontal momentum at release (kg m/s),
    kept since: ``Mt X' + S' = momentum`` with the machine's own mass and
    moment, so ``X = start_x + (momentum (t - t_r) - (S(q) - S(q_r))) / Mt``.
    """
    m = p._replace(mP=0.0)
    mass = total_mass(m)
    b1, b2, _, _ = frame_coupling(y[0], y[1], 0.0, y[2], y[3], 0.0, m)
    moved = horizontal_moment(y[0], y[1], 0.0, m) - horizontal_moment(start_y[0], start_y[1], 0.0, m)
    return (start_x + (momentum * (time - start_time) - moved) / mass,
            (momentum - b1 * y[2] - b2 * y[3]) / mass)


#: Peak loads are located on the dense output to this time tolerance, s (plus sqrt(eps) |t|):
#: Brent's bounded minimiser, scipy's ``minimize_scalar(method="bounded")`` on the reference
#: path and its port in the compiled one.
PEAK_TIME_TOLERANCE = 1e-10
#: What ``loads_at`` returns, in order (``analytic.eom.loads``): N, N, N, m/s^2.
LOAD_NAMES = ("axle_load", "hinge_load", "sling_tension", "projectile_acceleration")


def loads_at(stage, y, p):
    """``eom.loads`` at the stage-1 state ``[theta, phi, theta', phi']`` or the stage-2
    state ``[theta, phi, psi, theta', phi', psi']``: the accelerations and the base's
    push from the stage's own equations (0 push in stage 2)."""
    if stage == SLIDE:
        ddtheta, ddphi, normal = slide_accelerations(y[0], y[1], y[2], y[3], p)
        psi, dpsi, s, c, _ = slide_constraint(y[0], y[2], p)
        return loads(y[0], y[1], psi, y[2], y[3], dpsi, ddtheta, ddphi, s * ddtheta + c, normal, p)
    ddtheta, ddphi, ddpsi = swing_accelerations(y[0], y[1], y[2], y[3], y[4], y[5], p)
    return loads(y[0], y[1], y[2], y[3], y[4], y[5], ddtheta, ddphi, ddpsi, 0.0, p)
