"""The reference path: one shot of the analytic model, slide, swing, flight -> ``Shot``.

scipy's DOP853 steps the model's stages (``analytic.stages``: the same
right-hand sides and events the compiled path runs) from Python, under our
own event loop (``analytic.reference.ode``), and records histories, energies
and the sling tension for plots.
"""

from __future__ import annotations

import functools
import math

import numpy as np
from scipy.integrate import OdeSolution

from analytic import eom, friction, outcome, sequence, stages
from analytic.aero import DRAG_TABLE
from analytic.design import Design
from analytic.geometry import projectile_state
from analytic.reference.ode import Event, IntegrationError, Segment, integrate
from analytic.limits import DEFAULT_ATOL, DEFAULT_RTOL, STAGE_STEP_LIMITS, flight_time_limit
from analytic.outcome import Stage, Status
from analytic.parameters import Params, params
from analytic.reference.loads import (FLOAT_ERRORS, NO_PEAKS, peak_fields, pieces_peaks, quietly, smallest_tension,
                                      sling_tension_at, stage_rhs)
from analytic.result import EnergyBudget, History, Shot

#: Sample spacing of the returned histories (stages 1-2, flight), s.
SWING_OUTPUT_STEP = 5e-4
FLIGHT_OUTPUT_STEP = 5e-3
#: Most samples a stage's history may hold: a stage whose time limit would take
#: more at the spacings above is sampled more sparsely, so that a machine slowed
#: a thousandfold (a weak gravity, a vast size) cannot fill the memory. At
#: 2e5 the spacings hold up to time limits of 100 s (stages 1-2; 17 s over the
#: paper's bounds) and 1000 s of flight (a vacuum flight of 9 s).
HISTORY_SAMPLE_LIMIT = 200_000

#: Peak loads before any is found: (N_LOADS, 2) of -inf (value, time).


# A trial step of a stiff or extreme design may overflow or divide by zero: the
# integrator rejects such a step (or ends the shot as step_failed), as the
# compiled path does silently with its plain floats; numpy's scalars would warn.
@np.errstate(over="ignore", invalid="ignore", divide="ignore")
def simulate(design: Design, *, rtol: float = DEFAULT_RTOL, atol: float = DEFAULT_ATOL,
             histories: bool = True, loads: bool = True, after_release: bool | None = None,
             sample_step: float | None = None, flight_sample_step: float | None = None,
             sampled_loads: bool = True) -> Shot:
    """Simulate a shot of ``design`` through all three stages.

    Parameters
    ----------
    design : a validated ``Design``.
    rtol, atol : tolerances of the DOP853 integrator in every stage.
    histories : record the sampled histories, energies and sling tension. False
        gives only the summary (status, lift-off, release, landing, apex), the
        same as the fast path ``analytic.fast.simulate_fast``, about 5x sooner;
        the numbers are identical either way.
    loads : find the peak loads (on the continuous solution of stages 1-2: about a
        third more than a summary without them); False leaves them None.
    after_release : on a rolling frame, run the machine on from release to landing for
        the frame's place there (``frame_landing_*``; stage 4, friction included: with
        friction several times the cost of a summary). None: with histories only, so
        that a summary costs what it did and holds the fast path's numbers; False
        leaves them None. A fixed frame's are 0 either way.
    sample_step, flight_sample_step : spacing of the histories of stages 1-2 and of the flight, s
        (positive; None: ``SWING_OUTPUT_STEP``, ``FLIGHT_OUTPUT_STEP``). The integrator's steps,
        and so every sample two spacings share, are the same either way (the samples are the
        continuous solution read at other times). The summary is the same but for what is read
        off the samples of stages 1-2:
        ``min_ground_force``, ``max_frame_speed`` and the jump warning (a sampled extreme), and
        ``min_sling_tension``, refined from the smallest sample (the same minimum where
        the refinement finds it). A coarser spacing is for a caller that only draws the motion.
    sampled_loads : record ``History.axle_load``, ``hinge_load`` and
        ``projectile_acceleration`` on every sample (each a solve of the model's loads, in
        Python); False leaves them None and changes nothing else.

    Returns
    -------
    Shot
        A valid design that does not throw is a ``Shot`` whose ``status``
        names the failure and whose ``message`` explains it, never an exception.
        ``energy_dissipated`` holds the work each loss took (friction through
        stages 1-2, integrated with the motion; the drag's in flight, on the
        flight's steps), with histories or without; with histories
        ``energy.dissipated`` holds the friction's on every sample.
    """
    swing_spacing = spacing_argument("sample_step", sample_step, SWING_OUTPUT_STEP)
    flight_spacing = spacing_argument("flight_sample_step", flight_sample_step, FLIGHT_OUTPUT_STEP)
    p = params(design)
    output_step = max(swing_spacing, p.t_limit / HISTORY_SAMPLE_LIMIT) if histories else None
    finish = functools.partial(_finish_shot, sampled_loads=sampled_loads)
    machine = design.machine
    history = [] if histories else None
    segments = []
    reached = {}   # what the shot got to: lift-off, then release

    y1 = np.empty(stages.state_size(Stage.SLIDE, p))
    stages.slide_start(p, y1)
    ddtheta0, normal0 = quietly(stages.fires, p, otherwise=(math.nan, math.nan))
    if not (math.isfinite(ddtheta0) and math.isfinite(normal0)):
        # The equations cannot be evaluated even at rest: the design's numbers over- or
        # underflow the model's products (a mass or length near the ends of the float range).
        if histories:
            history.append(_history(Stage.SLIDE, Segment(np.zeros(1), y1[None, :], None, 0.0, y1, {}), p))
        return finish(design, p, history, segments, Status.STEP_FAILED,
                       outcome.failure_message(Status.STEP_FAILED, detail=Stage.SLIDE))
    if not ddtheta0 < 0.0:
        if histories:
            history.append(_history(Stage.SLIDE, Segment(np.zeros(1), y1[None, :], None, 0.0, y1, {}), p))
        balance = ((*friction.rest_balance(p), outcome.friction_holders(*friction.holders(p)))
                   if friction.lossy(p) else ())
        return finish(design, p, history, segments, Status.NEVER_FIRES,
                       outcome.failure_message(Status.NEVER_FIRES, fires=(ddtheta0, *balance)))

    stage = Stage.SLIDE
    switches = [0]   # friction's mode switches so far (stages.MODE_SWITCH_LIMIT)
    try:
        # Stage 1: slide on the base until the normal force vanishes.
        if normal0 > 0.0:
            pieces, action, _, detail = _run_modes(stage, p, 0.0, y1, p.t_limit, rtol, atol, output_step,
                                                   p.drag_swing > 0.0, switches)
            peaks = pieces_peaks(stage, pieces, p, loads, NO_PEAKS, rtol, atol)
            slide = _merge(pieces)
        else:  # the sling already pulls harder than the projectile's weight
            slide = Segment(np.zeros(1), y1[None, :], "liftoff", 0.0, y1, {})
            peaks, action = NO_PEAKS, sequence.NEXT_STAGE
        if histories:
            history.append(_history(Stage.SLIDE, slide, p))
        segments.append((Stage.SLIDE, slide))
        if action == sequence.FINISHED:
            return finish(design, p, history, segments, Status.NEVER_LIFTS_OFF,
                           outcome.failure_message(Status.NEVER_LIFTS_OFF, detail=detail, time_limit=p.t_limit),
                           **peak_fields(peaks))

        # Stage 2: free swing until release.
        stage = Stage.SWING
        reached["liftoff_time"] = slide.t_end
        y2 = np.empty(stages.state_size(stage, p))
        try:
            stages.swing_start(slide.y_end, p, y2)
        except FLOAT_ERRORS:
            y2[:] = math.nan   # the integrator ends the stage as step_failed
        pieces, action, status, _ = _run_modes(stage, p, slide.t_end, y2, p.t_limit, rtol, atol, output_step,
                                               p.drag_swing > 0.0, switches)
        peaks = pieces_peaks(stage, pieces, p, loads, peaks, rtol, atol)
        swing = _merge(pieces)
        reached.update(peak_fields(peaks))
        if histories:
            history.append(_history(Stage.SWING, swing, p)[1:])   # the first is lift-off, already recorded
        segments.append((Stage.SWING, swing))
        if status == sequence.HITS_BASE:
            return finish(design, p, history, segments, Status.HITS_BASE_BEFORE_RELEASE,
                           outcome.failure_message(Status.HITS_BASE_BEFORE_RELEASE, time=swing.t_end), **reached)
        if action == sequence.FINISHED:
            return finish(design, p, history, segments, Status.NEVER_RELEASES,
                           outcome.failure_message(Status.NEVER_RELEASES, time_limit=p.t_limit,
                                                   release=(machine.release_rule, machine.release_angle)), **reached)

        # Stage 3: flight.
        stage = Stage.FLIGHT
        release_time = swing.t_end
        start = np.array(quietly(stages.flight_start, swing.y_end, p, otherwise=(math.nan,) * 4))
        if not np.all(np.isfinite(start)):
            raise IntegrationError("non-finite release state", release_time)
        position, velocity = start[:2], start[2:]
        frame_x, frame_v = stages.frame_state(swing.y_end, p)
        reached.update(release_time=release_time, release_position=position, release_velocity=velocity,
                       frame_release_displacement=frame_x, frame_release_velocity=frame_v)
        t_max = release_time + flight_time_limit(position[1] + p.h, velocity[1], p.g)
        flight_step = (max(flight_spacing, (t_max - release_time) / HISTORY_SAMPLE_LIMIT)
                       if histories else None)
        # The continuous solution is kept for the drag's work (the steps are the same either way).
        flight = (_landed(start, release_time) if sequence.lands_at_release(position[1] + p.h, velocity[1])
                  else _run(stage, p, release_time, start, t_max, rtol, atol, flight_step, True))
    except IntegrationError as error:
        if stage is not Stage.FLIGHT and error.segment is not None:
            # The motion up to the failure (the flight's is not kept, as for any shot that does not land).
            if histories:
                history.append(_history(stage, error.segment, p)[0 if stage is Stage.SLIDE else 1:])
            segments.append((stage, error.segment))
        return finish(design, p, history, segments, Status.STEP_FAILED,
                       outcome.failure_message(Status.STEP_FAILED, time=error.time, detail=stage,
                                               step_limit=error.step_limit), **reached)
    reached["drag_work"] = drag_work(flight, p)
    _, status, _ = sequence.stretch_end(Stage.FLIGHT, _code(Stage.FLIGHT, flight), switches[0])
    if status == sequence.NO_LANDING:
        return finish(design, p, history, segments, Status.NO_LANDING,
                       outcome.failure_message(Status.NO_LANDING, time=t_max - release_time), **reached)
    apex = max([position[1]] + [y[1] for _, y in flight.roots["apex"]])
    landing = flight.y_end[:2]
    if not p.rolling:
        reached.update(frame_landing_displacement=0.0, frame_landing_velocity=0.0, after_release_speed=0.0)
    elif histories if after_release is None else after_release:
        reached.update(_frame_after_release(p, swing.y_end, release_time, flight.t_end, rtol, atol,
                                            reached["frame_release_displacement"], velocity[0], output_step))
    return finish(design, p, history, segments, Status.OK, outcome.thrown_message(landing[0]), **reached,
                   landing_time=flight.t_end, landing_position=landing, apex_height=apex + p.h,
                   flight_t=flight.t, flight_path=flight.y[:, :2])


def spacing_argument(name: str, value: float | None, default: float) -> float:
    """A history spacing argument of ``simulate``, s: ``default`` for None, else a positive number."""
    if value is None:
        return default
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0.0 < value < math.inf:
        raise ValueError(f"{name} = {value!r}: must be a positive number of seconds")
    return float(value)


def _frame_after_release(p: Params, release_state: np.ndarray, release_time: float, landing_time: float,
                         rtol: float, atol: float, release_x: float, projectile_vx: float,
                         output_step: float | None) -> dict:
    """The frame at landing (and, with ``output_step``, its largest speed after release): the machine
    swings on alone, its friction sticking and slipping (stage 4, section 10.9).

    A rolling frame only (a fixed one's machine moves nothing the shot reports after
    release). Zero momentum before release leaves the machine with the projectile's
    opposite, ``-mP vx``, after it. A run that fails leaves the frame's landing
    unreported, with a warning.
    """
    m = stages.machine_params(p)
    start = np.empty(stages.state_size(stages.MACHINE, m))
    try:
        stages.machine_start(release_state, m, start)
        pieces, _, _, _ = _run_modes(stages.MACHINE, m, release_time, start, landing_time, rtol, atol, output_step,
                                     False, [0])
    except (IntegrationError, *FLOAT_ERRORS) as error:
        return {"after_release_warning": after_release_warning(str(error))}
    machine = _merge(pieces)
    momentum = -p.mP * projectile_vx
    frames = np.array([stages.machine_frame(y, m, momentum, release_time, start, release_x, t)
                       for t, y in zip(machine.t, machine.y, strict=True)])
    return {"frame_landing_displacement": float(frames[-1, 0]), "frame_landing_velocity": float(frames[-1, 1]),
            "after_release_speed": float(np.max(np.abs(frames[:, 1])))}


def after_release_warning(why: str) -> str:
    """What a failed run of the machine after release means for the result."""
    return (f"the rolling machine's motion after release could not be integrated ({why}), so the frame's "
            f"place at landing is not reported")


# --------------------------------------------------------------------------- #
# A stage under scipy
# --------------------------------------------------------------------------- #

def _run(stage: Stage, p: Params, t0: float, y0: np.ndarray, t_end: float, rtol: float, atol: float,
         output_step: float | None, continuous: bool) -> Segment:
    """Integrate ``stage`` from (t0, y0) until one of its terminal events or ``t_end``; ``continuous``:
    keep the continuous solution."""
    return integrate(stage_rhs(stage, p, len(y0)), t0, y0, t_end, _events(stage, p), rtol=rtol, atol=atol,
                     output_step=output_step, continuous=continuous, max_steps=STAGE_STEP_LIMITS[stage])


def _landed(start: np.ndarray, t: float) -> Segment:
    """The flight of a projectile that lands where it is released (``sequence.lands_at_release``):
    one state, ended by the landing event at ``t``."""
    state = start.copy()
    return Segment(np.array([t]), state[None, :].copy(), "landing", t, state, {"apex": []},
                   step_t=np.array([t]), step_y=state[None, :].copy(), step_f=np.full((1, len(state)), np.nan),
                   steps=())


def _code(stage: Stage, piece: Segment) -> int:
    """How a stretch ended, as ``analytic.sequence`` numbers it: its event's index or ``REACHED_END``."""
    return sequence.REACHED_END if piece.event is None else stages.EVENT_NAMES[stage].index(piece.event)


def _run_modes(stage: Stage, p: Params, t0: float, y0: np.ndarray, t_end: float, rtol: float, atol: float,
               output_step: float | None, continuous: bool, switches: list[int]) -> tuple[list[Segment], int, int, int]:
    """``_run`` in stretches, switching the friction modes between them, until
    ``analytic.sequence.stretch_end`` says the stage is over.

    Returns the pieces integrated, one per mode (one for a design without
    friction), and ``stretch_end``'s ``(action, status, detail)`` at the last.
    ``switches`` ([count]) counts the switches of the whole shot; past
    ``stages.MODE_SWITCH_LIMIT`` the shot fails (``IntegrationError``).
    """
    pieces = []
    t, y = t0, y0
    while True:
        piece = _run(stage, p, t, y, t_end, rtol, atol, output_step, continuous)
        pieces.append(piece)
        code = _code(stage, piece)
        action, status, detail = sequence.stretch_end(int(stage), code, switches[0])
        if status == sequence.STEP_FAILED:
            raise IntegrationError(f"friction switched modes more than {stages.MODE_SWITCH_LIMIT} times",
                                   piece.t_end)
        if action != sequence.SWITCH_MODE:
            return pieces, action, status, detail
        switches[0] += 1
        t, y = piece.t_end, piece.y_end.copy()
        stages.switch_mode(int(stage), code, y, p)


def _merge(pieces: list[Segment]) -> Segment:
    """One ``Segment`` of a stage's pieces (``_run_modes``): each piece's last sample is dropped for
    the next one's first (the same instant, after the switch); the continuous solutions are joined."""
    if len(pieces) == 1:
        return pieces[0]
    last = pieces[-1]

    def joined(name):
        parts = [getattr(piece, name)[:-1] for piece in pieces[:-1]] + [getattr(last, name)]
        return None if any(part is None for part in parts) else np.concatenate(parts)

    ts, interpolants = [], []
    for piece in pieces:
        solution = piece.solution
        if solution is None or len(solution.interpolants) == 0:
            continue
        breaks, parts = list(solution.ts), list(solution.interpolants)
        while len(parts) > 1 and breaks[-2] >= piece.t_end:   # a step past the event's root
            breaks.pop()
            parts.pop()
        breaks[-1] = piece.t_end
        ts += breaks[1:] if ts else breaks   # each piece starts where the last one ended
        interpolants += parts
    solution = OdeSolution(ts, interpolants) if interpolants and len(ts) == len(interpolants) + 1 else None
    roots = {name: [root for piece in pieces for root in piece.roots.get(name, [])] for name in last.roots}
    return Segment(joined("t"), np.concatenate([piece.y[:-1, :] for piece in pieces[:-1]] + [last.y]),
                   last.event, last.t_end, last.y_end, roots, solution, joined("step_t"),
                   None if last.step_y is None else np.concatenate(
                       [piece.step_y[:-1] for piece in pieces[:-1]] + [last.step_y]))


#: Gauss-Legendre nodes and weights on [-1, 1] for the drag's work over each flight step: the
#: interpolant is a 7th-degree polynomial and the drag smooth, so 8 nodes integrate it to
#: round-off of the integrand's own accuracy.
_GAUSS = np.polynomial.legendre.leggauss(8)


def drag_work(flight: Segment, p: Params) -> float:
    """The work the air's drag took from the projectile in flight, J: ``-integral of F_drag . v dt``
    over the ground velocity ``v`` (negative when a tailwind gave more than the drag took).

    Integrated step by step on the integrator's continuous solution (Gauss-Legendre), so the
    projectile's mechanical energy at release equals its energy at landing plus this to the
    integrator's tolerance.
    """
    out = np.empty(4)

    def power(y):   # per unit of the projectile's mass
        stages.derivative(Stage.FLIGHT, y, p, DRAG_TABLE, out)
        return out[2] * y[2] + (out[3] + p.g) * y[3]

    return -_step_integral(flight, power, p.mP)


def swing_drag_work(segments, p: Params) -> float:
    """The work the air's drag took from the projectile in stages 1-2, J (0 unless ``p.drag_swing``):
    ``-integral of D . v dt`` on each stage's continuous solution (``eom.swing_drag``; ``v`` the
    projectile's ground velocity: about the pivot, plus a floating arm's axle's), as ``drag_work``
    integrates the flight's."""
    if not p.drag_swing > 0.0:
        return 0.0

    def power(stage):
        def at(y):
            theta, phi, psi, dtheta, dphi, dpsi = (eom.slide_state(y[0], y[1], y[2], y[3], p)
                                                   if stage is Stage.SLIDE else y[:6])
            dx, dy = eom.swing_drag(theta, psi, dtheta, dpsi, p)
            _, _, vx, vy = projectile_state(theta, psi, dtheta, dpsi, p.La, p.Ls)
            vx += eom.frame_velocity(theta, phi, psi, dtheta, dphi, dpsi, p)   # a floating arm's axle's
            return dx * vx + dy * vy
        return at

    return -sum(_step_integral(segment, power(stage), 1.0) for stage, segment in segments)


def _step_integral(segment: Segment, integrand, factor: float) -> float:
    """``factor`` times the ``integral of integrand(y(t)) dt`` over ``segment``, step by step on its
    continuous solution (Gauss-Legendre, ``_GAUSS``); 0 without one."""
    if segment.solution is None:
        return 0.0
    nodes, weights = _GAUSS
    total = 0.0
    for a, b, interpolant in zip(segment.solution.ts[:-1], segment.solution.ts[1:], segment.solution.interpolants,
                                 strict=True):
        b = min(b, segment.t_end)
        if not b > a:
            continue
        states = interpolant(0.5 * (b - a) * nodes + 0.5 * (a + b)).T.tolist()   # Python floats: see stage_rhs
        total += factor * 0.5 * (b - a) * sum(w * integrand(y) for w, y in zip(weights, states, strict=True))
    return float(total)


def _events(stage: Stage, p: Params) -> tuple[Event, ...]:
    """The stage's events (``analytic.stages``) as the integrator's ``Event`` objects, in order."""
    def event(k: int, name: str) -> Event:
        # A value or condition Python cannot compute is NaN or false, as compiled: no root there.
        return Event(name, lambda t, y: quietly(stages.event_value, stage, k, y.tolist(), p, otherwise=math.nan),
                     direction=stages.event_direction(stage, k),
                     armed=lambda t, y: quietly(stages.event_armed, stage, k, y.tolist(), p, otherwise=False),
                     terminal=stages.event_terminal(stage, k), turns=stages.event_turns(stage, k))

    names = stages.EVENT_NAMES[stage][:stages.event_count(stage, p)]   # friction's only with friction
    return tuple(event(k, name) for k, name in enumerate(names))


# --------------------------------------------------------------------------- #
# Histories and the result
# --------------------------------------------------------------------------- #

def _history(stage: Stage, segment: Segment, p: Params):
    """Rows ``(t, stage, (theta, phi, psi, theta', phi', psi'), sling tension, (axle, hinge, base work),
    stage state)`` of a segment."""
    core = stages.STATE_SIZE[stage]
    full = (lambda y: eom.slide_state(*y[:core], p)) if stage is Stage.SLIDE else (lambda y: tuple(y[:core]))
    lossy = friction.lossy(p)
    return [(t, stage, full(y), sling_tension_at(stage, y, p),
             tuple(y[core:core + 3]) if lossy else (0.0, 0.0, 0.0), y)
            for t, y in zip(segment.t.tolist(), segment.y.tolist(), strict=True)]   # Python floats: see stage_rhs


def jump_warning(force: float, time: float, gravity: float) -> str:
    """What a negative push of the ground on a rolling frame means for the result."""
    return (f"the frame would jump: the ground's push on it falls to {force:.3g} N at t = {time:.3f} s, "
            f"and this model keeps it on the ground, so the result cannot be trusted for a frame "
            f"this light (roughly {-force / gravity:.2g} kg more would keep it down)")


def _dissipated(p: Params, segments, drag: float) -> dict[str, float]:
    """``Shot.energy_dissipated`` from the last segment of stages 1-2 (its friction states) and the drag's work."""
    work = (0.0, 0.0, 0.0)
    if segments and friction.lossy(p):
        stage, segment = segments[-1]
        core = stages.STATE_SIZE[stage]
        work = tuple(float(w) for w in segment.y_end[core:core + 3])
    return outcome.dissipated(work, drag, swing_drag_work(segments, p), p.kind == eom.FLOATING)


def _support_extremes(stage: np.ndarray, raw: list, p: Params) -> dict[str, float]:
    """A floating arm's track and guide forces over the history's stage-1 and stage-2 rows, N:
    ``min_track_force``, ``max_track_force`` and ``max_guide_force`` (the largest magnitude)."""
    forces = np.array([stages.floating_supports(k, y, p) for k, y in zip(stage.tolist(), raw, strict=True)])
    return {"min_track_force": float(forces[:, 0].min()), "max_track_force": float(forces[:, 0].max()),
            "max_guide_force": float(np.abs(forces[:, 1]).max())}


def _finish_shot(design: Design, p: Params, history, segments, status: Status, message: str, *,
                 sampled_loads: bool = True, **fields) -> Shot:
    after_release = fields.pop("after_release_speed", None)
    warnings = tuple(filter(None, [fields.pop("after_release_warning", None)]))
    if history is None:   # summary only
        fields.pop("flight_t", None)
        fields.pop("flight_path", None)
        fields["energy_dissipated"] = _dissipated(p, segments, fields.pop("drag_work", 0.0))
        return Shot(design, status, message, **fields, warnings=warnings)
    rows = [row for part in history for row in part]
    if not rows:   # failed in its very first stretch: the state at rest
        y1 = np.empty(stages.state_size(Stage.SLIDE, p))
        stages.slide_start(p, y1)
        rows = _history(Stage.SLIDE, Segment(np.zeros(1), y1[None, :], None, 0.0, y1, {}), p)
    t = np.array([row[0] for row in rows])
    stage = np.array([int(row[1]) for row in rows])
    states = np.array([row[2] for row in rows])     # (n, 6): q, then q'
    tension = np.array([row[3] for row in rows])
    work = np.array([row[4] for row in rows])        # (n, 3): axle, hinge, base
    raw = [row[5] for row in rows]                   # each stage's own state
    state_rows = states.tolist()                     # Python floats for the model (see stage_rhs)

    v_machine0, v_projectile0 = eom.potential_energy(*state_rows[0][:3], p)
    budget = np.empty((len(t), 2))
    path = np.empty((len(t), 2))
    for i, (theta, phi, psi, dtheta, dphi, dpsi) in enumerate(state_rows):
        v_m, v_p = eom.potential_energy(theta, phi, psi, p)
        k_m, k_p = eom.kinetic_energy(theta, phi, psi, dtheta, dphi, dpsi, p)
        budget[i] = (k_m + v_m - v_machine0, k_p + v_p - v_projectile0)
        path[i] = projectile_state(theta, psi, dtheta, dpsi, p.La, p.Ls)[:2]
        path[i, 0] += eom.frame_displacement(theta, phi, psi, p)   # on the ground, as the flight is
    energy = EnergyBudget(projectile=budget[:, 1], machine=budget[:, 0], total=budget.sum(axis=1),
                          dissipated={name: work[:, i] for i, name in
                                      enumerate(outcome.friction_work_names(p.kind == eom.FLOATING))})
    fields["energy_dissipated"] = _dissipated(p, segments, fields.pop("drag_work", 0.0))
    frame_x = np.array([eom.frame_displacement(*state[:3], p) for state in state_rows])
    ground = np.array([eom.ground_force(*state, *stages.accelerations(int(k), y, p), p)
                       for k, state, y in zip(stage.tolist(), state_rows, raw, strict=True)])
    fields["min_ground_force"] = float(ground.min())
    if p.kind == eom.FLOATING:
        fields.update(_support_extremes(stage, raw, p))
    loads = (np.array([stages.loads_at(k, y, p) for k, y in zip(stage.tolist(), raw, strict=True)])   # (n, N_LOADS)
             if sampled_loads else None)
    if p.rolling and ground.min() < 0.0:
        warnings = (jump_warning(float(ground.min()), float(t[int(np.argmin(ground))]), p.g), *warnings)
    fields["warnings"] = warnings
    frame_speed = max(abs(eom.frame_velocity(*state, p)) for state in state_rows)
    if status is Status.OK and after_release is not None:
        fields["max_frame_speed"] = max(frame_speed, after_release)
    released = None
    if fields.get("release_time") is not None:
        released = v_machine0 - eom.potential_energy(*state_rows[-1][:3], p)[0]
        fields["projectile_energy_at_release"] = float(budget[-1, 1])
    history = History(t=t, stage=stage, q=states[:, :3], qdot=states[:, 3:], path=path,
                      sling_tension=tension, energy=energy,
                      frame_x=frame_x if p.rolling or p.kind == eom.FLOATING else np.empty(0),
                      flight_t=fields.pop("flight_t", np.empty(0)),
                      flight_path=fields.pop("flight_path", np.empty((0, 2))),
                      **({} if loads is None else
                         {"axle_load": loads[:, 0], "hinge_load": loads[:, 1], "projectile_acceleration": loads[:, 3],
                          "arm_bending_moment": loads[:, 4]}))
    return Shot(design, status, message, history=history,
                # A machine that never moves (never fires, or its equations fail at rest) holds
                # its projectile statically: no tension is defined.
                min_sling_tension=None if not segments else smallest_tension(t, stage, tension, segments, p),
                counterweight_energy_released=released, **fields)
