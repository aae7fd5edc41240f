"""Loads in the optimiser: limits on the peak loads, and the gentlest machine that still throws a distance."""

from __future__ import annotations

import dataclasses

import pytest
import tomli_w

from analytic import fast
from analytic.design import DesignError
from analytic.optimise import cli, optimise
from analytic.optimise.evaluate import Evaluator
from analytic.design_space import default_problem, design_at, problem_from_dict
from analytic.optimise.search import OUTCOME_FEASIBILITY, Settings, maximise
from test_analytic_optimise_problem import problem_dict


@pytest.fixture(scope="module")
def unconstrained():
    """The paper's problem maximised without load limits (the default search)."""
    problem = default_problem()
    optimum = maximise(problem, Evaluator(problem), Settings())
    return optimum, fast.simulate_fast(design_at(problem, optimum.values))


def test_a_problem_file_reads_load_limits_and_the_gentle_mode_with_units():
    data = problem_dict()
    data["loads"] = {"max_axle_load": "200 lbf", "max_projectile_acceleration": "60 g0"}
    problem = problem_from_dict(data)
    assert dict(problem.load_limits) == pytest.approx({"axle_load": 200 * 4.4482216152605,
                                                       "projectile_acceleration": 60 * 9.80665})
    assert problem.outcome_constraints == ("peak axle load <= 889.644", "peak projectile acceleration <= 588.399")
    data["loads"] = {"minimise": "hinge_load", "min_range": "100 ft"}
    problem = problem_from_dict(data)
    assert (problem.minimise, problem.min_range) == ("hinge_load", pytest.approx(30.48))


def test_a_problem_file_reads_the_arm_bending_moment_limit_in_ft_lbf():
    data = problem_dict()
    data["loads"] = {"max_arm_bending_moment": "30 ft lbf"}
    problem = problem_from_dict(data)
    # 1 ft lbf = 0.3048 m x 4.4482216152605 N (the international foot and pound-force).
    assert dict(problem.load_limits) == pytest.approx({"arm_bending_moment": 30 * 0.3048 * 4.4482216152605})
    assert problem.outcome_constraints == ("peak arm bending moment <= 40.6745",)


@pytest.mark.parametrize("loads, field", [
    ({"max_arm_bending_moment": "40 N"}, "loads.max_arm_bending_moment"),
    ({"max_arm_bending_moment": -1.0}, "loads.max_arm_bending_moment"),
    ({"max_axle_load": -5.0}, "loads.max_axle_load"),
    ({"max_axle_load": "5 kg"}, "loads.max_axle_load"),
    ({"max_bolt_load": 5.0}, "loads.max_bolt_load"),
    ({"minimise": "axle_load"}, "loads.min_range"),
    ({"minimise": "bolts", "min_range": 30.0}, "loads.minimise"),
    ({"min_range": 30.0}, "loads.min_range"),
], ids=lambda v: str(v))
def test_bad_loads_in_a_problem_name_the_field(loads, field, tmp_path, capsys):
    data = problem_dict()
    data["loads"] = loads
    with pytest.raises(DesignError) as caught:
        problem_from_dict(data)
    assert caught.value.field == field
    path = tmp_path / "bad.toml"
    path.write_text(tomli_w.dumps(data))
    assert cli.main([str(path), "--out", str(tmp_path / "out"), "--quiet"]) == 2
    assert f"invalid problem: {field}" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_robust_with_loads_is_refused_before_any_work(tmp_path, capsys):
    data = problem_dict()
    data["loads"] = {"max_axle_load": 1000.0}
    path = tmp_path / "p.toml"
    path.write_text(tomli_w.dumps(data))
    assert cli.main([str(path), "--robust", "--out", str(tmp_path / "out"), "--quiet"]) == 2
    assert "nominal shot only" in capsys.readouterr().err


@pytest.mark.parametrize("load", ["projectile_acceleration", "arm_bending_moment"])
def test_a_load_limit_is_met_and_costs_range(unconstrained, load):
    optimum, shot = unconstrained
    limit = 0.8 * getattr(shot, f"peak_{load}")
    problem = dataclasses.replace(default_problem(), load_limits=((load, limit),))
    limited = maximise(problem, Evaluator(problem), Settings())
    got = fast.simulate_fast(design_at(problem, limited.values))
    assert getattr(got, f"peak_{load}") <= limit * (1.0 + OUTCOME_FEASIBILITY)
    assert got.range == pytest.approx(limited.score, rel=1e-9)
    assert limited.score < optimum.score
    # The limit binds: it is active at the optimum, with a positive multiplier.
    (name,) = [n for n in limited.first_order.active_constraints if n.startswith("peak")]
    assert name.startswith(f"peak {load.replace('_', ' ')} <=")
    assert limited.first_order.constraint_multipliers[name] > 0.0


def test_the_gentle_mode_keeps_the_range_with_a_smaller_peak_load(unconstrained):
    optimum, shot = unconstrained
    problem = dataclasses.replace(default_problem(), minimise="axle_load", min_range=40.0)
    gentle = maximise(problem, Evaluator(problem), Settings())
    got = fast.simulate_fast(design_at(problem, gentle.values))
    assert got.range >= 40.0 * (1.0 - OUTCOME_FEASIBILITY)
    assert got.peak_axle_load == pytest.approx(-gentle.score, rel=1e-9)
    assert got.peak_axle_load < shot.peak_axle_load     # gentler than the longest throw's machine


def test_optimise_reports_the_peak_loads_of_every_design():
    problem = dataclasses.replace(default_problem(), load_limits=(("axle_load", 5000.0),))
    result = optimise(problem, seed=0)
    assert set(result.peaks) == set(result.ranges)
    for label, peaks in result.peaks.items():
        assert peaks["peak_axle_load"] > 0.0, label
    from analytic.optimise.report import format_report

    text = format_report(result)
    assert "Peak loads (stages 1-2); limits: axle_load 5000" in text and "axle load (N)" in text
    assert "arm bending moment (N m)" in text
    assert "arm bending moment (ft lbf)" in format_report(result, "imperial")
