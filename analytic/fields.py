"""A design's numeric fields by their file names (``machine.counterweight_mass``), read and replaced.

What the builders' tools (``analytic.aim``, ``analytic.chart``) vary. A field
is named as in a design file, table first (``machine.release_angle``,
``projectile.mass``, ``environment.wind_speed``, ``base.mass``); a bare
machine name (``release_angle``) means the machine's. Values are in the
file's units (SI, angles in degrees): ``get`` and ``replace`` convert to and
from the design's radians, and ``replace`` builds a new design through the
design's own checks.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from analytic.design import Base, Design, DesignError, Environment, Losses, Machine, Projectile
from analytic.suggest import did_you_mean
from analytic.units import ANGLE, FIELD_KINDS, Kind

#: The tables of a design and the dataclass each holds.
_TABLES = {"machine": Machine, "projectile": Projectile, "environment": Environment, "base": Base,
           "losses": Losses}
#: Fields of those dataclasses that are not numbers (choices), refused as fields to vary.
_CHOICES = {"release_rule", "kind", "drag", "mobility", "drag_during_swing"}
#: Fields that do not change the shot (what it is judged by: ``analytic.data.strength``), not offered to vary.
_NOT_VARIED = {"arm_section", "max_acceleration"}
#: Why a tool refuses to vary ``machine.release_angle`` under the ideal rule.
IDEAL_IGNORES_RELEASE_ANGLE = ("release_rule 'ideal' finds the release itself and ignores the release angle, so "
                               "varying it changes nothing; vary another field, or set release_rule to "
                               "'velocity' (the shot's launch_angle is the pin that throws as far)")


@dataclass(frozen=True)
class Field:
    """One numeric field of a design: ``table.key``, its kind and unit in files."""

    table: str
    key: str

    @property
    def name(self) -> str:
        return f"{self.table}.{self.key}"

    @property
    def kind(self) -> Kind:
        return FIELD_KINDS[self.key]

    @property
    def unit(self) -> str:
        """Its unit in files and in the tools' output (SI; ``deg`` for angles)."""
        return "deg" if self.kind is ANGLE else self.kind.file_unit.replace(" ", "")

    @property
    def label(self) -> str:
        """Its name and unit for an axis (``axis_label``)."""
        return axis_label(self.name, self.unit)

    def get(self, design: Design) -> float | None:
        """The field's value in ``design``, in file units (None: not set, e.g. a fixed frame's mass)."""
        value = getattr(getattr(design, self.table), self.key)
        if value is None and self.key.endswith("_static_friction"):   # not given: the kinetic coefficient
            value = design.losses.static(self.key.removesuffix("_static_friction"))
        if value is None:
            return None
        return math.degrees(value) if self.kind is ANGLE else float(value)

    def check(self, design: Design) -> float:
        """The field's value in ``design`` (file units); ``DesignError`` if the design does not use it
        (a fixed frame's mass; the release angle of a design whose ``release_rule`` is ``ideal``)."""
        if self.name == "machine.release_angle" and design.machine.release_rule == "ideal":
            raise DesignError("field", self.name, IDEAL_IGNORES_RELEASE_ANGLE)
        value = self.get(design)
        if value is None:
            reason = ('the frame is fixed: give [base] mobility = "rolling" and a mass to vary it'
                      if self.table == "base" else "this design does not set it")
            raise DesignError("field", self.name, reason)
        return value

    def replace(self, design: Design, value: float) -> Design:
        """``design`` with this field set to ``value`` (file units); ``DesignError`` if it cannot be built."""
        inner = math.radians(value) if self.kind is ANGLE else float(value)
        part = dataclasses.replace(getattr(design, self.table), **{self.key: inner})
        return dataclasses.replace(design, **{self.table: part})


def axis_label(name: str, unit: str) -> str:
    """``name (unit)``, or the name alone for a dimensionless quantity (no empty brackets)."""
    return f"{name} ({unit})" if unit else name


def field(name: str) -> Field:
    """The ``Field`` named ``name`` (dotted, or a bare machine name).

    Raises
    ------
    DesignError
        naming it, if no design has such a field or it is not a number (a choice).
    """
    if not isinstance(name, str) or not name:
        raise DesignError("field", name, "must name a design field, e.g. machine.release_angle")
    table, _, key = name.rpartition(".")
    table = table or "machine"
    if table not in _TABLES:
        raise DesignError("field", name, f"unknown table {table!r}; {did_you_mean(table, _TABLES)}"
                                         f"expected one of {', '.join(_TABLES)}")
    keys = [f.name for f in dataclasses.fields(_TABLES[table])]
    dotted = f"{table}.{key}"
    if key in _CHOICES and key in keys:
        raise DesignError("field", dotted, "is a choice, not a number; only numeric fields can be adjusted")
    if key not in keys or key not in FIELD_KINDS or key in _NOT_VARIED:
        numeric = [k for k in keys if k not in _CHOICES and k not in _NOT_VARIED]
        raise DesignError("field", dotted, f"no such field in [{table}]; {did_you_mean(key, numeric)}"
                                           f"expected one of {', '.join(numeric)}")
    return Field(table, key)
