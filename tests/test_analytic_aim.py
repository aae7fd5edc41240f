"""Aim: settings that land on a target, re-simulated here on the reference path (1 mm), and bad input."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from analytic import cli
from analytic.aim import AIM_TOLERANCE, aim
from analytic.design import DesignError
from analytic.design_file import save_design
from analytic.fields import field
from analytic.reference import simulate
from crosscheck.cases import sample_cases
from support import Stop, stops_at


def _landing(design, name, value):
    """The reference path's range with ``name`` set to ``value`` (file units), m."""
    shot = simulate(field(name).replace(design, value), histories=False)
    assert shot.ok, shot.message
    return shot.range


def _assert_lands(design, result):
    assert result.solutions, "no solution"
    for solution in result.solutions:
        assert abs(_landing(design, result.field.name, solution.value) - result.target) <= AIM_TOLERANCE
        assert solution.range == pytest.approx(_landing(design, result.field.name, solution.value), abs=1e-9)


@pytest.mark.parametrize("name, target", [
    ("machine.release_angle", 30.0), ("release_angle", 44.0), ("machine.counterweight_mass", 30.0),
    ("machine.sling_length", 40.0), ("projectile.mass", 40.0), ("environment.wind_speed", 46.5),
], ids=lambda v: str(v))
def test_aim_lands_within_a_millimetre_on_the_papers_design(table3, name, target):
    result = aim(table3, name, target)
    _assert_lands(table3, result)
    low, high = result.reachable
    assert low <= target <= high


def test_a_release_angle_has_a_low_and_a_high_throw(table3):
    result = aim(table3, "release_angle", 30.0)
    values = [s.value for s in result.solutions]
    assert len(values) >= 2 and values == sorted(values)
    # The low throw lands sooner as the angle rises; the high throw later.
    assert result.solutions[0].metres_per_unit > 0.0 > result.solutions[-1].metres_per_unit


#: Seeded designs over the paper's bounds that throw (seed 18: 14.5, 28.7 and 21.2 m).
THROWING_SAMPLES = sample_cases(4, seed=18)[:3]


@pytest.mark.parametrize("case", THROWING_SAMPLES, ids=lambda c: c.name)
@pytest.mark.parametrize("name", ["release_angle", "counterweight_mass", "sling_length", "projectile.mass"])
def test_aim_lands_within_a_millimetre_on_sampled_designs(case, name):
    shot = simulate(case.design, histories=False)
    assert shot.ok, shot.message
    target = 0.9 * shot.range
    _assert_lands(case.design, aim(case.design, name, target))


def test_metres_per_unit_is_the_reference_paths_slope(table3):
    (solution,) = aim(table3, "counterweight_mass", 30.0).solutions
    step = 1e-4   # kg; the range is smooth to ~1e-9 m, so the slope is good to ~1e-5 m/kg
    slope = (_landing(table3, "counterweight_mass", solution.value + step)
             - _landing(table3, "counterweight_mass", solution.value - step)) / (2 * step)
    assert solution.metres_per_unit == pytest.approx(slope, rel=1e-4)


def test_the_band_holds_the_settings_within_the_tolerance(table3):
    (solution,) = aim(table3, "counterweight_mass", 30.0, within=0.5).solutions
    low, high = solution.band
    assert low < solution.value < high
    for edge in (low, high):
        assert abs(_landing(table3, "counterweight_mass", edge) - 30.0) == pytest.approx(0.5, abs=1e-6)
    assert abs(_landing(table3, "counterweight_mass", 0.5 * (low + solution.value)) - 30.0) < 0.5


def test_a_target_out_of_reach_reports_the_reachable_span(table3):
    result = aim(table3, "counterweight_mass", 500.0, bounds=(2.0, 8.0))
    assert not result.reached
    low, high = result.reachable
    # The span's ends are the ranges at the bounds here (range grows with the counterweight).
    assert low == pytest.approx(_landing(table3, "counterweight_mass", 2.0), rel=1e-7)
    assert high == pytest.approx(_landing(table3, "counterweight_mass", 8.0), rel=1e-7)


def test_the_command_prints_json_and_exits_3_out_of_reach(table3, tmp_path, capsys):
    path = tmp_path / "d.toml"
    save_design(table3, path)
    assert cli.main(["aim", str(path), "--target", "30m", "--adjust", "machine.release_angle", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) >= {"field", "target", "solutions", "reachable"}
    assert out["field"] == "machine.release_angle" and out["target"] == 30.0
    assert all(set(s) >= {"value", "range", "metres_per_unit"} for s in out["solutions"])
    assert all(-90.0 < s["value"] < 90.0 for s in out["solutions"])      # degrees, as in files
    assert cli.main(["aim", str(path), "--target", "100 ft", "--adjust", "counterweight_mass",
                     "--bounds", "2kg:8kg", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["target"] == pytest.approx(30.48) and abs(out["solutions"][0]["range"] - 30.48) <= AIM_TOLERANCE
    assert cli.main(["aim", str(path), "--target", "500", "--adjust", "counterweight_mass",
                     "--bounds", "2:8", "--json"]) == 3
    captured = capsys.readouterr()
    out = json.loads(captured.out)
    assert out["solutions"] == [] and len(out["reachable"]) == 2
    assert "out of reach" in captured.err and f"{out['reachable'][1]:.3f}" in captured.err


@pytest.mark.parametrize("argv, words", [
    (["--target", "-5", "--adjust", "release_angle"], ['target = "-5" (-5 m)', "positive distance"]),
    (["--target", "3 kg", "--adjust", "release_angle"], ["target = '3 kg'", "length"]),
    (["--target", "30 bananas", "--adjust", "release_angle"], ["target = '30 bananas'", "unknown unit 'bananas'"]),
    (["--target", "far", "--adjust", "release_angle"], ["target = 'far'", "no number"]),
    (["--target", "30", "--adjust", "release_rule"], ["machine.release_rule", "not a number"]),
    (["--target", "30", "--adjust", "projectile.drag"], ["projectile.drag", "not a number"]),
    (["--target", "30", "--adjust", "machine.arm_lenght"], ["machine.arm_lenght", "no such field"]),
    (["--target", "30", "--adjust", "lever.mass"], ["lever.mass", "unknown table"]),
    (["--target", "30", "--adjust", "base.mass"], ["base.mass", "frame is fixed"]),
    (["--target", "30", "--adjust", "release_angle", "--bounds", "60:30"], ["bounds", "inverted"]),
    (["--target", "30", "--adjust", "release_angle", "--bounds", "30:30"], ["bounds", "empty"]),
    (["--target", "30", "--adjust", "counterweight_mass", "--bounds", "2m:3m"], ["bounds = '2m'", "mass"]),
    (["--target", "30", "--adjust", "release_angle", "--within", "-1"], ["within", "positive distance"]),
], ids=lambda v: " ".join(v) if isinstance(v, list) else None)
def test_bad_input_exits_2_with_the_reason(table3, tmp_path, capsys, argv, words):
    path = tmp_path / "d.toml"
    save_design(table3, path)
    assert cli.main(["aim", str(path), *argv]) == 2
    err = capsys.readouterr().err
    assert err.startswith("invalid input: ") and all(w in err for w in words), err


def test_the_library_refuses_bad_input_before_shooting(table3, monkeypatch):
    from analytic import fast

    def no_shots(*args, **kwargs):
        raise AssertionError("shot before the input was checked")

    monkeypatch.setattr(fast, "shoot", no_shots)
    for kwargs in ({"target": -1.0}, {"target": math.nan}, {"target": 30.0, "bounds": (5.0, 2.0)},
                   {"target": 30.0, "within": 0.0}):
        with pytest.raises(DesignError):
            aim(table3, "counterweight_mass", **kwargs)
    with pytest.raises(DesignError):
        aim(table3, "release_rule", 30.0)


def test_failures_in_the_scan_are_gaps_not_solutions(table3):
    # Light counterweights do not fire: their settings are gaps, and a solution still comes from the rest.
    result = aim(table3, "counterweight_mass", 30.0, bounds=(0.01, 8.0))
    assert np.isnan(result.ranges[0]) and result.status[0] != "ok"
    _assert_lands(table3, result)


def test_imperial_output_shows_feet_and_pounds(table3, tmp_path, capsys):
    path = tmp_path / "d.toml"
    save_design(table3, path)
    argv = ["aim", str(path), "--target", "100ft", "--adjust", "counterweight_mass", "--bounds", "2kg:8kg"]
    assert cli.main(argv + ["--json"]) == 0
    (solution,) = json.loads(capsys.readouterr().out)["solutions"]
    assert cli.main(argv + ["--units", "imperial"]) == 0
    text = capsys.readouterr().out
    pound, foot = 0.45359237, 0.3048   # the international pound and foot (1959)
    assert f"counterweight_mass = {solution['value'] / pound:.6f} lb" in text
    assert f"{solution['metres_per_unit'] / foot * pound:+.4f} ft per lb" in text
    assert "at 100.0000 ft" in text



@pytest.mark.parametrize("calls", [1, 5])
def test_a_check_that_raises_ends_aim_at_once(table3, calls, monkeypatch):
    # Counted from the fast shots aim asks for after its scan: none may follow the check that raised.
    from analytic import fast

    shots, original = [], fast.simulate_fast
    monkeypatch.setattr(fast, "simulate_fast", lambda *a, **k: shots.append(None) or original(*a, **k))
    check, seen = stops_at(calls)
    with pytest.raises(Stop):
        aim(table3, "machine.release_angle", 30.0, check=check)
    assert len(seen) == calls
    assert len(shots) == calls - 1   # each check before its shot: the last one's shot never ran
