"""The design fields the page shows: grouped, explained, with their kinds and the units each system shows them in."""

from __future__ import annotations

import dataclasses
import functools
import math
from typing import Any

from analytic.aero import DRAG_MODELS
from analytic.design import BUILT_KINDS, FRICTIONS, DesignError, MOBILITIES, Base, Environment, Losses, Machine, Projectile
from analytic.geometry import RELEASE_RULES
from analytic.result import PEAK_NAMES
from analytic.units import ACCELERATION_G, ANGLE, FIELD_KINDS, registry

#: Each group of fields, its table and its fields with a line a builder reads (file units: SI, degrees).
GROUPS = (
    ("Machine", "machine", (
        ("kind", "The machine: hinged (the counterweight hangs from a hinge on the short arm), fixed "
                 "(the counterweight bolted to the short arm, no link) or floating-arm (bolted, riding a "
                 "vertical guide while the axle rolls on a horizontal track)."),
        ("pivot_height", "Height of the axle above the base."),
        ("arm_long", "Axle to the sling end of the arm (the long arm)."),
        ("arm_short", "Axle to the counterweight hinge (the short arm)."),
        ("arm_mass", "Mass of the arm alone."),
        ("arm_cg", "Axle to the arm's centre of mass, toward the long end (negative: on the short side)."),
        ("arm_inertia", "The arm's moment of inertia about its own centre of mass."),
        ("counterweight_mass", "Mass of the counterweight box or weight."),
        ("counterweight_link", "Hinge to the counterweight's centre (how far it hangs; hinged machines only)."),
        ("counterweight_inertia", "The counterweight's moment of inertia about its own centre."),
        ("sling_length", "Arm tip to the projectile's centre, along the sling."),
        ("sling_mass", "Mass of the sling's cords, as a uniform rod from the arm tip to the projectile; it stays "
                       "on the arm at release and keeps its energy (empty: 0, a massless sling)."),
        ("pouch_mass", "Mass of the pouch, a small mass at the projectile's centre until release; then it stays "
                       "on the sling's end, with its energy (empty: 0, no pouch to carry)."),
        ("release_angle", "When the sling lets go: the projectile's flight direction above horizontal "
                          "(rule velocity), or the sling-to-arm angle (rule sling). The pin's setting. "
                          "Not used by rule ideal."),
        ("release_rule", "What the release angle measures: velocity direction, or sling-to-arm angle; or "
                         "ideal: release at the instant that throws farthest (its launch angle is the pin "
                         "to set for rule velocity)."),
    )),
    ("Projectile", "projectile", (
        ("mass", "Mass of the projectile."),
        ("diameter", "Diameter of the (spherical) projectile; sets its drag area."),
        ("drag", "The drag law: none, a constant coefficient, a smooth sphere or a golf ball."),
        ("drag_coefficient", "Cd of the constant drag law (only with drag = constant)."),
        ("drag_factor", "A multiplier on the drag force of any law (1: as the law gives)."),
    )),
    ("Environment", "environment", (
        ("gravity", "Acceleration of gravity."),
        ("air_density", "Density of the air (1.225 kg/m^3 at sea level, 15 C)."),
        ("air_viscosity", "Dynamic viscosity of the air; sets the Reynolds number of the drag laws."),
        ("wind_speed", "Horizontal wind, positive toward the target."),
        ("target_height", "Height of the target above the base (negative: a pit below it); the range is "
                          "measured where the projectile comes down to it (empty: 0, the base's level)."),
    )),
    ("Base", "base", (
        ("mobility", "Fixed: the frame is bolted down. Rolling: it rides on wheels and moves as the arm swings."),
        ("mass", "Mass of the rolling frame (required when rolling)."),
        ("trough_height", "Height above the base of the trough the projectile starts on and slides along "
                          "until lift-off, the long arm's tip resting at its level (0: on the base). "
                          "The shot lands on the base."),
    )),
    ("Losses", "losses", (
        ("axle_friction", "Coulomb coefficient of the axle in its bearing (0: frictionless)."),
        ("axle_radius", "Radius of the axle: friction torque = coefficient x radius x axle load."),
        ("hinge_friction", "Coulomb coefficient of the counterweight's hinge."),
        ("hinge_radius", "Radius of the hinge pin."),
        ("base_friction", "Coulomb coefficient of the projectile sliding on the base before lift-off."),
        ("axle_static_friction", "Static coefficient of the axle (empty: the kinetic one)."),
        ("hinge_static_friction", "Static coefficient of the hinge (empty: the kinetic one)."),
        ("base_static_friction", "Static coefficient of the projectile on the base (empty: the kinetic one)."),
        ("guide_friction", "Coulomb coefficient of the counterweight on its guide (floating arm only)."),
        ("track_friction", "Coulomb coefficient of the axle's carriage on its track (floating arm only)."),
        ("guide_static_friction", "Static coefficient of the guide (empty: the kinetic one)."),
        ("track_static_friction", "Static coefficient of the track (empty: the kinetic one)."),
    )),
)

#: Choices of the fields that are not numbers.
CHOICES = {"machine.kind": BUILT_KINDS, "machine.release_rule": RELEASE_RULES, "projectile.drag": tuple(DRAG_MODELS),
           "base.mobility": MOBILITIES}

#: Units shown in the imperial system for each kind of field (label, pint's spelling); a kind not
#: listed is shown as in files (degrees, pure numbers, viscosity).
IMPERIAL = {"length": ("ft", "ft"), "mass": ("lb", "lb"), "moment of inertia": ("lb ft²", "lb * ft ** 2"),
            "density": ("lb/ft³", "lb / ft ** 3"), "acceleration": ("ft/s²", "ft / s ** 2"),
            "speed": ("ft/s", "ft / s"), "force": ("lbf", "lbf"), "energy": ("ft lbf", "ft * lbf"),
            "moment": ("ft lbf", "ft * lbf"), "stress (MPa)": ("psi", "psi"),
            "viscosity": ("lb/(ft s)", "lb / ft / s")}
#: The units each field is shown in, metric, by kind (file units but friendlier labels).
METRIC_LABELS = {"moment": "N m", "moment of inertia": "kg m²", "density": "kg/m³", "acceleration": "m/s²", "speed": "m/s",
                 "viscosity": "Pa s", "angle": "deg"}


def _factor(si: str, unit: str) -> float:
    """How many ``unit`` make one ``si`` (pint)."""
    return float(registry().Quantity(1.0, si).to(unit).magnitude)


def units_table() -> dict[str, Any]:
    """For each kind: the label in each system and the factor from the file unit to it."""
    # the page receives values in file units, SI but for angles: a projectile's limit, written in g in
    # files (``ACCELERATION_G``), is an acceleration the page receives in m/s^2 as gravity's
    kinds = {kind.name: kind.file_unit for kind in FIELD_KINDS.values() if kind is not ACCELERATION_G}
    kinds.update({"energy": "J"})
    # a summary row's units that no system changes (``analytic.units.SHOWN_KINDS``)
    kinds.update({"time": "s", "percent": "%", "g": "g", "stress (MPa)": "MPa"})
    table = {}
    for name, si in kinds.items():
        metric = METRIC_LABELS.get(name, si)
        imperial = IMPERIAL.get(name)
        table[name] = {"metric": {"label": metric, "factor": 1.0},
                       "imperial": ({"label": metric, "factor": 1.0} if imperial is None
                                    else {"label": imperial[0], "factor": _factor(si, imperial[1])})}
    return table


def fields_table() -> list[dict[str, Any]]:
    """The groups of fields the page builds its form from (``GET /api/meta``)."""
    groups = []
    for title, table, fields in GROUPS:
        rows = []
        for key, help_text in fields:
            name = f"{table}.{key}"
            row = {"name": name, "key": key, "help": help_text}
            if name in CHOICES:
                row["choices"] = list(CHOICES[name])
            else:
                row["kind"] = FIELD_KINDS[key].name
            if name in SPANS:
                row["span"] = list(SPANS[name])
            if name in ZERO_SPANS:
                row["zero_span"] = list(ZERO_SPANS[name])
            row.update(field_default(table, key))
            rows.append(row)
        groups.append({"title": title, "table": table, "fields": rows})
    return groups


#: Slider spans, file units, of the fields whose span does not follow from their value (the page
#: spans any other around its value): angles, wind and target heights that may be negative, and
#: the coefficients and factors, which are pure numbers of their own scale.
SPANS = {
    "machine.release_angle": (-89, 89), "environment.wind_speed": (-20, 20), "environment.target_height": (-10, 20),
    **{f"losses.{name}": (0, 1) for name in (
        "axle_friction", "hinge_friction", "base_friction", "axle_static_friction", "hinge_static_friction",
        "base_static_friction", "guide_friction", "track_friction", "guide_static_friction",
        "track_static_friction")},
    "projectile.drag_factor": (0, 3),
    # on the arm: from the short arm's end to the long arm's (``analytic.design.Machine``'s rule)
    "machine.arm_cg": ("-machine.arm_short", "machine.arm_long"),
}
#: Slider spans, file units, of fields at zero (or not set): a few centimetres of pin, and a sling or pouch
#: up to as heavy as what it throws. A field named in a span stands for its value; a zero value of any
#: other field spans 0 to 1.
ZERO_SPANS = {"losses.axle_radius": (0, 0.1), "losses.hinge_radius": (0, 0.1),
              "machine.sling_mass": (0, "projectile.mass"), "machine.pouch_mass": (0, "projectile.mass")}

#: Each table's dataclass: what a design file leaves out takes its defaults.
TABLES = {"machine": Machine, "projectile": Projectile, "environment": Environment, "base": Base, "losses": Losses}
#: Fields whose default is another field's value: each static coefficient is its kinetic one (``Losses.static``).
DEFAULT_FROM = {f"losses.{name}_static_friction": f"losses.{name}_friction" for name in FRICTIONS}


def field_default(table: str, key: str) -> dict[str, Any]:
    """What the field ``table.key`` is when a design leaves it out: ``{"default": value}`` (file units),
    ``{"default_from": field}`` (that field's value), or ``{}`` (no default: required, or unused)."""
    name = f"{table}.{key}"
    if name in DEFAULT_FROM:
        return {"default_from": DEFAULT_FROM[name]}
    declared = next(f for f in dataclasses.fields(TABLES[table]) if f.name == key)
    if declared.default is dataclasses.MISSING or declared.default is None or not _files_may_leave_out(name):
        return {}
    kind = FIELD_KINDS.get(key)
    value = declared.default
    return {"default": math.degrees(value) if kind is ANGLE and isinstance(value, float) else value}


@functools.cache
def _files_may_leave_out(name: str) -> bool:
    """Whether a design file may leave ``name`` out (some fields with a default in ``analytic.design``,
    the drag law, a file must give): the built-in design's tables without it are read."""
    from analytic.design_file import default_design, design_from_dict, design_to_dict

    table, key = name.split(".")
    layout = design_to_dict(default_design())
    layout.get(table, {}).pop(key, None)
    try:
        design_from_dict(layout)
    except DesignError:
        return False
    return True


def loads_table() -> list[dict[str, Any]]:
    """The peak loads a what-if sweeps: name, the label on each kind of machine, and the kind of the
    unit it is shown in (``analytic.summary``'s, the projectile's acceleration in g)."""
    from analytic.summary import SHOWN_PEAK_UNITS, peak_label_of_kind
    from analytic.units import SHOWN_KINDS

    return [{"name": name, "labels": {kind: peak_label_of_kind(name, kind) for kind in BUILT_KINDS},
             "kind": SHOWN_KINDS[SHOWN_PEAK_UNITS[name]]} for name in PEAK_NAMES]

