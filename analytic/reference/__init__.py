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

from analytic import eom, friction, ideal, outcome, sequence, stages, states
from analytic.aero import DRAG_TABLE
from analytic.design import Design
from analytic.geometry import IDEAL_RULE, projectile_state
from analytic.floating_arm import sling_weighs
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
    if p.rule == IDEAL_RULE:   # the arm angle of the longest throw (analytic.ideal)
        p = p._replace(alpha=_ideal_arm_angle(design, p, rtol, atol))
    return _simulate(design, p, rtol, atol, histories, loads, after_release, swing_spacing, flight_spacing,
                     sampled_loads)


def _simulate(design: Design, p: Params, rtol: float, atol: float, histories: bool, loads: bool,
              after_release: bool | None, swing_spacing: float, flight_spacing: float, sampled_loads: bool) -> Shot:
    """``simulate`` of ``design`` with its numbers ``p`` (the ideal rule's arm angle found)."""
    output_step = max(swing_spacing, p.t_limit / HISTORY_SAMPLE_LIMIT) if histories else None
    finish = functools.partial(_finish_shot, design, p, sampled_loads=sampled_loads)
    history = [] if histories else None
    segments = []
    reached = {}   # what the shot got to: lift-off, then release

    y1 = np.empty(states.state_size(Stage.SLIDE, p))
    stages.slide_start(p, y1)
    ddtheta0, normal0 = quietly(stages.fires, p, otherwise=(math.nan, math.nan))
    if not (math.isfinite(ddtheta0) and math.isfinite(normal0) and ddtheta0 < 0.0):
        return _unfired(finish, p, y1, ddtheta0, normal0, history)

    stage = Stage.SLIDE
    switches = [0]   # friction's mode switches so far (states.MODE_SWITCH_LIMIT)
    try:
        slide, peaks, action, detail = _slide(p, y1, normal0, rtol, atol, output_step, loads, switches)
        _keep(Stage.SLIDE, slide, p, history, segments)
        if action == sequence.FINISHED:
            return finish(history, segments, Status.NEVER_LIFTS_OFF,
                          outcome.failure_message(Status.NEVER_LIFTS_OFF, detail=detail, time_limit=p.t_limit),
                          **peak_fields(peaks))
        stage = Stage.SWING
        reached["liftoff_time"] = slide.t_end
        swing, peaks, action, status = _swing(p, slide, peaks, rtol, atol, output_step, loads, switches)
        reached.update(peak_fields(peaks))
        _keep(Stage.SWING, swing, p, history, segments)
        if status == sequence.HITS_BASE:
            return finish(history, segments, Status.HITS_BASE_BEFORE_RELEASE,
                          outcome.failure_message(Status.HITS_BASE_BEFORE_RELEASE, time=swing.t_end), **reached)
        if action == sequence.FINISHED:
            return finish(history, segments, Status.NEVER_RELEASES,
                          outcome.failure_message(Status.NEVER_RELEASES, time_limit=p.t_limit,
                                                  release=(design.machine.release_rule,
                                                           design.machine.release_angle)), **reached)
        stage = Stage.FLIGHT
        start, release = _release(swing, p)
        reached.update(release)
        flight, t_max = _fly(p, start, swing.t_end, rtol, atol, flight_spacing if histories else None)
    except IntegrationError as error:
        if stage is not Stage.FLIGHT and error.segment is not None:
            # The motion up to the failure (the flight's is not kept, as for any shot that does not land).
            _keep(stage, error.segment, p, history, segments)
        return finish(history, segments, Status.STEP_FAILED,
                      outcome.failure_message(Status.STEP_FAILED, time=error.time, detail=stage,
                                              step_limit=error.step_limit), **reached)
    reached["drag_work"] = drag_work(flight, p)
    _, status, _ = sequence.stretch_end(Stage.FLIGHT, _code(Stage.FLIGHT, flight), switches[0])
    if status == sequence.NO_LANDING:
        return finish(history, segments, Status.NO_LANDING,
                      outcome.failure_message(Status.NO_LANDING, time=t_max - swing.t_end), **reached)
    apex_height = _apex_height(flight, start, p)
    if sequence.short_of_target(apex_height, p.yt):
        apex_height = max(apex_height, flight.y_end[states.FLIGHT_Y] + p.h)   # (its end: the apex, to the root)
        return finish(history, segments, Status.SHORT_OF_TARGET,
                      outcome.failure_message(Status.SHORT_OF_TARGET, apex=(apex_height, p.yt)),
                      apex_height=apex_height, flight_t=flight.t,
                      flight_path=flight.y[:, states.FLIGHT_X:states.FLIGHT_Y + 1], **reached)
    reached.update(_frame_at_landing(p, swing, flight, start, reached["frame_release_displacement"],
                                     histories if after_release is None else after_release, rtol, atol, output_step))
    return finish(history, segments, Status.OK, outcome.thrown_message(flight.y_end[states.FLIGHT_X]), **reached,
                  **_landing(flight, start, p))


def _ideal_arm_angle(design: Design, p: Params, rtol: float, atol: float) -> float:
    """The ideal rule's arm angle at release, rad (``analytic.ideal``): the window from the search
    pass, then summary shots released at candidate arm angles."""
    window = _ideal_window(p._replace(alpha=ideal.SEARCH_ANGLE), rtol, atol)
    if window is None:   # it never swings free: the shot fails before any release, as the search pass did
        return ideal.SEARCH_ANGLE

    def ranges(angles):
        return np.array([_range(_simulate(design, p._replace(alpha=float(angle)), rtol, atol, False, False, False,
                                          SWING_OUTPUT_STEP, FLIGHT_OUTPUT_STEP, False)) for angle in angles])

    return ideal.best_arm_angle(ranges, *window)


def _range(shot: Shot) -> float:
    """A shot's range, m; NaN if it did not land."""
    return math.nan if shot.range is None else shot.range


def _ideal_window(p: Params, rtol: float, atol: float) -> tuple[float, float] | None:
    """The ideal rule's search pass (``p.alpha`` the search's): the arm angle at lift-off and at the
    end of the free swing, rad; None if the machine never swings free (it never fires, never lifts
    off, or a step fails first)."""
    y1 = np.empty(states.state_size(Stage.SLIDE, p))
    stages.slide_start(p, y1)
    ddtheta0, normal0 = quietly(stages.fires, p, otherwise=(math.nan, math.nan))
    if not (math.isfinite(ddtheta0) and math.isfinite(normal0) and ddtheta0 < 0.0):
        return None
    switches = [0]
    try:
        slide, _, action, _ = _slide(p, y1, normal0, rtol, atol, None, False, switches)
        if action == sequence.FINISHED:
            return None
        swing, _, _, _ = _swing(p, slide, NO_PEAKS, rtol, atol, None, False, switches)
    except IntegrationError:
        return None
    return float(slide.y_end[0]), float(swing.y_end[0])


def _unfired(finish, p: Params, y1: np.ndarray, ddtheta0: float, normal0: float, history) -> Shot:
    """The shot of a machine that does not move, at rest in ``y1`` (``history``: its one sample there): the
    equations cannot be evaluated even at rest (the design's numbers over- or underflow the model's
    products, a mass or length near the ends of the float range: ``stages.fires``' ``ddtheta0`` or
    ``normal0`` not finite), or it never fires (``ddtheta0``, the arm's acceleration at rest, not
    negative; with friction, the message says what holds it)."""
    if history is not None:
        history.append(_history(Stage.SLIDE, Segment(np.zeros(1), y1[None, :], None, 0.0, y1, {}), p))
    if not (math.isfinite(ddtheta0) and math.isfinite(normal0)):
        return finish(history, [], Status.STEP_FAILED, outcome.failure_message(Status.STEP_FAILED,
                                                                               detail=Stage.SLIDE))
    balance = ((*friction.rest_balance(p), outcome.friction_holders(*friction.holders(p)))
               if friction.lossy(p) else ())
    return finish(history, [], Status.NEVER_FIRES, outcome.failure_message(Status.NEVER_FIRES,
                                                                           fires=(ddtheta0, *balance)))


def _keep(stage: Stage, segment: Segment, p: Params, history, segments) -> None:
    """Keep a stage's ``segment`` for the shot's end (``_finish_shot``), and with ``history`` its samples
    (the swing's first is the lift-off, the slide's last, kept once)."""
    if history is not None:
        history.append(_history(stage, segment, p)[0 if stage is Stage.SLIDE else 1:])
    segments.append((stage, segment))


def _slide(p: Params, y1: np.ndarray, normal0: float, rtol: float, atol: float, output_step: float | None,
           loads: bool, switches: list[int]) -> tuple[Segment, np.ndarray, int, int]:
    """Stage 1 from rest (``y1``): the slide on the base until the normal force vanishes; none where it
    does not push at rest (``normal0``: the sling already pulls harder than the projectile's weight).

    Returns the stage's segment, its peak loads (``pieces_peaks``) and ``stretch_end``'s action and
    detail at its end."""
    if not normal0 > 0.0:
        return Segment(np.zeros(1), y1[None, :], "liftoff", 0.0, y1, {}), NO_PEAKS, sequence.NEXT_STAGE, 0
    pieces, action, _, detail = _run_modes(Stage.SLIDE, p, 0.0, y1, p.t_limit, rtol, atol, output_step,
                                           p.drag_swing > 0.0, switches)
    peaks = pieces_peaks(Stage.SLIDE, pieces, p, loads, NO_PEAKS, rtol, atol)
    return _merge(pieces), peaks, action, detail


def _swing(p: Params, slide: Segment, peaks: np.ndarray, rtol: float, atol: float, output_step: float | None,
           loads: bool, switches: list[int]) -> tuple[Segment, np.ndarray, int, int]:
    """Stage 2 from the lift-off that ends ``slide``: the free swing until release.

    Returns the stage's segment, the peak loads with the swing's (``peaks``: the slide's), and
    ``stretch_end``'s action and status at its end."""
    y2 = np.empty(states.state_size(Stage.SWING, p))
    try:
        stages.swing_start(slide.y_end, p, y2)
    except FLOAT_ERRORS:
        y2[:] = math.nan   # the integrator ends the stage as step_failed
    pieces, action, status, _ = _run_modes(Stage.SWING, p, slide.t_end, y2, p.t_limit, rtol, atol, output_step,
                                           p.drag_swing > 0.0, switches)
    peaks = pieces_peaks(Stage.SWING, pieces, p, loads, peaks, rtol, atol)
    return _merge(pieces), peaks, action, status


def _release(swing: Segment, p: Params) -> tuple[np.ndarray, dict]:
    """The flight's start ``(x, y, vx, vy)`` on the ground at the release that ends ``swing``, and the
    ``Shot`` fields of the release; a release state that cannot be computed fails the shot."""
    start = np.array(quietly(stages.flight_start, swing.y_end, p, otherwise=(math.nan,) * 4))
    if not np.all(np.isfinite(start)):
        raise IntegrationError("non-finite release state", swing.t_end)
    frame_x, frame_v = stages.frame_state(swing.y_end, p)
    return start, dict(release_time=swing.t_end, release_position=start[states.FLIGHT_X:states.FLIGHT_Y + 1],
                       release_velocity=start[states.FLIGHT_VX:states.FLIGHT_VY + 1],
                       frame_release_displacement=frame_x, frame_release_velocity=frame_v)


def _fly(p: Params, start: np.ndarray, release_time: float, rtol: float, atol: float,
         flight_spacing: float | None) -> tuple[Segment, float]:
    """Stage 3: the flight from ``start`` at ``release_time`` until it lands or its time runs out
    (``limits.flight_time_limit``); sampled ``flight_spacing`` apart (None: no samples). Returns the
    flight's segment, its continuous solution kept for the drag's work (the steps are the same either
    way), and the time limit."""
    height, rising = start[states.FLIGHT_Y] + p.h - p.yt, start[states.FLIGHT_VY]   # above the target
    t_max = release_time + flight_time_limit(height, rising, p.g)
    flight_step = (None if flight_spacing is None else
                   max(flight_spacing, (t_max - release_time) / HISTORY_SAMPLE_LIMIT))
    if sequence.lands_at_release(height, rising):
        return _landed(start, release_time), t_max
    return _run(Stage.FLIGHT, p, release_time, start, t_max, rtol, atol, flight_step, True), t_max


def _landing(flight: Segment, start: np.ndarray, p: Params) -> dict:
    """The ``Shot`` fields of a flight that landed: where and when, its highest point above the base
    (``_apex_height``) and its samples."""
    return dict(landing_time=flight.t_end, landing_position=flight.y_end[states.FLIGHT_X:states.FLIGHT_Y + 1],
                apex_height=_apex_height(flight, start, p), flight_t=flight.t,
                flight_path=flight.y[:, states.FLIGHT_X:states.FLIGHT_Y + 1])


def _apex_height(flight: Segment, start: np.ndarray, p: Params) -> float:
    """The flight's highest point above the base, m: the release's height, or the highest apex root."""
    return max([start[states.FLIGHT_Y]] + [y[states.FLIGHT_Y] for _, y in flight.roots["apex"]]) + p.h


def spacing_argument(name: str, value: float | None, default: float) -> float:
    """A history spacing argument of ``simulate``, s: ``default`` for None, else a positive number."""
    if value is None:
        return default
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0.0 < value < math.inf:
        raise ValueError(f"{name} = {value!r}: must be a positive number of seconds")
    return float(value)


def _frame_at_landing(p: Params, swing: Segment, flight: Segment, start: np.ndarray, release_x: float, run: bool,
                      rtol: float, atol: float, output_step: float | None) -> dict:
    """The ``Shot`` fields of the frame at the landing that ends ``flight``: 0 on a fixed frame; on a
    rolling one, with ``run``, the machine's run on from the release that ends ``swing``
    (``_frame_after_release``), else none."""
    if not p.rolling:
        return dict(frame_landing_displacement=0.0, frame_landing_velocity=0.0, after_release_speed=0.0)
    if not run:
        return {}
    return _frame_after_release(p, swing.y_end, swing.t_end, flight.t_end, rtol, atol, release_x,
                                start[states.FLIGHT_VX], output_step)


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
    if sling_weighs(p):
        # The sling and the pouch stay on the arm and swing free of it: a third coordinate, which stage 4
        # (the arm and the counterweight alone) does not have [14.8].
        return {"after_release_warning": after_release_warning("the sling and the pouch, which have mass, swing "
                                                               "on the arm after release, and stage 4 does not "
                                                               "follow them")}
    m = stages.machine_params(p)
    start = np.empty(states.state_size(states.MACHINE, m))
    try:
        stages.machine_start(release_state, m, start)
        pieces, _, _, _ = _run_modes(states.MACHINE, m, release_time, start, landing_time, rtol, atol, output_step,
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
    return sequence.REACHED_END if piece.event is None else states.EVENT_NAMES[stage].index(piece.event)


def _run_modes(stage: Stage, p: Params, t0: float, y0: np.ndarray, t_end: float, rtol: float, atol: float,
               output_step: float | None, continuous: bool, switches: list[int]) -> tuple[list[Segment], int, int, int]:
    """``_run`` in stretches, switching the friction modes between them, until
    ``analytic.sequence.stretch_end`` says the stage is over.

    Returns the pieces integrated, one per mode (one for a design without
    friction), and ``stretch_end``'s ``(action, status, detail)`` at the last.
    ``switches`` ([count]) counts the switches of the whole shot; past
    ``states.MODE_SWITCH_LIMIT`` the shot fails (``IntegrationError``).
    """
    pieces = []
    t, y = t0, y0
    while True:
        piece = _run(stage, p, t, y, t_end, rtol, atol, output_step, continuous)
        pieces.append(piece)
        code = _code(stage, piece)
        action, status, detail = sequence.stretch_end(int(stage), code, switches[0])
        if status == sequence.STEP_FAILED:
            raise IntegrationError(f"friction switched modes more than {states.MODE_SWITCH_LIMIT} times",
                                   piece.t_end)
        if action != sequence.SWITCH_MODE:
            return pieces, action, status, detail
        switches[0] += 1
        t, y = piece.t_end, piece.y_end.copy()
        states.switch_mode(int(stage), code, y, p)


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
        at_nodes = interpolant(0.5 * (b - a) * nodes + 0.5 * (a + b)).T.tolist()   # Python floats: see stage_rhs
        total += factor * 0.5 * (b - a) * sum(w * integrand(y) for w, y in zip(weights, at_nodes, strict=True))
    return float(total)


def _events(stage: Stage, p: Params) -> tuple[Event, ...]:
    """The stage's events (``analytic.stages``) as the integrator's ``Event`` objects, in order."""
    def event(k: int, name: str) -> Event:
        # A value or condition Python cannot compute is NaN or false, as compiled: no root there.
        return Event(name, lambda t, y: quietly(stages.event_value, stage, k, y.tolist(), p, otherwise=math.nan),
                     direction=stages.event_direction(stage, k),
                     armed=lambda t, y: quietly(stages.event_armed, stage, k, y.tolist(), p, otherwise=False),
                     terminal=stages.event_terminal(stage, k), turns=stages.event_turns(stage, k))

    names = states.EVENT_NAMES[stage][:stages.event_count(stage, p)]   # friction's only with friction
    return tuple(event(k, name) for k, name in enumerate(names))


# --------------------------------------------------------------------------- #
# Histories and the result
# --------------------------------------------------------------------------- #

def _history(stage: Stage, segment: Segment, p: Params):
    """Rows ``(t, stage, (theta, phi, psi, theta', phi', psi'), sling tension, the friction's work
    (``states.friction_work``), stage state)`` of a segment."""
    core = states.STATE_SIZE[stage]
    full = (lambda y: eom.slide_state(*y[:core], p)) if stage is Stage.SLIDE else (lambda y: tuple(y[:core]))
    lossy = friction.lossy(p)
    idle = (0.0,) * len(outcome.friction_work_names(p.kind == eom.FLOATING, states.floating_base(p)))
    return [(t, stage, full(y), sling_tension_at(stage, y, p), states.friction_work(stage, y, p) if lossy else idle, y)
            for t, y in zip(segment.t.tolist(), segment.y.tolist(), strict=True)]   # Python floats: see stage_rhs


def jump_warning(force: float, time: float, gravity: float) -> str:
    """What a negative push of the ground on a rolling frame means for the result."""
    return (f"the frame would jump: the ground's push on it falls to {force:.3g} N at t = {time:.3f} s, "
            f"and this model keeps it on the ground, so the result cannot be trusted for a frame "
            f"this light (roughly {-force / gravity:.2g} kg more would keep it down)")


def _dissipated(p: Params, segments, drag: float) -> dict[str, float]:
    """``Shot.energy_dissipated`` from the last segment of stages 1-2 (its friction states) and the drag's work."""
    floating_base = states.floating_base(p)
    work = (0.0,) * len(outcome.friction_work_names(p.kind == eom.FLOATING, floating_base))
    if segments and friction.lossy(p):
        stage, segment = segments[-1]
        work = states.friction_work(stage, segment.y_end, p)
    return outcome.dissipated(work, drag, swing_drag_work(segments, p), p.kind == eom.FLOATING, floating_base)


def _support_extremes(stage: np.ndarray, raw: list, p: Params) -> dict[str, float]:
    """A floating arm's track and guide forces over the history's stage-1 and stage-2 rows, N:
    ``min_track_force``, ``max_track_force`` and ``max_guide_force`` (the largest magnitude)."""
    forces = np.array([stages.floating_supports(k, y, p) for k, y in zip(stage.tolist(), raw, strict=True)])
    return {"min_track_force": float(forces[:, 0].min()), "max_track_force": float(forces[:, 0].max()),
            "max_guide_force": float(np.abs(forces[:, 1]).max())}


def _finish_shot(design: Design, p: Params, history, segments, status: Status, message: str, *,
                 sampled_loads: bool = True, **fields) -> Shot:
    """The ``Shot`` of a shot that ended with ``status``: its ``fields`` so far, the energy each loss
    took (from the stages' ``segments``) and, with a ``history`` (None: a summary), what its
    samples give (``_with_history``)."""
    after_release = fields.pop("after_release_speed", None)
    warnings = tuple(filter(None, [fields.pop("after_release_warning", None)]))
    flight = fields.pop("flight_t", np.empty(0)), fields.pop("flight_path", np.empty((0, 2)))
    fields["energy_dissipated"] = _dissipated(p, segments, fields.pop("drag_work", 0.0))
    if history is None:   # summary only
        return Shot(design, status, message, **fields, warnings=warnings)
    return _with_history(design, p, history, segments, status, message, sampled_loads, after_release, warnings,
                         flight, fields)


def _with_history(design: Design, p: Params, history, segments, status: Status, message: str, sampled_loads: bool,
                  after_release: float | None, warnings: tuple[str, ...], flight, fields: dict) -> Shot:
    """The ``Shot`` with its ``History``: the stages' samples (``history``: each stage's rows of
    ``_history``) with the flight's (``flight``: its times and path), and what is read off them (the
    energies, the loads, the ground's push and the frame's speed) besides ``fields``."""
    t, stage, coordinates, tension, work, raw = _sampled(history, p)
    state_rows = coordinates.tolist()   # Python floats for the model (see stage_rhs)
    energy, path = _energy_budget(state_rows, work, p)
    frame_x = np.array([eom.frame_displacement(*state[:3], p) for state in state_rows])
    # A sample where the equations cannot be evaluated (a machine whose numbers over- or underflow them
    # even at rest: ``_unfired``) has no push nor loads: NaN there, and no smallest push.
    ground = np.array([quietly(_ground_force, int(k), state, y, p, otherwise=math.nan)
                       for k, state, y in zip(stage.tolist(), state_rows, raw, strict=True)])
    fields["min_ground_force"] = float(ground.min()) if np.isfinite(ground).all() else None
    if p.kind == eom.FLOATING:
        fields.update(_support_extremes(stage, raw, p))
    unknown = (math.nan,) * len(stages.LOAD_NAMES)
    loads = (np.array([quietly(stages.loads_at, k, y, p, otherwise=unknown)   # (n, N_LOADS)
                       for k, y in zip(stage.tolist(), raw, strict=True)]) if sampled_loads else None)
    if p.rolling and ground.min() < 0.0:
        warnings = (jump_warning(float(ground.min()), float(t[int(np.argmin(ground))]), p.g), *warnings)
    fields["warnings"] = warnings
    frame_speed = max(abs(eom.frame_velocity(*state, p)) for state in state_rows)
    if status is Status.OK and after_release is not None:
        fields["max_frame_speed"] = max(frame_speed, after_release)
    released = None
    if fields.get("release_time") is not None:
        released = (eom.potential_energy(*state_rows[0][:3], p)[0]
                    - eom.potential_energy(*state_rows[-1][:3], p)[0])
        fields["projectile_energy_at_release"] = float(energy.projectile[-1])
        fields["sling_energy_at_release"] = 0.0
        if sling_weighs(p):   # the machine's potential energy holds theirs: the counterweight's is the rest
            at_rest, at_release = eom.sling_energy(*state_rows[0], p), eom.sling_energy(*state_rows[-1], p)
            released -= at_rest[1] - at_release[1]
            fields["sling_energy_at_release"] = at_release[0] + at_release[1] - at_rest[1]
    history = History(t=t, stage=stage, q=coordinates[:, :3], qdot=coordinates[:, 3:], path=path,
                      sling_tension=tension, energy=energy,
                      frame_x=frame_x if p.rolling or p.kind == eom.FLOATING else np.empty(0),
                      flight_t=flight[0], flight_path=flight[1],
                      **({} if loads is None else {name: loads[:, stages.LOAD_NAMES.index(name)] for name in
                                                    ("axle_load", "hinge_load", "projectile_acceleration",
                                                     "arm_bending_moment")}))
    return Shot(design, status, message, history=history,
                # A machine that never moves (never fires, or its equations fail at rest) holds
                # its projectile statically: no tension is defined.
                min_sling_tension=None if not segments else smallest_tension(t, stage, tension, segments, p),
                counterweight_energy_released=released, **fields)


def _ground_force(stage: int, state: list, y, p: Params) -> float:
    """The ground's vertical push on the frame at a sample (``eom.ground_force``), N."""
    return eom.ground_force(*state, *stages.accelerations(stage, y, p), p)


def _sampled(history, p: Params):
    """The stages' samples (``history``: each stage's rows of ``_history``) as arrays: times (n,), stages
    (n,), coordinates and rates (n, 6), sling tension (n,), the friction's work (n, 3 or 4:
    ``outcome.friction_work_names``) and each sample's own stage state (a list). A shot that failed in
    its very first stretch has one: the state at rest."""
    rows = [row for part in history for row in part]
    if not rows:
        y1 = np.empty(states.state_size(Stage.SLIDE, p))
        stages.slide_start(p, y1)
        rows = _history(Stage.SLIDE, Segment(np.zeros(1), y1[None, :], None, 0.0, y1, {}), p)
    return (np.array([row[0] for row in rows]), np.array([int(row[1]) for row in rows]),
            np.array([row[2] for row in rows]), np.array([row[3] for row in rows]), np.array([row[4] for row in rows]),
            [row[5] for row in rows])


def _energy_budget(state_rows: list, work: np.ndarray, p: Params) -> tuple[EnergyBudget, np.ndarray]:
    """The energy budget at each sample (``state_rows``: coordinates then rates; ``work``: the friction's),
    each part's kinetic and potential energy over its energy at the first, and the projectile's path
    on the ground (n, 2)."""
    v_machine0, v_projectile0 = eom.potential_energy(*state_rows[0][:3], p)
    budget = np.empty((len(state_rows), 2))
    path = np.empty((len(state_rows), 2))
    for i, (theta, phi, psi, dtheta, dphi, dpsi) in enumerate(state_rows):
        v_m, v_p = eom.potential_energy(theta, phi, psi, p)
        k_m, k_p = eom.kinetic_energy(theta, phi, psi, dtheta, dphi, dpsi, p)
        budget[i] = (k_m + v_m - v_machine0, k_p + v_p - v_projectile0)
        path[i] = projectile_state(theta, psi, dtheta, dpsi, p.La, p.Ls)[:2]
        path[i, 0] += eom.frame_displacement(theta, phi, psi, p)   # on the ground, as the flight is
    energy = EnergyBudget(projectile=budget[:, 1], machine=budget[:, 0], total=budget.sum(axis=1),
                          dissipated={name: work[:, i] for i, name in
                                      enumerate(outcome.friction_work_names(p.kind == eom.FLOATING,
                                                                            states.floating_base(p)))})
    return energy, path
