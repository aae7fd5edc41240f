"""A problem around a design: its own machine, each design variable within bounds about its value.

``problem_around(design)`` turns a design into the optimiser's ``Problem``
(``analytic.design_space``): the six design variables (the paper's, Table II)
take bounds about the design's own values (``default_bounds``: half to twice
for lengths, an absolute window for angles, within the problem's valid range),
and everything else is the design's: its kind, losses, frame, trough, target,
projectile, air, release rule, counterweight (mass and inertia), sling and pouch
masses. Its arm is the design's arm scaled with its length (``ScaledArm``). The
size limits default to the design's own (its footprint and pivot height at rest,
``analytic.optimise.constraints``): a better machine of the same size; any of
them, and load limits, can be given instead.

``adopted`` puts an optimum's values back into the design, changing only the
fields the optimiser varies (``OPTIMISED_FIELDS``).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Mapping

import numpy as np

from analytic.design import ArmSection, Design, DesignError, Machine, require_number
from analytic.design_space import ANGLE_VARIABLES, VARIABLE_NAMES, Problem, Variable, design_at
from analytic.optimise.constraints import axle_distance, footprint

#: Lengths range from the design's value divided by this to the value times this.
DEFAULT_FACTOR = 2.0
#: Angles range this far either side of the design's value, rad (20 deg).
DEFAULT_ANGLE_WINDOW = math.radians(20.0)
#: Angle bounds stay this far inside the problem's open limits (0-90 deg starting, +-90 deg release), rad.
ANGLE_MARGIN = math.radians(1.0)
#: The problem's open limits of the angles, rad (``design_space.Problem``).
_ANGLE_LIMITS = {"starting_angle": (0.0, math.pi / 2), "release_angle": (-math.pi / 2, math.pi / 2)}
#: The design's fields an optimum changes (file names, ``[machine]``): the geometry the variables
#: give, and the arm's mass, centre and inertia, which follow its length (``ScaledArm``).
OPTIMISED_FIELDS = ("pivot_height", "arm_long", "arm_short", "counterweight_link", "sling_length",
                    "release_angle", "arm_mass", "arm_cg", "arm_inertia")


@dataclass(frozen=True)
class ScaledArm:
    """A design's arm scaled with its length: mass per length, the centre's offset from the
    arm's middle in proportion to the length, and the radius of gyration in proportion to the
    length (inertia as the cube). At the design's own lengths it is the design's arm.

    Attributes
    ----------
    length : m, the design's arm end to end (``arm_long + arm_short``).
    mass : kg. centre_offset : m, the centre of mass ahead of the arm's middle.
    inertia : kg m^2, about the centre of mass.
    section : the design's ``ArmSection`` (its width, depth and strength stay as the length
        changes), or None.
    """

    length: float
    mass: float
    centre_offset: float
    inertia: float
    section: ArmSection | None = None

    @property
    def rated(self) -> bool:
        """Whether the design keeps the arm's section (for the stress a shot reports)."""
        return self.section is not None

    @classmethod
    def of(cls, machine: Machine) -> ScaledArm:
        """The arm of ``machine``."""
        return cls(machine.arm_long + machine.arm_short, machine.arm_mass,
                   machine.arm_cg - (machine.arm_long - machine.arm_short) / 2.0, machine.arm_inertia,
                   machine.arm_section)

    def properties(self, arm_long: float, arm_short: float) -> tuple[float, float, float]:
        """Mass (kg), centre-of-mass distance toward the long end (m), inertia about it (kg m^2)."""
        scale = (arm_long + arm_short) / self.length
        return (self.mass * scale, (arm_long - arm_short) / 2.0 + self.centre_offset * scale,
                self.inertia * scale**3)


def start_values(design: Design) -> np.ndarray:
    """The design's six design variables, shape (6,), m and rad (``design_space.VARIABLE_NAMES``);
    the release angle 0 under the ideal rule, which has none."""
    m = design.machine
    return np.array([m.arm_short, m.counterweight_link, m.pivot_height - m.arm_short - m.counterweight_link,
                     m.sling_length, m.starting_angle, 0.0 if m.release_angle is None else m.release_angle])


def fixed_variables(design: Design) -> tuple[str, ...]:
    """The variables no bounds apply to: the link of a rigid counterweight, the release angle
    under the ideal rule."""
    m = design.machine
    return (("counterweight_link",) if m.kind != "hinged" else ()) + (
        ("release_angle",) if m.release_rule == "ideal" else ())


def default_bounds(design: Design, factor: float = DEFAULT_FACTOR,
                   angle_window: float = DEFAULT_ANGLE_WINDOW) -> dict[str, tuple[float, float]]:
    """Bounds about the design's values: name -> (lower, upper), m and rad, for each free variable.

    Lengths from ``value / factor`` to ``value * factor``; angles ``angle_window`` either side,
    cut to ``ANGLE_MARGIN`` inside the problem's limits.

    Raises
    ------
    DesignError
        naming ``factor`` (not above 1) or ``angle_window`` (not positive), or the release angle
        when it lies outside the optimiser's +-90 deg (a sling rule's wider angle).
    """
    if not require_number("factor", factor) > 1.0:
        raise DesignError("factor", factor, "must be above 1 (bounds from value / factor to value * factor)")
    if not require_number("angle_window", angle_window) > 0.0:
        raise DesignError("angle_window", angle_window, "must be a positive angle")
    fixed = fixed_variables(design)
    bounds = {}
    for name, value in zip(VARIABLE_NAMES, start_values(design), strict=True):
        if name in fixed:
            continue
        if name not in ANGLE_VARIABLES:
            bounds[name] = (value / factor, value * factor)
            continue
        low, high = (limit + sign * ANGLE_MARGIN for limit, sign in zip(_ANGLE_LIMITS[name], (1, -1)))
        bounds[name] = (max(value - angle_window, low), min(value + angle_window, high))
        if bounds[name][0] >= bounds[name][1]:
            raise DesignError(f"machine.{name}", f"{math.degrees(value):g} deg",
                              f"the optimiser's {name.replace('_', ' ')}s lie between "
                              f"{math.degrees(low):g} and {math.degrees(high):g} deg")
    return bounds


def problem_around(design: Design, bounds: Mapping[str, tuple[float, float]] | None = None, *,
                   factor: float = DEFAULT_FACTOR, angle_window: float = DEFAULT_ANGLE_WINDOW,
                   max_footprint: float | None = None, max_height: float | None = None,
                   axle_radius: float | None = None, load_limits: tuple[tuple[str, float], ...] = (),
                   minimise: str | None = None, min_range: float | None = None,
                   name: str | None = None) -> Problem:
    """The optimisation problem around ``design`` (module docstring).

    Parameters
    ----------
    bounds : name -> (lower, upper), m and rad, for any of ``VARIABLE_NAMES``; the others take
        ``default_bounds(design, factor, angle_window)``.
    max_footprint, max_height : m; default the design's own footprint at rest (on its trough)
        and pivot height.
    axle_radius : m, the axle the counterweight must clear at rest; default the design's
        ``losses.axle_radius``, else 0.
    load_limits, minimise, min_range : as ``Problem``'s.
    name : the problem's name; default ``around-<design name>``.

    Raises
    ------
    DesignError
        naming the field, the value and the reason: an unknown variable, bounds on a variable
        the design's kind or rule fixes, bounds out of the valid range or in the wrong order.
    """
    given = dict(bounds or {})
    unknown = sorted(set(given) - set(VARIABLE_NAMES))
    if unknown:
        raise DesignError("bounds", unknown[0], f"not a design variable; expected one of {', '.join(VARIABLE_NAMES)}")
    for fixed in fixed_variables(design):
        if fixed in given:
            raise DesignError(f"bounds.{fixed}", given[fixed],
                              f"fixed on this design (a {design.machine.kind} machine under release rule "
                              f"{design.machine.release_rule!r}): it takes no bounds")
    chosen = default_bounds(design, factor, angle_window) | given
    m = design.machine
    variables = tuple(Variable(n, *(chosen[n] if n in chosen else (value, value)))
                      for n, value in zip(VARIABLE_NAMES, start_values(design), strict=True))
    if m.kind != "hinged":
        variables = tuple(Variable(v.name, 0.0, 0.0) if v.name == "counterweight_link" else v for v in variables)
    axle = (design.losses.axle_radius or 0.0) if axle_radius is None else axle_radius
    return Problem(
        name=f"around-{design.name}" if name is None else name, variables=variables,
        max_footprint=footprint(m, design.base.trough_height) if max_footprint is None else max_footprint,
        max_height=m.pivot_height if max_height is None else max_height,
        axle_radius=axle, counterweight_mass=m.counterweight_mass, counterweight_density=None,
        counterweight_own_inertia=m.counterweight_inertia,
        counterweight_clearance_radius=clearance_radius(design, axle), arm=ScaledArm.of(m),
        projectile=design.projectile, environment=design.environment, release_rule=m.release_rule,
        base=design.base, losses=design.losses, load_limits=tuple(load_limits), minimise=minimise,
        min_range=min_range, kind=m.kind, sling_mass=m.sling_mass, pouch_mass=m.pouch_mass)


def clearance_radius(design: Design, axle_radius: float) -> float:
    """The counterweight's radius for the axle clearance around ``design``, m: the solid sphere's of its
    inertia, ``sqrt(5 I / (2 m))``, but no more than the design's own machine clears at rest (a box or a
    bucket of that inertia is not a sphere: the machine as built clears its axle, so its start is
    feasible)."""
    m = design.machine
    sphere = math.sqrt(2.5 * m.counterweight_inertia / m.counterweight_mass)
    room = axle_distance(m, design.base.trough_height) - axle_radius
    return max(0.0, min(sphere, room))


def adopted(design: Design, problem: Problem, values: np.ndarray) -> Design:
    """``design`` with the optimum at ``values`` (the problem's vector) in it: only
    ``OPTIMISED_FIELDS`` change, every other field of ``design`` is kept as it was."""
    optimum = design_at(problem, values).machine
    fields = {name: getattr(optimum, name) for name in OPTIMISED_FIELDS
              if not (name == "release_angle" and design.machine.release_rule == "ideal")}
    return dataclasses.replace(design, machine=dataclasses.replace(design.machine, **fields))
