"""Figures of a sweep: the map over its grid, the output's distribution, the Sobol' indices."""

from __future__ import annotations

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.colors import ListedColormap
from matplotlib.figure import Figure
from matplotlib.patches import Patch

from analytic.fields import axis_label
from analytic.sweep.analyses import OK, GridMap, Sensitivity, Spread

#: One colour per failure, none of them in the output's colour map (viridis).
FAILURE_COLOURS = {"never_fires": "#4d4d4d", "never_lifts_off": "#8c8c8c", "hits_base_before_release": "#d62728",
                   "never_releases": "#ff9896", "no_landing": "#9467bd", "step_failed": "#000000",
                   "short_of_target": "#e377c2"}
_OUTPUT_LABELS = {"range": "range (m)", "y": "y"}
#: The unit each output's figures carry in legends (none for a test function's y).
_OUTPUT_UNITS = {"range": " m", "y": ""}


def label(field: str, units: dict) -> str:
    return axis_label(field, units.get(field, ""))


def _figure(size) -> Figure:
    figure = Figure(figsize=size, layout="constrained")
    FigureCanvasAgg(figure)
    return figure


def grid_figure(grid: GridMap, output: str, units: dict) -> Figure:
    """A heat map of the output over two grid fields (one field: the output along it), failures by status."""
    figure = _figure((8.5, 6.0) if len(grid.fields) == 2 else (8.5, 4.5))
    ax = figure.subplots()
    shown = np.where(grid.status == OK, grid.value, np.nan)
    failures = [name for name in FAILURE_COLOURS if (grid.status == name).any()]
    if len(grid.fields) == 2:
        x, y = grid.axes[1], grid.axes[0]
        mesh = ax.pcolormesh(x, y, shown, shading="nearest", cmap="viridis")
        figure.colorbar(mesh, ax=ax, label=_OUTPUT_LABELS.get(output, output))
        if failures:
            codes = np.full(grid.status.shape, np.nan)
            for i, name in enumerate(failures):
                codes[grid.status == name] = i
            ax.pcolormesh(x, y, codes, shading="nearest", vmin=-0.5, vmax=len(failures) - 0.5,
                          cmap=ListedColormap([FAILURE_COLOURS[name] for name in failures]))
        partial = (grid.status == OK) & (grid.thrown < 1.0)
        if partial.any():
            rows, cols = np.nonzero(partial)
            ax.plot(x[cols], y[rows], ".", color="white", ms=3, label="some shots failed")
        ax.set(xlabel=label(grid.fields[1], units), ylabel=label(grid.fields[0], units))
        best = grid.best
        if best is not None:
            ax.plot(best[1][1], best[1][0], "*", color="white", mec="black", ms=14, clip_on=False,
                    label=f"best {best[0]:.4g}{_OUTPUT_UNITS.get(output, '')}")
        handles = [Patch(color=FAILURE_COLOURS[name], label=name) for name in failures]
        ax.legend(handles=ax.get_legend_handles_labels()[0] + handles, loc="upper left", fontsize=8,
                  framealpha=0.85)
    else:
        x = grid.axes[0]
        ax.plot(x, shown, "-", color="C0", label=output)
        for name in failures:
            where = grid.status == name
            low = np.nanmin(shown) if np.isfinite(shown).any() else 0.0
            ax.plot(x[where], np.full(where.sum(), low), "|", ms=14, color=FAILURE_COLOURS[name], label=name)
        ax.set(xlabel=label(grid.fields[0], units), ylabel=_OUTPUT_LABELS.get(output, output))
        ax.legend(fontsize=8)
    ax.set_title(f"{output} over the grid" + (f" (mean of the {grid.shots_per_point} shots at each point)"
                                              if grid.shots_per_point > 1 else ""))
    return figure


def spread_figure(spread: Spread, output: str) -> Figure:
    """Histogram of the thrown shots' output, and the probability of reaching each distance."""
    done = "thrown" if output == "range" else "ok"
    figure = _figure((11, 4.2))
    hist, reach = figure.subplots(1, 2)
    name, unit = _OUTPUT_LABELS.get(output, output), _OUTPUT_UNITS.get(output, "")
    hist.hist(spread.values, bins=min(80, max(10, int(np.sqrt(max(spread.thrown, 1))))), color="C0", alpha=0.8)
    for q, value in spread.quantiles.items():
        hist.axvline(value, color="C3" if q == 50 else "0.4", ls="-" if q == 50 else ":", lw=1)
    hist.axvline(spread.mean, color="C1", lw=1.5, label=f"mean {spread.mean:.4g}{unit}, sd {spread.sd:.3g}{unit}")
    hist.plot([], [], color="0.4", ls=":", label="5, 25, 75, 95 % quantiles")
    hist.plot([], [], color="C3", label=f"median {spread.quantiles[50]:.4g}{unit}")
    failed = spread.shots - spread.thrown
    hist.set(xlabel=name, ylabel="shots",
             title=f"{spread.thrown} of {spread.shots} shots {done}" + (f" ({failed} failed)" if failed else ""))
    hist.legend(fontsize=8)
    if spread.thrown:
        # P(output >= the i-th smallest thrown value): the thrown shots from it on, over all shots.
        probability = (spread.thrown - np.arange(spread.thrown)) / spread.shots
        reach.step(spread.values, probability, where="post", color="C0")
        for distance, p in spread.reach:
            reach.plot(distance, p, "o", color="C3", ms=4)
            reach.annotate(f"{p:.3f}", (distance, p), textcoords="offset points",
                           xytext=(4, -12 if p > 0.9 else 4), fontsize=8)
    reach.set(xlabel=name, ylabel="probability of reaching at least", ylim=(-0.02, 1.02),
              title="probability of reaching a distance (failures never reach)")
    reach.grid(alpha=0.3)
    return figure


def sensitivity_figure(indices: Sensitivity, output: str) -> Figure:
    """First-order and total Sobol' indices per field, with their confidence intervals."""
    figure = _figure((max(6.0, 1.3 * len(indices.fields) + 2.5), 4.5))
    ax = figure.subplots()
    at = np.arange(len(indices.fields))
    width = 0.38
    ax.bar(at - width / 2, indices.first, width, yerr=indices.first_conf, capsize=3, label="first order $S_1$")
    ax.bar(at + width / 2, indices.total, width, yerr=indices.total_conf, capsize=3, label="total $S_T$")
    ax.axhline(0.0, color="0.3", lw=0.8)
    ax.set_xticks(at, indices.fields, rotation=20, ha="right")
    ax.set(ylabel="Sobol' index",
           title=f"sensitivity of {output}: {indices.base_samples} base samples, "
                 f"{indices.confidence:.0%} intervals (SALib)")
    ax.legend()
    return figure
