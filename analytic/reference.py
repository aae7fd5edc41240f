"""The reference path: one shot of the analytic model, slide, swing, flight -> ``Shot``.

scipy's DOP853 steps the model's stages (``analytic.stages``: the same
right-hand sides and events the compiled path runs) from Python, under our
own event loop (``analytic.integrate``), and records histories, energies
and the sling tension for plots.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import minimize_scalar

from analytic import eom, outcome, stages
from analytic.aero import DRAG_TABLE
from analytic.design import Design
from analytic.geometry import projectile_state
from analytic.integrate import Event, IntegrationError, Segment, integrate
from analytic.limits import STAGE_STEP_LIMITS, flight_time_limit
from analytic.outcome import LiftoffFailure, Stage, Status
from analytic.parameters import Params, params
from analytic.result import EnergyBudget, Shot

#: Default integrator tolerances: a 100x tighter run changes the range by
#: 1.5e-10 relative on the paper's design and by at most 6.5e-9 where a
#: golf ball slows through its drag table's end (``analytic.bench``).
DEFAULT_RTOL = 1e-10
DEFAULT_ATOL = 1e-10
#: Sample spacing of the returned histories (stages 1-2, flight), s.
SWING_OUTPUT_STEP = 5e-4
FLIGHT_OUTPUT_STEP = 5e-3
#: Most samples a stage's history may hold: a stage whose time limit would take
#: more at the spacings above is sampled more sparsely, so that a machine slowed
#: a thousandfold (a weak gravity, a vast size) cannot fill the memory. At
#: 2e5 the spacings hold up to time limits of 100 s (stages 1-2; 17 s over the
#: paper's bounds) and 1000 s of flight (a vacuum flight of 9 s).
HISTORY_SAMPLE_LIMIT = 200_000

_LIFTOFF_FAILURES = {"under_tip": LiftoffFailure.UNDER_TIP, "arm_back": LiftoffFailure.ARM_BACK,
                     None: LiftoffFailure.TIME_LIMIT}


# A trial step of a stiff or extreme design may overflow or divide by zero: the
# integrator rejects such a step (or ends the shot as step_failed), as the
# compiled path does silently with its plain floats; numpy's scalars would warn.
@np.errstate(over="ignore", invalid="ignore", divide="ignore")
def simulate(design: Design, *, rtol: float = DEFAULT_RTOL, atol: float = DEFAULT_ATOL,
             histories: bool = True) -> Shot:
    """Simulate a shot of ``design`` through all three stages.

    Parameters
    ----------
    design : a validated ``Design``.
    rtol, atol : tolerances of the DOP853 integrator in every stage.
    histories : record the sampled histories, energies and sling tension. False
        gives only the summary (status, lift-off, release, landing, apex), the
        same as the fast path ``analytic.fast.simulate_fast``, about 5x sooner;
        the numbers are identical either way.

    Returns
    -------
    Shot
        A valid design that does not throw is a ``Shot`` whose ``status``
        names the failure and whose ``message`` explains it, never an exception.
    """
    p = params(design)
    output_step = max(SWING_OUTPUT_STEP, p.t_limit / HISTORY_SAMPLE_LIMIT) if histories else None
    machine = design.machine
    history = [] if histories else None
    segments = []
    reached = {}   # what the shot got to: lift-off, then release

    y1 = np.array([p.theta0, p.phi0, 0.0, 0.0])
    ddtheta0, normal0 = quietly(stages.fires, p, otherwise=(math.nan, math.nan))
    if not (math.isfinite(ddtheta0) and math.isfinite(normal0)):
        # The equations cannot be evaluated even at rest: the design's numbers over- or
        # underflow the model's products (a mass or length near the ends of the float range).
        if histories:
            history.append([(0.0, Stage.SLIDE, eom.slide_state(*y1, p), _tension(Stage.SLIDE, y1, p))])
        return _finish(design, p, history, segments, Status.STEP_FAILED,
                       outcome.step_failed_message(0.0, Stage.SLIDE))
    if not ddtheta0 < 0.0:
        if histories:
            history.append([(0.0, Stage.SLIDE, eom.slide_state(*y1, p), _tension(Stage.SLIDE, y1, p))])
        return _finish(design, p, history, segments, Status.NEVER_FIRES, outcome.never_fires_message(ddtheta0))

    stage = Stage.SLIDE
    try:
        # Stage 1: slide on the base until the normal force vanishes.
        if normal0 > 0.0:
            slide = _run(stage, p, 0.0, y1, p.t_limit, rtol, atol, output_step)
        else:  # the sling already pulls harder than the projectile's weight
            slide = Segment(np.zeros(1), y1[None, :], "liftoff", 0.0, y1, {})
        if histories:
            history.append(_history(Stage.SLIDE, slide, p))
        segments.append((Stage.SLIDE, slide))
        if slide.event != "liftoff":
            return _finish(design, p, history, segments, Status.NEVER_LIFTS_OFF,
                           outcome.never_lifts_off_message(_LIFTOFF_FAILURES[slide.event], p.t_limit))

        # Stage 2: free swing until release.
        stage = Stage.SWING
        reached["liftoff_time"] = slide.t_end
        swing_start = quietly(stages.swing_start, slide.y_end, p, otherwise=(math.nan,) * 6)
        swing = _run(stage, p, slide.t_end, np.array(swing_start), p.t_limit, rtol, atol, output_step)
        if histories:
            history.append(_history(Stage.SWING, swing, p)[1:])   # the first is lift-off, already recorded
        segments.append((Stage.SWING, swing))
        if swing.event == "hits_base":
            return _finish(design, p, history, segments, Status.HITS_BASE_BEFORE_RELEASE,
                           outcome.hits_base_message(swing.t_end), **reached)
        if swing.event is None:
            return _finish(design, p, history, segments, Status.NEVER_RELEASES,
                           outcome.never_releases_message(machine.release_rule, machine.release_angle,
                                                          p.t_limit), **reached)

        # Stage 3: flight.
        stage = Stage.FLIGHT
        release_time = swing.t_end
        start = np.array(quietly(stages.flight_start, swing.y_end, p, otherwise=(math.nan,) * 4))
        if not np.all(np.isfinite(start)):
            raise IntegrationError("non-finite release state", release_time)
        position, velocity = start[:2], start[2:]
        reached.update(release_time=release_time, release_position=position, release_velocity=velocity)
        t_max = release_time + flight_time_limit(position[1] + p.h, velocity[1], p.g)
        flight_step = (max(FLIGHT_OUTPUT_STEP, (t_max - release_time) / HISTORY_SAMPLE_LIMIT)
                       if histories else None)
        flight = _run(stage, p, release_time, start, t_max, rtol, atol, flight_step)
    except IntegrationError as error:
        if stage is not Stage.FLIGHT and error.segment is not None:
            # The motion up to the failure (the flight's is not kept, as for any shot that does not land).
            if histories:
                history.append(_history(stage, error.segment, p)[0 if stage is Stage.SLIDE else 1:])
            segments.append((stage, error.segment))
        return _finish(design, p, history, segments, Status.STEP_FAILED,
                       outcome.step_failed_message(error.time, stage, error.step_limit), **reached)
    if flight.event != "landing":
        return _finish(design, p, history, segments, Status.NO_LANDING,
                       outcome.no_landing_message(t_max - release_time), **reached)
    apex = max([position[1]] + [y[1] for _, y in flight.roots["apex"]])
    landing = flight.y_end[:2]
    return _finish(design, p, history, segments, Status.OK, outcome.thrown_message(landing[0]), **reached,
                   landing_time=flight.t_end, landing_position=landing, apex_height=apex + p.h,
                   flight_t=flight.t, flight_path=flight.y[:, :2])


# --------------------------------------------------------------------------- #
# A stage under scipy
# --------------------------------------------------------------------------- #

#: What Python's float arithmetic raises where the compiled path's IEEE
#: arithmetic (numba's ``error_model="numpy"``) quietly gives inf or NaN: a
#: division by zero, the sine of an overflowed angle, an overflowing power. A
#: trial stage of an extreme design can get there; the integrator then rejects
#: the step, or the shot ends as step_failed, on both paths alike.
FLOAT_ERRORS = (ArithmeticError, ValueError)


def quietly(function, *args, otherwise):
    """``function(*args)``, or ``otherwise`` where Python's floats raise one of ``FLOAT_ERRORS``."""
    try:
        return function(*args)
    except FLOAT_ERRORS:
        return otherwise


def _run(stage: Stage, p: Params, t0: float, y0: np.ndarray, t_end: float, rtol: float, atol: float,
         output_step: float | None) -> Segment:
    """Integrate ``stage`` from (t0, y0) until one of its terminal events or ``t_end``."""
    size = stages.STATE_SIZE[stage]

    def rhs(t, y):
        out = np.empty(size)
        try:
            stages.derivative(stage, y, p, DRAG_TABLE, out)
        except FLOAT_ERRORS:
            out[:] = math.nan   # the compiled path's inf or NaN: a rejected step
        return out

    return integrate(rhs, t0, y0, t_end, _events(stage, p), rtol=rtol, atol=atol, output_step=output_step,
                     max_steps=STAGE_STEP_LIMITS[stage])


def _events(stage: Stage, p: Params) -> tuple[Event, ...]:
    """The stage's events (``analytic.stages``) as the integrator's ``Event`` objects, in order."""
    def event(k: int, name: str) -> Event:
        # A value or condition Python cannot compute is NaN or false, as compiled: no root there.
        return Event(name, lambda t, y: quietly(stages.event_value, stage, k, y, p, otherwise=math.nan),
                     direction=stages.event_direction(stage, k),
                     armed=lambda t, y: quietly(stages.event_armed, stage, k, y, p, otherwise=False),
                     terminal=stages.event_terminal(stage, k))

    return tuple(event(k, name) for k, name in enumerate(stages.EVENT_NAMES[stage]))


# --------------------------------------------------------------------------- #
# Histories and the result
# --------------------------------------------------------------------------- #

def _history(stage: Stage, segment: Segment, p: Params):
    """Rows ``(t, stage, (theta, phi, psi, theta', phi', psi'), sling tension)`` of a segment."""
    full = (lambda y: eom.slide_state(*y, p)) if stage is Stage.SLIDE else tuple
    return [(t, stage, full(y), _tension(stage, y, p)) for t, y in zip(segment.t, segment.y, strict=True)]


def _tension(stage: Stage, y: np.ndarray, p: Params) -> float:
    """Sling tension at a stage-1 or stage-2 state (eq. 5.2), N (NaN where ``FLOAT_ERRORS`` say
    it cannot be computed)."""
    return quietly(_tension_at, stage, y, p, otherwise=math.nan)


def _tension_at(stage: Stage, y: np.ndarray, p: Params) -> float:
    if stage is Stage.SLIDE:
        theta, _, psi, dtheta, _, dpsi = eom.slide_state(*y, p)
        ddtheta, _, normal = eom.slide_accelerations(*y, p)
        return eom.sling_tension(theta, psi, dtheta, dpsi, ddtheta, normal, p)
    ddtheta = eom.swing_accelerations(*y, p)[0]
    return eom.sling_tension(y[0], y[2], y[3], y[5], ddtheta, 0.0, p)


def _smallest_tension(t: np.ndarray, stage: np.ndarray, tension: np.ndarray, segments, p: Params) -> float:
    """The minimum of the sling tension, refined between the output samples.

    The samples are ``SWING_OUTPUT_STEP`` apart while a push of the sling can
    last about a millisecond, so the sampled minimum is refined by a bounded
    scalar minimisation on the integrator's continuous solution around it.
    """
    i = int(np.argmin(tension))
    stage_i = Stage(stage[i])
    if stage_i not in dict(segments):   # never fired: the rest state alone
        return float(tension[i])
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
    states = np.array([row[2] for row in rows])     # (n, 6): q, then q'
    tension = np.array([row[3] for row in rows])

    v_machine0, v_projectile0 = eom.potential_energy(*states[0, :3], p)
    budget = np.empty((len(t), 2))
    path = np.empty((len(t), 2))
    for i, (theta, phi, psi, dtheta, dphi, dpsi) in enumerate(states):
        v_m, v_p = eom.potential_energy(theta, phi, psi, p)
        k_m, k_p = eom.kinetic_energy(theta, phi, psi, dtheta, dphi, dpsi, p)
        budget[i] = (k_m + v_m - v_machine0, k_p + v_p - v_projectile0)
        path[i] = projectile_state(theta, psi, dtheta, dpsi, p.La, p.Ls)[:2]
    energy = EnergyBudget(projectile=budget[:, 1], machine=budget[:, 0], total=budget.sum(axis=1))
    released = None
    if fields.get("release_time") is not None:
        released = v_machine0 - eom.potential_energy(*states[-1, :3], p)[0]
    return Shot(design, status, message, t=t, stage=stage, q=states[:, :3], qdot=states[:, 3:], path=path,
                sling_tension=tension, energy=energy,
                # A machine that never moves (never fires, or its equations fail at rest) holds
                # its projectile statically: no tension is defined.
                min_sling_tension=None if not segments else _smallest_tension(t, stage, tension, segments, p),
                counterweight_energy_released=released, **fields)
