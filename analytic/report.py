"""Human-readable text for a shot (the non-JSON output of ``simulate``)."""

from __future__ import annotations

import math

from analytic.result import Shot


def format_shot(shot: Shot) -> str:
    """A table of the shot's outcome, in the units a builder reads (m, m/s, deg, s, %)."""
    lines = [f"design   {shot.design.name}", f"status   {shot.status.value}: {shot.message}"]
    rows = []

    def row(label: str, value, unit: str = "", fmt: str = ".4f") -> None:
        if value is not None:
            rows.append((label, format(value, fmt), unit))

    row("lift-off time", shot.liftoff_time, "s")
    row("release time", shot.release_time, "s")
    if shot.release_position is not None:
        x, y = shot.release_position
        rows.append(("release position", f"({x:.4f}, {y:.4f})", "m from pivot"))
        vx, vy = shot.release_velocity
        rows.append(("release velocity", f"({vx:.4f}, {vy:.4f})", "m/s"))
    row("release speed", shot.release_speed, "m/s")
    row("launch angle", None if shot.launch_angle is None else math.degrees(shot.launch_angle), "deg", ".3f")
    row("range (from pivot)", shot.range, "m", ".3f")
    row("range (from release)", shot.range_from_release, "m", ".3f")
    row("apex height", shot.apex_height, "m above base", ".3f")
    row("flight time", shot.flight_time, "s")
    row("energy efficiency", None if shot.energy_efficiency is None else 100 * shot.energy_efficiency, "%", ".2f")
    row("range efficiency", None if shot.range_efficiency is None else 100 * shot.range_efficiency, "%", ".2f")
    row("min sling tension", shot.min_sling_tension, "N (negative: the rigid sling pushed)", ".3f")
    width = max((len(r[0]) for r in rows), default=0)
    lines += [f"  {label:<{width}}  {value:>20}  {unit}" for label, value, unit in rows]
    lines += [f"warning  {warning}" for warning in shot.warnings]
    return "\n".join(lines)
