"""The cross-check's target group: a raised target, a pit and an unreachable target on each kind of
machine in both models, their agreement, and that an engine landing at the base is caught."""

from __future__ import annotations

import dataclasses

import pytest

from crosscheck.cases import default_suite, target_cases
from crosscheck.comparison import compare, engine_simulate


def test_the_target_group_is_in_the_default_suite_on_every_kind():
    cases = target_cases()
    assert {case.group for case in cases} == {"target"}
    heights = {case.design.environment.target_height for case in cases}
    assert min(heights) < 0.0 < max(heights)
    for kind in ("hinged", "fixed", "floating-arm"):
        mine = [case for case in cases if case.design.machine.kind == kind]
        assert {case.expected for case in mine} == {None, "short_of_target"}, kind
        assert any(case.design.environment.target_height < 0.0 for case in mine), kind
    assert {case.name for case in cases} <= {case.name for case in default_suite(sample=0)}


@pytest.mark.parametrize("case", target_cases(), ids=lambda c: c.name)
def test_models_agree_at_the_target(case):
    result = compare(case)
    assert result.analytic_status == result.engine_status == (case.expected or "ok")
    assert result.agree, [(r.quantity, r.analytic, r.engine, r.tolerance) for r in result.rows if not r.ok]
    quantities = {r.quantity for r in result.rows}
    assert "apex_height" in quantities   # a short shot compares how far short it is
    assert ("range" in quantities) == (case.expected is None)


def test_an_engine_that_lands_at_the_base_is_caught():
    case = next(case for case in target_cases() if case.name.endswith("table3-raised-target"))

    def at_the_base(design, dt):
        return engine_simulate(dataclasses.replace(
            design, environment=dataclasses.replace(design.environment, target_height=0.0)), dt)

    result = compare(case, engine=at_the_base)
    assert not result.agree
    assert "range" in {r.quantity for r in result.rows if not r.ok}
