"""The engine's peak loads: from each body's momentum change, converging on the analytic model's."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from analytic.reference import simulate as analytic_simulate
from analytic.result import PEAK_NAMES
from crosscheck.cases import HELD_AXLE, HELD_COUNTERWEIGHT_MASS, STICKING_STATIC_HINGE, sample_cases
from crosscheck.tolerances import PEAK_LOAD_REL
from engine_model import loads, simulate
from engine_model.cli import EXIT_OK, main
from support import with_machine

#: Steps at which the paper's design's peaks are compared with the analytic model's.
STEPS = (1e-4, 5e-5)


@pytest.fixture(scope="module")
def light_arm():
    """``sample-0-015-light`` of the cross-check: a 3 g arm (ballast at the pivot in the engine)
    whose largest axle and hinge loads are at rest, before the counterweight drops."""
    return sample_cases(16, 0)[15].design


def _relative_errors(design, dt) -> np.ndarray:
    reference = analytic_simulate(design, histories=False)
    shot = simulate(design, dt=dt)
    return np.array([getattr(shot, name) / getattr(reference, name) - 1.0 for name in PEAK_NAMES])


#: The forces' peaks (all of ``PEAK_NAMES`` but the arm's bending moment, the last).
FORCES = slice(0, 4)


def test_the_peak_loads_converge_at_order_two_on_the_analytic_models(table3):
    # Measured: 7.4e-5 (axle, hinge) and 3.1e-5 (tension, acceleration) at 1e-4 s, a quarter of
    # that at 5e-5 s: the release's own order (tests/test_crosscheck.py, the step study).
    coarse, fine = (_relative_errors(table3, dt)[FORCES] for dt in STEPS)
    assert np.all(np.abs(fine) < 5e-5), fine
    assert np.all((3.0 < coarse / fine) & (coarse / fine < 5.0)), coarse / fine


def test_the_arm_bending_moment_converges_on_the_analytic_models(table3):
    # Measured on the paper's design: 3.1e-5 at 1e-4 s, 2.6e-5 at 5e-5 s, 1.5e-5 at 2.5e-5 s (order 1
    # from 5e-5 s on: the arm's angular acceleration, crosscheck.tolerances.ARM_BENDING_MOMENT_REL).
    errors = [abs(_relative_errors(table3, dt)[-1]) for dt in (*STEPS, STEPS[-1] / 2)]
    assert errors[1] < 5e-5 and errors[2] < 0.7 * errors[1] and errors[1] < errors[0], errors


def test_the_bending_moment_is_the_long_sides_newton_euler_equation(table3, monkeypatch):
    # The long side's own weight and inertia count: with a massless long side the paper's peak is the
    # sling's pull alone, 52 % lower (25 of its 49 N m are the long side's inertia; analytic model).
    reference = analytic_simulate(table3, histories=False)
    assert simulate(table3, dt=5e-5).peak_arm_bending_moment == pytest.approx(
        reference.peak_arm_bending_moment, rel=1e-4)
    monkeypatch.setattr(loads, "arm_long_side", lambda *args: (0.0, 0.0, 0.0))
    assert simulate(table3, dt=5e-5).peak_arm_bending_moment < 0.6 * reference.peak_arm_bending_moment


def test_the_solvers_settling_after_the_opening_step_is_left_out_of_the_peaks(light_arm, monkeypatch):
    reference = analytic_simulate(light_arm, histories=False)
    assert reference.peak_axle_load_time == reference.peak_hinge_load_time == 0.0   # at rest
    shot = simulate(light_arm, dt=5e-5)
    for name in ("peak_axle_load", "peak_hinge_load"):
        assert getattr(shot, name) == pytest.approx(getattr(reference, name), rel=1e-6)
    # Counted in, the dozen ringing steps give a peak 2 % too high (whatever the step).
    monkeypatch.setattr(loads, "SETTLING_STEPS", 0)
    rung = simulate(light_arm, dt=5e-5)
    assert rung.peak_hinge_load > 1.02 * reference.peak_hinge_load


def test_the_peak_of_a_sampled_load_is_its_parabolas_vertex():
    times = np.arange(8) / 10.0
    values = 5.0 - (times - 0.32) ** 2
    assert loads.peak(values, times) == pytest.approx((5.0, 0.32), rel=1e-12)
    # The last sample is off the grid (the release instant): taken as it is, as is the first.
    assert loads.peak(times, times) == (0.7, 0.7)
    assert loads.peak(-times, times) == (0.0, 0.0)


def test_the_peaks_of_a_hinge_that_sticks_under_load_converge_on_the_analytic_models(table3):
    # The hinge stops 26 ms before release under 666 N, its loads' peak: they fall to 72 N as it sticks
    # (the analytic model's ``hinge_stops``, its peak the slipping side's value there). Measured: axle and
    # hinge 6.4e-4 at 1e-4 s, 1.8e-4 at 5e-5 s; tension and acceleration 6.2e-4, 2.2e-4 (the first steps
    # of the stuck hinge ring by about 3e-3 N of 12.5 N: pymunk's solver starts from the slip's impulses).
    design = dataclasses.replace(table3, losses=STICKING_STATIC_HINGE)
    coarse, fine = (_relative_errors(design, dt) for dt in STEPS)
    assert np.all(np.abs(fine) < PEAK_LOAD_REL / 4.0), fine
    # The bending moment (4.0e-5 at 1e-4 s, 1.4e-4 at 5e-5 s: no order yet) is held to the bound alone.
    assert np.all(np.abs(coarse[FORCES]) > 2.0 * np.abs(fine[FORCES])), (coarse, fine)


def test_a_peak_where_a_load_jumps_down_is_its_stretchs_line_at_the_jump():
    # A load rising 2 a step falls at t = 4.55 steps from 109.1 to 20; each sample is the load's mean
    # over its step (a momentum change), so the sample at 5 holds 0.05 of the line and 0.95 of the 20.
    times = np.arange(10.0)
    values = np.where(times < 5.0, 100.0 + 2.0 * times, 20.0)
    values[5] = 0.05 * (100.0 + 2.0 * 4.525) + 0.95 * 20.0
    joined = np.ones(9, dtype=bool)
    joined[4:6] = False   # the jump's step is on neither stretch
    value, time = loads.peak(values, times, joined)
    assert value == pytest.approx(109.1, abs=0.01) and time == pytest.approx(4.55, abs=0.01)
    # A parabola through the jump puts a peak about an eighth of the fall over the top.
    assert loads.peak(values, times)[0] > 109.1 + 5.0


def test_a_machine_that_never_fires_has_no_peak_loads(table3):
    held = dataclasses.replace(with_machine(table3, counterweight_mass=HELD_COUNTERWEIGHT_MASS), losses=HELD_AXLE)
    shot = simulate(held)
    assert shot.status.value == "never_fires"
    assert all(getattr(shot, name) is None and getattr(shot, f"{name}_time") is None for name in PEAK_NAMES)


def test_simulate_json_gives_the_peak_loads_and_their_times(capsys):
    assert main(["simulate", "--json"]) == EXIT_OK
    data = json.loads(capsys.readouterr().out)
    for name in PEAK_NAMES:
        assert data[name] > 0.0 and 0.0 <= data[f"{name}_time"] <= data["release_time"], name
