"""The cross-check's floating-friction group: floating arms with friction on their guide and track, in
the default suite; both models agree on them within the named tolerances, and an engine that left out
a slide's friction is caught."""

from __future__ import annotations

import dataclasses
import functools

import pytest

from analytic.design import Losses
from crosscheck.cases import default_suite, floating_friction_cases
from crosscheck.comparison import compare, engine_simulate

#: The group's slower designs (the large machine's long swing).
SLOW = {"large-floating-arm-all-losses"}


@functools.cache
def _compared(name: str):
    return compare(next(case for case in floating_friction_cases() if case.name == name))


def test_the_group_has_each_slide_alone_and_together_and_is_in_the_default_suite():
    cases = floating_friction_cases()
    assert {case.group for case in cases} == {"floating-friction"}
    assert {case.design.machine.kind for case in cases} == {"floating-arm"}
    losses = {case.name: case.design.losses for case in cases}
    guide_only = [n for n, l in losses.items() if l.guide_friction > 0.0 and l.track_friction == 0.0]
    track_only = [n for n, l in losses.items() if l.track_friction > 0.0 and l.guide_friction == 0.0]
    with_axle = [n for n, l in losses.items() if l.guide_friction * l.track_friction * l.axle_friction > 0.0]
    assert guide_only and track_only and len(with_axle) >= 3
    assert any(l.guide_static_friction and l.track_static_friction for l in losses.values())
    assert [case.expected for case in cases if case.expected] == ["never_fires"]
    assert {case.name for case in cases} <= {case.name for case in default_suite(sample=0)}


@pytest.mark.parametrize("case", [pytest.param(c, marks=pytest.mark.slow) if c.name in SLOW else c
                                  for c in floating_friction_cases()], ids=lambda c: c.name)
def test_models_agree_on_floating_arms_with_friction_on_their_slides(case):
    result = _compared(case.name)
    failing = [(r.quantity, r.analytic, r.engine, r.tolerance) for r in result.rows if not r.ok]
    assert result.agree, f"{case.name}: {result.error or failing}"
    assert result.analytic_status == (case.expected or "ok") and result.kind == "floating-arm"


@pytest.mark.parametrize("slide", ["guide", "track"])
def test_an_engine_without_a_slides_friction_is_caught(slide):
    case = next(case for case in floating_friction_cases() if case.name == "table3-floating-arm-slide-friction")

    def without(design, dt):
        losses = dataclasses.replace(design.losses, **{f"{slide}_friction": 0.0})
        return engine_simulate(dataclasses.replace(design, losses=losses), dt)

    result = compare(case, engine=without)
    assert not result.agree
    assert {"range", "release_speed"} <= {r.quantity for r in result.rows if not r.ok}
    assert any(r.quantity.endswith(slide) and not r.ok for r in result.rows), [r.quantity for r in result.rows]


def test_the_held_machine_is_held_by_its_track_alone():
    """Below the coefficient that holds it the same machine fires (the case is a hold, not a machine
    that could never fire)."""
    case = next(case for case in floating_friction_cases() if case.expected == "never_fires")
    weaker = dataclasses.replace(case.design, losses=Losses(track_friction=0.5))
    assert engine_simulate(weaker, 5e-5).status.value == "ok"
