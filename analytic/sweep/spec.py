"""What a sweep is: its base design, grid and sample, and the fields it may vary (``Sweep``).

Sweep files are read and checked into these by ``analytic.sweep.sweep_file``;
a chunk's inputs are expanded from them by ``analytic.sweep.expand``. Fields
are dotted design-file names (``machine.release_angle``) in design-file units
(SI, angles in degrees).
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass

from analytic.units import ANGLE, kind_of
from analytic.sweep.distributions import Distribution

#: Every design-file number a sweep may vary.
SWEEP_FIELDS = (
    "machine.pivot_height", "machine.arm_long", "machine.arm_short", "machine.arm_mass", "machine.arm_cg",
    "machine.arm_inertia", "machine.counterweight_mass", "machine.counterweight_link",
    "machine.counterweight_inertia", "machine.sling_length", "machine.release_angle", "machine.clearance",
    "machine.starting_angle", "machine.arm_beam.width", "machine.arm_beam.depth", "machine.arm_beam.density",
    "projectile.mass", "projectile.diameter", "projectile.drag_coefficient", "projectile.drag_factor",
    "environment.gravity", "environment.air_density", "environment.air_viscosity", "environment.wind_speed",
    "environment.target_height", "losses.axle_friction", "losses.axle_radius", "losses.hinge_friction",
    "losses.hinge_radius", "losses.base_friction", "base.trough_height",
    "machine.sling_mass", "machine.pouch_mass",
)
#: Each one's unit in files: that of the kind its key names (``analytic.units.FIELD_KINDS``).
FIELD_UNITS = {field: kind_of(field).file_unit for field in SWEEP_FIELDS}
#: Fields in degrees in files (radians inside the model).
ANGLE_FIELDS = tuple(field for field in SWEEP_FIELDS if kind_of(field) is ANGLE)
#: Test functions with known sensitivity indices, and their inputs (dimensionless).
TEST_FUNCTIONS = {"ishigami": ("x1", "x2", "x3")}
METHODS = ("random", "sobol")
#: Designs per chunk unless the file says otherwise: large enough that a
#: cluster's per-task cost (scheduling, moving the results, writing a file)
#: stays a few per cent of the shooting (``python -m benchmarks``).
DEFAULT_CHUNK_SIZE = 4096


@dataclass(frozen=True)
class Axis:
    """One grid field and its values (file units), in order."""

    field: str
    values: tuple[float, ...]


@dataclass(frozen=True)
class Varied:
    """A sampled field: drawn from ``distribution``, or, if ``around_base``, base (or grid) value plus a draw."""

    field: str
    distribution: Distribution
    around_base: bool = False


@dataclass(frozen=True)
class Sample:
    """``n`` draws by ``method`` with ``seed`` over ``fields`` ([sample]'s, then [uncertain]'s)."""

    n: int
    method: str
    seed: int
    fields: tuple[Varied, ...]

    @property
    def rows(self) -> int:
        """Designs per grid point: ``n``, or ``n (D + 2)`` for Saltelli's Sobol' scheme (D fields)."""
        return self.n if self.method == "random" else self.n * (len(self.fields) + 2)


@dataclass(frozen=True)
class Base:
    """What the sweep varies around.

    Attributes
    ----------
    kind : ``"design"``, ``"problem"`` (its design-file form) or ``"function"`` (a test function).
    name : the design's, problem's or function's name.
    data : the design-file layout the varied fields are written into (empty for a function).
    values : field -> the base's value in file units, for every field it has one for.
    bounds : field -> (lower, upper) in file units, a problem's free variables.
    """

    kind: str
    name: str
    data: dict
    values: dict
    bounds: dict


@dataclass(frozen=True)
class Sweep:
    """A whole sweep: base, grid, sample and chunk size; row ``i`` is grid point
    ``i // sample_rows`` (C order over the axes) with sample row ``i % sample_rows``."""

    name: str
    base: Base
    grid: tuple[Axis, ...]
    sample: Sample | None
    chunk_size: int

    @property
    def fields(self) -> tuple[str, ...]:
        """The varied fields, each once: grid, then [sample], then [uncertain] (the table's input columns)."""
        names = [axis.field for axis in self.grid]
        for varied in self.sample.fields if self.sample else ():
            if varied.field not in names:
                names.append(varied.field)
        return tuple(names)

    @property
    def grid_shape(self) -> tuple[int, ...]:
        return tuple(len(axis.values) for axis in self.grid)

    @property
    def grid_size(self) -> int:
        return math.prod(self.grid_shape)

    @property
    def sample_rows(self) -> int:
        return self.sample.rows if self.sample else 1

    @property
    def shots(self) -> int:
        return self.grid_size * self.sample_rows

    @property
    def chunks(self) -> int:
        return -(-self.shots // self.chunk_size)

    @property
    def output(self) -> str:
        """The column the analyses study: ``range``, or ``y`` for a test function."""
        return "y" if self.base.kind == "function" else "range"

    def chunk_rows(self, chunk: int) -> tuple[int, int]:
        """Rows ``[start, stop)`` of chunk ``chunk``."""
        start = chunk * self.chunk_size
        return start, min(start + self.chunk_size, self.shots)

    def describe(self) -> dict:
        """Everything that decides the sweep's rows, as JSON-ready values (the identity stored with results)."""
        sample = None
        if self.sample is not None:
            sample = {"n": self.sample.n, "method": self.sample.method, "seed": self.sample.seed,
                      "fields": [{"field": v.field, "around_base": v.around_base, **v.distribution.describe()}
                                 for v in self.sample.fields]}
        return {"base": {"kind": self.base.kind, "name": self.base.name, "data": self.base.data},
                "grid": [{"field": axis.field, "values": list(axis.values)} for axis in self.grid],
                "sample": sample, "chunk_size": self.chunk_size, "shots": self.shots,
                "chunks": self.chunks, "fields": list(self.fields), "output": self.output,
                "units": {field: field_unit(self.base, field) for field in self.fields}}


def field_unit(base: Base, field: str) -> str:
    """A field's unit in files (``""`` for pure numbers)."""
    return "" if base.kind == "function" else FIELD_UNITS[field]


def extremes(sweep: Sweep) -> dict[str, tuple[float, float]]:
    """Each varied field's smallest and largest value anywhere in the sweep (file units)."""
    spans = {axis.field: (min(axis.values), max(axis.values)) for axis in sweep.grid}
    for varied in sweep.sample.fields if sweep.sample else ():
        low, high = varied.distribution.support
        if varied.around_base:
            centre_low, centre_high = spans.get(varied.field, (sweep.base.values.get(varied.field),) * 2)
            low, high = centre_low + low, centre_high + high
        spans[varied.field] = (low, high)
    return spans


def design_data(base: Base, values: dict[str, float]) -> dict:
    """The base's design-file layout with ``values`` (dotted field -> number, file units) written in."""
    data = copy.deepcopy(base.data)
    for field, value in values.items():
        *tables, key = field.split(".")
        place = data
        for table in tables:
            place = place.setdefault(table, {})
        place[key] = value
    return data
