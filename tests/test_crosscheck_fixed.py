"""The cross-check's fixed group: which machines it holds, that both models agree on them and on a fixed
machine's every failure, that a bolted counterweight modelled wrong is caught, and that ``--json`` names
every row's machine kind."""

from __future__ import annotations

import dataclasses
import functools
import json

import pytest

from analytic.design_file import save_design
from crosscheck.cases import FIXED_SAMPLE, Case, default_suite, fixed_cases, paper_cases
from crosscheck.cli import EXIT_AGREE, main
from crosscheck.comparison import compare, engine_simulate
from support import fixed_failure_designs

#: The group's rolling machine steps on through the whole flight (``engine_model.after_release``):
#: seconds, where the others take under one.
SLOW = {"paper-table3-fixed-rolling-10kg-all-losses"}


@functools.cache
def _compared(name: str):
    return compare(next(case for case in fixed_cases() if case.name == name))


def test_the_fixed_group_holds_the_paper_machine_samples_and_a_large_one_and_is_in_the_default_suite():
    cases = fixed_cases()
    assert {case.group for case in cases} == {"fixed"}
    assert {case.design.machine.kind for case in cases} == {"fixed"}
    by_name = {case.name: case.design for case in cases}
    paper = by_name["paper-table3-fixed"].machine
    # The paper's Table III machine (data/paper_table3.toml), its counterweight bolted: all else the same.
    hinged = paper_cases()[0].design.machine
    assert dataclasses.replace(paper, kind="hinged", counterweight_link=hinged.counterweight_link) == hinged
    assert len([name for name in by_name if name.startswith("sample-")]) >= FIXED_SAMPLE >= 3
    large = by_name["large-fixed"].machine
    assert large.arm_long + large.arm_short == pytest.approx(3.0) and large.counterweight_mass == 200.0
    assert {case.name for case in cases} <= {case.name for case in default_suite(sample=0)}


@pytest.mark.parametrize("case", [pytest.param(c, marks=pytest.mark.slow) if c.name in SLOW else c
                                  for c in fixed_cases()], ids=lambda c: c.name)
def test_models_agree_on_the_fixed_machines(case):
    result = _compared(case.name)
    failing = [(r.quantity, r.analytic, r.engine, r.tolerance) for r in result.rows if not r.ok]
    assert result.agree, f"{case.name}: {result.error or failing}"
    assert result.analytic_status == (case.expected or "ok") and result.kind == "fixed"


@pytest.mark.parametrize("status", list(fixed_failure_designs()), ids=lambda status: status.value)
def test_both_models_end_a_fixed_machine_in_each_failure_alike(status):
    # One fixed design per failure status (tests/support.py says how each was found).
    result = compare(Case(status.value, fixed_failure_designs()[status], "fixed"))
    assert result.agree, f"{status.value}: {result.error or [r for r in result.rows if not r.ok]}"
    assert result.analytic_status == result.engine_status == status.value


def test_a_bolted_counterweight_without_its_own_inertia_is_a_disagreement():
    # The mistake a fixed machine invites: the counterweight welded on as a point mass, its
    # inertia about its own centre (0.009345 kg m^2, 2.5 % of the machine's about the pivot) lost.
    def engine(design, dt):
        return engine_simulate(dataclasses.replace(
            design, machine=dataclasses.replace(design.machine, counterweight_inertia=0.0)), dt)

    case = next(case for case in fixed_cases() if case.name == "paper-table3-fixed")
    result = compare(case, engine=engine)
    assert not result.agree
    assert {"release_speed", "range", "release_time"} <= {r.quantity for r in result.rows if not r.ok}


def test_json_gives_every_design_and_every_row_its_machine_kind(tmp_path, capsys):
    paths = []
    for case in (paper_cases()[0], fixed_cases()[0]):
        paths.append(tmp_path / f"{case.name}.toml")
        save_design(case.design, paths[-1])
    assert main([*map(str, paths), "--json", "--workers", "1", "--no-progress"]) == EXIT_AGREE
    comparisons = json.loads(capsys.readouterr().out)["comparisons"]
    assert [c["kind"] for c in comparisons] == ["hinged", "fixed"]
    for comparison in comparisons:
        assert comparison["rows"] and {row["kind"] for row in comparison["rows"]} == {comparison["kind"]}


def test_a_comparison_the_engine_could_not_run_still_names_its_kind():
    from engine_model import EngineError

    def engine(design, dt):
        raise EngineError("refused")

    case = fixed_cases()[0]
    result = compare(Case(case.name, case.design, case.group), engine=engine)
    assert result.error and result.to_json()["kind"] == "fixed"
