"""``python -m analytic optimise``: outputs written and readable on either path, invalid input refused with exit code 2."""

from __future__ import annotations

import math

import pytest
import tomli_w

from analytic.design_file import default_design, load_design
from analytic.optimise import cli
from analytic.optimise.constraints import feasible
from analytic.design_space import load_problem, variables_of
from analytic.reference import simulate

from support import ANGLE_TOLERANCE_DEG, RANGE_TOLERANCE, release_angle_problem_dict, with_machine


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """The release-angle problem (quick) through the command, with the robust variant."""
    folder = tmp_path_factory.mktemp("optimise")
    problem_file = folder / "release-angle.toml"
    problem_file.write_text(tomli_w.dumps(release_angle_problem_dict()))
    code = cli.main([str(problem_file), "--robust", "--out", str(folder / "out"), "--quiet"])
    return code, problem_file, folder / "out"


def test_command_succeeds_and_writes_everything(run):
    code, _, out = run
    assert code == cli.EXIT_OK
    for name in ("report.txt", "optimum.toml", "robust-optimum.toml", "convergence.png", "sensitivity.png"):
        assert (out / name).stat().st_size > 0, name


def test_report_has_the_papers_tables_and_the_scatter_comparison(run):
    text = (run[2] / "report.txt").read_text()
    for heading in ("Table III", "Table IV", "Constraints at rest", "First-order optimality",
                    "Release-angle scatter: normal, sigma = 2 deg"):
        assert heading in text


def test_written_optimum_is_a_design_that_throws_further_than_table3(run):
    # The only free variable is the release angle; Table III's 43.4 deg is one of its values.
    _, problem_file, out = run
    problem = load_problem(problem_file)
    design = load_design(out / "optimum.toml")
    assert feasible(problem, design.machine)
    table3 = simulate(with_machine(design, release_angle=default_design().machine.release_angle))
    assert simulate(design).range >= table3.range
    assert variables_of(design.machine)[:5] == pytest.approx(variables_of(default_design().machine)[:5])


@pytest.mark.slow
def test_reference_path_writes_the_same_optimum(run, tmp_path):
    # The fast and reference paths agree to round-off in range (test_analytic_optimise_fast.py), so
    # both reach the release-angle problem's optimum within its known answer's tolerances.
    _, problem_file, out = run
    argv = [str(problem_file), "--path", "reference", "--out", str(tmp_path), "--quiet"]
    assert cli.main(argv) == cli.EXIT_OK
    assert "(reference path)" in (tmp_path / "report.txt").read_text()
    fast, reference = load_design(out / "optimum.toml"), load_design(tmp_path / "optimum.toml")
    assert math.degrees(fast.machine.release_angle) == pytest.approx(
        math.degrees(reference.machine.release_angle), abs=ANGLE_TOLERANCE_DEG)
    assert simulate(fast).range == pytest.approx(simulate(reference).range, rel=RANGE_TOLERANCE)


@pytest.mark.parametrize("argv", [["missing.toml"], ["--robust", "-1"], ["--robust", "nan"]],
                         ids=["missing-file", "negative-sigma", "nan-sigma"])
def test_invalid_input_exits_2(tmp_path, argv, capsys):
    assert cli.main(argv + ["--out", str(tmp_path)]) == cli.EXIT_INVALID
    assert "invalid" in capsys.readouterr().err
