"""Every tool takes every machine kind: the optimiser (a problem's ``[machine] kind``, ``--kind``),
a sweep, ``aim``, ``chart`` and calibration shoot a fixed machine as a fixed machine.

Each check compares a tool's answer with the fixed design shot on its own (``simulate_fast`` or
the reference path); a tool that lost the kind on the way would shoot a hinged machine with a
zero link, whose counterweight spins free of the arm, and land elsewhere (checked first).
"""

from __future__ import annotations

import dataclasses
import json
import math
import tomllib

import numpy as np
import pytest
from support import TABLE3_FIXED_FILE, with_machine

from analytic.aim import aim
from analytic.chart import chart, vary
from analytic.cli import main
from analytic.design import DesignError
from analytic.design_file import load_design
from analytic.design_space import (bolted, default_problem, design_at, problem_from_dict, sample_designs,
                                   variables_of, with_kind)
from analytic.fast import simulate_fast
from analytic.reference import simulate
from analytic.sweep import read_table, run_sweep, sweep_from_dict


@pytest.fixture(scope="module")
def fixed():
    return load_design(TABLE3_FIXED_FILE)


def _paper_problem_data() -> dict:
    from analytic.design_space import __file__ as here
    from pathlib import Path

    return tomllib.loads((Path(here).with_name("data") / "paper_problem.toml").read_text())


def test_a_fixed_machine_lands_elsewhere_than_a_hinged_one_with_no_link(fixed):
    # What every test below relies on to see a lost kind. (A hinged machine needs a link, so the
    # lost kind is mimicked with the shortest link a design file accepts.)
    hinged = with_machine(fixed, kind="hinged", counterweight_link=1e-9)
    assert abs(simulate_fast(hinged).range - simulate_fast(fixed).range) > 0.01


def test_a_problem_file_chooses_the_kind_and_the_link_drops_out():
    data = _paper_problem_data()
    del data["variables"]["counterweight_link"]
    problem = problem_from_dict({**data, "machine": {"kind": "fixed"}})
    assert problem.kind == "fixed" and problem.variables[1].lower == problem.variables[1].upper == 0.0
    designs = sample_designs(problem, 4, 3, str)
    assert {d.machine.kind for d in designs} == {"fixed"} and {d.machine.counterweight_link for d in designs} == {0.0}
    # The same problem through --kind: the paper's problem with the link fixed at 0.
    assert with_kind(default_problem(), "fixed") == dataclasses.replace(problem, name="paper")


@pytest.mark.parametrize("change, field, words", [
    ({"machine": {"kind": "fixed"}}, "variables.counterweight_link", "fixed machine has no link"),
    ({"machine": {"kind": "catapult"}}, "machine.kind", "must be one of hinged, fixed, floating-arm"),
    ({"machine": {"kind": "fixed", "arm": 1}}, "machine.arm", "unknown"),
])
def test_a_problem_file_refuses_a_link_on_a_rigid_counterweight_and_an_unknown_kind(change, field, words):
    with pytest.raises(DesignError) as refused:
        problem_from_dict({**_paper_problem_data(), **change})
    assert field in str(refused.value) and words in str(refused.value)


def test_bolting_keeps_the_frame_arms_and_sling():
    values = variables_of(load_design(TABLE3_FIXED_FILE.with_name("paper_table3.toml")).machine)
    hinged = design_at(default_problem(), values).machine
    fixed = design_at(with_kind(default_problem(), "fixed"), bolted(values)).machine
    for name in ("pivot_height", "arm_long", "arm_short", "sling_length", "release_angle"):
        assert getattr(fixed, name) == pytest.approx(getattr(hinged, name), rel=1e-15), name
    assert fixed.counterweight_link == 0.0 and fixed.kind == "fixed"


@pytest.mark.parametrize("kind", ["fixed", "floating-arm"])
def test_the_optimiser_searches_machines_of_a_kind_and_writes_its_optimum(tmp_path, capsys, kind):
    assert main(["optimise", "--kind", kind, "--out", str(tmp_path), "--quiet"]) == 0
    report = capsys.readouterr().out
    assert f"Machine: {kind}" in report and "mount load" in report and "hinge load" not in report
    optimum = load_design(tmp_path / "optimum.toml")
    assert optimum.machine.kind == kind
    # The optimum shot again on the reference path lands where the report says, and beyond the
    # paper's machine bolted, the search's own start among others.
    line = next(row for row in report.splitlines() if row.startswith("range (m)"))
    bolted_range, found = (float(v) for v in line.split()[2:])
    assert simulate(optimum, histories=False).range == pytest.approx(found, abs=0.005)
    assert found > bolted_range


def test_a_sweep_of_a_fixed_design_shoots_fixed_machines(tmp_path, fixed):
    sweep = sweep_from_dict({"design": str(TABLE3_FIXED_FILE), "grid": {
        "machine.sling_length": {"from": 0.45, "to": 0.61, "steps": 3},
        "machine.release_angle": {"from": 35.0, "to": 55.0, "steps": 2}}})
    run_sweep(sweep, tmp_path / "out")
    table = read_table(tmp_path / "out").to_pandas()
    for sling, angle, distance in zip(table["machine.sling_length"], table["machine.release_angle"],
                                      table["range"], strict=True):
        alone = simulate_fast(with_machine(fixed, sling_length=sling, release_angle=math.radians(angle)))
        assert distance == pytest.approx(alone.range, rel=1e-12)


def test_a_sweep_of_a_floating_arms_base_friction_shoots_each_friction(tmp_path):
    from analytic.design import Losses
    from support import TABLE3_FLOATING_FILE

    sweep = sweep_from_dict({"design": str(TABLE3_FLOATING_FILE), "grid": {
        "losses.base_friction": {"from": 0.0, "to": 0.6, "steps": 3}}})
    run_sweep(sweep, tmp_path / "out")
    table = read_table(tmp_path / "out").to_pandas()
    floating = load_design(TABLE3_FLOATING_FILE)
    distances = list(table["range"])
    for mu, distance in zip(table["losses.base_friction"], distances, strict=True):
        alone = simulate_fast(dataclasses.replace(floating, losses=Losses(base_friction=mu)))
        assert distance == pytest.approx(alone.range, rel=1e-12)
    assert len(set(distances)) == 3   # each friction throws its own range


def test_a_sweep_of_a_fixed_problem_shoots_fixed_machines(tmp_path):
    data = _paper_problem_data()
    del data["variables"]["counterweight_link"]
    data["variables"].update(arm_short={"value": 0.2}, clearance={"value": 0.3}, starting_angle={"value": 60.0},
                             release_angle={"value": 40.0})
    problem_file = tmp_path / "fixed-problem.toml"
    problem_file.write_text(_toml({**data, "machine": {"kind": "fixed"}}))
    sweep = sweep_from_dict({"problem": str(problem_file), "grid": {
        "machine.sling_length": {"from": 0.3, "to": 0.6, "steps": 3}}})
    run_sweep(sweep, tmp_path / "out")
    table = read_table(tmp_path / "out").to_pandas()
    from analytic.design_space import load_problem

    problem = load_problem(problem_file)
    for sling, distance in zip(table["machine.sling_length"], table["range"], strict=True):
        values = np.array([0.2, 0.0, 0.3, sling, math.radians(60.0), math.radians(40.0)])
        assert distance == pytest.approx(simulate_fast(design_at(problem, values)).range, rel=1e-12)


def test_aim_finds_a_fixed_machines_release_angle(fixed):
    target = 0.9 * simulate_fast(fixed).range
    found = aim(fixed, "machine.release_angle", target)
    assert found.solutions
    for solution in found.solutions:
        aimed = with_machine(fixed, release_angle=math.radians(solution.value))
        assert aimed.machine.kind == "fixed"
        assert simulate(aimed, histories=False).range == pytest.approx(target, abs=0.01)


def test_chart_shoots_a_fixed_machine_and_names_its_mount(fixed):
    result = chart(fixed, [vary("machine.sling_length", 0.4, 0.6, 3)])
    for (sling,), distance in zip(result.settings, result.range, strict=True):
        assert distance == pytest.approx(simulate_fast(with_machine(fixed, sling_length=sling)).range, rel=1e-12)


def _toml(data: dict) -> str:
    """A problem file's text from its tables (numbers, texts and inline tables of numbers)."""
    lines = []

    def value(v):
        if isinstance(v, dict):
            return "{ " + ", ".join(f"{k} = {value(x)}" for k, x in v.items()) + " }"
        return json.dumps(v)

    for key, v in data.items():
        if not isinstance(v, dict):
            lines.append(f"{key} = {value(v)}")
    for key, table in data.items():
        if isinstance(table, dict):
            lines.append(f"[{key}]")
            lines += [f"{k} = {value(v)}" for k, v in table.items()]
    return "\n".join(lines) + "\n"
