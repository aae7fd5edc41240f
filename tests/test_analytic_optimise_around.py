"""The problem around a design (``analytic.optimise.around``): the design rebuilt at its own values, bounds
about them, its machine kept, and the search never ending below it."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from analytic.design import BeamArm, DesignError
from analytic.design_file import default_design, load_design
from analytic.design_space import VARIABLE_NAMES, design_at
from analytic.fast import simulate_fast
from analytic.optimise import optimise
from analytic.optimise.around import (ANGLE_MARGIN, OPTIMISED_FIELDS, ScaledArm, adopted, default_bounds,
                                      problem_around, start_values)
from analytic.optimise.constraints import FEASIBILITY_TOLERANCE, constraint_values
from analytic.optimise.search import Settings

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "analytic" / "data"
#: Designs of every kind and size: the workbench's presets, the paper's machine bolted and floating.
DESIGNS = {path.stem: path for path in sorted((ROOT / "workbench" / "presets").glob("*.toml"))} | {
    "paper-fixed": DATA / "paper_table3_fixed.toml", "paper-floating": DATA / "paper_table3_floating.toml"}
#: A design rebuilt from its variables goes through asin and sin, a sum and a difference: a few ulps.
ROUND_OFF = 1e-12
#: A search too short to find much, long enough to take seconds: its start is in its first population.
TINY = Settings(popsize=3, maxiter=1, local_maxiter=4)


@pytest.fixture(params=sorted(DESIGNS), ids=sorted(DESIGNS))
def design(request):
    return load_design(DESIGNS[request.param])


def test_the_design_is_rebuilt_at_its_own_values_with_everything_else_kept(design):
    problem = problem_around(design)
    rebuilt = design_at(problem, start_values(design), name=design.name)
    for name, value in dataclasses.asdict(design.machine).items():
        if isinstance(value, float):
            assert getattr(rebuilt.machine, name) == pytest.approx(value, rel=ROUND_OFF, abs=ROUND_OFF), name
        else:
            assert getattr(rebuilt.machine, name) == value, name
    assert (rebuilt.projectile, rebuilt.environment, rebuilt.base, rebuilt.losses) == (
        design.projectile, design.environment, design.base, design.losses)


def test_the_design_meets_its_own_size_limits(design):
    assert np.all(constraint_values(problem_around(design), design.machine) >= -FEASIBILITY_TOLERANCE)


def test_lengths_range_half_to_twice_and_angles_a_window_inside_their_limits(design):
    bounds = default_bounds(design)
    values = dict(zip(VARIABLE_NAMES, start_values(design), strict=True))
    for name in ("arm_short", "clearance", "sling_length"):
        assert bounds[name] == (values[name] / 2, values[name] * 2)
    low, high = bounds["starting_angle"]
    assert low == pytest.approx(max(values["starting_angle"] - math.radians(20), ANGLE_MARGIN))
    assert high == pytest.approx(min(values["starting_angle"] + math.radians(20), math.pi / 2 - ANGLE_MARGIN))
    assert ("counterweight_link" in bounds) == (design.machine.kind == "hinged")


def test_a_rigid_counterweight_keeps_its_link_fixed_and_refuses_bounds_on_it():
    design = load_design(DESIGNS["paper-fixed"])
    problem = problem_around(design)
    assert problem.kind == "fixed" and problem.variables[1].fixed and problem.variables[1].lower == 0.0
    with pytest.raises(DesignError, match="counterweight_link"):
        problem_around(design, {"counterweight_link": (0.1, 0.2)})


def test_the_ideal_rule_has_no_release_angle_to_bound():
    design = dataclasses.replace(default_design(), machine=dataclasses.replace(
        default_design().machine, release_rule="ideal", release_angle=None))
    assert "release_angle" not in default_bounds(design)
    assert problem_around(design).variables[-1].fixed


@pytest.mark.parametrize("bounds, field", [({"arm": (0.1, 0.2)}, "bounds"), ({"sling_length": (0.5, 0.2)},
                                                                                  "variables.sling_length"),
                                           ({"starting_angle": (0.1, 2.0)}, "variables.starting_angle")],
                         ids=["unknown", "reversed", "past-90-deg"])
def test_bad_bounds_name_their_field(bounds, field):
    with pytest.raises(DesignError) as error:
        problem_around(default_design(), bounds)
    assert error.value.field == field


def test_a_factor_not_above_one_is_refused():
    with pytest.raises(DesignError, match="factor"):
        default_bounds(default_design(), factor=1.0)


def test_the_scaled_arm_of_a_thin_uniform_beam_is_that_beam_at_any_length():
    # A beam of negligible depth: BeamArm's inertia m (L^2 + d^2) / 12 is m L^2 / 12 to d^2 / L^2 (1e-14).
    beam = BeamArm(width=0.05, depth=1e-7, density=600.0)
    arm = ScaledArm(2.0, *(lambda m, cg, i: (m, cg - 0.5, i))(*beam.properties(1.5, 0.5)))
    for lengths in ((1.5, 0.5), (3.0, 0.4), (0.8, 0.7)):
        assert arm.properties(*lengths) == pytest.approx(beam.properties(*lengths), rel=1e-12)


def test_the_search_around_a_design_ends_no_worse_than_it_and_adopting_changes_only_its_fields():
    design = load_design(DESIGNS["warwolf"])
    problem = problem_around(design)
    result = optimise(problem, start=start_values(design), settings=TINY, workers=1)
    start = simulate_fast(design).range
    # the start is scored at the search's integrator tolerance, the optimum at the final one
    assert result.ranges["optimum"] >= start * (1 - 10 * TINY.search_tolerance)
    assert result.ranges["start"] == pytest.approx(start, rel=1e-9)
    found = adopted(design, problem, result.optimum.values)
    for name, value in dataclasses.asdict(design.machine).items():
        if name not in OPTIMISED_FIELDS:
            assert getattr(found.machine, name) == value, name
    assert (found.name, found.projectile, found.base, found.losses) == (design.name, design.projectile,
                                                                        design.base, design.losses)
    assert simulate_fast(found).range == pytest.approx(result.ranges["optimum"], rel=1e-7)


#: Trebuchator's presets (``analytic/data/designs/trebuchator``): three of them (punkin, siege, warwolf)
#: give counterweights whose solid sphere of their inertia would not clear the axle at rest.
TREBUCHATOR = sorted((DATA / "designs" / "trebuchator").glob("*.toml"))


@pytest.mark.parametrize("path", TREBUCHATOR, ids=[p.stem for p in TREBUCHATOR])
def test_every_machine_as_built_is_a_feasible_start(path):
    design = load_design(path)
    problem = problem_around(design)
    assert np.all(constraint_values(problem, design.machine) >= -FEASIBILITY_TOLERANCE)
    m = design.machine
    sphere = math.sqrt(2.5 * m.counterweight_inertia / m.counterweight_mass)   # I = 2/5 m r^2
    assert 0.0 <= problem.counterweight_radius <= sphere


def test_a_counterweight_that_clears_as_a_sphere_keeps_the_spheres_radius():
    design = default_design()   # the paper's 6.5 kg cast-iron sphere, r = 0.05995 m (paper_table3.toml)
    assert problem_around(design).counterweight_radius == pytest.approx(0.05995, abs=1e-5)
