"""First-order optimality: finite-difference gradients against closed forms, multipliers and residuals."""

from __future__ import annotations

import numpy as np
import pytest

from analytic.optimise.evaluate import NO_SCATTER
from analytic.optimise.kkt import (constraint_jacobian, first_order, range_gradient,
                                   unit_constraints)
from analytic.design_space import default_problem, from_unit, to_unit, variables_of


class QuadraticScore:
    """Stands in for ``Evaluator``: score = sum_i c_i x_i^2 + x_i^3 in SI, with a closed-form gradient."""

    def __init__(self, coefficients):
        self.c = np.asarray(coefficients, dtype=float)

    def scores(self, values, tolerance, scatter):
        values = np.atleast_2d(values)
        return (self.c * values**2 + values**3).sum(axis=1)

    def gradient(self, values):
        return 2.0 * self.c * values + 3.0 * values**2


@pytest.mark.parametrize("unit", [np.full(6, 0.5), np.array([0.0, 1.0, 0.3, 1.0, 0.0, 0.7])],
                         ids=["interior", "at-bounds"])
def test_range_gradient_matches_the_closed_form(unit):
    # Central differences inside, second-order one-sided at the bounds: both err by O(h^2) (the
    # cubic's third derivative 6 times h^2 = (1e-4 width)^2, times width: < 1e-6).
    problem = default_problem()
    stand_in = QuadraticScore([1.0, -2.0, 3.0, 0.5, -1.0, 2.0])
    score, gradient = range_gradient(stand_in, problem, unit, 0.0, NO_SCATTER)
    values = from_unit(problem, unit)
    width = problem.upper - problem.lower
    assert score == pytest.approx(stand_in.scores(values, 0.0, NO_SCATTER)[0])
    assert gradient == pytest.approx(stand_in.gradient(values) * width, rel=1e-6, abs=1e-6)


def test_constraint_jacobian_of_the_footprint():
    # footprint (tip to projectile) = limit - sling length: d/d(sling) = -1 m/m, nothing else.
    problem = default_problem()
    jacobian = constraint_jacobian(problem, np.full(6, 0.5))
    width = problem.upper - problem.lower
    expected = np.zeros(6)
    expected[3] = -width[3]
    assert jacobian[0] == pytest.approx(expected, abs=1e-8)


def test_kkt_at_table3_with_an_outward_gradient(table3):
    # Table III sits on the clearance's lower bound, the sling's upper bound and the footprint
    # limit (which is the sling length, so those two coincide). A gradient pushing out of all of
    # them is first-order optimal; the clearance's multiplier is its slope.
    problem = default_problem()
    unit = to_unit(problem, variables_of(table3.machine))
    width = problem.upper - problem.lower
    gradient = np.array([0.0, 0.0, -3.0, 5.0, 0.0, 0.0])
    result = first_order(problem, unit, 40.0, gradient)
    assert result.active_bounds == {"clearance": "lower", "sling_length": "upper"}
    assert result.active_constraints == ("footprint (tip to projectile)",)
    assert result.degenerate
    assert result.residual == pytest.approx(0.0, abs=1e-12)
    assert result.bound_multipliers["clearance"] == pytest.approx(3.0 / width[2])
    # However the sling's push is split between the bound and the footprint, it adds up.
    sling_share = result.bound_multipliers["sling_length"] * width[3]
    footprint_share = result.constraint_multipliers["footprint (tip to projectile)"] * width[3]
    assert sling_share + footprint_share == pytest.approx(5.0)


def test_kkt_residual_sees_a_free_direction_uphill(table3):
    # Arm_short is free at Table III: any slope along it is not first-order optimal.
    problem = default_problem()
    unit = to_unit(problem, variables_of(table3.machine))
    result = first_order(problem, unit, 40.0, np.array([2.0, 0.0, -4.0, 0.0, 0.0, 0.0]))
    assert result.residual == pytest.approx(2.0 / 40.0)   # the free slope relative to the score


def test_kkt_of_an_interior_point_has_nothing_active():
    # Short arm 15.5 cm, link and clearance 21.8 cm, sling 7 cm, starting angle 60 deg: every
    # constraint holds with room to spare.
    problem = default_problem()
    unit = np.array([0.5, 0.2, 0.2, 0.1, 50.0 / 70.0, 0.5])
    assert np.min(unit_constraints(problem, unit)) > 0.01
    result = first_order(problem, unit, 40.0, np.zeros(6) + 1e-3)
    assert result.active_bounds == {} and result.active_constraints == ()
    assert result.residual == pytest.approx(1e-3 / 40.0)
