"""Calibration charts: range and peak loads against one or two varied design fields.

The graphs a team brings to a competition: where to set the counterweight
(or the projectile, the release pin) for each distance. ``chart`` shoots the
whole grid in one fast batch (``analytic.fast.shoot``); ``write_csv`` writes a
row a design and ``chart_figure`` draws it. A setting that does not throw (or
cannot be built) is a gap with its status, never a zero.
"""

from __future__ import annotations

import csv
import itertools
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from analytic.design import Design, DesignError
from analytic.fields import Field, field
from analytic.result import hinge_load_label
from analytic.data.strength import bending_stress
from analytic.summary import PEAK_UNITS, in_g
from analytic.units import display

#: The loads a chart shows, in the order of its columns, with their units and labels.
LOAD_COLUMNS = tuple((name, PEAK_UNITS[name], name.replace("_", " "))
                     for name in ("peak_sling_tension", "peak_axle_load", "peak_hinge_load",
                                  "peak_projectile_acceleration", "peak_arm_bending_moment"))
#: Will it break: the margins a chart shows for a design that has them (``breaking_columns``), each
#: above 1 where it holds: the arm's safety factor (its strength over its peak stress) and the
#: projectile's margin (its limit over its peak acceleration), with units and labels.
BREAKING_COLUMNS = (("arm_safety_factor", "", "arm safety factor (strength / peak stress)"),
                    ("projectile_margin", "", "projectile margin (limit / peak acceleration)"))
#: Status of a grid point whose design cannot be built (its field values break a design rule).
DESIGN_ERROR = "design_error"
MAX_FIELDS = 2


@dataclass(frozen=True)
class Vary:
    """One varied field: ``steps`` evenly spaced settings from ``start`` to ``stop`` (file units)."""

    field: Field
    start: float
    stop: float
    steps: int

    @property
    def values(self) -> np.ndarray:
        """(steps,) the settings, file units."""
        return np.linspace(self.start, self.stop, self.steps)


def vary(name: str, start: float, stop: float, steps: int) -> Vary:
    """A checked ``Vary``: ``DesignError`` naming the bad part (field, an empty range, too few steps)."""
    target = field(name)
    for label, value in (("from", start), ("to", stop)):
        if not (isinstance(value, (int, float)) and math.isfinite(value)):
            raise DesignError(f"vary {target.name} {label}", value, "must be a finite number")
    if start == stop:
        raise DesignError(f"vary {target.name}", f"{start:g}:{stop:g}", "empty range: from and to are equal")
    if not (isinstance(steps, int) and steps >= 2):
        raise DesignError(f"vary {target.name} steps", steps, "must be a whole number of at least 2")
    return Vary(target, float(start), float(stop), steps)


@dataclass(frozen=True)
class Chart:
    """Range and peak loads over a grid of settings.

    Attributes
    ----------
    design : the design every other field comes from.
    varies : one or two ``Vary``; the grid is their product, the last varying fastest.
    settings : (S, F) each grid point's settings, file units (F = len(varies)).
    status : (S,) each point's status (``Status`` value, or ``design_error``).
    range : (S,) m, NaN where the shot did not throw.
    loads : name (``LOAD_COLUMNS``) -> (S,) peak load, N, m/s^2 or N m, NaN where not reached; and the
        margins of ``BREAKING_COLUMNS`` the design has (``breaking_columns``).
    seconds : wall time of building and shooting the grid.
    launch_angle : (S,) deg, NaN where the shot did not release, for a design whose
        ``release_rule`` is ``ideal`` (each setting's pin to set); None for the other rules.
    """

    design: Design
    varies: tuple[Vary, ...]
    settings: np.ndarray
    status: np.ndarray
    range: np.ndarray
    loads: dict[str, np.ndarray]
    seconds: float
    launch_angle: np.ndarray | None = None

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(v.steps for v in self.varies)


def chart(design: Design, varies: list[Vary]) -> Chart:
    """Shoot ``design`` at every combination of the varied settings, on the fast path in one batch.

    Parameters
    ----------
    design : the base design.
    varies : one or two ``Vary`` (``vary``), of different fields.

    Returns
    -------
    Chart
    """
    import time

    from analytic import fast

    if not 1 <= len(varies) <= MAX_FIELDS:
        raise DesignError("vary", len(varies), f"give one or {MAX_FIELDS} fields to vary")
    if len({v.field.name for v in varies}) != len(varies):
        raise DesignError("vary", [v.field.name for v in varies], "the same field twice")
    for v in varies:
        v.field.check(design)
    began = time.perf_counter()
    settings = np.array(list(itertools.product(*(v.values for v in varies))))
    status = np.full(len(settings), DESIGN_ERROR, dtype=object)
    built, designs = [], []
    for i, row in enumerate(settings):
        try:
            point = design
            for v, value in zip(varies, row, strict=True):
                point = v.field.replace(point, float(value))
        except DesignError:
            continue
        built.append(i)
        designs.append(point)
    ranges = np.full(len(settings), math.nan)
    loads = {name: np.full(len(settings), math.nan) for name, _, _ in LOAD_COLUMNS}
    ideal = design.machine.release_rule == "ideal"
    launch = np.full(len(settings), math.nan) if ideal else None
    if designs:
        shots = fast.shoot(designs, loads=True)   # the chart draws them
        status[built] = shots.status
        ranges[built] = shots.range
        for name in loads:
            loads[name][built] = getattr(shots, name)
        if ideal:
            launch[built] = np.degrees(shots.columns(("launch_angle",))["launch_angle"])
    loads.update(breaking_margins(design, loads))
    return Chart(design, tuple(varies), settings, status.astype(str), ranges, loads, time.perf_counter() - began,
                 launch)


def breaking_columns(design: Design) -> tuple[tuple[str, str, str], ...]:
    """The ``BREAKING_COLUMNS`` that ``design`` has: the arm's with a strength, the projectile's with a limit."""
    section = design.machine.arm_section
    has = {"arm_safety_factor": section is not None and section.bending_strength is not None,
           "projectile_margin": design.projectile.acceleration_limit is not None}
    return tuple(column for column in BREAKING_COLUMNS if has[column[0]])


def breaking_margins(design: Design, loads: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The margins of ``breaking_columns(design)`` from the peak loads (each (S,), NaN where not reached).

    The varied fields keep the arm's section and the projectile's limit (``fields`` does not vary
    them), so the base design's serve every point.
    """
    margins = {}
    for name, _, _ in breaking_columns(design):
        if name == "arm_safety_factor":
            section = design.machine.arm_section
            stress = bending_stress(loads["peak_arm_bending_moment"], section.width, section.depth)
            margins[name] = section.bending_strength / stress
        else:
            margins[name] = design.projectile.acceleration_limit / loads["peak_projectile_acceleration"]
    return margins


def write_csv(result: Chart, path: str | Path) -> None:
    """One row a design: the varied fields (file units), status, range (m), under the ideal rule
    the launch angle (deg: the pin to set), the peak loads, and the margins the design has
    (``breaking_columns``)."""
    launch = [] if result.launch_angle is None else ["launch_angle [deg]"]
    columns = LOAD_COLUMNS + breaking_columns(result.design)
    header = ([f"{v.field.name} [{v.field.unit}]" for v in result.varies] + ["status", "range [m]"] + launch
              + [f"{name} [{unit}]" if unit else name for name, unit, _ in columns])

    def cell(value: float) -> str:
        return "" if not math.isfinite(value) else repr(float(value))

    with Path(path).open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(header)
        for i, row in enumerate(result.settings):
            launch = [] if result.launch_angle is None else [cell(result.launch_angle[i])]
            writer.writerow([repr(float(v)) for v in row] + [result.status[i], cell(result.range[i])] + launch
                            + [cell(result.loads[name][i]) for name, _, _ in columns])


def chart_figure(result: Chart, units: str = "metric"):
    """The chart as a ``matplotlib.figure.Figure``: lines against one field, maps over two.

    Gaps where a setting does not throw, marked with its status. The maps' colours, colour
    bars and contour labels are in ``units`` (``analytic.units.display``); the axes are SI,
    for ``analytic.plot_units.in_units`` to show in them.
    """
    from matplotlib.figure import Figure

    if len(result.varies) == 1:
        return _line_figure(result, Figure(figsize=(9, 9), layout="constrained"))
    # A fixed layout: the constrained one measures every tick label again, which took most of
    # the time of a 2-D chart (measured, 4.6 of 8.9 s on a busy machine).
    return _map_figure(result, Figure(figsize=(14, 8.5)), units)


def _failures(result: Chart) -> dict[str, np.ndarray]:
    """Status -> (S,) mask of the points that failed so."""
    return {status: result.status == status for status in sorted(set(result.status.tolist())) if status != "ok"}


_MARKERS = "xv^sDP*"


def _line_figure(result: Chart, fig):
    (v,) = result.varies
    x = result.settings[:, 0]
    breaking = breaking_columns(result.design)
    ax_range, ax_joints, ax_sling, *ax_breaking = fig.subplots(3 + bool(breaking), 1, sharex=True)
    fig.suptitle(f"{result.design.name}: range and peak loads against {v.field.name}")
    ax_range.plot(x, result.range, "o-", ms=3, color="tab:red", label="range")
    ax_range.set(ylabel="range (m)")
    bottom = np.nanmin(result.range) if np.isfinite(result.range).any() else 0.0
    for (status, mask), marker in zip(_failures(result).items(), _MARKERS, strict=False):
        ax_range.plot(x[mask], np.full(mask.sum(), bottom), marker, color="k", ls="none",
                      label=f"{status.replace('_', ' ')} (no throw)")
    ax_range.legend(fontsize=8)
    ax_joints.plot(x, result.loads["peak_axle_load"], "-", color="tab:blue", label="peak axle load")
    ax_joints.plot(x, result.loads["peak_hinge_load"], "--", color="tab:green", label=hinge_load_label(result.design))
    ax_joints.set(ylabel="force (N)")
    ax_joints.legend(fontsize=8)
    ax_sling.plot(x, result.loads["peak_sling_tension"], "-", color="tab:purple", label="peak sling tension")
    ax_sling.set(xlabel=v.field.label, ylabel="peak sling tension (N)")
    _acceleration_scale(ax_sling, result)
    ax_sling.legend(fontsize=8)
    if breaking:
        _breaking_panel(ax_breaking[0], result, breaking)
        ax_sling.set(xlabel="")
    for ax in (ax_range, ax_joints, ax_sling, *ax_breaking):
        ax.grid(alpha=0.3)
    return fig


def _breaking_panel(ax, result: Chart, columns) -> None:
    """The margins against the varied field, with the line at 1 below which the part breaks."""
    x = result.settings[:, 0]
    for (name, _, label), colour in zip(columns, ("tab:brown", "tab:orange"), strict=False):
        ax.plot(x, result.loads[name], "-", color=colour, label=label)
    ax.axhline(1.0, color="tab:red", ls="--", lw=1.0, label="1: breaks below")
    ax.set(xlabel=result.varies[0].field.label, ylabel="margin (above 1 holds)")
    ax.set_ylim(bottom=0.0)
    ax.legend(fontsize=8)


#: Fields whose change breaks the proportion between sling tension and the projectile's felt acceleration.
_WEIGHT_FIELDS = ("projectile.mass", "environment.gravity")


def _proportional(result: Chart) -> bool:
    """True when the peak sling tension and the peak projectile acceleration are one quantity on two
    scales: after lift-off the sling's pull over the projectile's mass is the acceleration it feels,
    so with the projectile's weight the same at every setting they are proportional."""
    return not any(v.field.name in _WEIGHT_FIELDS for v in result.varies)


def _weight(result: Chart) -> float:
    return result.design.projectile.mass * result.design.environment.gravity


def _acceleration_scale(ax, result: Chart) -> None:
    """The projectile's peak acceleration (g) as the right-hand scale of a sling-tension axis where the
    two are proportional (``_proportional``); its own dashed curve on a twin axis where not."""
    if _proportional(result):
        weight = _weight(result)
        scale = ax.secondary_yaxis("right", functions=(lambda n: n / weight, lambda a: a * weight))
        scale.set_ylabel("peak projectile acceleration (g)")
        return
    twin = ax.twinx()
    twin.plot(result.settings[:, 0], in_g(result.loads["peak_projectile_acceleration"], result.design), "--", color="tab:orange",
              label="peak projectile acceleration (g)")
    twin.set(ylabel="projectile acceleration (g)")
    twin.legend(fontsize=8, loc="lower right")


#: The map panels: (column or "range", title, colour map). Peak projectile acceleration is the
#: sling tension's second scale where the two are proportional, a panel of its own where not.
_MAP_PANELS = (("range", "range (m)", "viridis"), ("peak_sling_tension", "peak sling tension (N)", "magma"),
               ("peak_axle_load", "peak axle load (N)", "magma"), ("peak_hinge_load", "peak hinge load (N)", "magma"),
               ("peak_arm_bending_moment", "peak arm bending moment (N m)", "magma"))
_ACCELERATION_PANEL = ("peak_projectile_acceleration", "peak projectile acceleration (g)", "magma")


def _map_figure(result: Chart, fig, units: str = "metric"):
    from matplotlib.colors import TwoSlopeNorm

    vx, vy = result.varies[1], result.varies[0]     # the last varies fastest: along x
    shape = result.shape
    grid_x, grid_y = vx.values, vy.values
    failures = _failures(result)
    panels = _MAP_PANELS if _proportional(result) else _MAP_PANELS + (_ACCELERATION_PANEL,)
    panels += tuple((name, label, "RdYlGn") for name, _, label in breaking_columns(result.design))
    columns = -(-(len(panels) + bool(failures)) // 2)     # two rows; the outcome panel last, if any
    fig.set_size_inches(14.0 * columns / 3, 8.5)
    axes = fig.subplots(2, columns, gridspec_kw=dict(left=0.06, right=0.97, bottom=0.07, top=0.91,
                                                     wspace=0.45, hspace=0.35)).ravel()
    fig.suptitle(f"{result.design.name}: range and peak loads over {vy.field.name} and {vx.field.name}"
                 + (" (grey: no throw)" if _failures(result) else ", every setting throws"))
    for ax, (name, title, cmap) in zip(axes, panels, strict=False):
        values = (result.range if name == "range" else in_g(result.loads[name], result.design)
                  if name == _ACCELERATION_PANEL[0] else result.loads[name])
        if name == "peak_hinge_load":
            title = title.replace("peak hinge load", hinge_load_label(result.design))
        unit = title[title.rindex("(") + 1:-1]
        factor, shown = display(1.0, unit, units)   # colours and contour labels in the shown unit
        title = title.replace(f"({unit})", f"({shown})")
        z = np.ma.masked_invalid(factor * values.reshape(shape))
        ax.set_facecolor("0.85")
        margin = cmap == "RdYlGn" and z.count() > 0 and z.min() < 1.0 < z.max()   # red below 1, green above
        mesh = ax.pcolormesh(grid_x, grid_y, z, shading="nearest", cmap=cmap,
                             norm=TwoSlopeNorm(1.0) if margin else None)
        bar = fig.colorbar(mesh, ax=ax, shrink=0.9)
        if name == "peak_sling_tension" and _proportional(result):   # its ticks in N and in g
            weight = factor * _weight(result)
            # (bound now: the formatter runs when the figure is drawn, after the later panels)
            bar.ax.yaxis.set_major_formatter(lambda n, _, unit=shown, weight=weight: f"{n:.3g} {unit} = "
                                                                                    f"{n / weight:.3g} g")
            title = f"peak sling tension ({shown}) = projectile acceleration (g)"
        if z.count() > 3 and np.ptp(z.compressed()) > 0:
            lines = ax.contour(grid_x, grid_y, z, levels=8, colors="w", linewidths=0.6)
            ax.clabel(lines, fontsize=7, fmt="%.4g")
        if margin and z.count() > 3:   # where it breaks
            ax.contour(grid_x, grid_y, z, levels=[1.0], colors="k", linewidths=1.5)
        ax.set(title=title, xlabel=vx.field.label, ylabel=vy.field.label)
    if failures:   # the settings that do not throw; with none, nothing to show
        ax_status = axes[len(panels)]
        ax_status.set_facecolor("0.85")
        ok = result.status == "ok"
        ax_status.plot(result.settings[ok, 1], result.settings[ok, 0], ".", color="tab:green", ms=4,
                       label="throws")
        for (status, mask), marker in zip(failures.items(), _MARKERS, strict=False):
            ax_status.plot(result.settings[mask, 1], result.settings[mask, 0], marker, color="k", ms=5,
                           ls="none", label=status.replace("_", " "))
        ax_status.set(title="outcome", xlabel=vx.field.label, ylabel=vy.field.label)
        ax_status.legend(fontsize=8, loc="best")
    for ax in axes[len(panels) + bool(failures):]:
        ax.set_visible(False)
    return fig


def save_chart(result: Chart, out: str | Path, units: str = "metric") -> tuple[Path, Path]:
    """Write ``chart.csv`` (SI) and ``chart.png`` (shown in ``units``, ``analytic.plot_units``) into the
    folder ``out``; their paths."""
    from analytic.plot import save_figure
    from analytic.plot_units import in_units

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    csv_path, png_path = out / "chart.csv", out / "chart.png"
    write_csv(result, csv_path)
    save_figure(in_units(chart_figure(result, units), units), png_path)
    return csv_path, png_path


__all__ = ["BREAKING_COLUMNS", "Chart", "LOAD_COLUMNS", "Vary", "breaking_columns", "chart", "chart_figure",
           "save_chart", "vary", "write_csv"]
