"""Each stage's state and events by name, and friction's modes in the state: stick and slip, written once.

The layout both paths read (``analytic.stages`` integrates these states, the
compiled path's kernel and the reference path step them): a stage's state is a
flat array of floats, and each entry and each event has a name here. Plain
``math`` on floats and indexing into ``y``, like the rest of the model.

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
       (``MACHINE``; ``p`` is ``stages.machine_params``)
=====  ===========================================  ================================================

With friction (``docs/derivation.md`` section 10) stages 1-2 and 4 carry six more
entries after the stage's own (``FRICTION_STATE``): the work each friction dissipated
(``SLIDE_WORK + AXLE`` ...), then the joints' modes (``SLIDE_MODES + AXLE`` ...); a floating
arm with the base's friction one more, its base's work (``SLIDE_BASE_WORK`` ...). A
friction event ends an integration, ``switch_mode`` writes the new modes into the
state and the stage goes on from there. Without friction those events are a
constant 1 and the state is as in the table.

The mechanical part of a state is read in the table's order, whole, into the
equations' arguments (``slide_accelerations(y[0], y[1], y[2], y[3], p)`` is
``(theta, phi, theta', phi')``); an entry read for its meaning has a name
(``FLIGHT_Y``, ``rate_slot``, the friction's slots).

Why the modes' choice lives beside the layout rather than beside the stages'
right-hand sides (``analytic.stages``): the stages' starts and events read the
modes and ask for new ones (``settle``, ``switch_mode``, ``friction_event``),
and the choice reads only the layout and the friction's equations
(``analytic.friction``), so it sits below the stages, not in a circle with them.
"""

from __future__ import annotations

from typing import NamedTuple

from analytic.scope import FLOATING_ARM, FRICTION   # what this copy handles (analytic.scope)
from analytic.eom import FLOATING, slide_constraint
from analytic.friction import (AXLE, BASE, HINGE, lossy, machine_friction, slide_friction, slide_rate, static_arm,
                               swing_friction)
from analytic.outcome import Stage

SLIDE, SWING, FLIGHT = int(Stage.SLIDE), int(Stage.SWING), int(Stage.FLIGHT)
#: The machine after release (stage 4): the arm and the counterweight swing on without the projectile.
MACHINE = 4
#: Length of the state of each stage (indexed by stage number), without friction.
STATE_SIZE = (0, 4, 6, 4, 4)
#: The flight's state: the projectile's centre and velocity, from the pivot.
FLIGHT_X, FLIGHT_Y, FLIGHT_VX, FLIGHT_VY = range(STATE_SIZE[FLIGHT])
#: A design with friction carries ``FRICTION_STATE`` more entries in stages 1-2 and 4, after
#: the stage's own (``state_size``): the work dissipated so far by the axle's, the
#: hinge's and the base's friction (J, integrated with the motion), then the modes
#: of the axle, the hinge and the base (constant between events: +1/-1 slipping
#: with that sign of the rate, 0 stuck; the base's is the slide's sign, 0 off it).
FRICTION_STATE = 6
#: Where the friction's parts start within it: the work (axle, hinge, base), then the modes.
FRICTION_WORK, FRICTION_MODES = 0, 3
#: Where each stage's friction work and modes start in its state: ``y[SLIDE_MODES + HINGE]``
#: is the hinge's mode in stage 1 (``friction.AXLE``, ``HINGE``, ``BASE`` in order).
SLIDE_WORK, SLIDE_MODES = STATE_SIZE[SLIDE] + FRICTION_WORK, STATE_SIZE[SLIDE] + FRICTION_MODES
SWING_WORK, SWING_MODES = STATE_SIZE[SWING] + FRICTION_WORK, STATE_SIZE[SWING] + FRICTION_MODES
MACHINE_WORK, MACHINE_MODES = STATE_SIZE[MACHINE] + FRICTION_WORK, STATE_SIZE[MACHINE] + FRICTION_MODES
#: A floating arm with the base's friction carries one entry more, after the modes: the base's work
#: (its three work entries are the axle's, the guide's and the track's) [12.13].
SLIDE_BASE_WORK, SWING_BASE_WORK, MACHINE_BASE_WORK = (STATE_SIZE[SLIDE] + FRICTION_STATE,
                                                       STATE_SIZE[SWING] + FRICTION_STATE,
                                                       STATE_SIZE[MACHINE] + FRICTION_STATE)
#: Events of each stage, in their index order (indexed by stage number). The
#: friction's (from ``arm_stalls`` and ``axle_stops`` on) are inert (a constant
#: 1) for a design without that friction.
EVENT_NAMES = ((), ("under_tip", "liftoff", "arm_back", "arm_stalls", "hinge_stops", "hinge_slips",
                    "slide_reverses"),
               ("release", "hits_base", "axle_stops", "axle_slips", "hinge_stops", "hinge_slips"),
               ("landing", "apex"), ("axle_stops", "axle_slips", "hinge_stops", "hinge_slips"))
#: Each event's index in its stage's ``EVENT_NAMES``, by name: what the events' functions take
#: (``stages.event_value``) and what a stretch that one ends reports (``sequence.stretch_end``).
SLIDE_UNDER_TIP = EVENT_NAMES[SLIDE].index("under_tip")
SLIDE_LIFTOFF = EVENT_NAMES[SLIDE].index("liftoff")
SLIDE_ARM_BACK = EVENT_NAMES[SLIDE].index("arm_back")
SLIDE_ARM_STALLS = EVENT_NAMES[SLIDE].index("arm_stalls")
SLIDE_HINGE_STOPS = EVENT_NAMES[SLIDE].index("hinge_stops")
SLIDE_REVERSES = EVENT_NAMES[SLIDE].index("slide_reverses")
SWING_RELEASE = EVENT_NAMES[SWING].index("release")
SWING_HITS_BASE = EVENT_NAMES[SWING].index("hits_base")
SWING_AXLE_STOPS = EVENT_NAMES[SWING].index("axle_stops")
FLIGHT_LANDING = EVENT_NAMES[FLIGHT].index("landing")
FLIGHT_APEX = EVENT_NAMES[FLIGHT].index("apex")
MACHINE_AXLE_STOPS = EVENT_NAMES[MACHINE].index("axle_stops")
#: How many events each stage has (``EVENT_NAMES``).
EVENT_COUNT = tuple(len(names) for names in EVENT_NAMES)
#: The first event of each stage that switches a friction mode (the stage goes on
#: from there in the new mode, ``switch_mode``); ``arm_stalls`` ends stage 1 instead. From
#: it on, a joint's events come in pairs, ``*_stops`` then ``*_slips``, the axle's before the
#: hinge's (``switched_joint``); stage 1's end with its base's ``slide_reverses``. The flight
#: switches none (its count).
FIRST_SWITCH = (0, SLIDE_HINGE_STOPS, SWING_AXLE_STOPS, EVENT_COUNT[FLIGHT], MACHINE_AXLE_STOPS)
#: The first friction event of each stage (``arm_stalls`` in stage 1): a design without
#: friction watches only the events before it (``stages.event_count``).
FIRST_FRICTION_EVENT = (0, SLIDE_ARM_STALLS, FIRST_SWITCH[SWING], EVENT_COUNT[FLIGHT], 0)
#: A shot may switch friction modes this many times; more is a failure
#: (``STEP_FAILED``): stick and slip chattering without end.
MODE_SWITCH_LIMIT = 2000


def state_size(stage, p):
    """Length of ``stage``'s state for the design ``p``: ``STATE_SIZE`` plus, in stages 1-2
    and 4 of a design with friction, ``FRICTION_STATE``, and one more for a floating arm's
    base work (``floating_base``)."""
    if stage != FLIGHT and FRICTION and lossy(p):
        return STATE_SIZE[stage] + FRICTION_STATE + (1 if floating_base(p) else 0)
    return STATE_SIZE[stage]


def floating_base(p):
    """Whether ``p`` is a floating arm with the base's (kinetic) friction, whose work its state carries
    in one more entry (``SLIDE_BASE_WORK`` ...) [12.13]."""
    return FLOATING_ARM and p.kind == FLOATING and p.mub > 0.0


def friction_work(stage, y, p):
    """The work the friction dissipated so far at ``stage``'s state ``y`` of a design with friction, J,
    in ``outcome.friction_work_names``' order: the three work entries, then a floating arm's base's.
    Python only (the paths' results)."""
    core = STATE_SIZE[stage]
    work = tuple(float(w) for w in y[core + FRICTION_WORK:core + FRICTION_WORK + 3])
    if floating_base(p):
        return (*work, float(y[core + FRICTION_STATE]))
    return work


def mode_slot(stage, joint):
    """Where ``joint``'s friction mode (``AXLE``, ``HINGE``, ``BASE``) is in ``stage``'s state."""
    return STATE_SIZE[stage] + FRICTION_MODES + joint


def rate_slot(stage, joint):
    """Where ``joint``'s rate (``AXLE``: theta', ``HINGE``: phi') is in ``stage``'s state: the rates
    follow the angles."""
    return STATE_SIZE[stage] // 2 + joint


def rest_modes(p):
    """The friction modes ``(axle, hinge, base)`` the shot starts in: the arm slips clockwise
    (-1), the projectile slides the way dx_P/dtheta theta' points, and the hinge, at rest,
    stays stuck if its static friction can hold the counterweight's link (0), or slips the
    way it is pushed (as ``decide_modes`` would)."""
    _, _, s, _, sin_beta = slide_constraint(p.theta0, 0.0, p)
    sb = -1.0 if slide_rate(p.theta0, s, sin_beta, p) >= 0.0 else 1.0
    sh = 1.0
    if static_arm(HINGE, p) > 0.0:
        held = slide_friction(p.theta0, p.phi0, 0.0, 0.0, -1.0, 0.0, sb, p)
        sh = 0.0
        if not abs(held.hinge_torque) < static_arm(HINGE, p) * held.hinge_load:
            sh = -1.0 if held.hinge_torque > 0.0 else 1.0
    return -1.0, sh, sb


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
    is the hold of ``friction.slides_friction`` (``friction.static_arm`` is 1), ``hinge_load`` the
    base's friction force F, N (0 off the base) [12.13].
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
        ddtheta, ddphi, normal, ta, th, fb, axle, hinge, dx = slide_friction(
            y[0], y[1], y[2], y[3], y[SLIDE_MODES + AXLE], y[SLIDE_MODES + HINGE], y[SLIDE_MODES + BASE], p)
        _, _, s, c, _ = slide_constraint(y[0], y[2], p)
        return FrictionSolution(ddtheta, ddphi, s * ddtheta + c, normal, ta, th, fb, axle, hinge, dx)
    if stage == MACHINE:
        ddtheta, ddphi, ta, th, axle, hinge = machine_friction(y[0], y[1], y[2], y[3], y[MACHINE_MODES + AXLE],
                                                               y[MACHINE_MODES + HINGE], p)
        ddpsi = 0.0
    else:
        ddtheta, ddphi, ddpsi, ta, th, axle, hinge = swing_friction(y[0], y[1], y[2], y[3], y[4], y[5],
                                                                    y[SWING_MODES + AXLE], y[SWING_MODES + HINGE], p)
    if FLOATING_ARM and p.kind == FLOATING:   # the track's force comes back in the hinge's place
        return FrictionSolution(ddtheta, ddphi, ddpsi, 0.0, ta, th, hinge, axle, 0.0, 0.0)
    return FrictionSolution(ddtheta, ddphi, ddpsi, 0.0, ta, th, 0.0, axle, hinge, 0.0)


def joint_torque(solution, joint):
    """The friction-free torque holding ``joint`` (``AXLE``, ``HINGE``) in ``solution``, N m."""
    return solution.axle_torque if joint == AXLE else solution.hinge_torque


def joint_load(solution, joint):
    """The load magnitude on ``joint``'s bearing in ``solution``, N."""
    return solution.axle_load if joint == AXLE else solution.hinge_load


def joint_acceleration(solution, joint):
    """The angular acceleration of ``joint``'s rate (the arm's, or the counterweight's) in ``solution``."""
    return solution.ddtheta if joint == AXLE else solution.ddphi


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
    if stage == SLIDE and k == SLIDE_ARM_STALLS:
        stalls = p.mua_s > 0.0 or p.mub_s > 0.0 or p.mug_s > 0.0 or p.mut_s > 0.0
        return -y[rate_slot(SLIDE, AXLE)] if stalls else 1.0
    if stage == SLIDE and k == SLIDE_REVERSES:
        if p.mub == 0.0:
            return 1.0
        # The slide's direction with the arm turning clockwise, as it does throughout stage 1
        # (``arm_stalls`` ends the stage where it stops): -D, not D theta', which also reaches 0
        # where the arm stalls, and would tie with arm_stalls there.
        _, _, s, _, sin_beta = slide_constraint(y[0], y[2], p)
        return -y[SLIDE_MODES + BASE] * slide_rate(y[0], s, sin_beta, p)
    joint = switched_joint(stage, k)
    slips = slip_event(stage, k)
    friction = static_arm(joint, p)
    mode = y[mode_slot(stage, joint)]
    if friction == 0.0 or (mode == 0.0) != slips:
        return 1.0
    if not slips:
        return mode * y[rate_slot(stage, joint)]
    solution = friction_solution(stage, y, p)
    return friction * joint_load(solution, joint) - abs(joint_torque(solution, joint))


def switched_joint(stage, k):
    """The joint (``AXLE``, ``HINGE``) of the friction event ``k``: stage 1 has only the hinge's
    (the axle's stall ends it), stages 2 and 4 the axle's then the hinge's."""
    if stage == SLIDE:
        return HINGE
    return (k - FIRST_SWITCH[stage]) // 2


def slip_event(stage, k):
    """Whether the friction event ``k`` is a joint's ``*_slips`` (its hold failed), not its ``*_stops``."""
    return (k - FIRST_SWITCH[stage]) % 2 == 1


#: A joint at rest may be stuck (0) or slip either way; tried in this order.
MODE_CHOICES = (0.0, -1.0, 1.0)


def _at_rest(stage, joint, y, p):
    """Whether ``joint`` has friction, may stick in ``stage`` (not the axle in stage 1) and its
    rate is exactly 0 (stuck, or just stopped): its mode is to be chosen."""
    if static_arm(joint, p) == 0.0 or (stage == SLIDE and joint == AXLE):
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
        if not (free_axle if joint == AXLE else free_hinge):
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
    ``must_slip``: a joint (``AXLE`` or ``HINGE``) whose hold just failed (its ``*_slips``
    event: the root lies within round-off of the balance, so sticking is not
    tried again), or -1. If no combination is consistent (not met in the
    tests), each joint at rest is tried alone, in order, as if the other's
    mode were final.
    """
    free_axle, free_hinge = _at_rest(stage, AXLE, y, p), _at_rest(stage, HINGE, y, p)
    if not (free_axle or free_hinge):
        return
    axle_slot, hinge_slot = mode_slot(stage, AXLE), mode_slot(stage, HINGE)
    kept_axle, kept_hinge = y[axle_slot], y[hinge_slot]
    for slipping in range(3):
        for i in range(3 if free_axle else 1):
            for j in range(3 if free_hinge else 1):
                axle = MODE_CHOICES[i] if free_axle else kept_axle
                hinge = MODE_CHOICES[j] if free_hinge else kept_hinge
                count = (1 if (free_axle and axle != 0.0) else 0) + (1 if (free_hinge and hinge != 0.0) else 0)
                if count != slipping or (must_slip == AXLE and axle == 0.0) or (must_slip == HINGE and hinge == 0.0):
                    continue
                y[axle_slot], y[hinge_slot] = axle, hinge
                if consistent(stage, y, p, free_axle, free_hinge, must_slip):
                    return
    for joint in range(2):
        if not (free_axle if joint == AXLE else free_hinge):
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
    if stage == SLIDE and k == SLIDE_REVERSES:
        y[SLIDE_MODES + BASE] = -y[SLIDE_MODES + BASE]
    else:
        joint = switched_joint(stage, k)
        y[rate_slot(stage, joint)] = 0.0
        if slip_event(stage, k):
            must_slip = joint
    decide_modes(stage, y, p, must_slip)
