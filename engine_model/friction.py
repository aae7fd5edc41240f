"""Friction in the engine (``design.losses``): Coulomb torques at the axle and the hinge, Coulomb friction on the
base, and on a floating arm's guide and track.

pymunk's own means, one velocity-level constraint per loss whose ``max_force``
is the friction's limit, set before every step from the load its joint
carries, predicted from the two steps before (pymunk reports a constraint's
impulse only after the step that applied it; ``predicted_loads``). The limit
takes the static coefficient while the joint holds and the kinetic one while
it slips (``limits``): a constraint that held in the last step (its impulse
under its limit, the relative motion stopped) is stuck for the next, one that
applied its whole limit (saturated) slips (``slipping``):

* axle: a ``SimpleMotor`` of rate 0 between the frame and the arm. It holds
  their relative rotation at zero (stick) unless that needs more torque than
  ``axle_friction * axle_radius * |axle load|``, where it saturates and
  applies the kinetic torque against the rotation (slip). A motor applies a pure
  torque, so it changes no joint's force directly.
* hinge: the same between the arm and the counterweight; for a point
  counterweight (a PinJoint link and a body whose own rotation is decoupled,
  ``engine_model.build``) it is a ``GrooveJoint`` on the arm, aimed along the
  link before every step, that limits the counterweight's motion across the
  link relative to the arm to ``torque / counterweight_link``: the same force
  pair a friction torque on a massless link gives the arm and the weight.
  Its load is the whole force through the hinge (the link's pull and this
  friction force).
* base: a ``GrooveJoint`` on the frame with a vertical groove, holding the
  projectile's sliding along the base up to ``base_friction * N`` (N the
  base's push, the slide groove's impulse). A pymunk contact with friction
  would solve the normal and friction impulses together, but only through
  collision shapes, whose slop and bias correction are pixel-sized defaults
  far coarser than the joints' (``error_bias = 0``); the slide groove and
  its lift-off test stay as they are.
* guide and track (a floating arm, ``engine_model.floating``): a ``GrooveJoint``
  on the frame holding the counterweight's slider with a horizontal groove
  (its sliding along the vertical guide) up to ``guide_friction * |G|``, and
  one holding the axle's carriage with a vertical groove (its sliding along
  the horizontal track) up to ``track_friction * |T|``; G and T are the
  guide's and the track's normal forces, their grooves' impulses
  (``slide_loads``). Slider and carriage never turn and are held at their
  centres, where pymunk's groove is exact.

A fixed machine (its counterweight part of the arm's body) has no hinge,
and a fixed design with hinge friction is refused when it is made: it gets
the axle's and the base's.

The friction constraints correct no position error (``max_bias = 0``): they
act on velocities alone, as a bearing does. An ideal design gets none of
them: its space is exactly what it was before friction existed.
"""

from __future__ import annotations

import math
import dataclasses
from dataclasses import dataclass

import numpy as np
import pymunk

from analytic import outcome
from analytic.design import Design
from engine_model import kinematics as kin
from engine_model.build import Rig, ballast_mass
from engine_model.readout import impulse, max_force, set_max_force, velocity

#: The friction joints' names, in the order ``impulses`` and ``loads`` give them
#: (``analytic.design.FRICTIONS``): the guide and the track are a floating arm's.
JOINTS = ("axle", "hinge", "base", "guide", "track")
#: A friction constraint whose impulse is within this fraction of its limit
#: counts as saturated (slipping): pymunk clamps a saturated impulse to the
#: limit exactly (a motor) or to its length computed by a square root (a groove).
SATURATION = 1e-9
#: A machine with friction whose arm's angular acceleration at rest (from the
#: opening half step) is no larger than this, rad/s^2, is held at rest: friction
#: holds it, and what is left is the solver's residual (2.6e-5 rad/s^2 at 1e-4 s
#: on a machine locked by its base's friction through a rigid sling). An arm
#: accelerating at 1e-3 rad/s^2 would turn 0.03 rad in the paper's 7.9 s swing
#: time limit: it could never fire either.
HELD_ACCELERATION = 1e-3
#: Length of the grooves, as a multiple of the machine's largest length, each
#: way: their ends must never be reached (there pymunk's groove also pushes along it).
GROOVE_REACH = 10.0

@dataclass(frozen=True)
class Friction:
    """The friction constraints added to a ``Rig`` (None where that loss is zero).

    Attributes
    ----------
    design : the design they were built for.
    axle : SimpleMotor, frame to arm.
    hinge : SimpleMotor, arm to counterweight, or GrooveJoint for a point counterweight.
    base : GrooveJoint, frame to projectile (vertical groove), while on the base.
    ballast : kg the engine put at the pivot (``build.arm_body_properties``):
        the pivot joint also carries its weight, which the real axle does not.
    guide : GrooveJoint, frame to a floating arm's slider (horizontal groove).
    track : GrooveJoint, frame to a floating arm's carriage (vertical groove).
    joints : all five in ``JOINTS``' order (None where absent).
    """

    design: Design
    axle: pymunk.SimpleMotor | None
    hinge: pymunk.Constraint | None
    base: pymunk.GrooveJoint | None
    ballast: float
    guide: pymunk.GrooveJoint | None = None
    track: pymunk.GrooveJoint | None = None
    point_hinge: bool = dataclasses.field(init=False)
    joints: tuple = dataclasses.field(init=False)

    def __post_init__(self):
        # Read at every step: attributes, not an isinstance check or a new tuple each time.
        object.__setattr__(self, "point_hinge", isinstance(self.hinge, pymunk.GrooveJoint))
        object.__setattr__(self, "joints", (self.axle, self.hinge, self.base, self.guide, self.track))


@dataclass(frozen=True)
class StaticBalance:
    """The arm at rest held at its axle: what gravity asks of the axle's friction.

    Attributes
    ----------
    gravity_torque : N m about the pivot from the arm's and counterweight's
        weights (clockwise, the firing direction, is negative). At rest the
        counterweight hangs plumb and the sling lies unloaded on the base.
    axle_load : N, the axle's reaction: the arm's and counterweight's weight.
    holding_torque : N m, the most the axle's static friction can hold:
        ``axle_static_friction * axle_radius * axle_load``.
    """

    gravity_torque: float
    axle_load: float
    holding_torque: float

    @property
    def holds(self) -> bool:
        """The axle's friction keeps a machine that would fire at rest."""
        return self.gravity_torque < 0.0 and -self.gravity_torque <= self.holding_torque


def static_balance(design: Design, rest: np.ndarray) -> StaticBalance:
    """The torque balance of the arm at rest (``rest``: the (24,) state row at rest, positions used)."""
    m, g = design.machine, design.environment.gravity
    arm_x = kin.arm_centre(rest[None, :], design)[0, 0] - rest[kin.ARM + kin.X]
    counterweight_x = rest[kin.COUNTERWEIGHT + kin.X] - rest[kin.ARM + kin.X]
    torque = -g * (m.arm_mass * arm_x + m.counterweight_mass * counterweight_x)
    load = (m.arm_mass + m.counterweight_mass) * g
    if m.sling_mass > 0.0:   # half the rod's weight on the long tip (``static_loads``)
        tip_x = kin.long_tip(rest[None, :], design)[0, 0] - rest[kin.ARM + kin.X]
        torque -= g * 0.5 * m.sling_mass * tip_x
        load += 0.5 * m.sling_mass * g
    losses = design.losses
    return StaticBalance(float(torque), float(load), losses.static("axle") * losses.axle_radius * load)


def attach(rig: Rig, design: Design, on_base: bool) -> Friction | None:
    """Add the friction constraints of ``design.losses`` to ``rig.space``; None (nothing added) when ideal.

    ``on_base``: the projectile starts on the base (the base's friction acts only there).
    """
    if design.losses.ideal:
        return None
    return _add(rig, design, on_base)


def renew(friction: Friction, rig: Rig) -> Friction:
    """The same friction constraints, new, in place of those that took the opening half step.

    pymunk starts each step's solver from the impulses of the step before,
    scaled by the ratio of the steps; a clamped constraint keeps the scaled
    part outside its clamp. After the opening half step that ratio is 2, so the
    first whole step would apply half a step's friction on top of its limit.
    New constraints start from nothing. (The joints' readings in that step are
    off the same way: ``engine_model.stepping`` does not measure loads in it.)
    """
    old = [joint for joint in friction.joints if joint is not None]
    rig.space.remove(*old)
    fresh = _add(rig, friction.design, friction.base is not None)
    for before, after in zip(old, [j for j in fresh.joints if j is not None], strict=True):
        after.max_force = before.max_force
        if isinstance(after, pymunk.GrooveJoint):
            after.groove_a, after.groove_b = before.groove_a, before.groove_b
    return fresh


def _add(rig: Rig, design: Design, on_base: bool) -> Friction:
    losses = design.losses
    m = design.machine
    reach = GROOVE_REACH * (m.arm_long + m.arm_short + m.counterweight_link + m.sling_length)
    axle = hinge = base = None
    # A static coefficient is never below its kinetic one: the static ones tell which joints have friction.
    if losses.static("axle") > 0.0:
        axle = pymunk.SimpleMotor(rig.frame, rig.arm, 0.0)
    if losses.static("hinge") > 0.0 and rig.hinge is not None:
        if m.counterweight_inertia == 0.0:
            # Aimed along the link before each step (``aim``).
            hinge = pymunk.GrooveJoint(rig.arm, rig.counterweight, (0.0, -reach), (0.0, reach), (0.0, 0.0))
        else:
            hinge = pymunk.SimpleMotor(rig.arm, rig.counterweight, 0.0)
    if losses.static("base") > 0.0 and on_base:
        base = pymunk.GrooveJoint(rig.frame, rig.projectile, (0.0, -reach), (0.0, reach), (0.0, 0.0))
    guide, track = _slides(rig, design, reach)
    added = [joint for joint in (axle, hinge, base, guide, track) if joint is not None]
    for joint in added:
        joint.max_bias = 0.0   # velocities only: no position to return to
        joint.collide_bodies = False
        joint.max_force = 0.0
    rig.space.add(*added)
    return Friction(design, axle, hinge, base, ballast_mass(design), guide, track)


def _slides(rig: Rig, design: Design, reach: float) -> tuple[pymunk.GrooveJoint | None, pymunk.GrooveJoint | None]:
    """A floating arm's guide and track friction grooves (None where that friction is zero, or no floating arm):
    a horizontal groove holding the slider's vertical sliding, a vertical one holding the carriage's horizontal."""
    if not rig.supports:
        return None, None
    carriage, slider = rig.supports[:2]
    losses = design.losses
    guide = track = None
    if losses.static("guide") > 0.0:
        guide = pymunk.GrooveJoint(rig.frame, slider, (-reach, 0.0), (reach, 0.0), (0.0, 0.0))
    if losses.static("track") > 0.0:
        track = pymunk.GrooveJoint(rig.frame, carriage, (0.0, -reach), (0.0, reach), (0.0, 0.0))
    return guide, track


def static_loads(design: Design) -> tuple[float, float, float, float, float]:
    """The joints' loads at rest, N (``JOINTS``): the weights the axle, the hinge, the base and a floating
    arm's track carry (a sling with mass taken as half on the long tip, half on the base, where the
    pouch lies with the projectile: the first step's loads, measured, replace these); the guide none (it pushes sideways only to turn the arm or to balance the track's
    friction, which the weights alone do not ask of it)."""
    m, g = design.machine, design.environment.gravity
    weight = (m.arm_mass + m.counterweight_mass) * g
    base = design.projectile.mass * g
    if m.sling_mass > 0.0 or m.pouch_mass > 0.0:   # the rod's weight shared by its ends, the pouch's on the base
        weight = (m.arm_mass + m.counterweight_mass + 0.5 * m.sling_mass) * g
        base = (kin.carried_mass(design) + 0.5 * m.sling_mass) * g
    track = weight if m.kind == "floating-arm" else 0.0
    return weight, m.counterweight_mass * g, base, 0.0, track


#: Steps, the coming one included, through which a joint must keep its mode (``limits``' ``slips``)
#: for its load to be extrapolated (``predicted_loads``): a joint that sticks or breaks free in a
#: step takes up the jump of its load within that step, so that step's load is neither mode's,
#: and the line through it and the step before predicts past the jump (a hinge sticking under
#: 666 N measures 122 N over the step it stops in and 44 N after it: the line gives less than
#: nothing, and the joint that had just stuck would be let go for two steps). The two loads the
#: line passes through must each come from a step that began in the coming step's mode: four.
STEADY_STEPS = 4


def steady(modes: list[tuple[bool, ...]], coming: tuple[bool, ...], coupled: bool = False) -> tuple[bool, ...]:
    """Which joints kept their mode (``limits``' ``slips``) through the steps ``modes`` (oldest first,
    the last ``STEADY_STEPS - 1`` steps taken) and the ``coming`` one: those whose load may be extrapolated.

    ``coupled``: each joint's load jumps where any joint's mode changes, so none is extrapolated
    unless all kept theirs. So on a floating arm, whose supports' pushes each take up the others'
    friction: where its guide's sliding turns back, the axle's load jumps with the guide's friction
    (95.7 N to 102.5 N on ``sample-8-000-wooden-floating-arm-all-losses``), and a line through the
    jump set the track's limit 1.3 N high for a step, which its loads then rang from for ten steps.
    """
    recent = modes[1 - STEADY_STEPS:]
    kept = tuple(all(mode[joint] == slip for mode in recent) for joint, slip in enumerate(coming))
    return (False,) * len(kept) if coupled and not all(kept) else kept


def predicted_loads(loads: tuple[float, ...], earlier: tuple[float, ...] | None,
                    steady_joints: tuple[bool, ...]) -> tuple[float, ...]:
    """The joints' loads in the coming step (N), extrapolated from those of the last two steps.

    pymunk gives a joint's load only after the step that applied it, so a
    limit set from the last step's load lags by one step: an error first order
    in the step (on the paper's design with all losses, 6.5e-4 m of range at
    the default step, halving with the step). A straight line through the last
    two loads is second order (the friction's share of the range then moves by
    6.7e-6 m from 5e-5 s to 2.5e-5 s, against 3.2e-4 m with the lag; README,
    "Friction in the engine"). A joint whose mode changed within ``STEADY_STEPS``
    (``steady``, ``steady_joints``) takes its last load: the line would cross its
    jump. Where another load jumps (lift-off) the line overshoots for one step;
    a load is never negative.
    """
    if earlier is None:
        return loads
    return tuple(max(2.0 * now - before, 0.0) if line else now
                 for now, before, line in zip(loads, earlier, steady_joints, strict=True))


def smooth(modes: list[tuple[bool, ...]], rows: int) -> np.ndarray:
    """(rows - 1,) whether the loads of rows i and i + 1 lie on one smooth stretch, from each row's step's
    joints' modes (``limits``' ``slips``, ``modes``, one a row from the opening half step): the steps
    before, of and after both rows in one mode. A joint that sticks or breaks free jumps its loads
    within the step whose mode differs from the one before, which is on neither stretch. Without
    friction (no ``modes``) all are."""
    joined = np.ones(max(rows - 1, 0), dtype=bool)
    if not modes:
        return joined
    changed = np.array([a != b for a, b in zip(modes[:-1], modes[1:])][:rows - 1], dtype=bool)
    changed = np.concatenate([changed, np.zeros(rows - 1 - len(changed), dtype=bool)])
    # Row i's step changed mode, or row i + 1's did: the pair straddles a jump.
    joined &= ~changed
    joined[1:] &= ~changed[:-1]
    return joined


#: Every friction joint stuck (``limits``' ``slips``): the machine at rest.
STUCK = (False,) * len(JOINTS)
#: The joints' relative rates at rest (``joint_rates``).
AT_REST = (0.0,) * len(JOINTS)


def limits(design: Design, loads: tuple[float, ...], slips: tuple[bool, ...]) -> tuple[float, ...]:
    """The friction each joint (``JOINTS``) can give under its load (N): torques ``mu r |F|`` (N m) at the
    axle and the hinge, forces ``mu N`` (N) on the base, the guide and the track; ``mu`` the kinetic
    coefficient where ``slips`` says the joint slips, the static one where it holds."""
    losses = design.losses
    axle, hinge, base, guide, track = (getattr(losses, f"{joint}_friction") if slip else losses.static(joint)
                                       for joint, slip in zip(JOINTS, slips, strict=True))
    return (axle * losses.axle_radius * loads[0], hinge * losses.hinge_radius * loads[1], base * loads[2],
            guide * loads[3], track * loads[4])


def set_limits(friction: Friction, loads: tuple[float, ...], slips: tuple[bool, ...]) -> tuple[float, ...]:
    """Set each friction constraint's limit from its joint's load (N) and mode (``limits``); returns them."""
    found = limits(friction.design, loads, slips)
    for joint, limit in zip(friction.joints, found, strict=True):
        if joint is not None:
            set_max_force(joint, limit)
    if friction.point_hinge:   # its groove's force, the torque over the link
        set_max_force(friction.hinge, found[1] / friction.design.machine.counterweight_link)
    return found


#: Most times a floating arm's opening half step is taken again with the limits its own loads give
#: (``engine_model.stepping.run_machine``) when its guide or track has friction, and the relative
#: change of every load at which they have settled (``settled``). The track's friction feeds back on
#: its own load (its push is the momentum balance less the guide's friction, and the arm's start
#: depends on both): on the first sampled floating arm with the track's friction (0.2) a retake cut
#: the error of the loads at rest by 0.12, the peak axle load (at rest) 59.014 N after one, 58.8405
#: after eight (the analytic model's 58.8405); one retake left it 3.0e-3 high, outside the
#: cross-check's 2e-3.
OPENING_RETAKES = 20
OPENING_TOLERANCE = 1e-9


def settled(loads: tuple[float, ...], before: tuple[float, ...]) -> bool:
    """The joints' loads (N) of a retaken opening half step are those it was taken with, ``before``, to
    ``OPENING_TOLERANCE`` of each."""
    return all(abs(now - then) <= OPENING_TOLERANCE * abs(then) for now, then in zip(loads, before, strict=True))


def slides(friction: Friction | None) -> bool:
    """A floating arm's guide or track has friction."""
    return friction is not None and (friction.guide is not None or friction.track is not None)


def holders(friction: Friction) -> str:
    """Whose friction holds a floating arm at rest, in the words both models use
    (``analytic.outcome.friction_holders``): each joint that has friction."""
    return outcome.friction_holders(friction.axle is not None, friction.guide is not None,
                                    friction.track is not None)


def track_axle_load(friction: Friction, rig: Rig, step: float) -> float:
    """A floating arm's axle load in the last step of ``step`` s, N: the track's whole force on the
    carriage, ``|(F_T, T)|`` (its friction along it, its push across it). The real carriage is
    massless, so its pin carries that force to the arm; the engine's carriage holds part of the arm's
    mass (``engine_model.floating.carriage_mass``), whose momentum change its pivot's own impulse
    leaves out."""
    sliding = 0.0 if friction.track is None else impulse(friction.track)
    return math.hypot(impulse(rig.track), sliding) / step


def slide_forces(impulse: np.ndarray, raw: np.ndarray, design: Design, steps: np.ndarray) -> np.ndarray:
    """A floating arm's slides' friction over each raw row's step, (n, 2) N: the track's on the axle
    (x) and the guide's on the counterweight (y), signed; zeros for the other kinds.

    pymunk reports their size (``impulse``, (n, 5) ``impulses`` rows, over ``steps``, (n,) s); each
    opposes its sliding after the step (``slide_rates`` on the (n, 24) ``raw`` rows), which a
    saturated groove does not stop, or where the step stopped it, the sliding before the step.
    """
    forces = np.zeros((len(raw), 2))
    if design.machine.kind != "floating-arm" or len(impulse) == 0:
        return forces
    guide, track = slide_rates(raw.T, design)
    for column, rate, joint in ((0, track, 4), (1, guide, 3)):
        before = np.concatenate([[0.0], rate[:-1]])
        sliding = np.where(rate != 0.0, rate, before)
        forces[:, column] = -np.sign(sliding) * impulse[:len(raw), joint] / steps
    return forces


def slide_loads(friction: Friction, rig: Rig, step: float) -> tuple[float, float]:
    """A floating arm's guide and track loads in the last step of ``step`` s, N: the normal forces |G| and
    |T|, the impulses of the grooves holding the slider on the guide and the carriage on the track
    (0 where that support has no friction)."""
    guide = 0.0 if friction.guide is None else impulse(rig.guide) / step
    track = 0.0 if friction.track is None else impulse(rig.track) / step
    return guide, track


def aim(friction: Friction, rig: Rig, dt: float) -> None:
    """Point a point counterweight's hinge groove along the link where the next step of ``dt`` will find it.

    pymunk moves the bodies before it solves the step's constraints, so the
    groove is aimed from the positions the current velocities lead to.
    """
    if not friction.point_hinge:
        return
    arm, weight = rig.arm, rig.counterweight
    angle = arm.angle + arm.angular_velocity * dt
    cos, sin = math.cos(angle), math.sin(angle)
    origin = arm.local_to_world((0.0, 0.0)) + arm.velocity_at_local_point((0.0, 0.0)) * dt
    centre = weight.position + weight.velocity * dt
    dx, dy = centre.x - origin.x, centre.y - origin.y
    # Into the arm's frame, relative to the short tip at (0, -arm_short).
    local_x, local_y = cos * dx + sin * dy, -sin * dx + cos * dy + friction.design.machine.arm_short
    length = math.hypot(local_x, local_y)
    reach = GROOVE_REACH * friction.design.machine.counterweight_link
    ux, uy = local_x / length, local_y / length
    short = -friction.design.machine.arm_short
    friction.hinge.groove_a = (-reach * ux, short - reach * uy)
    friction.hinge.groove_b = (reach * ux, short + reach * uy)


def impulses(friction: Friction, on_base: bool) -> tuple[float, ...]:
    """Each friction constraint's impulse in the last step (magnitude; 0 where absent; ``JOINTS``): the
    axle's and the hinge's as torque impulses, N m s (a point counterweight's groove: its impulse times
    the link), the base's, N s, only while ``on_base``, the guide's and the track's, N s."""
    hinge = 0.0 if friction.hinge is None else impulse(friction.hinge)
    if friction.point_hinge:
        hinge *= friction.design.machine.counterweight_link
    guide, track = (0.0 if joint is None else impulse(joint) for joint in friction.joints[3:])
    return (0.0 if friction.axle is None else impulse(friction.axle), hinge,
            0.0 if friction.base is None or not on_base else impulse(friction.base), guide, track)


def saturated(joint: pymunk.Constraint | None, step: float) -> bool:
    """The constraint applied its whole limit in the last step of ``step`` s (it slipped)."""
    return joint is not None and joint.impulse >= (1.0 - SATURATION) * joint.max_force * step


def slipping(friction: Friction, step: float, rate: tuple[float, ...],
             earlier: tuple[float, ...]) -> tuple[bool, ...]:
    """Which joints (``JOINTS``) slip in the next step: those whose constraint applied its whole
    limit in the last step of ``step`` s (``saturated``), unless about to stop. The others held: their
    relative motion stopped, and the next step holds them up to the static limit (``limits``).

    A slipping joint is about to stop when its relative rate (``joint_rates`` after the last step,
    ``rate``, and after the one before, ``earlier``), going on as it changed in the last step, reaches
    zero within the next: that step gets the static limit, under which the constraint stops the joint
    and holds it if the static friction can (a joint stopping with the kinetic limit alone would be
    driven through zero whenever holding it takes more than the kinetic friction).
    """
    return tuple(saturated(joint, step) and r * (2.0 * r - r0) > 0.0
                 for joint, r, r0 in zip(friction.joints, rate, earlier, strict=True))


def joint_rates(row: tuple, design: Design) -> tuple[float, ...]:
    """Each friction joint's signed relative rate at the raw ``row`` (pymunk's velocities after a step;
    ``JOINTS``): the arm's turn on the frame and the counterweight's (a point counterweight: its link's)
    on the arm, rad/s, the projectile's slide along the base, m/s, and a floating arm's slides
    (``slide_rates``), m/s."""
    m = design.machine
    arm_w = row[kin.ARM + kin.W]
    if m.kind != "hinged":
        hinge = 0.0
    elif m.counterweight_inertia == 0.0:
        theta, short = row[kin.ARM + kin.ANGLE], m.arm_short
        # The hinge at (0, -arm_short) on the arm; the link's turn is the weight's motion across it.
        dx = row[kin.COUNTERWEIGHT + kin.X] - (row[kin.ARM + kin.X] + short * math.sin(theta))
        dy = row[kin.COUNTERWEIGHT + kin.Y] - (row[kin.ARM + kin.Y] - short * math.cos(theta))
        dvx = row[kin.COUNTERWEIGHT + kin.VX] - (row[kin.ARM + kin.VX] + arm_w * short * math.cos(theta))
        dvy = row[kin.COUNTERWEIGHT + kin.VY] - (row[kin.ARM + kin.VY] + arm_w * short * math.sin(theta))
        hinge = (dx * dvy - dy * dvx) / (dx * dx + dy * dy) - arm_w
    else:
        hinge = row[kin.COUNTERWEIGHT + kin.W] - arm_w
    return (arm_w - row[kin.FRAME + kin.W], hinge, row[kin.PROJECTILE + kin.VX] - row[kin.FRAME + kin.VX],
            *slide_rates(row, design))


def slide_rates(row, design: Design) -> tuple:
    """A floating arm's counterweight sliding along its guide (vertical) and axle along its track
    (horizontal), m/s, signed: at a state ``row`` (24 numbers) or, given the transposed (24, n) rows,
    at each; 0 for the other kinds. A floating arm's row holds its slider in the counterweight's
    columns and its carriage in the frame's (``stepping.row_bodies``); its frame never rolls."""
    if design.machine.kind != "floating-arm":
        return 0.0, 0.0
    return row[kin.COUNTERWEIGHT + kin.VY], row[kin.FRAME + kin.VX]


def remove_base(friction: Friction, space: pymunk.Space) -> None:
    """Take the base's friction out with the base (at lift-off)."""
    if friction.base is not None and friction.base in space.constraints:
        space.remove(friction.base)


def base_friction_force(friction: Friction, rig: Rig, step: float, sling_x: float) -> float:
    """The base's friction force on the projectile in the last step, N, signed (+x ground).

    pymunk reports its size; it opposes the projectile's sliding when it
    slipped, and the sling's pull along the base when it held (the sling
    pulls: ``sling_x`` is the x part of the unit vector from projectile to tip).
    """
    joint = friction.base
    if joint is None:
        return 0.0
    applied = impulse(joint)
    size = applied / step
    sliding = velocity(rig.projectile)[0] - velocity(rig.frame)[0]
    if applied >= (1.0 - SATURATION) * max_force(joint) * step and sliding != 0.0:   # ``saturated``
        return -math.copysign(size, sliding)
    return -math.copysign(size, sling_x)


def axle_load_from_momentum(before: tuple, row: tuple, design: Design, base_force: tuple[float, float],
                            step: float, projectile: bool = True) -> float:
    """The axle's reaction force, N, from the momentum the arm (without ballast), the counterweight and
    the projectile took up over the step (raw rows: velocities half a step either side).

    The pivot joint also carries the ballast's weight and inertia, which the
    real axle does not; the design's own bodies do not include it. Outside
    forces on them: gravity, the axle, and on the base the base's push and
    friction ``base_force`` (N, signed). After release (``projectile`` False)
    the projectile is no part of the machine; a sling with mass and the pouch
    are, before release and after it (the row's projectile columns then hold
    the sling's end, ``engine_model.after_release``).
    """
    m, g = design.machine, design.environment.gravity
    masses = (m.arm_mass, m.counterweight_mass, design.projectile.mass if projectile else 0.0)
    if m.sling_mass > 0.0 or m.pouch_mass > 0.0:
        # The rod's centre moves at the mean of its ends' velocities; the pouch, at its end, is the
        # projectile's columns' (until release the projectile's, then the end's as it swings on).
        masses = (*masses[:2], masses[2] + m.pouch_mass, m.sling_mass)
    momentum = [0.0, 0.0]
    for state, sign in ((row, 1.0), (before, -1.0)):
        theta, spin = state[kin.ARM + kin.ANGLE], state[kin.ARM + kin.W]
        arm_vx = state[kin.ARM + kin.VX] - spin * m.arm_cg * math.cos(theta)
        arm_vy = state[kin.ARM + kin.VY] - spin * m.arm_cg * math.sin(theta)
        parts = [(masses[0], arm_vx, arm_vy),
                 (masses[1], state[kin.COUNTERWEIGHT + kin.VX], state[kin.COUNTERWEIGHT + kin.VY]),
                 (masses[2], state[kin.PROJECTILE + kin.VX], state[kin.PROJECTILE + kin.VY])]
        if len(masses) > 3:
            tip_vx = state[kin.ARM + kin.VX] - spin * m.arm_long * math.cos(theta)
            tip_vy = state[kin.ARM + kin.VY] - spin * m.arm_long * math.sin(theta)
            parts.append((masses[3], 0.5 * (tip_vx + state[kin.PROJECTILE + kin.VX]),
                          0.5 * (tip_vy + state[kin.PROJECTILE + kin.VY])))
        for mass, vx, vy in parts:
            momentum[0] += sign * mass * vx
            momentum[1] += sign * mass * vy
    force_x = momentum[0] / step - base_force[0]
    force_y = momentum[1] / step + sum(masses) * g - base_force[1]
    return math.hypot(force_x, force_y)


def rates(sync: np.ndarray, qdot: np.ndarray, design: Design) -> np.ndarray:
    """Each friction joint's relative sliding rate at the rows of ``sync`` (n, 5; ``JOINTS``): the arm's
    turn on the frame (rad/s), the counterweight's (for a point counterweight, its link's) on the arm
    (rad/s), the projectile's along the base (a floating arm's on the ground: its base's) and a floating
    arm's slides (``slide_rates``; m/s), as magnitudes. ``qdot``: (n, 3) ``kinematics.coordinates``' rates."""
    axle = np.abs(kin.column(sync, kin.ARM, kin.W) - kin.column(sync, kin.FRAME, kin.W))
    if design.machine.counterweight_inertia == 0.0 and design.machine.kind == "hinged":
        hinge = np.abs(qdot[:, 1])
    else:
        hinge = np.abs(kin.column(sync, kin.COUNTERWEIGHT, kin.W) - kin.column(sync, kin.ARM, kin.W))
    # The base stands on the frame; a floating arm's frame columns are its carriage's, its base on the ground.
    ground = design.machine.kind == "floating-arm"
    base = np.abs(kin.column(sync, kin.PROJECTILE, kin.VX) - (0.0 if ground else kin.column(sync, kin.FRAME, kin.VX)))
    guide, track = (np.broadcast_to(np.abs(rate), axle.shape) for rate in slide_rates(sync.T, design))
    return np.column_stack([axle, hinge, base, guide, track])


def dissipated_work(impulse: np.ndarray, rate: np.ndarray) -> np.ndarray:
    """Work each friction took, accumulated to each row's instant, J, shape (n, 5) (``JOINTS``).

    Parameters
    ----------
    impulse : (n, 5) each friction constraint's impulse in the step that produced the row.
    rate : (n, 5) its joint's sliding rate at the row's instant (``rates`` on synchronised rows).

    Notes
    -----
    A step's impulse changes the velocities from half a step before the row
    to half a step after it, so its work is the impulse times the mean of
    the two, the synchronised rate, exactly (friction opposes the sliding).
    The synchronised energy at a row holds half that step's velocity change,
    so the row is given half its step's work (trapezoidal accumulation).
    """
    work = impulse * rate
    return np.cumsum(work, axis=0) - 0.5 * work
