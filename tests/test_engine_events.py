"""Event location between fixed steps and the free flight, against closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from analytic.design_file import default_design
from conftest import with_environment, with_projectile
from engine_model.events import crossing_fraction, interpolate
from engine_model.flight import drag_acceleration, fly


@pytest.mark.parametrize("root", [0.0, 0.137, 0.5, 0.92, 1.0], ids=lambda r: f"root-{r}")
def test_quadratic_crossing_is_exact(root):
    # p(s) = (s - root)(s + 3) sampled at s = -1, 0, 1: its root in [0, 1] is `root`.
    samples = tuple((s - root) * (s + 3.0) for s in (-1.0, 0.0, 1.0))
    assert crossing_fraction(samples) == pytest.approx(root, abs=1e-12)


def test_linear_crossing_with_two_samples():
    assert crossing_fraction((-1.0, 3.0)) == pytest.approx(0.25)


def test_quadratic_interpolation_is_exact():
    # A parabola in each column, sampled at s = -1, 0, 1 and read back at s = 0.3.
    s = np.array([-1.0, 0.0, 1.0])
    samples = np.column_stack([2.0 + 3.0 * s - 5.0 * s**2, -s**2])
    assert interpolate(samples, 0.3) == pytest.approx([2.0 + 0.9 - 0.45, -0.09], abs=1e-14)


def test_flight_without_drag_lands_where_the_parabola_does():
    # Constant gravity: pymunk's symplectic Euler with the half-step start is
    # exact for positions, and the quadratic landing interpolation is exact too.
    design = with_projectile(default_design(), drag="none")
    g, h = design.environment.gravity, design.machine.pivot_height
    position, velocity = np.array([-0.5, 1.0]), np.array([17.0, 16.0])
    flight = fly(design, 0.4, position, velocity, 1e-3)
    time = (velocity[1] + math.sqrt(velocity[1]**2 + 2 * g * (position[1] + h))) / g
    assert flight.landing_time == pytest.approx(0.4 + time, rel=1e-12)
    assert flight.landing_position[0] == pytest.approx(position[0] + velocity[0] * time, rel=1e-12)
    assert flight.path[:, 1].max() == pytest.approx(position[1] + velocity[1]**2 / (2 * g), abs=g * 1e-6 / 8)


def test_drag_with_wind_matches_an_independent_integration():
    # The same ODE through scipy's DOP853 at 1e-12: the engine's flight is second
    # order, so at dt = 1e-4 it agrees to about 1e-6 relative (range ~ 40 m).
    design = with_environment(with_projectile(default_design(), drag="constant", drag_coefficient=0.3),
                              wind_speed=-4.0)
    h, g = design.machine.pivot_height, design.environment.gravity
    position, velocity = np.array([-0.5, 1.0]), np.array([17.0, 16.0])

    def rhs(t, y):
        ax, ay = drag_acceleration((y[2], y[3]), design)
        return [y[2], y[3], ax, ay - g]

    def landed(t, y):
        return y[1] + h
    landed.terminal, landed.direction = True, -1
    reference = solve_ivp(rhs, (0.0, 10.0), [*position, *velocity], method="DOP853", rtol=1e-12,
                          atol=1e-12, events=landed)
    flight = fly(design, 0.0, position, velocity, 1e-4)
    assert flight.landing_position[0] == pytest.approx(reference.y_events[0][0][0], rel=2e-6)
    assert flight.landing_time == pytest.approx(reference.t_events[0][0], rel=2e-6)


def test_drag_opposes_the_air_relative_velocity():
    # F = -1/2 rho Cd A |v_rel| v_rel with v_rel = v - (wind, 0): hand numbers.
    design = with_environment(with_projectile(default_design(), drag="constant", drag_coefficient=0.5),
                              wind_speed=3.0)
    proj, env = design.projectile, design.environment
    ax, ay = drag_acceleration((6.0, 4.0), design)  # v_rel = (3, 4), |v_rel| = 5
    k = 0.5 * env.air_density * 0.5 * math.pi * proj.diameter**2 / 4 / proj.mass
    assert (ax, ay) == pytest.approx((-k * 5.0 * 3.0, -k * 5.0 * 4.0), rel=1e-14)
