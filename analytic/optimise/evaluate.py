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
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from typing import Self

import numpy as np

from analytic.design import DesignError
from analytic.design_space import LOADS, Problem, design_at
from analytic.limits import FAST, PATHS, REFERENCE   # the two ways of shooting candidates (module docstring)
from analytic.optimise.robust import Scatter, expected, release_scatter
from analytic.result import PEAK_NAMES, Status
from analytic.data.strength import bending_stress
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
#: Worker processes of the reference path unless told otherwise.
DEFAULT_PROCESSES = 2


#: Score of a candidate that does not throw when a peak load is minimised (minus a load, N):
#: below any load a throw that keeps its range could have.
FAILURE_LOAD_SCORE = -1e9


@dataclass(frozen=True)
class Throw:
    """One shot reduced to what the optimiser needs: the range (m), or the failure kind, and
    the peak loads (``analytic.result.PEAK_NAMES`` -> N or m/s^2; empty for a failure)."""

    range: float | None
    failure: str | None = None
    loads: dict[str, float] = field(default_factory=dict)


def throw(problem: Problem, values: np.ndarray, tolerance: float, loads: bool = True) -> Throw:
    """Simulate the design at ``values`` (shape (6,), m and rad) with rtol = atol = ``tolerance``.

    The reference path: ``analytic.reference.simulate``; ``loads``: find the peak loads too.
    """
    try:
        design = design_at(problem, values)
    except DesignError:
        return Throw(None, DESIGN_ERROR)
    try:
        shot = simulate(design, rtol=tolerance, atol=tolerance, histories=False, loads=loads)
    except ValueError:
        # simulate promises a Status for every valid design; count the ones where
        # it raises instead, so the search goes on and the report shows them.
        return Throw(None, SIMULATOR_ERROR)
    if not shot.ok:
        return Throw(None, shot.status.value)
    return Throw(shot.range, loads={name: getattr(shot, name) for name in PEAK_NAMES} if loads else {})


def fast_throws(problem: Problem, values: np.ndarray, tolerance: float,
                threads: int | None = None, loads: bool = True) -> list[Throw]:
    """``throw`` for every row of ``values`` (shape (S, 6), m and rad) on the fast path, in one batch.

    The designs are built here (``DesignError``: not shot) and every buildable
    one goes to the kernel in a single ``analytic.fast.shoot`` call, which
    shares them among ``threads`` threads (default: every processor); ``loads``: find the
    peak loads too.
    """
    # Imported here, not at the top: importing the fast path imports numba, which the reference
    # path never needs, nor the command line's other tools, whose parser imports this module.
    from analytic import fast

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
        shots = fast.shoot(np.array(rows), rtol=tolerance, atol=tolerance, threads=threads, loads=loads)
        for j, (i, status, distance) in enumerate(zip(built, shots.status.tolist(), shots.range.tolist(),
                                                      strict=True)):
            peaks = {name: float(getattr(shots, name)[j]) for name in PEAK_NAMES} if loads else {}
            results[i] = Throw(distance, loads=peaks) if status is Status.OK else Throw(None, status.value)
    return results


_worker_problem: Problem | None = None


def _start_worker(problem: Problem) -> None:
    global _worker_problem
    _worker_problem = problem


def _throw_in_worker(task: tuple[np.ndarray, float, bool]) -> Throw:
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
    check : called before every batch of shots; what it raises ends the search there (a
        workbench job that was cancelled, or ran out of time).

    Attributes
    ----------
    problem, path, workers : as given (``workers`` resolved to the number used).
    failures : failure kind -> number of shots that failed so.
    shots : number of shots simulated.
    """

    def __init__(self, problem: Problem, *, path: str = FAST, workers: int | None = None,
                 check: Callable[[], None] | None = None):
        if path not in PATHS:
            raise ValueError(f"path = {path!r}: must be one of {', '.join(PATHS)}")
        if workers is None and path == FAST:
            from analytic.fast import default_threads   # (imported where used: see fast_throws)

            workers = default_threads()
        elif workers is None:
            workers = DEFAULT_PROCESSES
        if workers < 1:
            raise ValueError(f"workers = {workers!r}: need at least one")
        self.problem = problem
        self.path = path
        self._check = check
        self.failures: Counter[str] = Counter()
        self.shots = 0
        self._pool = None
        self._outcomes: dict[tuple[bytes, float], tuple[float, np.ndarray]] = {}
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

    def throws(self, values: np.ndarray, tolerance: float, loads: bool | None = None) -> list[Throw]:
        """Shoot each design once, in parallel (on the fast path in one batch), counting failures.

        Parameters
        ----------
        values : (S, n) design vectors (``problem.variables``), m, rad and kg.
        loads : find the peak loads; by default only when the problem constrains them.
        """
        if self._check is not None:
            self._check()
        values = np.asarray(values, dtype=float).reshape(-1, len(self.problem.variables))
        if loads is None:
            loads = bool(self.problem.outcome_constraints)
        if self.path == FAST:
            results = self._fast_throws(values, tolerance, loads)
        elif self._pool is None:
            results = [throw(self.problem, v, tolerance, loads) for v in values]
        else:
            tasks = [(v, tolerance, loads) for v in values]
            chunk = max(1, len(tasks) // (4 * self.workers))
            results = list(self._pool.map(_throw_in_worker, tasks, chunksize=chunk))
        self.shots += len(results)
        self.failures.update(r.failure for r in results if r.failure is not None)
        return results

    def _fast_throws(self, values: np.ndarray, tolerance: float, loads: bool) -> list[Throw]:
        return fast_throws(self.problem, values, tolerance, self.workers, loads)

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
        """Range (no scatter) or expected range (with scatter) of each design, shape (S,), m;
        for a problem that minimises a load, minus that peak load (``outcomes``)."""
        if self.problem.minimise is not None:
            if scatter.sigma != 0.0:
                raise ValueError("a problem that minimises a load has no release-angle scatter variant")
            return self.outcomes(values, tolerance)[0]
        return expected(scatter, self.node_ranges(values, tolerance, scatter))

    def outcomes(self, values: np.ndarray, tolerance: float) -> tuple[np.ndarray, np.ndarray]:
        """Score and the constraints on what each shot does, from one shot a design (nominal).

        The score is as ``scores``. The constraints (``problem.outcome_constraints``) are
        relative margins, feasible when >= 0: ``1 - peak / limit`` for each load limit,
        ``1 - least / actual`` arm safety factor with a least one, and
        ``range / min_range - 1`` when a load is minimised; -1 each for a failed shot. Shots
        are remembered by design and tolerance: the global stage asks for a generation's
        constraints and then its scores.

        Returns
        -------
        scores : (S,), m (or -N, -m/s^2).
        margins : (S, m) with m = len(problem.outcome_constraints).
        """
        values = np.asarray(values, dtype=float).reshape(-1, len(self.problem.variables))
        missing = [v for v in values if (v.tobytes(), tolerance) not in self._outcomes]
        if missing:
            for v, result in zip(missing, self.throws(np.array(missing), tolerance), strict=True):
                self._outcomes[(v.tobytes(), tolerance)] = self._outcome(result)
        rows = [self._outcomes[(v.tobytes(), tolerance)] for v in values]
        margins = np.array([r[1] for r in rows]).reshape(len(values), len(self.problem.outcome_constraints))
        return np.array([r[0] for r in rows]), margins

    def _outcome(self, result: Throw) -> tuple[float, np.ndarray]:
        problem = self.problem
        count = len(problem.outcome_constraints)
        if result.range is None:
            failed = FAILURE_RANGE if problem.minimise is None else FAILURE_LOAD_SCORE
            return failed, -np.ones(count)
        margins = [1.0 - result.loads[LOADS[load]] / limit for load, limit in problem.load_limits]
        if problem.min_arm_safety_factor is not None:   # 1 - least / actual safety factor: a load's margin
            arm = problem.arm
            stress = bending_stress(result.loads["peak_arm_bending_moment"], arm.width, arm.depth)
            margins.append(1.0 - problem.min_arm_safety_factor * stress / arm.section.bending_strength)
        if problem.minimise is not None:
            margins.append(result.range / problem.min_range - 1.0)
            return -result.loads[LOADS[problem.minimise]], np.array(margins)
        return result.range, np.array(margins)
