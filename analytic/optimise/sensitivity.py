"""Range along each design variable through an optimum, the others held, with feasibility marked."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from analytic.optimise.constraints import FEASIBILITY_TOLERANCE, constraint_values
from analytic.optimise.evaluate import NO_SCATTER, Evaluator
from analytic.design_space import Problem, design_at
from analytic.optimise.robust import Scatter, expected

#: Grid points per variable across its bounds (plus the optimum itself). Dense enough to draw
#: the range's real oscillation for slings under about 10 cm (peaks 2-5 cm apart on Table III's
#: design and on the paper's optimum: a short sling wobbles about the arm's tip, and the release rule's first crossing of
#: the release angle falls on one wobble or the next, at release speeds from 7.5 to 12 m/s on Table III's design;
#: the engine model throws the same ranges, and the integrator's tolerance does not move them,
#: see docs/guide/optimiser.md). 25 points, 2.5 cm apart, drew it as spikes. 6 x 101 shots
#: take well under a second on the fast path.
DEFAULT_POINTS = 101


@dataclass(frozen=True)
class Sensitivity:
    """One-at-a-time scans through ``optimum`` across each free variable's bounds.

    Attributes
    ----------
    optimum : (6,) the point scanned through, m and rad.
    score : the optimum's score, m.
    variables : (k,) indices of the scanned (free) variables.
    grid : (k, m) values of the scanned variable, m or rad, sorted.
    scores : (k, m) range or expected range there, m (nan where a shot failed).
    margins : (k, m, 5) the constraint vector there (``constraints``), m.
    scatter : the release-angle scatter the scores are under.
    """

    optimum: np.ndarray
    score: float
    variables: np.ndarray
    grid: np.ndarray
    scores: np.ndarray
    margins: np.ndarray
    scatter: Scatter

    @property
    def feasible(self) -> np.ndarray:
        """(k, m) every constraint holds (to ``FEASIBILITY_TOLERANCE``)."""
        return np.all(self.margins >= -FEASIBILITY_TOLERANCE, axis=-1)


def scan(evaluator: Evaluator, problem: Problem, optimum: np.ndarray, score: float, tolerance: float,
         scatter: Scatter = NO_SCATTER, points: int = DEFAULT_POINTS) -> Sensitivity:
    """Scan each free variable across its bounds through ``optimum`` (one parallel batch).

    Parameters
    ----------
    optimum : (6,) m and rad.
    score : the optimum's score (m), drawn as its point.
    tolerance : integrator rtol = atol of the scan's shots.
    """
    free = problem.free
    grids = np.array([np.sort(np.append(np.linspace(problem.lower[i], problem.upper[i], points),
                                        optimum[i])) for i in free])
    values = np.repeat(np.asarray(optimum, dtype=float)[None, None, :], grids.shape[1], axis=1)
    values = np.repeat(values, len(free), axis=0)
    for row, i in enumerate(free):
        values[row, :, i] = grids[row]
    flat = values.reshape(-1, values.shape[-1])
    ranges = evaluator.node_ranges(flat, tolerance, scatter, failure_range=math.nan)
    margins = np.array([constraint_values(problem, design_at(problem, v).machine) for v in flat])
    shape = grids.shape
    return Sensitivity(optimum=np.asarray(optimum, dtype=float), score=float(score), variables=free,
                       grid=grids, scores=expected(scatter, ranges).reshape(shape),
                       margins=margins.reshape(shape + (-1,)), scatter=scatter)
