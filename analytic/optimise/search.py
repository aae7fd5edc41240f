"""Maximise range: differential evolution over the box, then SLSQP on its best point.

Global stage: ``scipy.optimize.differential_evolution`` rather than the
paper's particle swarm. SciPy has no particle swarm; DE is its maintained
population method, seeded and reproducible, it handles the constraints by
Lampinen's feasibility rules (a feasible candidate beats an infeasible one,
two infeasible ones compare by violation), so no penalty weight has to be
tuned and infeasible candidates are never simulated, and with
``vectorized=True`` it hands over each generation whole, which
``Evaluator`` shoots in one batch (on numba's threads, or on the reference
path's worker processes). It runs a fixed budget of
generations (or fewer, once its population's ranges agree): it only has to
deliver a point in the optimum's basin.

Local stage: SLSQP (the same active-set SQP family as the paper's fmincon) from
the global best, with the range's gradient by parallel finite differences and
the geometric constraints' by cheap central differences.

Both stages work on the free variables scaled to [0, 1] and minimise
``-score``, where score is the range, or the expected range under a
release-angle scatter.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
from scipy.optimize import NonlinearConstraint, differential_evolution, minimize

from analytic.optimise.constraints import FEASIBILITY_TOLERANCE
from analytic.optimise.evaluate import NO_SCATTER, Evaluator
from analytic.optimise.kkt import (FirstOrder, constraint_jacobian, first_order, outcome_gradient,
                                   range_gradient, unit_constraints)
from analytic.design_space import Problem, from_unit, to_unit
from analytic.optimise.robust import Scatter
from analytic.limits import DEFAULT_RTOL

#: SLSQP stops once a step changes the objective (range / its starting value) by
#: less than this: 1e-10 of ~50 m is 5 nm, just above the range's noise at the
#: default integrator tolerance (~2e-9 m, ``kkt.RANGE_STEP``).
LOCAL_FTOL = 1e-10
#: An outcome constraint (a relative margin: a load limit, the least range) counts as met down
#: to this: SLSQP meets such a limit to a few 1e-5 of itself (``kkt.OUTCOME_ACTIVE_TOLERANCE``).
OUTCOME_FEASIBILITY = 1e-4


@dataclass(frozen=True)
class Settings:
    """How to search (the problem is in ``Problem``).

    Attributes
    ----------
    seed : seeds the global stage; the local stage is deterministic.
    popsize : DE population per free variable.
    maxiter : most DE generations. The global stage only has to deliver a point
        in the optimum's basin: with the paper's problem, 20 generations of 48
        (about 400 shots) do for seeds 0-4, which SLSQP then all takes to the
        same optimum (tests/test_analytic_optimise_run.py checks three).
    convergence : DE stops when the spread of its population's ranges is this
        fraction of their mean.
    search_tolerance : integrator rtol = atol of the global stage.
    final_tolerance : integrator rtol = atol of the local stage, the gradient
        and the answer (the simulator's default).
    local_maxiter : most SLSQP iterations.
    """

    seed: int = 0
    popsize: int = 8
    maxiter: int = 20
    convergence: float = 0.01
    search_tolerance: float = 1e-7
    final_tolerance: float = DEFAULT_RTOL
    local_maxiter: int = 60


@dataclass(frozen=True)
class History:
    """Best feasible score after each generation / iteration.

    Attributes
    ----------
    stage : (k,) ``"global"`` or ``"local"``.
    shots : (k,) shots simulated so far.
    best : (k,) best score so far, m (nan before a feasible candidate was scored).
    """

    stage: np.ndarray
    shots: np.ndarray
    best: np.ndarray


@dataclass(frozen=True)
class Optimum:
    """The result of ``maximise``.

    Attributes
    ----------
    problem, scatter, settings : what was maximised, and how.
    values : (6,) the optimum's design variables, m and rad.
    score : its range (or expected range), m, at ``settings.final_tolerance``.
    global_values, global_score : (6,) and m, the global stage's best (nan score if skipped).
    history : ``History``.
    failures : failure kind -> shots that failed so (``evaluate``).
    shots : total shots, each quadrature node of a scatter counting as one.
    local_message : SLSQP's exit message.
    first_order : KKT check at ``values``.
    seconds : wall time.
    """

    problem: Problem
    scatter: Scatter
    settings: Settings
    values: np.ndarray
    score: float
    global_values: np.ndarray
    global_score: float
    history: History
    failures: dict[str, int]
    shots: int
    local_message: str
    first_order: FirstOrder
    seconds: float


def maximise(problem: Problem, evaluator: Evaluator, settings: Settings = Settings(), *,
             scatter: Scatter = NO_SCATTER, start: np.ndarray | None = None,
             progress: bool = False, include: np.ndarray | None = None) -> Optimum:
    """Maximise the range (or the expected range under ``scatter``) over the problem's free variables.

    Parameters
    ----------
    evaluator : scores designs of ``problem`` (``evaluate.Evaluator``, either path).
    start : (6,) skip the global stage and start the local one here. The robust
        variant starts from the nominal optimum: the expected range under a
        scatter of sigma differs from the range by ``sigma^2 / 2 * d2R/dtheta^2 +
        O(sigma^4)``, a smooth perturbation that moves the optimum within its basin.
    progress : show progress bars (tqdm, on stderr).
    include : (6,) a design the global stage's first population holds (cut into the bounds): the
        search then ends on a design at least as good, to the local stage's tolerance, when it is
        feasible (a design optimised around itself, ``analytic.optimise.around``).
    """
    from analytic.cli_shared import progress_bar

    began = time.perf_counter()
    shots0, failures0 = evaluator.shots, evaluator.failures.copy()
    records: list[tuple[str, int, float]] = []

    def record(stage: str, score: float) -> None:
        previous = records[-1][2] if records else -math.inf
        records.append((stage, evaluator.shots - shots0, max(score, previous)))

    if start is None:
        unit, global_score = _global_stage(problem, evaluator, settings, scatter, record,
                                           progress_bar(total=settings.maxiter, desc="global (DE)",
                                                unit="gen", disable=not progress, leave=False),
                                           None if include is None else np.clip(to_unit(problem, problem.complete(include)), 0.0, 1.0))
    else:
        unit, global_score = to_unit(problem, start), math.nan
    global_values = from_unit(problem, unit)
    unit, message, score, gradient, outcomes = _local_stage(
        problem, evaluator, settings, scatter, unit, record,
        progress_bar(total=settings.local_maxiter, desc="local (SLSQP)", unit="it", disable=not progress, leave=False))
    stage, shots, best = zip(*records, strict=True)
    failures = evaluator.failures - failures0
    return Optimum(problem=problem, scatter=scatter, settings=settings,
                   values=from_unit(problem, unit), score=score,
                   global_values=global_values, global_score=global_score,
                   history=History(np.array(stage), np.array(shots),
                                   np.array([b if math.isfinite(b) else math.nan for b in best])),
                   failures=dict(failures), shots=evaluator.shots - shots0, local_message=message,
                   first_order=first_order(problem, unit, score, gradient, *outcomes),
                   seconds=time.perf_counter() - began)


def _global_stage(problem, evaluator, settings, scatter, record, bar, x0=None):
    """Differential evolution over the unit box (``x0``, if given, in its first population); returns its
    best point and score."""
    n = len(problem.free)

    def objective(units: np.ndarray) -> np.ndarray:  # (n, S) -> (S,)
        values = np.array([from_unit(problem, u) for u in units.T]).reshape(-1, len(problem.variables))
        return -evaluator.scores(values, settings.search_tolerance, scatter)

    def constraints(units: np.ndarray) -> np.ndarray:  # (n, S) -> (5 + m, S); (n,) -> (5 + m,) at set-up
        if units.ndim == 1:
            return constraints(units[:, None])[:, 0]
        geometric = np.array([unit_constraints(problem, u) for u in units.T]).T
        if not problem.outcome_constraints:
            return geometric
        # What the shots do (their loads, their range): shot once, remembered for the scores.
        values = np.array([from_unit(problem, u) for u in units.T]).reshape(-1, len(problem.variables))
        return np.vstack([geometric, evaluator.outcomes(values, settings.search_tolerance)[1].T])

    def callback(intermediate_result) -> None:
        record("global", -intermediate_result.fun)
        bar.update()

    with bar:
        result = differential_evolution(
            objective, [(0.0, 1.0)] * n, popsize=settings.popsize, maxiter=settings.maxiter,
            tol=settings.convergence, rng=np.random.default_rng(settings.seed),
            constraints=NonlinearConstraint(constraints, 0.0, np.inf), vectorized=True, updating="deferred",
            polish=False, callback=callback, x0=x0)
    return result.x, -result.fun


def _local_stage(problem, evaluator, settings, scatter, unit, record, bar):
    """SLSQP from ``unit``; returns the point, SLSQP's message, the score and gradient there, and
    the outcome constraints and their Jacobian there (``(None, None)`` without them)."""
    tolerance = settings.final_tolerance
    cache: dict[bytes, tuple[float, np.ndarray | None]] = {}
    outcome_cache: dict[bytes, tuple] = {}
    with_outcomes = bool(problem.outcome_constraints)

    def score(u: np.ndarray) -> float:
        key = u.tobytes()
        if key not in cache:
            cache[key] = (float(evaluator.scores(from_unit(problem, u)[None], tolerance, scatter)[0]), None)
        return cache[key][0]

    def differentiated(u: np.ndarray) -> tuple:
        key = u.tobytes()
        if key not in outcome_cache:
            outcome_cache[key] = outcome_gradient(evaluator, problem, u, tolerance)
        return outcome_cache[key]

    def gradient(u: np.ndarray) -> np.ndarray:
        if with_outcomes:
            return differentiated(u)[1]
        key = u.tobytes()
        if key not in cache or cache[key][1] is None:
            cache[key] = range_gradient(evaluator, problem, u, tolerance, scatter)
        return cache[key][1]

    scale = max(abs(score(unit)), 1.0)   # SLSQP's tolerances are absolute: make the objective O(1)
    record("local", score(unit))

    visited = [unit]   # SLSQP's iterates: the best feasible one is kept if it ends on a worse point

    def callback(u: np.ndarray) -> None:
        record("local", score(u))
        visited.append(np.clip(u, 0.0, 1.0))
        bar.update()

    constraints = [{"type": "ineq", "fun": lambda u: unit_constraints(problem, u),
                    "jac": lambda u: constraint_jacobian(problem, u)}]
    if with_outcomes:
        constraints.append({"type": "ineq", "fun": lambda u: differentiated(u)[2],
                            "jac": lambda u: differentiated(u)[3]})

    def feasible(u: np.ndarray) -> bool:
        return (np.min(unit_constraints(problem, u)) >= -FEASIBILITY_TOLERANCE
                and (not with_outcomes or np.min(differentiated(u)[2]) >= -OUTCOME_FEASIBILITY))

    with bar:
        result = minimize(lambda u: -score(u) / scale, unit, jac=lambda u: -gradient(u) / scale,
                          method="SLSQP", bounds=[(0.0, 1.0)] * len(unit), constraints=constraints,
                          callback=callback,
                          options={"maxiter": settings.local_maxiter, "ftol": LOCAL_FTOL})
    best = np.clip(result.x, 0.0, 1.0)
    message = str(result.message)
    # SLSQP may end on a worse or infeasible point after a failed line search or at its
    # iteration limit; then the best feasible point it passed (its start included) is kept.
    # A converged end is kept unless it is infeasible or worse than the start; from an
    # infeasible start (the global stage found nothing feasible) any feasible point is better.
    candidates = [] if result.success else [u for u in [best, *visited] if feasible(u)]   # the end wins a tie
    if candidates:
        kept = max(candidates, key=score)
        if kept is not best:
            best = kept
            message += " (kept the starting point)" if kept is unit else " (kept the best feasible iterate)"
    elif not feasible(best) or (feasible(unit) and score(best) < score(unit)):
        best, message = unit, f"{message} (kept the starting point)"
    outcomes = differentiated(best)[2:] if with_outcomes else (None, None)
    return best, message, score(best), gradient(best), outcomes
