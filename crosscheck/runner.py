"""Run a list of cases through both models, on several processes: the cross-check's ``Report``."""

from __future__ import annotations

import os
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import partial

from analytic import fast
from analytic.limits import FAST, PATHS
from analytic.reference import simulate
from analytic.cli_shared import progress_bar
from analytic.design import Design
from analytic.result import Shot
from crosscheck.cases import Case, default_suite
from crosscheck.comparison import (DEFAULT_DT, ENGINE_FAILED, Comparison, compare, engine_simulate,
                                   verdict_counts)
from crosscheck.pool import WorkerLost, map_in_processes


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
        """Whether no case is ``disagree``, ``engine_failed`` or ``engine_untrusted`` (a ``sensitive``
        case is listed, not counted against the models)."""
        return all(c.agree for c in self.comparisons)

    @property
    def disagreements(self) -> tuple[Comparison, ...]:
        """The comparisons that count against agreement (``Comparison.agree`` false)."""
        return tuple(c for c in self.comparisons if not c.agree)

    def verdicts(self) -> dict[str, int]:
        """How many cases have each verdict (``crosscheck.comparison.VERDICTS``, every one listed)."""
        return verdict_counts(self.comparisons)

    def to_json(self) -> dict:
        """``{"agree": bool, "verdicts": {...}, "comparisons": [...]}``, as ``python -m crosscheck
        --json`` prints it."""
        return {"agree": self.agree, "verdicts": self.verdicts(),
                "comparisons": [c.to_json() for c in self.comparisons]}



def run(cases: list[Case] | None = None, *, dt: float = DEFAULT_DT, workers: int | None = None,
        progress: bool = False, path: str = FAST,
        engine: Callable[[Design, float], Shot] | None = None) -> Report:
    """Compare every case on both models.

    The analytic side of every case is shot first, in one fast-path batch
    (``analytic.fast.simulate_fast_many``, all cores, well under a second);
    the engine runs then take the processes (``crosscheck.pool``). A worker
    that dies (a crash in the engine's C library, a signal) costs only the
    case it was running: that case's verdict is ``engine_failed`` with the
    reason, and the others complete.

    Parameters
    ----------
    cases : the designs to run (``default_suite()``, about a minute, when None;
        ``quick_suite()`` takes seconds; ``Case(name, design, group)`` wraps any design).
    dt : the engine's step, s.
    workers : processes for the engine runs (default: up to 2, the cores there are; 1: in this
        process, where a crash of the engine ends the run).
    progress : show a progress bar on stderr.
    path : the analytic model's path, one of ``analytic.limits.PATHS``: ``"fast"``, or
        ``"reference"``, the scipy path's summaries (``analytic.reference.simulate``): the same
        numbers to round-off, without the compile that a checkout's first fast shot pays (tens
        of seconds), at tens of milliseconds a design (seconds for one that flies for minutes).
    engine : ``(design, dt) -> Shot``, the engine as ``crosscheck.compare`` takes it (None: the
        pymunk model, ``crosscheck.comparison.engine_simulate``).

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
    tasks = [(case, shot) for case, shot in zip(cases, analytic, strict=True)]
    compare_one = partial(_compare_shot, dt=dt, engine=engine_simulate if engine is None else engine)
    if workers <= 1:
        results = []
        for task in tasks:
            results.append(compare_one(*task))
            bar.update()
    else:
        results = map_in_processes(compare_one, tasks, workers, done=lambda: bar.update())
        results = [_lost(case, shot, dt, result) if isinstance(result, WorkerLost) else result
                   for (case, shot), result in zip(tasks, results, strict=True)]
    bar.close()
    return Report(tuple(results), dt, tuple(analytic))


def _compare_shot(case: Case, shot: Shot, dt: float, engine: Callable[[Design, float], Shot]) -> Comparison:
    return compare(case, dt=dt, analytic_shot=shot, engine=engine)


def _lost(case: Case, shot: Shot, dt: float, lost: WorkerLost) -> Comparison:
    """The comparison of a case whose worker died: ``engine_failed``, the reason in ``error``."""
    return Comparison(case.name, case.group, shot.status.value, "error", (), None,
                      f"the engine's worker process {lost.reason} while running this case; the other cases "
                      f"went on in a new worker", engine_dt=dt, kind=case.design.machine.kind,
                      verdict=ENGINE_FAILED)
