"""The engine against the analytic model: agreement at the default step, second-order convergence."""

from __future__ import annotations

import math

import pytest

from analytic.design_file import default_design
from analytic.reference import simulate as analytic_simulate
from support import with_environment, with_machine, with_projectile
from engine_model import DEFAULT_DT, simulate

#: The brief's agreement for release speed and range: 0.05 per cent. Measured on
#: the paper's design: 7e-6 and 1.1e-5 at the default step (engine's O(dt^2)
#: error; the analytic model's own is below 1e-7).
AGREEMENT = 5e-4
#: Halving the step should cut the error about fourfold (second order); this
#: band leaves room for the O(dt^3) terms at these steps.
CONVERGENCE_BAND = (3.0, 5.0)

CASES = {
    "table3-golf-ball": lambda d: d,
    "vacuum": lambda d: with_projectile(d, drag="none"),
    "smooth-sphere-headwind": lambda d: with_environment(with_projectile(d, drag="smooth-sphere"), wind_speed=-5.0),
    "constant-drag-tailwind": lambda d: with_environment(
        with_projectile(d, drag="constant", drag_coefficient=0.4), wind_speed=4.0),
    "point-counterweight": lambda d: with_machine(d, counterweight_inertia=0.0),
    "light-arm-with-ballast": lambda d: with_machine(d, arm_mass=0.05),
    "arm-centre-on-short-side": lambda d: with_machine(d, arm_cg=-0.1),
    "sling-rule": lambda d: with_machine(d, release_rule="sling", release_angle=math.radians(20.0)),
}


@pytest.fixture(scope="module")
def table3():
    return default_design()


@pytest.fixture(scope="module")
def reference(table3):
    return analytic_simulate(table3)


def _errors(shot, reference) -> tuple[float, float]:
    return (shot.release_speed / reference.release_speed - 1.0, shot.range / reference.range - 1.0)


@pytest.mark.parametrize("case", list(CASES))
def test_release_and_range_agree_with_the_analytic_model(table3, case):
    design = CASES[case](table3)
    expected = analytic_simulate(design)
    shot = simulate(design)
    assert expected.ok and shot.ok, (expected.message, shot.message)
    speed_error, range_error = _errors(shot, expected)
    assert abs(speed_error) < AGREEMENT, f"release speed {shot.release_speed} vs {expected.release_speed}"
    assert abs(range_error) < AGREEMENT, f"range {shot.range} vs {expected.range}"
    assert shot.launch_angle == pytest.approx(expected.launch_angle, abs=AGREEMENT)
    for name in ("liftoff_time", "release_time", "landing_time", "apex_height", "counterweight_energy_released"):
        assert getattr(shot, name) == pytest.approx(getattr(expected, name), rel=AGREEMENT), name


def test_error_falls_fourfold_when_the_step_is_halved(table3, reference):
    errors = {dt: _errors(simulate(table3, dt=dt), reference) for dt in (2 * DEFAULT_DT, DEFAULT_DT)}
    for which in range(2):  # release speed, range
        ratio = errors[2 * DEFAULT_DT][which] / errors[DEFAULT_DT][which]
        assert CONVERGENCE_BAND[0] < ratio < CONVERGENCE_BAND[1], (which, errors)
