"""The optimisation problem: design variables and bounds, fixed values, constraint limits, TOML in.

A problem says what may vary (the paper's six design variables, section II.A
and Table II), what is fixed (counterweight, projectile, arm material, air,
release rule) and how large the machine may be (``analytic.optimise.constraints``).
The built-in default is the paper's (``data/paper_problem.toml``).

Inside, everything is SI with angles in radians. In files, lengths are in
metres and angles in degrees, as in design files (``analytic.design``).
"""

from __future__ import annotations

import dataclasses
import math
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from analytic.design import (RELEASE_RULES, BeamArm, Design, DesignError, Environment, Machine,
                             Projectile, paper_geometry)
from analytic.design_file import reject_unknown_keys

#: The design variables in the paper's order (Table II), the order of every vector here.
VARIABLE_NAMES = ("arm_short", "counterweight_link", "clearance", "sling_length",
                  "starting_angle", "release_angle")
#: Variables that are angles (degrees in files and tables, radians inside).
ANGLE_VARIABLES = ("starting_angle", "release_angle")

_TABLES = ("name", "variables", "constraints", "counterweight", "arm_beam", "projectile",
           "environment", "release")


@dataclass(frozen=True)
class Variable:
    """One design variable and its bounds (m or rad); ``lower == upper`` fixes it."""

    name: str
    lower: float
    upper: float

    def __post_init__(self) -> None:
        for bound in ("lower", "upper"):
            value = getattr(self, bound)
            if not math.isfinite(value):
                raise DesignError(f"variables.{self.name}.{bound}", value, "must be finite")
        if self.lower > self.upper:
            raise DesignError(f"variables.{self.name}", (self.lower, self.upper),
                              "lower bound is above upper bound")

    @property
    def fixed(self) -> bool:
        return self.lower == self.upper


@dataclass(frozen=True)
class Problem:
    """Everything that defines the optimisation except the method (SI, radians).

    Attributes
    ----------
    name : label used in reports and output files.
    variables : the six ``Variable`` in ``VARIABLE_NAMES`` order.
    max_footprint : m, limit on the machine's horizontal span at rest.
    max_height : m, limit on the pivot height.
    axle_radius : m, radius of the axle the counterweight must clear at rest.
    counterweight_mass : kg.
    counterweight_density : kg/m^3; the counterweight is a solid sphere of it.
    arm : the beam the arm is cut from.
    projectile, environment : as in a design.
    release_rule : ``"velocity"`` or ``"sling"`` (``analytic.design.release_function``).
    """

    name: str
    variables: tuple[Variable, ...]
    max_footprint: float
    max_height: float
    axle_radius: float
    counterweight_mass: float
    counterweight_density: float
    arm: BeamArm
    projectile: Projectile
    environment: Environment
    release_rule: str = "velocity"

    def __post_init__(self) -> None:
        if tuple(v.name for v in self.variables) != VARIABLE_NAMES:
            raise DesignError("variables", [v.name for v in self.variables],
                              f"must be exactly {', '.join(VARIABLE_NAMES)} in that order")
        for name, key in (("max_footprint", "constraints.max_footprint"),
                          ("max_height", "constraints.max_height"),
                          ("counterweight_mass", "counterweight.mass"),
                          ("counterweight_density", "counterweight.density")):
            if not getattr(self, name) > 0.0:
                raise DesignError(key, getattr(self, name), "must be positive")
        if not self.axle_radius >= 0.0:
            raise DesignError("constraints.axle_radius", self.axle_radius, "must not be negative")
        if self.release_rule not in RELEASE_RULES:
            raise DesignError("release.rule", self.release_rule,
                              f"must be one of {', '.join(RELEASE_RULES)}")
        limits = {"arm_short": (0.0, math.inf), "counterweight_link": (0.0, math.inf),
                  "clearance": (0.0, math.inf), "sling_length": (0.0, math.inf),
                  "starting_angle": (0.0, math.pi / 2), "release_angle": (-math.pi / 2, math.pi / 2)}
        for variable in self.variables:
            low, high = limits[variable.name]
            if not (low < variable.lower and variable.upper < high):
                raise DesignError(f"variables.{variable.name}", (variable.lower, variable.upper),
                                  f"bounds must lie strictly between {low:g} and {high:g} "
                                  f"({'rad' if variable.name in ANGLE_VARIABLES else 'm'})")

    @property
    def lower(self) -> np.ndarray:
        """Lower bounds, shape (6,)."""
        return np.array([v.lower for v in self.variables])

    @property
    def upper(self) -> np.ndarray:
        """Upper bounds, shape (6,)."""
        return np.array([v.upper for v in self.variables])

    @property
    def free(self) -> np.ndarray:
        """Indices of the variables that are not fixed, shape (n_free,)."""
        return np.array([i for i, v in enumerate(self.variables) if not v.fixed], dtype=int)

    @property
    def counterweight_radius(self) -> float:
        """Radius of the solid-sphere counterweight, m: ``(3 m / (4 pi rho))^(1/3)``."""
        return (3.0 * self.counterweight_mass / (4.0 * math.pi * self.counterweight_density)) ** (1 / 3)

    @property
    def counterweight_inertia(self) -> float:
        """Moment of inertia of the solid sphere about its centre, kg m^2: ``2/5 m r^2``."""
        return 0.4 * self.counterweight_mass * self.counterweight_radius**2


def design_at(problem: Problem, values: np.ndarray, name: str = "optimum") -> Design:
    """The design for a full vector of the six design variables.

    Parameters
    ----------
    values : (6,) in ``VARIABLE_NAMES`` order, m and rad. Bounds are not
        enforced (finite-difference steps may cross them); buildability is.

    Raises
    ------
    DesignError
        if the combination cannot be built.
    """
    arm_short, link, clearance, sling, starting_angle, release_angle = (float(v) for v in values)
    pivot_height, arm_long = paper_geometry(arm_short, link, clearance, starting_angle)
    arm_mass, arm_cg, arm_inertia = problem.arm.properties(arm_long, arm_short)
    machine = Machine(pivot_height=pivot_height, arm_long=arm_long, arm_short=arm_short,
                      arm_mass=arm_mass, arm_cg=arm_cg, arm_inertia=arm_inertia,
                      counterweight_mass=problem.counterweight_mass, counterweight_link=link,
                      counterweight_inertia=problem.counterweight_inertia, sling_length=sling,
                      release_angle=release_angle, release_rule=problem.release_rule)
    return Design(machine, problem.projectile, problem.environment, name=name)


def variables_of(machine: Machine) -> np.ndarray:
    """The six design variables of an existing machine, shape (6,), m and rad (inverse of ``design_at``).

    ``clearance = pivot_height - arm_short - counterweight_link`` and the
    starting angle is ``asin(pivot_height / arm_long)`` (``Machine.starting_angle``).
    """
    return np.array([machine.arm_short, machine.counterweight_link,
                     machine.pivot_height - machine.arm_short - machine.counterweight_link,
                     machine.sling_length, machine.starting_angle, machine.release_angle])


def from_unit(problem: Problem, unit: np.ndarray) -> np.ndarray:
    """The full design vector, shape (6,), m and rad, from the free variables scaled to [0, 1].

    The optimiser works on ``unit`` (shape (n_free,)), 0 at each lower bound and 1
    at the upper, so that every direction has the same scale; fixed variables
    keep their value.
    """
    free = problem.free
    values = problem.lower.copy()
    values[free] += np.asarray(unit, dtype=float) * (problem.upper[free] - problem.lower[free])
    return values


def to_unit(problem: Problem, values: np.ndarray) -> np.ndarray:
    """The free variables of a full design vector scaled to [0, 1], shape (n_free,) (inverse of ``from_unit``)."""
    free = problem.free
    return (np.asarray(values, dtype=float)[free] - problem.lower[free]) / (problem.upper[free] - problem.lower[free])


# --------------------------------------------------------------------------- #
# TOML
# --------------------------------------------------------------------------- #

def problem_from_dict(data: dict[str, Any], name: str = "problem") -> Problem:
    """Build a problem from the TOML layout (see ``data/paper_problem.toml``).

    Each ``[variables]`` entry is ``{ lower = .., upper = .. }`` or ``{ value = .. }``
    (fixed); lengths in m, angles in degrees.
    """
    reject_unknown_keys("problem", data, _TABLES)
    tables = {}
    for table in _TABLES[1:]:
        if table in ("environment", "release"):
            tables[table] = data.get(table, {})
        elif not isinstance(data.get(table), dict):
            raise DesignError(f"[{table}]", data.get(table), "required table is missing")
        else:
            tables[table] = data[table]

    reject_unknown_keys("variables", tables["variables"], VARIABLE_NAMES)
    variables = []
    for key in VARIABLE_NAMES:
        entry = _table(f"variables.{key}", tables["variables"].get(key))
        if "value" in entry:
            reject_unknown_keys(f"variables.{key}", entry, ("value",))
            lower = upper = _number(f"variables.{key}.value", entry["value"])
        else:
            reject_unknown_keys(f"variables.{key}", entry, ("lower", "upper"))
            lower = _number(f"variables.{key}.lower", entry.get("lower"))
            upper = _number(f"variables.{key}.upper", entry.get("upper"))
        if key in ANGLE_VARIABLES:
            lower, upper = math.radians(lower), math.radians(upper)
        variables.append(Variable(key, lower, upper))

    constraints = tables["constraints"]
    reject_unknown_keys("constraints", constraints, ("max_footprint", "max_height", "axle_radius"))
    counterweight = tables["counterweight"]
    reject_unknown_keys("counterweight", counterweight, ("mass", "density"))
    beam = tables["arm_beam"]
    reject_unknown_keys("arm_beam", beam, ("width", "depth", "density"))
    release = tables["release"]
    reject_unknown_keys("release", release, ("rule",))
    reject_unknown_keys("projectile", tables["projectile"], _field_names(Projectile))
    reject_unknown_keys("environment", tables["environment"], _field_names(Environment))
    return Problem(
        name=str(data.get("name", name)),
        variables=tuple(variables),
        max_footprint=_number("constraints.max_footprint", constraints.get("max_footprint")),
        max_height=_number("constraints.max_height", constraints.get("max_height")),
        axle_radius=_number("constraints.axle_radius", constraints.get("axle_radius")),
        counterweight_mass=_number("counterweight.mass", counterweight.get("mass")),
        counterweight_density=_number("counterweight.density", counterweight.get("density")),
        arm=BeamArm(**{k: _number(f"arm_beam.{k}", beam.get(k)) for k in ("width", "depth", "density")}),
        projectile=Projectile(**{k: _number(f"projectile.{k}", v) if k != "drag" else v
                                 for k, v in tables["projectile"].items()}),
        environment=Environment(**{k: _number(f"environment.{k}", v)
                                   for k, v in tables["environment"].items()}),
        release_rule=str(release.get("rule", "velocity")),
    )


def load_problem(path: str | Path) -> Problem:
    """Read a problem TOML file; errors name the file or the field, the value and the reason."""
    path = Path(path)
    try:
        with path.open("rb") as handle:
            data = tomllib.load(handle)
    except tomllib.TOMLDecodeError as error:
        raise DesignError(str(path), "(file)", f"not valid TOML: {error}") from None
    except OSError as error:
        raise DesignError(str(path), "(file)", f"cannot be read: {error.strerror}") from None
    return problem_from_dict(data, name=path.stem)


def default_problem() -> Problem:
    """The built-in default: the paper's problem (``data/paper_problem.toml``)."""
    return load_problem(Path(__file__).parents[1] / "data" / "paper_problem.toml")


def _field_names(cls) -> tuple[str, ...]:
    return tuple(f.name for f in dataclasses.fields(cls))


def _table(name: str, value: Any) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise DesignError(name, value, "required table is missing")
    return value


def _number(name: str, value: Any) -> float:
    if value is None:
        raise DesignError(name, None, "required value is missing")
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise DesignError(name, value, "must be a number")
    return float(value)


