"""The cross-check: the analytic model and the pymunk engine on the same designs, held to named tolerances.

The public names::

    from crosscheck import run, compare, Case, Report

    report = run(quick_suite())            # both models on every case -> Report
    report.agree                           # True when every quantity is within its tolerance
    for c in report.disagreements: ...     # Comparison: statuses and Rows (quantity, both values, tolerance)

* ``run(cases=None, *, dt, workers, progress) -> Report``: every case on both
  models (``default_suite()`` when no cases are given);
* ``compare(case, dt) -> Comparison``: one case;
* ``Case(name, design, group)``: a design to check; ``default_suite``,
  ``quick_suite``, ``sample_cases`` and ``file_cases`` build lists of them;
* ``Report``: the comparisons in order, ``agree``, ``disagreements``,
  ``to_json()``; ``Comparison`` and ``Row``: one case, one quantity.

The tolerances, each with the reason for its size, are ``crosscheck.tolerances``;
the command line is ``python -m crosscheck``.
"""

from __future__ import annotations

from crosscheck.cases import Case, default_suite, file_cases, quick_suite, sample_cases
from crosscheck.comparison import Comparison, Row, compare
from crosscheck.runner import Report, run

__all__ = ["Case", "Comparison", "Report", "Row", "compare", "default_suite", "file_cases", "quick_suite", "run",
           "sample_cases"]
