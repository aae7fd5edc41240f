"""The cross-check: the analytic model and the pymunk engine on the same designs, held to named tolerances.

The public names, each loaded on first use (as ``analytic``'s)::

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

import importlib

#: Public name -> the module that defines it.
_EXPORTS = {
    "run": "crosscheck.runner", "Report": "crosscheck.runner",
    "compare": "crosscheck.comparison", "Comparison": "crosscheck.comparison", "Row": "crosscheck.comparison",
    "Case": "crosscheck.cases", "default_suite": "crosscheck.cases", "quick_suite": "crosscheck.cases",
    "sample_cases": "crosscheck.cases", "file_cases": "crosscheck.cases",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name not in _EXPORTS:
        raise AttributeError(f"module 'crosscheck' has no attribute {name!r}")
    value = getattr(importlib.import_module(_EXPORTS[name]), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_EXPORTS))
