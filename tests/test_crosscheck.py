"""The cross-check: the models agree on a fast subset, the suite can fail, the CLI reports."""

from __future__ import annotations

import ast
import dataclasses
import json
from pathlib import Path

import pytest

from analytic.design_file import save_design
from crosscheck import tolerances
from crosscheck.cases import exercise_cases, failure_cases, paper_cases, sample_cases
from crosscheck.cli import EXIT_AGREE, main
from crosscheck.compare import compare, engine_simulate, step_study

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
    from analytic.simulate import simulate

    case = paper_cases()[0]
    reference, default = compare(case, analytic=simulate), compare(case)
    assert reference.agree and default.agree
    for a, b in zip(reference.rows, default.rows, strict=True):
        assert a.quantity == b.quantity and a.engine == b.engine
        if isinstance(a.analytic, float):   # the paths agree far inside the cross-check's tolerances
            assert a.analytic == pytest.approx(b.analytic, rel=1e-9, abs=1e-12)


def test_an_analytic_failure_from_the_batch_is_raised_not_hidden():
    from analytic.integrate import IntegrationError

    with pytest.raises(IntegrationError, match="step size"):
        compare(paper_cases()[0], analytic_shot=IntegrationError("the step size fell below the resolution"))


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
    # (issue 3's measurement: ~4x per halving); a fit over 4 steps must show it.
    study = step_study(paper_cases()[0].design)
    assert 1.8 < study.speed_order < 2.2 and 1.8 < study.range_order < 2.2


@pytest.mark.slow
def test_full_default_suite_agrees(tmp_path):
    code = main(["--report", str(tmp_path), "--no-progress"])
    report = json.loads((tmp_path / "crosscheck.json").read_text())
    failing = [c["case"] for c in report["comparisons"] if not c["agree"]]
    assert code == EXIT_AGREE, f"disagreeing designs: {failing}"
    assert {p.name for p in tmp_path.iterdir()} == {"crosscheck.json", "agreement.png", "errors.png", "convergence.png"}


def test_benchmark_reports_ratios_to_its_baseline(capsys):
    from crosscheck.benchmark import main as benchmark_main

    assert benchmark_main(["--repeat", "1"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert "1.0000 x baseline" in lines[1] and len(lines) == 7
    assert any("fast path" in line for line in lines)
