"""Stage 3 in pymunk: the released projectile alone under gravity, drag and wind, to base level."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pymunk

from analytic.aero import drag_coefficient, reynolds_number
from analytic.design import Design
from engine_model.events import crossing_fraction, interpolate


class FlightError(RuntimeError):
    """The flight did not end (no landing within the flight time limit) or went non-finite."""


@dataclass(frozen=True)
class Flight:
    """A flight from release to base level.

    Attributes
    ----------
    t : (k,) times from firing, s: the release instant, every step, the landing instant.
    path : (k, 2) projectile centre, m from the pivot.
    landing_time : s from firing.
    landing_position : (2,) m.
    steps : pymunk steps taken.
    """

    t: np.ndarray
    path: np.ndarray
    landing_time: float
    landing_position: np.ndarray
    steps: int


def drag_acceleration(velocity: tuple[float, float], design: Design) -> tuple[float, float]:
    """Drag acceleration of the projectile, m/s^2: ``-(rho Cd A / 2 m) |v_rel| v_rel``.

    ``v_rel = v - (wind_speed, 0)`` is the air-relative velocity and
    ``Cd = analytic.aero.drag_coefficient(model, Re)`` with ``Re = rho |v_rel| d / mu``.
    """
    env, proj = design.environment, design.projectile
    if proj.drag == "none" or env.air_density == 0.0:
        return 0.0, 0.0
    rel_x, rel_y = velocity[0] - env.wind_speed, velocity[1]
    speed = math.hypot(rel_x, rel_y)
    if speed == 0.0:
        return 0.0, 0.0
    reynolds = reynolds_number(speed, proj.diameter, env.air_density, env.air_viscosity)
    cd = drag_coefficient(proj.drag, reynolds, proj.drag_coefficient)
    k = 0.5 * env.air_density * cd * proj.frontal_area * speed / proj.mass
    return -k * rel_x, -k * rel_y


def flight_time_limit(position: np.ndarray, velocity: np.ndarray, design: Design) -> float:
    """Longest flight allowed, s: 100 times the vacuum flight time plus a minute.

    Drag shortens the climb and at worst stretches the fall to the terminal
    speed, so a bound this loose is only reached by a broken run.
    """
    g, h = design.environment.gravity, design.machine.pivot_height
    vacuum = (velocity[1] + math.sqrt(max(velocity[1]**2 + 2.0 * g * (position[1] + h), 0.0))) / g
    return 100.0 * vacuum + 60.0


def fly(design: Design, release_time: float, position: np.ndarray, velocity: np.ndarray,
        dt: float) -> Flight:
    """Step the free projectile in its own pymunk Space until its centre is back at base level.

    The drag is applied as a force each step. pymunk's step moves the position
    with the velocity of the previous half step, then updates the velocity
    with the force it is given: evaluating the drag at the velocity predicted
    for the position's instant (half a step on) keeps the scheme second order.

    Parameters
    ----------
    release_time : s from firing; position (2,) m and velocity (2,) m/s at release.
    dt : fixed step, s.
    """
    g, h = design.environment.gravity, design.machine.pivot_height
    mass = design.projectile.mass
    space = pymunk.Space()
    space.gravity = (0.0, -g)
    space.damping = 1.0
    body = pymunk.Body(mass, 0.4 * mass * (design.projectile.diameter / 2.0)**2)
    space.add(body)

    def predicted(v: tuple[float, float], ahead: float) -> tuple[float, float]:
        ax, ay = drag_acceleration(v, design)
        return v[0] + ax * ahead, v[1] + (ay - g) * ahead

    # Leapfrog start: position at the release instant, velocity half a step later.
    ax, ay = drag_acceleration(predicted(tuple(velocity), 0.25 * dt), design)
    body.position = (float(position[0]), float(position[1]))
    body.velocity = (velocity[0] + ax * 0.5 * dt, velocity[1] + (ay - g) * 0.5 * dt)

    times, path = [release_time], [(float(position[0]), float(position[1]))]
    limit = flight_time_limit(position, velocity, design)
    steps = 0
    while True:
        ax, ay = drag_acceleration(predicted(tuple(body.velocity), 0.5 * dt), design)
        body.force = (mass * ax, mass * ay)
        space.step(dt)
        steps += 1
        x, y = body.position
        if not (math.isfinite(x) and math.isfinite(y)):
            raise FlightError(f"the flight went non-finite after {steps} steps of {dt:g} s")
        times.append(release_time + steps * dt)
        path.append((x, y))
        if y + h < 0.0:
            break
        if steps * dt > limit:
            raise FlightError(f"the projectile did not come down within {limit:.3g} s of flight")
    heights = [p[1] + h for p in path[-3:]]
    fraction = crossing_fraction(tuple(heights))
    landing_position = interpolate(np.array(path[-len(heights):]), fraction)
    landing_position[1] = -h
    landing_time = times[-2] + fraction * (times[-1] - times[-2])
    t = np.array(times[:-1] + [landing_time])
    flight_path = np.array(path[:-1] + [tuple(landing_position)])
    return Flight(t, flight_path, landing_time, landing_position, steps)
