"""The trebuchet design: validated inputs and derived start geometry (files: ``analytic.design_file``).

This module is the contract both models read (``engine_model`` may import it,
its file module and ``analytic.aero``, nothing else of ``analytic``). Everything
inside is SI with angles in radians; degrees exist only in TOML files
(``analytic.design_file``). Every check raises ``DesignError`` naming the field
as it stands in a file, table first.

Geometry and angle conventions (the same symbols as ``docs/derivation.md``):

* origin at the pivot, x forward (the direction of the throw), y up; the base
  is the line ``y = -pivot_height``, and the trough the projectile starts on
  (``Base.trough_height`` above the base, 0 by default: the base itself) the
  line ``y = -(pivot_height - trough_height)``;
* ``arm_angle`` (theta): angle of the long arm from the upward vertical,
  counter-clockwise positive, so the long-arm tip is at
  ``arm_long * (-sin theta, cos theta)``; the arm swings clockwise when firing;
* ``weight_angle`` (phi): angle of the counterweight link relative to the
  short arm's extension, so the counterweight centre is at
  ``arm_short * (sin theta, -cos theta) + counterweight_link * (sin(theta+phi), -cos(theta+phi))``;
* ``sling_angle`` (psi): angle of the sling relative to the long arm, so the
  projectile is at ``tip + sling_length * (-sin(theta+psi), cos(theta+psi))``.
"""

from __future__ import annotations

import math
import numbers
import sys
from dataclasses import dataclass, field, fields
from typing import Any

import numpy as np

from analytic.aero import DRAG_MODELS
from analytic.geometry import RELEASE_RULES
from analytic.data.strength import MATERIALS, PROJECTILE_KINDS, STANDARD_GRAVITY


#: The machine kinds (``Machine.kind``): the counterweight hinged, bolted to the arm, or on a floating arm.
KINDS = ("hinged", "fixed", "floating-arm")
#: The kinds both models simulate today (each kind joins when the analytic model and the engine have it).
BUILT_KINDS = ("hinged", "fixed", "floating-arm")

#: Largest ``|release angle|`` for the ``velocity`` rule: the velocity must point forward.
MAX_VELOCITY_RELEASE_ANGLE = math.radians(90.0)
#: Largest ``|release angle|`` for the ``sling`` rule (sling-to-arm angle).
MAX_SLING_RELEASE_ANGLE = math.radians(180.0)
#: Largest magnitude of any number in a design, SI units: the largest float whose fourth
#: power is finite (1.16e77, the largest float's fourth root rounded down). It bounds what
#: the model can compute, not what can be built (how big a machine is plausible is
#: ``analytic.plausibility``'s to say, in warnings): the equations multiply a design's
#: numbers together (a mass by gravity by a length, a mass by a length squared), and a
#: number past it overflows even its own square's square. The products themselves are
#: checked too (``computable_scales``).
MAX_MAGNITUDE = math.nextafter(sys.float_info.max ** 0.25, 0.0)
#: Shortest sling, as a fraction of the long arm. At rest the projectile lies on
#: the base a sling's length from the arm tip, at the angle whose cosine is the
#: tip's height above the base over the sling; rounding leaves that height off
#: by up to 3.3e-16 arm_long (``arm_long cos(theta0) + pivot_height`` over every
#: proportion of the two), so below 1e-5 arm_long the start angle would be set
#: by rounding to worse than the integrator's tolerance (1e-10), and below about
#: 3e-16 it is undefined. No sling that short is a sling.
MIN_SLING_FRACTION = 1e-5


class DesignError(ValueError):
    """A design that cannot be built: ``table.field = value: reason``.

    Attributes
    ----------
    field : the value's place in a design file, table first (``machine.arm_short``).
    value : the offending value (``None`` when it is missing).
    reason : why it is refused.
    """

    def __init__(self, field_name: str, value: Any, reason: str):
        self.field = field_name
        self.value = value
        self.reason = reason
        super().__init__(self._message())

    def _message(self) -> str:
        return f"{self.field} = {self.value!r}: {self.reason}"

    def __reduce__(self):
        # Rebuilt from its parts, so it survives a process pool.
        return type(self), (self.field, self.value, self.reason)


class MissingValueError(DesignError):
    """A required value or table that is absent: ``machine.sling_length: required value is missing``."""

    def __init__(self, field_name: str, value: Any = None, reason: str = "required value is missing"):
        super().__init__(field_name, value, reason)

    def _message(self) -> str:
        return f"{self.field}: {self.reason}"


@dataclass(frozen=True)
class Machine:
    """The machine's geometry and masses (SI, radians).

    Attributes
    ----------
    pivot_height : height h of the pivot above the base, m.
    arm_long : pivot to long-arm (sling) tip, m.
    arm_short : pivot to short-arm (counterweight hinge) tip, m.
    arm_mass : mass of the arm, kg.
    arm_cg : distance from the pivot to the arm's centre of mass, measured
        toward the long end (negative if on the short side), m.
    arm_inertia : moment of inertia of the arm about its own centre of mass, kg m^2.
    counterweight_mass : kg.
    counterweight_link : hinge to counterweight centre, m.
    counterweight_inertia : about the counterweight's own centre, kg m^2.
    sling_length : long-arm tip to projectile centre, m.
    release_angle : rad; the velocity direction above horizontal (rule
        ``velocity``) or the sling-to-arm angle (rule ``sling``, see
        ``analytic.geometry.sling_arm_angle``). Not used by the rule ``ideal``:
        None there, or a number, which is ignored.
    release_rule : ``"velocity"``, ``"sling"`` or ``"ideal"`` (release at the instant
        of the free swing that throws farthest: ``analytic.ideal``).
    kind : ``"hinged"`` (the counterweight hangs from a hinge at the short
        arm's tip, the default), ``"fixed"`` (bolted: rigid on the arm, its
        centre at ``arm_short`` on the arm's axis) or ``"floating-arm"``
        (the axle rides a horizontal track and the counterweight a vertical
        guide). ``counterweight_link`` is 0 unless the kind is hinged.
    sling_mass : mass of the sling, kg (0 by default: massless): a uniform straight rod from
        the long-arm tip to the projectile's centre; it stays on the arm at release.
    pouch_mass : mass of the pouch, kg (0 by default): a point at the projectile's centre
        while it holds the projectile; it stays with the sling at release.
    arm_section : the arm's cross-section and strength (``ArmSection``), for the stress a shot
        puts in it; None (the default) where the design gives no beam. The dynamics never read it.
    """

    pivot_height: float
    arm_long: float
    arm_short: float
    arm_mass: float
    arm_cg: float
    arm_inertia: float
    counterweight_mass: float
    counterweight_link: float
    counterweight_inertia: float
    sling_length: float
    release_angle: float | None
    release_rule: str = "velocity"
    kind: str = "hinged"
    sling_mass: float = 0.0
    pouch_mass: float = 0.0
    arm_section: ArmSection | None = None

    def __post_init__(self) -> None:
        require_kind("machine.kind", self.kind)
        if self.arm_section is not None and not isinstance(self.arm_section, ArmSection):
            raise DesignError("machine.arm_beam", self.arm_section, "must be an ArmSection")
        for name in ("pivot_height", "arm_long", "arm_short", "arm_mass",
                     "counterweight_mass", "sling_length"):
            require_positive(f"machine.{name}", getattr(self, name))
        if self.kind == "hinged":
            require_positive("machine.counterweight_link", self.counterweight_link)
        elif require_number("machine.counterweight_link", self.counterweight_link) != 0.0:
            raise DesignError("machine.counterweight_link", self.counterweight_link,
                              f"a {self.kind} machine has no link: its counterweight is rigid on the "
                              f"arm; leave counterweight_link out (or 0)")
        for name in ("arm_inertia", "counterweight_inertia", "sling_mass", "pouch_mass"):
            require_non_negative(f"machine.{name}", getattr(self, name))
        require_number("machine.arm_cg", self.arm_cg)
        require_choice("machine.release_rule", self.release_rule, RELEASE_RULES)
        if self.release_angle is not None or self.release_rule != "ideal":   # the ideal rule ignores it
            if self.release_angle is None:
                raise DesignError("machine.release_angle", None,
                                  f"release_rule {self.release_rule!r} needs a release angle (only "
                                  f"release_rule 'ideal' goes without one)")
            require_number("machine.release_angle", self.release_angle)
        if not -self.arm_short <= self.arm_cg <= self.arm_long:
            raise DesignError("machine.arm_cg", self.arm_cg,
                              f"the arm's centre of mass must lie on the arm, between "
                              f"-arm_short ({-self.arm_short:g} m) and arm_long ({self.arm_long:g} m)")
        if self.arm_long <= self.pivot_height:
            raise DesignError("machine.arm_long", self.arm_long,
                              f"the long arm cannot reach the base: it must be longer than "
                              f"pivot_height ({self.pivot_height:g} m)")
        if not self.sling_length >= MIN_SLING_FRACTION * self.arm_long:
            raise DesignError("machine.sling_length", self.sling_length,
                              f"shorter than {MIN_SLING_FRACTION:g} of arm_long ({self.arm_long:g} m): the "
                              f"sling's angle at rest would be set by rounding")
        if self.kind != "hinged" and self.arm_short >= self.pivot_height:
            raise DesignError("machine.arm_short", self.arm_short,
                              f"the counterweight would strike the base: on a {self.kind} machine "
                              f"arm_short must be less than pivot_height ({self.pivot_height:g} m)")
        if self.arm_short + self.counterweight_link >= self.pivot_height:
            raise DesignError("machine.counterweight_link", self.counterweight_link,
                              f"the counterweight would strike the base: arm_short + "
                              f"counterweight_link ({self.arm_short + self.counterweight_link:g} m) "
                              f"must be less than pivot_height ({self.pivot_height:g} m)")
        limit = (MAX_VELOCITY_RELEASE_ANGLE if self.release_rule == "velocity"
                 else MAX_SLING_RELEASE_ANGLE)
        if self.release_rule != "ideal" and not -limit < self.release_angle < limit:
            raise DesignError("machine.release_angle", f"{math.degrees(self.release_angle):g} deg",
                              f"with release_rule {self.release_rule!r} it must lie strictly "
                              f"between {-math.degrees(limit):g} and {math.degrees(limit):g} deg")

    @property
    def starting_angle(self) -> float:
        """Angle of the long arm below the horizontal at rest, rad (the paper's theta_0)."""
        return math.asin(self.pivot_height / self.arm_long)


@dataclass(frozen=True)
class Projectile:
    """A spherical projectile (point mass in the dynamics, a sphere for drag).

    Attributes
    ----------
    mass : kg.
    diameter : m.
    drag : the drag model (``analytic.aero.DRAG_MODELS``).
    drag_coefficient : Cd of ``drag = "constant"`` (only there).
    drag_factor : a multiplier on the drag force of any model (its Cd at every Re),
        1 by default: what a calibration fits when a real ball drags more or less
        than its model (``analytic.calibrate``). The Reynolds number is unchanged.
    drag_during_swing : whether the drag (with the wind) also acts in stages 1-2, before
        release; False by default, the paper's model (drag in flight only).
    max_acceleration : m/s^2, the largest acceleration the projectile survives (in g in
        files), or None: no limit given (unless its ``kind`` has one).
    kind : what the projectile is (``analytic.data.strength.PROJECTILE_KINDS``: ``"egg"``, ...), whose
        documented limit applies; None by default. Give ``kind`` or ``max_acceleration``, not both.
    """

    mass: float
    diameter: float
    drag: str = "none"
    drag_coefficient: float | None = None
    drag_factor: float = 1.0
    drag_during_swing: bool = False
    max_acceleration: float | None = None
    kind: str | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.drag_during_swing, bool):
            raise DesignError("projectile.drag_during_swing", self.drag_during_swing, "must be true or false")
        require_positive("projectile.mass", self.mass)
        require_positive("projectile.diameter", self.diameter)
        require_positive("projectile.drag_factor", self.drag_factor)
        require_choice("projectile.drag", self.drag, DRAG_MODELS)
        if self.drag == "constant":
            if self.drag_coefficient is None:
                raise MissingValueError("projectile.drag_coefficient", reason='required with drag = "constant"')
            require_positive("projectile.drag_coefficient", self.drag_coefficient)
        elif self.drag_coefficient is not None:
            raise DesignError("projectile.drag_coefficient", self.drag_coefficient,
                              f'only used with drag = "constant", not {self.drag!r}; remove it')
        if self.kind is not None:
            require_choice("projectile.kind", self.kind, tuple(PROJECTILE_KINDS))
            if self.max_acceleration is not None:
                raise DesignError("projectile.max_acceleration", f"{self.max_acceleration / STANDARD_GRAVITY:g} g",
                                  f"give either max_acceleration or kind ({self.kind!r} has its own limit, "
                                  f"{PROJECTILE_KINDS[self.kind].max_acceleration_g:g} g), not both")
        if self.max_acceleration is not None:
            require_positive("projectile.max_acceleration", self.max_acceleration)

    @property
    def acceleration_limit(self) -> float | None:
        """The largest acceleration the projectile survives, m/s^2: ``max_acceleration``, or its
        ``kind``'s documented limit, or None (no limit given)."""
        if self.max_acceleration is not None:
            return self.max_acceleration
        return None if self.kind is None else PROJECTILE_KINDS[self.kind].max_acceleration_g * STANDARD_GRAVITY

    @property
    def frontal_area(self) -> float:
        """Cross-sectional area pi d^2 / 4, m^2."""
        return math.pi * self.diameter**2 / 4.0

    @property
    def drag_area(self) -> float:
        """The area the drag acts on, ``frontal_area * drag_factor``, m^2 (the frontal area itself
        at the default factor 1, to the bit)."""
        return self.frontal_area * self.drag_factor


@dataclass(frozen=True)
class Environment:
    """Gravity and air; the defaults are standard sea-level values.

    ``target_height`` (m, either sign) is the level the shot lands at, above the base (below it,
    negative: a pit); the flight ends where the projectile's centre comes down through it, and a
    shot that never rises to it is ``short_of_target`` (``docs/derivation.md``, the flight).
    """

    gravity: float = 9.81
    air_density: float = 1.225
    air_viscosity: float = 1.81e-5
    wind_speed: float = 0.0
    target_height: float = 0.0

    def __post_init__(self) -> None:
        require_positive("environment.gravity", self.gravity)
        require_non_negative("environment.air_density", self.air_density)
        require_positive("environment.air_viscosity", self.air_viscosity)
        require_number("environment.wind_speed", self.wind_speed)
        require_number("environment.target_height", self.target_height)


#: How the frame stands: bolted to the ground, or free to roll horizontally.
MOBILITIES = ("fixed", "rolling")


@dataclass(frozen=True)
class Base:
    """The frame (pivot, base and everything fixed to them but arm, counterweight and projectile).

    Attributes
    ----------
    mobility : ``"fixed"`` (bolted down) or ``"rolling"`` (translates
        horizontally as one rigid body on frictionless wheels; it does not
        lift or tip).
    mass : kg, the frame's effective translational mass (the frame, the
        wheels and, if wished, the wheels' rotational inertia as I / r^2);
        required when rolling.
    trough_height : m, the height above the base of the horizontal trough the
        projectile starts on and slides along in stage 1, part of the frame
        (0, the default: the projectile slides on the base itself). The
        long-arm tip rests at its level; the flight lands on the base.
    """

    mobility: str = "fixed"
    mass: float | None = None
    trough_height: float = 0.0

    def __post_init__(self) -> None:
        require_choice("base.mobility", self.mobility, MOBILITIES)
        require_non_negative("base.trough_height", self.trough_height)
        if self.mass is not None:
            require_positive("base.mass", self.mass)
        elif self.mobility == "rolling":
            raise MissingValueError("base.mass", reason='required value is missing (with mobility = "rolling")')

    @property
    def rolling(self) -> bool:
        return self.mobility == "rolling"


#: The ``[losses]`` table's joints: each has a Coulomb coefficient and the
#: radius of the pin (or bearing) it acts at.
FRICTION_JOINTS = ("axle", "hinge")
#: The floating arm's sliding supports: its counterweight's guide and its axle's track, each a
#: Coulomb coefficient against the support's normal force (no radius).
SLIDES = ("guide", "track")
#: Every friction of the ``[losses]`` table: the joints', the base's and the slides'; each has a kinetic
#: coefficient ``{name}_friction`` and an optional static one ``{name}_static_friction``.
FRICTIONS = ("axle", "hinge", "base") + SLIDES


@dataclass(frozen=True)
class Losses:
    """Friction in the machine (``[losses]`` in design files); all zero is the ideal machine.

    Attributes
    ----------
    axle_friction : Coulomb coefficient of the main axle in its bearing.
    axle_radius : m, the axle's radius: the friction torque is
        ``axle_friction * axle_radius * |axle reaction force|``, opposing the arm's rotation.
    hinge_friction, hinge_radius : the same for the counterweight's hinge on the
        short arm, opposing the link's rotation relative to the arm.
    base_friction : Coulomb coefficient of the projectile (or its sled)
        sliding on the base in stage 1: ``base_friction * N`` against its sliding.
    guide_friction : Coulomb coefficient of a floating arm's counterweight
        sliding on its vertical guide: ``guide_friction * |G|`` against its
        sliding, G the guide's horizontal (normal) force on it.
    track_friction : Coulomb coefficient of a floating arm's axle sliding on
        its horizontal track: ``track_friction * |T|`` against its sliding,
        T the track's vertical (normal) force on it.
    axle_static_friction, hinge_static_friction, base_static_friction,
    guide_static_friction, track_static_friction : the
        static coefficients: a joint at rest (or the projectile at rest on
        the base, or a slide at rest on its support) holds up to this
        coefficient times its load, and once it slips the kinetic one above
        acts. None (not given): the kinetic coefficient (``static``). Never
        below the kinetic one.

    A joint's coefficient without its radius is refused: the torque needs both.
    A radius with a zero coefficient is a frictionless bearing of known size,
    the ideal machine's joint.
    """

    axle_friction: float = 0.0
    axle_radius: float = 0.0
    hinge_friction: float = 0.0
    hinge_radius: float = 0.0
    base_friction: float = 0.0
    axle_static_friction: float | None = None
    hinge_static_friction: float | None = None
    base_static_friction: float | None = None
    guide_friction: float = 0.0
    track_friction: float = 0.0
    guide_static_friction: float | None = None
    track_static_friction: float | None = None

    def __post_init__(self) -> None:
        for name in ("axle_friction", "axle_radius", "hinge_friction", "hinge_radius", "base_friction",
                     "guide_friction", "track_friction"):
            require_non_negative(f"losses.{name}", getattr(self, name))
        for joint in FRICTION_JOINTS:
            coefficient, radius = getattr(self, f"{joint}_friction"), getattr(self, f"{joint}_radius")
            if coefficient > 0.0 and radius == 0.0:
                raise DesignError(f"losses.{joint}_friction", coefficient,
                                  f"a coefficient without its radius: give losses.{joint}_radius (m) too")
        for friction in FRICTIONS:
            static = getattr(self, f"{friction}_static_friction")
            if static is None:
                continue
            name, kinetic = f"losses.{friction}_static_friction", getattr(self, f"{friction}_friction")
            require_non_negative(name, static)
            if static < kinetic:
                raise DesignError(name, static, f"is below the kinetic coefficient losses.{friction}_friction = "
                                                f"{kinetic:g}: what a joint holds at rest is at least what it "
                                                f"gives slipping")
            if friction in FRICTION_JOINTS and static > 0.0 and getattr(self, f"{friction}_radius") == 0.0:
                raise DesignError(name, static,
                                  f"a coefficient without its radius: give losses.{friction}_radius (m) too")

    def static(self, friction: str) -> float:
        """The static coefficient of ``friction`` (one of ``FRICTIONS``): as given, or its kinetic one."""
        return static_coefficient(getattr(self, f"{friction}_static_friction"), getattr(self, f"{friction}_friction"))

    @property
    def ideal(self) -> bool:
        """No friction anywhere: every coefficient zero, kinetic and static (a joint's radius alone adds none)."""
        return all(getattr(self, f"{name}_friction") == 0.0 and self.static(name) == 0.0
                   for name in FRICTIONS)


@dataclass(frozen=True)
class Design:
    """A whole shot's inputs: machine, projectile, environment, the frame it stands on and its losses."""

    machine: Machine
    projectile: Projectile
    environment: Environment = field(default_factory=Environment)
    name: str = "design"
    base: Base = field(default_factory=Base)
    losses: Losses = field(default_factory=Losses)

    def __post_init__(self) -> None:
        if not isinstance(self.name, str):
            raise DesignError("name", self.name, "must be text")
        if not isinstance(self.base, Base):
            raise DesignError("base", self.base, "must be a Base")
        if not isinstance(self.losses, Losses):
            raise DesignError("losses", self.losses, "must be a Losses")
        if self.projectile.drag_during_swing and self.base.rolling:
            raise DesignError("projectile.drag_during_swing", True,
                              "not modelled on a rolling frame (the drag would change the frame's momentum, "
                              "which the rolling model keeps at zero); use a fixed base or leave it false")
        if isinstance(self.machine, Machine) and self.machine.kind != "hinged":
            for name in ("hinge_friction", "hinge_static_friction"):
                value = getattr(self.losses, name)
                if value is not None and value > 0.0:
                    raise DesignError(f"losses.{name}", value,
                                      f"a {self.machine.kind} machine has no hinge: its counterweight is rigid "
                                      f"on the arm; leave losses.{name} out (or 0)")
        if isinstance(self.machine, Machine) and self.base.trough_height > 0.0:
            self._check_trough()
        if isinstance(self.machine, Machine) and self.machine.kind == "floating-arm":
            self._check_floating()
        elif isinstance(self.machine, Machine):
            self._check_no_slides()
        if isinstance(self.machine, Machine) and isinstance(self.projectile, Projectile) \
                and isinstance(self.environment, Environment):
            self._check_computable()

    def _check_computable(self) -> None:
        """Refuse numbers that each lie within ``MAX_MAGNITUDE`` but together overflow the equations.

        The model's scales (``computable_scales``) are the products its equations form: the
        mass matrix's entries (an inertia), the generalised forces and energies (a weight by a
        length), the speeds squared and the drag. Each must stay within ``MAX_MAGNITUDE``, so that
        the mass matrix's determinant (three entries multiplied) and its solutions (two entries by
        a force) stay finite. The error names the most extreme number in the scale that passes:
        the one farthest from 1 in decades, the one to change.
        """
        for what, unit, scale, inputs in computable_scales(self):
            if not scale <= MAX_MAGNITUDE:
                name, value = _most_extreme(inputs)
                raise DesignError(name, value,
                                  f"is past the float range the model computes in: with the design's other "
                                  f"values {what} comes to {scale:.3g} {unit}, beyond {MAX_MAGNITUDE:.3g}, the "
                                  f"largest at which the equations' products of it stay finite")
        for what, inertia, inputs in pivot_inertias(self.machine, self.projectile):
            if not inertia >= sys.float_info.min:
                name, value = _most_extreme(inputs)
                raise DesignError(name, value,
                                  f"is past the float range the model computes in: with the design's other "
                                  f"values {what} comes to {inertia:.3g} kg m^2, below the smallest normal float "
                                  f"({sys.float_info.min:.3g}), and the equations divide by it")

    def _check_trough(self) -> None:
        """Refuse a trough the long arm's tip cannot come down to. At rest the tip lies on the trough,
        ``arm_long cos theta0 = -(pivot_height - trough_height)``, below the pivot and behind it: a
        trough at or above the pivot leaves the arm no way down to it. (Below the pivot every trough is
        within reach, ``arm_long > pivot_height`` being ``Machine``'s; the counterweight's clearance
        is the base's, checked there too: it swings under the pivot, clear of a trough ahead.)"""
        m, trough = self.machine, self.base.trough_height
        if not trough < m.pivot_height:
            raise DesignError("base.trough_height", trough,
                              f"the long arm's tip cannot come down to a trough at or above the pivot: "
                              f"it must be less than pivot_height ({m.pivot_height:g} m)")

    def _check_no_slides(self) -> None:
        """Refuse guide and track friction on a machine without a guide and a track."""
        for slide in SLIDES:
            for name in (f"{slide}_friction", f"{slide}_static_friction"):
                value = getattr(self.losses, name)
                if value is not None and value > 0.0:
                    raise DesignError(f"losses.{name}", value,
                                      f"only a floating-arm machine has a guide and a track; a "
                                      f"{self.machine.kind} machine has neither: leave losses.{name} out (or 0)")

    def _check_floating(self) -> None:
        """Refuse what the floating-arm machine does not model: a rolling frame (its axle already rides a
        track); the axle's, the base's, the guide's and the track's friction and the drag before release
        are modelled."""
        if self.base.rolling:
            raise DesignError("base.mobility", self.base.mobility,
                              "a floating-arm machine's axle already rides its track: its frame cannot roll; "
                              'use mobility = "fixed"')


def computable_scales(design: Design) -> list[tuple[str, str, float, tuple[tuple[str, float], ...]]]:
    """The products the equations form of ``design``'s numbers, each with the numbers it is made of.

    Returns
    -------
    list of (what, unit, scale, inputs)
        ``what`` names the scale and its formula, ``inputs`` are ``(field, SI value)`` pairs.
    """
    m, p, env, losses = design.machine, design.projectile, design.environment, design.losses
    lengths = (("machine.pivot_height", m.pivot_height), ("machine.arm_long", m.arm_long),
               ("machine.arm_short", m.arm_short), ("machine.counterweight_link", m.counterweight_link),
               ("machine.sling_length", m.sling_length), ("projectile.diameter", p.diameter),
               ("losses.axle_radius", losses.axle_radius), ("losses.hinge_radius", losses.hinge_radius))
    masses = (("machine.arm_mass", m.arm_mass), ("machine.counterweight_mass", m.counterweight_mass),
              ("projectile.mass", p.mass)) + ((("base.mass", design.base.mass),) if design.base.mass else ())
    masses += tuple((f"machine.{name}", getattr(m, name)) for name in ("sling_mass", "pouch_mass") if getattr(m, name))
    inertias = (("machine.arm_inertia", m.arm_inertia), ("machine.counterweight_inertia", m.counterweight_inertia))
    coefficients = tuple((f"losses.{name}", getattr(losses, name) or 0.0)
                         for name in [f"{f}_friction" for f in FRICTIONS] + [f"{f}_static_friction" for f in FRICTIONS])
    gravity, wind = ("environment.gravity", env.gravity), ("environment.wind_speed", env.wind_speed)
    length, mass = sum(v for _, v in lengths), sum(v for _, v in masses)
    grip = 1.0 + max(v for _, v in coefficients)   # friction multiplies the loads by up to this
    speed_squared = env.gravity * length + env.wind_speed ** 2
    # The drag curves' Cd is at most about 1 but at creeping flow, where the viscous term takes over.
    drag_scale = p.drag_factor * (env.air_density * (p.drag_coefficient or 1.0) * p.diameter ** 2 * speed_squared
                                  + env.air_viscosity * p.diameter * math.sqrt(speed_squared))
    return [
        ("the machine's size (the sum of its lengths)", "m", length, lengths),
        ("the machine's mass (the sum of its masses)", "kg", mass, masses),
        ("the machine's inertia (its inertias and mass x size^2)", "kg m^2",
         sum(v for _, v in inertias) + mass * length ** 2, inertias + masses + lengths),
        ("the work of the machine's weight (mass x gravity x size, with friction)", "J",
         mass * env.gravity * length * grip, masses + lengths + coefficients + (gravity,)),
        ("the speed squared (gravity x size + wind^2)", "m^2/s^2", speed_squared, lengths + (gravity, wind)),
        ("the projectile's drag", "N", drag_scale,
         (("projectile.drag_factor", p.drag_factor), ("projectile.diameter", p.diameter),
          ("environment.air_density", env.air_density), ("environment.air_viscosity", env.air_viscosity),
          gravity, wind) + lengths
         + ((("projectile.drag_coefficient", p.drag_coefficient),) if p.drag_coefficient is not None else ())),
    ]


def pivot_inertias(machine: Machine, projectile: Projectile) -> list[tuple[str, float, tuple[tuple[str, float], ...]]]:
    """The mass matrix's diagonal at its smallest, kg m^2, each with the numbers it is made of.

    Each body's inertia about the joint it turns on: the arm with everything on it about the pivot,
    the hinged counterweight about its hinge, the projectile about the sling's tip. The equations
    divide by the mass matrix's determinant; an inertia that underflows to zero makes it zero.
    """
    m, p = machine, projectile
    arm = (("machine.arm_inertia", m.arm_inertia), ("machine.arm_mass", m.arm_mass), ("machine.arm_cg", m.arm_cg),
           ("machine.counterweight_mass", m.counterweight_mass), ("machine.arm_short", m.arm_short),
           ("projectile.mass", p.mass), ("machine.arm_long", m.arm_long))
    found = [("the arm's inertia about the pivot (with its counterweight and projectile)",
              m.arm_inertia + m.arm_mass * m.arm_cg**2 + m.counterweight_mass * m.arm_short**2
              + p.mass * m.arm_long**2, arm)]
    if m.kind == "hinged":
        found.append(("the counterweight's inertia about its hinge (counterweight_inertia + mass x link^2)",
                      m.counterweight_inertia + m.counterweight_mass * m.counterweight_link**2,
                      (("machine.counterweight_inertia", m.counterweight_inertia),
                       ("machine.counterweight_mass", m.counterweight_mass),
                       ("machine.counterweight_link", m.counterweight_link))))
    found.append(("the projectile's inertia about the arm's tip (mass x sling_length^2)",
                  p.mass * m.sling_length**2, (("projectile.mass", p.mass), ("machine.sling_length", m.sling_length))))
    return found


def _most_extreme(inputs: tuple[tuple[str, float], ...]) -> tuple[str, float]:
    """The ``(field, value)`` of ``inputs`` farthest from 1 in decades (zeros left out): the one to change."""
    return max(((n, v) for n, v in inputs if v != 0.0), key=lambda item: abs(math.log10(abs(item[1]))))


# --------------------------------------------------------------------------- #
# Alternative parametrisations (the paper's, and an arm made of a uniform beam)
# --------------------------------------------------------------------------- #

def paper_geometry(arm_short: float, counterweight_link: float, clearance: float,
                   starting_angle: float) -> tuple[float, float]:
    """Pivot height and long arm from the paper's design variables.

    The paper (section II.A) sets ``h = arm_short + link + clearance`` and takes
    the long arm so that its tip rests on the base at the starting angle
    (below horizontal): ``arm_long = h / sin(starting_angle)``.

    Returns
    -------
    (pivot_height, arm_long) : m
    """
    for name, value in (("arm_short", arm_short), ("clearance", clearance)):
        require_positive(f"machine.{name}", value)
    require_non_negative("machine.counterweight_link", counterweight_link)   # 0: rigid on the arm
    if not 0.0 < require_number("machine.starting_angle", starting_angle) < math.pi / 2:
        raise DesignError("machine.starting_angle", f"{math.degrees(starting_angle):g} deg",
                          "must lie strictly between 0 and 90 deg")
    pivot_height = arm_short + counterweight_link + clearance
    return pivot_height, pivot_height / math.sin(starting_angle)


@dataclass(frozen=True)
class ArmSection:
    """The arm's rectangular cross-section and what it is made of: what the stress needs.

    Attributes
    ----------
    width : m, across the swing plane.
    depth : m, in the swing plane (the bending's).
    material : a name of ``analytic.data.strength.MATERIALS`` (its strength is the table's), or None.
    strength : Pa, the material's strength given directly, or None. Give ``material`` or
        ``strength``, not both; neither: the stress is known, the safety factor not.
    """

    width: float
    depth: float
    material: str | None = None
    strength: float | None = None

    def __post_init__(self) -> None:
        for name in ("width", "depth"):
            require_positive(f"machine.arm_beam.{name}", getattr(self, name))
        if self.material is not None:
            require_choice("machine.arm_beam.material", self.material, tuple(MATERIALS))
            if self.strength is not None:
                raise DesignError("machine.arm_beam.strength", self.strength,
                                  f"give either material or strength, not both (material {self.material!r} "
                                  f"has its own, {MATERIALS[self.material].strength:g} Pa)")
        if self.strength is not None:
            require_positive("machine.arm_beam.strength", self.strength)

    @property
    def bending_strength(self) -> float | None:
        """Pa: ``strength``, or the material's (``analytic.data.strength.MATERIALS``), or None."""
        if self.strength is not None:
            return self.strength
        return None if self.material is None else MATERIALS[self.material].strength


@dataclass(frozen=True)
class BeamArm:
    """An arm cut from a uniform rectangular beam (depth measured in the swing plane), of a ``material``
    or a ``strength`` (Pa) if given (``ArmSection``)."""

    width: float
    depth: float
    density: float
    material: str | None = None
    strength: float | None = None

    def __post_init__(self) -> None:
        for name in ("width", "depth", "density"):
            require_positive(f"machine.arm_beam.{name}", getattr(self, name))
        ArmSection(self.width, self.depth, self.material, self.strength)   # checks the material and strength

    @property
    def rated(self) -> bool:
        """Whether the beam names a material or a strength (then a design keeps its ``section``)."""
        return self.material is not None or self.strength is not None

    @property
    def section(self) -> ArmSection:
        """The beam's section and strength, which the design keeps for the stress."""
        return ArmSection(self.width, self.depth, self.material, self.strength)

    def properties(self, arm_long: float, arm_short: float) -> tuple[float, float, float]:
        """Mass (kg), centre-of-mass distance toward the long end (m), inertia about it (kg m^2).

        The beam runs from the short tip to the long tip, length ``L = arm_long + arm_short``;
        its in-plane inertia about its centre is ``m (L^2 + depth^2) / 12``.
        """
        length = arm_long + arm_short
        mass = self.density * self.width * self.depth * length
        inertia = mass * (length * length + self.depth * self.depth) / 12.0
        if not math.isfinite(inertia):
            raise DesignError("machine.arm_beam", f"{self.width:g} x {self.depth:g} m, {self.density:g} kg/m^3",
                              f"a beam {length:g} m long has a mass or inertia past the float range")
        return mass, (arm_long - arm_short) / 2.0, inertia


# --------------------------------------------------------------------------- #
# Start state
# --------------------------------------------------------------------------- #

def initial_angles(machine: Machine, trough_height: float = 0.0) -> np.ndarray:
    """Generalised coordinates at rest before firing, shape (3,): [theta, phi, psi], rad.

    The long-arm tip rests on the trough (``arm_long cos theta = -(h - trough_height)``;
    ``trough_height`` the design's ``base.trough_height``, 0: on the base), the
    counterweight hangs plumb (``theta + phi = 0``) and the sling lies along the
    trough pointing forward (``theta + psi = -pi/2``).
    """
    theta = rest_angle(machine, trough_height)
    return np.array([theta, -theta, -math.pi / 2 - theta])


def rest_angle(machine: Machine, trough_height: float = 0.0) -> float:
    """The arm's angle at rest before firing, rad: its long-arm tip on the trough
    (``arm_long cos theta = -(h - trough_height)``; 0, the base: ``-h`` to the bit)."""
    return math.acos(-(machine.pivot_height - trough_height) / machine.arm_long)


def static_coefficient(static: float | None, kinetic: float) -> float:
    """A joint's static Coulomb coefficient: ``static`` as given, or ``kinetic`` when not given (None)."""
    return kinetic if static is None else static


def largest_length(machine: Machine) -> float:
    """``arm_long + sling_length + arm_short + counterweight_link``, m: the machine's largest
    length, which sets its time and speed scales."""
    m = machine
    return m.arm_long + m.sling_length + m.arm_short + m.counterweight_link


# --------------------------------------------------------------------------- #
# Validation helpers
# --------------------------------------------------------------------------- #

def require_number(name: str, value: Any) -> float:
    """``value`` as a float if it is a real number, finite and within ``MAX_MAGNITUDE`` (the float range's).

    Parameters
    ----------
    name : the field, table first, for the error.
    value : anything read from a file or given by a caller.

    Raises
    ------
    DesignError
        for text, booleans, lists, tables, dates, nan, infinities and huge numbers.
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise DesignError(name, value, "must be a number")
    try:
        number = float(value)
    except OverflowError:  # an integer beyond any float: out of range, below
        number = math.inf
    if math.isnan(number) or (math.isinf(number) and not isinstance(value, numbers.Integral)):
        raise DesignError(name, value, "must be finite")
    if not abs(number) <= MAX_MAGNITUDE:
        raise DesignError(name, value, f"is past the float range the model computes in: it must lie between "
                                       f"{-MAX_MAGNITUDE:.3g} and {MAX_MAGNITUDE:.3g} (SI units), where the "
                                       f"equations' products of it stay finite")
    return number


def require_positive(name: str, value: Any) -> float:
    """``require_number``, and greater than zero."""
    number = require_number(name, value)
    if number <= 0:
        raise DesignError(name, value, "must be positive")
    return number


def require_non_negative(name: str, value: Any) -> float:
    """``require_number``, and not below zero."""
    number = require_number(name, value)
    if number < 0:
        raise DesignError(name, value, "must not be negative")
    return number


def require_kind(name: str, value: Any) -> str:
    """``value`` if it is one of ``KINDS`` that both models simulate (``BUILT_KINDS``)."""
    require_choice(name, value, KINDS)
    if value not in BUILT_KINDS:
        raise DesignError(name, value, f"both models simulate {', '.join(BUILT_KINDS)} machines so far; the "
                                       f"{value} machine is being built")
    return value


def require_choice(name: str, value: Any, choices: tuple[str, ...]) -> str:
    """``value`` if it is one of the texts ``choices``."""
    if not (isinstance(value, str) and value in choices):
        raise DesignError(name, value, f"must be one of {', '.join(choices)}")
    return value
