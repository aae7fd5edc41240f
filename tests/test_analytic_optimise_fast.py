"""The optimiser on the fast path: the same scores and failure kinds as the reference path, and the same optimum."""

from __future__ import annotations

import math

import numpy as np
import pytest

from analytic import fast
from analytic.optimise import optimise
from analytic.optimise.evaluate import DESIGN_ERROR, Evaluator, FAILURE_RANGE, FAST, REFERENCE
from analytic.design_space import default_problem, from_unit, variables_of
from analytic.optimise.report import display
from analytic.optimise.robust import release_scatter
from analytic.optimise.search import Settings, maximise
from analytic.result import Shots, Status
from support import SEED_DESIGN_AGREEMENT, SEED_RANGE_AGREEMENT

#: The two paths share equations, integrator and events, so their ranges differ by
#: round-off only (measured: < 3e-13 relative on the candidates below, at both tolerances).
#: Not so for a machine that swings for seconds before it releases: the swing is chaotic
#: and amplifies that round-off, so at the search tolerance the paths can then differ
#: in range by percent and even in outcome (e.g. unit point [0.74, 0.94, 0.31, 0.22,
#: 0.12, 0.265], released after 10.9 s). The candidates below that throw release within 0.8 s.
SCORE_AGREEMENT = 1e-9

#: Candidates in unit coordinates of the paper's box, one per outcome, found by shooting
#: random points on a 0.01 grid on the fast path and checked on both.
CANDIDATES = {
    "throws": [0.26, 0.3, 0.81, 0.09, 0.6, 0.05],
    "throws-at-the-upper-release-bound": [0.19, 0.06, 0.27, 0.66, 0.56, 1.0],
    "never-fires": [0.32, 0.92, 0.47, 0.69, 0.11, 1.0],
    "hits-base-before-release": [0.04, 0.62, 0.49, 0.24, 0.53, 0.98],
    "never-lifts-off": [0.04, 0.24, 0.64, 0.72, 0.43, 1.0],
    "never-releases": [1.0, 0.04, 0.9, 0.35, 0.75, 0.125],
    # Set to -44 deg, 1 deg above the release angle (-45.x deg) below which it never releases.
    "throws-near-its-release-edge": [1.0, 0.04, 0.9, 0.35, 0.75, 0.225],
}
#: Outside the box: a negative sling cannot be built (m and rad).
UNBUILDABLE = [0.2, 0.2, 0.16, -0.1, 1.0, 0.5]

#: The default run's optimum found on the reference path alone (``python -m analytic optimise
#: --path reference``, seed 0), its optimum.toml re-simulated at the default tolerance.
#: Variables in m and rad, as ``VARIABLE_NAMES``; the report shows 50.07 m, L_As 19.29, L_W 24.32,
#: clearance 16.00, L_S 61.00 cm, start 62.3 deg, release 35.3 deg.
REFERENCE_OPTIMUM = np.array([0.19286404835432258, 0.24323533750197135, 0.16, 0.61,
                              1.087445377987638, 0.6161159931771489])
REFERENCE_OPTIMUM_RANGE = 50.06933032723386


@pytest.fixture(scope="module")
def problem():
    return default_problem()


@pytest.fixture(scope="module")
def values(problem, table3) -> np.ndarray:
    """Table III, the candidates and the unbuildable vector, shape (9, 6), m and rad."""
    rows = [variables_of(table3.machine)] + [from_unit(problem, np.array(u)) for u in CANDIDATES.values()]
    return np.array(rows + [UNBUILDABLE])


@pytest.mark.parametrize("tolerance", [Settings().search_tolerance, Settings().final_tolerance],
                         ids=["search-tolerance", "final-tolerance"])
def test_paths_give_the_same_scores_and_failure_kinds(problem, values, tolerance):
    fast_path, reference = Evaluator(problem, path=FAST), Evaluator(problem, path=REFERENCE, workers=1)
    fast_throws, reference_throws = fast_path.throws(values, tolerance), reference.throws(values, tolerance)
    for row, (a, b) in enumerate(zip(fast_throws, reference_throws, strict=True)):
        assert a.failure == b.failure, f"candidate {row}: fast {a.failure}, reference {b.failure}"
        if b.failure is None:
            assert a.range == pytest.approx(b.range, rel=SCORE_AGREEMENT), \
                f"candidate {row}: fast {a.range} m, reference {b.range} m"
    assert fast_path.failures == reference.failures
    assert fast_path.shots == reference.shots == len(values)
    assert set(fast_path.failures) == {"never_fires", "hits_base_before_release", "never_lifts_off",
                                       "never_releases", DESIGN_ERROR}   # every outcome is covered
    # What the optimiser sees: the range, or FAILURE_RANGE.
    expected = [FAILURE_RANGE if b.range is None else b.range for b in reference_throws]
    assert fast_path.scores(values, tolerance) == pytest.approx(expected, rel=SCORE_AGREEMENT)


def test_paths_give_the_same_ranges_at_scatter_nodes(problem, table3):
    # The nodes move the release angle by up to 3.5 deg, so the edge candidate's lowest node
    # (-47.5 deg) never releases while the others throw: failures and throws in one design.
    values = np.array([variables_of(table3.machine),
                       from_unit(problem, np.array(CANDIDATES["throws-near-its-release-edge"]))])
    scatter = release_scatter(math.radians(2.0), 3)
    tolerance = Settings().search_tolerance
    fast_nodes = Evaluator(problem).node_ranges(values, tolerance, scatter, failure_range=math.nan)
    reference_nodes = Evaluator(problem, path=REFERENCE, workers=1).node_ranges(
        values, tolerance, scatter, failure_range=math.nan)
    assert np.isnan(fast_nodes).tolist() == [[False, False, False], [True, False, False]]
    assert np.isnan(reference_nodes).tolist() == np.isnan(fast_nodes).tolist()
    assert fast_nodes == pytest.approx(reference_nodes, rel=SCORE_AGREEMENT, nan_ok=True)


@pytest.mark.parametrize("status", [Status.STEP_FAILED, Status.NO_LANDING], ids=lambda s: s.value)
def test_a_failure_the_candidates_never_reach_is_counted_under_its_status(problem, values, monkeypatch, status):
    # None of the candidates above fails a step or never lands: the batch is
    # stood in for, to show that every status is counted under its own name.
    def shoot(rows, *, rtol, atol, threads, loads=True):
        return Shots(status=Shots.statuses(np.full(len(rows), status.code)), **{
            name: np.full(len(rows), math.nan) for name in Shots.__dataclass_fields__
            if name not in ("status", "designs", "shot_at")})

    monkeypatch.setattr(fast, "shoot", shoot)
    evaluator = Evaluator(problem)
    (result,) = evaluator.throws(values[0], 1e-7)
    assert result.range is None and result.failure == status.value
    assert evaluator.failures == {status.value: 1}


def test_default_search_on_the_fast_path_reaches_the_reference_optimum(problem):
    optimum = maximise(problem, Evaluator(problem), Settings())
    assert optimum.score == pytest.approx(REFERENCE_OPTIMUM_RANGE, rel=SEED_RANGE_AGREEMENT)
    for variable, x, y in zip(problem.variables, optimum.values, REFERENCE_OPTIMUM, strict=True):
        gap = abs(display(variable.name, x) - display(variable.name, y))
        assert gap <= SEED_DESIGN_AGREEMENT, f"{variable.name} differs by {gap} from the reference path's"
    assert optimum.failures == {} and optimum.local_message == "Optimization terminated successfully"


def test_evaluator_refuses_an_unknown_path_or_no_workers(problem):
    with pytest.raises(ValueError, match="path = 'numba'"):
        Evaluator(problem, path="numba")
    with pytest.raises(ValueError, match="workers = 0"):
        Evaluator(problem, workers=0)


@pytest.mark.parametrize("sigma", [0.0, -0.01, math.nan], ids=["zero", "negative", "nan"])
def test_the_entry_point_refuses_a_scatter_that_is_not_a_positive_angle(problem, sigma):
    with pytest.raises(ValueError, match="robust_sigma = "):
        optimise(problem, robust_sigma=sigma)

