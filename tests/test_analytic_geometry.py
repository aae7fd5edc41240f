"""Kinematics and the release rule (``analytic.geometry``): conventions and closed-form cases."""

from __future__ import annotations

import math

import numpy as np
import pytest

from analytic.design import initial_angles
from analytic.geometry import (PARTS, SLING_RULE, VELOCITY_RULE, machine_points, part_positions,
                               projectile_state, release_value, sling_arm_angle)


def test_sling_arm_angle_sign_convention():
    # Sling straight in line with the arm: 0; sling a quarter turn clockwise ahead: +90 deg.
    assert sling_arm_angle(0.0, 1.0, 0.0, 1.0) == 0.0
    assert sling_arm_angle(0.0, 1.0, 1.0, 0.0) == pytest.approx(math.pi / 2)
    assert sling_arm_angle(0.0, 1.0, -1.0, 0.0) == pytest.approx(-math.pi / 2)


def test_at_rest_the_long_tip_and_the_projectile_lie_on_the_base(table3):
    m = table3.machine
    points = machine_points(initial_angles(m), m)
    assert points["long_tip"][1] == pytest.approx(-m.pivot_height, abs=1e-15)
    assert points["projectile"][1] == pytest.approx(-m.pivot_height, abs=1e-15)
    # The sling lies along the base, forward of the tip; the counterweight hangs plumb below the short tip.
    assert points["projectile"][0] - points["long_tip"][0] == pytest.approx(m.sling_length)
    assert points["counterweight"][0] == pytest.approx(points["short_tip"][0], abs=1e-15)
    assert points["short_tip"][1] - points["counterweight"][1] == pytest.approx(m.counterweight_link)


def test_machine_points_is_part_positions_row_by_row(table3):
    m = table3.machine
    q = np.random.default_rng(0).uniform(-3, 3, (7, 3))
    points = machine_points(q, m)
    for i, (theta, phi, psi) in enumerate(q):
        flat = part_positions(theta, phi, psi, m.arm_long, m.arm_short, m.arm_cg, m.counterweight_link,
                              m.sling_length)
        for j, name in enumerate(PARTS):
            assert tuple(points[name][i]) == flat[2 * j: 2 * j + 2]


def test_projectile_velocity_is_the_time_derivative_of_its_position():
    # Central difference of the position along a straight line in (theta, psi) space.
    theta, psi, dtheta, dpsi, la, ls, h = 1.1, -2.0, -7.0, 3.0, 0.7, 0.6, 1e-6
    x1, y1, *_ = projectile_state(theta - h * dtheta, psi - h * dpsi, 0, 0, la, ls)
    x2, y2, *_ = projectile_state(theta + h * dtheta, psi + h * dpsi, 0, 0, la, ls)
    _, _, vx, vy = projectile_state(theta, psi, dtheta, dpsi, la, ls)
    assert vx == pytest.approx((x2 - x1) / (2 * h), rel=1e-8)
    assert vy == pytest.approx((y2 - y1) / (2 * h), rel=1e-8)


def test_velocity_rule_rises_through_zero_as_the_direction_passes_the_angle_clockwise():
    alpha = math.radians(40.0)
    before = release_value(VELOCITY_RULE, alpha, 0, 1, 0, 1, math.cos(alpha + 0.01), math.sin(alpha + 0.01))
    after = release_value(VELOCITY_RULE, alpha, 0, 1, 0, 1, math.cos(alpha - 0.01), math.sin(alpha - 0.01))
    opposite = release_value(VELOCITY_RULE, alpha, 0, 1, 0, 1, -math.cos(alpha), -math.sin(alpha))
    assert before[0] < 0.0 < after[0] and before[1] and after[1]
    assert not opposite[1]   # pointing backwards along the angle: not armed


def test_sling_rule_value_is_the_sine_of_the_angle_past_the_release_angle():
    alpha = math.radians(-30.0)
    gamma = math.radians(-20.0)   # the sling 20 deg behind the arm, i.e. 10 deg past alpha
    sx, sy = math.sin(gamma), math.cos(gamma)   # arm straight up: clockwise by gamma
    value, armed = release_value(SLING_RULE, alpha, 0.0, 1.0, sx, sy, 0.0, 0.0)
    assert value == pytest.approx(math.sin(gamma - alpha)) and armed
