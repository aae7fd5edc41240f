"""Physics of the analytic model: conservation, the base constraint, release, flight."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from analytic.eom import slide_accelerations
from analytic.geometry import sling_arm_angle
from analytic.parameters import params
from analytic.result import Stage, Status
from analytic.reference import DEFAULT_ATOL, DEFAULT_RTOL, simulate

from support import with_environment, with_machine, with_projectile


@pytest.fixture(scope="module")
def vacuum_shot(table3_vacuum):
    return simulate(table3_vacuum)


def test_energy_is_conserved_through_slide_and_swing(vacuum_shot):
    # Exact property of the conservative stage-1/2 dynamics (no friction, drag only in flight).
    shot = vacuum_shot
    assert shot.ok
    drift = np.max(np.abs(shot.history.energy.total)) / shot.counterweight_energy_released
    assert drift < 1e-8


@pytest.mark.parametrize("rule, angle_deg", [("velocity", 43.4), ("velocity", 61.0), ("sling", -40.0)])
def test_energy_conserved_for_other_release_settings(table3_vacuum, rule, angle_deg):
    shot = simulate(with_machine(table3_vacuum, release_rule=rule, release_angle=math.radians(angle_deg)))
    assert shot.ok
    assert np.max(np.abs(shot.history.energy.total)) / shot.counterweight_energy_released < 1e-8


def test_projectile_stays_on_the_base_in_stage_1(vacuum_shot, table3_vacuum):
    shot, h = vacuum_shot, table3_vacuum.machine.pivot_height
    on_base = shot.history.stage == Stage.SLIDE
    assert on_base.sum() > 100
    # path is recomputed from (theta, psi) by the forward kinematics, not from the constraint.
    assert np.max(np.abs(shot.history.path[on_base, 1] + h)) < 1e-9


def test_normal_force_pushes_until_liftoff_and_vanishes_there(vacuum_shot, table3_vacuum):
    p = params(table3_vacuum)
    samples = np.flatnonzero(vacuum_shot.history.stage == Stage.SLIDE)
    normal = [slide_accelerations(*vacuum_shot.history.q[i, :2], *vacuum_shot.history.qdot[i, :2], p)[2] for i in samples]
    weight = p.mP * p.g
    assert min(normal[:-1]) > 0.0
    assert normal[0] == pytest.approx(weight, rel=1e-12)  # at rest the sling is horizontal: N = m g
    last = samples[-1]  # the lift-off instant itself is the last stage-1 sample
    assert vacuum_shot.history.t[last] == vacuum_shot.liftoff_time
    assert abs(normal[-1]) < 1e-9 * weight


def test_velocity_rule_releases_along_the_release_angle(vacuum_shot, table3_vacuum):
    assert vacuum_shot.launch_angle == pytest.approx(table3_vacuum.machine.release_angle, abs=1e-9)


def test_sling_rule_releases_at_the_sling_to_arm_angle(table3_vacuum):
    alpha = math.radians(-40.0)
    shot = simulate(with_machine(table3_vacuum, release_rule="sling", release_angle=alpha))
    q = shot.history.q[-1]
    beta = q[0] + q[2]
    assert sling_arm_angle(-math.sin(q[0]), math.cos(q[0]), -math.sin(beta), math.cos(beta)) == pytest.approx(alpha, abs=1e-9)


def test_vacuum_flight_is_the_closed_form_parabola(vacuum_shot, table3_vacuum):
    # Closed form: x = x0 + vx t, y = y0 + vy t - g t^2 / 2, landing at y = -h.
    g, h = table3_vacuum.environment.gravity, table3_vacuum.machine.pivot_height
    (x0, y0), (vx, vy) = vacuum_shot.release_position, vacuum_shot.release_velocity
    flight_time = (vy + math.sqrt(vy * vy + 2.0 * g * (y0 + h))) / g
    assert vacuum_shot.flight_time == pytest.approx(flight_time, rel=1e-9)
    assert vacuum_shot.range == pytest.approx(x0 + vx * flight_time, rel=1e-9)
    assert vacuum_shot.apex_height == pytest.approx(y0 + h + vy * vy / (2.0 * g), rel=1e-9)
    t = vacuum_shot.history.flight_t - vacuum_shot.release_time
    np.testing.assert_allclose(vacuum_shot.history.flight_path[:, 1], y0 + vy * t - 0.5 * g * t * t, rtol=0, atol=1e-9)


def test_drag_flight_matches_an_independent_integration(table3):
    """Constant-Cd flight integrated again with scipy's solve_ivp (RK45, its own event handling)."""
    design = with_environment(with_projectile(table3, drag="constant", drag_coefficient=0.45), wind_speed=-3.0)
    shot = simulate(design)
    env, proj = design.environment, design.projectile
    k = env.air_density * proj.frontal_area * 0.45 / (2.0 * proj.mass)

    def rhs(t, s):
        vrx, vy = s[2] - env.wind_speed, s[3]
        speed = math.hypot(vrx, vy)
        return [s[2], s[3], -k * speed * vrx, -env.gravity - k * speed * vy]

    land = lambda t, s: s[1] + design.machine.pivot_height  # noqa: E731
    land.terminal, land.direction = True, -1
    ref = solve_ivp(rhs, (0.0, 30.0), [*shot.release_position, *shot.release_velocity], method="RK45",
                    rtol=1e-12, atol=1e-12, events=land)
    assert shot.range == pytest.approx(ref.y_events[0][0][0], rel=1e-8)
    assert shot.flight_time == pytest.approx(ref.t_events[0][0], rel=1e-8)


@pytest.mark.parametrize("drag", [dict(drag="constant", drag_coefficient=0.47), dict(drag="smooth-sphere"),
                                  dict(drag="golf-ball")], ids=["constant", "smooth-sphere", "golf-ball"])
def test_drag_shortens_the_range(vacuum_shot, table3_vacuum, drag):
    shot = simulate(with_projectile(table3_vacuum, **drag))
    assert shot.ok and shot.range < vacuum_shot.range
    assert shot.release_speed == pytest.approx(vacuum_shot.release_speed, rel=1e-12)  # drag acts only in flight


def test_tailwind_lengthens_and_headwind_shortens(table3):
    ranges = {w: simulate(with_environment(table3, wind_speed=w)).range for w in (-5.0, 0.0, 5.0)}
    assert ranges[-5.0] < ranges[0.0] < ranges[5.0]


def test_wind_without_air_does_nothing(table3_vacuum, vacuum_shot):
    shot = simulate(with_environment(table3_vacuum, wind_speed=10.0))
    assert shot.range == pytest.approx(vacuum_shot.range, rel=1e-12)


@pytest.mark.parametrize("drag", ["none", "golf-ball"])
def test_tolerance_is_converged(table3, drag):
    """100x tighter tolerances change the range by < 1e-7 relative: the default tolerance is converged
    far below the 1e-7 to which the two paths are held."""
    design = with_projectile(table3, drag=drag)
    nominal = simulate(design)
    tight = simulate(design, rtol=DEFAULT_RTOL / 100, atol=DEFAULT_ATOL / 100)
    assert abs(tight.range - nominal.range) / abs(nominal.range) < 1e-7
    assert abs(tight.release_speed - nominal.release_speed) / nominal.release_speed < 1e-7


def test_result_arrays_have_documented_shapes(vacuum_shot):
    n = len(vacuum_shot.history.t)
    assert vacuum_shot.history.q.shape == vacuum_shot.history.qdot.shape == (n, 3)
    assert vacuum_shot.history.path.shape == (n, 2) and vacuum_shot.history.stage.shape == vacuum_shot.history.sling_tension.shape == (n,)
    assert vacuum_shot.history.energy.total.shape == (n,)
    assert vacuum_shot.history.flight_path.shape == (len(vacuum_shot.history.flight_t), 2)
    assert np.all(np.diff(vacuum_shot.history.t) > 0) and vacuum_shot.history.t[-1] == vacuum_shot.release_time
    assert vacuum_shot.status is Status.OK


def test_min_sling_tension_is_refined_between_samples(table3_vacuum, vacuum_shot, monkeypatch):
    """The sling pushes for about a millisecond near release (the default design's
    tension dips to about -4 N); the reported minimum must match a 50x denser sampling."""
    import analytic.reference as simulate_module

    monkeypatch.setattr(simulate_module, "SWING_OUTPUT_STEP", simulate_module.SWING_OUTPUT_STEP / 50)
    dense = simulate_module.simulate(table3_vacuum)
    dense_min = float(dense.history.sling_tension.min())
    coarse_min = float(vacuum_shot.history.sling_tension.min())
    assert vacuum_shot.min_sling_tension <= dense_min + 1e-12
    assert abs(vacuum_shot.min_sling_tension - dense_min) < 1e-4 * abs(dense_min)
    assert abs(coarse_min - dense_min) > 1e-3 * abs(dense_min), "the test needs a coarse grid that misses the dip"
