"""The cross-check's trough group: the projectile on a raised trough on each kind, with the base's
friction (on the trough) and on a rolling frame, in the default suite; both models agree on them
within the named tolerances, and an engine that left the projectile on the base is caught."""

from __future__ import annotations

import dataclasses
import functools

import pytest

from analytic.design import Base
from crosscheck.cases import default_suite, trough_cases
from crosscheck.comparison import compare, engine_simulate

#: The group's slower designs (a rolling frame's engine steps on through the whole flight).
SLOW = {"paper-table3-trough-rolling-10kg-all-losses", "paper-table3-fixed-trough-rolling-10kg-all-losses"}


@functools.cache
def _compared(name: str):
    return compare(next(case for case in trough_cases() if case.name == name))


def test_the_group_has_each_kind_with_friction_and_rolling_and_is_in_the_default_suite():
    cases = trough_cases()
    assert {case.group for case in cases} == {"trough"}
    assert all(0.0 < case.design.base.trough_height < case.design.machine.pivot_height for case in cases)
    kinds = {case.design.machine.kind for case in cases}
    assert kinds == {"hinged", "fixed", "floating-arm"}
    for kind in kinds:
        designs = [case.design for case in cases if case.design.machine.kind == kind]
        assert any(d.losses.axle_friction > 0.0 for d in designs)
        if kind != "floating-arm":   # (a rolling frame is refused on a floating arm; its base friction: its own group)
            assert any(d.losses.base_friction > 0.0 for d in designs)
            assert any(d.base.rolling and d.losses.base_friction > 0.0 for d in designs)
    assert {case.name for case in cases} <= {case.name for case in default_suite(sample=0)}


@pytest.mark.parametrize("case", [pytest.param(c, marks=pytest.mark.slow) if c.name in SLOW else c
                                  for c in trough_cases()], ids=lambda c: c.name)
def test_models_agree_on_a_raised_trough(case):
    result = _compared(case.name)
    failing = [(r.quantity, r.analytic, r.engine, r.tolerance) for r in result.rows if not r.ok]
    assert result.agree, f"{case.name}: {result.error or failing}"
    assert result.analytic_status == "ok" and result.kind == case.design.machine.kind


def test_an_engine_that_left_the_projectile_on_the_base_is_caught():
    case = next(case for case in trough_cases() if case.name == "paper-table3-trough")

    def on_the_base(design, dt):
        return engine_simulate(dataclasses.replace(design, base=Base()), dt)

    result = compare(case, engine=on_the_base)
    assert not result.agree
    assert {"liftoff_time", "release_speed", "range"} <= {r.quantity for r in result.rows if not r.ok}
