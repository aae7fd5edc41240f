"""The cross-check's sling-mass group: a sling with mass, a pouch and both on each kind, with every loss,
the drag during the swing and a rolling frame, in the default suite; both models agree on them within
the named tolerances, and an engine that ignored the sling's and the pouch's mass is caught."""

from __future__ import annotations

import dataclasses
import functools

import pytest

from crosscheck.cases import default_suite, sling_mass_cases
from crosscheck.comparison import compare, engine_simulate

#: The group's slower design (a rolling frame's engine steps on through the whole flight).
SLOW = {"table3-sling-and-pouch-rolling-10kg"}


@functools.cache
def _compared(name: str):
    return compare(next(case for case in sling_mass_cases() if case.name == name))


def test_the_group_weighs_the_sling_and_the_pouch_on_each_kind_and_is_in_the_default_suite():
    cases = sling_mass_cases()
    assert {case.group for case in cases} == {"sling-mass"}
    for kind in ("hinged", "fixed", "floating-arm"):
        machines = [case.design.machine for case in cases if case.design.machine.kind == kind]
        assert any(m.sling_mass > 0.0 and m.pouch_mass == 0.0 for m in machines)
        assert any(m.pouch_mass > 0.0 and m.sling_mass == 0.0 for m in machines)
        assert any(m.sling_mass > 0.0 and m.pouch_mass > 0.0 for m in machines)
    assert any(case.design.base.rolling for case in cases)
    assert any(case.design.projectile.drag_during_swing for case in cases)
    assert {case.name for case in cases} <= {case.name for case in default_suite(sample=0)}


@pytest.mark.parametrize("case", [pytest.param(c, marks=pytest.mark.slow) if c.name in SLOW else c
                                  for c in sling_mass_cases()], ids=lambda c: c.name)
def test_models_agree_on_a_sling_and_a_pouch_with_mass(case):
    result = _compared(case.name)
    failing = [(r.quantity, r.analytic, r.engine, r.tolerance) for r in result.rows if not r.ok]
    assert result.agree, f"{case.name}: {result.error or failing}"
    assert result.analytic_status == "ok" and result.kind == case.design.machine.kind


def test_an_engine_that_ignored_the_slings_and_the_pouchs_mass_is_caught():
    case = next(case for case in sling_mass_cases() if case.name == "table3-sling-and-pouch")

    def massless(design, dt):
        machine = dataclasses.replace(design.machine, sling_mass=0.0, pouch_mass=0.0)
        return engine_simulate(dataclasses.replace(design, machine=machine), dt)

    result = compare(case, engine=massless)
    assert not result.agree
    assert {"release_speed", "range"} <= {r.quantity for r in result.rows if not r.ok}
