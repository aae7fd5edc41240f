"""The trebuchet design: validated inputs, derived start geometry, TOML in and out.

This module is the contract both models read (``engine_model`` may import it and
``analytic.aero``, nothing else of ``analytic``). Everything inside is SI with
angles in radians; degrees exist only in TOML files (see ``design_from_dict``).

Geometry and angle conventions (the same symbols as ``docs/derivation.md``):

* origin at the pivot, x forward (the direction of the throw), y up; the base
  is the line ``y = -pivot_height``;
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

import dataclasses
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from analytic import limits
from analytic.aero import DRAG_MODELS
from analytic.geometry import RELEASE_RULES


#: Largest |release angle| for the ``velocity`` rule: the velocity must point forward.
MAX_VELOCITY_RELEASE_ANGLE = math.radians(90.0)
#: Largest |release angle| for the ``sling`` rule (sling-to-arm angle).
MAX_SLING_RELEASE_ANGLE = math.radians(180.0)


class DesignError(ValueError):
    """A design that cannot be built: names the field, its value and the reason."""

    def __init__(self, field_name: str, value: Any, reason: str):
        self.field = field_name
        self.value = value
        self.reason = reason
        super().__init__(f"{field_name} = {value!r}: {reason}")


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
        ``analytic.geometry.sling_arm_angle``).
    release_rule : ``"velocity"`` or ``"sling"``.
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
    release_angle: float
    release_rule: str = "velocity"

    def __post_init__(self) -> None:
        for name in ("pivot_height", "arm_long", "arm_short", "arm_mass",
                     "counterweight_mass", "counterweight_link", "sling_length"):
            _require_positive(name, getattr(self, name))
        for name in ("arm_inertia", "counterweight_inertia"):
            _require_non_negative(name, getattr(self, name))
        _require_finite("arm_cg", self.arm_cg)
        _require_finite("release_angle", self.release_angle)
        if self.release_rule not in RELEASE_RULES:
            raise DesignError("release_rule", self.release_rule,
                              f"must be one of {', '.join(RELEASE_RULES)}")
        if not -self.arm_short <= self.arm_cg <= self.arm_long:
            raise DesignError("arm_cg", self.arm_cg,
                              f"the arm's centre of mass must lie on the arm, between "
                              f"-arm_short ({-self.arm_short:g} m) and arm_long ({self.arm_long:g} m)")
        if self.arm_long <= self.pivot_height:
            raise DesignError("arm_long", self.arm_long,
                              f"the long arm cannot reach the base: it must be longer than "
                              f"pivot_height ({self.pivot_height:g} m)")
        if self.arm_short + self.counterweight_link >= self.pivot_height:
            raise DesignError("counterweight_link", self.counterweight_link,
                              f"the counterweight would strike the base: arm_short + "
                              f"counterweight_link ({self.arm_short + self.counterweight_link:g} m) "
                              f"must be less than pivot_height ({self.pivot_height:g} m)")
        limit = (MAX_VELOCITY_RELEASE_ANGLE if self.release_rule == "velocity"
                 else MAX_SLING_RELEASE_ANGLE)
        if not -limit < self.release_angle < limit:
            raise DesignError("release_angle", f"{math.degrees(self.release_angle):g} deg",
                              f"with release_rule {self.release_rule!r} it must lie strictly "
                              f"between {-math.degrees(limit):g} and {math.degrees(limit):g} deg")

    @property
    def starting_angle(self) -> float:
        """Angle of the long arm below the horizontal at rest, rad (the paper's theta_0)."""
        return math.asin(self.pivot_height / self.arm_long)


@dataclass(frozen=True)
class Projectile:
    """A spherical projectile (point mass in the dynamics, a sphere for drag)."""

    mass: float
    diameter: float
    drag: str = "none"
    drag_coefficient: float | None = None

    def __post_init__(self) -> None:
        _require_positive("mass", self.mass)
        _require_positive("diameter", self.diameter)
        if self.drag not in DRAG_MODELS:
            raise DesignError("drag", self.drag, f"must be one of {', '.join(DRAG_MODELS)}")
        if self.drag == "constant":
            if self.drag_coefficient is None:
                raise DesignError("drag_coefficient", None, 'required with drag = "constant"')
            _require_positive("drag_coefficient", self.drag_coefficient)
        elif self.drag_coefficient is not None:
            raise DesignError("drag_coefficient", self.drag_coefficient,
                              f'only used with drag = "constant", not {self.drag!r}; remove it')

    @property
    def frontal_area(self) -> float:
        """Cross-sectional area pi d^2 / 4, m^2."""
        return math.pi * self.diameter**2 / 4.0


@dataclass(frozen=True)
class Environment:
    """Gravity and air; the defaults are standard sea-level values."""

    gravity: float = 9.81
    air_density: float = 1.225
    air_viscosity: float = 1.81e-5
    wind_speed: float = 0.0

    def __post_init__(self) -> None:
        _require_positive("gravity", self.gravity)
        _require_non_negative("air_density", self.air_density)
        _require_positive("air_viscosity", self.air_viscosity)
        _require_finite("wind_speed", self.wind_speed)


@dataclass(frozen=True)
class Design:
    """A whole shot's inputs: machine, projectile and environment."""

    machine: Machine
    projectile: Projectile
    environment: Environment = field(default_factory=Environment)
    name: str = "design"


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
    _require_positive("clearance", clearance)
    if not 0.0 < starting_angle < math.pi / 2:
        raise DesignError("starting_angle", f"{math.degrees(starting_angle):g} deg",
                          "must lie strictly between 0 and 90 deg")
    pivot_height = arm_short + counterweight_link + clearance
    return pivot_height, pivot_height / math.sin(starting_angle)


@dataclass(frozen=True)
class BeamArm:
    """An arm cut from a uniform rectangular beam (depth measured in the swing plane)."""

    width: float
    depth: float
    density: float

    def __post_init__(self) -> None:
        for name in ("width", "depth", "density"):
            _require_positive(name, getattr(self, name))

    def properties(self, arm_long: float, arm_short: float) -> tuple[float, float, float]:
        """Mass (kg), centre-of-mass distance toward the long end (m), inertia about it (kg m^2).

        The beam runs from the short tip to the long tip, length ``L = arm_long + arm_short``;
        its in-plane inertia about its centre is ``m (L^2 + depth^2) / 12``.
        """
        length = arm_long + arm_short
        mass = self.density * self.width * self.depth * length
        return mass, (arm_long - arm_short) / 2.0, mass * (length**2 + self.depth**2) / 12.0


# --------------------------------------------------------------------------- #
# Start state
# --------------------------------------------------------------------------- #

def initial_angles(machine: Machine) -> np.ndarray:
    """Generalised coordinates at rest before firing, shape (3,): [theta, phi, psi], rad.

    The long-arm tip rests on the base (``arm_long cos theta = -h``), the
    counterweight hangs plumb (``theta + phi = 0``) and the sling lies along the
    base pointing forward (``theta + psi = -pi/2``).
    """
    theta = math.acos(-machine.pivot_height / machine.arm_long)
    return np.array([theta, -theta, -math.pi / 2 - theta])


def largest_length(machine: Machine) -> float:
    """``arm_long + sling_length + arm_short + counterweight_link``, m: the machine's largest
    length, which sets its time and speed scales."""
    m = machine
    return m.arm_long + m.sling_length + m.arm_short + m.counterweight_link


def swing_time_limit(machine: Machine, gravity: float) -> float:
    """Longest time allowed from firing to release, s (``analytic.limits.swing_time_limit``)."""
    return limits.swing_time_limit(largest_length(machine), gravity)


# --------------------------------------------------------------------------- #
# TOML
# --------------------------------------------------------------------------- #

_MACHINE_KEYS = tuple(f.name for f in dataclasses.fields(Machine))
_PROJECTILE_KEYS = tuple(f.name for f in dataclasses.fields(Projectile))
_ENVIRONMENT_KEYS = tuple(f.name for f in dataclasses.fields(Environment))
_ANGLE_KEYS = ("release_angle", "starting_angle")  # degrees in files
_ARM_KEYS = ("arm_mass", "arm_cg", "arm_inertia")
_PAPER_KEYS = ("clearance", "starting_angle")


def design_from_dict(data: dict[str, Any], name: str = "design") -> Design:
    """Build a design from the TOML layout (SI units, angles in degrees).

    Besides the direct ``[machine]`` keys, two alternative forms are accepted:

    * the paper's: ``clearance`` and ``starting_angle`` (deg) instead of
      ``pivot_height`` and ``arm_long`` (see ``paper_geometry``);
    * ``[machine.arm_beam]`` with ``width``, ``depth``, ``density`` instead of
      ``arm_mass``, ``arm_cg``, ``arm_inertia`` (see ``BeamArm``).
    """
    reject_unknown_keys("design", data, ("machine", "projectile", "environment", "name"))
    for table in ("machine", "projectile"):
        if not isinstance(data.get(table), dict):
            raise DesignError(f"[{table}]", data.get(table), "required table is missing")
    machine_data = dict(data["machine"])
    beam_data = machine_data.pop("arm_beam", None)
    reject_unknown_keys("machine", machine_data, _MACHINE_KEYS + _PAPER_KEYS)
    values = {key: _number_or_text(f"machine.{key}", value) for key, value in machine_data.items()}
    for key in _ANGLE_KEYS:
        if key in values:
            values[key] = math.radians(values[key])

    if any(key in values for key in _PAPER_KEYS):
        for key in ("pivot_height", "arm_long"):
            if key in values:
                raise DesignError(f"machine.{key}", values[key],
                                  "give either pivot_height and arm_long, or the paper's "
                                  "clearance and starting_angle, not both")
        for key in _PAPER_KEYS + ("arm_short", "counterweight_link"):
            _require_present("machine", key, values)
        values["pivot_height"], values["arm_long"] = paper_geometry(
            values["arm_short"], values["counterweight_link"],
            values.pop("clearance"), values.pop("starting_angle"))

    if beam_data is not None:
        if not isinstance(beam_data, dict):
            raise DesignError("machine.arm_beam", beam_data, "must be a table")
        for key in _ARM_KEYS:
            if key in values:
                raise DesignError(f"machine.{key}", values[key],
                                  "give either arm_mass, arm_cg and arm_inertia, or [machine.arm_beam], not both")
        reject_unknown_keys("machine.arm_beam", beam_data, ("width", "depth", "density"))
        for key in ("width", "depth", "density"):
            _require_present("machine.arm_beam", key, beam_data)
        for key in ("pivot_height", "arm_long", "arm_short"):
            _require_present("machine", key, values)
        beam = BeamArm(**{k: _number_or_text(f"machine.arm_beam.{k}", v) for k, v in beam_data.items()})
        values["arm_mass"], values["arm_cg"], values["arm_inertia"] = beam.properties(
            values["arm_long"], values["arm_short"])

    for key in _MACHINE_KEYS:
        if key != "release_rule":
            _require_present("machine", key, values)
    machine = Machine(**values)

    reject_unknown_keys("projectile", data["projectile"], _PROJECTILE_KEYS)
    for key in ("mass", "diameter", "drag"):
        _require_present("projectile", key, data["projectile"])
    projectile = Projectile(**{k: _number_or_text(f"projectile.{k}", v)
                               for k, v in data["projectile"].items()})

    env_data = data.get("environment", {})
    reject_unknown_keys("environment", env_data, _ENVIRONMENT_KEYS)
    environment = Environment(**{k: _number_or_text(f"environment.{k}", v) for k, v in env_data.items()})
    return Design(machine, projectile, environment, name=str(data.get("name", name)))


def design_to_dict(design: Design) -> dict[str, Any]:
    """The canonical TOML layout of a design (direct form, angles in degrees)."""
    machine = dataclasses.asdict(design.machine)
    machine["release_angle"] = math.degrees(machine["release_angle"])
    projectile = {k: v for k, v in dataclasses.asdict(design.projectile).items() if v is not None}
    return {"name": design.name, "machine": machine, "projectile": projectile,
            "environment": dataclasses.asdict(design.environment)}


def load_design(path: str | Path) -> Design:
    """Read a design TOML file; errors name the file, the field, the value and the reason."""
    path = Path(path)
    try:
        with path.open("rb") as handle:
            data = tomllib.load(handle)
    except tomllib.TOMLDecodeError as error:
        raise DesignError("file", str(path), f"not valid TOML: {error}") from None
    except OSError as error:
        raise DesignError("file", str(path), f"cannot be read: {error.strerror}") from None
    return design_from_dict(data, name=path.stem)


def dumps_design(design: Design) -> str:
    """The design as TOML text (direct form)."""
    import tomli_w

    return tomli_w.dumps(design_to_dict(design))


def save_design(design: Design, path: str | Path) -> None:
    """Write a design as TOML that ``load_design`` reads back to an equal design."""
    Path(path).write_text(dumps_design(design))


def default_design() -> Design:
    """The built-in default: the paper's Table III optimum (see ``data/paper_table3.toml``)."""
    return load_design(Path(__file__).with_name("data") / "paper_table3.toml")


# --------------------------------------------------------------------------- #
# Validation helpers
# --------------------------------------------------------------------------- #

def _require_finite(name: str, value: Any) -> None:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise DesignError(name, value, "must be a number")
    if not math.isfinite(value):
        raise DesignError(name, value, "must be finite")


def _require_positive(name: str, value: Any) -> None:
    _require_finite(name, value)
    if value <= 0:
        raise DesignError(name, value, "must be positive")


def _require_non_negative(name: str, value: Any) -> None:
    _require_finite(name, value)
    if value < 0:
        raise DesignError(name, value, "must not be negative")


def _require_present(table: str, key: str, values: dict[str, Any]) -> None:
    if key not in values:
        raise DesignError(f"{table}.{key}", None, "required value is missing")


def reject_unknown_keys(table: str, values: dict[str, Any], allowed: tuple[str, ...]) -> None:
    """Raise ``DesignError`` naming the first key of ``values`` not in ``allowed`` (typo guard for files)."""
    for key in values:
        if key not in allowed:
            raise DesignError(f"{table}.{key}", values[key],
                              f"unknown key; expected one of {', '.join(allowed)}")


def _number_or_text(name: str, value: Any) -> Any:
    if isinstance(value, bool):
        raise DesignError(name, value, "must be a number")
    if isinstance(value, int):
        return float(value)
    return value
