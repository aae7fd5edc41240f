"""The cross-check's ideal-release group: each model finds its own best release, and they agree."""

from __future__ import annotations

import functools

import pytest

from crosscheck.cases import default_suite, ideal_release_cases
from crosscheck.comparison import compare


@functools.cache
def _compared(name: str):
    return compare(next(case for case in ideal_release_cases() if case.name == name))


def test_the_ideal_release_group_covers_each_kind_and_is_in_the_default_suite():
    cases = ideal_release_cases()
    assert {case.group for case in cases} == {"ideal-release"}
    assert all(case.design.machine.release_rule == "ideal" for case in cases)
    assert {case.design.machine.kind for case in cases} == {"hinged", "fixed", "floating-arm"}
    assert {case.design.projectile.drag == "none" for case in cases} == {True, False}
    assert any(case.design.environment.wind_speed != 0.0 for case in cases)
    assert {case.name for case in cases} <= {case.name for case in default_suite(sample=0)}


@pytest.mark.slow
@pytest.mark.parametrize("case", ideal_release_cases(), ids=lambda c: c.name)
def test_models_agree_on_the_ideal_release(case):
    result = _compared(case.name)
    failing = [(r.quantity, r.analytic, r.engine, r.tolerance) for r in result.rows if not r.ok]
    assert result.agree, f"{case.name}: {result.error or failing}"
    assert {"range", "launch_angle"} <= {r.quantity for r in result.rows if r.ok}
