"""The three stages of a shot: their right-hand sides, events, starts and loads, written once.

A stage is integrated from a start state until one of its terminal events
(or its time limit). Both analytic paths drive the same functions: the
reference path (``analytic.reference``) runs them under scipy's DOP853, the
compiled path (``analytic.fast.kernel``) compiles the same source. Plain ``math``
on floats and indexing into ``y`` and ``out``, nothing else. Each stage's state
and events, by name, and friction's modes in the state are ``analytic.states``
(its table lists every state and event); the equations are ``analytic.eom``
and ``analytic.friction``; what a stage's end means is ``analytic.sequence``.

Stage 4 (``states.MACHINE``) is not a stage of the shot's outcome: it runs
alongside the flight, from release to landing, for the frame's place at landing
(``docs/derivation.md`` section 10.9). Its functions take ``machine_params(p)``,
the design's numbers without the projectile (mP = 0), so that they are stage
2's with one row and column fewer.

Two terminal events whose roots in one step lie within the root finder's
tolerance of each other are one instant, and the earlier-listed wins
(``first_event``: both paths decide by it).
"""

from __future__ import annotations

import math
from typing import NamedTuple

from analytic.scope import FLOATING_ARM, FRICTION   # what this copy handles (analytic.scope)
from analytic.aero import drag_rate
from analytic.eom import (FLOATING, Loads, floating_supports_in_air, frame_coupling, frame_displacement,
                          frame_velocity, horizontal_moment, joint_forces_sliding, loads, loads_sliding,
                          machine_accelerations, slide_accelerations, slide_constraint, swing_accelerations,
                          total_mass)
from analytic.friction import AXLE, BASE, HINGE, lossy, machine_friction, rest_balance, slide_friction, swing_friction
from analytic.geometry import IDEAL_RULE, ideal_release, projectile_state, release_at
from analytic.limits import SLING_VERTICAL_LIMIT
from analytic.states import (EVENT_COUNT, FIRST_FRICTION_EVENT, FIRST_SWITCH, FLIGHT, FLIGHT_APEX, FLIGHT_LANDING,
                             FLIGHT_VY, FLIGHT_Y, MACHINE, MACHINE_BASE_WORK, MACHINE_MODES, MACHINE_WORK, SLIDE,
                             SLIDE_ARM_STALLS, SLIDE_BASE_WORK, SLIDE_LIFTOFF, SLIDE_MODES, SLIDE_UNDER_TIP,
                             SLIDE_WORK, SWING, SWING_BASE_WORK, SWING_MODES, SWING_RELEASE, SWING_WORK,
                             friction_event, friction_solution, rest_modes, settle)

#: Event roots are located to this absolute time tolerance, s (Brent's method on the dense output).
ROOT_TIME_TOLERANCE = 1e-14
#: Brent's method's relative tolerance on a root's time: ``ROOT_RELATIVE_TOLERANCE |t|``
#: beside ``ROOT_TIME_TOLERANCE`` (4 float64 epsilons, scipy's ``brentq`` default).
ROOT_RELATIVE_TOLERANCE = 4.0 * 2.0**-52
#: A root that does not count is stepped past by at least this many units in the
#: last place of t before the search goes on: Brent's method stops within
#: ``ROOT_TIME_TOLERANCE + 4 eps |t|`` (up to 8 units), which past t = 64 s is more
#: than the ten tolerances stepped otherwise; past t = 450 s those are less than
#: one unit, and the search would find the same root again forever.
ROOT_NUDGE_ULPS = 8.0
#: An event whose value is exactly 0 at a step's start (a joint's rate that a friction switch
#: set to 0: its ``*_stops`` event) may leave zero and come back within that step; the step's
#: dense output is probed at this many equal intervals for the value on the other side.
ZERO_START_PROBES = 16


def derivative(stage, y, p, table, out):
    """Write the state derivative of ``stage`` at ``y`` into ``out``.

    Stage 1 gives NaN past the sling's reach (``eom.slide_constraint``), so a
    step that gets there is rejected; flight has quadratic drag on the
    air-relative velocity, ``a = -g e_y - (rho A / 2 m) Cd(Re) |v - w| (v - w)``
    with ``w = (wind, 0)``; ``table`` is ``analytic.aero.DRAG_TABLE``.
    """
    if stage == SLIDE:
        if FRICTION and lossy(p):
            ddtheta, ddphi, _, ta, th, fb, _, hinge, dx = slide_friction(
                y[0], y[1], y[2], y[3], y[SLIDE_MODES + AXLE], y[SLIDE_MODES + HINGE], y[SLIDE_MODES + BASE], p)
            out[0], out[1], out[2], out[3] = y[2], y[3], ddtheta, ddphi
            # The friction's power, -t rate: |t rate| while the mode is consistent, and
            # smooth where a rate crosses zero inside a step whose event root then ends the
            # stretch (an absolute value would put a kink inside that step).
            out[SLIDE_WORK + AXLE], out[SLIDE_WORK + HINGE], out[SLIDE_WORK + BASE] = (-ta * y[2], -th * y[3],
                                                                                    -fb * dx * y[2])
            if FLOATING_ARM and p.kind == FLOATING:
                slides_powers(y[0], y[2], ta, th, fb, p, out, SLIDE_WORK)
                if p.mub > 0.0:   # the base's friction F (``hinge``) against the slide D theta' [12.13]
                    out[SLIDE_BASE_WORK] = -hinge * dx * y[2]
            out[SLIDE_MODES + AXLE], out[SLIDE_MODES + HINGE], out[SLIDE_MODES + BASE] = 0.0, 0.0, 0.0
            return
        ddtheta, ddphi, _ = slide_accelerations(y[0], y[1], y[2], y[3], p)
        out[0], out[1], out[2], out[3] = y[2], y[3], ddtheta, ddphi
    elif stage == SWING:
        if FRICTION and lossy(p):
            a, b, c, ta, th, _, hinge = swing_friction(y[0], y[1], y[2], y[3], y[4], y[5], y[SWING_MODES + AXLE],
                                                       y[SWING_MODES + HINGE], p)
            out[0], out[1], out[2], out[3], out[4], out[5] = y[3], y[4], y[5], a, b, c
            out[SWING_WORK + AXLE], out[SWING_WORK + HINGE], out[SWING_WORK + BASE] = -ta * y[3], -th * y[4], 0.0
            if FLOATING_ARM and p.kind == FLOATING:
                slides_powers(y[0], y[3], ta, th, hinge, p, out, SWING_WORK)
                if p.mub > 0.0:
                    out[SWING_BASE_WORK] = 0.0
            out[SWING_MODES + AXLE], out[SWING_MODES + HINGE], out[SWING_MODES + BASE] = 0.0, 0.0, 0.0
            return
        a, b, c = swing_accelerations(y[0], y[1], y[2], y[3], y[4], y[5], p)
        out[0], out[1], out[2], out[3], out[4], out[5] = y[3], y[4], y[5], a, b, c
    elif stage == MACHINE:
        if FRICTION and lossy(p):
            ddtheta, ddphi, ta, th, _, hinge = machine_friction(y[0], y[1], y[2], y[3], y[MACHINE_MODES + AXLE],
                                                                y[MACHINE_MODES + HINGE], p)
            out[0], out[1], out[2], out[3] = y[2], y[3], ddtheta, ddphi
            out[MACHINE_WORK + AXLE], out[MACHINE_WORK + HINGE], out[MACHINE_WORK + BASE] = -ta * y[2], -th * y[3], 0.0
            if FLOATING_ARM and p.kind == FLOATING:
                slides_powers(y[0], y[2], ta, th, hinge, p, out, MACHINE_WORK)
                if p.mub > 0.0:
                    out[MACHINE_BASE_WORK] = 0.0
            out[MACHINE_MODES + AXLE], out[MACHINE_MODES + HINGE], out[MACHINE_MODES + BASE] = 0.0, 0.0, 0.0
            return
        ddtheta, ddphi = machine_accelerations(y[0], y[1], y[2], y[3], p)
        out[0], out[1], out[2], out[3] = y[2], y[3], ddtheta, ddphi
    else:
        vx_rel = y[2] - p.wind
        vy = y[3]
        k = drag_rate(int(p.drag), vx_rel, vy, p.diameter, p.rho, p.mu, p.cd, p.area, p.mP, table)
        out[0], out[1], out[2], out[3] = y[2], vy, -k * vx_rel, -p.g - k * vy


def slides_powers(theta, dtheta, q, fg, ft, p, out, at):
    """A floating arm's friction powers into ``out[at:at + 3]`` (a stage's work slots), W: the axle's,
    the guide's and the track's, each its force against its sliding [12.12], from the friction's generalised force ``q``
    on theta (N m) and the guide's and the track's forces ``fg``, ``ft`` (N)."""
    ls, lc = p.Lb * math.sin(theta), p.Lb * math.cos(theta)
    axle = q - ls * fg + lc * ft if p.mua > 0.0 else 0.0   # the axle's torque (exactly 0 without its friction)
    out[at + AXLE], out[at + HINGE], out[at + BASE] = -axle * dtheta, -ls * fg * dtheta, lc * ft * dtheta


def sling_off_vertical(theta, p):
    """Stage 1: ``|sin beta| - SLING_VERTICAL_LIMIT`` from the constraint, defined (as
    ``-limit``) even beyond the sling's reach."""
    cos_beta = -(p.h - p.ht + p.La * math.cos(theta)) / p.Ls
    return math.sqrt(max(0.0, 1.0 - cos_beta * cos_beta)) - SLING_VERTICAL_LIMIT


def event_count(stage, p):
    """How many of ``stage``'s events (``states.EVENT_NAMES``, in order) the design ``p`` watches: the
    friction events only with friction (without it they are a constant 1 and never fire)."""
    if FRICTION and lossy(p):
        return EVENT_COUNT[stage]
    return FIRST_FRICTION_EVENT[stage]


def event_value(stage, k, y, p):
    """Value of event ``k`` of ``stage`` at ``y`` (``analytic.states``' table)."""
    if stage == SLIDE:
        if FRICTION and k >= SLIDE_ARM_STALLS:   # (friction's events: watched only with friction, event_count)
            return friction_event(stage, k, y, p)
        off_vertical = sling_off_vertical(y[0], p)
        if k == SLIDE_UNDER_TIP:
            return off_vertical
        if k == SLIDE_LIFTOFF:
            if off_vertical <= 0.0:
                return 1.0   # no lift-off under the tip: under_tip ends the stage there
            if FRICTION and lossy(p):
                return slide_friction(y[0], y[1], y[2], y[3], y[SLIDE_MODES + AXLE], y[SLIDE_MODES + HINGE],
                                      y[SLIDE_MODES + BASE], p).normal
            return slide_accelerations(y[0], y[1], y[2], y[3], p).normal
        return p.La * math.cos(y[0]) + p.h - p.ht   # arm_back: the tip back down on the trough
    if stage == SWING:
        if FRICTION and k >= FIRST_SWITCH[SWING]:
            return friction_event(stage, k, y, p)
        if k == SWING_RELEASE:
            if p.rule == IDEAL_RULE:   # (analytic.ideal: the arm's angle, or its stop)
                return ideal_release(p.alpha, y[0], y[3]).value
            vx, vy = ground_velocity(y, p)
            return release_at(int(p.rule), p.alpha, y[0], y[2], vx, vy).value
        return p.La * math.cos(y[0]) + p.Ls * math.cos(y[0] + y[2]) + p.h - p.ht   # hits_base: back on the trough
    if stage == MACHINE:
        return friction_event(stage, k, y, p) if FRICTION else 1.0
    if k == FLIGHT_LANDING:
        return landing_value(y, p)
    return y[FLIGHT_VY]   # apex


def landing_value(y, p):
    """The flight's landing event at the state ``y`` (``docs/derivation.md``, the flight's landing):
    the centre's height above the target, ``y + h - yt``, which falls through zero where it comes
    down to the target's level (below the base for a pit, ``yt < 0``).

    A raised target (``yt > 0``) may be out of reach: the larger of the upward speed and the
    height above the target, which is positive while the projectile rises and falls through zero
    either where it comes down to the target (the height's root) or at an apex below it (the
    speed's root: the flight ends there, and ``sequence.short_of_target`` names it). Only the
    sign counts; the root that ends the flight is the one of the two that is zero there.
    """
    above = y[FLIGHT_Y] + p.h - p.yt
    if p.yt > 0.0:
        return max(y[FLIGHT_VY], above)
    return above


def first_event(t_a, k_a, t_b, k_b):
    """Which of two terminal events' roots in one step ends it: ``(t_a, k_a)`` (the root at
    ``t_a`` of event ``k_a``) or ``(t_b, k_b)`` (``k_b`` -1: none yet).

    The earlier root, unless the two are one instant to the root finder: Brent's method
    stops with a root within ``ROOT_TIME_TOLERANCE + ROOT_RELATIVE_TOLERANCE |t|`` of
    the sign change, so two roots of one sign change (``arm_stalls`` and
    ``slide_reverses`` both vanish with theta', ``docs/derivation.md`` 10.4) may lie
    up to twice that apart, either way round, and differently on the two paths.
    Within that the event listed first in ``states.EVENT_NAMES`` wins: a stage's end
    before a friction mode's switch.
    """
    if k_b < 0:
        return t_a, k_a
    window = 2.0 * (ROOT_TIME_TOLERANCE + ROOT_RELATIVE_TOLERANCE * max(abs(t_a), abs(t_b)))
    if abs(t_a - t_b) <= window:
        return (t_a, k_a) if k_a < k_b else (t_b, k_b)
    return (t_a, k_a) if t_a < t_b else (t_b, k_b)


def event_direction(stage, k):
    """+1: only rising crossings count; -1: only falling ones."""
    return 1 if (stage == SWING and k == SWING_RELEASE) else -1


def event_terminal(stage, k):
    """Whether a counted root of the event ends the stage (the apex is only recorded)."""
    return not (stage == FLIGHT and k == FLIGHT_APEX)


def event_turns(stage, k):
    """Whether a step in which the event's value keeps its sign but turns back is searched for a root
    there (``analytic.sequence``, ``turns_back``): the release's."""
    return stage == SWING and k == SWING_RELEASE


def event_armed(stage, k, y, p):
    """Whether a root of the event at ``y`` counts: only the release has a condition."""
    if stage == SWING and k == SWING_RELEASE:
        if p.rule == IDEAL_RULE:
            return True
        vx, vy = ground_velocity(y, p)
        return release_at(int(p.rule), p.alpha, y[0], y[2], vx, vy).armed
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


class Firing(NamedTuple):
    """The machine at rest (``fires``): the arm's acceleration, rad/s^2, and the base's push on the
    projectile, N."""

    ddtheta: float
    normal: float


def fires(p):
    """``Firing(theta'', N)`` at rest: the machine fires when theta'' < 0, and the projectile
    starts on the base when N > 0 (otherwise stage 1 is skipped).

    With friction the arm is stuck at rest: it fires only when gravity's torque
    beats what the axle's and the base's friction can hold (``friction.rest_balance``),
    and theta'' is then the slipping machine's (0 when held).
    """
    if not (FRICTION and lossy(p)):
        ddtheta, _, normal = slide_accelerations(p.theta0, p.phi0, 0.0, 0.0, p)
        return Firing(ddtheta, normal)
    drive, axle_hold, base_hold = rest_balance(p)
    sa, sh, sb = rest_modes(p)
    slipping = slide_friction(p.theta0, p.phi0, 0.0, 0.0, sa, sh, sb, p)
    normal = slipping.normal
    if not drive > axle_hold + base_hold:
        if FLOATING_ARM and p.kind == FLOATING:   # held: its base push (slipping, its guide and track may jam [12.10])
            normal = slide_friction(p.theta0, p.phi0, 0.0, 0.0, 0.0, sh, sb, p).normal
        return Firing(0.0, normal)
    return Firing(slipping.ddtheta, normal)


def slide_start(p, y):
    """Write the state at rest into ``y`` (``states.state_size(SLIDE, p)``): the arm and the counterweight
    at their rest angles, still; with friction, nothing dissipated and the ``states.rest_modes``."""
    y[0], y[1], y[2], y[3] = p.theta0, p.phi0, 0.0, 0.0
    if FRICTION and lossy(p):
        y[SLIDE_WORK + AXLE], y[SLIDE_WORK + HINGE], y[SLIDE_WORK + BASE] = 0.0, 0.0, 0.0
        y[SLIDE_MODES + AXLE], y[SLIDE_MODES + HINGE], y[SLIDE_MODES + BASE] = rest_modes(p)
        if FLOATING_ARM and p.kind == FLOATING and p.mub > 0.0:
            y[SLIDE_BASE_WORK] = 0.0


def swing_start(y, p, out):
    """Write the stage-2 start into ``out`` (``states.state_size(SWING, p)``) from the stage-1 state ``y`` at
    lift-off: ``(theta, phi, psi, theta', phi', psi')``, then with friction the work so far and the
    joints' modes (the base's off; a stuck joint is checked again: ``states.settle``)."""
    psi, dpsi, _, _, _ = slide_constraint(y[0], y[2], p)
    out[0], out[1], out[2], out[3], out[4], out[5] = y[0], y[1], psi, y[2], y[3], dpsi
    if FRICTION and lossy(p):
        _carry_friction(y, SLIDE_WORK, SLIDE_MODES, out, SWING_WORK, SWING_MODES)
        if FLOATING_ARM and p.kind == FLOATING and p.mub > 0.0:
            out[SWING_BASE_WORK] = y[SLIDE_BASE_WORK]
        settle(SWING, out, p)


def _carry_friction(y, work, modes, out, out_work, out_modes):
    """Copy the friction's work and the axle's and the hinge's modes from the state ``y`` (its slots at
    ``work``, ``modes``) into the next stage's ``out`` (at ``out_work``, ``out_modes``), the base's
    mode off: the projectile has left it."""
    out[out_work + AXLE], out[out_work + HINGE], out[out_work + BASE] = y[work + AXLE], y[work + HINGE], y[work + BASE]
    out[out_modes + AXLE], out[out_modes + HINGE], out[out_modes + BASE] = y[modes + AXLE], y[modes + HINGE], 0.0


def accelerations(stage, y, p):
    """``(theta'', phi'', psi'')`` at the stage-1 state ``[theta, phi, theta', phi', ...]`` or the
    stage-2 state ``[theta, phi, psi, theta', phi', psi', ...]``, friction included."""
    if FRICTION and lossy(p):
        solution = friction_solution(stage, y, p)
        return solution.ddtheta, solution.ddphi, solution.ddpsi
    if stage == SLIDE:
        ddtheta, ddphi, _ = slide_accelerations(y[0], y[1], y[2], y[3], p)
        _, _, s, c, _ = slide_constraint(y[0], y[2], p)
        return ddtheta, ddphi, s * ddtheta + c
    return swing_accelerations(y[0], y[1], y[2], y[3], y[4], y[5], p)


def flight_start(y, p):
    """The flight start ``(x, y, vx, vy)`` on the ground from the stage-2 state at release:
    x from the pivot's place at rest (where a rolling frame's pivot stood)."""
    x, height, vx, vy = projectile_state(y[0], y[2], y[3], y[5], p.La, p.Ls)
    frame_x, frame_v = frame_state(y, p)
    return x + frame_x, height, vx + frame_v, vy


def machine_params(p):
    """The design's ``Params`` without the projectile (mP = 0, and so no drag on it): the machine after release, the
    ``p`` of every stage-4 function (section 10.9). Python only (a namedtuple's ``_replace``): the
    fast path compiles stage 4 with the rest of this module but never runs it."""
    return p._replace(mP=0.0, drag_swing=0.0)


def machine_start(y, m, out):
    """Write the stage-4 start into ``out`` (``states.state_size(MACHINE, m)``) from the stage-2 state ``y``
    at release: ``(theta, phi, theta', phi')``, then with friction the work so far and the joints' modes,
    a stuck joint checked again without the sling's pull (``states.settle``). ``m``: ``machine_params``."""
    out[0], out[1], out[2], out[3] = y[0], y[1], y[3], y[4]
    if FRICTION and lossy(m):
        _carry_friction(y, SWING_WORK, SWING_MODES, out, MACHINE_WORK, MACHINE_MODES)
        if FLOATING_ARM and m.kind == FLOATING and m.mub > 0.0:
            out[MACHINE_BASE_WORK] = y[SWING_BASE_WORK]
        settle(MACHINE, out, m)


def machine_frame(y, m, momentum, start_time, start_y, start_x, time):
    """The frame's ``(X, X')`` after release at ``time`` and stage-4 state ``y`` (section 10.9).

    ``m``: ``machine_params``. ``momentum`` is the machine's horizontal momentum
    at release (kg m/s), kept since (the friction's torques are internal):
    ``Mt X' + S' = momentum`` with the machine's own mass and moment, so
    ``X = start_x + (momentum (t - t_r) - (S(q) - S(q_r))) / Mt``.
    """
    mass = total_mass(m)
    b1, b2, _, _ = frame_coupling(y[0], y[1], 0.0, y[2], y[3], 0.0, m)
    moved = horizontal_moment(y[0], y[1], 0.0, m) - horizontal_moment(start_y[0], start_y[1], 0.0, m)
    return (start_x + (momentum * (time - start_time) - moved) / mass,
            (momentum - b1 * y[2] - b2 * y[3]) / mass)


def floating_supports(stage, y, p):
    """A floating arm's ``(track_y, guide_x)``, N (``analytic.eom.floating_supports_in_air``), at the
    stage-1 state ``[theta, phi, theta', phi']`` or the stage-2 state ``[theta, phi, psi, theta', phi', psi']``
    (the axle's, the guide's, the track's and the base's friction and the drag during the swing included)."""
    if FRICTION and lossy(p):
        solution = friction_solution(stage, y, p)
        ddtheta, ddpsi, normal = solution.ddtheta, solution.ddpsi, solution.normal
        guide_friction, track_friction, base_friction = solution.hinge_torque, solution.base_force, solution.hinge_load
    else:
        ddtheta, _, ddpsi = accelerations(stage, y, p)
        normal = slide_accelerations(y[0], y[1], y[2], y[3], p).normal if stage == SLIDE else 0.0
        guide_friction, track_friction, base_friction = 0.0, 0.0, 0.0
    if stage == SLIDE:
        psi, dpsi, _, _, _ = slide_constraint(y[0], y[2], p)
        dtheta = y[2]
    else:
        psi, dtheta, dpsi = y[2], y[3], y[5]
    track_y, guide_x = floating_supports_in_air(y[0], psi, dtheta, dpsi, ddtheta, ddpsi, normal, p)
    # Each support's normal force is the momentum's rate less the other supports' friction [12.10], [12.13].
    return track_y - guide_friction, guide_x - track_friction - base_friction


#: What ``loads_at`` returns, in order (``analytic.eom.Loads``): N, N, N, m/s^2, N m.
LOAD_NAMES = Loads._fields


def loads_after_step(stage, y, f, p):
    """``loads_at(stage, y, p)`` at a step's end, where the integrator already holds the derivative
    ``f`` at ``y``: stage 2 reads its accelerations from ``f`` (the same numbers ``loads_at`` would
    compute again), stage 1 computes them with the base's push, and so does a floating arm with
    friction (its loads need the guide's and the track's friction forces too)."""
    if stage == SWING and (not (FLOATING_ARM and p.kind == FLOATING) or not (FRICTION and lossy(p))):
        return loads(y[0], y[1], y[2], y[3], y[4], y[5], f[3], f[4], f[5], 0.0, p)
    return loads_at(stage, y, p)


def loads_at(stage, y, p):
    """``eom.loads`` (a ``Loads``) at the stage-1 state ``[theta, phi, theta', phi']`` or the stage-2
    state ``[theta, phi, psi, theta', phi', psi']``: the accelerations and the base's
    push from the stage's own equations (0 push in stage 2)."""
    if FRICTION and lossy(p):
        solution = friction_solution(stage, y, p)
        ddtheta, ddphi, ddpsi, normal = solution.ddtheta, solution.ddphi, solution.ddpsi, solution.normal
        if FLOATING_ARM and p.kind == FLOATING:   # the guide's and the track's friction forces
            return _floating_loads(stage, y, ddtheta, ddpsi, normal, solution.hinge_torque, solution.base_force,
                                   solution.hinge_load, p)
        if stage == SLIDE:
            psi, dpsi, _, _, _ = slide_constraint(y[0], y[2], p)
            return loads_sliding(y[0], y[1], psi, y[2], y[3], dpsi, ddtheta, ddphi, ddpsi, normal,
                                 solution.base_force, p)
        return loads(y[0], y[1], y[2], y[3], y[4], y[5], ddtheta, ddphi, ddpsi, 0.0, p)
    if stage == SLIDE:
        ddtheta, ddphi, normal = slide_accelerations(y[0], y[1], y[2], y[3], p)
        psi, dpsi, s, c, _ = slide_constraint(y[0], y[2], p)
        return loads(y[0], y[1], psi, y[2], y[3], dpsi, ddtheta, ddphi, s * ddtheta + c, normal, p)
    ddtheta, ddphi, ddpsi = swing_accelerations(y[0], y[1], y[2], y[3], y[4], y[5], p)
    return loads(y[0], y[1], y[2], y[3], y[4], y[5], ddtheta, ddphi, ddpsi, 0.0, p)


def _floating_loads(stage, y, ddtheta, ddpsi, normal, guide_friction, track_friction, base_friction, p):
    """``loads_at`` of a floating arm with friction: ``eom.loads_sliding`` with the base's friction
    ``base_friction`` (N, 0 off the base) [12.13], with the axle's load the carriage's ``(ft, T)`` and the
    counterweight's mount's less the guide's friction too [12.10]."""
    if stage == SLIDE:
        psi, dpsi, _, _, _ = slide_constraint(y[0], y[2], p)
        theta, phi, dtheta, dphi = y[0], y[1], y[2], y[3]
    else:
        theta, phi, psi, dtheta, dphi, dpsi = y[0], y[1], y[2], y[3], y[4], y[5]
    _, _, tension, felt, bending = loads_sliding(theta, phi, psi, dtheta, dphi, dpsi, ddtheta, 0.0, ddpsi, normal,
                                                 base_friction, p)
    _, track, mount_x, mount_y, _, _ = joint_forces_sliding(theta, phi, psi, dtheta, dphi, dpsi, ddtheta, 0.0, ddpsi,
                                                            normal, base_friction, p)
    track -= guide_friction
    mount_x += track_friction
    mount_y -= guide_friction
    return Loads(math.sqrt(track_friction * track_friction + track * track),
                 math.sqrt(mount_x * mount_x + mount_y * mount_y), tension, felt, bending)
