"""Design files: TOML in and out (SI units, angles in degrees, or values with units), every value checked before use."""

from __future__ import annotations

import dataclasses
import json
import math
import re
import tomllib
from pathlib import Path
from typing import Any

from analytic.design import (ArmSection, Base, BeamArm, Design, DesignError, Environment, Losses, Machine,
                             MissingValueError, Projectile, paper_geometry, require_number, require_positive)
from analytic.data.strength import STANDARD_GRAVITY
from analytic.suggest import did_you_mean
from analytic.units import (ANGLE, FIELD_KINDS, SYSTEM_KINDS, Written, from_file, kind_of, to_file_text,
                            written_system)

_MACHINE_NUMBERS = tuple(f.name for f in dataclasses.fields(Machine)
                         if f.name not in ("release_rule", "kind", "arm_section"))
#: The machine's numbers a file may leave out (0 by default: massless sling and pouch).
_MACHINE_OPTIONAL = ("sling_mass", "pouch_mass")
_ENVIRONMENT_KEYS = tuple(f.name for f in dataclasses.fields(Environment))
_BEAM_KEYS = ("width", "depth", "density")
_ANGLE_KEYS = ("release_angle", "starting_angle")  # degrees in files
_ARM_KEYS = ("arm_mass", "arm_cg", "arm_inertia")
_PAPER_KEYS = ("clearance", "starting_angle")
#: Where a design file keeps the beam, and so where ``BeamArm`` says its fields are.
BEAM_TABLE = "machine.arm_beam"
#: A key TOML writes without quotes.
_BARE_KEY = re.compile(r"[A-Za-z0-9_-]+")


def design_from_dict(data: dict[str, Any], name: str = "design") -> Design:
    """Build a design from the TOML layout (SI units, angles in degrees).

    Besides the direct ``[machine]`` keys, two alternative forms are accepted:

    * the paper's: ``clearance`` and ``starting_angle`` (deg) instead of
      ``pivot_height`` and ``arm_long`` (see ``paper_geometry``);
    * ``[machine.arm_beam]`` with ``width``, ``depth``, ``density`` instead of
      ``arm_mass``, ``arm_cg``, ``arm_inertia`` (see ``BeamArm``). Without ``density``
      it gives only the arm's section, beside those three. Either way it may name a
      ``material`` or give a ``strength`` (Pa); the design keeps the section (``ArmSection``),
      for the stress a shot puts in the arm, when it does or when the table gives the section alone.

    Every value is checked (its table, presence and type) before any
    arithmetic uses it.

    Parameters
    ----------
    data : the file's tables, as ``tomllib`` reads them.
    name : the design's name unless the file gives one.

    Raises
    ------
    DesignError
        naming the field as ``table.key``, its value and the reason.
    """
    reject_unknown_keys("", require_table("design", data),
                        ("machine", "projectile", "environment", "base", "losses", "name"))
    try:
        machine = machine_from_dict(data.get("machine"))
        projectile = projectile_from_dict(data.get("projectile"))
        environment = environment_from_dict(data.get("environment"))
        base = base_from_dict(data.get("base"))
        losses = losses_from_dict(data.get("losses"))
        return Design(machine, projectile, environment, name=data.get("name", name), base=base, losses=losses)
    except DesignError as error:
        raise as_written(error, written_texts(data)) from None


def written_texts(data: dict[str, Any], table: str = "") -> dict[str, str]:
    """Every value of a file's tables written as a text (``"-200 lb"``), by its place
    (``machine.counterweight_mass``)."""
    return dict(_texts(data, table))


def _texts(data: dict[str, Any], table: str = ""):
    """(place, text) for every text value of ``data``, its tables and its arrays of tables (``[[shot]]``)."""
    for key, value in data.items():
        place = f"{table}.{key}" if table else key
        items = value if isinstance(value, list) else [value]
        for item in items:
            if isinstance(item, dict):
                yield from _texts(item, place)
            elif isinstance(item, str):
                yield place, item


def as_written(error: DesignError, texts: dict[str, str]) -> DesignError:
    """``error`` echoing its value as the file wrote it, with the value in file units in brackets
    (``machine.counterweight_mass = "-200 lb" (-90.7185 kg): must be positive``), when the file
    gave it with a unit; otherwise ``error`` itself."""
    text, kind = texts.get(error.field), kind_of(error.field)
    if text is None or kind is None or not kind.file_unit or error.value == text:
        return error
    if isinstance(error.value, str):   # the design's checks showed it in file units already
        return type(error)(error.field, Written(text, error.value, kind), error.reason)
    try:
        value = math.degrees(error.value) if kind is ANGLE else float(error.value)
    except (TypeError, ValueError):
        return error
    return type(error)(error.field, Written(text, value, kind), error.reason)


def chosen_units(given: str | None, path: str | Path | None) -> str:
    """The units a command shows: ``given`` (``--units``) if given, else the design file's own
    (``file_system``), else ``metric`` (no file: the built-in default design)."""
    if given is not None:
        return given
    return "metric" if path is None else file_system(path)


def file_system(path: str | Path) -> str:
    """The unit system a design file is mostly written in (``analytic.units.written_system`` over its
    lengths, masses, speeds and forces with units), ``metric`` if it gives none: the default of ``--units``."""
    texts = [text for place, text in _texts(read_toml(path)) if kind_of(place) in SYSTEM_KINDS]
    return written_system(texts)


def machine_from_dict(data: Any) -> Machine:
    """The ``[machine]`` table of a design file (any of its forms, see ``design_from_dict``)."""
    table = "machine"
    values = dict(require_table(table, data))
    beam_data = values.pop("arm_beam", None)
    values = read_values(table, values, numbers=_MACHINE_NUMBERS + _PAPER_KEYS, texts=("release_rule", "kind"),
                         also_allowed=("arm_beam",))
    if values.get("kind", "hinged") != "hinged":
        values.setdefault("counterweight_link", 0.0)   # no link: the counterweight is rigid on the arm
    for key in _ANGLE_KEYS:
        if key in values:
            values[key] = math.radians(values[key])

    if any(key in values for key in _PAPER_KEYS):
        for key in ("pivot_height", "arm_long"):
            if key in values:
                raise DesignError(f"{table}.{key}", values[key],
                                  "give either pivot_height and arm_long, or the paper's "
                                  "clearance and starting_angle, not both")
        require_keys(table, values, _PAPER_KEYS + ("arm_short", "counterweight_link"))
        values["pivot_height"], values["arm_long"] = paper_geometry(
            values["arm_short"], values["counterweight_link"],
            values.pop("clearance"), values.pop("starting_angle"))

    if beam_data is not None and "density" not in require_table(f"{table}.arm_beam", beam_data):
        values["arm_section"] = arm_section_from_dict(beam_data, values)
    elif beam_data is not None:
        for key in _ARM_KEYS:
            if key in values:
                raise DesignError(f"{table}.{key}", values[key],
                                  f"give either arm_mass, arm_cg and arm_inertia, or [{table}.arm_beam], "
                                  f"not both")
        beam = beam_arm_from_dict(beam_data, f"{table}.arm_beam")
        require_keys(table, values, ("pivot_height", "arm_long", "arm_short"))
        values["arm_mass"], values["arm_cg"], values["arm_inertia"] = beam.properties(
            values["arm_long"], values["arm_short"])
        if beam.rated:   # kept only with a strength, so that other designs read as they always have
            values["arm_section"] = beam.section

    if values.get("release_rule") == "ideal":   # the ideal rule needs no release angle (and ignores one)
        values.setdefault("release_angle", None)
    require_keys(table, values, tuple(key for key in _MACHINE_NUMBERS if key not in _MACHINE_OPTIONAL))
    return Machine(**values)


def projectile_from_dict(data: Any) -> Projectile:
    """The ``[projectile]`` table of a design (or problem) file; ``mass``, ``diameter`` and ``drag`` required
    (``max_acceleration`` in g)."""
    values = read_values("projectile", require_table("projectile", data),
                         numbers=("mass", "diameter", "drag_coefficient", "drag_factor", "max_acceleration"),
                         texts=("drag", "drag_during_swing", "kind"),
                         required=("mass", "diameter", "drag"))
    if "max_acceleration" in values:   # in g in files, checked there so that errors show it so
        values["max_acceleration"] = STANDARD_GRAVITY * require_positive("projectile.max_acceleration",
                                                                         values["max_acceleration"])
    return Projectile(**values)


def environment_from_dict(data: Any) -> Environment:
    """The optional ``[environment]`` table of a design (or problem) file; what it omits takes the defaults."""
    values = read_values("environment", require_table("environment", data, optional=True),
                         numbers=_ENVIRONMENT_KEYS)
    return Environment(**values)


def base_from_dict(data: Any) -> Base:
    """The optional ``[base]`` table: ``mobility`` ("fixed", the default, or "rolling"), ``mass`` (kg) and
    ``trough_height`` (m, 0 by default)."""
    values = read_values("base", require_table("base", data, optional=True), numbers=("mass", "trough_height"),
                         texts=("mobility",))
    return Base(**values)


_LOSSES_KEYS = ("axle_friction", "axle_radius", "hinge_friction", "hinge_radius", "base_friction",
                "axle_static_friction", "hinge_static_friction", "base_static_friction",
                "guide_friction", "track_friction", "guide_static_friction", "track_static_friction")


def losses_from_dict(data: Any) -> Losses:
    """The optional ``[losses]`` table: Coulomb coefficients and pin radii (m), each 0 if absent (a static
    coefficient, if absent, is its kinetic one)."""
    values = read_values("losses", require_table("losses", data, optional=True), numbers=_LOSSES_KEYS)
    return Losses(**values)


def beam_arm_from_dict(data: Any, table: str = BEAM_TABLE) -> BeamArm:
    """A beam table (``width``, ``depth``, ``density``, all required), errors named under ``table``.

    ``[machine.arm_beam]`` in design files, ``[arm_beam]`` in problem files.
    """
    values = read_values(table, require_table(table, data), numbers=_BEAM_KEYS + ("strength",),
                         texts=("material",), required=_BEAM_KEYS)
    try:
        return BeamArm(**values)
    except DesignError as error:
        if table == BEAM_TABLE or not error.field.startswith(BEAM_TABLE):
            raise
        # A problem file keeps its beam elsewhere: name the field where this file has it.
        raise DesignError(table + error.field.removeprefix(BEAM_TABLE), error.value, error.reason) from None


def arm_section_from_dict(data: Any, machine: dict[str, Any]) -> ArmSection:
    """A ``[machine.arm_beam]`` table without ``density``: the section of an arm whose ``arm_mass``,
    ``arm_cg`` and ``arm_inertia`` the ``[machine]`` table (its read ``machine``) gives itself."""
    if not any(key in machine for key in _ARM_KEYS):
        raise MissingValueError(f"{BEAM_TABLE}.density")   # or arm_mass, arm_cg and arm_inertia beside it
    values = read_values(BEAM_TABLE, data, numbers=("width", "depth", "strength"), texts=("material",),
                         required=("width", "depth"))
    return ArmSection(**values)


def _arm_section_to_dict(section: ArmSection) -> dict[str, Any]:
    """An ``ArmSection`` as its ``[machine.arm_beam]`` table (without density: beside the arm's numbers)."""
    return {key: value for key, value in dataclasses.asdict(section).items() if value is not None}


def _in_g(acceleration: float) -> float:
    """``acceleration`` (m/s^2) in g, the float that the file reader turns back into it to the bit
    where one of its neighbours does so."""
    written = acceleration / STANDARD_GRAVITY
    for candidate in (written, math.nextafter(written, math.inf), math.nextafter(written, -math.inf)):
        if candidate * STANDARD_GRAVITY == acceleration:
            return candidate
    return written


def design_to_dict(design: Design, units: dict[str, str] | None = None) -> dict[str, Any]:
    """The canonical TOML layout of a design (direct form, angles in degrees).

    Parameters
    ----------
    units : write every number as a text with units instead: kind name (``"length"``,
        ``"mass"``, ... of ``analytic.units``) -> the unit to write it in (pint's
        spelling, ``"ft"``); kinds not named are written in the file's own units.
        ``{}`` writes every value with its file unit (``"0.61 m"``).
    """
    machine = dataclasses.asdict(design.machine)
    if machine["release_angle"] is None:   # the ideal rule's: none
        del machine["release_angle"]
    else:
        machine["release_angle"] = math.degrees(machine["release_angle"])
    if machine["kind"] == "hinged":   # the default: left out, so files read as they were written
        del machine["kind"]
    else:   # no link on a rigid counterweight
        del machine["counterweight_link"]
    for key in _MACHINE_OPTIONAL:   # massless by default: left out, so files read as they were written
        if machine[key] == 0.0:
            del machine[key]
    del machine["arm_section"]
    projectile = {k: v for k, v in dataclasses.asdict(design.projectile).items() if v is not None}
    if "max_acceleration" in projectile:   # in g in files
        projectile["max_acceleration"] = _in_g(projectile["max_acceleration"])
    if projectile["drag_factor"] == 1.0:   # the default: left out, so files read as they were written
        del projectile["drag_factor"]
    if not projectile["drag_during_swing"]:   # the default, the paper's model: left out
        del projectile["drag_during_swing"]
    environment = dataclasses.asdict(design.environment)
    if environment["target_height"] == 0.0:   # the default, the base's level: left out
        del environment["target_height"]
    layout = {"name": design.name, "machine": machine, "projectile": projectile, "environment": environment}
    if design.base != Base():   # a fixed frame is the default: its table is left out
        layout["base"] = {k: v for k, v in dataclasses.asdict(design.base).items()
                          if v is not None and not (k == "trough_height" and v == 0.0)}   # 0: the default
    if design.losses != Losses():   # no friction and no radii is the default: its table is left out
        layout["losses"] = {k: v for k, v in dataclasses.asdict(design.losses).items() if v is not None}
    if units is not None:
        for table in layout.values():
            if isinstance(table, dict):
                for key, value in table.items():
                    kind = FIELD_KINDS.get(key)
                    if kind is not None and kind.file_unit and isinstance(value, float):
                        table[key] = to_file_text(value, kind, units.get(kind.name))
    if design.machine.arm_section is not None:   # after the units: a nested table, written in SI
        machine["arm_beam"] = _arm_section_to_dict(design.machine.arm_section)
    return layout


def load_design(path: str | Path) -> Design:
    """Read a design TOML file; errors name the file, the field, the value and the reason."""
    data = read_toml(path)
    if not data:
        raise DesignError("file", str(path), "is empty (no tables, no keys); a design needs at least [machine] "
                                             "and [projectile], see analytic/data/paper_table3.toml")
    return design_from_dict(data, name=Path(path).stem)


def dumps_design(design: Design, units: dict[str, str] | None = None) -> str:
    """The design as TOML text (direct form; ``units`` as for ``design_to_dict``)."""
    import tomli_w

    return tomli_w.dumps(design_to_dict(design, units))


def save_design(design: Design, path: str | Path, units: dict[str, str] | None = None) -> None:
    """Write a design as TOML that ``load_design`` reads back to an equal design (with ``units``
    in other units than the file's own, equal to the last bit or two of each conversion)."""
    Path(path).write_text(dumps_design(design, units))


def default_design() -> Design:
    """The built-in default: the paper's Table III optimum (see ``data/paper_table3.toml``)."""
    return load_design(Path(__file__).with_name("data") / "paper_table3.toml")


# --------------------------------------------------------------------------- #
# Checks shared by every file (design and problem)
# --------------------------------------------------------------------------- #

def require_table(name: str, value: Any, *, optional: bool = False) -> dict[str, Any]:
    """``value`` if it is a table; if absent ``{}`` when ``optional``, else ``MissingValueError``.

    Anything else where a table belongs raises ``DesignError``.
    """
    if value is None:
        if optional:
            return {}
        raise MissingValueError(name, reason="required table is missing")
    if not isinstance(value, dict):
        raise DesignError(name, value, "must be a table")
    return value


def require_keys(table: str, values: dict[str, Any], keys: tuple[str, ...]) -> None:
    """Raise ``MissingValueError`` naming the first of ``keys`` absent from the table ``values``."""
    for key in keys:
        if key not in values:
            raise MissingValueError(f"{table}.{key}")


def read_values(table: str, values: dict[str, Any], *, numbers: tuple[str, ...], texts: tuple[str, ...] = (),
                required: tuple[str, ...] = (), also_allowed: tuple[str, ...] = ()) -> dict[str, Any]:
    """A table's values, checked before anything computes with them.

    Parameters
    ----------
    table : the table's name (``machine``), for the errors.
    values : the table as read.
    numbers : keys whose values must be numbers (returned as float; ``require_number``), bare
        in the file's units or texts with units (``analytic.units.from_file``).
    texts : keys whose values are passed on as they are, for the design to check as choices.
    required : keys that must be present.
    also_allowed : further keys the caller has taken out of ``values`` (nested tables).

    Returns
    -------
    The checked values, keyed as ``values``.

    Raises
    ------
    DesignError
        for an unknown key, a wrong type or a value out of range; ``MissingValueError``
        for a missing required key.
    """
    reject_unknown_keys(table, values, numbers + texts + also_allowed)
    require_keys(table, values, required)
    return {key: value if key in texts else require_number(f"{table}.{key}", from_file(f"{table}.{key}", value))
            for key, value in values.items()}


def reject_unknown_keys(table: str, values: dict[str, Any], allowed: tuple[str, ...]) -> None:
    """Raise ``DesignError`` naming the first key of ``values`` not in ``allowed`` (typo guard for files).

    ``table`` is ``""`` for the file's top level.
    """
    for key in values:
        if key not in allowed:
            name = toml_key(key)
            raise DesignError(f"{table}.{name}" if table else name, values[key],
                              f"unknown key; {did_you_mean(key, allowed)}expected one of {', '.join(allowed)}")


def toml_key(key: str) -> str:
    """``key`` as a TOML file writes it: bare if it can be, else quoted with escapes, so that an
    error naming it stays on one line (a key may hold any text, a newline included)."""
    return key if _BARE_KEY.fullmatch(key) else json.dumps(key)


def read_toml(path: str | Path) -> dict[str, Any]:
    """The tables of a TOML file; ``DesignError`` (field ``file``) if it cannot be read or parsed."""
    path = Path(path)
    try:
        with path.open("rb") as handle:
            return tomllib.load(handle)
    except tomllib.TOMLDecodeError as error:
        raise DesignError("file", str(path), f"not valid TOML: {error}") from None
    except OSError as error:
        raise DesignError("file", str(path), f"cannot be read: {error.strerror}") from None
