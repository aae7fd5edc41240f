"""Plots of a shot: trajectory, the machine at release, the energy budget and the loads (Agg, no pyplot).

Each function takes a ``analytic.result.Shot`` that has a ``history``; this
module does not import ``analytic.result`` (``Shot.plot`` calls it).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.patches import Circle

from analytic.geometry import machine_points
from analytic.outcome import LOSS_NAMES, Stage
from analytic.summary import in_g


def draw_machine(ax, shot, index: int, alpha: float = 1.0) -> None:
    """Draw frame, arm, counterweight link and mass, sling and projectile at sample ``index`` of ``shot.history``.

    On the ground: a rolling frame is drawn where it has rolled to, on wheels, with its trough if raised.
    """
    h = shot.design.machine.pivot_height
    history = shot.history
    x = float(history.frame_x[index]) if len(history.frame_x) else 0.0
    pts = {name: point + np.array([x, 0.0]) for name, point in
           machine_points(history.q[index], shot.design.machine).items()}
    pts["weight"] = pts["counterweight"]
    ax.plot([x - 0.3 * h, x, x + 0.3 * h], [-h, 0.0, -h], color="0.4", lw=2, alpha=alpha)
    trough = shot.design.base.trough_height
    if trough > 0.0:   # on the frame, from under the tip at rest to half a sling past the projectile at rest
        m = shot.design.machine
        start = x - math.sqrt(m.arm_long**2 - (h - trough) ** 2)
        end = start + 1.5 * m.sling_length
        ax.plot([start, start, end, end], [-h, trough - h, trough - h, -h], color="0.5", lw=1.5, alpha=alpha)
    if shot.design.base.rolling:
        radius = 0.06 * h
        ax.plot([x - 0.3 * h, x + 0.3 * h], [-h + 2 * radius, -h + 2 * radius], color="0.4", lw=2, alpha=alpha)
        for centre in (x - 0.3 * h, x + 0.3 * h):
            ax.add_patch(Circle((centre, -h + radius), radius, fill=False, color="0.3", lw=1.5, alpha=alpha))
    ax.plot(*np.c_[pts["short_tip"], pts["long_tip"]], color="saddlebrown", lw=3, alpha=alpha)
    ax.plot(*np.c_[pts["short_tip"], pts["weight"]], color="0.2", lw=1.5, alpha=alpha)
    ax.plot(*pts["weight"], "s", color="0.2", ms=10, alpha=alpha)
    ax.plot(*np.c_[pts["long_tip"], pts["projectile"]], color="tab:blue", lw=1, alpha=alpha)
    ax.plot(*pts["projectile"], "o", color="tab:red", ms=5, alpha=alpha)
    ax.plot(x, 0.0, "o", color="k", ms=4, alpha=alpha)


#: A load above this fraction of its peak is part of the stroke: the loads panels show
#: the window from the first such sample to the end of the history, widened by
#: ``STROKE_PAD`` of its width before it, so the rise is seen from the flat.
STROKE_FRACTION, STROKE_PAD = 0.05, 0.5


def shot_figure(shot, units: str = "metric") -> Figure:
    """Five panels of a ``Shot`` with a history, on a 2 x 3 grid that fits a laptop screen (1430 x 825
    pixels at the default 110 dpi): the flight and the machine at release (or at the end) above; the
    energy, the joint loads and the sling tension below, the loads zoomed on the stroke (``stroke_window``).
    Drawn in SI and shown in ``units`` (``analytic.plot_units``)."""
    history = shot.history
    if history is None:
        raise ValueError(f"shot of {shot.design.name!r} has no histories to plot (a summary from the "
                         f"fast path or simulate(histories=False)): simulate it with histories")
    fig = Figure(figsize=(13, 7.5), layout="constrained")
    panels = fig.subplot_mosaic([["flight", "flight", "machine"], ["energy", "loads", "sling"]],
                                height_ratios=[1, 1.15])
    ax_flight, ax_machine = panels["flight"], panels["machine"]
    h = shot.design.machine.pivot_height
    title = f"{shot.design.name}: {shot.status.value}"
    if shot.range is not None:
        title += f", range {shot.range:.2f} m, release {shot.release_speed:.2f} m/s at {math.degrees(shot.launch_angle):.1f} deg"
    fig.suptitle(title)

    ax_flight.axhline(0.0, color="0.5", lw=1)
    ax_flight.plot(history.path[:, 0], history.path[:, 1] + h, color="tab:blue", lw=1, label="in the sling")
    if len(history.flight_path):
        ax_flight.plot(history.flight_path[:, 0], history.flight_path[:, 1] + h, color="tab:red", label="flight")
    ax_flight.plot(0.0, h, "k^", label="pivot")
    ax_flight.set(xlabel="x from pivot (m)", ylabel="height above base (m)", title="trajectory")
    ax_flight.set_aspect("equal", adjustable="box")
    top = max(float(np.max(history.path[:, 1])), float(np.max(history.flight_path[:, 1], initial=-h))) + h
    ax_flight.set_ylim(-0.05 * top - 0.1, 1.1 * top + 0.1)
    ax_flight.legend(loc="upper right", fontsize=8)

    ax_machine.axhline(-h, color="0.5", lw=1)
    ax_machine.plot(history.path[:, 0], history.path[:, 1], color="tab:blue", lw=0.8, ls=":")
    draw_machine(ax_machine, shot, 0, alpha=0.25)
    draw_machine(ax_machine, shot, len(history.t) - 1)
    when = "release" if shot.release_time is not None else "end"
    ax_machine.set(xlabel="x (m)", ylabel="y (m)", title=f"machine at start (faint) and {when}")
    ax_machine.set_aspect("equal", adjustable="datalim")

    draw_energy(panels["energy"], shot)
    draw_loads(panels["loads"], shot)
    draw_sling(panels["sling"], shot)
    window = stroke_window(shot)
    if window is not None:
        panels["energy"].axvspan(*window, color="0.85", zorder=0, label="the loads' window")
        panels["energy"].legend(fontsize=8)
    from analytic.plot_units import in_units

    return in_units(fig, units)


def stroke_window(shot) -> tuple[float, float] | None:
    """(start, end) s: where the axle carries more than ``STROKE_FRACTION`` of its peak, to the
    history's end (release), widened before by ``STROKE_PAD``; None without loads."""
    history = shot.history
    if history.axle_load is None or not len(history.t):
        return None
    loads = np.abs(history.axle_load)
    above = np.flatnonzero(loads > STROKE_FRACTION * float(np.max(loads)))
    start, end = float(history.t[above[0]]), float(history.t[-1])
    start = max(float(history.t[0]), start - STROKE_PAD * (end - start))
    return (start, end) if end > start else None


def draw_energy(ax_energy, shot) -> None:
    """The mechanical energies through stages 1-2 and each friction loss as its own band (J)."""
    history = shot.history
    ax_energy.plot(history.t, history.energy.projectile, label="projectile")
    ax_energy.plot(history.t, history.energy.machine,
                   label="arm + counterweight" + (" + frame" if shot.design.base.rolling else ""))
    ax_energy.plot(history.t, history.energy.total, "k--", label="total")
    # Each loss as its own band, stacked from the total up: together they close the audit
    # (the top edge is the energy at rest, 0).
    bottom = history.energy.total
    colors = ("tab:red", "tab:olive", "tab:brown", "tab:purple", "tab:cyan")
    for name, color in zip((n for n in LOSS_NAMES if n not in ("drag", "swing_drag")), colors, strict=True):
        taken = history.energy.dissipated.get(name)
        if taken is None or not np.any(taken > 0.0):
            continue
        total_taken = shot.energy_dissipated[name] if shot.energy_dissipated else taken[-1]
        ax_energy.fill_between(history.t, bottom, bottom + taken, color=color, alpha=0.35, lw=0,
                               label=f"lost to {name} friction ({total_taken:.3g} J)")
        bottom = bottom + taken
    if shot.liftoff_time is not None:
        ax_energy.axvline(shot.liftoff_time, color="0.6", lw=0.8)
        ax_energy.text(shot.liftoff_time, ax_energy.get_ylim()[1], " lift-off", va="top", fontsize=8)
    ax_energy.set(xlabel="time (s)", ylabel="energy relative to rest (J)",
                  title=f"energy, stages {int(Stage.SLIDE)}-{int(Stage.SWING)}")
    ax_energy.legend(fontsize=8)


def draw_loads(ax, shot) -> None:
    """The axle and hinge loads (N) over the stroke (``stroke_window``), each peak marked; the
    panel hidden where the history holds no loads."""
    history = shot.history
    if history.axle_load is None:
        ax.set_visible(False)
        return
    loads = ((history.axle_load, shot.peak_axle_load, shot.peak_axle_load_time, "axle", "tab:blue"),
             (history.hinge_load, shot.peak_hinge_load, shot.peak_hinge_load_time, "hinge", "tab:green"))
    for values, peak, when, label, color in loads:
        ax.plot(history.t, values, color=color, lw=1.2, label=label)
    _zoom(ax, shot)
    _label_peaks(ax, [(peak, when, label, color) for _, peak, when, label, color in loads if peak is not None])
    ax.set(xlabel="time (s)", ylabel="force (N)", title="joint loads over the stroke (dots: peaks)")
    ax.legend(fontsize=8, loc="upper left")


def _label_peaks(ax, peaks: list[tuple[float, float, str, str]]) -> None:
    """Mark each (peak N, time s, name, colour) and label it on the side of the panel with more room
    (the labels grow in other units: "hinge 356.8 lbf"), the higher peak's label a line above the other's
    (the peaks often nearly coincide)."""
    if not peaks:
        return
    start, end = ax.get_xlim()
    side = "right" if max(when for _, when, _, _ in peaks) > 0.5 * (start + end) else "left"
    low, high = ax.get_ylim()
    ax.set_ylim(low, high + 0.06 * (len(peaks) - 1) * (high - low))   # room for the label a line up
    for line, (peak, when, label, color) in enumerate(sorted(peaks)):
        ax.plot(when, peak, "o", color=color, ms=4)
        ax.annotate(f"{label} {peak:.0f} N", (when, peak), textcoords="offset points", ha=side, fontsize=8,
                    xytext=(-6 if side == "right" else 6, 4 + 11 * line), color=color)


def draw_sling(ax, shot) -> None:
    """The sling tension (N) over the stroke, with the projectile's felt acceleration (g) as a second
    scale of the same curve: after lift-off the sling's pull is the only force but gravity on the
    projectile, so the two are one curve there, drawn once."""
    history = shot.history
    if history.sling_tension is None:
        ax.set_visible(False)
        return
    ax.plot(history.t, history.sling_tension, color="tab:purple", lw=1.2, label="sling tension")
    if shot.peak_sling_tension is not None:
        ax.plot(shot.peak_sling_tension_time, shot.peak_sling_tension, "o", color="tab:purple", ms=4)
    ax.axhline(0.0, color="0.6", lw=0.6)
    _zoom(ax, shot)
    ax.set(xlabel="time (s)", ylabel="sling tension (N)", title="sling over the stroke")
    weight = shot.design.projectile.mass * shot.design.environment.gravity
    felt = ax.secondary_yaxis("right", functions=(lambda n: n / weight, lambda a: a * weight))
    felt.set_ylabel("projectile acceleration after lift-off (g)")
    if shot.peak_projectile_acceleration is not None:
        ax.annotate(f"peak {in_g(shot.peak_projectile_acceleration, shot.design):.0f} g", (shot.peak_projectile_acceleration_time,
                    shot.peak_projectile_acceleration * shot.design.projectile.mass), textcoords="offset points",
                    xytext=(-6, 4), ha="right", fontsize=8, color="tab:purple")


def _zoom(ax, shot) -> None:
    window = stroke_window(shot)
    if window is not None:
        ax.set_xlim(*window)
        history, (start, end) = shot.history, window
        inside = (history.t >= start) & (history.t <= end)
        lines = [line.get_ydata() for line in ax.get_lines() if len(line.get_ydata()) == len(history.t)]
        if lines and inside.any():
            top = max(float(np.max(np.asarray(y)[inside])) for y in lines)
            low = min(0.0, min(float(np.min(np.asarray(y)[inside])) for y in lines))
            ax.set_ylim(low - 0.04 * (top - low), top + 0.12 * (top - low))
    ax.grid(alpha=0.3)


def save_figure(figure: Figure, path: str | Path, dpi: int = 110) -> None:
    """Render ``figure`` to ``path`` through the Agg canvas (the format follows the suffix).

    PNGs are compressed at zlib's fastest level: a chart's few flat colours compress
    nearly as well at it, and the default level's search costs more time than the
    larger file (``python -m benchmarks`` times a chart's write).
    """
    FigureCanvasAgg(figure)
    options = {"pil_kwargs": {"compress_level": 1}} if str(path).lower().endswith(".png") else {}
    figure.savefig(path, dpi=dpi, **options)


def save_shot_figure(shot: Shot, path: str | Path, dpi: int = 110, units: str = "metric") -> None:
    """Render ``shot_figure`` to a file, shown in ``units`` (``metric`` or ``imperial``)."""
    save_figure(shot_figure(shot, units), path, dpi)
