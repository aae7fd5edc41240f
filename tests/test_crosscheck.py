"""The cross-check: the models agree on a fast subset, the suite can fail, the CLI reports."""

from __future__ import annotations

import ast
import dataclasses
import json
from pathlib import Path

import pytest

from analytic.design_file import save_design
from analytic import outcome
from analytic.result import Shot, Status
from conftest import with_machine
from crosscheck import tolerances
from crosscheck.cases import exercise_cases, failure_cases, paper_cases, sample_cases
from crosscheck.cli import EXIT_AGREE, EXIT_DISAGREE, main
from crosscheck.compare import compare, engine_simulate, step_study
from engine_model import EngineError

FAST = {"table3", "sling-rule", "constant-drag", "fails-never_fires", "fails-never_lifts_off"}


def _fast_cases():
    return [c for c in paper_cases() + exercise_cases() + failure_cases() if c.name in FAST]


@pytest.mark.parametrize("case", _fast_cases(), ids=lambda c: c.name)
def test_models_agree_on_the_fast_subset(case):
    result = compare(case)
    failing = [(r.quantity, r.analytic, r.engine, r.tolerance) for r in result.rows if not r.ok]
    assert result.agree, f"{case.name}: {result.error or failing}"
    assert result.rows[0].quantity == "outcome"


def test_the_reference_path_can_stand_in_for_the_fast_one():
    from analytic.reference import simulate

    case = paper_cases()[0]
    reference, default = compare(case, analytic=simulate), compare(case)
    assert reference.agree and default.agree
    for a, b in zip(reference.rows, default.rows, strict=True):
        assert a.quantity == b.quantity and a.engine == b.engine
        if isinstance(a.analytic, float):   # the paths agree far inside the cross-check's tolerances
            assert a.analytic == pytest.approx(b.analytic, rel=1e-9, abs=1e-12)


def test_an_engine_that_cannot_be_trusted_is_a_disagreement_with_its_message():
    steps = []

    def untrusted(design, dt):
        steps.append(dt)
        raise EngineError(f"joints apart at dt = {dt:g} s")

    table3 = paper_cases()[0]
    result = compare(table3, dt=1e-4, engine=untrusted, analytic_shot=Shot(table3.design, Status.OK, "thrown"))
    assert steps == [1e-4, 5e-5, 2.5e-5]  # halved MAX_STEP_HALVINGS times, then given up
    assert not result.agree and result.engine_status == "error" and result.engine_dt == 2.5e-5
    assert result.error == "EngineError: joints apart at dt = 2.5e-05 s"


def test_a_design_the_engine_cannot_model_exits_1_with_the_reason(tmp_path, capsys):
    path = tmp_path / "lever.toml"  # the analytic model throws it; a pymunk body needs inertia
    save_design(with_machine(paper_cases()[0].design, arm_inertia=0.0, arm_cg=0.0), path)
    assert main([str(path), "--json", "--workers", "1", "--no-progress"]) == EXIT_DISAGREE
    comparison = json.loads(capsys.readouterr().out)["comparisons"][0]
    assert comparison["engine_status"] == "error" and "massless lever" in comparison["error"]


def test_a_flight_that_never_lands_is_compared_like_any_outcome():
    # A flight past its bound used to raise in the engine, uncaught, ending the
    # whole cross-check (this design even came out "thrown": its explicit drag
    # overshot in one step). The analytic side stands in with its verdict on
    # this design (no_landing within 64.9 s: tests/test_analytic_failures.py).
    case = next(c for c in failure_cases() if c.expected == Status.NO_LANDING.value)
    verdict = Shot(case.design, Status.NO_LANDING, outcome.no_landing_message(64.9))
    result = compare(case, analytic_shot=verdict)
    assert result.agree, result.error or result.rows
    assert (result.analytic_status, result.engine_status) == ("no_landing", "no_landing")


@pytest.mark.parametrize("mistake", [
    lambda m: {"counterweight_inertia": 3.0 * m.counterweight_inertia},
    lambda m: {"arm_inertia": 1.1 * m.arm_inertia},
], ids=["counterweight-inertia-x3", "arm-inertia-+10pc"])
def test_a_perturbed_model_is_reported_as_disagreement(mistake):
    table3 = paper_cases()[0]
    result = compare(table3, engine=_engine_with_changes(mistake))
    assert not result.agree
    assert {r.quantity for r in result.rows if not r.ok} & {"release_speed", "range", "release_time"}


def _engine_with_changes(mistake):
    """An engine handed a subtly wrong machine: what a modelling bug looks like."""
    def engine(design, dt):
        wrong = dataclasses.replace(design, machine=dataclasses.replace(design.machine, **mistake(design.machine)))
        return engine_simulate(wrong, dt)
    return engine


def test_every_tolerance_states_its_reason():
    source = Path(tolerances.__file__).read_text()
    lines = source.splitlines()
    for node in ast.parse(source).body:
        if isinstance(node, ast.Assign) and node.targets[0].id.isupper():
            assert lines[node.lineno - 2].startswith("#:") or lines[node.lineno - 3].startswith("#:"), \
                f"{node.targets[0].id} has no reason"


def test_sample_is_seeded_and_covers_both_arms():
    first, again = sample_cases(6, seed=3), sample_cases(6, seed=3)
    assert [c.design for c in first] == [c.design for c in again]
    assert {c.name.rsplit("-", 1)[1] for c in first} == {"wooden", "light"}
    assert [c.design for c in sample_cases(6, seed=4)] != [c.design for c in first]


def test_cli_on_a_user_file_prints_json_and_exit_code(tmp_path, capsys):
    path = tmp_path / "mine.toml"
    save_design(dataclasses.replace(paper_cases()[1].design, name="mine"), path)
    assert main([str(path), "--json", "--workers", "1", "--no-progress"]) == EXIT_AGREE
    out = json.loads(capsys.readouterr().out)
    assert out["agree"] and out["comparisons"][0]["case"] == "mine"


@pytest.mark.slow
def test_engine_converges_with_order_two():
    # Symplectic Euler with error_bias = 0 is second-order in positions at events
    # (measured: ~4x per halving); a fit over 4 steps must show it.
    study = step_study(paper_cases()[0].design)
    assert 1.8 < study.speed_order < 2.2 and 1.8 < study.range_order < 2.2


@pytest.mark.slow
def test_full_default_suite_agrees(tmp_path, capsys):
    code = main(["--report", str(tmp_path), "--no-progress"])
    report = json.loads((tmp_path / "crosscheck.json").read_text())
    failing = [c["case"] for c in report["comparisons"] if not c["agree"]]
    assert code == EXIT_AGREE, f"disagreeing designs: {failing}"
    assert {p.name for p in tmp_path.iterdir()} == {"crosscheck.json", "table.txt", "agreement.png", "errors.png",
                                                    "convergence.png"}
    # The terminal gets the verdict and the worst case per quantity; every design's rows go to table.txt.
    printed = capsys.readouterr().out.splitlines()
    assert len(printed) < 20 and printed[0].startswith(f"{len(report['comparisons'])} of ")
    assert len((tmp_path / "table.txt").read_text().splitlines()) > 10 * len(report["comparisons"])


@pytest.mark.slow   # --report runs the engine's step study
def test_the_full_table_is_printed_only_when_asked(tmp_path, capsys, table3):
    path = tmp_path / "t3.toml"
    save_design(table3, path)
    assert main([str(path), "--workers", "1", "--no-progress", "--report", str(tmp_path / "r")]) == EXIT_AGREE
    short = capsys.readouterr().out
    assert "tolerance" in short and "verdict" not in short
    assert short.splitlines()[-1].startswith(f"report in {tmp_path / 'r'}: crosscheck.json, table.txt")
    assert "verdict" in (tmp_path / "r" / "table.txt").read_text()
    assert main([str(path), "--workers", "1", "--no-progress", "--table"]) == EXIT_AGREE
    assert capsys.readouterr().out.startswith("design ")
