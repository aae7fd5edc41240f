"""The cross-check's swing-drag group: the drag acting in stages 1-2 in both models, their agreement,
and that an engine leaving the drag out of the swing is caught."""

from __future__ import annotations

import dataclasses
import functools

import pytest

from crosscheck.cases import Case, default_suite, swing_drag_cases
from crosscheck.comparison import compare, engine_simulate

#: The group's slower designs (the large machine's long swing; every loss's friction joints): run as slow.
SLOW = {"large-swing-drag", "swing-drag-all-losses"}


@functools.cache
def _compared(name: str):
    return compare(next(case for case in swing_drag_cases() if case.name == name))


def test_the_swing_drag_group_is_in_the_default_suite_with_the_flag_on():
    cases = swing_drag_cases()
    assert {case.group for case in cases} == {"swing-drag"}
    assert all(case.design.projectile.drag_during_swing for case in cases)
    assert {case.design.machine.kind for case in cases} == {"hinged", "fixed", "floating-arm"}
    assert {case.name for case in cases} <= {case.name for case in default_suite(sample=0)}


@pytest.mark.parametrize("case", [pytest.param(c, marks=pytest.mark.slow) if c.name in SLOW else c
                                  for c in swing_drag_cases()], ids=lambda c: c.name)
def test_models_agree_with_the_drag_in_the_swing(case):
    result = _compared(case.name)
    failing = [(r.quantity, r.analytic, r.engine, r.tolerance) for r in result.rows if not r.ok]
    assert result.agree, f"{case.name}: {result.error or failing}"
    swing_drag = next(r for r in result.rows if r.quantity == "dissipated_swing_drag")
    assert swing_drag.analytic != 0.0 and swing_drag.ok


def test_an_engine_without_the_drag_in_the_swing_is_caught():
    case = next(case for case in swing_drag_cases() if case.name == "swing-drag-tailwind")

    def without(design, dt):
        return engine_simulate(dataclasses.replace(
            design, projectile=dataclasses.replace(design.projectile, drag_during_swing=False)), dt)

    result = compare(case, engine=without)
    assert not result.agree
    assert {"dissipated_swing_drag"} < {r.quantity for r in result.rows if not r.ok}
