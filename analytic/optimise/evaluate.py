"""Score batches of candidate designs in parallel, counting the ones that fail to throw by kind.

The optimiser only ever sees a number per candidate: its range, or with a
release-angle scatter the expected range (``analytic.optimise.robust``). A
candidate that cannot be built (``DesignError``) or that does not throw
(``Status`` other than ``OK``) scores ``FAILURE_RANGE`` and is counted under
that kind, so the search goes on.

Two paths shoot the candidates, with the same answers (to round-off, ~1e-12
relative in range, except where a machine swings chaotically for seconds before
it releases; ``tests/test_analytic_optimise_fast.py``): ``"fast"`` (the default)
hands each batch to the compiled kernel in one call (``analytic.fast.shoot``,
threads on every core); ``"reference"`` runs ``analytic.reference`` one
shot at a time in a pool of worker processes, kept to compare against.
"""

from __future__ import annotations

import multiprocessing
from collections import Counter
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from typing import Self

import numpy as np

from analytic import fast
from analytic.design import DesignError
from analytic.optimise.problem import Problem, design_at
from analytic.optimise.robust import Scatter, expected, release_scatter
from analytic.result import Status
from analytic.reference import simulate

#: Score of a candidate that does not throw, m. Any throw does better: with the
#: velocity release rule and |release angle| < 90 deg the projectile leaves
#: forward, so it lands ahead of its release point, which is at most a long
#: arm plus a sling (< 2 m for the paper's bounds) behind the pivot.
FAILURE_RANGE = -10.0
#: The nominal problem: one node at the set release angle.
NO_SCATTER = release_scatter(0.0)
#: Failure kinds besides ``Status``: cannot be built / the simulator raised
#: (it promises a ``Status`` for every valid design; counted, should it break that).
DESIGN_ERROR, SIMULATOR_ERROR = "design_error", "simulator_error"
#: The two ways of shooting candidates (module docstring).
FAST, REFERENCE = "fast", "reference"
PATHS = (FAST, REFERENCE)
#: Worker processes of the reference path unless told otherwise.
DEFAULT_PROCESSES = 2


@dataclass(frozen=True)
class Throw:
    """One shot reduced to what the optimiser needs: the range (m), or the failure kind."""

    range: float | None
    failure: str | None = None


def throw(problem: Problem, values: np.ndarray, tolerance: float) -> Throw:
    """Simulate the design at ``values`` (shape (6,), m and rad) with rtol = atol = ``tolerance``.

    The reference path: ``analytic.reference.simulate``.
    """
    try:
        design = design_at(problem, values)
    except DesignError:
        return Throw(None, DESIGN_ERROR)
    try:
        shot = simulate(design, rtol=tolerance, atol=tolerance, histories=False)
    except ValueError:
        # simulate promises a Status for every valid design; count the ones where
        # it raises instead, so the search goes on and the report shows them.
        return Throw(None, SIMULATOR_ERROR)
    if not shot.ok:
        return Throw(None, shot.status.value)
    return Throw(shot.range)


def fast_throws(problem: Problem, values: np.ndarray, tolerance: float,
                threads: int | None = None) -> list[Throw]:
    """``throw`` for every row of ``values`` (shape (S, 6), m and rad) on the fast path, in one batch.

    The designs are built here (``DesignError``: not shot) and every buildable
    one goes to the kernel in a single ``analytic.fast.shoot`` call, which
    shares them among ``threads`` threads (default: every processor).
    """
    results: list[Throw | None] = [None] * len(values)
    built, rows = [], []
    for i, v in enumerate(values):
        try:
            design = design_at(problem, v)
        except DesignError:
            results[i] = Throw(None, DESIGN_ERROR)
        else:
            built.append(i)
            rows.append(fast.pack(design))
    if rows:
        shots = fast.shoot(np.array(rows), rtol=tolerance, atol=tolerance, threads=threads)
        for i, status, distance in zip(built, shots.status.tolist(), shots.range.tolist(), strict=True):
            results[i] = (Throw(distance) if status == Status.OK.value
                          else Throw(None, status))
    return results


_worker_problem: Problem | None = None


def _start_worker(problem: Problem) -> None:
    global _worker_problem
    _worker_problem = problem


def _throw_in_worker(task: tuple[np.ndarray, float]) -> Throw:
    return throw(_worker_problem, *task)


class Evaluator:
    """Scores designs of one problem on the fast path (threads) or the reference path (processes).

    Use as a context manager (on the reference path it owns a process pool
    when ``workers > 1``). Those workers are spawned, so a script that makes
    one needs the usual ``if __name__ == "__main__":`` guard.

    Parameters
    ----------
    problem : the problem whose designs are scored.
    path : ``"fast"`` or ``"reference"`` (module docstring).
    workers : threads (fast path; default ``analytic.fast.default_threads()``)
        or worker processes (reference path; default ``DEFAULT_PROCESSES``)
        shooting at once.

    Attributes
    ----------
    problem, path, workers : as given (``workers`` resolved to the number used).
    failures : failure kind -> number of shots that failed so.
    shots : number of shots simulated.
    """

    def __init__(self, problem: Problem, *, path: str = FAST, workers: int | None = None):
        if path not in PATHS:
            raise ValueError(f"path = {path!r}: must be one of {', '.join(PATHS)}")
        if workers is None:
            workers = fast.default_threads() if path == FAST else DEFAULT_PROCESSES
        if workers < 1:
            raise ValueError(f"workers = {workers!r}: need at least one")
        self.problem = problem
        self.path = path
        self.failures: Counter[str] = Counter()
        self.shots = 0
        self._pool = None
        if path == REFERENCE and workers > 1:
            # spawn, not fork: the parent may run threads (tqdm's monitor, a
            # batch's), and forking a threaded process can deadlock.
            self._pool = ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn"),
                                             initializer=_start_worker, initargs=(problem,))
        self.workers = workers

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        if self._pool is not None:
            self._pool.shutdown()
            self._pool = None

    def throws(self, values: np.ndarray, tolerance: float) -> list[Throw]:
        """Shoot each design once, in parallel (on the fast path in one batch), counting failures.

        Parameters
        ----------
        values : (S, n) design vectors (``problem.variables``), m, rad and kg.
        """
        values = np.asarray(values, dtype=float).reshape(-1, len(self.problem.variables))
        if self.path == FAST:
            results = self._fast_throws(values, tolerance)
        elif self._pool is None:
            results = [throw(self.problem, v, tolerance) for v in values]
        else:
            tasks = [(v, tolerance) for v in values]
            chunk = max(1, len(tasks) // (4 * self.workers))
            results = list(self._pool.map(_throw_in_worker, tasks, chunksize=chunk))
        self.shots += len(results)
        self.failures.update(r.failure for r in results if r.failure is not None)
        return results

    def _fast_throws(self, values: np.ndarray, tolerance: float) -> list[Throw]:
        return fast_throws(self.problem, values, tolerance, self.workers)

    def node_ranges(self, values: np.ndarray, tolerance: float, scatter: Scatter,
                    failure_range: float = FAILURE_RANGE) -> np.ndarray:
        """Ranges at the release-angle scatter's nodes, shape (S, n_nodes), m.

        Parameters
        ----------
        values : (S, n) set design vectors; each is shot with its release angle
            (index 5) moved by every node offset.
        failure_range : what a failed shot scores (``nan`` to mark it instead).
        """
        values = np.asarray(values, dtype=float).reshape(-1, len(self.problem.variables))
        offsets = scatter.offsets
        shots = np.repeat(values, len(offsets), axis=0)
        shots[:, 5] += np.tile(offsets, len(values))
        ranges = [failure_range if r.range is None else r.range for r in self.throws(shots, tolerance)]
        return np.array(ranges).reshape(len(values), len(offsets))

    def scores(self, values: np.ndarray, tolerance: float, scatter: Scatter = NO_SCATTER) -> np.ndarray:
        """Range (no scatter) or expected range (with scatter) of each design, shape (S,), m."""
        return expected(scatter, self.node_ranges(values, tolerance, scatter))
