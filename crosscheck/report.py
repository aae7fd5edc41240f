"""Cross-check output: the terminal table, the summary of worst cases, JSON and plots."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from crosscheck.comparison import AGREE, SENSITIVE, Comparison, Row, StepStudy, verdict_counts


def _display(value, unit: str) -> tuple[str, str]:
    """Value and unit as shown: radians become degrees here, at the edge."""
    if isinstance(value, str):
        return value, unit
    if value is None:
        return "-", unit
    if unit == "rad":
        return f"{math.degrees(value):.6g}", "deg"
    return f"{value:.6g}", unit


def format_table(comparisons: list[Comparison]) -> str:
    """Design, quantity, analytic, engine, difference, tolerance, verdict: one line each."""
    header = ("design", "quantity", "analytic", "engine", "difference", "tolerance", "verdict")
    lines = []
    for c in comparisons:
        if c.error:
            lines.append((c.case, "engine", c.analytic_status, c.engine_status, "-", "-",
                          f"{c.verdict.upper()}: {c.error}"))
        for row in c.rows:
            a, unit = _display(row.analytic, row.unit)
            e, _ = _display(row.engine, row.unit)
            d, _ = _display(row.difference, row.unit)
            t, _ = _display(row.tolerance, row.unit)
            lines.append((c.case, f"{row.quantity} ({unit})" if unit else row.quantity, a, e, d, t,
                          row_verdict(c, row)))
    widths = [max(len(str(r[i])) for r in [header, *lines]) for i in range(len(header))]
    return "\n".join("  ".join(str(v).ljust(w) for v, w in zip(r, widths, strict=True)).rstrip()
                     for r in [header, *lines])


def row_verdict(comparison: Comparison, row: Row) -> str:
    """One quantity's verdict: ``ok``; ``sensitive`` where it is apart but the design's own spread
    of it is over its tolerance (``Comparison.sensitivity``); ``FAIL`` otherwise."""
    if row.ok:
        return "ok"
    spread = (comparison.sensitivity or {}).get(row.quantity)
    if spread is not None and spread > (row.tolerance or 0.0):
        return "sensitive"
    return "FAIL"


def format_verdicts(comparisons: list[Comparison]) -> list[str]:
    """A line per case whose verdict is not ``agree``: the verdict and why (empty when all agree)."""
    lines = []
    for c in comparisons:
        if c.verdict == AGREE:
            continue
        if c.verdict == SENSITIVE:
            apart = [row for row in c.rows if not row.ok]
            worst = max(apart, key=lambda row: c.sensitivity.get(row.quantity, 0.0) / (row.tolerance or 1.0))
            spread, unit = _display(c.sensitivity[worst.quantity], worst.unit)
            tolerance, _ = _display(worst.tolerance, worst.unit)
            why = (f"{len(apart)} quantities apart, each moved past its tolerance by the design itself: "
                   f"{worst.quantity} spreads {spread} {unit} (tolerance {tolerance}) when the inputs "
                   f"move by parts in 1e9")
        elif c.error:
            why = c.error
        else:
            apart = [row.quantity for row in c.rows if not row.ok]
            why = f"apart on {', '.join(apart)}"
        lines.append(f"  {c.case}: {c.verdict} ({why})")
    return lines


def worst_cases(comparisons: list[Comparison]) -> dict[str, dict]:
    """For each quantity, the largest |difference| / tolerance and where it happened."""
    worst: dict[str, dict] = {}
    for c in comparisons:
        for row in c.rows:
            if row.difference is None or row_verdict(c, row) == "sensitive":
                continue
            ratio = abs(row.difference) / row.tolerance
            # 0 against 0 (a fixed frame's displacement, an absent loss's work) is no difference.
            relative = (abs(row.difference) / abs(row.analytic) if row.analytic
                        else math.inf if row.difference else 0.0)
            if ratio >= worst.get(row.quantity, {}).get("fraction_of_tolerance", -1.0):
                worst[row.quantity] = {"case": c.case, "difference": row.difference, "unit": row.unit,
                                       "relative": relative, "fraction_of_tolerance": ratio}
    return worst


def format_summary(comparisons: list[Comparison], study: StepStudy | None, steps_detail: bool = True,
                   title: str | None = None) -> str:
    """The verdict (after ``title``, if given), the worst case per quantity as a fraction of its
    tolerance, the engine's step and drift and the convergence study (with a line per step if
    ``steps_detail``)."""
    agreed = sum(c.agree for c in comparisons)
    outcomes = {}
    for c in comparisons:
        outcomes[c.analytic_status] = outcomes.get(c.analytic_status, 0) + 1
    lines = [("" if title is None else f"{title}: ") + f"{agreed} of {len(comparisons)} designs agree "
             f"(analytic outcomes: {', '.join(f'{k} {v}' for k, v in sorted(outcomes.items()))})"]
    others = format_verdicts(comparisons)
    if others:
        counts = verdict_counts(comparisons)
        lines.append("verdicts: " + ", ".join(f"{name} {n}" for name, n in counts.items() if n))
        lines += others
    lines.append("worst case per quantity (|difference| as a fraction of its tolerance; "
                 "sensitive quantities left out):")
    worst = worst_cases(comparisons)
    width = max(map(len, worst), default=0)
    for quantity, w in worst.items():
        shown, unit = _display(w["difference"], w["unit"])
        lines.append(f"  {quantity:<{width}} {shown:>12} {unit:<5} rel {w['relative']:.2e}  "
                     f"{w['fraction_of_tolerance']:.3f} of tolerance  ({w['case']})")
    steps = sorted({c.engine_dt for c in comparisons if c.engine_dt is not None})
    if len(steps) > 1:
        refined = [f"{c.case} ({c.engine_dt:.3g} s)" for c in comparisons if c.engine_dt not in (None, steps[-1])]
        lines.append("engine step finer than the run's where a case starts finer (the floating arm's), its "
                     "energy error was above the trust limit or the models differed at the coarser steps: "
                     f"{', '.join(refined)}")
    extrapolated = [f"{c.case} ({', '.join(c.extrapolated)})" for c in comparisons if c.extrapolated]
    if extrapolated:
        lines.append("engine values extrapolated from its last two steps (Richardson), the runs themselves "
                     f"still too coarse: {'; '.join(extrapolated)}")
    drifts = [c.max_joint_drift for c in comparisons if c.max_joint_drift is not None]
    engine = [f"largest joint drift {max(drifts):.3g} m"] if drifts else []
    if study is not None:
        engine.append(f"convergence on {study.design}: order {study.speed_order:.2f} (release speed), "
                      f"{study.range_order:.2f} (range)")
    if engine:
        lines.append("engine: " + "; ".join(engine))
    if study is not None:
        if steps_detail:
            for dt, s, r in zip(study.dt, study.speed_error, study.range_error, strict=True):
                lines.append(f"  dt {dt:.1e} s   speed error {s:.2e}   range error {r:.2e}")
    return "\n".join(lines)


def format_plain(comparisons: list[Comparison], details: str | None = None) -> str:
    """The cross-check in words a newcomer reads: whether the two models agree, how closely on
    the range, what a deliberate failure case is there for, and where the details are (``details``)."""
    agreed = [c for c in comparisons if c.agree]
    sensitive = [c.case for c in comparisons if c.verdict == SENSITIVE]
    ranges = [abs(row.difference) / abs(row.analytic) for c in comparisons for row in c.rows
              if row.quantity == "range" and row.difference is not None and row.analytic and c.verdict == AGREE]
    closeness = f", to {max(ranges):.1g} of the range at worst" if ranges else ""
    if len(agreed) == len(comparisons):
        lines = [f"the engine and the analytic model agree on all {len(comparisons)} designs{closeness}"]
    else:
        lines = [f"the engine and the analytic model DISAGREE on {len(comparisons) - len(agreed)} of "
                 f"{len(comparisons)} designs: "
                 + ", ".join(f"{c.case} ({c.verdict})" for c in comparisons if not c.agree)]
    if sensitive:
        lines.append(f"  too sensitive to compare (the design itself moves past a tolerance when its inputs "
                     f"move by parts in 1e9): {', '.join(sensitive)}")
    for c in comparisons:
        if c.group == "failure":
            lines.append(f"  ({c.case} is a design made to fail on purpose, ending in "
                         f"{c.analytic_status.replace('_', ' ')}: the check is that both models say so"
                         + (", and they do)" if c.agree else ")"))
    lines.append(f"details, quantity by quantity: {details}" if details is not None
                 else "details, quantity by quantity: add --table, or --report DIR for table.txt and plots")
    return "\n".join(lines)


def write_report(directory: str | Path, comparisons: list[Comparison], study: StepStudy | None) -> list[Path]:
    """``crosscheck.json``, ``table.txt`` (every design and quantity, and the summary) and three plots
    in ``directory``; returns the paths written."""
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    table = out / "table.txt"
    table.write_text(format_table(comparisons) + "\n\n" + format_summary(comparisons, study) + "\n")
    report = {"agree": all(c.agree for c in comparisons), "verdicts": verdict_counts(comparisons),
              "comparisons": [c.to_json() for c in comparisons],
              "worst": worst_cases(comparisons),
              "step_study": None if study is None else study.to_json()}
    paths = [out / "crosscheck.json", table]
    paths[0].write_text(json.dumps(report, indent=2))
    for name, figure in (("agreement.png", agreement_figure(comparisons)),
                         ("errors.png", error_figure(comparisons))):
        paths.append(out / name)
        _save(figure, paths[-1])
    if study is not None:
        paths.append(out / "convergence.png")
        _save(convergence_figure(study), paths[-1])
    return paths


def _save(figure: Figure, path: Path) -> None:
    FigureCanvasAgg(figure)
    figure.savefig(path, dpi=100)


_PLOTTED = ("release_speed", "launch_angle", "range", "apex_height", "release_time", "liftoff_time")


def agreement_figure(comparisons: list[Comparison]) -> Figure:
    """Engine against analytic for each quantity; points on the diagonal agree."""
    fig = Figure(figsize=(12, 7), layout="constrained")
    axes = fig.subplots(2, 3).ravel()
    drawn = []
    for ax, quantity in zip(axes, _PLOTTED, strict=True):
        pairs = [(r.analytic, r.engine, r.ok, r.unit) for c in comparisons for r in c.rows if r.quantity == quantity]
        if not pairs:
            ax.set_visible(False)
            continue
        unit = pairs[0][3]
        scale = (180.0 / math.pi) if unit == "rad" else 1.0
        a = np.array([p[0] for p in pairs]) * scale
        e = np.array([p[1] for p in pairs]) * scale
        ok = np.array([p[2] for p in pairs])
        span = [min(a.min(), e.min()), max(a.max(), e.max())]
        ax.plot(span, span, color="0.7", lw=1)
        ax.scatter(a[ok], e[ok], s=14, color="tab:blue", label="agree")
        if (~ok).any():
            ax.scatter(a[~ok], e[~ok], s=30, color="tab:red", marker="x", label="disagree")
        shown = "deg" if unit == "rad" else unit
        ax.set(title=quantity, xlabel=f"analytic ({shown})", ylabel=f"engine ({shown})")
        drawn.append(ax)
    if drawn:
        drawn[0].legend(fontsize=8)
    else:   # (designs that all fail before release: only their outcomes are compared)
        fig.text(0.5, 0.5, "no design reached a plotted quantity", ha="center", va="center")
    fig.suptitle("analytic vs engine, every design that reached each quantity")
    return fig


def error_figure(comparisons: list[Comparison]) -> Figure:
    """Distribution of |difference| / tolerance per quantity (1 = at the tolerance)."""
    fig = Figure(figsize=(10, 4.5), layout="constrained")
    ax = fig.subplots()
    quantities = sorted({r.quantity for c in comparisons for r in c.rows if r.difference is not None})
    data = [[max(abs(r.difference) / r.tolerance, 1e-8) for c in comparisons for r in c.rows
             if r.quantity == q] for q in quantities]
    if data:
        ax.boxplot(data, tick_labels=quantities, whis=(0, 100))
    ax.axhline(1.0, color="tab:red", lw=1, ls="--", label="tolerance")
    ax.set_yscale("log")
    ax.set(ylabel="|engine - analytic| / tolerance", title="error distribution over all designs")
    ax.tick_params(axis="x", rotation=30)
    ax.legend()
    return fig


def convergence_figure(study: StepStudy) -> Figure:
    """Engine error against step on log-log axes, with a slope-2 guide."""
    fig = Figure(figsize=(6, 4.5), layout="constrained")
    ax = fig.subplots()
    ax.loglog(study.dt, study.speed_error, "o-", label=f"release speed (order {study.speed_order:.2f})")
    ax.loglog(study.dt, study.range_error, "s-", label=f"range (order {study.range_order:.2f})")
    guide = study.range_error[0] * (study.dt / study.dt[0]) ** 2
    ax.loglog(study.dt, guide, "k:", label="slope 2")
    ax.set(xlabel="engine step (s)", ylabel="|engine / analytic - 1|",
           title=f"engine convergence on {study.design}")
    ax.legend()
    return fig
