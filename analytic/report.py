"""Human-readable text for a shot (the non-JSON output of ``simulate``), in metric or imperial units."""

from __future__ import annotations

from analytic.result import Shot
from analytic.summary import LOSS_LABELS, row_text, summary_rows

__all__ = ["LOSS_LABELS", "format_shot"]


def format_shot(shot: Shot, units: str = "metric") -> str:
    """A table of the shot's outcome, in the units a builder reads: every row of
    ``analytic.summary.summary_rows``.

    Parameters
    ----------
    shot : the shot.
    units : ``"metric"`` (m, m/s, N) or ``"imperial"`` (ft, ft/s, lbf); times in s, angles
        in deg, the projectile's acceleration in g either way.
    """
    lines = [f"design   {shot.design.name}", f"status   {shot.status.value}: {shot.message}"]
    rows = [("  " * row.level + row.label, *row_text(row, units)) for row in summary_rows(shot)]
    width = max((len(r[0]) for r in rows), default=0)
    lines += [f"  {label:<{width}}  {value:>20}  {unit}" for label, value, unit in rows]
    lines += [f"warning  {warning}" for warning in shot.warnings]
    return "\n".join(lines)

