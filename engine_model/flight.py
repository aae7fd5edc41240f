"""Stage 3 in pymunk: the released projectile alone under gravity, drag and wind, to the target's level."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, NamedTuple

import numpy as np
import pymunk

from analytic.aero import DRAG_MODELS, DRAG_TABLE, GOLF_BALL_DRAG_COEFFICIENT, drag_coefficient, reynolds_number
from analytic.aero import drag_rate as aero_drag_rate
from analytic.design import Design
from analytic.limits import flight_time_limit
from engine_model.build import EngineError, placeholder_moment
from engine_model.events import crossing_fraction, highest, interpolate
from engine_model.readout import motion, set_force, stepper


#: The flight's step as a multiple of the machine's ``dt``. The machine needs
#: its short step for its joints (each opens by the one-step chord error,
#: ``dt^2``); the free projectile has no joint, and its leapfrog's error goes
#: as the step squared over a smooth path. Measured on the paper's design
#: against the analytic model (range, relative): -2.708e-6 at 1x dt,
#: -2.709e-6 at 10x, -2.713e-6 at 20x, -2.730e-6 at 40x (2 ms): the machine's
#: error, not the flight's, at a fortieth of the flight's steps (28 ms instead
#: of 97 ms for the paper's flight). Over the default cross-check's 63 designs
#: no comparison moved by more than 6.2e-5 of its tolerance from 10x to 40x,
#: and the worst of each quantity is the same or better.
FLIGHT_STEP_MULTIPLE = 40
#: Most pymunk steps in flight, after which the flight ends unlanded and the
#: shot ``STEP_FAILED`` (``engine_model.stepping.MACHINE_STEP_LIMIT`` for the
#: machine). A real flight takes a few thousand (the cross-check's suite at
#: most 7,156); a flight under a gravity of 1e-6 m/s^2 would take billions.
FLIGHT_STEP_LIMIT = 400_000

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
    """A flight from release to the target's level (``environment.target_height`` above the base), or to
    the flight time limit, or to its apex below a raised target (``short``).

    Attributes
    ----------
    t : (k,) times from firing, s: the release instant, every step, and the
        landing instant (if it landed).
    path : (k, 2) projectile centre, m from the pivot.
    landing_time : s from firing, or None if it did not land within ``limit``.
    landing_position : (2,) m, or None.
    steps : pymunk steps taken.
    limit : the flight time bound, s from release (``analytic.limits.flight_time_limit``).
    short : it never reaches a raised target: it turned down below it (the caller names it
        ``short_of_target``; ``apex`` is then its highest point).
    apex : highest centre height, m from the pivot: the vertex of the parabola through
        the highest sample and its neighbours (``events.highest``), not the highest sample.
    drag_work : J the drag took from the projectile from release to landing (or
        to the flight's end), over the ground velocity: ``-F_drag . v`` integrated,
        the projectile's loss of mechanical energy, as ``analytic.reference.drag_work``
        defines it (with a tailwind it can be negative: the air gave more than
        it took; the air itself dissipates ``m k |v_rel|^2``, which differs by
        the wind's share ``F_drag . wind``).
    """

    t: np.ndarray
    path: np.ndarray
    landing_time: float | None
    landing_position: np.ndarray | None
    steps: int
    limit: float
    apex: float
    drag_work: float = 0.0
    out_of_steps: bool = False
    short: bool = False

    @property
    def landed(self) -> bool:
        return self.landing_time is not None


def drag_rate(velocity: tuple[float, float], design: Design) -> float:
    """``k`` in the drag acceleration ``-k v_rel``, 1/s, at ``velocity`` (m/s, over the ground):
    ``drag_rate_function(design)`` at that velocity."""
    return drag_rate_function(design)(*velocity)


def drag_rate_function(design: Design) -> Callable[[float, float], float]:
    """``k`` of ``design`` as a function of the velocity ``(vx, vy)`` over the ground alone, 1/s.

    ``analytic.aero.drag_rate`` (the law the analytic model's flight uses) with
    ``v_rel = v - (wind_speed, 0)``; the design's drag inputs are checked once here,
    not at each of the flight's steps.
    """
    env, proj = design.environment, design.projectile
    if proj.drag == "none" or env.air_density == 0.0:
        return lambda vx, vy: 0.0
    reynolds_number(0.0, proj.diameter, env.air_density, env.air_viscosity)   # checks the inputs
    drag_coefficient(proj.drag, 0.0, proj.drag_coefficient)
    model, wind = DRAG_MODELS.index(proj.drag), env.wind_speed
    constant = math.nan if proj.drag_coefficient is None else proj.drag_coefficient
    inputs = (proj.diameter, env.air_density, env.air_viscosity, constant, proj.drag_area, proj.mass, DRAG_TABLE)

    def rate(vx: float, vy: float) -> float:
        return aero_drag_rate(model, vx - wind, vy, *inputs)

    return rate


def swing_drag_function(design: Design) -> Callable[[float, float], tuple[float, float]] | None:
    """The drag on the projectile in stages 1-2 as a function of its velocity over the ground,
    ``(Fx, Fy)`` in N: the flight's (``drag_rate_function``) times its mass. None unless
    ``projectile.drag_during_swing``."""
    if not design.projectile.drag_during_swing:
        return None
    rate, mass, wind = drag_rate_function(design), design.projectile.mass, design.environment.wind_speed

    def force(vx: float, vy: float) -> tuple[float, float]:
        k = rate(vx, vy)
        return -mass * k * (vx - wind), -mass * k * vy

    return force


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
    c = 0.5 * env.air_density * cd * proj.drag_area / proj.mass
    return math.sqrt(env.gravity / c) if c > 0.0 else math.inf


def fly(design: Design, release_time: float, position: np.ndarray, velocity: np.ndarray,
        dt: float) -> Flight:
    """Step the free projectile in its own pymunk Space until its centre comes down to the target's
    level (``environment.target_height`` above the base; below it for a pit).

    The step is ``FLIGHT_STEP_MULTIPLE`` times the machine's ``dt``, or shorter
    where the drag is stiff (below).

    The drag is applied as a force each step. pymunk's step moves the position
    with the velocity of the previous half step, then updates the velocity
    with the force it is given: evaluating the drag at the velocity predicted
    for the position's instant (half a step on) keeps the scheme second order.
    Where the drag's time scale is short the step shrinks below ``dt``
    (``DRAG_STEP_FRACTION``); each velocity update then spans the mean of the
    steps on either side of its instant (a variable-step leapfrog, still second order).

    A flight that does not reach the target's level within ``analytic.limits.flight_time_limit``
    is returned unlanded (``landing_time`` None): the caller names it ``no_landing``.
    It ends as soon as landing in time is impossible: the rest of the fall
    takes at least ``height / max(w, fall_speed_bound)`` at falling speed ``w``.

    A raised target is reached once the centre is at or above its level; a flight that turns
    down (its centre lower than at the step before) without having reached it never will (the
    height only falls after the apex) and is returned unlanded and ``short``, as is one released
    below it and not rising. A flight released above a target it never rises to, or over a pit,
    lands where it comes down through the target's level.

    Parameters
    ----------
    release_time : s from firing; position (2,) m and velocity (2,) m/s at release.
    dt : the machine's fixed step, s; the flight's is ``FLIGHT_STEP_MULTIPLE`` times it.

    Raises
    ------
    EngineError
        The flight went non-finite.
    """
    g, h = design.environment.gravity, design.machine.pivot_height
    target = design.environment.target_height
    reached = target <= 0.0 or float(position[1]) + h >= target   # (a release is at or above the base)
    dt = FLIGHT_STEP_MULTIPLE * dt
    scheme = _Scheme(drag_rate_function(design), design.environment.wind_speed, g, design.projectile.mass, dt)
    space, body = _flight_space(design)
    step, start_work = _leapfrog_start(body, scheme, position, velocity)
    vx, vy = body.velocity
    kicks = 0.0
    work = [0.0]
    times, path = [release_time], [(float(position[0]), float(position[1]))]
    limit = flight_time_limit(float(position[1]) + h - target, float(velocity[1]), g)
    if not reached and float(velocity[1]) <= 0.0:   # below a raised target, not rising: its start is its apex
        return Flight(np.array(times), np.array(path), None, None, 0, limit, float(position[1]), 0.0, short=True)
    # The bound is 100 vacuum flights plus a minute: a projectile that only
    # drifts down at its terminal speed would take 1.3e6 steps of 50 us to
    # reach it (the 10 mg, 1 m balloon of crosscheck.cases), so the flight
    # stops once the fall speed bound proves it cannot land in time (the
    # balloon: after 3.3 ms of flight, falling 1.42 m at 2.08 cm/s at most
    # takes 68.3 s of flight, past its bound of 64.9 s). A real throw never
    # comes near.
    fall_cap = fall_speed_bound(design)
    # Time flown: steps of dt counted apart from shorter ones, so that a flight
    # at dt throughout has its times exactly release_time + n dt.
    steps = full_steps = 0
    short_time = 0.0
    taken = [0.0, 0.0]  # the last two steps
    advance = stepper(space)
    while True:
        kick = scheme.kick(vx, vy, step)
        set_force(body, *kick.force)
        before = (vx, vy)
        advance(step)
        steps += 1
        if step == dt:
            full_steps += 1
        else:
            short_time += step
        taken = [taken[1], step]
        step = kick.following
        x, y, vx, vy = motion(body)
        if not math.isfinite(x + y + vx + vy):
            raise EngineError(f"the flight went non-finite after {steps} steps of at most {dt:g} s")
        kick_work = -(kick.impulse[0] * 0.5 * (before[0] + vx) + kick.impulse[1] * 0.5 * (before[1] + vy))
        work.append(start_work + kicks + 0.5 * kick_work)
        kicks += kick_work
        flown = full_steps * dt + short_time
        times.append(release_time + flown)
        path.append((x, y))
        if y + h - target < 0.0 and reached:
            return _landed(times, path, work, steps, taken, limit, h, target)
        if not reached:
            reached = y + h >= target
            if not reached and y < path[-2][1]:   # turned down below the target
                path_array = np.array(path)
                return Flight(np.array(times), path_array, None, None, steps, limit,
                              highest(np.array(times), path_array[:, 1]), work[-1], short=True)
        out_of_steps = steps >= FLIGHT_STEP_LIMIT
        if out_of_steps or flown > limit or flown + (y + h - target) / max(-kick.fall_velocity, fall_cap) > limit:
            path_array = np.array(path)
            return Flight(np.array(times), path_array, None, None, steps, limit,
                          highest(np.array(times), path_array[:, 1]), work[-1], out_of_steps)


class _Kick(NamedTuple):
    """One step's velocity update: the force to apply over the step, N (drag and the share of gravity
    that stretches it to the mean of this step and the next), the drag's impulse, N s, the next
    step, s, and the vertical velocity predicted for the step's middle, m/s."""

    force: tuple[float, float]
    impulse: tuple[float, float]
    following: float
    fall_velocity: float


@dataclass(frozen=True)
class _Scheme:
    """The flight's leapfrog: the drag rate ``rate(vx, vy)`` (``drag_rate_function``, 1/s), the wind,
    m/s, gravity, m/s^2, the projectile's mass, kg, and its longest step ``dt``, s."""

    rate: Callable[[float, float], float]
    wind: float
    gravity: float
    mass: float
    dt: float

    def step_after(self, rate: float) -> float:
        """The step after a kick at the drag ``rate`` (1/s): ``dt``, or shorter where the drag's time
        scale is short (``DRAG_STEP_FRACTION``)."""
        return self.dt if rate * self.dt <= DRAG_STEP_FRACTION else DRAG_STEP_FRACTION / rate

    def predicted(self, vx: float, vy: float, ahead: float) -> tuple[float, float]:
        """The velocity ``ahead`` s on from ``(vx, vy)``, m/s, under drag and gravity (one Euler step)."""
        k = self.rate(vx, vy)
        return vx + -k * (vx - self.wind) * ahead, vy + (-k * vy - self.gravity) * ahead

    def kick(self, vx: float, vy: float, step: float) -> _Kick:
        """The velocity update of a ``step`` from the half-step velocity ``(vx, vy)``: the drag at the
        velocity predicted for the position's instant, half a step on."""
        mass, g, wind = self.mass, self.gravity, self.wind
        v_next = self.predicted(vx, vy, 0.5 * step)
        rate = self.rate(*v_next)
        ax, ay = -rate * (v_next[0] - wind), -rate * v_next[1]
        following = self.step_after(rate)
        drag_impulse = (-mass * rate * (v_next[0] - wind) * step, -mass * rate * v_next[1] * step)
        if following != step:
            # pymunk applies force and gravity over this step; the velocity
            # update must span the mean of this step and the next.
            scale = 0.5 * (step + following) / step
            ax, ay = ax * scale, (ay - g) * scale + g
            drag_impulse = (drag_impulse[0] * scale, drag_impulse[1] * scale)
        return _Kick((mass * ax, mass * ay), drag_impulse, following, v_next[1])


def _flight_space(design: Design) -> tuple[pymunk.Space, pymunk.Body]:
    """A Space of its own for the released projectile under gravity, and its body (its rotation
    decoupled: any moment will do)."""
    mass = design.projectile.mass
    space = pymunk.Space()
    space.gravity = (0.0, -design.environment.gravity)
    space.damping = 1.0
    body = pymunk.Body(mass, placeholder_moment(0.4 * mass, design.projectile.diameter / 2.0))
    space.add(body)
    return space, body


def _leapfrog_start(body: pymunk.Body, scheme: _Scheme, position: np.ndarray,
                    velocity: np.ndarray) -> tuple[float, float]:
    """Put the projectile at its release ``position`` with its velocity half a step after release
    (the leapfrog's start), and return that first step, s, and the drag's work over its half, J.

    The drag's work is taken over the ground velocity: each kick's impulse times the mean of the
    velocities it joins (exact for a kick); a sample holds half of its own kick's.
    """
    g, wind, mass = scheme.gravity, scheme.wind, scheme.mass
    step = scheme.step_after(scheme.rate(float(velocity[0]), float(velocity[1])))
    quarter = scheme.predicted(float(velocity[0]), float(velocity[1]), 0.25 * step)
    k = scheme.rate(*quarter)
    ax, ay = -k * (quarter[0] - wind), -k * quarter[1]
    body.position = (float(position[0]), float(position[1]))
    body.velocity = (velocity[0] + ax * 0.5 * step, velocity[1] + (ay - g) * 0.5 * step)
    vx, vy = body.velocity
    return step, -mass * 0.5 * step * (ax * 0.5 * (velocity[0] + vx) + ay * 0.5 * (velocity[1] + vy))


def _landed(times: list[float], path: list[tuple[float, float]], work: list[float], steps: int,
            taken: list[float], limit: float, pivot_height: float, target: float) -> Flight:
    """The flight whose last step took its centre below the target's level (``target`` m above the
    base), its last sample moved back to the landing instant (``events.crossing_fraction``): on the
    parabola through three equally spaced samples, or after a change of step (``taken``, the last two
    steps), on the line through two."""
    h = pivot_height
    samples = 3 if steps >= 2 and taken[0] == taken[1] else 2
    heights = [p[1] + h - target for p in path[-samples:]]
    fraction = crossing_fraction(tuple(heights))
    landing_position = interpolate(np.array(path[-samples:]), fraction)
    landing_position[1] = target - h
    landing_time = times[-2] + fraction * (times[-1] - times[-2])
    t = np.array(times[:-1] + [landing_time])
    flight_path = np.array(path[:-1] + [tuple(landing_position)])
    drag_work = work[-2] + fraction * (work[-1] - work[-2])
    return Flight(t, flight_path, landing_time, landing_position, steps, limit, highest(t, flight_path[:, 1]),
                  drag_work)
