"""Run a list of cases through both models, on several processes: the cross-check's ``Report``."""

from __future__ import annotations

import os
import sys
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from functools import partial

from analytic import fast
from analytic.limits import FAST, PATHS
from analytic.reference import simulate
from analytic.cli_shared import progress_bar
from analytic.result import Shot
from crosscheck.cases import Case, default_suite
from crosscheck.comparison import DEFAULT_DT, Comparison, compare


@dataclass(frozen=True)
class Report:
    """The cross-check of a list of cases.

    Attributes
    ----------
    comparisons : each case's ``Comparison`` (both models' statuses and every
        compared quantity with its difference and tolerance), in the order of the cases.
    dt : the engine's step, s.
    analytic_shots : the analytic model's ``Shot`` of each case (the summary of ``run``'s
        ``path``), in the same order.
    """

    comparisons: tuple[Comparison, ...]
    dt: float
    analytic_shots: tuple[Shot, ...] = field(default=(), repr=False, compare=False)

    @property
    def agree(self) -> bool:
        """Whether the models agree on every case, within every tolerance (``crosscheck.tolerances``)."""
        return all(c.agree for c in self.comparisons)

    @property
    def disagreements(self) -> tuple[Comparison, ...]:
        """The comparisons on which the models disagree."""
        return tuple(c for c in self.comparisons if not c.agree)

    def to_json(self) -> dict:
        """``{"agree": bool, "comparisons": [...]}``, as ``python -m crosscheck --json`` prints it."""
        return {"agree": self.agree, "comparisons": [c.to_json() for c in self.comparisons]}


def run(cases: list[Case] | None = None, *, dt: float = DEFAULT_DT, workers: int | None = None,
        progress: bool = False, path: str = FAST) -> Report:
    """Compare every case on both models.

    The analytic side of every case is shot first, in one fast-path batch
    (``analytic.fast.simulate_fast_many``, all cores, well under a second);
    the engine runs then take the processes.

    Parameters
    ----------
    cases : the designs to run (``default_suite()``, about a minute, when None;
        ``quick_suite()`` takes seconds; ``Case(name, design, group)`` wraps any design).
    dt : the engine's step, s.
    workers : processes for the engine runs (default: up to 2, the cores there are).
    progress : show a progress bar on stderr.
    path : the analytic model's path, one of ``analytic.limits.PATHS``: ``"fast"``, or
        ``"reference"``, the scipy path's summaries (``analytic.reference.simulate``): the same
        numbers to round-off, without the compile that a checkout's first fast shot pays (tens
        of seconds), at tens of milliseconds a design (seconds for one that flies for minutes).

    Returns
    -------
    Report
    """
    if path not in PATHS:
        raise ValueError(f"path = {path!r}: must be one of {', '.join(PATHS)}")
    cases = default_suite() if cases is None else list(cases)
    workers = min(2, os.cpu_count() or 1) if workers is None else workers
    designs = [case.design for case in cases]
    if path == FAST:
        fast.compile(fast.scope_for(designs), progress=progress)
        analytic = fast.simulate_fast_many(designs)
    else:
        analytic = [simulate(design, histories=False) for design in designs]
    bar = progress_bar(total=len(cases), desc="cross-check", unit="design", disable=not progress, file=sys.stderr)
    results = []
    if workers <= 1:
        for case, shot in zip(cases, analytic, strict=True):
            results.append(compare(case, dt=dt, analytic_shot=shot))
            bar.update()
    else:
        with ProcessPoolExecutor(max_workers=workers) as pool:
            for result in pool.map(partial(_compare_shot, dt=dt), cases, analytic):
                results.append(result)
                bar.update()
    bar.close()
    return Report(tuple(results), dt, tuple(analytic))


def _compare_shot(case: Case, shot: Shot, dt: float) -> Comparison:
    return compare(case, dt=dt, analytic_shot=shot)
