"""The ideal release rule: the longest range of the swing, on both analytic paths, and in design files."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from analytic import fast
from analytic.design import DesignError
from analytic.design_file import default_design, design_from_dict, design_to_dict
from analytic.reference import simulate
from crosscheck.cases import ideal

#: Pinned release angles of the grid the ideal release must beat, deg: the velocity rule's whole
#: useful span at 1 deg.
GRID = np.arange(10.0, 71.0, 1.0)
#: How far the best of the grid may fall short of the ideal: half a grid step off the best launch
#: angle costs about 1 - cos(2 x 0.5 deg) = 1.5e-4 of a vacuum range; the swing's speed changes
#: little over that half step.
GRID_MARGIN = 1e-3
#: Round-off of one range between two shots of the same path, relative (a pinned release and the
#: ideal one at the same instant land within it).
ROUND_OFF = 1e-9
#: The paths' agreement on the range, relative (``analytic.fast``'s docstring: 7e-9 at worst).
PATHS_RANGE = 1e-7
#: The paths' agreement on the launch angle, rad: the range is flat at its maximum
#: (R(a + d) = R - c d^2 with c about R, per rad^2), so a difference of 7e-9 R in the range the
#: search compares moves the maximum's angle by up to sqrt(7e-9) = 8e-5 rad; three times that.
PATHS_ANGLE = 2.5e-4


def _vacuum():
    return dataclasses.replace(default_design(), projectile=dataclasses.replace(default_design().projectile,
                                                                              drag="none"))


def _pinned(design, angle_deg):
    return dataclasses.replace(design, machine=dataclasses.replace(design.machine, release_rule="velocity",
                                                                   release_angle=math.radians(angle_deg)))


def test_the_ideal_release_beats_every_pinned_angle_in_vacuum():
    design = _vacuum()
    best = fast.simulate_fast(ideal(design, "ideal-vacuum"))
    grid = fast.shoot([_pinned(design, a) for a in GRID]).range
    assert np.all(np.isfinite(grid))
    assert best.range >= grid.max() * (1.0 - ROUND_OFF), (best.range, GRID[np.argmax(grid)], grid.max())
    assert grid.max() >= best.range * (1.0 - GRID_MARGIN), (best.range, grid.max())


@pytest.mark.parametrize("drag", ["none", "golf-ball"])
def test_the_launch_angle_is_the_pin_that_throws_as_far(drag):
    """A builder pins the velocity rule at the ideal shot's ``launch_angle``: the same throw."""
    design = dataclasses.replace(default_design(), projectile=dataclasses.replace(default_design().projectile,
                                                                                drag=drag))
    best = fast.simulate_fast(ideal(design, "ideal"))
    pinned = fast.simulate_fast(_pinned(design, math.degrees(best.launch_angle)))
    assert pinned.range == pytest.approx(best.range, rel=1e-7)
    assert pinned.release_time == pytest.approx(best.release_time, abs=1e-6)


@pytest.mark.parametrize("kind", ["hinged", "fixed", "floating-arm"])
def test_both_paths_find_the_same_release(kind):
    from crosscheck.cases import fixed_design, floating_design
    design = {"hinged": default_design(), "fixed": fixed_design(default_design(), "fixed"),
              "floating-arm": floating_design(default_design(), "floating")}[kind]
    design = ideal(design, f"ideal-{kind}")
    compiled, reference = fast.simulate_fast(design), simulate(design, histories=False)
    assert compiled.ok and reference.ok
    assert compiled.range == pytest.approx(reference.range, rel=PATHS_RANGE)
    assert compiled.launch_angle == pytest.approx(reference.launch_angle, abs=PATHS_ANGLE)


def test_a_batch_releases_each_ideal_design_as_one_shot_does():
    designs = [ideal(default_design(), "ideal"), default_design()]
    shots = fast.shoot(designs)
    assert shots.range[0] == fast.simulate_fast(designs[0]).range
    assert shots.range[1] == fast.simulate_fast(designs[1]).range


def test_a_design_file_may_omit_the_release_angle_of_the_ideal_rule():
    layout = design_to_dict(default_design())
    del layout["machine"]["release_angle"]
    with pytest.raises(DesignError, match="machine.release_angle"):
        design_from_dict(layout)
    layout["machine"]["release_rule"] = "ideal"
    design = design_from_dict(layout)
    assert design.machine.release_angle is None
    assert "release_angle" not in design_to_dict(design)["machine"]
    assert design_from_dict(design_to_dict(design)) == design


def test_a_release_angle_given_with_the_ideal_rule_is_ignored():
    layout = design_to_dict(default_design())
    layout["machine"]["release_rule"] = "ideal"
    given = design_from_dict(layout)
    layout["machine"]["release_angle"] = 80.0   # beyond the velocity rule's span: not checked, not used
    assert fast.simulate_fast(design_from_dict(layout)).range == fast.simulate_fast(given).range


def test_the_optimiser_does_not_vary_the_release_angle_of_an_ideal_problem():
    from analytic.design_space import default_problem
    with pytest.raises(DesignError, match="variables.release_angle"):
        dataclasses.replace(default_problem(), release_rule="ideal")
