"""Design files: TOML in and out (SI units, angles in degrees), every value checked before use."""

from __future__ import annotations

import dataclasses
import math
import tomllib
from pathlib import Path
from typing import Any

from analytic.design import (BeamArm, Design, DesignError, Environment, Machine, Projectile,
                             paper_geometry)

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
