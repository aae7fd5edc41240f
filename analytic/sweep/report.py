"""The report of a finished sweep: a summary (text and JSON) and the figures that apply to it.

* a grid of one or two fields: the output over it, failures marked by status
  (``grid.png``);
* a sample without a grid: the output's distribution, quantiles and the
  probability of reaching each distance (``distribution.png``);
* a Sobol' sample without a grid: first-order and total indices with their
  confidence intervals (``sensitivity.png``).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from analytic.design import DesignError
from analytic.plot_units import in_units
from analytic.sweep import analyses, plot, storage
from analytic.units import display


@dataclass(frozen=True)
class Report:
    """A sweep's report: ``summary`` (JSON-ready), its ``text``, and the files written (paths)."""

    summary: dict
    text: str
    files: tuple[Path, ...]


def check_results(results: str | Path) -> dict:
    """The settings of a finished sweep's results folder.

    Raises
    ------
    DesignError
        if ``results`` is not a sweep's results folder, or some of its chunks are missing.
    """
    results = Path(results)
    if not (results / storage.SETTINGS_NAME).is_file():
        raise DesignError("--report", str(results), f"not a sweep's results folder (no {storage.SETTINGS_NAME})")
    settings = storage.read_settings(results)
    if settings.get("format") != storage.FORMAT:
        raise DesignError("--report", str(results), f"results of format {settings.get('format')!r}; "
                                                    f"this version reads format {storage.FORMAT}")
    chunks = settings["sweep"]["chunks"]
    written = storage.written_chunks(results)
    if len(written) < chunks:
        raise DesignError("--report", str(results), f"{len(written)} of {chunks} chunks written: the sweep is "
                                                    f"not finished; run it again with the same --out to resume")
    return settings


def make_report(results: str | Path, out: str | Path | None = None, distances=None,
                system: str = "metric") -> Report:
    """Analyse a finished sweep and write the summary and figures.

    Parameters
    ----------
    results : the sweep's results folder.
    out : where to write (default ``RESULTS/_report``, which pyarrow's dataset reader skips).
    distances : where to give the probability of reaching (default: round numbers across the outputs).
    system : the units of the summary's text, ``metric`` or ``imperial`` (``analytic.units.display``);
        the figures are labelled in them too (``analytic.plot_units``); ``summary.json`` stays in the
        file units (SI, degrees).
    """
    settings = check_results(results)
    sweep = settings["sweep"]
    output, units = sweep["output"], sweep["units"]
    output_unit = "m" if output == "range" else ""

    def shown(value: float, unit: str, fmt: str = ".6g") -> str:
        number, label = display(value, unit, system)
        return f"{number:{fmt}} {label}".rstrip()
    table = storage.read_table(results, ["status", output], ordered=False)
    out = Path(results) / storage.REPORT_NAME if out is None else Path(out)
    out.mkdir(parents=True, exist_ok=True)
    statuses = analyses.status_counts(*analyses.status_codes(table["status"]))
    summary: dict = {"name": settings.get("name"), "shots": table.num_rows, "output": output,
                     "statuses": statuses}
    lines = [f"sweep {settings.get('name')}: {table.num_rows} shots, "
             + ", ".join(f"{n} {name}" for name, n in summary["statuses"].items())]
    files = []

    grid = analyses.grid_map(settings, table)
    if grid is not None:
        best = grid.best
        summary["grid"] = {"fields": list(grid.fields), "shape": list(grid.value.shape),
                           "points_thrown": int(np.count_nonzero(grid.status == analyses.OK)),
                           "best": None if best is None else {"value": best[0], "at": dict(zip(grid.fields, best[1]))}}
        lines.append(f"grid over {' x '.join(grid.fields)} ({' x '.join(map(str, grid.value.shape))} points): "
                     f"{summary['grid']['points_thrown']} points throw")
        if best is not None:
            where = ", ".join(f"{f} = {shown(v, units.get(f, ''))}" for f, v in zip(grid.fields, best[1]))
            lines.append(f"  best {output} {shown(best[0], output_unit)} at {where}")
        files.append(_save(in_units(plot.grid_figure(grid, output, units), system), out / "grid.png"))
    elif sweep["grid"]:
        lines.append(f"grid of {len(sweep['grid'])} fields: maps are drawn for grids of one or two fields")

    spread = analyses.spread(settings, table, distances)
    if spread is not None:
        summary["distribution"] = {"shots": spread.shots, "thrown": spread.thrown, "mean": spread.mean,
                                   "sd": spread.sd, "quantiles": {str(q): v for q, v in spread.quantiles.items()},
                                   "reach": [{"distance": d, "probability": p} for d, p in spread.reach]}
        lines += [f"{output} over the sample: mean {shown(spread.mean, output_unit)}, "
                  f"sd {shown(spread.sd, output_unit, '.4g')} ({spread.thrown} of {spread.shots} thrown)",
                  "  quantiles " + ", ".join(f"{q} %: {shown(v, output_unit, '.5g')}"
                                             for q, v in spread.quantiles.items()),
                  "  probability of reaching " + ", ".join(f"{shown(d, output_unit, 'g')}: {p:.4f}"
                                                           for d, p in spread.reach)]
        files.append(_save(in_units(plot.spread_figure(spread, output), system), out / "distribution.png"))

    indices = analyses.sensitivity(settings, table)
    if isinstance(indices, analyses.Sensitivity):
        summary["sensitivity"] = {field: {"S1": float(s1), "S1_conf": float(c1), "ST": float(st), "ST_conf": float(ct)}
                                  for field, s1, c1, st, ct in zip(indices.fields, indices.first, indices.first_conf,
                                                                   indices.total, indices.total_conf)}
        lines.append(f"Sobol' indices of {output} ({indices.base_samples} base samples, "
                     f"{indices.confidence:.0%} intervals):")
        lines += [f"  {field:<32} S1 {s1:7.4f} +- {c1:.4f}   ST {st:7.4f} +- {ct:.4f}"
                  for field, s1, c1, st, ct in zip(indices.fields, indices.first, indices.first_conf,
                                                   indices.total, indices.total_conf)]
        files.append(_save(plot.sensitivity_figure(indices, output), out / "sensitivity.png"))
    elif settings["sweep"]["sample"] is not None:
        summary["sensitivity"] = None
        lines.append(f"Sobol' indices: none ({indices})")

    summary["files"] = [str(path) for path in files]
    text = "\n".join(lines)
    (out / "summary.txt").write_text(text + "\n")
    (out / "summary.json").write_text(json.dumps(summary, indent=1))
    return Report(summary, text, (*files, out / "summary.txt", out / "summary.json"))


def _save(figure, path: Path) -> Path:
    figure.savefig(path, dpi=110)
    return path
