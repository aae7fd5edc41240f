"""Event location between fixed steps and the free flight, against closed forms and independent integrations."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from analytic.design_file import default_design
from analytic.aero import drag_coefficient
from analytic.limits import flight_time_limit
from analytic.result import Status
from support import failure_designs, with_environment, with_projectile
from engine_model import flight as flight_module
from engine_model.build import EngineError
from engine_model.events import crossing_fraction, interpolate
from engine_model.flight import (SMALLEST_DRAG_COEFFICIENT, drag_acceleration, drag_rate, fall_speed_bound,
                                 fly)
from engine_model import DEFAULT_DT


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
    # The apex is the vertex through the highest samples: exact on this parabola too.
    assert flight.apex == pytest.approx(position[1] + velocity[1]**2 / (2 * g), rel=1e-12)


def test_drag_with_wind_matches_an_independent_integration():
    # The same ODE through scipy's DOP853 at 1e-12: the engine's flight is second
    # order, so at dt = 1e-4 it agrees to about 1e-6 relative (range ~ 40 m).
    design = with_environment(with_projectile(default_design(), drag="constant", drag_coefficient=0.3),
                              wind_speed=-4.0)
    position, velocity = np.array([-0.5, 1.0]), np.array([17.0, 16.0])
    landing_time, landing = _reference_landing(design, position, velocity)
    flight = fly(design, 0.0, position, velocity, 1e-4)
    assert flight.landing_position[0] == pytest.approx(landing[0], rel=2e-6)
    assert flight.landing_time == pytest.approx(landing_time, rel=2e-6)


def _reference_landing(design, position, velocity) -> tuple[float, np.ndarray]:
    """The flight's ODE through scipy's DOP853 at 1e-12: landing time (s) and state [x, y, vx, vy]."""
    h, g = design.machine.pivot_height, design.environment.gravity

    def rhs(t, y):
        ax, ay = drag_acceleration((y[2], y[3]), design)
        return [y[2], y[3], ax, ay - g]

    def landed(t, y):
        return y[1] + h
    landed.terminal, landed.direction = True, -1
    reference = solve_ivp(rhs, (0.0, 100.0), [*position, *velocity], method="DOP853", rtol=1e-12,
                          atol=1e-12, events=landed)
    return reference.t_events[0][0], reference.y_events[0][0]


def test_drag_opposes_the_air_relative_velocity():
    # F = -1/2 rho Cd A |v_rel| v_rel with v_rel = v - (wind, 0): hand numbers.
    design = with_environment(with_projectile(default_design(), drag="constant", drag_coefficient=0.5),
                              wind_speed=3.0)
    proj, env = design.projectile, design.environment
    ax, ay = drag_acceleration((6.0, 4.0), design)  # v_rel = (3, 4), |v_rel| = 5
    k = 0.5 * env.air_density * 0.5 * math.pi * proj.diameter**2 / 4 / proj.mass
    assert (ax, ay) == pytest.approx((-k * 5.0 * 3.0, -k * 5.0 * 4.0), rel=1e-14)


@pytest.mark.parametrize("model", sorted(SMALLEST_DRAG_COEFFICIENT))
def test_the_smallest_drag_coefficient_bounds_the_curve(model):
    # fall_speed_bound is only a bound if no Reynolds number gives a smaller Cd;
    # and it is only useful if it is the curve's own minimum (to 1e-3).
    reynolds = np.logspace(-6, 12, 200_001)
    cd = np.array([drag_coefficient(model, re) for re in reynolds])
    assert SMALLEST_DRAG_COEFFICIENT[model] <= cd.min() < SMALLEST_DRAG_COEFFICIENT[model] * (1.0 + 1e-3)


#: A 0.1 g, 30 cm ball: at 23 m/s drag alone would stop it in 0.2 ms, a fifth
#: of the 1 ms step below; it falls at 0.22 m/s in the end.
FEATHER = dict(mass=1e-4, diameter=0.3, drag="constant", drag_coefficient=0.47)


def test_a_stiff_drag_is_flown_in_shorter_steps_and_matches_an_independent_integration():
    design = with_projectile(default_design(), **FEATHER)
    position, velocity = np.array([-0.5, 1.0]), np.array([17.0, 16.0])
    dt = 1e-3
    assert drag_rate(tuple(velocity), design) * dt > 2.0  # one explicit step of dt would overshoot
    landing_time, landing = _reference_landing(design, position, velocity)
    flight = fly(design, 0.0, position, velocity, dt)
    assert np.any(np.diff(flight.t) < dt / 2.0)
    # Measured: 5.3e-6 in time, 9 um in x (of 7.4 s and 0.48 m), set by
    # DRAG_STEP_FRACTION in the first milliseconds rather than by dt.
    assert flight.landing_time == pytest.approx(landing_time, rel=1e-5)
    assert flight.landing_position[0] == pytest.approx(landing[0], abs=2e-5)
    # With a constant Cd the bound on the falling speed is the terminal speed itself.
    assert -landing[3] == pytest.approx(fall_speed_bound(design), rel=1e-9)


def test_a_flight_gone_non_finite_is_an_engine_error(monkeypatch):
    # Without the shorter steps the explicit drag overshoots by a factor of 7 a step.
    monkeypatch.setattr(flight_module, "DRAG_STEP_FRACTION", math.inf)
    design = with_projectile(default_design(), **FEATHER)
    with pytest.raises(EngineError, match="non-finite"):
        fly(design, 0.0, np.array([-0.5, 1.0]), np.array([17.0, 16.0]), 1e-3)


def _balloon():
    """The known no-landing design and the state the engine releases it in
    (measured: ``simulate`` at the default step): 1.42 m above the base, flung down at 33 m/s."""
    design = failure_designs()[Status.NO_LANDING]
    return design, np.array([0.95073617, 0.82894282]), np.array([16.53552727, -28.64037337])


def test_a_flight_that_cannot_land_in_time_ends_unlanded_as_soon_as_that_is_certain():
    design, position, velocity = _balloon()
    flight = fly(design, 0.4, position, velocity, DEFAULT_DT)
    h, g = design.machine.pivot_height, design.environment.gravity
    assert not flight.landed and flight.landing_position is None
    assert flight.limit == flight_time_limit(position[1] + h, velocity[1], g)  # 64.9 s
    # Certain after 3.3 ms: its 1.42 m at no more than 2.08 cm/s take 68.3 s.
    assert flight.t[-1] - 0.4 < 0.01 and flight.steps < 1000
    height = flight.path[-1, 1] + h
    assert flight.t[-1] - 0.4 + height / fall_speed_bound(design) > flight.limit


@pytest.mark.slow
def test_flown_to_the_limit_the_balloon_is_still_in_the_air(monkeypatch):
    # The early end is sound: flown the whole way, it is still 7 cm up at 64.9 s.
    # (At 1e-4 s, which the drag still allows: 650,000 steps, about 25 s.)
    monkeypatch.setattr(flight_module, "fall_speed_bound", lambda design: math.inf)
    monkeypatch.setattr(flight_module, "FLIGHT_STEP_LIMIT", 10**7)   # past the engine's budget on purpose
    design, position, velocity = _balloon()
    flight = fly(design, 0.4, position, velocity, 1e-4)
    assert not flight.landed and flight.t[-1] - 0.4 > flight.limit
    assert 0.05 < flight.path[-1, 1] + design.machine.pivot_height < 0.1
