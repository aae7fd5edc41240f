"""Release-angle scatter: Gauss-Hermite moments of a normal law, and enough nodes for the paper's optimum."""

from __future__ import annotations

import math

import numpy as np
import pytest

from analytic.optimise.evaluate import Evaluator
from analytic.design_space import default_problem, variables_of
from analytic.optimise.robust import DEFAULT_NODES, expected, release_scatter, spread
from analytic.reference import DEFAULT_RTOL

SIGMA = math.radians(2.0)


@pytest.mark.parametrize("nodes", [3, DEFAULT_NODES, 15])
def test_normal_moments_are_exact(nodes):
    # Moments of N(0, s^2): E e = 0, E e^2 = s^2, E e^4 = 3 s^4; n-node Gauss-Hermite is exact to degree 2n - 1.
    scatter = release_scatter(SIGMA, nodes)
    e = scatter.offsets
    assert scatter.weights.sum() == pytest.approx(1.0, abs=1e-14)
    assert expected(scatter, e) == pytest.approx(0.0, abs=1e-16)
    assert expected(scatter, e**2) == pytest.approx(SIGMA**2, rel=1e-12)
    assert expected(scatter, e**4) == pytest.approx(3.0 * SIGMA**4, rel=1e-12)
    assert spread(scatter, e) == pytest.approx(SIGMA, rel=1e-12)


def test_smooth_expectation_matches_closed_form():
    # E cos(e) = exp(-s^2 / 2) for e ~ N(0, s^2) (characteristic function of the normal law).
    scatter = release_scatter(SIGMA)
    assert expected(scatter, np.cos(scatter.offsets)) == pytest.approx(math.exp(-SIGMA**2 / 2), abs=1e-14)


def test_no_scatter_is_one_node_at_the_set_angle():
    scatter = release_scatter(0.0)
    assert scatter.offsets.tolist() == [0.0] and scatter.weights.tolist() == [1.0]


def test_expected_works_along_the_last_axis():
    scatter = release_scatter(SIGMA, 5)
    ranges = np.arange(10.0).reshape(2, 5)
    assert expected(scatter, ranges).shape == (2,) and spread(scatter, ranges).shape == (2,)


@pytest.mark.parametrize("sigma, nodes", [(-1.0, 7), (math.nan, 7), (SIGMA, 0)],
                         ids=["negative", "nan", "no-nodes"])
def test_invalid_scatter_is_refused(sigma, nodes):
    with pytest.raises(ValueError):
        release_scatter(sigma, nodes)


def test_default_node_count_is_converged_for_the_papers_optimum(table3):
    # The claim behind DEFAULT_NODES: with sigma = 2 deg, 7 and 15 nodes agree to < 1e-4 relative.
    problem = default_problem()
    values = variables_of(table3.machine)
    evaluator = Evaluator(problem, workers=1)
    few = evaluator.scores(values, DEFAULT_RTOL, release_scatter(SIGMA, DEFAULT_NODES))[0]
    many = evaluator.scores(values, DEFAULT_RTOL, release_scatter(SIGMA, 15))[0]
    assert few == pytest.approx(many, rel=1e-4), f"{DEFAULT_NODES} nodes {few} m, 15 nodes {many} m"
