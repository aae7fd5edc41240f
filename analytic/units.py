"""Values with units at the edge (files, command lines, printed tables): pint outside, SI and radians inside.

A value in a design or problem file may be a bare number, in the file's own
units (SI, angles in degrees), or a text with units, ``"61 cm"``,
``"14 lb"``, ``"43.4 deg"``, ``"1.2 kg/m^3"``, that pint reads and
converts to the file's units before anything else sees it. Every field's
kind (a length, a mass, ...) is known here by its key, so a unit of the
wrong kind (``sling_length = "3 kg"``) is refused naming the field, the
value and the kind expected. Output can be shown in metric or imperial
units (``display``); the model never sees any of it.

pint is imported only when a text value or an imperial table needs it: a
unit registry takes a moment to build, and a file of bare numbers needs none.
"""

from __future__ import annotations

import functools
import math
import os
import sys
import threading
from pathlib import Path
from typing import Any, NamedTuple

from analytic.design import DesignError
from analytic.suggest import did_you_mean


class Kind(NamedTuple):
    """What a field measures: its name for messages, pint's dimensionality, its unit in
    files (SI; degrees for angles) and an example for messages."""

    name: str
    dimensionality: str
    file_unit: str
    example: str


LENGTH = Kind("length", "[length]", "m", '"61 cm" or "2 ft"')
MASS = Kind("mass", "[mass]", "kg", '"6.5 kg" or "14 lb"')
ANGLE = Kind("angle", "", "deg", '"43.4 deg" or "0.76 rad"')
INERTIA = Kind("moment of inertia", "[mass] * [length] ** 2", "kg * m ** 2", '"0.0093 kg m^2"')
DENSITY = Kind("density", "[mass] / [length] ** 3", "kg / m ** 3", '"1.2 kg/m^3"')
VISCOSITY = Kind("viscosity", "[mass] / [length] / [time]", "Pa * s", '"1.81e-5 Pa s"')
ACCELERATION = Kind("acceleration", "[length] / [time] ** 2", "m / s ** 2", '"9.81 m/s^2" or "50 g0"')
SPEED = Kind("speed", "[length] / [time]", "m / s", '"3 m/s" or "10 ft/s"')
FORCE = Kind("force", "[length] * [mass] / [time] ** 2", "N", '"200 N" or "45 lbf"')
MOMENT = Kind("moment", "[length] ** 2 * [mass] / [time] ** 2", "N * m", '"40 N m" or "30 ft lbf"')
NUMBER = Kind("pure number", "", "", "0.47")
#: An acceleration written in g (standard gravity, pint's ``g0``): a projectile's limit.
ACCELERATION_G = Kind("acceleration", "[length] / [time] ** 2", "g0", '"150 g0" or "1470 m/s^2"')
STRESS = Kind("stress", "[mass] / [length] / [time] ** 2", "Pa", '"59 MPa" or "8600 psi"')

#: Units a builder writes, offered for a mistyped one ("6 ftt": did you mean 'ft'?).
COMMON_UNITS = ("m", "cm", "mm", "km", "in", "inch", "ft", "foot", "feet", "yd", "mi", "kg", "g", "lb", "oz",
                "N", "kN", "lbf", "s", "ms", "deg", "degree", "rad", "m/s", "ft/s", "mph", "g0", "Pa")

#: The kind of every numeric key of a design or problem file (the key alone decides it;
#: a problem's ``lower``, ``upper`` and ``value`` take their table's, see ``kind_of``).
FIELD_KINDS = {
    "pivot_height": LENGTH, "arm_long": LENGTH, "arm_short": LENGTH, "arm_cg": LENGTH, "clearance": LENGTH,
    "counterweight_link": LENGTH, "sling_length": LENGTH, "diameter": LENGTH, "width": LENGTH,
    "depth": LENGTH, "max_footprint": LENGTH, "max_height": LENGTH, "axle_radius": LENGTH,
    "min_range": LENGTH, "trough_height": LENGTH, "target_height": LENGTH,
    "arm_mass": MASS, "counterweight_mass": MASS, "mass": MASS, "frame_mass": MASS,
    "sling_mass": MASS, "pouch_mass": MASS,
    "arm_inertia": INERTIA, "counterweight_inertia": INERTIA,
    "release_angle": ANGLE, "starting_angle": ANGLE,
    "drag_coefficient": NUMBER, "drag_factor": NUMBER, "axle_friction": NUMBER, "hinge_friction": NUMBER, "base_friction": NUMBER,
    "axle_static_friction": NUMBER, "hinge_static_friction": NUMBER, "base_static_friction": NUMBER,
    "guide_friction": NUMBER, "track_friction": NUMBER, "guide_static_friction": NUMBER,
    "track_static_friction": NUMBER,
    "hinge_radius": LENGTH,
    "gravity": ACCELERATION, "max_projectile_acceleration": ACCELERATION,
    "air_density": DENSITY, "density": DENSITY,
    "air_viscosity": VISCOSITY,
    "wind_speed": SPEED,
    "max_sling_tension": FORCE, "max_axle_load": FORCE, "max_hinge_load": FORCE,
    "max_arm_bending_moment": MOMENT,
    "max_acceleration": ACCELERATION_G, "strength": STRESS, "min_arm_safety_factor": NUMBER,
}
_BOUND_KEYS = ("lower", "upper", "value")


_REGISTRY_LOCK = threading.Lock()


@functools.cache
def _built_registry():
    import pint

    return pint.UnitRegistry(cache_folder=unit_cache_folder())


def registry():
    """pint's unit registry, built once: 0.4 s, 0.1 s from its disk cache (``unit_cache_folder``).

    Built under a lock: threads that first read a unit at the same time (a server's requests)
    must share one registry, since a quantity of one registry is not a quantity of another.
    """
    with _REGISTRY_LOCK:
        return _built_registry()


def unit_cache_folder() -> Path | None:
    """Where pint caches its parsed definitions: inside this Python environment, or nowhere.

    Not pint's shared per-user folder (``cache_folder=":auto:"``): pint 0.25's
    cache keeps the path of the definition files it was first built from, and
    a cache shared by several environments fails in all of them once that one
    is deleted (seen: every value with a unit refused, pint raising
    FileNotFoundError on a removed checkout's ``.venv``). An environment
    that cannot be written (a system install) gets no cache.
    """
    folder = Path(sys.prefix) / "var" / "cache" / "pint"
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:
        return None
    return folder if os.access(folder, os.W_OK) else None


def kind_of(field: str) -> Kind | None:
    """The kind of a file field named ``table.key`` (``variables.sling_length.lower``: a length)."""
    parts = field.split(".")
    key = parts[-2] if parts[-1] in _BOUND_KEYS and len(parts) > 1 else parts[-1]
    return FIELD_KINDS.get(key)


def from_file(field: str, value: Any) -> Any:
    """A file value in the file's units: a text with units converted, anything else as it is
    (for the design's checks to judge: ``analytic.design.require_number``).

    Parameters
    ----------
    field : the value's place, ``table.key``; its key decides the kind (``FIELD_KINDS``).
    value : as read from the file.

    Raises
    ------
    DesignError
        for a text without a unit ("must be a number"), with an unknown unit, or with a
        unit of the wrong kind, naming the field, the value and the kind expected.
    """
    if not isinstance(value, str):
        return value
    from analytic.design import require_number

    kind = kind_of(field)
    if kind is None:
        raise DesignError(field, value, "must be a number")
    try:
        return require_number(field, parse(field, value, kind))
    except DesignError as error:   # name the value as the file has it
        raise DesignError(field, value, error.reason) from None


def parse(field: str, text: str, kind: Kind) -> float | int:
    """The quantity ``text`` in ``kind.file_unit``, as a float; ``DesignError`` naming ``field`` otherwise."""
    import pint

    expected = f"expected a {kind.name}, e.g. {kind.example}"
    if not any(character.isdigit() for character in text):   # pint reads "m" alone as 1 m
        raise DesignError(field, text, f"must be a number, or a {kind.name} with a unit: there is no number; "
                                       f"{expected}")
    units = registry()
    try:
        quantity = units.Quantity(text)
    except pint.UndefinedUnitError as error:
        names = ", ".join(repr(name) for name in error.unit_names)
        guess = did_you_mean(error.unit_names[0], COMMON_UNITS) if error.unit_names else ""
        raise DesignError(field, text, f"must be a number, or a {kind.name} with a unit: unknown unit {names}; "
                                       f"{guess}{expected}") from None
    except Exception:   # pint's parser raises assorted errors for text that is no expression at all
        raise DesignError(field, text, f"must be a number, or a {kind.name} with a unit; {expected}") from None
    if not isinstance(quantity, units.Quantity):   # a bare number in text
        quantity = units.Quantity(quantity)
    if quantity.unitless:
        if kind is NUMBER:
            raise DesignError(field, text, "must be a number")
        raise DesignError(field, text, f"must be a number (in {kind.file_unit}), or a {kind.name} with a unit; "
                                       f"{expected}")
    if kind is ANGLE:
        compatible = quantity.dimensionless and quantity.units != units.dimensionless
    else:
        compatible = kind.dimensionality != "" and quantity.check(kind.dimensionality)
    if not compatible:
        found = "a pure number" if quantity.dimensionless else f"{quantity.dimensionality}"
        raise DesignError(field, text, f"has the wrong kind of unit ({found}); {expected}")
    magnitude = quantity.to(kind.file_unit).magnitude
    if isinstance(magnitude, bool) or not isinstance(magnitude, (int, float)):
        raise DesignError(field, text, "must be a real number with a unit")
    return magnitude   # an int beyond any float is left for require_number to refuse by its size


def to_file_text(value: float, kind: Kind, unit: str | None = None) -> str:
    """``value`` (in ``kind.file_unit``) as a text with units for a file, in ``unit`` (pint's
    spelling) or the file's own; ``parse`` reads it back (exactly in the file's own unit)."""
    if unit is None or unit == kind.file_unit:
        return f"{value!r} {kind.file_unit}"
    converted = registry().Quantity(value, kind.file_unit).to(unit).magnitude
    return f"{float(converted)!r} {unit}"


# --------------------------------------------------------------------------- #
# Showing numbers
# --------------------------------------------------------------------------- #

#: Unit systems for printed output (``--units``): SI unit -> (shown unit, pint's spelling).
SYSTEMS = {
    "metric": {},
    "imperial": {"m": ("ft", "ft"), "kg": ("lb", "lb"), "m/s": ("ft/s", "ft / s"), "N": ("lbf", "lbf"),
                 "m/s^2": ("ft/s^2", "ft / s ** 2"), "J": ("ft lbf", "ft * lbf"), "N m": ("ft lbf", "ft * lbf"),
                 "MPa": ("psi", "psi")},
}
_PINT_SI = {"m": "m", "kg": "kg", "m/s": "m / s", "N": "N", "m/s^2": "m / s ** 2", "J": "J", "N m": "N * m", "MPa": "MPa"}


def display(value: float, unit: str, system: str = "metric") -> tuple[float, str]:
    """``value`` in the SI ``unit`` as it is shown in ``system``: ``(number, unit label)``.

    Units the system leaves alone (s, deg, %, and everything in ``metric``) pass unchanged.
    """
    if system not in SYSTEMS:
        raise ValueError(f"units = {system!r}: must be one of {', '.join(SYSTEMS)}")
    shown = SYSTEMS[system].get(unit)
    if shown is None or value is None or not math.isfinite(value):
        return value, (unit if shown is None else shown[0])
    return float(registry().Quantity(value, _PINT_SI[unit]).to(shown[1]).magnitude), shown[0]


#: The SI unit (a key of ``SYSTEMS``' tables) each kind is shown in, for kinds a system changes.
_SHOWN_AS = {LENGTH: "m", MASS: "kg", SPEED: "m/s", FORCE: "N", ACCELERATION: "m/s^2", MOMENT: "N m"}
#: The kinds whose unit a system decides: what a file's dominant units are counted on (``written_system``).
SYSTEM_KINDS = tuple(_SHOWN_AS)


def from_display(value: float, unit: str, system: str = "metric") -> float:
    """The inverse of ``display``: ``value`` as shown in ``system`` for the SI ``unit``, back in ``unit``."""
    shown = SYSTEMS[system].get(unit)
    if shown is None or not math.isfinite(value):
        return value
    # 12 significant digits: what a typed number carries, without the conversion's last-bit noise
    return float(f"{registry().Quantity(value, shown[1]).to(_PINT_SI[unit]).magnitude:.12g}")


def command_line_value(name: str, text: str, kind: Kind, system: str = "metric") -> float:
    """A value typed on a command line, in ``kind.file_unit``: a text with units as ``parse`` reads
    it, a bare number in ``system``'s units (``--units imperial``: ``150`` is 150 ft)."""
    try:
        number = float(text)
    except ValueError:
        return parse(name, text, kind)
    unit = _SHOWN_AS.get(kind)
    return number if unit is None else from_display(number, unit, system)


def json_units(system: str) -> dict:
    """The ``units`` block a ``--json`` object gains when ``system`` is not metric: what the
    numbers are in (always SI, angles in degrees) and how the text output showed them."""
    return {"json": "SI (angles in degrees)", "shown": system,
            "shown_as": {si: shown for si, (shown, _) in SYSTEMS[system].items()}}


def with_units(obj: dict, system: str) -> dict:
    """``obj`` (a ``--json`` object) with a ``units`` block (``json_units``) if ``system`` is imperial;
    as it is for metric, so that its keys stay as they were."""
    return obj if system == "metric" else {**obj, "units": json_units(system)}


#: Units that mark a value as written in imperial units (pint's names).
_IMPERIAL_NAMES = {"foot", "inch", "yard", "mile", "pound", "ounce", "stone", "pound_force", "slug",
                   "mile_per_hour", "foot_per_second", "kip"}


def written_system(texts: list[str]) -> str:
    """``imperial`` if more of ``texts`` (a file's values with units) are in imperial units than in
    any other, else ``metric``. A text pint cannot read counts for neither."""
    imperial = metric = 0
    for text in texts:
        try:
            quantity = registry().Quantity(text)
            names = {str(name) for name in getattr(quantity, "_units", {})}
        except Exception:
            continue
        if names & _IMPERIAL_NAMES:
            imperial += 1
        elif names:
            metric += 1
    return "imperial" if imperial > metric else "metric"


class Written(str):
    """A file's value as the user wrote it, with its value in file units in brackets
    (``"-200 lb" (-90.7185 kg)``): what a ``DesignError`` echoes for a value given with a unit."""

    def __new__(cls, text: str, value: float | str, kind: Kind):
        inside = value if isinstance(value, str) else f"{value:.6g} {kind.file_unit}"
        return super().__new__(cls, f'"{text}" ({inside})')

    def __repr__(self) -> str:
        return str(self)


#: The kind (``workbench``'s unit tables' names) of each unit a summary row is in
#: (``analytic.summary.Row.unit``): the SI ones a system converts, and those no system changes.
SHOWN_KINDS = {"m": LENGTH.name, "kg": MASS.name, "m/s": SPEED.name, "N": FORCE.name, "m/s^2": ACCELERATION.name,
               "J": "energy", "N m": MOMENT.name, "s": "time", "deg": ANGLE.name, "%": "percent", "g": "g",
               "MPa": "stress (MPa)", "": NUMBER.name}
