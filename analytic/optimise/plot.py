"""Figures of an optimisation: convergence history, and range along each variable through the optimum."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from analytic.optimise.constraints import CONSTRAINT_NAMES, FEASIBILITY_TOLERANCE
from analytic.design_space import LOADS, Problem
from analytic.optimise.report import Scales
from analytic.plot_units import in_units
from analytic.optimise.search import Optimum
from analytic.optimise.sensitivity import Sensitivity
from analytic.summary import PEAK_UNITS

#: m: slings shorter than this throw ranges that oscillate with their length (``sensitivity.DEFAULT_POINTS``).
SHORT_SLING = 0.1
#: Axis label and kind of each variable: a machine's length (cm, or in), an angle (deg) or a mass (kg, or lb).
_LABELS = {"arm_short": ("short arm $L_{As}$", "short"), "counterweight_link": ("weight link $L_W$", "short"),
           "clearance": ("clearance", "short"), "sling_length": ("sling $L_S$", "short"),
           "starting_angle": (r"starting angle $\theta_0$", "deg"),
           "release_angle": (r"release angle $\theta$", "deg"), "frame_mass": ("frame mass", "mass")}


def convergence_figure(optima: dict[str, Optimum], system: str = "metric") -> Figure:
    """Best score against shots simulated, and the shortfall from the final score on a log scale.

    Parameters
    ----------
    optima : label -> ``Optimum`` (e.g. nominal and robust), drawn one after the other.
    system : the units shown, ``metric`` or ``imperial`` (``analytic.plot_units.in_units``).
    """
    figure = Figure(figsize=(11, 4.2), layout="constrained")
    best_ax, gap_ax = figure.subplots(1, 2)
    offset = 0
    for label, optimum in optima.items():
        history = optimum.history
        shots = history.shots + offset
        for stage, style in (("global", "-"), ("local", "-o")):
            mask = history.stage == stage
            if mask.any():
                best_ax.plot(shots[mask], history.best[mask], style, ms=3, label=f"{label}: {stage} stage")
                gap = np.maximum(optimum.score - history.best[mask], 1e-12)
                gap_ax.semilogy(shots[mask], gap, style, ms=3, label=f"{label}: {stage} stage")
        offset = shots[-1]
    score = score_label(next(iter(optima.values())).problem)
    name, unit = score[:score.rindex(" (")], score[score.rindex(" ("):]
    robust = "; robust: the expected range" if name == "range" and len(optima) > 1 else ""
    best_ax.set(xlabel="shots simulated", ylabel=f"best {name} so far{robust}{unit}", title="convergence")
    gap_ax.set(xlabel="shots simulated", ylabel=f"final - best so far{unit}",
               title="shortfall from the final optimum")
    for ax in (best_ax, gap_ax):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    return in_units(figure, system)


def score_label(problem: Problem) -> str:
    """What the optimiser maximises, for an axis: the range, or minus a peak load."""
    if problem.minimise is None:
        return "range (m)"
    unit = PEAK_UNITS[LOADS[problem.minimise]]
    return f"minus the peak {problem.minimise.replace('_', ' ')} ({unit})"


def _shown(name: str, values, scales: Scales):
    """A variable's value(s), SI, as its axis shows them (``Scales``: cm or in, deg, kg or lb), and that unit."""
    kind = _LABELS[name][1]
    if kind == "deg":
        return np.degrees(values), "deg"
    unit, factor = getattr(scales, kind)
    return factor * np.asarray(values), unit


def sensitivity_figure(problem: Problem, sensitivity: Sensitivity, title: str, system: str = "metric") -> Figure:
    """Range along each free variable across its bounds through the optimum, the others held.

    Stretches that violate a constraint are shaded and labelled with the
    constraints they violate; the axes span the variables' bounds. Shown in
    ``system``'s units (``metric``: the paper's cm; ``imperial``: in, lb, ft).
    """
    scales = Scales.of(system)
    count = len(sensitivity.variables)
    columns = min(3, count)
    rows = math.ceil(count / columns)
    figure = Figure(figsize=(4.2 * columns, 3.3 * rows), layout="constrained")
    axes = np.atleast_1d(figure.subplots(rows, columns, squeeze=False).ravel())
    label = "expected range (m)" if sensitivity.scatter.sigma > 0 else score_label(problem)
    for ax in axes[count:]:   # a grid of 3 columns may have more panels than variables
        ax.set_visible(False)
    for ax, row, index in zip(axes[:count], range(count), sensitivity.variables, strict=True):
        name = problem.variables[index].name
        x, unit = _shown(name, sensitivity.grid[row], scales)
        y = sensitivity.scores[row]
        ax.plot(x, y, "-", color="C0")
        infeasible = ~sensitivity.feasible[row]
        ax.plot(x[infeasible], y[infeasible], "x", color="C3", ms=3, markevery=4, label="violates a constraint")
        for start, stop in _runs(infeasible):
            ax.axvspan(x[start], x[stop], color="C3", alpha=0.12, lw=0)
            violated = np.any(sensitivity.margins[row, start:stop + 1] < -FEASIBILITY_TOLERANCE, axis=0)
            names = sorted({CONSTRAINT_NAMES[j].split(" (")[0] for j in np.flatnonzero(violated)})
            ax.text((x[start] + x[stop]) / 2, 0.03, "\n".join(names), transform=ax.get_xaxis_transform(),
                    ha="center", va="bottom", fontsize=7, color="C3")
        failed = ~np.isfinite(y)
        if failed.any():
            floor = np.min(y[~failed]) if (~failed).any() else 0.0
            ax.plot(x[failed], np.full(failed.sum(), floor), "v", color="k", ms=4, label="does not throw")
        ax.plot(_shown(name, sensitivity.optimum[index], scales)[0], sensitivity.score, "o", color="C2",
                label="optimum")
        ax.set(xlabel=f"{_LABELS[name][0]} ({unit})", ylabel=label)
        if name == "sling_length" and sensitivity.grid[row][0] < SHORT_SLING:
            ax.text(0.03, 0.97, f"under {_shown(name, SHORT_SLING, scales)[0]:.2g} {unit} the range oscillates: "
                                f"the short sling\n"
                                f"wobbles about the arm's tip, and release falls on\none wobble or the next "
                                f"(both models agree)", transform=ax.transAxes, va="top", fontsize=7, color="0.3")
        ax.grid(True, alpha=0.3)
    for ax in axes[count:]:
        ax.set_visible(False)
    legend = {}
    for ax in axes[:count]:
        for handle, text in zip(*ax.get_legend_handles_labels(), strict=True):
            legend.setdefault(text, handle)
    figure.legend(legend.values(), legend.keys(), loc="outside lower center", ncols=len(legend), fontsize=8)
    figure.suptitle(title)
    return in_units(figure, system)


def save_figure(figure: Figure, path: str | Path, dpi: int = 110) -> None:
    """Render with the Agg canvas (no pyplot) to ``path``."""
    FigureCanvasAgg(figure)
    figure.savefig(path, dpi=dpi)


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) indices of each run of True in ``mask``."""
    runs, start = [], None
    for i, flag in enumerate(mask):
        if flag and start is None:
            start = i
        if not flag and start is not None:
            runs.append((start, i - 1))
            start = None
    if start is not None:
        runs.append((start, len(mask) - 1))
    return runs
