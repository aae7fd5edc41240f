"""The ideal release rule in the builders' tools: aim, charts, sweeps, the optimiser and calibration.

Under the rule the release angle is ignored (``analytic.ideal`` finds the release), so every tool
refuses to vary it, naming the field and the rule, and every other field works as for another rule.
"""

from __future__ import annotations

import csv
import dataclasses
import math

import numpy as np
import pyarrow.dataset as ds
import pytest

from analytic import cli, fast
from analytic.aim import aim
from analytic.calibrate import calibrate, load_calibration
from analytic.chart import chart, save_chart, vary
from analytic.design import DesignError
from analytic.design_file import default_design, load_design, save_design
from analytic.design_space import VARIABLE_NAMES, design_at, problem_from_dict, variables_of
from analytic.fields import field
from analytic.optimise import optimise
from analytic.optimise.report import IDEAL_NOTE, PAPER_LABEL, PUBLISHED_LABEL, format_report, format_tables
from analytic.sweep import run_sweep, sweep_from_dict
from crosscheck.cases import ideal
from support import problem_dict, with_projectile
from test_analytic_calibrate import PROTOTYPE_FILE, write_calibration

#: The rule's message names it and the field (``analytic.fields.IDEAL_IGNORES_RELEASE_ANGLE``).
RULE = "release_rule 'ideal'"


@pytest.fixture(scope="module")
def ideal_design():
    return ideal(default_design(), "ideal")


@pytest.fixture
def ideal_file(tmp_path, ideal_design):
    path = tmp_path / "ideal.toml"
    save_design(ideal_design, path)
    return path


# --------------------------------------------------------------------------- #
# aim
# --------------------------------------------------------------------------- #

def test_aim_refuses_the_release_angle_of_an_ideal_design(ideal_design):
    with pytest.raises(DesignError, match=rf"machine\.release_angle.*{RULE}"):
        aim(ideal_design, "machine.release_angle", 30.0)
    # A release angle given in the file is ignored as well: still refused, not varied.
    given = dataclasses.replace(ideal_design, machine=dataclasses.replace(ideal_design.machine,
                                                                          release_angle=math.radians(40.0)))
    with pytest.raises(DesignError, match=RULE):
        aim(given, "release_angle", 30.0)


def test_aim_command_refuses_it_with_exit_2(ideal_file, capsys):
    assert cli.main(["aim", str(ideal_file), "--target", "30", "--adjust", "machine.release_angle"]) == 2
    err = capsys.readouterr().err
    assert "machine.release_angle" in err and RULE in err and "Traceback" not in err


@pytest.mark.slow
def test_aim_by_another_field_lands_an_ideal_design(ideal_design):
    """The counterweight's mass that lands the ideal shot 30 m out: checked here on the fast path
    (the aim confirms on the reference path, within its 1 mm; the paths agree to 1e-7)."""
    result = aim(ideal_design, "machine.counterweight_mass", 30.0)
    assert result.solutions
    for solution in result.solutions:
        landed = fast.simulate_fast(field("machine.counterweight_mass").replace(ideal_design, solution.value)).range
        assert landed == pytest.approx(30.0, abs=2e-3)


# --------------------------------------------------------------------------- #
# charts
# --------------------------------------------------------------------------- #

def test_a_chart_of_an_ideal_design_gives_each_settings_launch_angle(ideal_design, tmp_path):
    masses = (4.0, 6.5, 9.0)
    result = chart(ideal_design, [vary("machine.counterweight_mass", masses[0], masses[-1], len(masses))])
    csv_path, _ = save_chart(result, tmp_path / "chart")
    with csv_path.open() as handle:
        rows = list(csv.DictReader(handle))
    for mass, row in zip(masses, rows, strict=True):
        shot = fast.simulate_fast(field("machine.counterweight_mass").replace(ideal_design, mass))
        assert row["status"] == "ok"
        assert float(row["range [m]"]) == pytest.approx(shot.range, rel=1e-12)
        assert float(row["launch_angle [deg]"]) == pytest.approx(math.degrees(shot.launch_angle), rel=1e-12)
    # Another rule's chart is as it was: no launch angle column.
    assert chart(default_design(), [vary("machine.counterweight_mass", 4.0, 9.0, 2)]).launch_angle is None


def test_a_chart_refuses_the_release_angle_of_an_ideal_design(ideal_design, ideal_file, tmp_path, capsys):
    with pytest.raises(DesignError, match=RULE):
        chart(ideal_design, [vary("machine.release_angle", 30.0, 50.0, 3)])
    assert cli.main(["chart", str(ideal_file), "--vary", "machine.release_angle=30:50:3",
                     "--out", str(tmp_path / "c")]) == 2
    assert "machine.release_angle" in capsys.readouterr().err
    assert not (tmp_path / "c").exists()


# --------------------------------------------------------------------------- #
# sweeps
# --------------------------------------------------------------------------- #

def test_a_sweep_of_an_ideal_design_stores_range_and_launch_angle(ideal_file, tmp_path):
    sweep = sweep_from_dict({"design": str(ideal_file), "grid": {
        "machine.sling_length": {"from": 0.45, "to": 0.65, "steps": 3},
        "environment.wind_speed": {"values": [-2.0, 2.0]}}})
    run_sweep(sweep, tmp_path / "out")
    table = ds.dataset(str(tmp_path / "out")).to_table().sort_by("index")
    assert table.num_rows == 6 and "launch_angle" in table.column_names
    for row in table.to_pylist():
        design = field("environment.wind_speed").replace(
            field("machine.sling_length").replace(load_design(ideal_file), row["machine.sling_length"]),
            row["environment.wind_speed"])
        shot = fast.simulate_fast(design, loads=False)
        assert row["status"] == "ok"
        assert row["range"] == shot.range   # the kernel rows are the designs' own, bit for bit
        assert row["launch_angle"] == shot.launch_angle


@pytest.mark.parametrize("table", ["grid", "sample", "uncertain"])
def test_a_sweep_refuses_the_release_angle_of_an_ideal_design(ideal_file, table):
    entries = {"grid": {"grid": {"machine.release_angle": {"from": 30.0, "to": 50.0, "steps": 3}}},
               "sample": {"sample": {"n": 4, "method": "random", "seed": 0,
                                     "machine.release_angle": {"from": 30.0, "to": 50.0}}},
               "uncertain": {"sample": {"n": 4, "method": "random", "seed": 0,
                                        "machine.sling_length": {"from": 0.5, "to": 0.6}},
                             "uncertain": {"machine.release_angle": {"distribution": "normal", "sd": 1.0}}}}
    with pytest.raises(DesignError, match=RULE) as error:
        sweep_from_dict({"design": str(ideal_file), **entries[table]})
    assert error.value.field == f"{table}.machine.release_angle"


# --------------------------------------------------------------------------- #
# the optimiser
# --------------------------------------------------------------------------- #

def _ideal_problem_dict(**variables) -> dict:
    data = problem_dict()
    data["release"] = {"rule": "ideal"}
    del data["variables"]["release_angle"]
    data["variables"].update(variables)
    return data


def test_an_ideal_problem_has_no_release_angle_variable():
    problem = problem_from_dict(_ideal_problem_dict())
    free = [problem.names[i] for i in problem.free]
    assert free == list(VARIABLE_NAMES[:5])
    design = design_at(problem, variables_of(default_design().machine))
    assert design.machine.release_rule == "ideal" and design.machine.release_angle is None
    # A fixed value is allowed, and ignored.
    fixed = problem_from_dict(_ideal_problem_dict(release_angle={"value": 30.0}))
    assert design_at(fixed, variables_of(default_design().machine)).machine == design.machine


def test_an_ideal_problem_that_bounds_the_release_angle_is_refused():
    data = _ideal_problem_dict(release_angle={"lower": 10.0, "upper": 60.0})
    with pytest.raises(DesignError, match="ideal.*no variable") as error:
        problem_from_dict(data)
    assert error.value.field == "variables.release_angle"
    assert error.value.value == {"lower": 10.0, "upper": 60.0}   # as the file wrote it (deg)


def test_an_ideal_problem_has_no_robust_variant(tmp_path, capsys):
    import tomli_w

    problem = problem_from_dict(_ideal_problem_dict())
    with pytest.raises(ValueError, match="ideal"):
        optimise(problem, robust_sigma=0.02)
    path = tmp_path / "ideal-problem.toml"
    path.write_text(tomli_w.dumps(_ideal_problem_dict()))
    assert cli.main(["optimise", str(path), "--robust", "--out", str(tmp_path / "o"), "--quiet"]) == 2
    assert "ideal" in capsys.readouterr().err and not (tmp_path / "o").exists()


def test_the_report_of_an_ideal_problem_says_the_release_angle_was_dropped():
    problem = problem_from_dict(_ideal_problem_dict())
    values = variables_of(default_design().machine)
    table = format_tables(problem, [(PUBLISHED_LABEL, values, 35.9), (PAPER_LABEL, values, 0.0)])
    row = next(line for line in table.splitlines() if "release angle" in line)
    # The published optimum's pin (Table III: 43.4 deg) is its own; the same machine under the ideal
    # rule releases where it throws farthest.
    assert row.split()[-2:] == ["43.4", "(ideal)"], row


@pytest.mark.slow
def test_the_optimiser_searches_an_ideal_problem_without_the_release_angle(tmp_path):
    """Only the sling free (the rest at Table III, vacuum, so the search is short): the optimum's
    range is at least that of each of a grid of slings across the bounds (fast path, same rule),
    and its design file has no release angle."""
    values = variables_of(default_design().machine)
    fixed = {name: {"value": math.degrees(v) if name.endswith("angle") else float(v)}
             for name, v in zip(VARIABLE_NAMES[:5], values[:5], strict=True) if name != "sling_length"}
    data = _ideal_problem_dict(**fixed, sling_length={"lower": 0.2, "upper": 0.61})
    data["projectile"]["drag"] = "none"
    problem = problem_from_dict(data)
    result = optimise(problem, workers=1)
    best = result.ranges["optimum"]
    slings = np.linspace(0.2, 0.61, 9)
    grid = fast.shoot([design_at(problem, np.r_[values[:3], s, values[4:]]) for s in slings], loads=False).range
    assert best >= np.nanmax(grid) * (1.0 - 1e-6), (best, slings[np.nanargmax(grid)])
    assert result.optimum.values[5] == problem.variables[5].lower   # never moved
    assert IDEAL_NOTE in format_report(result)
    path = tmp_path / "optimum.toml"
    save_design(design_at(problem, result.optimum.values), path)
    assert "release_angle" not in path.read_text()


# --------------------------------------------------------------------------- #
# calibration
# --------------------------------------------------------------------------- #

def _ideal_prototype(tmp_path):
    design = ideal(load_design(PROTOTYPE_FILE), "prototype-ideal")
    save_design(design, tmp_path / "ideal.toml")
    return design


def test_calibration_refuses_a_release_angle_offset_on_an_ideal_shot(tmp_path):
    _ideal_prototype(tmp_path)
    shots = [{"design": "ideal.toml", "range": 20.0, "range_uncertainty": 0.5}]
    for fit in (["release_angle_offset"], ["machine.release_angle"]):
        with pytest.raises(DesignError, match=RULE) as error:
            load_calibration(write_calibration(tmp_path / "c.toml", fit, shots))
        assert error.value.field == "fit"


def test_calibration_fits_the_drag_factor_of_ideal_shots(tmp_path):
    """Noise-free ranges of the ideal prototype at a known drag factor: the fit gives it back."""
    design = _ideal_prototype(tmp_path)
    truth = 1.3
    measured = fast.simulate_fast(with_projectile(design, drag_factor=truth), loads=False)
    assert measured.ok
    shots = [{"design": "ideal.toml", "range": measured.range, "range_uncertainty": 0.5}]
    result = calibrate(load_calibration(write_calibration(tmp_path / "c.toml", ["drag_factor"], shots)))
    assert result.converged, result.warnings
    # The ideal range is flat in the release instant at its maximum, so the search's own
    # tolerance moves it by far less than this (1e-4 of the factor is 3e-6 of the range here).
    assert result.values[0] == pytest.approx(truth, abs=1e-4)
