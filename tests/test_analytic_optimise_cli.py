"""``python -m analytic optimise``: outputs written and readable on either path, invalid input refused with exit code 2."""

from __future__ import annotations

import math
from pathlib import Path

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


ROOT_FOLDER = Path(__file__).resolve().parents[1]
WARWOLF = ROOT_FOLDER / "workbench" / "presets" / "warwolf.toml"


def test_around_a_design_writes_that_design_improved_in_its_optimised_fields_only(tmp_path, capsys):
    from analytic.fast import simulate_fast
    from analytic.optimise.around import OPTIMISED_FIELDS

    argv = ["--around", str(WARWOLF), "--generations", "1", "--quiet", "--units", "imperial",
            "--max-axle-load", "200000 lbf", "--bound", "sling_length", "25", "40", "--out", str(tmp_path)]
    assert cli.main(argv) == cli.EXIT_OK
    report = capsys.readouterr().out
    assert "around-warwolf-scale" in report and "peak loads at most axle load 200000 lbf" in report
    start, found = load_design(WARWOLF), load_design(tmp_path / "optimum.toml")
    for name, value in vars(start.machine).items():
        if name not in OPTIMISED_FIELDS:
            assert getattr(found.machine, name) == value, name
    assert (found.projectile, found.losses, found.base) == (start.projectile, start.losses, start.base)
    # --bound in the --units: 25 to 40 ft (7.62 to 12.192 m)
    assert 7.62 <= found.machine.sling_length <= 12.192
    shot = simulate_fast(found, loads=True)
    # the axle-load limit is met to SLSQP's relative margin on outcome limits (search.OUTCOME_FEASIBILITY)
    assert shot.peak_axle_load <= 200000 * 4.4482216152605 * (1 + 1e-4)   # the pound-force: 4.4482216152605 N, exact


@pytest.mark.parametrize("argv", [["--bound", "arm", "1", "2"], ["--bound", "sling_length", "2", "1"],
                                  ["--factor", "0.5"], ["--kind", "fixed"], ["--max-height", "tall"]],
                         ids=["unknown-variable", "reversed-bounds", "factor-below-one", "other-kind", "no-number"])
def test_invalid_around_options_exit_2(tmp_path, argv, capsys):
    assert cli.main(["--around", str(WARWOLF), *argv, "--out", str(tmp_path), "--quiet"]) == cli.EXIT_INVALID
    assert "invalid" in capsys.readouterr().err
