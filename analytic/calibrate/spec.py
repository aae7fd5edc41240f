"""The calibration file: what to fit and the shots measured, every value checked before any shot.

```toml
fit = ["losses.axle_friction"]          # dotted design fields, or drag_factor, release_angle_offset
design = "prototype-61.toml"            # optional: the design of every shot that names none
[[shot]]
design = "prototype-61.toml"            # optional with the shared design above; relative to this file
range = 26.8                            # m
range_uncertainty = 0.5                 # m, one standard deviation
"machine.counterweight_mass" = "6 kg"   # optional: this shot's setting of any design field
# release_time, liftoff_time (s), release_angle (deg): optional, each with its _uncertainty
# track = "shot1.csv" with track_point, track_length_unit, ...: a measured track, beside or
# instead of the range (analytic.calibrate.track)
[given]                                 # optional: fields set on every shot's design, not fitted
"losses.axle_radius" = 0.0064
[start]                                 # optional: where the fit starts (default: the first design's value)
"losses.axle_friction" = 0.1
[bounds]                                # optional: narrower than the field's own validity
"losses.axle_friction" = [0.0, 1.0]
```

One set of parameters applies to every shot; each shot's design file, with
the shot's own settings (dotted field names, quoted or as sub-tables) on top,
gives everything else. Values are in design-file units (SI, degrees), bare
or as texts with units (``"26.8 m"``, ``"350 ms"``, ``"61 deg"``). Every
error is a ``DesignError`` naming the field (``shot[2].range_uncertainty``,
shots counted from 1), its value and the reason.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from analytic.calibrate.track import TRACK_KEYS, Track, track_spec
from analytic.design import (
    FRICTION_JOINTS,
    MAX_MAGNITUDE,
    MAX_SLING_RELEASE_ANGLE,
    MAX_VELOCITY_RELEASE_ANGLE,
    Design,
    DesignError,
    require_number,
)
from analytic.design_file import (
    load_design,
    read_toml,
    reject_unknown_keys,
    require_table,
)
from analytic.fields import Field, field
from analytic.units import ANGLE, LENGTH, NUMBER, Kind, parse

TIME = Kind("time", "[time]", "s", '"0.35 s" or "350 ms"')

#: What a shot may measure: name -> (kind, unit). Every one is predicted by the model
#: (``analytic.calibrate.fit.predict``): the range from the pivot's place at rest;
#: release and lift-off times from the firing instant (the trigger's release); the
#: release angle as the direction of the projectile's velocity at release above the
#: horizontal (the paper's "releasing at 61 degrees", section IV).
QUANTITIES: dict[str, tuple[Kind, str]] = {"range": (LENGTH, "m"), "release_time": (TIME, "s"),
                                           "liftoff_time": (TIME, "s"), "release_angle": (ANGLE, "deg")}
#: Parameters that are not a design field: name -> (the field they stand for, or None, unit).
#: ``drag_factor`` is ``projectile.drag_factor`` (every drag model's force times it);
#: ``release_angle_offset`` is added to every shot's ``machine.release_angle``.
DRAG_FACTOR, RELEASE_ANGLE_OFFSET = "drag_factor", "release_angle_offset"
_TOP_KEYS = ("fit", "design", "shot", "given", "start", "bounds")
#: Where a loss coefficient starts when every design leaves it at 0: a middling Coulomb
#: coefficient (greased steel 0.05-0.15, dry wood on wood 0.25-0.5).
DEFAULT_LOSS_START = 0.1
#: Fields that may be zero (every other numeric field must be positive, ``analytic.design``);
#: ``_FREE`` ones may be negative too. Release angles are bounded by their rule.
_NON_NEGATIVE = ("machine.arm_inertia", "machine.counterweight_inertia", "environment.air_density",
                 "machine.sling_mass", "machine.pouch_mass")
#: Where a sling's or a pouch's mass starts when every design leaves it at 0 (massless), as a
#: fraction of the first shot's projectile: inside its bounds, and of the size a sling has.
SLING_MASS_START = 0.2
_FREE = ("machine.arm_cg", "environment.wind_speed")


@dataclass(frozen=True)
class Parameter:
    """One fitted parameter.

    Attributes
    ----------
    name : as the calibration file names it (``losses.axle_friction``, ``drag_factor``).
    unit : its unit in files and reports (``deg`` for angles, ``""`` for pure numbers).
    field : the design field it sets on every shot, or None for ``release_angle_offset``.
    start : where the fit starts, file units.
    lower, upper : bounds, file units: the field's validity (coefficients >= 0, lengths and
        masses > 0, release angles inside their rule's limits), or the file's narrower ones.
    scale : its typical size, file units: the finite-difference steps and the fit's
        variable scaling are fractions of it.
    """

    name: str
    unit: str
    field: Field | None
    start: float
    lower: float
    upper: float
    scale: float


@dataclass(frozen=True)
class Measurement:
    """One measured quantity of a shot (``QUANTITIES``), file units, with one standard deviation."""

    quantity: str
    value: float
    uncertainty: float

    @property
    def unit(self) -> str:
        return QUANTITIES[self.quantity][1]


@dataclass(frozen=True)
class ShotSpec:
    """One measured shot: its design (as read, with the shot's settings, before ``given`` and the
    parameters), its measurements, and its settings (field name -> file units; ``written``: the
    same as the file wrote them, for names and fitted files)."""

    number: int
    design_file: str
    design: Design
    measurements: tuple[Measurement, ...]
    settings: dict[str, float] = dataclasses.field(default_factory=dict)
    written: dict[str, Any] = dataclasses.field(default_factory=dict)
    track: Track | None = None

    @property
    def label(self) -> str:
        return f"shot[{self.number}]"


@dataclass(frozen=True)
class CalibrationSpec:
    """A checked calibration file.

    Attributes
    ----------
    path : the file.
    parameters : the fitted parameters, in the file's order.
    shots : the measured shots, in the file's order.
    given : design field name -> value (file units) set on every shot's design.
    """

    path: Path
    parameters: tuple[Parameter, ...]
    shots: tuple[ShotSpec, ...]
    given: dict[str, float]

    @property
    def measurements(self) -> int:
        """Measured numbers: each quantity, and each coordinate of each track's point."""
        return sum(len(shot.measurements) + (2 * shot.track.points if shot.track else 0) for shot in self.shots)

    @property
    def time_origins(self) -> int:
        """Tracks, each with its time origin fitted beside the parameters."""
        return sum(shot.track is not None for shot in self.shots)

    def design_at(self, shot: ShotSpec, values) -> Design:
        """``shot``'s design with ``given`` and the parameters at ``values`` (file units, in order).

        Raises
        ------
        DesignError
            if the design cannot be built there (a cross-field rule, e.g. the counterweight
            reaching the base).
        """
        settings = dict(self.given)
        offset = 0.0
        for parameter, value in zip(self.parameters, values, strict=True):
            if parameter.field is None:
                offset += float(value)
            else:
                settings[parameter.field.name] = float(value)
        design = with_fields(shot.design, settings)
        if offset:
            machine = dataclasses.replace(design.machine, release_angle=design.machine.release_angle
                                          + math.radians(offset))
            design = dataclasses.replace(design, machine=machine)
        return design


def with_fields(design: Design, settings: dict[str, float]) -> Design:
    """``design`` with several fields set at once (file units), one replacement per table.

    At once, because the losses' rules tie fields together (a coefficient needs
    its radius).
    """
    tables: dict[str, dict[str, float]] = {}
    for name, value in settings.items():
        target = field(name)
        inner = math.radians(value) if target.kind is ANGLE else float(value)
        tables.setdefault(target.table, {})[target.key] = inner
    parts = {table: dataclasses.replace(getattr(design, table), **values) for table, values in tables.items()}
    return dataclasses.replace(design, **parts)


def load_calibration(path: str | Path) -> CalibrationSpec:
    """Read and check a calibration file: its designs built, every parameter usable on every shot.

    Raises
    ------
    DesignError
        naming the field, its value and the reason: an unknown key, a missing or unreadable
        design, a design that cannot be built (with ``given`` and the starting values), a
        parameter that cannot be fitted (unknown, not a number, not used by a design), a
        missing, non-positive or non-numeric uncertainty, a measurement without its
        uncertainty or the reverse, fewer measurements than parameters, bad start or bounds.
    """
    path = Path(path)
    data = read_toml(path)
    reject_unknown_keys("", data, _TOP_KEYS)
    names = _fit_names(data.get("fit"))
    raw_shots = data.get("shot")
    if raw_shots is None:
        raise DesignError("shot", None, "no shots: give at least one [[shot]] table")
    if not isinstance(raw_shots, list) or not all(isinstance(s, dict) for s in raw_shots) or not raw_shots:
        raise DesignError("shot", raw_shots, "must be [[shot]] tables, at least one")
    shared = data.get("design")
    if shared is not None and (not isinstance(shared, str) or not shared):
        raise DesignError("design", shared, "must be a file name (text), relative to this file")
    fitted = {_target_of(n) for n in names}
    shots = tuple(_shot(i, raw, path.parent, shared, fitted) for i, raw in enumerate(raw_shots, 1))
    given = {}
    for name, value in dotted_table("given", data.get("given")).items():
        target = field(name)
        if any(_target_of(n) == target.name for n in names):
            raise DesignError(f"given.{name}", value, "is also fitted: give it in [start] instead")
        for shot in shots:
            if target.name in shot.settings:
                raise DesignError(f"given.{name}", value, f"{shot.label} sets it too: give it in one place")
        given[name] = require_number(f"given.{name}", _value(f"given.{name}", value, target.kind))
    starts = dotted_table("start", data.get("start"))
    bounds = dotted_table("bounds", data.get("bounds"))
    for table, entries in (("start", starts), ("bounds", bounds)):
        for name in entries:
            if name not in names:
                raise DesignError(f"{table}.{name}", entries[name], f"not a fitted parameter; fit is {names}")
    spec = CalibrationSpec(path, (), shots, given)
    for shot in shots:   # given alone, before any parameter: its errors are its own
        _build(spec, shot, (), f"{shot.label}.design")
    parameters = tuple(_parameter(name, spec, starts.get(name), bounds.get(name)) for name in names)
    spec = dataclasses.replace(spec, parameters=parameters)
    if spec.measurements - spec.time_origins < len(parameters):
        raise DesignError("fit", names, f"{len(parameters)} parameters but only {spec.measurements} "
                                        f"measurement{'s' if spec.measurements != 1 else ''}: "
                                        f"a fit needs at least as many measurements as parameters")
    for shot in shots:
        _build(spec, shot, [p.start for p in parameters], f"{shot.label}.design")
    return spec


def _fit_names(value: Any) -> list[str]:
    if value is None:
        raise DesignError("fit", None, 'required: the parameters to fit, e.g. fit = ["losses.axle_friction"]')
    if not isinstance(value, list) or not value:
        raise DesignError("fit", value, "must be a list of parameter names, at least one")
    for name in value:
        if not isinstance(name, str):
            raise DesignError("fit", name, "must be a parameter name (text)")
    targets = [_target_of(name) for name in value]
    for i, target in enumerate(targets):
        if target in targets[:i]:
            raise DesignError("fit", value[i], "the same parameter twice")
    if RELEASE_ANGLE_OFFSET in value and "machine.release_angle" in targets:
        raise DesignError("fit", value, f"{RELEASE_ANGLE_OFFSET} and machine.release_angle together: "
                                        f"they move the same angle, so no data can tell them apart; fit one")
    return list(value)


def _target_of(name: str) -> str:
    """The design field a parameter name sets (or the pseudo-parameter's own name)."""
    if name == RELEASE_ANGLE_OFFSET:
        return name
    if name == DRAG_FACTOR:
        return "projectile.drag_factor"
    return field(name).name


def dotted_table(table: str, value: Any) -> dict[str, Any]:
    """A table keyed by dotted field names, quoted (``"losses.axle_radius" = ..``) or nested
    (``losses.axle_radius = ..``, which TOML reads as a sub-table)."""
    entries: dict[str, Any] = {}

    def walk(node: dict, prefix: str) -> None:
        for key, item in node.items():
            name = f"{prefix}{key}"
            if isinstance(item, dict):
                walk(item, f"{name}.")
            else:
                entries[name] = item

    walk(require_table(table, value, optional=True), "")
    return entries


def _value(name: str, value: Any, kind: Kind) -> Any:
    """A file value: texts with units converted to ``kind``'s file unit, anything else as it is."""
    if isinstance(value, str):
        if kind is NUMBER:
            raise DesignError(name, value, "must be a number")
        return parse(name, value, kind)
    return value


def _shot(number: int, raw: dict, folder: Path, shared: str | None, fitted: set[str]) -> ShotSpec:
    label = f"shot[{number}]"
    allowed = ("design",) + tuple(k for q in QUANTITIES for k in (q, f"{q}_uncertainty")) + TRACK_KEYS
    written = {name: value for name, value in dotted_table(label, {k: v for k, v in raw.items() if k not in allowed
                                                              and ("." in k or isinstance(v, dict))}).items()}
    reject_unknown_keys(label, {k: v for k, v in raw.items() if "." not in k and not isinstance(v, dict)}, allowed)
    design_file = raw.get("design", shared)
    if design_file is None:
        raise DesignError(f"{label}.design", None, "required: the shot's design file (relative to this file), "
                                                   "or one design for every shot at the top of the file")
    if not isinstance(design_file, str) or not design_file:
        raise DesignError(f"{label}.design", design_file, "must be a file name (text)")
    design_path = folder / design_file
    if not design_path.is_file():
        raise DesignError(f"{label}.design", design_file, f"no such file ({design_path})")
    try:
        design = load_design(design_path)
    except DesignError as error:
        raise DesignError(f"{label}.design", design_file, f"cannot be built: {error}") from None
    settings = {}
    for name, value in written.items():
        try:
            target = field(name)
        except DesignError as error:
            raise DesignError(f"{label}.{name}", value, error.reason) from None
        if target.name in fitted:
            raise DesignError(f"{label}.{name}", value, "is also fitted: a shot cannot set a fitted parameter")
        settings[target.name] = float(require_number(f"{label}.{name}", _value(f"{label}.{name}", value,
                                                                                  target.kind)))
    written = {field(name).name: value for name, value in written.items()}
    try:
        design = with_fields(design, settings)
    except DesignError as error:
        raise DesignError(f"{label}.{error.field}", error.value, f"{error.reason} (with the shot's settings "
                                                                 f"on {design_file})") from None
    measurements = []
    for quantity, (kind, unit) in QUANTITIES.items():
        key, sd_key = quantity, f"{quantity}_uncertainty"
        if key not in raw and sd_key not in raw:
            continue
        if key not in raw:
            raise DesignError(f"{label}.{sd_key}", raw[sd_key], f"an uncertainty without its measurement: give "
                                                                f"{label}.{key} too, or remove it")
        if sd_key not in raw:
            raise DesignError(f"{label}.{key}", raw[key], f"a measurement without its uncertainty: give "
                                                          f"{label}.{sd_key} ({unit}, one standard deviation)")
        value = require_number(f"{label}.{key}", _value(f"{label}.{key}", raw[key], kind))
        sd = require_number(f"{label}.{sd_key}", _value(f"{label}.{sd_key}", raw[sd_key], kind))
        if not sd > 0.0:
            raise DesignError(f"{label}.{sd_key}", raw[sd_key], "must be positive (one standard deviation)")
        if kind is TIME and not value > 0.0:
            raise DesignError(f"{label}.{key}", raw[key], "must be positive (s from the firing instant)")
        measurements.append(Measurement(quantity, float(value), float(sd)))
    track = track_spec(label, raw, folder)
    if "range" not in raw and track is None:
        raise DesignError(f"{label}.range", None, "required: the measured range (m) with range_uncertainty, "
                                                  "or a measured track (track = \"FILE.csv\")")
    return ShotSpec(number, design_file, design, tuple(measurements), settings, written, track)


def _build(spec: CalibrationSpec, shot: ShotSpec, values, where: str) -> Design:
    try:
        return spec.design_at(shot, values)
    except DesignError as error:
        at = ", ".join(f"{p.name} = {v:g}" for p, v in zip(spec.parameters, values, strict=True))
        raise DesignError(where, shot.design_file, f"cannot be built with {at or 'the given fields'}: {error}") \
            from None


def _validity(name: str, target: Field | None, spec: CalibrationSpec) -> tuple[float, float]:
    """The bounds a parameter's validity sets, file units, over every shot."""
    if target is None or target.name == "machine.release_angle":
        lower, upper = -math.inf, math.inf
        for shot in spec.shots:
            limit = math.degrees(MAX_VELOCITY_RELEASE_ANGLE if shot.design.machine.release_rule == "velocity"
                                 else MAX_SLING_RELEASE_ANGLE)
            angle = 0.0 if target is not None else math.degrees(shot.design.machine.release_angle)
            lower, upper = max(lower, -limit - angle), min(upper, limit - angle)
        return lower, upper
    if target.table == "losses" or target.name in _NON_NEGATIVE:
        return 0.0, MAX_MAGNITUDE
    if target.name in _FREE:
        return -MAX_MAGNITUDE, MAX_MAGNITUDE
    return 0.0, MAX_MAGNITUDE   # positive: the fit's iterates stay strictly inside its bounds


def _parameter(name: str, spec: CalibrationSpec, start: Any, bounds: Any) -> Parameter:
    if name == RELEASE_ANGLE_OFFSET:
        for shot in spec.shots:
            if shot.design.machine.release_rule == "ideal":
                raise DesignError("fit", name, f"{shot.label} ({shot.design_file}) has release_rule 'ideal', "
                                               f"which finds the release itself and ignores the release angle: "
                                               f"an offset to it changes nothing; leave {name} out of fit")
        target, unit, default, scale = None, "deg", 0.0, 1.0
    else:
        target = field("projectile.drag_factor" if name == DRAG_FACTOR else name)
        unit = target.unit
        values = []
        for shot in spec.shots:
            design = spec.design_at(shot, [])
            try:
                values.append(target.check(design))
            except DesignError as error:
                raise DesignError("fit", name, f"{shot.label} ({shot.design_file}) does not use it: "
                                               f"{error.reason}") from None
            _require_used(name, target, shot, design, spec.given)
        default = values[0]
        if target.table == "losses" and default == 0.0:
            default = DEFAULT_LOSS_START
        if target.name in ("machine.sling_mass", "machine.pouch_mass") and default == 0.0:
            default = SLING_MASS_START * spec.design_at(spec.shots[0], []).projectile.mass
        scale = max(abs(default), 1.0 if target.kind is ANGLE else 0.0, 0.1 if target.table == "losses" else 0.0)
        scale = scale or 1.0
    lower, upper = _validity(name, target, spec)
    if bounds is not None:
        if not (isinstance(bounds, list) and len(bounds) == 2):
            raise DesignError(f"bounds.{name}", bounds, "must be [lower, upper]")
        kind = ANGLE if unit == "deg" else (target.kind if target is not None else NUMBER)
        low, high = (require_number(f"bounds.{name}", _value(f"bounds.{name}", b, kind)) for b in bounds)
        if not low < high:
            raise DesignError(f"bounds.{name}", bounds, "the lower bound must be below the upper")
        if low < lower or high > upper:
            raise DesignError(f"bounds.{name}", bounds, f"outside the parameter's validity "
                                                        f"[{lower:g}, {upper:g}] {unit}".rstrip())
        lower, upper = float(low), float(high)
    if start is not None:
        kind = ANGLE if unit == "deg" else (target.kind if target is not None else NUMBER)
        default = require_number(f"start.{name}", _value(f"start.{name}", start, kind))
        if not lower <= default <= upper:
            raise DesignError(f"start.{name}", start, f"outside the bounds [{lower:g}, {upper:g}]")
    else:
        default = min(max(default, lower), upper)
    return Parameter(name, unit, target, float(default), float(lower), float(upper), float(scale))


def _require_used(name: str, target: Field, shot: ShotSpec, design: Design, given: dict[str, float]) -> None:
    """Refuse a parameter that cannot change this shot: a joint's coefficient without its
    radius, a drag factor without drag."""
    joint = target.key.partition("_")[0]
    if target.table == "losses" and target.key.endswith("_friction") and joint in FRICTION_JOINTS:
        radius = f"{joint}_radius"
        if given.get(f"losses.{radius}", getattr(shot.design.losses, radius)) == 0.0:
            raise DesignError("fit", name, f"{shot.label} ({shot.design_file}) has no losses.{radius}: the "
                                           f"torque is coefficient x radius x load, so give the radius (m) in "
                                           f"the design's [losses] or in this file's [given]")
    if target.key == "drag_factor" and (design.projectile.drag == "none" or design.environment.air_density == 0.0):
        raise DesignError("fit", name, f"{shot.label} ({shot.design_file}) has no drag "
                                       f"(projectile.drag = {design.projectile.drag!r}, air density "
                                       f"{design.environment.air_density:g}): a drag factor changes nothing")
