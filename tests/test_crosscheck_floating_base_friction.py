"""The cross-check's floating-base-friction group: floating arms whose projectile slides on the base with
friction, alone and with their slides' and axle's, in the default suite; both models agree on them within
the named tolerances, and an engine that left out the base's friction is caught."""

from __future__ import annotations

import dataclasses
import functools

import pytest

from analytic import friction
from analytic.design_file import default_design
from analytic.parameters import params
from crosscheck.cases import default_suite, floating_base_friction_cases
from crosscheck.comparison import compare, engine_simulate


@functools.cache
def _compared(name: str):
    return compare(next(case for case in floating_base_friction_cases() if case.name == name))


def test_the_group_has_the_base_alone_with_the_slides_static_and_held_and_is_in_the_default_suite():
    cases = floating_base_friction_cases()
    assert {case.group for case in cases} == {"floating-base-friction"}
    assert {case.design.machine.kind for case in cases} == {"floating-arm"}
    losses = {case.name: case.design.losses for case in cases}
    assert all(l.base_friction > 0.0 for l in losses.values())
    alone = [n for n, l in losses.items() if l.guide_friction == l.track_friction == l.axle_friction == 0.0]
    with_slides = [n for n, l in losses.items() if l.guide_friction * l.track_friction > 0.0]
    assert alone and len(with_slides) >= 3
    assert any(l.base_static_friction and l.guide_static_friction for l in losses.values())
    assert [case.expected for case in cases if case.expected] == ["never_fires"]
    assert {case.name for case in cases} <= {case.name for case in default_suite(sample=0)}


@pytest.mark.parametrize("case", floating_base_friction_cases(), ids=lambda c: c.name)
def test_models_agree_on_floating_arms_with_the_bases_friction(case):
    result = _compared(case.name)
    failing = [(r.quantity, r.analytic, r.engine, r.tolerance) for r in result.rows if not r.ok]
    assert result.agree, f"{case.name}: {result.error or failing}"
    assert result.analytic_status == (case.expected or "ok") and result.kind == "floating-arm"
    if not case.expected:
        base = next(r for r in result.rows if r.quantity == "dissipated_base")
        assert base.analytic > 0.0


def test_an_engine_without_the_bases_friction_is_caught():
    case = next(case for case in floating_base_friction_cases() if case.name.endswith("-base-friction"))

    def without(design, dt):
        return engine_simulate(dataclasses.replace(design, losses=dataclasses.replace(design.losses,
                                                                                      base_friction=0.0)), dt)

    result = compare(case, engine=without)
    assert not result.agree
    assert "dissipated_base" in {r.quantity for r in result.rows if not r.ok}


def test_the_held_machine_is_held_by_its_bases_static_friction():
    """At rest the base's static friction holds the arm through the flat sling (``rest_balance``: the
    base's hold above gravity's drive), its kinetic friction would not, and without the stone's weight
    on the base (the design's own golf ball) the same friction lets it fire, in the engine."""
    case = next(case for case in floating_base_friction_cases() if case.expected == "never_fires")
    drive, slides, base = friction.rest_balance(params(case.design))
    kinetic = friction.rest_balance(params(dataclasses.replace(
        case.design, losses=dataclasses.replace(case.design.losses, base_static_friction=None))))[2]
    assert slides == 0.0 and kinetic < drive < base
    light = dataclasses.replace(case.design, projectile=default_design().projectile)
    assert engine_simulate(light, 5e-5).status.value == "ok"
