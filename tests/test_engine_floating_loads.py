"""A floating arm's peak loads in the engine against the analytic model's, within the cross-check's
tolerances: on the designs of the cross-check's seeded suites whose peaks the engine once took from its
solver's ringing (``engine_model.floating.resolves``), and on a sample of floating arms, ideal and with
every loss. The analytic side is the reference path's, simulated in the same run."""

from __future__ import annotations

import dataclasses

import pytest

from analytic import simulate as analytic_simulate
from crosscheck.cases import FLOATING_LOSSES, floating_cases, floating_design, floating_friction_cases, sample_cases
from crosscheck.tolerances import ARM_BENDING_MOMENT_REL, PEAK_LOAD_REL
from engine_model import DEFAULT_DT, floating
from engine_model import simulate as engine_simulate

#: The peaks compared, each with the cross-check's relative tolerance (``crosscheck.tolerances``).
PEAKS = {"peak_axle_load": PEAK_LOAD_REL, "peak_hinge_load": PEAK_LOAD_REL,
         "peak_arm_bending_moment": ARM_BENDING_MOMENT_REL}

#: Floating arms of the cross-check's seeded suites (``python -m crosscheck --sample 60 --seed S``:
#: the floating-arm and floating-friction groups of ``default_suite(60, S)``), by their suite's seed,
#: whose peaks disagreed with the analytic model's before the engine solved its second whole step
#: and its friction's changes of mode with ``floating.STARTUP_ITERATIONS`` and stopped every friction
#: limit's line at any joint's change (``friction.steady``). In each comment, ``crosscheck.comparison.
#: compare``'s axle, hinge and bending-moment rows as multiples of their tolerances, before -> after
#: (measured 2026-11-29).
RINGING = {
    "sample-8-004-wooden-floating-arm": 8,             # 24.6, 24.8, 0.0 -> 0.0, 0.0, 0.0
    "sample-7-004-wooden-floating-arm": 7,             # 8.0, 9.3, 0.0 -> 0.0, 0.0, 0.0
    "sample-8-000-wooden-floating-arm-all-losses": 8,  # 8.7, 7.5, 0.01 -> 0.11, 0.03, 0.02
    "sample-1-000-wooden-floating-arm-all-losses": 1,  # 5.4, 4.7, 1.8 -> 0.12, 0.08, 0.0
    "sample-4-000-wooden-floating-arm-all-losses": 4,  # 3.4, 2.6, 0.0 -> 0.21, 0.26, 0.0
    "sample-7-000-wooden-floating-arm-all-losses": 7,  # 0.0, 0.0, 7.7 -> 0.0, 0.0, 0.0
}

#: The sample's seed, neither the default suite's (0) nor one of ``RINGING``'s, and its number of
#: wooden-armed designs (taken as ``crosscheck.cases.floating_cases`` takes them): 6 of the 8 throw;
#: before the change above 5 of those 6 disagreed with ``FLOATING_LOSSES``, by 2.0x to 11.9x their
#: tolerance, and all 6 agreed without losses.
SAMPLE_SEED = 21
SAMPLE_SIZE = 8


def ringing_case(name: str):
    seed = RINGING[name]
    return next(case for case in floating_cases(seed=seed) + floating_friction_cases(seed=seed)
                if case.name == name)


def sampled_designs():
    wooden = [case for case in sample_cases(2 * SAMPLE_SIZE, SAMPLE_SEED) if "light" not in case.name][:SAMPLE_SIZE]
    for case in wooden:
        design = floating_design(case.design, f"{case.name}-floating-arm")
        yield design
        yield dataclasses.replace(design, name=f"{design.name}-all-losses", losses=FLOATING_LOSSES)


SAMPLED = {design.name: design for design in sampled_designs()}


def assert_peaks_agree(design):
    analytic, engine = analytic_simulate(design), engine_simulate(design, dt=DEFAULT_DT)
    assert engine.status is analytic.status, (engine.status, engine.message, analytic.message)
    if not analytic.ok:
        return
    off = {name: (getattr(engine, name), getattr(analytic, name)) for name, rel in PEAKS.items()
           if abs(getattr(engine, name) - getattr(analytic, name)) > rel * abs(getattr(analytic, name))}
    assert not off, f"{design.name}: (engine, analytic) {off}"


@pytest.mark.parametrize("name", RINGING)
def test_peak_loads_where_the_solver_rang(name):
    case = ringing_case(name)
    assert case.design.machine.kind == "floating-arm"
    assert_peaks_agree(case.design)


@pytest.mark.slow
@pytest.mark.parametrize("name", SAMPLED)
def test_peak_loads_on_a_sample_of_floating_arms(name):
    assert_peaks_agree(SAMPLED[name])


def test_the_steps_solved_afresh():
    """The second whole step, and a step whose friction modes differ from the step before's."""
    slipping, held = (True,) * 5, (False,) * 5
    turned = (True, False, False, True, True)
    assert floating.resolves(1, [])
    assert not any(floating.resolves(k, []) for k in (0, 2, 3, 100))
    assert floating.resolves(7, [slipping, slipping, turned])
    assert floating.resolves(8, [slipping, turned, slipping])
    assert not floating.resolves(9, [turned, slipping, slipping])
    assert not floating.resolves(9, [held, held])
