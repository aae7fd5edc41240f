"""The engine against the analytic model: within the cross-check's tolerances, second-order convergence."""

from __future__ import annotations

import pytest

from analytic.design_file import default_design
from analytic.reference import simulate as analytic_simulate
from crosscheck import tolerances as tol
from engine_model import DEFAULT_DT, simulate
from support import table3_variants

#: The counterweight's energy released by release goes as the release speed
#: squared, so its budget is twice the speed's.
ENERGY_RELEASED_REL = 2.0 * tol.RELEASE_SPEED_REL
#: Halving the step should cut the error about fourfold (second order); this
#: band leaves room for the O(dt^3) terms at these steps.
CONVERGENCE_BAND = (3.0, 5.0)

#: Variants of Table III that the engine builds differently (no drag, wind in
#: either drag, a point counterweight on a distance joint, a light arm with
#: ballast, an arm centre on the short side, the sling rule). Measured errors:
#: 3e-3 to 5e-3 of the speed and range tolerances, 5e-4 of the times.
CASES = ("table3", "vacuum", "smooth-sphere-headwind", "constant-drag-tailwind", "point-counterweight",
         "light-arm", "arm-centre-on-short-side", "sling-rule-ahead")


@pytest.fixture(scope="module")
def table3():
    return default_design()


@pytest.fixture(scope="module")
def reference(table3):
    return analytic_simulate(table3)


def _errors(shot, reference) -> tuple[float, float]:
    return (shot.release_speed / reference.release_speed - 1.0, shot.range / reference.range - 1.0)


@pytest.mark.parametrize("case", CASES)
def test_release_and_range_agree_with_the_analytic_model(case):
    design = table3_variants()[case]
    expected, shot = analytic_simulate(design), simulate(design)
    assert expected.ok and shot.ok, (expected.message, shot.message)
    speed = expected.release_speed
    limits = {"release_speed": tol.RELEASE_SPEED_REL * speed,
              "range": tol.RANGE_REL * max(abs(expected.range), tol.RANGE_FLOOR),
              "launch_angle": tol.LAUNCH_ANGLE, "apex_height": tol.APEX_HEIGHT_REL * expected.apex_height,
              "liftoff_time": tol.EVENT_TIME, "release_time": tol.EVENT_TIME, "landing_time": tol.EVENT_TIME,
              "counterweight_energy_released": ENERGY_RELEASED_REL * expected.counterweight_energy_released}
    for name, limit in limits.items():
        a, e = getattr(expected, name), getattr(shot, name)
        assert abs(e - a) <= limit, f"{name}: engine {e}, analytic {a}, limit {limit:.3g}"


def test_error_falls_fourfold_when_the_step_is_halved(table3, reference):
    errors = {dt: _errors(simulate(table3, dt=dt), reference) for dt in (2 * DEFAULT_DT, DEFAULT_DT)}
    for which in range(2):  # release speed, range
        ratio = errors[2 * DEFAULT_DT][which] / errors[DEFAULT_DT][which]
        assert CONVERGENCE_BAND[0] < ratio < CONVERGENCE_BAND[1], (which, errors)
