"""Sweep files: the base design and what varies around it, read and checked before any work.

A sweep file (TOML) names a base (``design``: a design file or a built-in
design; ``problem``: the optimiser's problem; ``function``: a test function
with known sensitivity indices) and what varies:

* ``[grid]``: a regular grid, every combination of each field's values,
  ``{from, to, steps}`` or ``{values = [...]}``;
* ``[sample]``: ``n`` draws by ``method`` (``random`` or ``sobol``) with a
  ``seed``, over per-field ranges (``{from, to}``: uniform) or distributions
  (``{distribution = "normal", mean, sd}``, truncated by ``from``/``to``);
* ``[uncertain]``: distributions added around the base value (or the grid
  value) of a field: ``{distribution = "normal", sd}`` or
  ``{distribution = "uniform", half_width}``, drawn with ``[sample]``'s n,
  method and seed.

A grid and a sample together make every sample at every grid point. Fields
are dotted design-file names (``machine.release_angle``) in design-file
units (SI, angles in degrees); any value may instead be text with its unit
(``"40 cm"``, ``"2 deg"``), converted by pint here, when the file is read.
Every error is a ``DesignError`` naming the sweep file's field, the value
and the reason.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from pathlib import Path
from typing import Any

import numpy as np

from analytic.design import DesignError, MissingValueError, require_choice, require_number
from analytic.design_file import design_from_dict, read_toml, reject_unknown_keys, require_table
from analytic.fields import IDEAL_IGNORES_RELEASE_ANGLE
from analytic.units import registry
from analytic.sweep.distributions import MIN_WINDOW_PROBABILITY, Distribution, Normal, Uniform
from analytic.sweep.spec import (ANGLE_FIELDS, DEFAULT_CHUNK_SIZE, FIELD_UNITS, METHODS, TEST_FUNCTIONS, Axis, Base,
                                 Sample, Sweep, Varied, design_data, extremes, field_unit)

#: Every corner of the box the varied fields span is built before the sweep
#: starts (2^n designs): beyond this many fields that check alone takes minutes.
MAX_VARIED_FIELDS = 16
DATA_DIR = Path(__file__).parents[1] / "data"
_TOP_KEYS = ("name", "design", "problem", "function", "chunk_size", "grid", "sample", "uncertain")
_SAMPLE_SETTINGS = ("n", "method", "seed")
_ENTRY_KEYS = ("from", "to", "steps", "values", "distribution", "mean", "sd", "half_width")


def load_sweep(path: str | Path) -> Sweep:
    """Read and check a sweep file; a relative ``design``/``problem`` path is relative to it.

    Raises
    ------
    DesignError
        naming the field, its value and the reason, before any design is shot.
    """
    path = Path(path)
    return sweep_from_dict(read_toml(path), name=path.stem, directory=path.parent)


def sweep_from_dict(data: dict[str, Any], name: str = "sweep", directory: Path | None = None) -> Sweep:
    """A ``Sweep`` from a sweep file's tables (see the module docstring); every value checked.

    Parameters
    ----------
    data : the file's tables, as ``tomllib`` reads them.
    name : the sweep's name unless the file gives one.
    directory : where relative paths start (the sweep file's folder); None: the working folder.
    """
    reject_unknown_keys("", require_table("sweep", data), _TOP_KEYS)
    base = _base(data, directory)
    grid = _grid(data.get("grid"), base)
    sample = _sample(data.get("sample"), data.get("uncertain"), base, grid)
    if not grid and sample is None:
        raise MissingValueError("grid", reason="a sweep needs [grid] or [sample] (or both)")
    chunk_size = _whole("chunk_size", data.get("chunk_size", DEFAULT_CHUNK_SIZE), minimum=1)
    sweep_name = data.get("name", name)
    if not isinstance(sweep_name, str):
        raise DesignError("name", sweep_name, "must be text")
    sweep = Sweep(sweep_name, base, grid, sample, chunk_size)
    _check_free_variables(sweep)
    _check_corners(sweep)
    return sweep


def quantity(field: str, value: Any, unit: str) -> float:
    """A number in ``unit``: a number is taken as already in it; text is a quantity with its unit.

    ``"40 cm"`` for a field in m gives 0.4; ``"2 deg"`` stays 2.0. Design files
    are plain numbers in fixed units; sweep files also take units, parsed by
    pint, because a sweep's ranges are what people write by hand.

    Raises
    ------
    DesignError
        for text pint cannot read, a unit of the wrong kind, or a value that is not a finite number.
    """
    if not isinstance(value, str):
        return require_number(field, value)
    import pint

    try:
        parsed = registry().Quantity(value)
    except (pint.errors.PintError, ValueError, TypeError, SyntaxError, AttributeError) as error:
        raise DesignError(field, value, f"not a number with a unit that pint can read ({error})") from None
    try:
        magnitude = parsed.to(unit or "dimensionless").magnitude
    except pint.errors.DimensionalityError:
        raise DesignError(field, value, f"must be in units of {unit or 'nothing (a pure number)'}"
                                        f"{' or convertible to it' if unit else ''}") from None
    return require_number(field, magnitude)


def _base(data: dict, directory: Path | None) -> Base:
    given = [key for key in ("design", "problem", "function") if key in data]
    if len(given) != 1:
        if not given:
            raise MissingValueError("design", reason="give the base: design, problem or function")
        raise DesignError(given[1], data[given[1]], f"give one base, not both {given[0]} and {given[1]}")
    key = given[0]
    value = data[key]
    if key == "function":
        require_choice("function", value, tuple(TEST_FUNCTIONS))
        return Base("function", value, {}, {}, {})
    if not isinstance(value, str):
        raise DesignError(key, value, "must be text: a file path or a built-in name")
    path = _resolve(key, value, directory)
    if key == "design":
        file_data = read_toml(path)
        design = design_from_dict(file_data, name=path.stem)
        values = _numbers(file_data)
        for table, part in (("machine", design.machine), ("projectile", design.projectile),
                            ("environment", design.environment), ("losses", design.losses)):
            for item in dataclasses.fields(part):
                number = getattr(part, item.name)
                field = f"{table}.{item.name}"
                if field in FIELD_UNITS and number is not None and field not in values:
                    values[field] = math.degrees(number) if field in ANGLE_FIELDS else number
        return Base("design", design.name, file_data, values, {})
    from analytic.design_space import ANGLE_VARIABLES, load_problem

    problem = load_problem(path)
    machine = {"counterweight_mass": problem.counterweight_mass,
               "counterweight_inertia": problem.counterweight_inertia, "release_rule": problem.release_rule,
               "arm_beam": {k: v for k, v in dataclasses.asdict(problem.arm).items() if v is not None}}
    if problem.kind != "hinged":
        machine["kind"] = problem.kind
    bounds = {}
    for variable in problem.variables:
        if variable.name == "release_angle" and problem.release_rule == "ideal":
            continue   # no variable: the rule finds its own release
        lower, upper = ((math.degrees(variable.lower), math.degrees(variable.upper))
                        if variable.name in ANGLE_VARIABLES else (variable.lower, variable.upper))
        if variable.fixed:
            machine[variable.name] = lower
        else:
            bounds[f"machine.{variable.name}"] = (lower, upper)
    file_data = {"name": problem.name, "machine": machine,
                 "projectile": {k: v for k, v in dataclasses.asdict(problem.projectile).items() if v is not None},
                 "environment": dataclasses.asdict(problem.environment)}
    return Base("problem", problem.name, file_data, _numbers(file_data), bounds)


def _resolve(key: str, value: str, directory: Path | None) -> Path:
    """A path relative to the sweep file, else a built-in file of that name in ``analytic/data``."""
    given = Path(value)
    candidate = given if directory is None or given.is_absolute() else directory / given
    if candidate.is_file():
        return candidate
    builtin = DATA_DIR / (value if value.endswith(".toml") else f"{value}.toml")
    if "/" not in value and builtin.is_file():
        return builtin
    names = ", ".join(sorted(p.stem for p in DATA_DIR.glob("*.toml")))
    raise DesignError(key, value, f"no such file (relative to the sweep file) and no built-in of that name "
                                  f"(built-ins: {names})")


def _numbers(data: dict, prefix: str = "") -> dict[str, float]:
    """The numeric fields of a design-file layout, flattened to dotted names."""
    found = {}
    for key, value in data.items():
        if isinstance(value, dict):
            found.update(_numbers(value, f"{prefix}{key}."))
        elif f"{prefix}{key}" in FIELD_UNITS and not isinstance(value, (bool, str)):
            found[f"{prefix}{key}"] = float(value)
    return found


def _entries(table_name: str, table: Any, base: Base) -> dict[str, dict]:
    """A [grid]/[sample]/[uncertain] table's field entries by field, whether keys were quoted
    (``"machine.sling_length" = {..}``) or dotted (``machine.sling_length = {..}``)."""
    known = TEST_FUNCTIONS[base.name] if base.kind == "function" else tuple(FIELD_UNITS)
    entries = {}

    def walk(values: dict, prefix: str) -> None:
        for key, entry in values.items():
            field = f"{prefix}{key}"
            if table_name == "sample" and not prefix and key in _SAMPLE_SETTINGS:
                continue
            if field in known:
                if field == "machine.release_angle" and base.data.get("machine", {}).get("release_rule") == "ideal":
                    raise DesignError(f"{table_name}.{field}", entry, IDEAL_IGNORES_RELEASE_ANGLE)
                entries[field] = require_table(f"{table_name}.{field}", entry)
            elif isinstance(entry, dict) and not set(entry) & set(_ENTRY_KEYS) and any(
                    name.startswith(f"{field}.") for name in known):
                walk(entry, f"{field}.")
            else:
                raise DesignError(f"{table_name}.{field}", entry,
                                  f"unknown field; expected one of {', '.join(known)}")

    walk(table, "")
    return entries


def _whole(field: str, value: Any, minimum: int) -> int:
    if value is None:
        raise MissingValueError(field)
    if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
        raise DesignError(field, value, f"must be a whole number of at least {minimum}")
    return value


def _range(where: str, entry: dict, base: Base, field: str) -> tuple[float, float]:
    """``from`` and ``to`` of an entry; a problem's free variable may omit them for its bounds."""
    unit = field_unit(base, field)
    if "from" not in entry and "to" not in entry and field in base.bounds:
        return base.bounds[field]
    for key in ("from", "to"):
        if key not in entry:
            raise MissingValueError(f"{where}.{key}")
    low, high = quantity(f"{where}.from", entry["from"], unit), quantity(f"{where}.to", entry["to"], unit)
    if not low < high:
        raise DesignError(f"{where}.to", entry["to"], f"must be greater than from ({entry['from']!r})")
    return low, high


def _grid(table: Any, base: Base) -> tuple[Axis, ...]:
    axes = []
    for field, entry in _entries("grid", require_table("grid", table, optional=True), base).items():
        where = f"grid.{field}"
        if "values" in entry:
            reject_unknown_keys(where, entry, ("values",))
            listed = entry["values"]
            if not isinstance(listed, list) or not listed:
                raise DesignError(f"{where}.values", listed, "must be a non-empty list of numbers")
            values = [quantity(f"{where}.values", v, field_unit(base, field)) for v in listed]
        else:
            reject_unknown_keys(where, entry, ("from", "to", "steps"))
            low, high = _range(where, entry, base, field)
            steps = _whole(f"{where}.steps", entry.get("steps"), minimum=2)
            values = np.linspace(low, high, steps)
        axes.append(Axis(field, tuple(float(v) for v in values)))
    return tuple(axes)


def _distribution(where: str, entry: dict, base: Base, field: str) -> Distribution:
    """A [sample] entry: ``{from, to}`` (uniform) or ``{distribution = "normal", mean, sd[, from, to]}``."""
    kind = require_choice(f"{where}.distribution", entry.get("distribution", "uniform"), ("uniform", "normal"))
    unit = field_unit(base, field)
    if kind == "uniform":
        reject_unknown_keys(where, entry, ("distribution", "from", "to"))
        return Uniform(*_range(where, entry, base, field))
    reject_unknown_keys(where, entry, ("distribution", "mean", "sd", "from", "to"))
    for key in ("mean", "sd"):
        if key not in entry:
            raise MissingValueError(f"{where}.{key}", reason='required with distribution = "normal"')
    mean, sd = quantity(f"{where}.mean", entry["mean"], unit), quantity(f"{where}.sd", entry["sd"], unit)
    if not sd > 0.0:
        raise DesignError(f"{where}.sd", entry["sd"], "must be positive")
    low = quantity(f"{where}.from", entry["from"], unit) if "from" in entry else None
    high = quantity(f"{where}.to", entry["to"], unit) if "to" in entry else None
    if low is not None and high is not None and not low < high:
        raise DesignError(f"{where}.to", entry["to"], f"must be greater than from ({entry['from']!r})")
    normal = Normal(mean, sd, low, high)
    if not normal.window_probability >= MIN_WINDOW_PROBABILITY:
        raise DesignError(where, entry, f"the truncation window holds a probability of "
                                        f"{normal.window_probability:.3g}, too little to sample")
    return normal


def _offset(where: str, entry: dict, base: Base, field: str) -> Distribution:
    """An [uncertain] entry, centred on zero: ``{distribution = "normal", sd}`` or ``{... "uniform", half_width}``."""
    if "distribution" not in entry:
        raise MissingValueError(f"{where}.distribution", reason="required: normal (with sd) or uniform "
                                                                "(with half_width)")
    kind = require_choice(f"{where}.distribution", entry["distribution"], ("uniform", "normal"))
    key = "sd" if kind == "normal" else "half_width"
    reject_unknown_keys(where, entry, ("distribution", key))
    if key not in entry:
        raise MissingValueError(f"{where}.{key}", reason=f'required with distribution = "{kind}"')
    width = quantity(f"{where}.{key}", entry[key], field_unit(base, field))
    if not width > 0.0:
        raise DesignError(f"{where}.{key}", entry[key], "must be positive")
    return Normal(0.0, width) if kind == "normal" else Uniform(-width, width)


def _sample(table: Any, uncertain: Any, base: Base, grid: tuple[Axis, ...]) -> Sample | None:
    if table is None:
        if uncertain is not None:
            raise MissingValueError("sample", reason="required table with [uncertain]: it gives n, method and seed")
        return None
    table = require_table("sample", table)
    n = _whole("sample.n", table.get("n"), minimum=1)
    if "method" not in table:
        raise MissingValueError("sample.method")
    method = require_choice("sample.method", table["method"], METHODS)
    seed = _whole("sample.seed", table.get("seed"), minimum=0)
    if method == "sobol" and n & (n - 1):
        raise DesignError("sample.n", n, f"the Sobol' method needs a power of 2 (such as {1 << n.bit_length()})")
    on_grid = {axis.field for axis in grid}
    fields = []
    for field, entry in _entries("sample", table, base).items():
        if field in on_grid:
            raise DesignError(f"sample.{field}", entry, "already varied by [grid]; vary a field in one of them")
        fields.append(Varied(field, _distribution(f"sample.{field}", entry, base, field)))
    for field, entry in _entries("uncertain", require_table("uncertain", uncertain, optional=True), base).items():
        where = f"uncertain.{field}"
        if any(v.field == field for v in fields):
            raise DesignError(where, entry, "already drawn by [sample]; give it in one of them")
        if field not in on_grid and field not in base.values:
            raise DesignError(where, entry, "the base has no value to scatter it around; "
                                            "put it on [grid] or draw it in [sample]")
        fields.append(Varied(field, _offset(where, entry, base, field), around_base=True))
    if not fields:
        raise MissingValueError("sample", reason="names no field to vary (give fields here or in [uncertain])")
    return Sample(n, method, seed, tuple(fields))


def _check_free_variables(sweep: Sweep) -> None:
    """A problem's free variables have no value of their own: the sweep must vary each."""
    varied = set(sweep.fields)
    for field, (lower, upper) in sweep.base.bounds.items():
        if field not in varied:
            raise MissingValueError(field, reason=f"the problem leaves it free ({lower:g} to {upper:g}): vary it "
                                                  f"in [grid] or [sample], or fix it in the problem file")


def _check_corners(sweep: Sweep) -> None:
    """Build the design at every corner of the box the varied fields span.

    Every check a design makes is linear in its design-file numbers (signs,
    ``arm_cg`` between ``-arm_short`` and ``arm_long``, ``arm_short + link <
    pivot_height``, ``arm_long > pivot_height``, the release angle's limits)
    or holds everywhere by construction (the paper's and the beam's forms),
    so if every corner builds, every design inside the box does: the sweep
    can be refused before it starts instead of failing in its millionth row.
    """
    if sweep.base.kind == "function":
        return
    spans = extremes(sweep)
    if len(spans) > MAX_VARIED_FIELDS:
        raise DesignError("sample", sorted(spans), f"at most {MAX_VARIED_FIELDS} fields may vary (every corner of "
                                                   f"the box they span, 2^n designs, is checked before the sweep)")
    for corner in itertools.product(*spans.values()):
        values = dict(zip(spans, corner))
        try:
            design_from_dict(design_data(sweep.base, values))
        except DesignError as error:
            where = ", ".join(f"{field} = {value:.6g}" for field, value in values.items())
            raise DesignError(error.field, error.value, f"{error.reason} (a design the sweep reaches: {where})") \
                from None
