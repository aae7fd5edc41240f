"""A problem of a machine as built: the sling's and the pouch's mass, a trough and a target's level fixed
in the problem file reach every design and its shot, the size limits stand the arm on the trough, and
the optimiser improves on a start under them."""

from __future__ import annotations

import dataclasses
import math

import pytest

from analytic.design import Base, DesignError, Environment
from analytic.design_space import default_problem, design_at, problem_from_dict, variables_of
from analytic.optimise.constraints import feasible, footprint, rest_points
from analytic.optimise.evaluate import Evaluator, throw
from analytic.optimise.report import format_constraints, format_tables
from analytic.optimise.search import Settings, maximise
from analytic.reference import DEFAULT_RTOL, simulate
from support import problem_dict

#: The as-built parts of the problems here: a heavy sling (a chain of 20 g, 44 % of the 45.6 g golf
#: ball) and a pouch of 5 g, in the file's units as a user writes them; a trough 15 cm up; a target
#: 3 m above the base (the paper's optimum rises 14 m).
SLING, POUCH, TROUGH, TARGET = "20 g", "5 g", 0.15, 3.0


def _as_built(trough: float = TROUGH) -> dict:
    data = problem_dict()
    data["machine"] = {"sling_mass": SLING, "pouch_mass": POUCH}
    data["base"] = {"trough_height": trough}
    data["environment"]["target_height"] = TARGET
    return data


def test_the_problem_files_fixed_parts_reach_every_design(table3):
    problem = problem_from_dict(_as_built())
    assert (problem.sling_mass, problem.pouch_mass) == (pytest.approx(0.020), pytest.approx(0.005))
    design = design_at(problem, variables_of(table3.machine))
    assert (design.machine.sling_mass, design.machine.pouch_mass) == (problem.sling_mass, problem.pouch_mass)
    assert design.base.trough_height == TROUGH and design.environment.target_height == TARGET
    # Left out, each is the massless sling, no pouch, no trough, the base's level: the paper's problem.
    paper = design_at(default_problem(), variables_of(table3.machine))
    assert (paper.machine.sling_mass, paper.machine.pouch_mass, paper.base, paper.environment) == (
        0.0, 0.0, Base(), Environment())


@pytest.mark.parametrize(("table", "entry", "field"), [
    ("machine", {"sling_mass": -0.01}, "machine.sling_mass"),
    ("machine", {"pouch_mass": "heavy"}, "machine.pouch_mass"),
    ("machine", {"sling_mass": {"lower": 0.0, "upper": 0.02}}, "machine.sling_mass"),   # no variable
    ("machine", {"chain_mass": 0.01}, "machine.chain_mass"),
    ("base", {"trough_height": -0.1}, "base.trough_height"),
    ("environment", {"target_height": "up"}, "environment.target_height"),
], ids=["negative-sling", "pouch-not-a-number", "sling-bounds", "unknown-part", "negative-trough", "target-text"])
def test_a_bad_part_is_refused_naming_its_field(table, entry, field):
    data = problem_dict()
    data.setdefault(table, {}).update(entry)
    with pytest.raises(DesignError) as raised:
        problem_from_dict(data)
    assert raised.value.field == field


def test_the_machine_rests_on_the_trough_for_the_size_limits(table3):
    # The arm's length is the variables' (it reaches the base at the starting angle); on a trough
    # h_t up its tip rests at the trough's level, arm_long from the pivot:
    # x = -sqrt(arm_long^2 - (h - h_t)^2), the sling lying forward along the trough.
    m = table3.machine
    points = rest_points(m, TROUGH)
    rise = m.pivot_height - TROUGH
    assert points["long_tip"] == pytest.approx([-math.sqrt(m.arm_long**2 - rise**2), -rise], abs=1e-12)
    assert points["projectile"] == pytest.approx(points["long_tip"] + [m.sling_length, 0.0], abs=1e-12)
    # The short arm is the long arm's extension through the pivot.
    assert points["short_tip"] / m.arm_short == pytest.approx(-points["long_tip"] / m.arm_long, abs=1e-12)
    # Farther back than on the base: the paper's optimum, 61 cm across on the base, outgrows its box.
    assert footprint(m) == pytest.approx(0.61, abs=1e-4) and footprint(m, TROUGH) > 0.62
    problem = problem_from_dict(_as_built())
    assert not feasible(problem, m) and feasible(default_problem(), m)
    # On the base, the starting angle's geometry to the bit, as before there were troughs.
    theta0 = m.starting_angle
    assert list(rest_points(m)["long_tip"]) == [-m.arm_long * math.cos(theta0), -m.pivot_height]


def test_the_report_states_the_machine_as_built(table3):
    problem = problem_from_dict(_as_built())
    values = variables_of(table3.machine)
    metric = format_tables(problem, [("Table III", values, 35.9)]).splitlines()[1]
    assert metric == ("as built: sling 0.02 kg, pouch 0.005 kg, trough 15 cm up, "
                      "target 3 m above the base (the range measured there)")
    imperial = format_tables(problem, [("Table III", values, 35.9)], "imperial").splitlines()[1]
    assert "trough 5.91 in up" in imperial and "target 9.84 ft above" in imperial   # 15 / 2.54, 3 / 0.3048
    assert not format_tables(default_problem(), [("Table III", values, 35.9)]).splitlines()[1].startswith("as built")


def _row(line: str) -> tuple[str, list[str]]:
    """A constraints table's row: its label (34 characters, a margin's 44) and its columns."""
    width = 44 if line.startswith("  margin") else 34
    return line[:width].strip(), line[width:].split()


def test_the_reports_constraint_rows_stand_the_machine_on_the_trough(table3):
    # Each row at rest less its limit is the margin the optimiser met, on the trough as on the base.
    problem = problem_from_dict(_as_built())
    text = format_constraints(problem, [("Table III", variables_of(table3.machine), 35.9)])
    rows = dict(_row(line) for line in text.splitlines()[2:])
    limit, value = rows["counterweight link to axle"][1:]
    assert float(value) - float(limit) == pytest.approx(float(rows["margin: axle clearance"][0]), abs=0.01)
    limit, value = rows["footprint (horizontal span)"][1:]
    tightest = min(float(rows[f"margin: footprint ({span})"][0])
                   for span in ("tip to projectile", "tip to pivot", "tip to short-arm tip"))
    assert float(limit) - float(value) == pytest.approx(tightest, abs=0.01)


@pytest.mark.slow
def test_the_optimiser_beats_its_start_under_a_heavy_sling_at_a_raised_target(table3):
    # No trough: the paper's Table III design, the start, stays inside the box (61 cm on the base).
    problem = problem_from_dict(_as_built(trough=0.0))
    start = variables_of(table3.machine)
    began = throw(problem, start, DEFAULT_RTOL, loads=False)
    assert began.failure is None and feasible(problem, design_at(problem, start).machine)
    with Evaluator(problem) as evaluator:
        optimum = maximise(problem, evaluator, Settings(local_maxiter=30), start=start)
    design = design_at(problem, optimum.values)
    assert feasible(problem, design.machine)
    assert optimum.score > began.range + 0.5, (optimum.score, began.range)
    # The score is the range at the target of the design with every part (the reference path's shot,
    # to its integrator's tolerance), not that of the bare machine at the base.
    shot = simulate(design, histories=False)
    assert shot.ok and shot.landing_position[1] == pytest.approx(TARGET - design.machine.pivot_height)
    assert optimum.score == pytest.approx(shot.range, rel=1e-6)
    bare = dataclasses.replace(design, machine=dataclasses.replace(design.machine, sling_mass=0.0, pouch_mass=0.0),
                               environment=dataclasses.replace(design.environment, target_height=0.0))
    assert simulate(bare, histories=False).range > 1.05 * optimum.score
