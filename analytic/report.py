"""Human-readable text for a shot (the non-JSON output of ``simulate``), in metric or imperial units."""

from __future__ import annotations

import math

from analytic.result import LOSS_NAMES, Shot, hinge_load_label, origin_label
from analytic.data.strength import MATERIALS, STANDARD_GRAVITY
from analytic.units import display


def format_shot(shot: Shot, units: str = "metric") -> str:
    """A table of the shot's outcome, in the units a builder reads.

    Parameters
    ----------
    shot : the shot.
    units : ``"metric"`` (m, m/s, N) or ``"imperial"`` (ft, ft/s, lbf); times in s, angles
        in deg, the projectile's acceleration in g either way.
    """
    lines = [f"design   {shot.design.name}", f"status   {shot.status.value}: {shot.message}"]
    rows = []

    def row(label: str, value, unit: str = "", fmt: str = ".4f", note: str = "") -> None:
        if value is not None:
            number, shown = display(value, unit, units)
            rows.append((label, format(number, fmt), f"{shown}{note}"))

    def pair(label: str, values, unit: str, note: str = "") -> None:
        if values is not None:
            (x, shown), (y, _) = display(values[0], unit, units), display(values[1], unit, units)
            rows.append((label, f"({x:.4f}, {y:.4f})", f"{shown}{note}"))

    def at(name: str) -> str:
        time = getattr(shot, f"{name}_time")
        return "" if time is None else f" at t = {time:.4f} s"

    row("lift-off time", shot.liftoff_time, "s")
    row("release time", shot.release_time, "s")
    origin = origin_label(shot.design)
    pair("release position", shot.release_position, "m", f" from {origin}")
    pair("release velocity", shot.release_velocity, "m/s")
    row("release speed", shot.release_speed, "m/s")
    row("launch angle", None if shot.launch_angle is None else math.degrees(shot.launch_angle), "deg", ".3f")
    row(f"range (from {origin})", shot.range, "m", ".3f")
    row("range (from release)", shot.range_from_release, "m", ".3f")
    row("apex height", shot.apex_height, "m", ".3f", " above base")
    row("flight time", shot.flight_time, "s")
    row("energy efficiency", None if shot.energy_efficiency is None else 100 * shot.energy_efficiency, "%", ".2f")
    row("range efficiency", None if shot.range_efficiency is None else 100 * shot.range_efficiency, "%", ".2f")
    _energy_rows(shot, row)
    pushed = shot.min_sling_tension is not None and shot.min_sling_tension < 0.0
    row("min sling tension", shot.min_sling_tension, "N", ".3f",
        " (negative: the rigid sling pushed)" if pushed else "")
    row("peak sling tension", shot.peak_sling_tension, "N", ".3f", at("peak_sling_tension"))
    row("peak axle load", shot.peak_axle_load, "N", ".3f", at("peak_axle_load"))
    row(hinge_load_label(shot.design), shot.peak_hinge_load, "N", ".3f", at("peak_hinge_load"))
    row("track force, min", shot.min_track_force, "N", ".3f", " (vertical, on the axle)")
    row("track force, max", shot.max_track_force, "N", ".3f", " (vertical, on the axle)")
    row("max guide force", shot.max_guide_force, "N", ".3f", " (horizontal, on the counterweight)")
    row("axle at release", shot.axle_displacement_at_release, "m", ".4f", " from the guide")
    if shot.peak_projectile_acceleration is not None:
        rows.append(("peak projectile accel.", f"{shot.peak_projectile_acceleration / shot.design.environment.gravity:.2f}",
                     f"g{at('peak_projectile_acceleration')}"))
    row("peak arm bending moment", shot.peak_arm_bending_moment, "N m", ".3f", at("peak_arm_bending_moment"))
    _breaking_rows(shot, rows)
    width = max((len(r[0]) for r in rows), default=0)
    lines += [f"  {label:<{width}}  {value:>20}  {unit}" for label, value, unit in rows]
    lines += [f"warning  {warning}" for warning in shot.warnings]
    return "\n".join(lines)


#: How each loss is named in the summary.
LOSS_LABELS = {"axle": "axle friction", "hinge": "hinge friction", "base": "base friction",
               "drag": "air drag in flight", "swing_drag": "air drag before release",
               "guide": "guide friction", "track": "track friction"}


def _energy_rows(shot: Shot, row) -> None:
    """Where the counterweight's energy went: what each loss took (J, and as a share of the
    counterweight's energy; the share that reached the projectile is the energy efficiency)."""
    released = shot.counterweight_energy_released
    if shot.energy_dissipated is None or not released:
        return
    # Its share in the projectile at release is the energy efficiency, just above.
    row("counterweight energy", released, "J", ".3f", " given up by release (counterweight and arm)")
    losses = shot.design.losses
    for name in sorted(LOSS_NAMES, key=lambda loss: loss in ("drag", "swing_drag")):   # the friction first
        if name == "swing_drag" and not shot.design.projectile.drag_during_swing:
            continue
        if name not in ("drag", "swing_drag") and getattr(losses, f"{name}_friction") == 0.0:
            continue   # a loss the design does not have: no row of zeros
        taken = shot.energy_dissipated[name]
        row(f"  {LOSS_LABELS[name]}", taken, "J", ".4f", f" ({100 * taken / released:.2f} % of it)")


def _breaking_rows(shot: Shot, rows: list) -> None:
    """Will it break: the arm's peak stress and safety factor, and whether the projectile survives."""
    stress, factor = shot.peak_arm_stress, shot.arm_safety_factor
    if stress is not None:
        rows.append(("peak arm stress", f"{stress / 1e6:.3f}", "MPa (at the axle's section)"))
    if factor is not None:
        verdict = "holds" if factor > 1.0 else ("yields" if _metal(shot) else "breaks")
        rows.append(("arm safety factor", f"{factor:.2f}", f"(the arm {verdict}; against its strength)"))
    survives, limit = shot.projectile_survives, shot.design.projectile.acceleration_limit
    if survives is not None:
        rows.append(("projectile", "survives" if survives else "breaks",
                     f"(its limit {limit / STANDARD_GRAVITY:g} g)"))


def _metal(shot: Shot) -> bool:
    """Whether the arm's strength is a yield strength (a metal's: past it the arm bends for good)."""
    material = shot.design.machine.arm_section.material
    return material is not None and MATERIALS[material].strength_kind == "yield strength"
