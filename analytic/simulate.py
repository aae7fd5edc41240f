"""Simulate one shot of the analytic model: slide, swing, flight -> ``Shot``."""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import minimize_scalar

from analytic import aero
from analytic.design import Design, initial_angles, release_function, swing_time_limit
from analytic.eom import (
    OutOfReach,
    Params,
    arm_direction,
    kinetic_energy,
    params,
    potential_energy,
    projectile_state,
    slide_accelerations,
    slide_full_state,
    slide_kinematics,
    slide_rhs,
    sling_direction,
    sling_tension,
    swing_accelerations,
    swing_rhs,
)
from analytic.integrate import Event, IntegrationError, Segment, integrate
from analytic.result import EnergyBudget, Shot, Stage, Status

#: Default integrator tolerances: tight enough that a 100x tighter run changes
#: the range by < 1e-7 relative (tests/test_analytic_convergence.py).
DEFAULT_RTOL = 1e-10
DEFAULT_ATOL = 1e-10
#: Sample spacing of the returned histories (stages 1-2, flight), s.
SWING_OUTPUT_STEP = 5e-4
FLIGHT_OUTPUT_STEP = 5e-3
#: Stage 1 ends as never_lifts_off once the sling is this close to vertical
#: (|sin beta|, i.e. within about 0.57 deg): the projectile is being dragged
#: under the arm tip and the reduced equations become singular.
SLING_VERTICAL_LIMIT = 1e-2


def simulate(design: Design, *, rtol: float = DEFAULT_RTOL, atol: float = DEFAULT_ATOL,
             histories: bool = True) -> Shot:
    """Simulate a shot of ``design`` through all three stages.

    Never raises for a valid design that fails to throw: the returned
    ``Shot.status`` names the failure and ``Shot.message`` explains it.

    Parameters
    ----------
    design : a validated ``Design``.
    rtol, atol : tolerances of the DOP853 integrator in every stage.
    histories : record the sampled histories, energies and sling tension. False
        gives only the summary (status, lift-off, release, landing, apex), the
        same as the fast path ``analytic.fast.simulate_fast``, about 5x sooner;
        the numbers are identical either way.
    """
    output_step = SWING_OUTPUT_STEP if histories else None
    flight_step = FLIGHT_OUTPUT_STEP if histories else None
    p = params(design)
    machine = design.machine
    q0 = initial_angles(machine)
    t_limit = swing_time_limit(machine, p.g)

    ddtheta0, _, normal0 = slide_accelerations(q0[0], q0[1], 0.0, 0.0, p)
    if ddtheta0 >= 0.0:
        return Shot(design, Status.NEVER_FIRES, never_fires_message(ddtheta0),
                    t=np.zeros(1), stage=np.array([Stage.SLIDE]), q=q0[None, :], qdot=np.zeros((1, 3)))

    # Stage 1: slide on the base until the normal force vanishes.
    y1 = np.array([q0[0], q0[1], 0.0, 0.0])
    if normal0 > 0.0:
        slide = integrate(lambda t, y: _guarded_slide_rhs(t, y, p), 0.0, y1, t_limit,
                          _slide_events(p), rtol=rtol, atol=atol, output_step=output_step)
    else:  # the sling already pulls harder than the projectile's weight
        slide = Segment(np.zeros(1), y1[None, :], "liftoff", 0.0, y1, {})
    history = [_slide_history(slide, p)] if histories else None
    segments = [(Stage.SLIDE, slide)]
    if slide.event != "liftoff":
        return _finish(design, p, history, segments, Status.NEVER_LIFTS_OFF,
                       never_lifts_off_message(slide.event, t_limit))

    # Stage 2: free swing until release.
    liftoff_time = slide.t_end
    q, qdot = slide_full_state(slide.y_end, p)
    swing = integrate(lambda t, y: swing_rhs(t, y, p), liftoff_time, np.concatenate([q, qdot]),
                      t_limit, _swing_events(design, p), rtol=rtol, atol=atol,
                      output_step=output_step)
    if histories:
        history.append(_swing_history(swing, p))
    segments.append((Stage.SWING, swing))
    if swing.event == "hits_base":
        return _finish(design, p, history, segments, Status.HITS_BASE_BEFORE_RELEASE,
                       hits_base_message(swing.t_end), liftoff_time=liftoff_time)
    if swing.event is None:
        return _finish(design, p, history, segments, Status.NEVER_RELEASES,
                       never_releases_message(machine, t_limit), liftoff_time=liftoff_time)

    # Stage 3: flight.
    release_time = swing.t_end
    position, velocity = projectile_state(swing.y_end[:3], swing.y_end[3:], p)
    flight = _fly(design, release_time, position, velocity, rtol, atol, flight_step)
    apex = max([position[1]] + [y[1] for _, y in flight.roots["apex"]])
    landing = flight.y_end[:2]
    return _finish(design, p, history, segments, Status.OK, thrown_message(landing[0]),
                   liftoff_time=liftoff_time,
                   release_time=release_time, release_position=position, release_velocity=velocity,
                   landing_time=flight.t_end, landing_position=landing, apex_height=apex + p.h,
                   flight_t=flight.t, flight_path=flight.y[:, :2])


# --------------------------------------------------------------------------- #
# Events
# --------------------------------------------------------------------------- #

def _guarded_slide_rhs(t: float, y: np.ndarray, p: Params) -> np.ndarray:
    """Stage-1 derivative; NaN where a trial stage of a step overshoots the sling's reach.

    With a very short sling the tip can rise past the sling's length within one
    trial step, before the ``under_tip`` event (checked on accepted steps) can
    end the stage. A non-finite derivative makes DOP853 reject the step and
    retry with a fifth of it, so accepted states always lie within reach.
    """
    try:
        return slide_rhs(t, y, p)
    except OutOfReach:
        return np.full(4, np.nan)


def _slide_events(p: Params) -> tuple[Event, ...]:
    def sling_off_vertical(t, y):
        # |sin beta| from the constraint, defined (zero) even beyond the reach.
        cos_beta = -(p.h + p.La * math.cos(y[0])) / p.Ls
        return math.sqrt(max(0.0, 1.0 - cos_beta * cos_beta)) - SLING_VERTICAL_LIMIT

    def normal(t, y):
        if sling_off_vertical(t, y) <= 0.0:
            return 1.0  # no lift-off here: under the tip, the under_tip event ends the stage
        return slide_accelerations(y[0], y[1], y[2], y[3], p)[2]

    def tip_height(t, y):
        return p.La * math.cos(y[0]) + p.h

    # under_tip first: in a tie the earlier-listed event is reported.
    return (Event("under_tip", sling_off_vertical, direction=-1),
            Event("liftoff", normal, direction=-1),
            Event("arm_back", tip_height, direction=-1))


def _swing_events(design: Design, p: Params) -> tuple[Event, ...]:
    machine = design.machine

    def release(t, y):
        return release_function(machine, arm_direction(y[:3]), sling_direction(y[:3]),
                                projectile_state(y[:3], y[3:], p)[1])

    def height_above_base(t, y):
        return p.La * math.cos(y[0]) + p.Ls * math.cos(y[0] + y[2]) + p.h

    return (Event("release", lambda t, y: release(t, y)[0], direction=+1,
                  armed=lambda t, y: release(t, y)[1]),
            Event("hits_base", height_above_base, direction=-1))


# --------------------------------------------------------------------------- #
# Flight
# --------------------------------------------------------------------------- #

def flight_rhs(t: float, y: np.ndarray, design: Design) -> np.ndarray:
    """Point-mass flight with quadratic drag on the air-relative velocity, y = [x, y, vx, vy].

    ``a = -g e_y - (rho A / 2 m) Cd(Re) |v - w| (v - w)`` with ``w = (wind_speed, 0)``.
    """
    env, proj = design.environment, design.projectile
    vx_rel = y[2] - env.wind_speed
    vy = y[3]
    speed = math.hypot(vx_rel, vy)
    factor = aero.drag_force_factor(proj.drag, speed, proj.diameter, env.air_density,
                                    env.air_viscosity, proj.drag_coefficient)
    k = env.air_density * proj.frontal_area / (2.0 * proj.mass) * factor
    return np.array([y[2], vy, -k * vx_rel, -env.gravity - k * vy])


def _fly(design: Design, t0: float, position: np.ndarray, velocity: np.ndarray,
         rtol: float, atol: float, output_step: float | None) -> Segment:
    g, h = design.environment.gravity, design.machine.pivot_height
    # No drag and no wind: the flight would take this long; drag shortens the
    # climb and at worst stretches the fall to the terminal speed, so a
    # hundred times that (plus a minute) is a bound that is never reached.
    vacuum_time = (velocity[1] + math.sqrt(velocity[1] ** 2 + 2.0 * g * (position[1] + h))) / g
    t_max = t0 + 100.0 * vacuum_time + 60.0
    events = (Event("landing", lambda t, y: y[1] + h, direction=-1),
              Event("apex", lambda t, y: y[3], direction=-1, terminal=False))
    flight = integrate(lambda t, y: flight_rhs(t, y, design), t0, np.concatenate([position, velocity]),
                       t_max, events, rtol=rtol, atol=atol, output_step=output_step)
    if flight.event != "landing":
        raise IntegrationError(no_landing_message(t_max - t0))
    return flight


# --------------------------------------------------------------------------- #
# What each outcome says (shared with the fast path, ``analytic.fast``)
# --------------------------------------------------------------------------- #

def never_fires_message(ddtheta0: float) -> str:
    return (f"the counterweight cannot lift the arm: at rest the arm's angular "
            f"acceleration is {ddtheta0:+.4g} rad/s^2, not clockwise (negative)")


def never_lifts_off_message(event: str | None, t_limit: float) -> str:
    """``event``: the stage-1 event that ended the slide (``under_tip``, ``arm_back``), None at the time limit."""
    reason = {"under_tip": "it was dragged under the arm tip (the sling turned vertical)",
              "arm_back": "the arm swung back down to the base",
              None: f"it was still on the base after the time limit of {t_limit:.3g} s"}[event]
    return f"the projectile never lifts off: {reason}"


def hits_base_message(t: float) -> str:
    return (f"the projectile came back down to the base at t = {t:.4f} s "
            f"before the release condition was met")


def never_releases_message(machine, t_limit: float) -> str:
    rule = "velocity direction" if machine.release_rule == "velocity" else "sling-to-arm angle"
    return (f"the {rule} never reached the release angle of "
            f"{math.degrees(machine.release_angle):g} deg within the time limit of {t_limit:.3g} s")


def thrown_message(range_: float) -> str:
    return "thrown, but the projectile landed behind the pivot" if range_ < 0.0 else "thrown"


def no_landing_message(flight_time_limit: float) -> str:
    return f"the projectile did not come down within {flight_time_limit:.3g} s of flight"


# --------------------------------------------------------------------------- #
# Histories and the result
# --------------------------------------------------------------------------- #

def _slide_history(segment: Segment, p: Params):
    return [(t, Stage.SLIDE, *slide_full_state(y, p), _tension(Stage.SLIDE, y, p))
            for t, y in zip(segment.t, segment.y, strict=True)]


def _swing_history(segment: Segment, p: Params):
    # The first sample is the lift-off instant, already the slide's last sample.
    return [(t, Stage.SWING, y[:3], y[3:], _tension(Stage.SWING, y, p))
            for t, y in zip(segment.t[1:], segment.y[1:], strict=True)]


def _tension(stage: Stage, y: np.ndarray, p: Params) -> float:
    """Sling tension at a stage-1 or stage-2 state (eq. 5.2), N."""
    if stage is Stage.SLIDE:
        q, qdot = slide_full_state(y, p)
        kin = slide_kinematics(y[0], y[2], p)
        ddtheta, ddphi, normal = slide_accelerations(y[0], y[1], y[2], y[3], p)
        return sling_tension(q, qdot, (ddtheta, ddphi, kin.s * ddtheta + kin.c), normal, p)
    q, qdot = y[:3], y[3:]
    return sling_tension(q, qdot, swing_accelerations(q, qdot, p), 0.0, p)


def _smallest_tension(t: np.ndarray, stage: np.ndarray, tension: np.ndarray, segments, p: Params) -> float:
    """The minimum of the sling tension, refined between the output samples.

    The samples are ``SWING_OUTPUT_STEP`` apart while a push of the sling can
    last about a millisecond, so the sampled minimum is refined by a bounded
    scalar minimisation on the integrator's continuous solution around it.
    """
    i = int(np.argmin(tension))
    stage_i = Stage(stage[i])
    solution = dict(segments)[stage_i].solution
    same = np.flatnonzero(stage == stage_i)
    low, high = t[max(i - 1, same[0])], t[min(i + 1, same[-1])]
    if solution is None or high <= low:
        return float(tension[i])
    low, high = max(low, solution.t_min), min(high, solution.t_max)
    best = minimize_scalar(lambda s: _tension(stage_i, solution(s), p), bounds=(low, high),
                           method="bounded", options={"xatol": 1e-9})
    return float(min(best.fun, tension[i]))


def _finish(design: Design, p: Params, history, segments, status: Status, message: str, **fields) -> Shot:
    if history is None:   # summary only
        fields.pop("flight_t", None)
        fields.pop("flight_path", None)
        return Shot(design, status, message, **fields)
    rows = [row for part in history for row in part]
    t = np.array([row[0] for row in rows])
    stage = np.array([int(row[1]) for row in rows])
    q = np.array([row[2] for row in rows])
    qdot = np.array([row[3] for row in rows])
    tension = np.array([row[4] for row in rows])

    v_machine0, v_projectile0 = potential_energy(q[0], p)
    budget = np.empty((len(t), 2))
    path = np.empty((len(t), 2))
    for i in range(len(t)):
        v_m, v_p = potential_energy(q[i], p)
        k_m, k_p = kinetic_energy(q[i], qdot[i], p)
        budget[i] = (k_m + v_m - v_machine0, k_p + v_p - v_projectile0)
        path[i] = projectile_state(q[i], qdot[i], p)[0]
    energy = EnergyBudget(projectile=budget[:, 1], machine=budget[:, 0], total=budget.sum(axis=1))
    released = None
    if fields.get("release_time") is not None:
        released = v_machine0 - potential_energy(q[-1], p)[0]
    return Shot(design, status, message, t=t, stage=stage, q=q, qdot=qdot, path=path,
                sling_tension=tension, energy=energy,
                min_sling_tension=_smallest_tension(t, stage, tension, segments, p),
                counterweight_energy_released=released, **fields)
