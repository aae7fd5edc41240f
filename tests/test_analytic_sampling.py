"""``simulate``'s history spacings and its per-sample loads: options that change what is sampled, not the shot."""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

from analytic.design import Base
from analytic.design_file import default_design
from analytic.reference import FLIGHT_OUTPUT_STEP, SWING_OUTPUT_STEP, simulate
from workbench.presets import PRESETS

#: The summary's fields read off the samples of stages 1-2 (``simulate``'s docstring): a
#: coarser spacing may miss the sampled extreme, so only these may differ between spacings.
SAMPLED = {"min_ground_force", "max_frame_speed", "min_sling_tension", "warnings"}
#: Two grids' times are sums of different float steps (``t0 + step + step ...``), a few ulp
#: apart: a sample both share is the same continuous solution read a few ulp of time apart.
SHARED_TIME = 1e-12
SAME_READING = 1e-9


def designs():
    """The paper's machine; the backyard preset (axle friction); a rolling frame (the machine after release)."""
    paper = default_design()
    return {"paper": paper, "backyard": PRESETS["backyard"][1](),
            "rolling": dataclasses.replace(paper, base=Base("rolling", 8.0))}


@pytest.fixture(scope="module", params=list(designs()), ids=list(designs()))
def pair(request):
    design = designs()[request.param]
    return simulate(design), simulate(design, sample_step=4 * SWING_OUTPUT_STEP, flight_sample_step=0.02)


def shared(fine_t: np.ndarray, coarse_t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Indices into each of two sample grids of the times they share."""
    j = np.searchsorted(fine_t, coarse_t).clip(1, len(fine_t) - 1)
    nearest = np.where(np.abs(fine_t[j - 1] - coarse_t) < np.abs(fine_t[j] - coarse_t), j - 1, j)
    both = np.abs(fine_t[nearest] - coarse_t) < SHARED_TIME
    return nearest[both], np.flatnonzero(both)


def test_a_coarser_spacing_samples_the_same_motion_less_often(pair):
    fine, coarse = pair
    assert len(coarse.history.t) < len(fine.history.t) / 3
    assert len(coarse.history.flight_t) < len(fine.history.flight_t) / 3
    swing = np.diff(coarse.history.t)[1:-1]   # the first and last spacings end at lift-off and release
    assert np.median(swing) == pytest.approx(4 * SWING_OUTPUT_STEP, rel=1e-6)
    assert np.median(np.diff(coarse.history.flight_t)[:-1]) == pytest.approx(0.02, rel=1e-6)
    for fine_t, coarse_t, fine_x, coarse_x in [
            (fine.history.t, coarse.history.t, np.hstack([fine.history.q, fine.history.qdot]),
             np.hstack([coarse.history.q, coarse.history.qdot])),
            (fine.history.flight_t, coarse.history.flight_t, fine.history.flight_path, coarse.history.flight_path)]:
        i, j = shared(fine_t, coarse_t)
        assert len(j) > len(coarse_t) / 2   # most of the coarse grid lies on the fine one
        np.testing.assert_allclose(coarse_x[j], fine_x[i], rtol=SAME_READING, atol=SAME_READING)
    # the release and the landing are each grid's last sample, the same instants
    assert coarse.history.t[-1] == fine.history.t[-1]
    assert coarse.history.flight_t[-1] == fine.history.flight_t[-1]


def test_a_coarser_spacing_gives_the_same_summary_but_its_sampled_extremes(pair):
    fine, coarse = pair
    a, b = json.loads(json.dumps(fine.to_json())), json.loads(json.dumps(coarse.to_json()))
    assert {key: a[key] for key in a if key not in SAMPLED} == {key: b[key] for key in b if key not in SAMPLED}
    # The coarse grid is every fourth sample of the fine one: its extremes are no more extreme.
    for key, sign in (("min_ground_force", 1), ("min_sling_tension", 1), ("max_frame_speed", -1)):
        low, high = getattr(fine, key), getattr(coarse, key)
        if low is not None:
            assert sign * (high - low) >= -SAME_READING * max(1.0, abs(low)), (key, low, high)


def test_without_sampled_loads_only_the_load_histories_are_missing():
    design = PRESETS["backyard"][1]()
    full, light = simulate(design), simulate(design, sampled_loads=False)
    assert full.history.axle_load is not None
    assert light.history.axle_load is light.history.hinge_load is light.history.projectile_acceleration is None
    assert light.to_json() == full.to_json()
    for name in ("t", "q", "qdot", "path", "sling_tension", "frame_x", "flight_t", "flight_path"):
        np.testing.assert_array_equal(getattr(light.history, name), getattr(full.history, name), err_msg=name)


@pytest.mark.parametrize("name", ["sample_step", "flight_sample_step"])
@pytest.mark.parametrize("value", [0.0, -1e-3, math.nan, math.inf, True, "2 ms"],
                         ids=["zero", "negative", "nan", "inf", "bool", "text"])
def test_a_bad_spacing_is_refused_naming_it(name, value):
    with pytest.raises(ValueError, match=rf"^{name} = .*must be a positive number of seconds"):
        simulate(default_design(), **{name: value})


def test_the_default_spacings_are_the_documented_constants():
    history = simulate(default_design()).history
    assert np.median(np.diff(history.t)) == pytest.approx(SWING_OUTPUT_STEP, rel=1e-6)
    assert np.median(np.diff(history.flight_t)) == pytest.approx(FLIGHT_OUTPUT_STEP, rel=1e-6)
