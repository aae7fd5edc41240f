"""Stage 3 in pymunk: the released projectile alone under gravity, drag and wind, to base level."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pymunk

from analytic.aero import GOLF_BALL_DRAG_COEFFICIENT, drag_coefficient, reynolds_number
from analytic.design import Design
from analytic.limits import flight_time_limit
from engine_model.build import EngineError
from engine_model.events import crossing_fraction, interpolate


#: Longest flight step, as a fraction of the drag's time scale ``|v_rel| / |a_drag|``
#: (the time in which drag alone would stop the projectile). The step is the
#: engine's ``dt`` unless that is longer: a very light, large projectile (the
#: 10 mg, 1 m balloon of ``crosscheck.cases``) released at 33 m/s has a time
#: scale of 1.3 us, and one step of 50 us with the drag taken explicitly
#: overshoots (it reported a throw after a single step). The scheme's error
#: per step is then about ``(2 x FRACTION)^3 / 6`` of the velocity (quadratic
#: drag damps at twice ``1 / time scale``), 1.7e-4 at 0.05, for the few
#: hundred steps the drag needs to slow it; a golf ball's time scale is
#: seconds, so its flight keeps ``dt`` and its numbers.
DRAG_STEP_FRACTION = 0.05

#: The smallest drag coefficient of each Reynolds-dependent drag model at any
#: Re (``analytic.aero``): the golf ball's smallest table value (its PCHIP
#: interpolant is monotone between nodes and clamped outside the table), and
#: the smooth sphere's at the bottom of its drag crisis (Re = 4.03e5, where
#: Clift's two pieces meet at 0.070556), rounded down. ``tests/test_engine_events.py``
#: checks both against the curves over Re from 1e-6 to 1e12.
SMALLEST_DRAG_COEFFICIENT = {"golf-ball": min(GOLF_BALL_DRAG_COEFFICIENT), "smooth-sphere": 0.0705}


@dataclass(frozen=True)
class Flight:
    """A flight from release to base level, or to the flight time limit.

    Attributes
    ----------
    t : (k,) times from firing, s: the release instant, every step, and the
        landing instant (if it landed).
    path : (k, 2) projectile centre, m from the pivot.
    landing_time : s from firing, or None if it did not land within ``limit``.
    landing_position : (2,) m, or None.
    steps : pymunk steps taken.
    limit : the flight time bound, s from release (``analytic.limits.flight_time_limit``).
    """

    t: np.ndarray
    path: np.ndarray
    landing_time: float | None
    landing_position: np.ndarray | None
    steps: int
    limit: float

    @property
    def landed(self) -> bool:
        return self.landing_time is not None


def drag_rate(velocity: tuple[float, float], design: Design) -> float:
    """``k`` in the drag acceleration ``-k v_rel``, 1/s: ``rho Cd A |v_rel| / (2 m)``.

    ``v_rel = v - (wind_speed, 0)`` is the air-relative velocity and
    ``Cd = analytic.aero.drag_coefficient(model, Re)`` with ``Re = rho |v_rel| d / mu``;
    ``1 / k`` is the time in which drag alone would stop the projectile.
    """
    env, proj = design.environment, design.projectile
    if proj.drag == "none" or env.air_density == 0.0:
        return 0.0
    speed = math.hypot(velocity[0] - env.wind_speed, velocity[1])
    if speed == 0.0:
        return 0.0
    reynolds = reynolds_number(speed, proj.diameter, env.air_density, env.air_viscosity)
    cd = drag_coefficient(proj.drag, reynolds, proj.drag_coefficient)
    return 0.5 * env.air_density * cd * proj.frontal_area * speed / proj.mass


def drag_acceleration(velocity: tuple[float, float], design: Design) -> tuple[float, float]:
    """Drag acceleration of the projectile, m/s^2: ``-k v_rel`` (``drag_rate``)."""
    k = drag_rate(velocity, design)
    return -k * (velocity[0] - design.environment.wind_speed), -k * velocity[1]


def fall_speed_bound(design: Design) -> float:
    """A downward speed the projectile cannot exceed once below it, m/s (inf without drag).

    With the wind horizontal, the vertical motion is ``dvy/dt = -g - k vy``
    with ``k = rho Cd A |v_rel| / (2 m) >= c |vy|``, ``c = rho Cd_min A / (2 m)``,
    so a falling speed ``w = -vy`` obeys ``dw/dt <= g - c w^2``: it never rises
    above ``max(w, sqrt(g / c))``, the terminal speed at the smallest Cd
    (``SMALLEST_DRAG_COEFFICIENT``).
    """
    env, proj = design.environment, design.projectile
    cd = proj.drag_coefficient if proj.drag == "constant" else SMALLEST_DRAG_COEFFICIENT.get(proj.drag, 0.0)
    c = 0.5 * env.air_density * cd * proj.frontal_area / proj.mass
    return math.sqrt(env.gravity / c) if c > 0.0 else math.inf


def fly(design: Design, release_time: float, position: np.ndarray, velocity: np.ndarray,
        dt: float) -> Flight:
    """Step the free projectile in its own pymunk Space until its centre is back at base level.

    The drag is applied as a force each step. pymunk's step moves the position
    with the velocity of the previous half step, then updates the velocity
    with the force it is given: evaluating the drag at the velocity predicted
    for the position's instant (half a step on) keeps the scheme second order.
    Where the drag's time scale is short the step shrinks below ``dt``
    (``DRAG_STEP_FRACTION``); each velocity update then spans the mean of the
    steps on either side of its instant (a variable-step leapfrog, still second order).

    A flight that does not reach base level within ``analytic.limits.flight_time_limit``
    is returned unlanded (``landing_time`` None): the caller names it ``no_landing``.
    It ends as soon as landing in time is impossible: the rest of the fall
    takes at least ``height / max(w, fall_speed_bound)`` at falling speed ``w``.

    Parameters
    ----------
    release_time : s from firing; position (2,) m and velocity (2,) m/s at release.
    dt : fixed step, s.

    Raises
    ------
    EngineError
        The flight went non-finite.
    """
    g, h = design.environment.gravity, design.machine.pivot_height
    mass = design.projectile.mass
    space = pymunk.Space()
    space.gravity = (0.0, -g)
    space.damping = 1.0
    body = pymunk.Body(mass, 0.4 * mass * (design.projectile.diameter / 2.0)**2)
    space.add(body)

    wind = design.environment.wind_speed

    def step_after(rate: float) -> float:
        return dt if rate * dt <= DRAG_STEP_FRACTION else DRAG_STEP_FRACTION / rate

    def predicted(v: tuple[float, float], ahead: float) -> tuple[float, float]:
        ax, ay = drag_acceleration(v, design)
        return v[0] + ax * ahead, v[1] + (ay - g) * ahead

    # Leapfrog start: position at the release instant, velocity half a step later.
    step = step_after(drag_rate(tuple(velocity), design))
    ax, ay = drag_acceleration(predicted(tuple(velocity), 0.25 * step), design)
    body.position = (float(position[0]), float(position[1]))
    body.velocity = (velocity[0] + ax * 0.5 * step, velocity[1] + (ay - g) * 0.5 * step)

    times, path = [release_time], [(float(position[0]), float(position[1]))]
    limit = flight_time_limit(float(position[1]) + h, float(velocity[1]), g)
    # The bound is 100 vacuum flights plus a minute: a projectile that only
    # drifts down at its terminal speed would take 1.3e6 steps of 50 us to
    # reach it (33 s for the 10 mg, 1 m balloon of crosscheck.cases), so the
    # flight stops once the fall speed bound proves it cannot land in time
    # (the balloon: after 3.3 ms of flight, falling 1.42 m at 2.08 cm/s at most
    # takes 68.3 s against a bound of 64.9 s). A real throw never comes near.
    fall_cap = fall_speed_bound(design)
    # Time flown: steps of dt counted apart from shorter ones, so that a flight
    # at dt throughout has its times exactly release_time + n dt.
    steps = full_steps = 0
    short_time = 0.0
    taken = [0.0, 0.0]  # the last two steps
    while True:
        v_next = predicted(tuple(body.velocity), 0.5 * step)
        rate = drag_rate(v_next, design)
        ax, ay = -rate * (v_next[0] - wind), -rate * v_next[1]
        following = step_after(rate)
        if following != step:
            # pymunk applies force and gravity over this step; the velocity
            # update must span the mean of this step and the next.
            scale = 0.5 * (step + following) / step
            ax, ay = ax * scale, (ay - g) * scale + g
        body.force = (mass * ax, mass * ay)
        space.step(step)
        steps += 1
        if step == dt:
            full_steps += 1
        else:
            short_time += step
        taken = [taken[1], step]
        step = following
        x, y = body.position
        if not math.isfinite(x + y + body.velocity[0] + body.velocity[1]):
            raise EngineError(f"the flight went non-finite after {steps} steps of at most {dt:g} s")
        flown = full_steps * dt + short_time
        times.append(release_time + flown)
        path.append((x, y))
        if y + h < 0.0:
            break
        if flown > limit or flown + (y + h) / max(-v_next[1], fall_cap) > limit:
            return Flight(np.array(times), np.array(path), None, None, steps, limit)
    # Equally spaced samples locate the landing on a parabola; after a change of step, a line.
    samples = 3 if steps >= 2 and taken[0] == taken[1] else 2
    heights = [p[1] + h for p in path[-samples:]]
    fraction = crossing_fraction(tuple(heights))
    landing_position = interpolate(np.array(path[-samples:]), fraction)
    landing_position[1] = -h
    landing_time = times[-2] + fraction * (times[-1] - times[-2])
    t = np.array(times[:-1] + [landing_time])
    flight_path = np.array(path[:-1] + [tuple(landing_position)])
    return Flight(t, flight_path, landing_time, landing_position, steps, limit)
