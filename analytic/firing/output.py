"""A firing table's files: CSV (a row a setting), JSON (``FiringTable.to_json``), a printable one-page card.

The card is an A4 page, portrait, drawn with matplotlib's Agg canvas: the
machine's name, the date, the units and the field adjusted on top; a row a
target and a column a projectile mass, each cell the settings that land there
in big type (and, calibrated, the band of one standard deviation); the
calibration's shots underneath. Everything a builder reads at the machine is
in the ``--units`` chosen; the CSV and JSON stay SI.
"""

from __future__ import annotations

import csv
import datetime
import json
import math
from pathlib import Path

from analytic.firing.table import FiringTable
from analytic.units import ANGLE, display

#: The files a table is written to, inside the ``--out`` folder.
FILE_NAMES = {"csv": "firing-table.csv", "json": "firing-table.json", "png": "firing-table.png"}
#: The card's page, inches (A4 portrait) and its resolution, dots per inch.
PAGE = (8.27, 11.69)
CARD_DPI = 150
#: The cells' type size, points, for a table of a few rows; smaller as rows and columns grow.
CELL_POINTS = 22
SMALLEST_POINTS = 9


def paths(out: str | Path) -> dict[str, Path]:
    """The files a table writes into ``out``: kind -> path."""
    return {kind: Path(out) / name for kind, name in FILE_NAMES.items()}


def write_csv(table: FiringTable, path: str | Path) -> None:
    """A row a setting (an out-of-reach entry: one row with no setting), SI, the setting in its file unit."""
    fitted = table.fitted is not None
    header = ["target [m]", "projectile_mass [kg]", "field", "status", "solution",
              f"setting [{table.field.unit}]", "landed [m]", f"metres_per_unit [m/{table.field.unit or '1'}]"]
    if fitted:
        header += ["predicted [m]", "range_sd [m]", "fit_sd [m]", "band_1sd_low [m]", "band_1sd_high [m]",
                   "band_2sd_low [m]", "band_2sd_high [m]", "calibration_shots"]

    def cell(value) -> str:
        return "" if value is None or not math.isfinite(value) else repr(float(value))

    with Path(path).open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(header)
        for e in table.entries:
            if not e.settings:
                writer.writerow([cell(e.target), cell(e.projectile_mass), table.field.name, e.status]
                                + [""] * (len(header) - 4))
                continue
            one, two = e.bands(1.0), e.bands(2.0)
            for i, value in enumerate(e.settings):
                row = [cell(e.target), cell(e.projectile_mass), table.field.name, e.status, str(i + 1),
                       cell(value), cell(e.landed[i]), cell(e.metres_per_unit[i])]
                if fitted:
                    row += [cell(e.predicted[i]), cell(e.range_sd[i]), cell(e.fit_sd[i]), cell(one[i][0]),
                            cell(one[i][1]), cell(two[i][0]), cell(two[i][1]), str(table.fitted.shots)]
                writer.writerow(row)


def write_json(table: FiringTable, path: str | Path, system: str = "metric") -> None:
    Path(path).write_text(json.dumps(table.to_json(system), indent=2) + "\n")


def _shown(value: float, unit: str, system: str) -> tuple[float, str]:
    """``display`` with file units' spellings (``kg``, ``m``; ``deg`` and pure numbers pass)."""
    return display(value, unit, system)


def setting_text(table: FiringTable, value: float, system: str) -> str:
    """One setting as the card and the text show it: in ``system``'s units, angles in degrees."""
    shown, unit = _shown(value, table.field.unit, system)
    digits = 1 if table.field.kind is ANGLE else 3
    return f"{shown:.{digits}f}{'°' if unit == 'deg' else (' ' + unit if unit else '')}"


def card_figure(table: FiringTable, system: str = "metric", date: datetime.date | None = None):
    """The printable card as a ``matplotlib.figure.Figure`` (one A4 page)."""
    from matplotlib.figure import Figure

    date = date or datetime.date.today()
    fig = Figure(figsize=PAGE)
    length = _shown(1.0, "m", system)[1]
    mass_unit = _shown(1.0, "kg", system)[1]
    setting_unit = "deg" if table.field.kind is ANGLE else (_shown(1.0, table.field.unit, system)[1] or "")
    fig.text(0.5, 0.965, table.design.name, ha="center", va="top", fontsize=30, weight="bold")
    fig.text(0.5, 0.915, f"firing table: set {table.field.name}" + (f" ({setting_unit})" if setting_unit else ""),
             ha="center", va="top", fontsize=17)
    fig.text(0.5, 0.883, f"{date.isoformat()}   ·   units: {system} (distances in {length}, masses in "
                         f"{mass_unit})", ha="center", va="top", fontsize=13, color="0.3")
    columns, rows = len(table.masses), len(table.targets)
    top, bottom, left, right = 0.845, 0.11, 0.06, 0.96
    head = 0.04
    row_height = min(0.1, (top - head - bottom) / max(rows, 1))   # a short table keeps its rows compact
    col_width = (right - left - 0.18) / max(columns, 1)
    lines = 1 + (table.fitted is not None)
    size = max(SMALLEST_POINTS, min(CELL_POINTS, row_height * PAGE[1] * 72 / (1.6 * lines),
                                    col_width * PAGE[0] * 72 / 9.0))
    fig.text(left, top - head / 2, f"target ({length})", va="center", fontsize=size * 0.8, weight="bold")
    for j, mass in enumerate(table.masses):
        x = left + 0.18 + (j + 0.5) * col_width
        shown_mass, unit = _shown(float(mass), "kg", system)
        fig.text(x, top - head / 2, f"{shown_mass:.3g} {unit}", ha="center", va="center", fontsize=size * 0.8,
                 weight="bold")
    by_cell = {(e.projectile_mass, e.target): e for e in table.entries}
    for i, target in enumerate(table.targets):
        y = top - head - (i + 0.5) * row_height
        if i % 2 == 0:
            fig.patches.append(_band_patch(fig, left, y - row_height / 2, right - left, row_height))
        shown_target, _ = _shown(float(target), "m", system)
        fig.text(left, y, f"{shown_target:.4g}", va="center", fontsize=size, weight="bold")
        for j, mass in enumerate(table.masses):
            entry = by_cell[(float(mass), float(target))]
            x = left + 0.18 + (j + 0.5) * col_width
            if not entry.settings:
                fig.text(x, y, "out of reach", ha="center", va="center", fontsize=size * 0.7, color="0.45",
                         style="italic")
                continue
            text = " / ".join(setting_text(table, v, system).replace(f" {setting_unit}", "")
                              for v in entry.settings)
            band = entry.band()
            if band is None:
                fig.text(x, y, text, ha="center", va="center", fontsize=size)
                continue
            half = 0.5 * (band[0][1] - band[0][0])
            spread, _ = _shown(half, "m", system)
            fig.text(x, y + row_height * 0.16, text, ha="center", va="center", fontsize=size)
            fig.text(x, y - row_height * 0.24, f"± {spread:.{1 if spread >= 1.0 else 2}f} {length}", ha="center",
                     va="center", fontsize=size * 0.6, color="0.3")
    notes = ["two settings in a cell: a low and a high throw (either lands there)"
             if any(len(e.settings) > 1 for e in table.entries) else "",
             "reference path, within 1 mm of the target"]
    if table.fitted is not None:
        notes[:0] = [f"calibrated on {table.fitted.shots} measured shot{'s' if table.fitted.shots != 1 else ''} "
                     f"({table.fitted.spec.path.name})",
                     "± one standard deviation of where a shot lands (68 %; twice it: 95 %)"]
    below = top - head - rows * row_height - 0.03
    fig.text(0.5, below, "\n".join(n for n in notes if n), ha="center", va="top", fontsize=12, color="0.25",
             linespacing=1.6)
    return fig


def _band_patch(fig, x, y, width, height):
    from matplotlib.patches import Rectangle

    return Rectangle((x, y), width, height, transform=fig.transFigure, facecolor="0.93", edgecolor="none",
                     zorder=-1)


def write_card(table: FiringTable, path: str | Path, system: str = "metric") -> None:
    from analytic.plot import save_figure

    save_figure(card_figure(table, system), path, dpi=CARD_DPI)


def save_table(table: FiringTable, out: str | Path, system: str = "metric") -> dict[str, Path]:
    """Write the CSV, the JSON and the card into the folder ``out``; their paths by kind."""
    written = paths(out)
    write_csv(table, written["csv"])
    write_json(table, written["json"], system)
    write_card(table, written["png"], system)
    return written


def format_table(table: FiringTable, system: str = "metric") -> str:
    """The table as text for a builder, in ``system``'s units."""
    length = _shown(1.0, "m", system)[1]
    lines = [f"firing table of {table.design.name}: {table.field.name}, "
             f"{len(table.targets)} targets x {len(table.masses)} projectile mass{'es' if len(table.masses) > 1 else ''}"]
    if table.fitted is not None:
        lines.append(f"  calibrated on {table.fitted.shots} measured shots ({table.fitted.spec.path.name}); "
                     f"band: one standard deviation of where a shot lands")
    for e in table.entries:
        target, _ = _shown(e.target, "m", system)
        mass, mass_unit = _shown(e.projectile_mass, "kg", system)
        head = f"  {target:9.3f} {length}  {mass:8.4g} {mass_unit}: "
        if not e.settings:
            lines.append(head + "out of reach")
            continue
        parts = []
        one = e.bands(1.0)
        for i, value in enumerate(e.settings):
            part = setting_text(table, value, system)
            if one is not None:
                spread, _ = _shown(e.range_sd[i], "m", system)
                part += f" (±{spread:.3g} {length})"
            parts.append(part)
        lines.append(head + " or ".join(parts))
    return "\n".join(lines)
