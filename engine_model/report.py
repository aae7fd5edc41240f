"""Readable text for an engine shot: the shared JSON fields in builder's units, plus the engine's diagnostics."""

from __future__ import annotations

from analytic.result import Shot, origin_label
from analytic.units import display

#: (JSON key, label, unit, format) in the order printed; values are as in ``Shot.to_json``.
_FIELDS = (
    ("liftoff_time", "lift-off", "s", "{:.5f}"),
    ("release_time", "release", "s", "{:.5f}"),
    ("release_position", "release at", "m from pivot", "({0[0]:.4f}, {0[1]:.4f})"),
    ("release_velocity", "release velocity", "m/s", "({0[0]:.4f}, {0[1]:.4f})"),
    ("release_speed", "release speed", "m/s", "{:.5f}"),
    ("launch_angle", "launch angle", "deg", "{:.4f}"),
    ("range", "range from pivot", "m", "{:.4f}"),
    ("range_from_release", "range from release", "m", "{:.4f}"),
    ("apex_height", "apex above base", "m", "{:.4f}"),
    ("flight_time", "flight time", "s", "{:.4f}"),
    ("landed_behind_pivot", "landed behind pivot", "", "{}"),
    ("energy_efficiency", "energy efficiency", "", "{:.2%}"),
    ("range_efficiency", "range efficiency", "", "{:.2%}"),
    ("min_sling_tension", "min sling tension", "N", "{:.4f}"),
    ("peak_arm_stress", "peak arm stress", "Pa", "{:.4g}"),
    ("arm_safety_factor", "arm safety factor", "", "{:.3f}"),
    ("projectile_survives", "projectile survives", "", "{}"),
)
#: (Shot attribute, label, unit, format): a rolling frame's motion, printed for rolling frames only.
_FRAME_FIELDS = (
    ("frame_release_displacement", "frame at release", "m from rest", "{:+.5f}"),
    ("frame_release_velocity", "frame velocity at release", "m/s", "{:+.5f}"),
    ("frame_landing_displacement", "frame at landing", "m from rest", "{:+.5f}"),
    ("frame_landing_velocity", "frame velocity at landing", "m/s", "{:+.5f}"),
    ("max_frame_speed", "largest frame speed", "m/s", "{:.5f}"),
)


#: (key of ``EngineDiagnostics.support_loads``, label, unit, format): a floating arm's supports.
_SUPPORT_FIELDS = (
    ("min_track_force", "least track force", "N up on the axle", "{:.4f}"),
    ("max_track_force", "largest track force", "N up on the axle", "{:.4f}"),
    ("max_guide_force", "largest guide force", "N across the counterweight", "{:.4f}"),
    ("axle_displacement_at_release", "axle at release", "m from the guide", "{:+.5f}"),
)


def _shown(value, unit: str, system: str):
    """``value`` (a number or a pair, in the SI unit that ``unit`` starts with) and ``unit`` as shown in ``system``."""
    si, _, rest = unit.partition(" ")
    if isinstance(value, (list, tuple)):
        return [_shown(v, unit, system)[0] for v in value], _shown(1.0, unit, system)[1]
    if not isinstance(value, float):
        return value, unit
    number, label = display(value, si, system)
    return number, f"{label} {rest}".rstrip()


def format_shot(shot: Shot, units: str = "metric") -> str:
    """A two-column table of what the engine's shot reached (fields it never reached are left
    out) and its ``shot.diagnostics``; lengths, speeds, forces and energies in ``units``."""
    data = shot.to_json()
    rows = [("design", data["design"], ""), ("status", data["status"], data["message"])]

    def row(label: str, value, unit: str, fmt: str) -> tuple[str, str, str]:
        number, shown = _shown(value, unit, units)
        return label, fmt.format(number), shown

    origin = origin_label(shot.design)   # the pivot; a floating arm's guide, where its track meets it
    rows += [row(label.replace("pivot", origin), data[key], unit.replace("pivot", origin), fmt)
             for key, label, unit, fmt in _FIELDS if data[key] is not None]
    if shot.min_sling_tension is not None and shot.min_sling_tension < 0.0:   # said only where it is so
        rows = [(label, value, f"{unit} (negative: the rigid sling pushed)" if label == "min sling tension"
                 else unit) for label, value, unit in rows]
    if shot.design.base.rolling:
        rows += [row(label, getattr(shot, name), unit, fmt)
                 for name, label, unit, fmt in _FRAME_FIELDS if getattr(shot, name) is not None]
    supports = shot.diagnostics.support_loads if shot.diagnostics is not None else None
    if supports:
        rows += [row(label, supports[key], unit, fmt) for key, label, unit, fmt in _SUPPORT_FIELDS
                 if supports[key] is not None]
    if shot.energy_dissipated is not None:
        losses = shot.design.losses   # a loss the design does not have: no row of zeros
        labels = {"drag": "drag in flight", "swing_drag": "drag before release"}
        shown = {"drag": True, "swing_drag": shot.design.projectile.drag_during_swing}
        # The engine's own losses (``friction.JOINTS``, the drag's) in its order: a floating arm's guide and track too.
        rows += [row(labels.get(name, f"{name} friction"), work, "J dissipated", "{:.4f}")
                 for name, work in shot.energy_dissipated.items()
                 if shown.get(name, getattr(losses, f"{name}_friction", 0.0) != 0.0)]
    diagnostics = shot.diagnostics
    drift, drift_unit = _shown(diagnostics.max_joint_drift, "m", units)
    rows += [("engine", f"dt {diagnostics.dt:g} s, {diagnostics.iterations} iterations",
              f"{diagnostics.sling} sling"),
             ("max joint drift", f"{drift:.3g}", drift_unit),
             ("energy error", f"{diagnostics.energy_error:.3g}", "of the counterweight's available energy")]
    if diagnostics.discarded_steps or diagnostics.after_release_dt > diagnostics.dt:
        rows.append(("step budget", _budget_note(diagnostics), ""))
    if shot.design.base.rolling:
        rows += [("momentum error", f"{diagnostics.momentum_error:.3g}", "of the largest frame momentum"),
                 ("energy error after release", f"{diagnostics.after_release_energy_error:.3g}",
                  "of the counterweight's available energy")]
    rows += [("warning", warning, "") for warning in shot.warnings]
    width = max(len(label) for label, _, _ in rows)
    return "\n".join(f"{label:<{width}}  {value}  {unit}".rstrip() for label, value, unit in rows)


def _budget_note(diagnostics) -> str:
    """What the step budget of a shot at the default step changed (``engine_model.budget.SHOT_STEP_BUDGET``)."""
    from engine_model.budget import DEFAULT_DT, MACHINE_FINE_STEPS

    notes = []
    if diagnostics.discarded_steps:
        notes.append(f"stages 1-2 outlasted {MACHINE_FINE_STEPS:,} steps of the default step, and were run "
                     f"again at {diagnostics.dt:g} s ({diagnostics.discarded_steps:,} steps discarded)")
    if diagnostics.after_release_dt > diagnostics.dt:
        notes.append(f"the run after release at {diagnostics.after_release_dt:.3g} s")
    return "; ".join(notes) + f"; --dt {DEFAULT_DT:g} keeps the default step, however long it takes"
