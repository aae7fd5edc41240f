"""The summary of a shot as rows (name, value, unit, order): what the text report, the notebook and the page show.

``summary_rows`` is the one list of what a shot's summary says: the text
report (``analytic.report.format_shot``) prints every row, the notebook's
table (``Shot._repr_html_``) shows them, and the workbench page receives
them with each shot and converts each by its unit's kind. The names that
depend on the machine (a fixed machine's counterweight has a mount, not a
hinge; a floating arm's positions count from its guide), the acceleration
in g and each load's unit are written here once.

Values are SI, but for the units no unit system changes: angles in degrees,
shares in %, the projectile's acceleration in g (of the design's gravity); and
stresses in MPa (a builder's unit; psi in imperial).
This module reads a shot's attributes and imports nothing of
``analytic.result``, which uses it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from analytic.outcome import LOSS_NAMES

if TYPE_CHECKING:
    from analytic.design import Design
    from analytic.result import Shot

#: Each peak load's SI unit (``analytic.units.display``'s spelling): ``PEAK_NAMES``' units.
PEAK_UNITS = {"peak_axle_load": "N", "peak_hinge_load": "N", "peak_sling_tension": "N",
              "peak_projectile_acceleration": "m/s^2", "peak_arm_bending_moment": "N m"}
#: How each loss (``LOSS_NAMES``) is named.
LOSS_LABELS = {"axle": "axle friction", "hinge": "hinge friction", "base": "base friction",
               "drag": "air drag in flight", "swing_drag": "air drag before release",
               "guide": "guide friction", "track": "track friction"}
#: The losses after release: the rest are taken from the counterweight's energy before it.
FLIGHT_LOSSES = ("drag",)
#: The unit an acceleration in g is shown in.
G = "g"
#: The unit a stress is shown in (``analytic.units.display`` turns it to psi in imperial).
MPA = "MPa"
#: The unit each peak load is shown in: ``PEAK_UNITS``', but the projectile's acceleration in g (``in_g``).
SHOWN_PEAK_UNITS = {**PEAK_UNITS, "peak_projectile_acceleration": G}


def origin_label(design: Design) -> str:
    """Where a shot's positions are measured from: the pivot, or a floating arm's guide (where it meets
    the track)."""
    return "guide" if design.machine.kind == "floating-arm" else "pivot"


def hinge_load_label(design: Design) -> str:
    """What a table calls ``peak_hinge_load``: a fixed machine has no hinge, and the force is its
    counterweight's mount's."""
    return peak_label_of_kind("peak_hinge_load", design.machine.kind)


def peak_label(name: str, design: Design) -> str:
    """What a table calls the peak load ``name`` (a ``PEAK_UNITS`` key) of ``design``."""
    return peak_label_of_kind(name, design.machine.kind)


def peak_label_of_kind(name: str, kind: str) -> str:
    """``peak_label`` on a machine of ``kind`` (``analytic.design.BUILT_KINDS``), for a page that
    names the loads before it has a design."""
    if name == "peak_hinge_load":
        return "peak hinge load" if kind == "hinged" else "peak mount load"
    return name.replace("_", " ")


def in_g(acceleration, design: Design):
    """``acceleration`` (m/s^2, a number or an array) in g: multiples of the design's own gravity."""
    return acceleration / design.environment.gravity


def weighs(design: Design) -> bool:
    """Whether the design's sling or pouch has mass (and keeps energy at release)."""
    return design.machine.sling_mass > 0.0 or design.machine.pouch_mass > 0.0


@dataclass(frozen=True)
class Row:
    """One line of a shot's summary.

    key : what it shows, a ``Shot`` attribute (``energy.axle`` for a loss).
    label : its name, in words.
    value : in ``unit``: a number, or (x, y) for a position or a velocity.
    unit : SI as ``analytic.units.display`` spells it (m, m/s, N, J, N m), or one no unit system
        changes (s, deg, %, g); ``analytic.units.SHOWN_KINDS`` gives its kind.
    decimals : the text report's decimals (in the unit shown).
    note : words after the unit, the same in any unit system.
    time : when a peak occurred, s from firing (None: not a peak).
    level : 1 for a share of the row before (the counterweight's energy's parts).
    brief : one of the few a glance needs (the page shows them; the rest under "all numbers").
    verdict : for a margin, whether it holds (the page shows it green or red); None for the rest.
    """

    key: str
    label: str
    value: Any
    unit: str
    decimals: int
    note: str = ""
    time: float | None = None
    level: int = 0
    brief: bool = False
    verdict: bool | None = None

    def to_json(self) -> dict[str, Any]:
        from analytic.units import SHOWN_KINDS

        value = list(map(float, self.value)) if isinstance(self.value, (tuple, list)) else float(self.value)
        return {"key": self.key, "label": self.label, "value": value, "unit": self.unit,
                "kind": SHOWN_KINDS[self.unit], "note": self.note, "time": self.time, "level": self.level,
                "brief": self.brief, "verdict": self.verdict}


def summary_rows(shot: Shot) -> list[Row]:
    """The rows of ``shot``'s summary, in the order they read; a value the shot did not reach has no row."""
    design = shot.design
    rows: list[Row] = []

    def row(key: str, label: str, value, unit: str, decimals: int, note: str = "", brief: bool = False,
            level: int = 0) -> None:
        if value is not None:
            time = getattr(shot, f"{key}_time", None) if key.startswith("peak_") else None
            rows.append(Row(key, label, value, unit, decimals, note, time, level, brief))

    def pair(values) -> tuple[float, float] | None:
        return None if values is None else (float(values[0]), float(values[1]))

    def percent(share: float | None) -> float | None:
        return None if share is None else 100.0 * share

    launch = None if shot.launch_angle is None else math.degrees(shot.launch_angle)
    origin = origin_label(design)
    row("liftoff_time", "lift-off time", shot.liftoff_time, "s", 4)
    row("release_time", "release time", shot.release_time, "s", 4)
    row("release_position", "release position", pair(shot.release_position), "m", 4, f" from {origin}")
    row("release_velocity", "release velocity", pair(shot.release_velocity), "m/s", 4)
    row("release_speed", "release speed", shot.release_speed, "m/s", 4, brief=True)
    row("launch_angle", "launch angle", launch, "deg", 3, brief=True)
    if design.machine.release_rule == "ideal":   # the velocity rule's pin that throws as far
        row("release_pin", "release pin", launch, "deg", 3, " (set the pin to this for rule velocity)", brief=True)
    row("range", f"range (from {origin})", shot.range, "m", 3)
    row("range_from_release", "range (from release)", shot.range_from_release, "m", 3)
    row("apex_height", "apex height", shot.apex_height, "m", 3, " above base", brief=True)
    row("flight_time", "flight time", shot.flight_time, "s", 4, brief=True)
    row("energy_efficiency", "energy efficiency", percent(shot.energy_efficiency), "%", 2, brief=True)
    if weighs(design):   # what the counterweight gave the sling and the pouch stays on the machine
        row("sling_energy_at_release", "kept by sling and pouch", shot.sling_energy_at_release, "J", 3, brief=True)
    row("range_efficiency", "range efficiency", percent(shot.range_efficiency), "%", 2, brief=True)
    rows += energy_rows(shot)
    pushed = shot.min_sling_tension is not None and shot.min_sling_tension < 0.0
    row("min_sling_tension", "min sling tension", shot.min_sling_tension, "N", 3,
        " (negative: the rigid sling pushed)" if pushed else "")
    for name in ("peak_sling_tension", "peak_axle_load", "peak_hinge_load"):
        row(name, peak_label(name, design), getattr(shot, name), PEAK_UNITS[name], 3, brief=True)
    row("min_track_force", "track force, min", shot.min_track_force, "N", 3, " (vertical, on the axle)")
    row("max_track_force", "track force, max", shot.max_track_force, "N", 3, " (vertical, on the axle)")
    row("max_guide_force", "max guide force", shot.max_guide_force, "N", 3, " (horizontal, on the counterweight)")
    row("axle_displacement_at_release", "axle at release", shot.axle_displacement_at_release, "m", 4,
        " from the guide")
    acceleration = shot.peak_projectile_acceleration
    row("peak_projectile_acceleration", "peak projectile accel.",
        None if acceleration is None else in_g(acceleration, design), G, 2, brief=True)
    row("peak_arm_bending_moment", peak_label("peak_arm_bending_moment", design), shot.peak_arm_bending_moment,
        PEAK_UNITS["peak_arm_bending_moment"], 3, brief=True)
    rows += breaking_rows(shot)
    return rows


def breaking_rows(shot: Shot) -> list[Row]:
    """Will it break: the arm's peak stress (at the axle's section) and its safety factor against its
    strength, and the projectile's margin (its limit over its peak acceleration); each margin with its
    verdict. A design without a strength or a limit has no such row."""
    from analytic.data.strength import MATERIALS, STANDARD_GRAVITY

    rows = []
    stress, factor = shot.peak_arm_stress, shot.arm_safety_factor
    if stress is not None:
        rows.append(Row("peak_arm_stress", "peak arm stress", stress / 1e6, MPA, 3, " at the axle's section",
                        brief=factor is not None))
    if factor is not None:
        material = shot.design.machine.arm_section.material
        metal = material is not None and MATERIALS[material].strength_kind == "yield strength"
        verdict = "holds" if factor > 1.0 else ("yields" if metal else "breaks")
        rows.append(Row("arm_safety_factor", "arm safety factor", factor, "", 2,
                        f" (the arm {verdict}: strength / peak stress)", brief=True, verdict=factor > 1.0))
    survives = shot.projectile_survives
    if survives is not None:
        limit = shot.design.projectile.acceleration_limit
        rows.append(Row("projectile_margin", "projectile margin", limit / shot.peak_projectile_acceleration, "", 2,
                        f" (it {'survives' if survives else 'breaks'}: limit {limit / STANDARD_GRAVITY:g} g "
                        f"/ peak acceleration)", brief=True, verdict=survives))
    return rows


def energy_rows(shot: Shot) -> list[Row]:
    """Where the counterweight's energy went: what each loss took (J, and as a share of the
    counterweight's energy; the share that reached the projectile is the energy efficiency).
    A loss the design does not have has no row."""
    released = shot.counterweight_energy_released
    if shot.energy_dissipated is None or not released:
        return []
    # Its share in the projectile at release is the energy efficiency, above.
    rows = [Row("counterweight_energy_released", "counterweight energy", released, "J", 3,
                " given up by release (counterweight and arm)")]
    for name in present_losses(shot):
        taken = shot.energy_dissipated[name]
        rows.append(Row(f"energy.{name}", LOSS_LABELS[name], taken, "J", 4,
                        f" ({100 * taken / released:.2f} % of it)", level=1))
    return rows


def present_losses(shot: Shot) -> list[str]:
    """The losses of ``LOSS_NAMES`` the shot's design has, the frictions first, then the drag."""
    losses = shot.design.losses
    present = []
    for name in sorted(LOSS_NAMES, key=lambda loss: loss in ("drag", "swing_drag")):   # the friction first
        if name == "swing_drag" and not shot.design.projectile.drag_during_swing:
            continue
        if name not in ("drag", "swing_drag") and getattr(losses, f"{name}_friction") == 0.0:
            continue   # a loss the design does not have: no row of zeros
        present.append(name)
    return present


def row_text(row: Row, units: str = "metric") -> tuple[str, str]:
    """A row's value, and its unit with the row's note and time, as text in ``units``."""
    from analytic.units import display

    when = "" if row.time is None else f" at t = {row.time:.4f} s"
    if isinstance(row.value, tuple):
        (x, shown), (y, _) = display(row.value[0], row.unit, units), display(row.value[1], row.unit, units)
        return f"({x:.{row.decimals}f}, {y:.{row.decimals}f})", f"{shown}{row.note}{when}"
    number, shown = display(row.value, row.unit, units)
    return f"{number:.{row.decimals}f}", f"{shown}{row.note}{when}"
