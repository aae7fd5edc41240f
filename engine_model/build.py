"""Build the trebuchet of a design as a pymunk Space: bodies, joints and the handles to them.

Body frames (pymunk rotates each body about its centre of gravity and reports
``body.velocity`` for that centre; ``body.position`` is the body's own origin):

* arm: origin at the pivot, long tip at local ``(0, arm_long)``, short tip at
  ``(0, -arm_short)``, centre of gravity at ``(0, arm_cg)``; so ``body.angle``
  is the design's arm angle theta (CCW from the upward vertical).
* counterweight: origin and centre of gravity at its centre, hinge at local
  ``(0, counterweight_link)``; so ``body.angle`` is theta + phi.
* a fixed (bolted) counterweight (``machine.kind = "fixed"``) is no body of
  its own: it is part of the arm's body (``fixed_arm_properties``), its
  centre at local ``(0, -arm_short)``. One rigid body is exact in pymunk,
  where a weld (a pivot and a gear joint between two bodies) would hold the
  two together only as well as the iterative solver converges, the error
  growing with the counterweight-to-arm mass ratio. Its state (position,
  velocity, angle and spin) is that point of the arm's (``engine_model.readout``).
* projectile: origin and centre of gravity at its centre. It carries the
  pouch (``machine.pouch_mass``, a point mass at its centre) while the sling
  holds it: one body of both masses.
* sling (``machine.sling_mass`` > 0 only): a uniform rod, origin at the long
  tip's end, its other end (the projectile's centre) at local
  ``(0, sling_length)``, centre of gravity halfway, moment ``m L^2 / 12``
  about it; so ``body.angle`` is theta + psi. A massless sling is a joint
  (``build``'s ``sling``).
* frame (rolling only): origin at the pivot, infinite moment (it never
  turns), held on a horizontal groove along the ground through the pivot's
  rest height; so ``body.position.x`` is the frame's displacement X. A fixed
  frame is the space's static body, origin at the pivot.

pymunk's world coordinates are ground coordinates, with the origin at the
pivot's position at rest: for a rolling frame every position and velocity
read from a body is a ground one (its position relative to the pivot plus X).

Every joint has ``error_bias = 0`` (pymunk's error_bias is the fraction of
joint error left uncorrected after one second; 0 removes the whole error in
the next step), ``max_bias`` left at infinity (a cap would bring back the slow
first-order correction) and ``collide_bodies`` off. There are no collision
shapes: the parts never touch each other, and the base (or a raised trough,
``base.trough_height`` above it) acts on the projectile only through the slide
constraint, a groove at its height (``trough_level``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import pymunk

from analytic.design import Design, initial_angles, largest_length
from analytic.geometry import machine_points
from engine_model import floating
from engine_model.kinematics import carried_mass

#: Default solver iterations per step. With ``error_bias = 0`` pymunk needs at
#: least about 20 to stay stable on a machine with a counterweight 140 times
#: the projectile. From 20 up the release speed moves by only 2e-7 (relative):
#: the error left is the step's. But below about 200 the sling tension rings
#: for a few steps after each change of the constraint set (firing, lift-off),
#: by 10 % at 30 iterations and 0.1 % at 100; 200 costs 35 ms more per shot
#: than 30 (measured on the paper's design, 3800 steps to release).
DEFAULT_ITERATIONS = 200

SLINGS = ("rigid", "rope")

#: The arm body is never lighter than this fraction of the counterweight: pymunk's
#: iterative solver does not converge for a light arm hinged between a heavy
#: counterweight and the frame (a 10 g arm under 6.5 kg blows up even at 5000
#: iterations). A lighter arm gets ballast at the pivot (see ``arm_body_properties``).
ARM_MASS_FRACTION = 0.02

#: A sling with mass is never lighter than this fraction of what it carries (the projectile and the
#: pouch): pymunk's solver does not converge for a light rod pinned between the arm and the projectile
#: (on the paper's design a sling of 0.22 % of the ball missed its pin's target velocity by 2.7 m/s,
#: 6600 times ``diagnostics.RESIDUAL_LIMIT``; 0.66 % by half of it, 1.1 % by a fifth).
SLING_MASS_FRACTION = 0.01

#: A hinged counterweight's link is never shorter than this fraction of the machine's size (pivot
#: height, long arm and sling): pymunk holds positions as floats, each rounded to about 1e-16 of the
#: size, and the link's direction is the difference of two of them (a link of 1e-9 m on a machine
#: of 1.5e11 m came out 0/0). At this fraction its direction is good to about 1e-7 rad.
LINK_FRACTION = 1e-9


class EngineError(RuntimeError):
    """The engine cannot model the design or its run cannot be trusted; the message says why."""

#: Length of the groove that holds the projectile on the base, in units of the
#: machine's largest length, each way from the pivot: the projectile must never
#: reach its ends (where pymunk's groove also constrains the sliding direction).
GROOVE_HALF_LENGTH_FACTOR = 10.0
#: Length of the rail (the groove along the ground) a rolling frame runs on,
#: each way from the rest position, m: far beyond any frame's travel (a few
#: metres at most while the projectile flies), since at its ends pymunk's
#: groove would stop the frame.
RAIL_HALF_LENGTH = 1e6


@dataclass(frozen=True)
class Rig:
    """A design built in pymunk: the space and handles to its bodies and joints.

    The pymunk objects are mutable (the space steps them); the record of which
    object is which is not.

    Attributes
    ----------
    space : the pymunk Space (gravity, iterations, damping 1 set).
    arm, counterweight, projectile : the dynamic bodies; ``counterweight`` is
        None for a fixed machine (its counterweight is part of the arm's body).
    pivot : PivotJoint, frame to arm at the pivot.
    hinge : PivotJoint (counterweight with inertia) or PinJoint (a point
        counterweight, inertia 0: see ``build``), arm short tip to
        counterweight; None for a fixed machine.
    sling : PinJoint (rigid) or SlideJoint (rope), long tip to projectile; for a sling with
        mass, the PivotJoint of the sling body's end to the projectile.
    groove : GrooveJoint holding the projectile on the base (stage 1).
    sling_kind : ``"rigid"`` or ``"rope"``.
    frame : the body carrying the pivot and the base: the space's static body
        for a fixed frame, a dynamic body that only translates for a rolling one.
    rail : GrooveJoint holding a rolling frame on the ground (None when fixed).
    mount : a fixed or floating-arm machine's counterweight centre in the arm
        body's frame, ``(0, -arm_short)``, m (None when hinged: the counterweight is a body).
    supports : a floating arm's (carriage, slider) bodies and (track, guide,
        slider pivot) joints (``engine_model.floating``); ``pivot`` is then the
        arm's pivot on the carriage. Empty for the other kinds.
    sling_body : the sling with mass as a body (a rod, ``sling_body``), or after release
        (``build(released=True)``) what stays on the arm: the rod with the pouch at its end, or
        the pouch alone on a massless sling; None for a massless sling (and no pouch after release).
    sling_tip : the joint of ``sling_body`` to the long tip (PivotJoint for a rod, PinJoint for
        the pouch alone); None without ``sling_body``.
    """

    space: pymunk.Space
    arm: pymunk.Body
    counterweight: pymunk.Body | None
    projectile: pymunk.Body
    pivot: pymunk.PivotJoint
    hinge: pymunk.Constraint | None
    sling: pymunk.Constraint
    groove: pymunk.GrooveJoint
    sling_kind: str
    frame: pymunk.Body
    rail: pymunk.GrooveJoint | None = None
    mount: tuple[float, float] | None = None
    supports: tuple = ()
    sling_body: pymunk.Body | None = None
    sling_tip: pymunk.Constraint | None = None

    @property
    def machine_parts(self) -> tuple:
        """Bodies and joints of the arm and counterweight (removed from the space at release)."""
        parts = (self.pivot, self.hinge, *self.supports, self.arm, self.counterweight, self.sling_tip,
                 self.sling_body)
        return tuple(part for part in parts if part is not None)

    @property
    def guide(self) -> pymunk.GrooveJoint | None:
        """A floating arm's guide, the groove holding the counterweight on x = 0 (None otherwise)."""
        return self.supports[3] if self.supports else None

    @property
    def track(self) -> pymunk.GrooveJoint | None:
        """A floating arm's track, the groove holding the axle's carriage on y = 0 (None otherwise)."""
        return self.supports[2] if self.supports else None


def start_positions(design: Design) -> dict[str, tuple[float, float]]:
    """World positions at rest (``analytic.design.initial_angles``), m: see
    ``analytic.geometry.machine_points``, moved by ``axle_start`` along x."""
    points = machine_points(initial_angles(design.machine, design.base.trough_height), design.machine)
    shift = axle_start(design)
    return {name: (float(p[0]) + shift, float(p[1])) for name, p in points.items()}


def axle_start(design: Design) -> float:
    """The axle's x at rest, m: ``-arm_short sin(theta0)`` for a floating arm (whose origin is where
    the counterweight's guide meets the axle's track), 0 for the other kinds (the origin is the axle)."""
    m = design.machine
    if m.kind != "floating-arm":
        return 0.0
    return -m.arm_short * math.sin(initial_angles(m, design.base.trough_height)[0])


def fixed_arm_properties(design: Design) -> tuple[float, float, float]:
    """Mass (kg), centre of gravity along the long arm (m) and moment about it (kg m^2) of a fixed
    machine's arm body: the arm and the counterweight bolted to it, one rigid body.

    The counterweight's centre is at ``-arm_short`` on the arm's axis and its
    ``counterweight_inertia`` about that centre; parallel axes give the whole
    body's moment about their common centre of gravity. Never zero: the counterweight
    has mass and sits off the pivot.
    """
    m = design.machine
    mass = m.arm_mass + m.counterweight_mass
    cg = (m.arm_mass * m.arm_cg - m.counterweight_mass * m.arm_short) / mass
    moment = (m.arm_inertia + m.arm_mass * (m.arm_cg - cg) ** 2
              + m.counterweight_inertia + m.counterweight_mass * (m.arm_short + cg) ** 2)
    return mass, cg, moment


def ballast_mass(design: Design) -> float:
    """Mass the engine puts at the pivot of the arm body, kg (``arm_body_properties``; 0 for a fixed
    machine, whose arm body carries its counterweight)."""
    if design.machine.kind != "hinged":
        return 0.0
    return arm_body_properties(design)[0] - design.machine.arm_mass


def arm_body_properties(design: Design) -> tuple[float, float, float]:
    """Mass (kg), centre of gravity along the long arm (m) and moment about it (kg m^2) of the
    pymunk arm body (of a hinged machine; a fixed one's: ``fixed_arm_properties``).

    These are the design's own unless the arm is lighter than ``ARM_MASS_FRACTION``
    of the counterweight, or has ``arm_inertia = 0`` (pymunk needs a positive
    moment): then ballast is added at the pivot. A mass at the pivot of a body
    pinned there changes nothing of the motion, which depends on the arm only
    through ``arm_mass * arm_cg`` (its weight's torque) and its inertia about
    the pivot ``arm_inertia + arm_mass * arm_cg**2``; both are kept.

    Raises
    ------
    EngineError
        The arm has no inertia about the pivot at all (``arm_inertia = 0`` and
        ``arm_cg = 0``): a massless lever, which a pymunk body cannot be.
    """
    m = design.machine
    pivot_inertia = m.arm_inertia + m.arm_mass * m.arm_cg**2
    if pivot_inertia == 0.0:
        raise EngineError("the arm has no moment of inertia about the pivot (arm_inertia = 0 and "
                          "arm_cg = 0): the engine cannot model a massless lever; give the arm an inertia")
    mass = max(m.arm_mass, ARM_MASS_FRACTION * m.counterweight_mass)
    if m.arm_inertia == 0.0 and mass == m.arm_mass:
        mass = 2.0 * m.arm_mass
    if mass == m.arm_mass:
        return m.arm_mass, m.arm_cg, m.arm_inertia
    cg = m.arm_mass * m.arm_cg / mass
    return mass, cg, pivot_inertia - mass * cg**2


def placeholder_moment(mass: float, radius: float) -> float:
    """``mass * radius**2`` for a body whose rotation nothing couples to (a point counterweight on a
    pin joint, the projectile on its pin): any positive moment gives the same motion, so where the
    product underflows to 0 (radii of 1e-160 m and less), ``mass`` times 1 m^2 stands in."""
    moment = mass * radius**2
    return moment if moment > 0.0 else mass


def frame_body_mass(design: Design) -> float:
    """Mass of the pymunk frame body of a rolling design, kg: the frame's less the arm's ballast.

    Ballast at the pivot (``arm_body_properties``) is neutral on a fixed frame,
    but on a rolling one it moves with the pivot, so it is part of the mass
    that translates with the frame: taking it off the frame body keeps the
    translating mass the design's ``base.mass``.

    Raises
    ------
    EngineError
        The frame is no heavier than the ballast (a frame under a few per cent
        of the counterweight with a light arm): its body would have no mass left.
    """
    ballast = ballast_mass(design)
    mass = design.base.mass - ballast
    if not mass > 0.0:
        raise EngineError(f"base.mass = {design.base.mass:g} kg is no heavier than the {ballast:.3g} kg "
                          f"of ballast the engine puts at the pivot of this light arm (a frame under "
                          f"{ARM_MASS_FRACTION:.0%} of the counterweight): the engine cannot model it")
    return mass


def build(design: Design, *, sling: str = "rigid", iterations: int = DEFAULT_ITERATIONS,
          on_base: bool = True, released: bool = False) -> Rig:
    """The machine of ``design`` at rest, ready to fire, in a new pymunk Space.

    Parameters
    ----------
    design : the validated design.
    sling : ``"rigid"`` (a PinJoint: a massless rod that can pull and push) or
        ``"rope"`` (a SlideJoint with min 0 and max ``sling_length``: it pulls
        only, and goes slack where the rigid sling would push).
    iterations : solver iterations per step.
    on_base : add the groove that holds the projectile on the base, or on its
        trough (False when the sling already lifts it at rest).
    released : the machine as it swings on after release (``engine_model.after_release``, which
        takes the projectile and ``sling`` out): a sling with mass and the pouch stay on the arm,
        as ``sling_body`` (``released_sling``).

    Notes
    -----
    A counterweight with ``counterweight_inertia = 0`` is a point mass on a
    massless link: a body with zero moment hinged off its centre would have a
    massless rotation that pymunk cannot solve, so the link is then a PinJoint
    of length ``counterweight_link`` between the short tip and the
    counterweight's centre (the same dynamics; the body's own rotation is
    decoupled and its moment only a placeholder). A light arm, or one with
    ``arm_inertia = 0``, carries ballast at the pivot (``arm_body_properties``).

    A rolling frame (``design.base.rolling``) is a body of ``frame_body_mass``
    with an infinite moment on a horizontal groove (``rail``) along the ground;
    it carries the pivot and the groove that holds the projectile on the base,
    at the base's (or the trough's) height below the pivot. It has no friction and never lifts.

    A sling with mass (``machine.sling_mass``) is a rod of its own (``sling_body``), pinned to the
    long tip at one end and to the projectile's centre at the other: a rigid sling only. The pouch
    (``machine.pouch_mass``) rides in the projectile's body until release.
    """
    if sling not in SLINGS:
        raise ValueError(f"sling = {sling!r}: must be one of {', '.join(SLINGS)}")
    if sling != "rigid" and design.machine.sling_mass > 0.0:
        raise EngineError(f"sling = {sling!r}: the engine models a sling with mass (machine.sling_mass = "
                          f"{design.machine.sling_mass:g} kg) as a rod, rigid only")
    m = design.machine
    size = m.pivot_height + m.arm_long + m.sling_length
    if m.kind == "hinged" and m.counterweight_link < LINK_FRACTION * size:
        raise EngineError(f"machine.counterweight_link = {m.counterweight_link:g} m is under {LINK_FRACTION:g} of "
                          f"the machine's size ({size:g} m): the engine's positions, floats, cannot resolve "
                          f"its direction; make it longer")
    carried = carried_mass(design)
    if 0.0 < design.machine.sling_mass < SLING_MASS_FRACTION * carried:
        raise EngineError(f"machine.sling_mass = {design.machine.sling_mass:g} kg is under "
                          f"{SLING_MASS_FRACTION:.0%} of the {carried:g} kg it carries: the engine's solver "
                          f"does not converge for so light a sling; make it massless (0) or heavier")
    if iterations < 1:
        raise ValueError(f"iterations = {iterations!r}: must be at least 1")
    m = design.machine
    fixed = m.kind != "hinged"   # the counterweight is part of the arm's body
    start = start_positions(design)
    space = _space(design, iterations)
    frame, rail = _frame(design, space)
    arm = _arm(design)
    counterweight = None if fixed else _counterweight(design, start["counterweight"])
    projectile = _projectile(design, start["projectile"])
    supports: tuple = ()
    if m.kind == "floating-arm":
        pivot, carried, held = floating.supports(design, frame, arm, (axle_start(design), 0.0))
        supports = carried + held
    else:
        pivot = pymunk.PivotJoint(frame, arm, (0.0, 0.0), (0.0, 0.0))
    hinge = None if fixed else _hinge(design, arm, counterweight)
    sling_body = sling_tip = None
    if released:
        sling_body, sling_tip = released_sling(design, arm)
        sling_joint = _sling(design, sling, arm, projectile)
    elif m.sling_mass > 0.0:
        sling_body = sling_rod(design)
        sling_tip = pymunk.PivotJoint(arm, sling_body, (0.0, m.arm_long), (0.0, 0.0))
        sling_joint = pymunk.PivotJoint(sling_body, projectile, (0.0, m.sling_length), (0.0, 0.0))
    else:
        sling_joint = _sling(design, sling, arm, projectile)
    groove = _trough(design, frame, projectile)

    joints = [pivot] + ([] if hinge is None else [hinge]) + list(supports[2:])
    joints += ([] if sling_tip is None else [sling_tip]) + [sling_joint]
    joints += ([groove] if on_base else []) + ([rail] if rail else [])
    for joint in joints + [groove]:
        joint.error_bias = 0.0
        joint.max_bias = math.inf
        joint.collide_bodies = False
    named = [("arm", arm), ("counterweight", counterweight), ("projectile", projectile)]
    named += [("frame", frame)] if rail else []
    named += list(zip(("carriage", "slider"), supports[:2]))
    named += [] if sling_body is None else [("sling", sling_body)]
    space.add(*_checked_bodies(named), *joints)
    return Rig(space, arm, counterweight, projectile, pivot, hinge, sling_joint, groove, sling, frame, rail,
               (0.0, -m.arm_short) if fixed else None, supports, sling_body, sling_tip)


def trough_level(design: Design) -> float:
    """The height below the pivot of what the projectile slides on, m: the trough's top,
    ``pivot_height - trough_height`` (the base itself without a trough)."""
    return design.machine.pivot_height - design.base.trough_height


def _trough(design: Design, frame: pymunk.Body, projectile: pymunk.Body) -> pymunk.GrooveJoint:
    """The trough the projectile slides on: a horizontal groove on the frame at ``trough_level`` below the
    pivot, ``GROOVE_HALF_LENGTH_FACTOR`` machine lengths either way (the projectile is dragged back under
    the pivot before it swings forward; neither end is ever reached). Removed at lift-off, it leaves
    the flight to fall past it to the ground (nothing collides)."""
    reach, level = GROOVE_HALF_LENGTH_FACTOR * largest_length(design.machine), trough_level(design)
    return pymunk.GrooveJoint(frame, projectile, (-reach, -level), (reach, -level), (0.0, 0.0))


def _space(design: Design, iterations: int) -> pymunk.Space:
    """An empty Space under the design's gravity, undamped, solving ``iterations`` times a step."""
    space = pymunk.Space()
    space.gravity = (0.0, -design.environment.gravity)
    space.damping = 1.0
    space.iterations = int(iterations)
    # No shapes collide, but keep pymunk's pixel-sized defaults out of a metre world.
    space.collision_slop = 1e-6 * largest_length(design.machine)
    return space


def _frame(design: Design, space: pymunk.Space) -> tuple[pymunk.Body, pymunk.GrooveJoint | None]:
    """The body carrying the pivot and the base, and the rail it rolls on: a rolling frame's own body
    (``frame_body_mass``, never turning) on a groove along the ground; else the space's static body
    and no rail."""
    if not design.base.rolling:
        return space.static_body, None
    frame = pymunk.Body(frame_body_mass(design), math.inf)
    frame.position = (0.0, 0.0)
    rail = pymunk.GrooveJoint(space.static_body, frame, (-RAIL_HALF_LENGTH, 0.0), (RAIL_HALF_LENGTH, 0.0),
                              (0.0, 0.0))
    return frame, rail


def _arm(design: Design) -> pymunk.Body:
    """The arm's body at rest: a hinged machine's arm (``arm_body_properties``), a fixed one's with its
    counterweight (``fixed_arm_properties``), or a floating arm's (``floating.arm_properties``)."""
    m = design.machine
    if m.kind == "floating-arm":
        mass, cg, moment = floating.arm_properties(design)
    elif m.kind != "hinged":
        mass, cg, moment = fixed_arm_properties(design)
    else:
        mass, cg, moment = arm_body_properties(design)
    arm = pymunk.Body(mass, moment)
    # pymunk keeps the centre of gravity fixed when the angle is set: set the
    # centre of gravity, then the angle, then the origin's position.
    arm.center_of_gravity = (0.0, cg)
    arm.angle = initial_angles(m, design.base.trough_height)[0]
    arm.position = (axle_start(design), 0.0)
    return arm


def _counterweight(design: Design, position: tuple[float, float]) -> pymunk.Body:
    """A hinged machine's counterweight at rest, centred at ``position``; a point counterweight's moment
    is a placeholder (``placeholder_moment``: its rotation is decoupled, see ``build``)."""
    m = design.machine
    theta, phi, _ = initial_angles(m, design.base.trough_height)
    moment = (placeholder_moment(m.counterweight_mass, m.counterweight_link) if m.counterweight_inertia == 0.0
              else m.counterweight_inertia)
    counterweight = pymunk.Body(m.counterweight_mass, moment)
    counterweight.angle = theta + phi
    counterweight.position = position
    return counterweight


def _projectile(design: Design, position: tuple[float, float]) -> pymunk.Body:
    """The projectile at ``position``, with the pouch it sits in (``kinematics.carried_mass``): a solid
    sphere's moment, which nothing couples to."""
    proj = design.projectile
    projectile = pymunk.Body(carried_mass(design), placeholder_moment(0.4 * proj.mass, proj.diameter / 2.0))
    projectile.position = position
    return projectile


def sling_rod(design: Design) -> pymunk.Body:
    """A sling with mass at rest: a uniform rod of ``sling_mass`` from the long tip (its origin) to the
    projectile's centre (local ``(0, sling_length)``), moment ``m L^2 / 12`` about its centre."""
    m = design.machine
    theta, _, psi = initial_angles(m, design.base.trough_height)
    rod = pymunk.Body(m.sling_mass, m.sling_mass * m.sling_length**2 / 12.0)
    rod.center_of_gravity = (0.0, 0.5 * m.sling_length)
    rod.angle = theta + psi
    rod.position = start_positions(design)["long_tip"]
    return rod


def released_sling(design: Design, arm: pymunk.Body) -> tuple[pymunk.Body | None, pymunk.Constraint | None]:
    """What stays on the long tip after release, and its joint to it: the rod (``sling_rod``) with the
    pouch at its end, one body (its centre of gravity and moment those of both, by parallel axes); the
    pouch alone on a massless sling, a point body (origin at its centre, a placeholder moment) on a
    PinJoint as long as the sling; (None, None) for a massless sling without a pouch. Placed as at rest:
    the caller moves it to the release state (``engine_model.after_release``)."""
    m = design.machine
    if m.sling_mass > 0.0:
        rod = sling_rod(design)
        if m.pouch_mass > 0.0:
            mass = m.sling_mass + m.pouch_mass
            cg = (0.5 * m.sling_mass + m.pouch_mass) * m.sling_length / mass
            moment = (m.sling_mass * m.sling_length**2 / 12.0 + m.sling_mass * (cg - 0.5 * m.sling_length) ** 2
                      + m.pouch_mass * (m.sling_length - cg) ** 2)
            rod.mass, rod.moment = mass, moment
            angle, position = rod.angle, rod.position
            rod.center_of_gravity = (0.0, cg)
            rod.angle, rod.position = angle, position
        return rod, pymunk.PivotJoint(arm, rod, (0.0, m.arm_long), (0.0, 0.0))
    if m.pouch_mass > 0.0:
        pouch = pymunk.Body(m.pouch_mass, placeholder_moment(m.pouch_mass, m.sling_length))
        pouch.position = start_positions(design)["projectile"]
        tip = pymunk.PinJoint(arm, pouch, (0.0, m.arm_long), (0.0, 0.0))
        tip.distance = m.sling_length
        return pouch, tip
    return None, None


def _hinge(design: Design, arm: pymunk.Body, counterweight: pymunk.Body) -> pymunk.Constraint:
    """The short tip's hinge to the counterweight: a PivotJoint at the end of the link, or for a point
    counterweight (no inertia) a PinJoint as long as the link to its centre."""
    m = design.machine
    if m.counterweight_inertia == 0.0:
        hinge = pymunk.PinJoint(arm, counterweight, (0.0, -m.arm_short), (0.0, 0.0))
        hinge.distance = m.counterweight_link
        return hinge
    return pymunk.PivotJoint(arm, counterweight, (0.0, -m.arm_short), (0.0, m.counterweight_link))


def _sling(design: Design, sling: str, arm: pymunk.Body, projectile: pymunk.Body) -> pymunk.Constraint:
    """The sling from the long tip to the projectile: a PinJoint (``"rigid"``) or a SlideJoint that
    pulls only (``"rope"``)."""
    m = design.machine
    if sling == "rigid":
        joint = pymunk.PinJoint(arm, projectile, (0.0, m.arm_long), (0.0, 0.0))
        joint.distance = m.sling_length
        return joint
    return pymunk.SlideJoint(arm, projectile, (0.0, m.arm_long), (0.0, 0.0), 0.0, m.sling_length)


def _checked_bodies(named: list[tuple[str, pymunk.Body | None]]) -> list[pymunk.Body]:
    """The bodies of ``(name, body)`` pairs (None left out), each checked to have a positive, finite
    mass and a positive moment.

    Raises
    ------
    EngineError
        A body's mass or moment is not: the design's numbers underflow or overflow them.
    """
    named = [(name, body) for name, body in named if body is not None]
    for name, body in named:
        if not (0.0 < body.mass < math.inf and body.moment > 0.0):
            raise EngineError(f"the {name}'s pymunk body would have mass {body.mass:.3g} kg and moment "
                              f"{body.moment:.3g} kg m^2: the engine needs both positive and finite "
                              f"(the design's numbers underflow or overflow them)")
    return [body for _, body in named]
