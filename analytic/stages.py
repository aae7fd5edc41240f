"""The three stages of a shot: their states, right-hand sides and events, written once.

A stage is integrated from a start state until one of its terminal events
(or its time limit). Both analytic paths drive the same functions: the
reference path (``analytic.reference``) runs them under scipy's DOP853, the
compiled path (``analytic.fast.kernel``) compiles the same source. Plain ``math``
on floats and indexing into ``y`` and ``out``, nothing else.

=====  ===========================================  ================================================
stage  state y                                      events (value; counted direction; ends stage?)
=====  ===========================================  ================================================
1      [theta, phi, theta', phi']                   under_tip (|sin beta| - limit; falling; yes),
       (psi from the base constraint)               liftoff (normal force; falling; yes),
                                                    arm_back (tip height above base; falling; yes),
                                                    arm_stalls (-theta'; falling; yes),
                                                    hinge_stops, hinge_slips, slide_reverses
                                                    (``friction_event``; falling; switch modes)
2      [theta, phi, psi, theta', phi', psi']        release (the rule's value; rising; yes, only
                                                    when armed), hits_base (projectile height; falling; yes),
                                                    axle_stops, axle_slips, hinge_stops, hinge_slips
                                                    (``friction_event``; falling; switch modes)
3      [x, y, vx, vy] from the pivot                landing (height above base; falling; yes),
                                                    apex (vy; falling; no: recorded)
4      [theta, phi, theta', phi']: the machine      axle_stops, axle_slips, hinge_stops, hinge_slips
       after release, without the projectile        (``friction_event``; falling; switch modes)
       (``MACHINE``; ``p`` is ``machine_params``)
=====  ===========================================  ================================================

Stage 4 is not a stage of the shot's outcome: it runs alongside the flight, from
release to landing, for the frame's place at landing (``docs/derivation.md``
section 10.9). Its functions take ``machine_params(p)``, the design's numbers
without the projectile (mP = 0), so that they are stage 2's with one row and
column fewer.

With friction (``docs/derivation.md`` section 10) stages 1-2 and 4 carry six more
entries (``FRICTION_STATE``: the work each friction dissipated, then the
modes); a friction event ends an integration, ``switch_mode`` writes the new
modes into the state and the stage goes on from there. Without friction
those events are a constant 1 and the state is as in the table.

Two terminal events whose roots in one step lie within the root finder's
tolerance of each other are one instant, and the earlier-listed wins
(``first_event``: both paths decide by it).

Why one file of about 600 lines: the stages' right-hand sides, events and
starts read the friction modes in the state, and the modes' choice
(``decide_modes``, ``switch_mode``) reads the stages' layout and events; apart,
the two would import each other. The equations themselves are elsewhere
(``analytic.eom``, ``analytic.friction``), and what a stage's end means is
``analytic.sequence``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from analytic.scope import FLOATING_ARM, FRICTION   # what this copy handles (analytic.scope)
from analytic.aero import drag_rate
from analytic.eom import (FLOATING, floating_supports_in_air, frame_coupling, frame_displacement, frame_velocity,
                          horizontal_moment, joint_forces, loads, loads_sliding, machine_accelerations,
                          slide_accelerations, slide_constraint, swing_accelerations, total_mass)
from analytic.friction import (lossy, machine_friction, rest_balance, slide_friction, slide_rate, static_arm,
                               swing_friction)
from analytic.geometry import projectile_state, release_at
from analytic.limits import SLING_VERTICAL_LIMIT
from analytic.outcome import Stage

SLIDE, SWING, FLIGHT = int(Stage.SLIDE), int(Stage.SWING), int(Stage.FLIGHT)
#: The machine after release (stage 4): the arm and the counterweight swing on without the projectile.
MACHINE = 4
#: Length of the state of each stage (indexed by stage number), without friction.
STATE_SIZE = (0, 4, 6, 4, 4)
#: A design with friction carries ``FRICTION_STATE`` more entries in stages 1-2 and 4, after
#: the stage's own (``state_size``): the work dissipated so far by the axle's, the
#: hinge's and the base's friction (J, integrated with the motion), then the modes
#: of the axle, the hinge and the base (constant between events: +1/-1 slipping
#: with that sign of the rate, 0 stuck; the base's is the slide's sign, 0 off it).
FRICTION_STATE = 6
#: Where the friction's parts start within it: the work (axle, hinge, base), then the modes.
FRICTION_WORK, FRICTION_MODES = 0, 3
#: Events of each stage, in their index order (indexed by stage number). The
#: friction's (from ``arm_stalls`` and ``axle_stops`` on) are inert (a constant
#: 1) for a design without that friction.
EVENT_NAMES = ((), ("under_tip", "liftoff", "arm_back", "arm_stalls", "hinge_stops", "hinge_slips",
                    "slide_reverses"),
               ("release", "hits_base", "axle_stops", "axle_slips", "hinge_stops", "hinge_slips"),
               ("landing", "apex"), ("axle_stops", "axle_slips", "hinge_stops", "hinge_slips"))
#: The first event of each stage that switches a friction mode (the stage goes on
#: from there in the new mode, ``switch_mode``); ``arm_stalls`` ends stage 1 instead.
FIRST_SWITCH = (0, 4, 2, 2, 0)
#: Index of ``arm_stalls`` in stage 1.
ARM_STALLS = 3
#: The first friction event of each stage (``arm_stalls`` in stage 1): a design without
#: friction watches only the events before it (``event_count``).
FIRST_FRICTION_EVENT = (0, ARM_STALLS, FIRST_SWITCH[2], 2, 0)
#: How many events each stage has (``EVENT_NAMES``).
EVENT_COUNT = tuple(len(names) for names in EVENT_NAMES)
#: A shot may switch friction modes this many times; more is a failure
#: (``STEP_FAILED``): stick and slip chattering without end.
MODE_SWITCH_LIMIT = 2000
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
            ddtheta, ddphi, _, ta, th, fb, _, _, dx = slide_friction(y[0], y[1], y[2], y[3], y[7], y[8], y[9], p)
            out[0], out[1], out[2], out[3] = y[2], y[3], ddtheta, ddphi
            # The friction's power, -t rate: |t rate| while the mode is consistent, and
            # smooth where a rate crosses zero inside a step whose event root then ends the
            # stretch (an absolute value would put a kink inside that step).
            out[4], out[5], out[6] = -ta * y[2], -th * y[3], -fb * dx * y[2]
            if FLOATING_ARM and p.kind == FLOATING:
                slides_powers(y[0], y[2], ta, th, fb, p, out, 4)
            out[7], out[8], out[9] = 0.0, 0.0, 0.0
            return
        ddtheta, ddphi, _ = slide_accelerations(y[0], y[1], y[2], y[3], p)
        out[0], out[1], out[2], out[3] = y[2], y[3], ddtheta, ddphi
    elif stage == SWING:
        if FRICTION and lossy(p):
            a, b, c, ta, th, _, hinge = swing_friction(y[0], y[1], y[2], y[3], y[4], y[5], y[9], y[10], p)
            out[0], out[1], out[2], out[3], out[4], out[5] = y[3], y[4], y[5], a, b, c
            out[6], out[7], out[8] = -ta * y[3], -th * y[4], 0.0
            if FLOATING_ARM and p.kind == FLOATING:
                slides_powers(y[0], y[3], ta, th, hinge, p, out, 6)
            out[9], out[10], out[11] = 0.0, 0.0, 0.0
            return
        a, b, c = swing_accelerations(y[0], y[1], y[2], y[3], y[4], y[5], p)
        out[0], out[1], out[2], out[3], out[4], out[5] = y[3], y[4], y[5], a, b, c
    elif stage == MACHINE:
        if FRICTION and lossy(p):
            ddtheta, ddphi, ta, th, _, hinge = machine_friction(y[0], y[1], y[2], y[3], y[7], y[8], p)
            out[0], out[1], out[2], out[3] = y[2], y[3], ddtheta, ddphi
            out[4], out[5], out[6] = -ta * y[2], -th * y[3], 0.0
            if FLOATING_ARM and p.kind == FLOATING:
                slides_powers(y[0], y[2], ta, th, hinge, p, out, 4)
            out[7], out[8], out[9] = 0.0, 0.0, 0.0
            return
        ddtheta, ddphi = machine_accelerations(y[0], y[1], y[2], y[3], p)
        out[0], out[1], out[2], out[3] = y[2], y[3], ddtheta, ddphi
    else:
        vx_rel = y[2] - p.wind
        vy = y[3]
        k = drag_rate(int(p.drag), vx_rel, vy, p.diameter, p.rho, p.mu, p.cd, p.area, p.mP, table)
        out[0], out[1], out[2], out[3] = y[2], vy, -k * vx_rel, -p.g - k * vy


def slides_powers(theta, dtheta, q, fg, ft, p, out, at):
    """A floating arm's friction powers into ``out[at:at + 3]``, W: the axle's, the guide's and the
    track's, each its force against its sliding [12.12], from the friction's generalised force ``q``
    on theta (N m) and the guide's and the track's forces ``fg``, ``ft`` (N)."""
    ls, lc = p.Lb * math.sin(theta), p.Lb * math.cos(theta)
    axle = q - ls * fg + lc * ft if p.mua > 0.0 else 0.0   # the axle's torque (exactly 0 without its friction)
    out[at], out[at + 1], out[at + 2] = -axle * dtheta, -ls * fg * dtheta, lc * ft * dtheta


def sling_off_vertical(theta, p):
    """Stage 1: ``|sin beta| - SLING_VERTICAL_LIMIT`` from the constraint, defined (as
    ``-limit``) even beyond the sling's reach."""
    cos_beta = -(p.h + p.La * math.cos(theta)) / p.Ls
    return math.sqrt(max(0.0, 1.0 - cos_beta * cos_beta)) - SLING_VERTICAL_LIMIT


def event_count(stage, p):
    """How many of ``stage``'s events (``EVENT_NAMES``, in order) the design ``p`` watches: the
    friction events only with friction (without it they are a constant 1 and never fire)."""
    if FRICTION and lossy(p):
        return EVENT_COUNT[stage]
    return FIRST_FRICTION_EVENT[stage]


def event_value(stage, k, y, p):
    """Value of event ``k`` of ``stage`` at ``y`` (see the table above)."""
    if stage == SLIDE:
        if FRICTION and k >= ARM_STALLS:   # (friction's events: watched only with friction, event_count)
            return friction_event(stage, k, y, p)
        off_vertical = sling_off_vertical(y[0], p)
        if k == 0:
            return off_vertical
        if k == 1:
            if off_vertical <= 0.0:
                return 1.0   # no lift-off under the tip: under_tip ends the stage there
            if FRICTION and lossy(p):
                return slide_friction(y[0], y[1], y[2], y[3], y[7], y[8], y[9], p)[2]
            return slide_accelerations(y[0], y[1], y[2], y[3], p)[2]
        return p.La * math.cos(y[0]) + p.h
    if stage == SWING:
        if FRICTION and k >= FIRST_SWITCH[SWING]:
            return friction_event(stage, k, y, p)
        if k == 0:
            vx, vy = ground_velocity(y, p)
            return release_at(int(p.rule), p.alpha, y[0], y[2], vx, vy)[0]
        return p.La * math.cos(y[0]) + p.Ls * math.cos(y[0] + y[2]) + p.h
    if stage == MACHINE:
        return friction_event(stage, k, y, p) if FRICTION else 1.0
    if k == 0:
        return y[1] + p.h
    return y[3]


def first_event(t_a, k_a, t_b, k_b):
    """Which of two terminal events' roots in one step ends it: ``(t_a, k_a)`` (the root at
    ``t_a`` of event ``k_a``) or ``(t_b, k_b)`` (``k_b`` -1: none yet).

    The earlier root, unless the two are one instant to the root finder: Brent's method
    stops with a root within ``ROOT_TIME_TOLERANCE + ROOT_RELATIVE_TOLERANCE |t|`` of
    the sign change, so two roots of one sign change (``arm_stalls`` and
    ``slide_reverses`` both vanish with theta', ``docs/derivation.md`` 10.4) may lie
    up to twice that apart, either way round, and differently on the two paths.
    Within that the event listed first in ``EVENT_NAMES`` wins: a stage's end
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
    return 1 if (stage == SWING and k == 0) else -1


def event_terminal(stage, k):
    """Whether a counted root of the event ends the stage (the apex is only recorded)."""
    return not (stage == FLIGHT and k == 1)


def event_turns(stage, k):
    """Whether a step in which the event's value keeps its sign but turns back is searched for a root
    there (``analytic.sequence``, ``turns_back``): the release's."""
    return stage == SWING and k == 0


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
    starts on the base when N > 0 (otherwise stage 1 is skipped).

    With friction the arm is stuck at rest: it fires only when gravity's torque
    beats what the axle's and the base's friction can hold (``friction.rest_balance``),
    and theta'' is then the slipping machine's (0 when held).
    """
    if not (FRICTION and lossy(p)):
        ddtheta, _, normal = slide_accelerations(p.theta0, p.phi0, 0.0, 0.0, p)
        return ddtheta, normal
    drive, axle_hold, base_hold = rest_balance(p)
    sa, sh, sb = rest_modes(p)
    ddtheta, _, normal, _, _, _, _, _, _ = slide_friction(p.theta0, p.phi0, 0.0, 0.0, sa, sh, sb, p)
    if not drive > axle_hold + base_hold:
        if FLOATING_ARM and p.kind == FLOATING:   # held: its base push (slipping, its guide and track may jam [12.10])
            normal = slide_friction(p.theta0, p.phi0, 0.0, 0.0, 0.0, sh, sb, p)[2]
        return 0.0, normal
    return ddtheta, normal


def rest_modes(p):
    """The friction modes ``(axle, hinge, base)`` the shot starts in: the arm slips clockwise
    (-1), the projectile slides the way dx_P/dtheta theta' points, and the hinge, at rest,
    stays stuck if its static friction can hold the counterweight's link (0), or slips the
    way it is pushed (as ``decide_modes`` would)."""
    _, _, s, _, sin_beta = slide_constraint(p.theta0, 0.0, p)
    sb = -1.0 if slide_rate(p.theta0, s, sin_beta, p) >= 0.0 else 1.0
    sh = 1.0
    if static_arm(1, p) > 0.0:
        _, _, _, _, th, _, _, hinge, _ = slide_friction(p.theta0, p.phi0, 0.0, 0.0, -1.0, 0.0, sb, p)
        sh = 0.0
        if not abs(th) < static_arm(1, p) * hinge:
            sh = -1.0 if th > 0.0 else 1.0
    return -1.0, sh, sb


def state_size(stage, p):
    """Length of ``stage``'s state for the design ``p``: ``STATE_SIZE`` plus, in stages 1-2
    of a design with friction, ``FRICTION_STATE``."""
    if stage != FLIGHT and FRICTION and lossy(p):
        return STATE_SIZE[stage] + FRICTION_STATE
    return STATE_SIZE[stage]


def slide_start(p, y):
    """Write the state at rest into ``y`` (``state_size(SLIDE, p)``): the arm and the counterweight
    at their rest angles, still; with friction, nothing dissipated and the ``rest_modes``."""
    y[0], y[1], y[2], y[3] = p.theta0, p.phi0, 0.0, 0.0
    if FRICTION and lossy(p):
        sa, sh, sb = rest_modes(p)
        y[4], y[5], y[6], y[7], y[8], y[9] = 0.0, 0.0, 0.0, sa, sh, sb


def swing_start(y, p, out):
    """Write the stage-2 start into ``out`` (``state_size(SWING, p)``) from the stage-1 state ``y`` at
    lift-off: ``(theta, phi, psi, theta', phi', psi')``, then with friction the work so far and the
    joints' modes (the base's off; a stuck joint is checked again: ``settle``)."""
    psi, dpsi, _, _, _ = slide_constraint(y[0], y[2], p)
    out[0], out[1], out[2], out[3], out[4], out[5] = y[0], y[1], psi, y[2], y[3], dpsi
    if FRICTION and lossy(p):
        out[6], out[7], out[8], out[9], out[10], out[11] = y[4], y[5], y[6], y[7], y[8], 0.0
        settle(SWING, out, p)


# --------------------------------------------------------------------------- #
# Friction's modes: stick and slip [10.4]
# --------------------------------------------------------------------------- #

class FrictionSolution(NamedTuple):
    """The motion and the friction at a state of a design with friction (``friction_solution``).

    Accelerations in rad/s^2; the normal force ``normal`` and the base's friction
    force ``base_force`` in N, 0 off the base; the friction torques in N m and the
    joints' load magnitudes ``|A|``, ``|H|`` in N; ``slide_ratio`` dx_P/dtheta, m/rad
    (0 off the base).

    A floating arm's [12.10]: ``axle_torque`` is the generalised force on theta of the axle's,
    the guide's and the track's friction together, N m; ``hinge_torque`` and ``base_force`` are
    the guide's and the track's friction forces, N (its hinge and base have none); ``axle_load``
    is the hold of ``friction.slides_friction`` (``friction.static_arm`` is 1), ``hinge_load`` 0.
    """

    ddtheta: float
    ddphi: float
    ddpsi: float
    normal: float
    axle_torque: float
    hinge_torque: float
    base_force: float
    axle_load: float
    hinge_load: float
    slide_ratio: float


def friction_solution(stage, y, p):
    """The ``FrictionSolution`` at the stage-1, stage-2 or stage-4 state ``y`` of a design with
    friction (psi'' 0 in stage 4)."""
    if stage == SLIDE:
        ddtheta, ddphi, normal, ta, th, fb, axle, hinge, dx = slide_friction(y[0], y[1], y[2], y[3], y[7],
                                                                            y[8], y[9], p)
        _, _, s, c, _ = slide_constraint(y[0], y[2], p)
        return FrictionSolution(ddtheta, ddphi, s * ddtheta + c, normal, ta, th, fb, axle, hinge, dx)
    if stage == MACHINE:
        ddtheta, ddphi, ta, th, axle, hinge = machine_friction(y[0], y[1], y[2], y[3], y[7], y[8], p)
        ddpsi = 0.0
    else:
        ddtheta, ddphi, ddpsi, ta, th, axle, hinge = swing_friction(y[0], y[1], y[2], y[3], y[4], y[5], y[9],
                                                                    y[10], p)
    if FLOATING_ARM and p.kind == FLOATING:   # the track's force comes back in the hinge's place
        return FrictionSolution(ddtheta, ddphi, ddpsi, 0.0, ta, th, hinge, axle, 0.0, 0.0)
    return FrictionSolution(ddtheta, ddphi, ddpsi, 0.0, ta, th, 0.0, axle, hinge, 0.0)


def joint_torque(solution, joint):
    """The friction-free torque holding ``joint`` (0 the axle, 1 the hinge) in ``solution``, N m."""
    return solution.axle_torque if joint == 0 else solution.hinge_torque


def joint_load(solution, joint):
    """The load magnitude on ``joint``'s bearing in ``solution``, N."""
    return solution.axle_load if joint == 0 else solution.hinge_load


def joint_acceleration(solution, joint):
    """The angular acceleration of ``joint``'s rate (the arm's, or the counterweight's) in ``solution``."""
    return solution.ddtheta if joint == 0 else solution.ddphi


def mode_slot(stage, joint):
    """Where ``joint``'s friction mode (0 the axle, 1 the hinge, 2 the base) is in ``stage``'s state."""
    return STATE_SIZE[stage] + FRICTION_MODES + joint


def rate_slot(stage, joint):
    """Where ``joint``'s rate (0 theta', 1 phi') is in ``stage``'s state: the rates follow the angles."""
    return STATE_SIZE[stage] // 2 + joint


def friction_event(stage, k, y, p):
    """Value of the friction event ``k`` (``EVENT_NAMES``) at ``y``; each counts falling crossings.

    * ``arm_stalls``: ``-theta'`` (stage 1, with axle or base friction);
    * ``axle_stops``, ``hinge_stops``: the slipping joint's rate times its mode;
    * ``axle_slips``, ``hinge_slips``: the stuck joint's static friction capacity less the
      torque holding it, ``mu_s r |F| - |t|`` (``friction.static_arm``);
    * ``slide_reverses``: the slide's direction over the base times its mode, ``-sigma_b D``
      (its velocity is ``D theta'`` with ``theta' < 0`` throughout stage 1).

    An event for a friction the design lacks, or for a joint in the other
    mode, is the constant 1 (it never fires).
    """
    if not (FRICTION and lossy(p)):
        return 1.0
    if stage == SLIDE and k == ARM_STALLS:
        return -y[2] if (p.mua_s > 0.0 or p.mub_s > 0.0 or p.mug_s > 0.0 or p.mut_s > 0.0) else 1.0
    if stage == SLIDE and k == 6:
        if p.mub == 0.0:
            return 1.0
        # The slide's direction with the arm turning clockwise, as it does throughout stage 1
        # (``arm_stalls`` ends the stage where it stops): -D, not D theta', which also reaches 0
        # where the arm stalls, and would tie with arm_stalls there.
        _, _, s, _, sin_beta = slide_constraint(y[0], y[2], p)
        return -y[9] * slide_rate(y[0], s, sin_beta, p)
    joint = switched_joint(stage, k)
    slips = (k - FIRST_SWITCH[stage]) % 2 == 1
    friction = static_arm(joint, p)
    mode = y[mode_slot(stage, joint)]
    if friction == 0.0 or (mode == 0.0) != slips:
        return 1.0
    if not slips:
        return mode * y[rate_slot(stage, joint)]
    solution = friction_solution(stage, y, p)
    return friction * joint_load(solution, joint) - abs(joint_torque(solution, joint))


def switched_joint(stage, k):
    """The joint (0 axle, 1 hinge) of the friction event ``k``: stage 1 has only the hinge's
    (the axle's stall ends it), stages 2 and 4 the axle's then the hinge's."""
    if stage == SLIDE:
        return 1
    return (k - FIRST_SWITCH[stage]) // 2


#: A joint at rest may be stuck (0) or slip either way; tried in this order.
MODE_CHOICES = (0.0, -1.0, 1.0)


def _at_rest(stage, joint, y, p):
    """Whether ``joint`` has friction, may stick in ``stage`` (not the axle in stage 1) and its
    rate is exactly 0 (stuck, or just stopped): its mode is to be chosen."""
    if static_arm(joint, p) == 0.0 or (stage == SLIDE and joint == 0):
        return False
    return y[rate_slot(stage, joint)] == 0.0


def consistent(stage, y, p, free_axle, free_hinge, must_slip):
    """Whether the modes in ``y`` of the joints at rest (``free_*``) are consistent: each stuck
    one is held by its static friction with room to spare, ``mu_s r |F| > |t|``
    (``friction.static_arm``); each slipping one accelerates the way it slips
    (its kinetic friction opposes the motion it starts). The joint ``must_slip``
    (its hold just failed: with equal coefficients its acceleration slipping is 0
    to round-off) must slip the way its holding torque pushes it instead, the sign of ``-t``."""
    solution = friction_solution(stage, y, p)
    for joint in range(2):
        if not (free_axle if joint == 0 else free_hinge):
            continue
        slot = mode_slot(stage, joint)
        mode = y[slot]
        if mode == 0.0:
            if not abs(joint_torque(solution, joint)) < static_arm(joint, p) * joint_load(solution, joint):
                return False
        elif joint == must_slip:
            y[slot] = 0.0
            held = friction_solution(stage, y, p)
            y[slot] = mode
            if joint_torque(held, joint) * mode > 0.0:
                return False
        elif joint_acceleration(solution, joint) * mode < 0.0:
            return False
    return True


def decide_modes(stage, y, p, must_slip):
    """Choose the modes of every joint at rest in ``y`` (``_at_rest``) together, and write them.

    The joints are coupled (each one's torque moves the other), so the
    combinations are tried, fewest slipping first, and the first ``consistent``
    one is taken: a joint sticks if the friction can hold it with the other
    joint as it then moves, else slips the way that its own friction opposes.
    ``must_slip``: a joint (0 or 1) whose hold just failed (its ``*_slips``
    event: the root lies within round-off of the balance, so sticking is not
    tried again), or -1. If no combination is consistent (not met in the
    tests), each joint at rest is tried alone, in order, as if the other's
    mode were final.
    """
    free_axle, free_hinge = _at_rest(stage, 0, y, p), _at_rest(stage, 1, y, p)
    if not (free_axle or free_hinge):
        return
    axle_slot, hinge_slot = mode_slot(stage, 0), mode_slot(stage, 1)
    kept_axle, kept_hinge = y[axle_slot], y[hinge_slot]
    for slipping in range(3):
        for i in range(3 if free_axle else 1):
            for j in range(3 if free_hinge else 1):
                axle = MODE_CHOICES[i] if free_axle else kept_axle
                hinge = MODE_CHOICES[j] if free_hinge else kept_hinge
                count = (1 if (free_axle and axle != 0.0) else 0) + (1 if (free_hinge and hinge != 0.0) else 0)
                if count != slipping or (must_slip == 0 and axle == 0.0) or (must_slip == 1 and hinge == 0.0):
                    continue
                y[axle_slot], y[hinge_slot] = axle, hinge
                if consistent(stage, y, p, free_axle, free_hinge, must_slip):
                    return
    for joint in range(2):
        if not (free_axle if joint == 0 else free_hinge):
            continue
        slot = mode_slot(stage, joint)
        y[slot] = 0.0
        solution = friction_solution(stage, y, p)
        torque = joint_torque(solution, joint)
        if joint == must_slip or not abs(torque) < static_arm(joint, p) * joint_load(solution, joint):
            y[slot] = -1.0 if torque > 0.0 else 1.0


def settle(stage, y, p):
    """Choose again the modes of the joints at rest in ``y`` (a new stage): ``decide_modes``."""
    decide_modes(stage, y, p, -1)


def switch_mode(stage, k, y, p):
    """After the friction event ``k`` (from ``FIRST_SWITCH[stage]``) at ``y``: the new modes, written
    into ``y``. A joint whose rate reached 0 is stopped (its rate set to exactly 0) and the
    modes of every joint at rest are chosen together (``decide_modes``; one whose hold
    failed must slip); the base's slide reverses its sign."""
    must_slip = -1
    if stage == SLIDE and k == 6:
        y[9] = -y[9]
    else:
        joint = switched_joint(stage, k)
        y[STATE_SIZE[stage] // 2 + joint] = 0.0
        if (k - FIRST_SWITCH[stage]) % 2 == 1:
            must_slip = joint
    decide_modes(stage, y, p, must_slip)


def accelerations(stage, y, p):
    """``(theta'', phi'', psi'')`` at the stage-1 state ``[theta, phi, theta', phi', ...]`` or the
    stage-2 state ``[theta, phi, psi, theta', phi', psi', ...]``, friction included."""
    if FRICTION and lossy(p):
        solution = friction_solution(stage, y, p)
        return solution[0], solution[1], solution[2]
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
    """Write the stage-4 start into ``out`` (``state_size(MACHINE, m)``) from the stage-2 state ``y`` at
    release: ``(theta, phi, theta', phi')``, then with friction the work so far and the joints' modes,
    a stuck joint checked again without the sling's pull (``settle``). ``m``: ``machine_params``."""
    out[0], out[1], out[2], out[3] = y[0], y[1], y[3], y[4]
    if FRICTION and lossy(m):
        out[4], out[5], out[6], out[7], out[8], out[9] = y[6], y[7], y[8], y[9], y[10], 0.0
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
    (the axle's, the guide's and the track's friction and the drag during the swing included)."""
    if FRICTION and lossy(p):
        solution = friction_solution(stage, y, p)
        ddtheta, ddpsi, normal = solution.ddtheta, solution.ddpsi, solution.normal
        guide_friction, track_friction = solution.hinge_torque, solution.base_force
    else:
        ddtheta, _, ddpsi = accelerations(stage, y, p)
        normal = slide_accelerations(y[0], y[1], y[2], y[3], p)[2] if stage == SLIDE else 0.0
        guide_friction, track_friction = 0.0, 0.0
    if stage == SLIDE:
        psi, dpsi, _, _, _ = slide_constraint(y[0], y[2], p)
        dtheta = y[2]
    else:
        psi, dtheta, dpsi = y[2], y[3], y[5]
    track_y, guide_x = floating_supports_in_air(y[0], psi, dtheta, dpsi, ddtheta, ddpsi, normal, p)
    # Each support's normal force is the momentum's rate less the other support's friction [12.10].
    return track_y - guide_friction, guide_x - track_friction


#: What ``loads_at`` returns, in order (``analytic.eom.loads``): N, N, N, m/s^2, N m.
LOAD_NAMES = ("axle_load", "hinge_load", "sling_tension", "projectile_acceleration", "arm_bending_moment")


def loads_after_step(stage, y, f, p):
    """``loads_at(stage, y, p)`` at a step's end, where the integrator already holds the derivative
    ``f`` at ``y``: stage 2 reads its accelerations from ``f`` (the same numbers ``loads_at`` would
    compute again), stage 1 computes them with the base's push, and so does a floating arm with
    friction (its loads need the guide's and the track's friction forces too)."""
    if stage == SWING and (not (FLOATING_ARM and p.kind == FLOATING) or not (FRICTION and lossy(p))):
        return loads(y[0], y[1], y[2], y[3], y[4], y[5], f[3], f[4], f[5], 0.0, p)
    return loads_at(stage, y, p)


def loads_at(stage, y, p):
    """``eom.loads`` at the stage-1 state ``[theta, phi, theta', phi']`` or the stage-2
    state ``[theta, phi, psi, theta', phi', psi']``: the accelerations and the base's
    push from the stage's own equations (0 push in stage 2)."""
    if FRICTION and lossy(p):
        ddtheta, ddphi, ddpsi, normal, _, th, fb, _, _, _ = friction_solution(stage, y, p)
        if FLOATING_ARM and p.kind == FLOATING:
            return _floating_loads(stage, y, ddtheta, ddpsi, normal, th, fb, p)
        if stage == SLIDE:
            psi, dpsi, _, _, _ = slide_constraint(y[0], y[2], p)
            return loads_sliding(y[0], y[1], psi, y[2], y[3], dpsi, ddtheta, ddphi, ddpsi, normal, fb, p)
        return loads(y[0], y[1], y[2], y[3], y[4], y[5], ddtheta, ddphi, ddpsi, 0.0, p)
    if stage == SLIDE:
        ddtheta, ddphi, normal = slide_accelerations(y[0], y[1], y[2], y[3], p)
        psi, dpsi, s, c, _ = slide_constraint(y[0], y[2], p)
        return loads(y[0], y[1], psi, y[2], y[3], dpsi, ddtheta, ddphi, s * ddtheta + c, normal, p)
    ddtheta, ddphi, ddpsi = swing_accelerations(y[0], y[1], y[2], y[3], y[4], y[5], p)
    return loads(y[0], y[1], y[2], y[3], y[4], y[5], ddtheta, ddphi, ddpsi, 0.0, p)


def _floating_loads(stage, y, ddtheta, ddpsi, normal, guide_friction, track_friction, p):
    """``loads_at`` of a floating arm with friction: ``eom.loads``, with the axle's load the carriage's
    ``(ft, T)`` and the counterweight's mount's less the guide's friction too [12.10]."""
    if stage == SLIDE:
        psi, dpsi, _, _, _ = slide_constraint(y[0], y[2], p)
        theta, phi, dtheta, dphi = y[0], y[1], y[2], y[3]
    else:
        theta, phi, psi, dtheta, dphi, dpsi = y[0], y[1], y[2], y[3], y[4], y[5]
    _, _, tension, felt, bending = loads(theta, phi, psi, dtheta, dphi, dpsi, ddtheta, 0.0, ddpsi, normal, p)
    _, track, mount_x, mount_y, _, _ = joint_forces(theta, phi, psi, dtheta, dphi, dpsi, ddtheta, 0.0, ddpsi,
                                                    normal, p)
    track -= guide_friction
    mount_x += track_friction
    mount_y -= guide_friction
    return (math.sqrt(track_friction * track_friction + track * track),
            math.sqrt(mount_x * mount_x + mount_y * mount_y), tension, felt, bending)
