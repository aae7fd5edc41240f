"""First-order optimality of a constrained maximum: finite-difference gradients, active sets, multipliers.

For "maximise R(x) subject to g(x) >= 0 and lower <= x <= upper", a point is a
first-order (KKT) point when multipliers lambda, mu >= 0 on the active
constraints and bounds make the Lagrangian stationary,

    grad R + sum_j lambda_j grad g_j + sum_(i at lower) mu_i e_i - sum_(i at upper) mu_i e_i = 0.

The multipliers are found by non-negative least squares on the active set;
the size of what is left over is the stationarity residual. Each multiplier is
a shadow price: lambda_j is the range gained per metre the limit of constraint
j is relaxed, mu_i the range gained per unit the bound on variable i is moved.
Everything here works on the free variables scaled to [0, 1] (``problem.to_unit``)
and converts to SI only in ``FirstOrder``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import nnls

from analytic.optimise.constraints import CONSTRAINT_NAMES, constraint_values
from analytic.optimise.evaluate import Evaluator
from analytic.design_space import Problem, design_at, from_unit
from analytic.optimise.robust import Scatter

#: Finite-difference step of the range, in unit (bound-width) coordinates. The
#: range at rtol = atol = 1e-10 carries noise of about 2e-9 m (its scatter about a
#: quadratic fit over +-1e-6 of each variable of the paper's optimum), and the
#: third derivative is O(1e3) m: a central step of 1e-4 keeps both the noise
#: (2e-9 / 1e-4 = 2e-5 m) and the truncation (1e-8 * 1e3 / 6) far below the
#: O(10) m gradients.
RANGE_STEP = 1e-4
#: Step for the constraints: closed-form geometry, smooth and noise-free.
CONSTRAINT_STEP = 1e-7
#: A constraint (m) or a unit coordinate this close to its limit counts as active.
ACTIVE_TOLERANCE = 1e-7
#: An outcome constraint (a relative margin of a load or the range) this close to 0 counts as
#: active: SLSQP stops with such a limit met to a few 1e-5 of itself (measured: 2.0e-5 with the
#: paper's problem under 80 % of its optimum's projectile acceleration), the constraint's
#: Jacobian being differenced with steps of ``RANGE_STEP`` of each bound's width.
OUTCOME_ACTIVE_TOLERANCE = 1e-4


def range_gradient(evaluator: Evaluator, problem: Problem, unit: np.ndarray, tolerance: float,
                   scatter: Scatter, step: float = RANGE_STEP) -> tuple[float, np.ndarray]:
    """Score and its gradient in unit coordinates, from one parallel batch of 2 n + 1 shots.

    Central differences inside the box; at (or within a step of) a bound a
    second-order one-sided difference into the box, so no shot leaves it.

    Returns
    -------
    score : m.
    gradient : (n_free,) m per unit coordinate.
    """
    points, offsets = difference_points(unit, step)
    scores = evaluator.scores(np.array([from_unit(problem, p) for p in points]), tolerance, scatter)
    return float(scores[0]), differences(scores, offsets, step)


def outcome_gradient(evaluator: Evaluator, problem: Problem, unit: np.ndarray, tolerance: float,
                     step: float = RANGE_STEP) -> tuple[float, np.ndarray, np.ndarray, np.ndarray]:
    """Score, gradient, and the outcome constraints (``Evaluator.outcomes``) with their Jacobian,
    from the same batch of 2 n + 1 shots as ``range_gradient``.

    Returns
    -------
    score : m (or minus a load).
    gradient : (n_free,).
    margins : (m,) the outcome constraints (relative margins, >= 0 feasible).
    jacobian : (m, n_free) their derivatives per unit coordinate.
    """
    points, offsets = difference_points(unit, step)
    scores, margins = evaluator.outcomes(np.array([from_unit(problem, p) for p in points]), tolerance)
    return float(scores[0]), differences(scores, offsets, step), margins[0], differences(margins, offsets, step).T


def difference_points(unit: np.ndarray, step: float) -> tuple[np.ndarray, np.ndarray]:
    """The point and its 2 n finite-difference neighbours, (2 n + 1, n), and the offsets, (2 n, n).

    Central inside the box; within a step of a bound, two steps into the box (one-sided).
    """
    unit = np.asarray(unit, dtype=float)
    n = len(unit)
    offsets = np.empty((2 * n, n))
    for i in range(n):
        if unit[i] - step < 0.0:
            first, second = step, 2.0 * step
        elif unit[i] + step > 1.0:
            first, second = -step, -2.0 * step
        else:
            first, second = -step, step
        offsets[2 * i] = offsets[2 * i + 1] = 0.0
        offsets[2 * i, i], offsets[2 * i + 1, i] = first, second
    return np.vstack([unit, unit + offsets]), offsets


def differences(values: np.ndarray, offsets: np.ndarray, step: float) -> np.ndarray:
    """Derivatives per coordinate, (n, ...), from ``values`` (2 n + 1, ...) at ``difference_points``."""
    n = len(offsets) // 2
    f0, pairs = values[0], values[1:].reshape(n, 2, *values.shape[1:])
    gradient = np.empty((n, *values.shape[1:]))
    for i in range(n):
        a, b = offsets[2 * i, i], offsets[2 * i + 1, i]
        if a == -b:   # central
            gradient[i] = (pairs[i, 1] - pairs[i, 0]) / (2.0 * step)
        else:         # one-sided: (-3 f0 + 4 f(a) - f(2a)) / (2a)
            gradient[i] = (-3.0 * f0 + 4.0 * pairs[i, 0] - pairs[i, 1]) / (2.0 * a)
    return gradient


def unit_constraints(problem: Problem, unit: np.ndarray) -> np.ndarray:
    """The constraint vector (``constraints.constraint_values``) at unit coordinates, shape (5,), m."""
    return constraint_values(problem, design_at(problem, from_unit(problem, unit)).machine)


def constraint_jacobian(problem: Problem, unit: np.ndarray, step: float = CONSTRAINT_STEP) -> np.ndarray:
    """d g / d unit by central differences, shape (5, n_free), m per unit coordinate."""
    unit = np.asarray(unit, dtype=float)
    columns = []
    for i in range(len(unit)):
        delta = np.zeros_like(unit)
        delta[i] = step
        columns.append((unit_constraints(problem, unit + delta)
                        - unit_constraints(problem, unit - delta)) / (2.0 * step))
    return np.array(columns).T


@dataclass(frozen=True)
class FirstOrder:
    """First-order optimality at a point (SI: per m of length, per rad of angle).

    Attributes
    ----------
    gradient : (6,) d score / d variable, m per m or m per rad (0 for fixed variables).
    active_bounds : variable name -> ``"lower"`` or ``"upper"``.
    bound_multipliers : variable name -> mu >= 0, m per m or m per rad.
    active_constraints : names (``CONSTRAINT_NAMES``) of the constraints at their limit.
    constraint_multipliers : constraint name -> lambda >= 0, m of range per m of limit.
    residual : largest component of the Lagrangian's gradient in unit coordinates,
        relative to the score: the fraction of the range a move across a whole
        bound width would still gain to first order (0 at an exact KKT point;
        finite differences of the noisy range leave ~1e-6).
    degenerate : the active gradients are linearly dependent, so the multipliers
        are not unique (only their effect is).
    """

    gradient: np.ndarray
    active_bounds: dict[str, str]
    bound_multipliers: dict[str, float]
    active_constraints: tuple[str, ...]
    constraint_multipliers: dict[str, float]
    residual: float
    degenerate: bool


def first_order(problem: Problem, unit: np.ndarray, score: float, gradient: np.ndarray,
                outcome_margins: np.ndarray | None = None, outcome_jacobian: np.ndarray | None = None) -> FirstOrder:
    """KKT multipliers and stationarity residual at ``unit`` given the score and its gradient there.

    Parameters
    ----------
    unit : (n_free,) the point, unit coordinates.
    score : m, sets the scale of the residual.
    gradient : (n_free,) d score / d unit, m (``range_gradient``).
    outcome_margins, outcome_jacobian : (m,) and (m, n_free), the outcome constraints and
        their Jacobian (``outcome_gradient``), for a problem that has them; their
        multipliers are per unit of relative margin.
    """
    unit = np.asarray(unit, dtype=float)
    free = problem.free
    names = [problem.variables[i].name for i in free]
    width = problem.upper[free] - problem.lower[free]
    g = unit_constraints(problem, unit)
    jacobian = constraint_jacobian(problem, unit)
    constraint_names = CONSTRAINT_NAMES
    if outcome_margins is not None and len(outcome_margins):
        g = np.concatenate([g, outcome_margins])
        jacobian = np.vstack([jacobian, outcome_jacobian])
        constraint_names = CONSTRAINT_NAMES + problem.outcome_constraints
    active = [j for j in range(len(g))
              if g[j] <= (ACTIVE_TOLERANCE if j < len(CONSTRAINT_NAMES) else OUTCOME_ACTIVE_TOLERANCE)]
    columns, labels = [], []
    for j in active:
        columns.append(jacobian[j])
        labels.append(("constraint", j))
    for i, u in enumerate(unit):
        if u <= ACTIVE_TOLERANCE or u >= 1.0 - ACTIVE_TOLERANCE:
            side = "lower" if u <= ACTIVE_TOLERANCE else "upper"
            column = np.zeros(len(unit))
            column[i] = 1.0 if side == "lower" else -1.0
            columns.append(column)
            labels.append((side, i))
    scale = max(abs(score), np.finfo(float).tiny)
    if columns:
        matrix = np.array(columns).T
        multipliers, _ = nnls(matrix, -gradient)
        stationarity = gradient + matrix @ multipliers
        degenerate = np.linalg.matrix_rank(matrix) < matrix.shape[1]
    else:
        multipliers, stationarity, degenerate = np.zeros(0), gradient, False
    full_gradient = np.zeros(len(problem.variables))
    full_gradient[free] = gradient / width
    return FirstOrder(
        gradient=full_gradient,
        active_bounds={names[i]: kind for kind, i in labels if kind != "constraint"},
        bound_multipliers={names[i]: float(m / width[i])
                           for (kind, i), m in zip(labels, multipliers, strict=True) if kind != "constraint"},
        active_constraints=tuple(constraint_names[j] for j in active),
        constraint_multipliers={constraint_names[i]: float(m)
                                for (kind, i), m in zip(labels, multipliers, strict=True) if kind == "constraint"},
        residual=float(np.max(np.abs(stationarity)) / scale),
        degenerate=bool(degenerate),
    )
