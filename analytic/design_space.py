"""The design space: design variables and their bounds, fixed values, size limits, the problem file.

The optimiser searches it, and the sweeps, the cross-check and the
benchmarks draw designs from it. A problem says what may vary (the paper's six design variables, section II.A
and Table II), what is fixed (counterweight, projectile, arm material, air,
release rule) and how large the machine may be (``analytic.optimise.constraints``).
The built-in default is the paper's (``data/paper_problem.toml``).

Inside, everything is SI with angles in radians. In files, lengths are in
metres and angles in degrees, as in design files; the tables a problem file
shares with them (``[projectile]``, ``[environment]``, the beam) are read by
the same functions (``analytic.design_file``), and every error has the same
form, ``table.field = value: reason``.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Sequence

import numpy as np

from analytic.design import (RELEASE_RULES, Base, BeamArm, Design, DesignError, Environment, Losses, Machine,
                             Projectile, paper_geometry, require_choice, require_kind, require_non_negative,
                             require_number, require_positive)
from analytic.design_file import (base_from_dict, beam_arm_from_dict, environment_from_dict, losses_from_dict,
                                  projectile_from_dict,
                                  read_toml, read_values, reject_unknown_keys, require_table)

#: The design variables in the paper's order (Table II), the order of every vector here.
VARIABLE_NAMES = ("arm_short", "counterweight_link", "clearance", "sling_length",
                  "starting_angle", "release_angle")
#: Variables that are angles (degrees in files and tables, radians inside).
ANGLE_VARIABLES = ("starting_angle", "release_angle")
#: Why a problem under the ideal rule may not bound the release angle.
IDEAL_RELEASE_NOT_A_VARIABLE = ("release.rule 'ideal' finds each design's release itself (its longest throw), "
                                "so the release angle is no variable: leave release_angle out of [variables]")
#: A seventh variable, present only when a rolling frame's mass is free between bounds, kg.
FRAME_MASS = "frame_mass"

_TABLES = ("name", "machine", "variables", "constraints", "counterweight", "arm_beam", "projectile",
           "environment", "release", "base", "loads", "losses")
_CONSTRAINT_KEYS = ("max_footprint", "max_height", "axle_radius")
#: What ``[constraints]`` may also limit: the arm's least safety factor (``Problem.min_arm_safety_factor``)
#: and the projectile's peak acceleration (m/s^2, as ``[loads] max_projectile_acceleration``: one or the other).
_BREAKING_KEYS = ("min_arm_safety_factor", "max_projectile_acceleration")
#: The ``[machine]`` table's fixed parts of every design, kg (besides its ``kind``).
_MACHINE_PARTS = ("sling_mass", "pouch_mass")
#: The loads a problem may limit or minimise (``[loads]``): the name in the file -> the
#: ``Shot`` peak it bounds (N, N, N, m/s^2, N m).
LOADS = {"axle_load": "peak_axle_load", "hinge_load": "peak_hinge_load",
         "sling_tension": "peak_sling_tension", "projectile_acceleration": "peak_projectile_acceleration",
         "arm_bending_moment": "peak_arm_bending_moment"}
_LOAD_KEYS = tuple(f"max_{name}" for name in LOADS) + ("min_range",)


@dataclass(frozen=True)
class Variable:
    """One design variable and its bounds (m or rad); ``lower == upper`` fixes it."""

    name: str
    lower: float
    upper: float

    def __post_init__(self) -> None:
        for bound in ("lower", "upper"):
            require_number(f"variables.{self.name}.{bound}", getattr(self, bound))
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
    variables : the six ``Variable`` in ``VARIABLE_NAMES`` order, and a seventh,
        ``frame_mass`` (kg), when a rolling frame's mass is free between bounds.
    max_footprint : m, limit on the machine's horizontal span at rest.
    max_height : m, limit on the pivot height.
    axle_radius : m, radius of the axle the counterweight must clear at rest.
    counterweight_mass : kg.
    counterweight_density : kg/m^3; the counterweight is a solid sphere of it. None with
        ``counterweight_own_inertia``.
    arm : the beam the arm is cut from (``BeamArm``), or any arm whose ``properties(arm_long,
        arm_short)`` give its mass, centre and inertia (``analytic.optimise.around.ScaledArm``).
    projectile, environment : as in a design; the environment's ``target_height`` is the level every
        design's range is measured at (``short_of_target`` below it scores as a failure).
    release_rule : ``"velocity"``, ``"sling"`` (``analytic.geometry.release_value``) or ``"ideal"``
        (``analytic.ideal``: each design releases at its longest throw, so the release angle is no
        variable: ``release_angle`` is fixed, its value ignored, and designs have none).
    base : the frame every design stands on (``analytic.design.Base``); with a
        ``frame_mass`` variable, its mass is the variable's. Its ``trough_height`` raises every
        design's trough; the variables still give the arm's length (``paper_geometry``: the length
        that reaches the base at ``starting_angle``), and the arm rests on the trough, shallower
        (``analytic.optimise.constraints.rest_points``).
    losses : the friction every design has (``analytic.design.Losses``, ``[losses]`` as in
        design files); the ideal machine by default.
    load_limits : ``(load, limit)`` pairs, a load of ``LOADS`` whose peak through
        stages 1-2 must stay at or below the limit (N; m/s^2 for the projectile's
        acceleration).
    minimise : a load of ``LOADS`` to minimise instead of maximising the range, with the
        range held at ``min_range`` (m) or more: a gentler machine for the same throw.
    min_range : m, with ``minimise``.
    kind : the machine every design is (``analytic.design.KINDS``): ``"hinged"`` (the
        paper's), or ``"fixed"`` or ``"floating-arm"``, whose counterweight is rigid on the
        arm: their ``counterweight_link`` variable is fixed at 0 (a file may leave it out).
    sling_mass, pouch_mass : kg, the sling's and the pouch's mass of every design (``[machine]``,
        as ``machine.sling_mass`` and ``pouch_mass`` of a design file; 0, massless, by default).
    counterweight_own_inertia : kg m^2, the counterweight's inertia about its centre as a design gives
        it (a problem around a design, ``analytic.optimise.around``), instead of a sphere of
        ``counterweight_density``'s; its radius for the axle clearance is then the solid sphere's of
        that inertia, ``sqrt(5 I / (2 m))``. None (the default): the sphere of the density.
    counterweight_clearance_radius : m, the counterweight's radius for the axle clearance where a design
        gives it (``analytic.optimise.around``: no larger than its own machine clears), instead of
        a sphere's; None (the default): the sphere's.
    min_arm_safety_factor : the least safety factor every design's arm must keep against its
        strength (``analytic.result.Shot.arm_safety_factor``; the arm needs a material or a
        strength), or None: no such limit.
    """

    name: str
    variables: tuple[Variable, ...]
    max_footprint: float
    max_height: float
    axle_radius: float
    counterweight_mass: float
    counterweight_density: float | None
    arm: BeamArm
    projectile: Projectile
    environment: Environment
    release_rule: str = "velocity"
    base: Base = Base()
    losses: Losses = Losses()
    load_limits: tuple[tuple[str, float], ...] = ()
    minimise: str | None = None
    min_range: float | None = None
    kind: str = "hinged"
    sling_mass: float = 0.0
    pouch_mass: float = 0.0
    counterweight_own_inertia: float | None = None
    min_arm_safety_factor: float | None = None
    counterweight_clearance_radius: float | None = None

    def __post_init__(self) -> None:
        require_kind("machine.kind", self.kind)
        if self.counterweight_own_inertia is not None:
            require_non_negative("machine.counterweight_inertia", self.counterweight_own_inertia)
        elif self.counterweight_density is None:
            raise DesignError("counterweight.density", None, "required value is missing")
        if self.min_arm_safety_factor is not None:
            require_positive("constraints.min_arm_safety_factor", self.min_arm_safety_factor)
            if not self.arm.rated:
                raise DesignError("constraints.min_arm_safety_factor", self.min_arm_safety_factor,
                                  "needs the arm's strength: give [arm_beam] a material or a strength (Pa)")
        for name in ("sling_mass", "pouch_mass"):
            require_non_negative(f"machine.{name}", getattr(self, name))
        for load, limit in self.load_limits:
            require_choice("loads", load, tuple(LOADS))
            require_positive(f"loads.max_{load}", limit)
        if self.minimise is not None:
            require_choice("loads.minimise", self.minimise, tuple(LOADS))
            if self.min_range is None:
                raise DesignError("loads.min_range", None, "required with loads.minimise: the range to keep")
            require_positive("loads.min_range", self.min_range)
        elif self.min_range is not None:
            raise DesignError("loads.min_range", self.min_range, "only used with loads.minimise; give both")
        names = tuple(v.name for v in self.variables)
        if names not in (VARIABLE_NAMES, VARIABLE_NAMES + (FRAME_MASS,)):
            raise DesignError("variables", list(names),
                              f"must be exactly {', '.join(VARIABLE_NAMES)} in that order "
                              f"(and {FRAME_MASS} last for a rolling frame of free mass)")
        if FRAME_MASS in names and not self.base.rolling:
            raise DesignError("base.mass", (self.variables[-1].lower, self.variables[-1].upper),
                              'bounds on the frame mass need mobility = "rolling"')
        if not isinstance(self.name, str):
            raise DesignError("name", self.name, "must be text")
        for name, key in (("max_footprint", "constraints.max_footprint"),
                          ("max_height", "constraints.max_height"),
                          ("counterweight_mass", "counterweight.mass"),
                          ("counterweight_density", "counterweight.density")):
            if getattr(self, name) is not None or name != "counterweight_density":
                require_positive(key, getattr(self, name))
        require_non_negative("constraints.axle_radius", self.axle_radius)
        require_choice("release.rule", self.release_rule, RELEASE_RULES)
        limits = {"arm_short": (0.0, math.inf), "counterweight_link": (0.0, math.inf),
                  "clearance": (0.0, math.inf), "sling_length": (0.0, math.inf),
                  "starting_angle": (0.0, math.pi / 2), "release_angle": (-math.pi / 2, math.pi / 2),
                  FRAME_MASS: (0.0, math.inf)}
        for variable in self.variables:
            if variable.name == "counterweight_link" and self.kind != "hinged":
                if (variable.lower, variable.upper) != (0.0, 0.0):
                    raise DesignError("variables.counterweight_link", (variable.lower, variable.upper),
                                      f"a {self.kind} machine has no link: its counterweight is rigid on "
                                      f"the arm; leave the variable out (or fix it at 0)")
                continue
            if variable.name == "release_angle" and self.release_rule == "ideal":
                if not variable.fixed:
                    raise DesignError("variables.release_angle", (variable.lower, variable.upper),
                                      IDEAL_RELEASE_NOT_A_VARIABLE)
                continue
            low, high = limits[variable.name]
            if not (low < variable.lower and variable.upper < high):
                unit = "rad" if variable.name in ANGLE_VARIABLES else ("kg" if variable.name == FRAME_MASS else "m")
                field = "base.mass" if variable.name == FRAME_MASS else f"variables.{variable.name}"
                raise DesignError(field, (variable.lower, variable.upper),
                                  f"bounds must lie strictly between {low:g} and {high:g} ({unit})")

    @property
    def outcome_constraints(self) -> tuple[str, ...]:
        """Names of the constraints on what a shot does (its loads, its range), in the order of
        ``analytic.optimise.evaluate.Evaluator.outcomes``; empty for the paper's problem."""
        names = tuple(f"peak {load.replace('_', ' ')} <= {limit:g}" for load, limit in self.load_limits)
        if self.min_arm_safety_factor is not None:
            names += (f"arm safety factor >= {self.min_arm_safety_factor:g}",)
        return names + ((f"range >= {self.min_range:g} m",) if self.minimise is not None else ())

    @property
    def names(self) -> tuple[str, ...]:
        """The variables' names, in order (6, or 7 with a free frame mass)."""
        return tuple(v.name for v in self.variables)

    def complete(self, values: np.ndarray) -> np.ndarray:
        """Six design variables completed to this problem's vector: with a free frame
        mass, the lightest frame allowed is appended (the lower bound)."""
        values = np.asarray(values, dtype=float)
        if len(values) == len(self.variables):
            return values
        return np.append(values, [v.lower for v in self.variables[len(values):]])

    @property
    def lower(self) -> np.ndarray:
        """Lower bounds, shape (n,): n = 6, or 7 with a free frame mass."""
        return np.array([v.lower for v in self.variables])

    @property
    def upper(self) -> np.ndarray:
        """Upper bounds, shape (n,)."""
        return np.array([v.upper for v in self.variables])

    @property
    def free(self) -> np.ndarray:
        """Indices of the variables that are not fixed, shape (n_free,)."""
        return np.array([i for i, v in enumerate(self.variables) if not v.fixed], dtype=int)

    @property
    def counterweight_radius(self) -> float:
        """Radius of the solid-sphere counterweight, m: ``(3 m / (4 pi rho))^(1/3)``, or with
        ``counterweight_own_inertia`` the solid sphere's of that inertia, ``sqrt(5 I / (2 m))``;
        ``counterweight_clearance_radius`` where given."""
        if self.counterweight_clearance_radius is not None:
            return self.counterweight_clearance_radius
        if self.counterweight_own_inertia is not None:
            return math.sqrt(2.5 * self.counterweight_own_inertia / self.counterweight_mass)
        return (3.0 * self.counterweight_mass / (4.0 * math.pi * self.counterweight_density)) ** (1 / 3)

    @property
    def counterweight_inertia(self) -> float:
        """Moment of inertia of the solid sphere about its centre, kg m^2: ``2/5 m r^2``
        (``counterweight_own_inertia`` when given)."""
        if self.counterweight_own_inertia is not None:
            return self.counterweight_own_inertia
        return 0.4 * self.counterweight_mass * self.counterweight_radius**2


def with_kind(problem: Problem, kind: str) -> Problem:
    """``problem`` for machines of ``kind`` (``analytic.design.KINDS``): the same variables, limits
    and parts; a kind without a link has its ``counterweight_link`` fixed at 0.

    Raises
    ------
    DesignError
        naming ``machine.kind`` for a kind that is not built, or ``variables.counterweight_link``
        for a hinged machine from a problem whose link is fixed at 0.
    """
    require_kind("machine.kind", kind)
    variables = tuple(Variable(v.name, 0.0, 0.0) if v.name == "counterweight_link" and kind != "hinged" else v
                      for v in problem.variables)
    return dataclasses.replace(problem, kind=kind, variables=variables)


def bolted(values: np.ndarray) -> np.ndarray:
    """A design vector (``VARIABLE_NAMES`` order, m and rad) with its counterweight bolted to the
    short arm's end: the link's length joins the clearance, so the pivot height, the arms and
    the sling are the same, and the link is 0 (a fixed or floating-arm machine's)."""
    values = np.array(values, dtype=float)
    link = VARIABLE_NAMES.index("counterweight_link")
    values[VARIABLE_NAMES.index("clearance")] += values[link]
    values[link] = 0.0
    return values


def design_at(problem: Problem, values: np.ndarray, name: str = "optimum") -> Design:
    """The design for a full vector of the problem's design variables.

    Parameters
    ----------
    values : (n,) in the order of ``problem.variables`` (``VARIABLE_NAMES``, then
        ``frame_mass`` if free), m, rad and kg. Bounds are not enforced
        (finite-difference steps may cross them); buildability is.

    Raises
    ------
    DesignError
        if the combination cannot be built.
    """
    arm_short, link, clearance, sling, starting_angle, release_angle = (float(v) for v in values[:6])
    base = problem.base if len(values) == 6 else dataclasses.replace(problem.base, mass=float(values[6]))
    pivot_height, arm_long = paper_geometry(arm_short, link, clearance, starting_angle)
    arm_mass, arm_cg, arm_inertia = problem.arm.properties(arm_long, arm_short)
    machine = Machine(pivot_height=pivot_height, arm_long=arm_long, arm_short=arm_short,
                      arm_mass=arm_mass, arm_cg=arm_cg, arm_inertia=arm_inertia,
                      counterweight_mass=problem.counterweight_mass, counterweight_link=link,
                      counterweight_inertia=problem.counterweight_inertia, sling_length=sling,
                      # the ideal rule finds its own release: the angle is no variable, and a design has none
                      release_angle=None if problem.release_rule == "ideal" else release_angle,
                      release_rule=problem.release_rule, kind=problem.kind,
                      sling_mass=problem.sling_mass, pouch_mass=problem.pouch_mass,
                      arm_section=problem.arm.section if problem.arm.rated else None)
    return Design(machine, problem.projectile, problem.environment, name=name, base=base, losses=problem.losses)


def sample_designs(problem: Problem, count: int, seed: int, name: Callable[[int], str],
                   arms: Sequence[BeamArm] = ()) -> list[Design]:
    """``count`` designs drawn uniformly over the problem's box of free variables (``from_unit``).

    Seeded: ``numpy.random.default_rng(seed)`` draws one row of ``len(problem.free)``
    unit values a design, so the first k designs of any count are the same. Design i is
    built on ``arms[i % len(arms)]`` (default: the problem's own arm) and named ``name(i)``.
    Designs that cannot be built raise ``DesignError`` (none over the paper's box).
    """
    arms = tuple(arms) or (problem.arm,)
    problems = [problem if arm is problem.arm else dataclasses.replace(problem, arm=arm) for arm in arms]
    units = np.random.default_rng(seed).uniform(0.0, 1.0, size=(count, len(problem.free)))
    return [design_at(problems[i % len(problems)], from_unit(problem, unit), name=name(i))
            for i, unit in enumerate(units)]


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
    (fixed); lengths in m, angles in degrees. ``[projectile]``, ``[environment]``
    (optional) and ``[arm_beam]`` are read as in design files, ``[machine]``'s ``kind``,
    ``sling_mass`` and ``pouch_mass`` (kg) as there, ``[base]`` as there (its ``trough_height``
    too) or with the frame's mass between bounds. Under ``[release]
    rule = "ideal"`` the release angle is no variable: leave it out (a fixed value is ignored).

    Raises
    ------
    DesignError
        naming the field as ``table.key``, its value and the reason, before any
        arithmetic uses a value.
    """
    reject_unknown_keys("", require_table("problem", data), _TABLES)
    machine = read_values("machine", require_table("machine", data.get("machine"), optional=True),
                          numbers=_MACHINE_PARTS, texts=("kind",))
    kind = require_kind("machine.kind", machine.get("kind", "hinged"))
    variables = require_table("variables", data.get("variables"))
    reject_unknown_keys("variables", variables, VARIABLE_NAMES)
    if kind != "hinged" and "counterweight_link" not in variables:
        variables = {**variables, "counterweight_link": {"value": 0.0}}   # rigid on the arm: no link
    release = read_values("release", require_table("release", data.get("release"), optional=True),
                          numbers=(), texts=("rule",))
    if release.get("rule") == "ideal":   # no variable: it finds its own release
        entry = variables.get("release_angle")
        if entry is None:
            variables = {**variables, "release_angle": {"value": 0.0}}
        elif isinstance(entry, dict) and "value" not in entry and entry.get("lower") != entry.get("upper"):
            raise DesignError("variables.release_angle", entry, IDEAL_RELEASE_NOT_A_VARIABLE)   # as written
    constraints = read_values("constraints", require_table("constraints", data.get("constraints")),
                              numbers=_CONSTRAINT_KEYS + _BREAKING_KEYS, required=_CONSTRAINT_KEYS)
    counterweight = read_values("counterweight", require_table("counterweight", data.get("counterweight")),
                                numbers=("mass", "density"), required=("mass", "density"))
    base, frame_mass = _base(data.get("base"))
    loads = require_table("loads", data.get("loads"), optional=True)
    reject_unknown_keys("loads", loads, _LOAD_KEYS + ("minimise",))
    minimise = loads.get("minimise")
    loads = read_values("loads", {k: v for k, v in loads.items() if k != "minimise"}, numbers=_LOAD_KEYS)
    if "max_projectile_acceleration" in constraints:
        if "max_projectile_acceleration" in loads:
            raise DesignError("constraints.max_projectile_acceleration", constraints["max_projectile_acceleration"],
                              "the same limit as [loads] max_projectile_acceleration: give it once")
        loads["max_projectile_acceleration"] = constraints["max_projectile_acceleration"]
    return Problem(
        name=data.get("name", name),
        variables=tuple(_variable(key, variables.get(key)) for key in VARIABLE_NAMES) + frame_mass,
        max_footprint=constraints["max_footprint"],
        max_height=constraints["max_height"],
        axle_radius=constraints["axle_radius"],
        counterweight_mass=counterweight["mass"],
        counterweight_density=counterweight["density"],
        arm=beam_arm_from_dict(data.get("arm_beam"), "arm_beam"),
        projectile=projectile_from_dict(data.get("projectile")),
        environment=environment_from_dict(data.get("environment")),
        release_rule=release.get("rule", "velocity"),
        base=base,
        losses=losses_from_dict(data.get("losses")),
        load_limits=tuple((name, loads[f"max_{name}"]) for name in LOADS if f"max_{name}" in loads),
        minimise=minimise,
        min_range=loads.get("min_range"),
        kind=kind,
        **{part: machine[part] for part in _MACHINE_PARTS if part in machine},
        min_arm_safety_factor=constraints.get("min_arm_safety_factor"),
    )


def load_problem(path: str | Path) -> Problem:
    """Read a problem TOML file; errors name the file or the field, the value and the reason."""
    return problem_from_dict(read_toml(path), name=Path(path).stem)


def default_problem() -> Problem:
    """The built-in default: the paper's problem (``analytic/data/paper_problem.toml``)."""
    return load_problem(Path(__file__).with_name("data") / "paper_problem.toml")


def _base(entry: Any) -> tuple[Base, tuple[Variable, ...]]:
    """The ``[base]`` table: as in a design file, or with ``mass = { lower = .., upper = .. }``
    to make the rolling frame's mass a design variable (``frame_mass``)."""
    table = require_table("base", entry, optional=True)
    mass = table.get("mass")
    if not isinstance(mass, dict):
        return base_from_dict(entry), ()
    try:
        variable = _variable(FRAME_MASS, mass, table="base.mass")
    except DesignError as error:   # a Variable names itself under [variables]: name the file's field
        raise DesignError("base.mass", error.value, error.reason) from None
    base = base_from_dict({**table, "mass": variable.lower})
    return base, (() if variable.fixed else (variable,))


def _variable(key: str, entry: Any, table: str | None = None) -> Variable:
    """One ``[variables]`` entry: bounds, or a fixed value (degrees for angles in the file)."""
    table = table or f"variables.{key}"
    entry = require_table(table, entry)
    if "value" in entry:
        lower = upper = read_values(table, entry, numbers=("value",))["value"]
    else:
        bounds = read_values(table, entry, numbers=("lower", "upper"), required=("lower", "upper"))
        lower, upper = bounds["lower"], bounds["upper"]
    if key in ANGLE_VARIABLES:
        lower, upper = math.radians(lower), math.radians(upper)
    return Variable(key, lower, upper)
