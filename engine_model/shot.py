"""Simulate one shot in pymunk: fire, slide, swing, release, fly -> ``Shot`` (with ``EngineDiagnostics``).

The machine is stepped at a fixed ``dt`` from rest (``engine_model.stepping``;
at the default step within the shot's step budget, ``engine_model.budget``).
Events (lift-off, release, landing, failures) are watched after every step and
located between steps by quadratic interpolation (``engine_model.events``). pymunk's velocities run
half a step ahead of its positions; every quantity reported pairs a position
with the velocity of the same instant (``engine_model.kinematics.synchronise``).

A rolling frame is one more body (``engine_model.build``); after release its
machine is stepped on to the landing instant (``engine_model.after_release``)
for the frame's position there.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from analytic import outcome
from analytic.design import Design, initial_angles
from analytic.result import PEAK_NAMES, EnergyBudget, History, Shot, Stage, Status
from engine_model import floating, ideal
from engine_model import friction as fr
from engine_model import kinematics as kin
from engine_model import loads as engine_loads
from engine_model import stepping
from engine_model.after_release import after_release_steps, run_after_release
from engine_model.budget import after_release_step, flight_step_base, run_within_budget
from engine_model.build import DEFAULT_ITERATIONS, EngineError
from engine_model.diagnostics import EngineDiagnostics, diagnose, diagnose_after_release
from engine_model.events import interpolate
from engine_model.flight import FLIGHT_STEP_LIMIT, FLIGHT_STEP_MULTIPLE, Flight, fly


def simulate(design: Design, *, dt: float | None = None, iterations: int = DEFAULT_ITERATIONS,
             sling: str = "rigid", machine_after_release: bool = False,
             step_limit: int | None = None) -> Shot:
    """Simulate a shot of ``design`` in pymunk through all three stages.

    A valid design that fails to throw is not an error: ``Shot.status`` names
    the failure and ``Shot.message`` explains it (a flight that does not come
    down within ``analytic.limits.flight_time_limit`` is ``NO_LANDING``).

    Parameters
    ----------
    design : a validated ``Design``.
    dt : fixed step, s. None (the default): ``DEFAULT_DT`` within the shot's
        step budget (``engine_model.budget``), lengthened
        for a swing or a rolling machine's run after release that would
        need more; ``shot.diagnostics`` gives the steps taken. A step given
        is kept whatever it costs (up to ``step_limit`` steps).
    iterations : pymunk solver iterations per step (at least about 20).
    sling : ``"rigid"`` (PinJoint) or ``"rope"`` (SlideJoint, pulls only).
    machine_after_release : also step a fixed frame's machine on from release to landing (a
        rolling one's always is) and keep its motion in ``history.machine_t``, ``machine_q`` and
        ``machine_frame_x``, for drawing it swinging on (``engine_model.render``).
    step_limit : most steps of stages 1-2, and of a rolling machine's run after release, at a
        step given; None (the default): ``stepping.MACHINE_STEP_LIMIT`` (the cross-check's refined
        runs take more, ``crosscheck.tolerances.REFINEMENT_STEP_LIMIT``).

    Returns
    -------
    Shot
        As the analytic model's, with its ``history``: ``t`` (n,), ``q`` and ``qdot``
        (n, 3), ``path`` (n, 2), ``sling_tension`` (n,), ``frame_x`` (n,) and
        ``energy`` on the steps of stages 1-2 (the last sample is the release
        instant, if any); ``flight_t`` (k,) and ``flight_path`` (k, 2) on the
        flight's steps; no load histories (``axle_load`` ... None). Positions are over the ground from the pivot's rest
        position. ``shot.diagnostics`` is the run's ``EngineDiagnostics``.

    Raises
    ------
    EngineError
        The design cannot be modelled (a massless arm, a rolling frame no
        heavier than the arm's ballast), or the run cannot be trusted:
        non-finite values, the solver unconverged (``diagnostics.RESIDUAL_LIMIT``; a
        rolling frame far lighter than the counterweight), an energy jump
        (``ENERGY_LIMIT``) or joints apart (``DRIFT_LIMIT``), in stages 1-2 or
        in a rolling machine's run after release; use a smaller ``dt`` or more
        ``iterations``. A floating-arm design: the engine builds it
        (``engine_model.build``) but does not yet read a shot of it.
    """
    budget = dt is None
    step_limit = stepping.MACHINE_STEP_LIMIT if step_limit is None else step_limit
    given = design
    if design.machine.release_rule == "ideal":
        design, dt, run, discarded = _ideal_run(design, dt, iterations, sling, step_limit, budget)
    else:
        dt, run, discarded = _run_machine(design, dt, iterations, sling, step_limit)
    raw, on_base = np.array(run.raw), np.array(run.on_base)
    steps = _step_lengths(len(raw), dt)
    drift = kin.joint_drift(raw, design, sling, on_base)
    residual = kin.constraint_residuals(raw, design, sling, on_base, steps)
    records = _records(design, run, raw, steps, dt)
    fields: dict = {"liftoff_time": run.liftoff_time}
    flight, release_state, axle_x = None, None, None
    if run.release_fraction is not None:
        records, release_state = _cut_at_release(records, run.release_fraction, dt, sling)
        axle_x = float(release_state[kin.ARM + kin.X])
        flight, flight_fields, failure = _fly_from_release(design, records.times[-1], release_state,
                                                           dt, budget)
        fields.update(flight_fields)
        if failure is not None:
            run.status, run.message = failure
    fields.update(_stage_fields(design, run, records, sling, 0.0 if flight is None else flight.drag_work))
    shot = _assemble(design, run, records.times, records.sync, records.tension, fields)
    diagnostics = diagnose(design, dt, iterations, sling, len(raw), 0 if flight is None else flight.steps, drift,
                           residual, shot, records.sync, records.dissipated, records.swing_drag)
    after_release_dt = 0.0
    if design.base.rolling:
        shot, diagnostics, after_release_dt = _roll_on(design, shot, diagnostics, release_state, dt, iterations,
                                                       budget, len(raw), discarded, machine_after_release,
                                                       step_limit)
    elif shot.landing_time is not None:
        shot = _swing_on(design, shot, release_state, dt, iterations, len(raw), discarded, machine_after_release)
    diagnostics = dataclasses.replace(diagnostics, friction_steps=_friction_steps(run, dt),
                                      after_release_dt=after_release_dt,
                                      discarded_steps=discarded if budget else 0)
    if design.machine.kind == "floating-arm":
        diagnostics = dataclasses.replace(diagnostics,
                                          support_loads=floating.support_loads(records.supports, records.times,
                                                                               axle_x))
    return dataclasses.replace(shot, design=given, diagnostics=diagnostics)


def _ideal_run(design: Design, dt: float | None, iterations: int, sling: str, step_limit: int,
               budget: bool) -> tuple[Design, float, stepping.Run, int]:
    """Stages 1-2 of an ideal-rule design (``engine_model.ideal``): the search pass to the arm's stop, then
    the run released at the best arm angle, at the search's step. Returns the design as released (its
    ``release_angle`` that arm angle), the step, the run, and the steps of the runs discarded."""
    dt, search, discarded = _run_machine(ideal.searching(design), dt, iterations, sling, step_limit)
    released = ideal.released_at(design, ideal.best_arm_angle(design, search, dt, budget))
    run, _ = stepping.run_machine(released, dt, iterations, sling, len(search.raw) + 1)
    return released, dt, run, discarded + len(search.raw)


@dataclass(frozen=True)
class _Records:
    """Stages 1-2 as the shot reports them, one row per step from rest; once cut at release
    (``_cut_at_release``), the last row is the release instant.

    Attributes
    ----------
    times : (n,) s from firing.
    sync : (n, 24) state rows, each position with the velocity of its instant (``kinematics.synchronise``).
    tension : (n,) the sling's tension, N.
    loads : (n, 5) the loads a builder sizes the machine for (``loads.load_histories``).
    supports : (n, 2) a floating arm's guide's and track's push, their friction taken off, N.
    dissipated : (n, 5) the work each friction had taken by each instant, J (``friction.JOINTS``).
    swing_drag : (n,) the work the air's drag had taken from the projectile by each instant, J.
    """

    times: np.ndarray
    sync: np.ndarray
    tension: np.ndarray
    loads: np.ndarray
    supports: np.ndarray
    dissipated: np.ndarray
    swing_drag: np.ndarray


def _run_machine(design: Design, dt: float | None, iterations: int, sling: str,
                 step_limit: int) -> tuple[float, stepping.Run, int]:
    """Stages 1-2 at ``dt`` (at most ``step_limit`` steps), or at the default step within the step
    budget where ``dt`` is None (``budget.run_within_budget``): the step used, the run, and the
    steps of the runs discarded."""
    if dt is None:
        dt, run, _, discarded = run_within_budget(design, iterations, sling)
        return dt, run, discarded
    if not (math.isfinite(dt) and dt > 0.0):
        raise ValueError(f"dt = {dt!r}: must be a positive number of seconds")
    run, _ = stepping.run_machine(design, dt, iterations, sling, step_limit)
    return dt, run, 0


def _step_lengths(rows: int, dt: float) -> np.ndarray:
    """(rows,) the step that produced each raw row, s: the opening half step, then whole ones."""
    steps = np.full(rows, dt)
    steps[0] = 0.5 * dt
    return steps


def _records(design: Design, run: stepping.Run, raw: np.ndarray, steps: np.ndarray, dt: float) -> _Records:
    """The records of stages 1-2 from the run's raw rows, ``steps`` (s) the step of each."""
    sync = kin.synchronise(raw, kin.origin_carried(design))
    tension = np.array(run.tension)
    slide_friction = fr.slide_forces(np.array(run.friction_impulse).reshape(-1, len(fr.JOINTS)), raw, design, steps)
    loads = engine_loads.load_histories(raw, tension, design, dt, slide_friction)
    # A floating arm's guide's and track's push: the supports' force less their friction.
    pull = engine_loads.tip_force(raw, engine_loads.sling_force(raw, tension, design, dt), design, dt)
    supports = (engine_loads.support_force(raw, pull, design, dt)
                - slide_friction)
    swing_drag = np.array(run.drag_work) if len(run.drag_work) == len(raw) else np.zeros(len(raw))
    return _Records(dt * np.arange(len(raw)), sync, tension, loads, supports, _friction_work(run, sync, design),
                    swing_drag)


def _cut_at_release(records: _Records, fraction: float, dt: float, sling: str) -> tuple[_Records, np.ndarray]:
    """The records with their last row moved back to the release instant, ``fraction`` of the last
    step (``events.interpolate``), and the state row there."""
    release_state = interpolate(records.sync[-3:], fraction)
    # A rope's tension jumps when it snaps taut: no parabola through a jump.
    release_tension = interpolate(records.tension[-3:] if sling == "rigid" else records.tension[-2:], fraction)

    def cut(values: np.ndarray) -> np.ndarray:
        return np.vstack([values[:-1], interpolate(values[-3:], fraction)])

    return _Records(times=np.append(records.times[:-1], records.times[-2] + fraction * dt),
                    sync=np.vstack([records.sync[:-1], release_state]),
                    tension=np.append(records.tension[:-1], release_tension),
                    loads=cut(records.loads), supports=cut(records.supports), dissipated=cut(records.dissipated),
                    swing_drag=np.append(records.swing_drag[:-1], interpolate(records.swing_drag[-3:], fraction)),
                    ), release_state


def _fly_from_release(design: Design, release_time: float, release_state: np.ndarray, dt: float,
                      budget: bool) -> tuple[Flight, dict, tuple[Status, str] | None]:
    """Stage 3 from the release instant: the flight, the ``Shot`` fields it gives, and the status and
    message of a flight that did not land (None where it did)."""
    position = kin.position(release_state[None, :], kin.PROJECTILE)[0]
    velocity = kin.velocity(release_state[None, :], kin.PROJECTILE)[0]
    # Within the budget the flight steps at the default's multiple (a lone body's steps are
    # cheap), lengthened only for a flight far longer than anything buildable throws.
    flight_base = flight_step_base(design, position, velocity) if budget else dt
    flight = fly(design, release_time, position, velocity, flight_base)
    fields = dict(release_time=release_time, release_position=position,
                  release_velocity=velocity, flight_t=flight.t, flight_path=flight.path,
                  frame_release_displacement=_frame(release_state, kin.X, design),
                  frame_release_velocity=_frame(release_state, kin.VX, design))
    if flight.landed:
        fields.update(landing_time=flight.landing_time, landing_position=flight.landing_position,
                      apex_height=flight.apex + design.machine.pivot_height)
        return flight, fields, None
    if flight.short:
        apex_height = flight.apex + design.machine.pivot_height
        fields["apex_height"] = apex_height
        return flight, fields, (Status.SHORT_OF_TARGET, outcome.short_of_target_message(
            apex_height, design.environment.target_height))
    if flight.out_of_steps:
        return flight, fields, (Status.STEP_FAILED, stepping.step_limit_message(
            "the flight", flight.steps, FLIGHT_STEP_MULTIPLE * flight_base, flight.limit, FLIGHT_STEP_LIMIT))
    return flight, fields, (Status.NO_LANDING, outcome.no_landing_message(flight.limit))


def _stage_fields(design: Design, run: stepping.Run, records: _Records, sling: str, drag_work: float) -> dict:
    """``Shot``'s summaries of stages 1-2: the smallest sling tension, the frame's top speed, the peak
    loads, and the work each friction and the air took (``drag_work``, J, the flight's)."""
    tension = records.tension
    fields = {"min_sling_tension": smallest_sample(tension) if sling == "rigid" else float(tension.min()),
              "max_frame_speed": (largest_speed(kin.column(records.sync, kin.FRAME, kin.VX)) if design.base.rolling
                                  else 0.0)}
    fields.update(_peaks(records.loads, records.times, run))
    fields["energy_dissipated"] = {**dict(zip(fr.JOINTS, (float(w) for w in records.dissipated[-1]), strict=True)),
                                   "drag": float(drag_work), "swing_drag": float(records.swing_drag[-1])}
    return fields


def _swing_on(design: Design, shot: Shot, release_state: np.ndarray, dt: float, iterations: int,
              machine_steps: int, discarded: int, machine_after_release: bool) -> Shot:
    """A fixed frame's landed shot: its frame still at landing, and with ``machine_after_release`` the
    machine stepped on from release to landing (``after_release.run_after_release``) in its history."""
    shot = dataclasses.replace(shot, frame_landing_displacement=0.0, frame_landing_velocity=0.0)
    if not machine_after_release:
        return shot
    after_dt = after_release_step(dt, shot.release_time, shot.landing_time, machine_steps, discarded)
    after = run_after_release(design, shot.release_time, release_state, shot.landing_time, after_dt,
                              iterations, stepping.STARTUP_ITERATIONS)
    return _with_machine_after_release(shot, after, design)


def _roll_on(design: Design, shot: Shot, diagnostics: EngineDiagnostics, release_state: np.ndarray | None,
             dt: float, iterations: int, budget: bool, machine_steps: int, discarded: int,
             machine_after_release: bool, step_limit: int) -> tuple[Shot, EngineDiagnostics, float]:
    """A rolling machine's shot with its frame at landing: the machine stepped on from release to
    landing (``after_release.run_after_release``), checked as stages 1-2 were; the shot, its
    diagnostics, and the step taken after release (0 where none was)."""
    if shot.landing_time is None:
        return shot, diagnostics, 0.0
    after_dt = dt
    if budget:
        after_dt = after_release_step(dt, shot.release_time, shot.landing_time, machine_steps, discarded)
    after_steps = after_release_steps(shot.release_time, shot.landing_time, after_dt)
    if after_steps > step_limit:
        message = stepping.step_limit_message("the rolling machine's run after release", after_steps, dt,
                                              shot.landing_time - shot.release_time, step_limit, ahead=True)
        return dataclasses.replace(shot, status=Status.STEP_FAILED, message=message), diagnostics, float(after_dt)
    # The machine was trusted up to release; only then is it worth stepping on.
    after = run_after_release(design, shot.release_time, release_state, shot.landing_time, after_dt,
                              iterations, stepping.STARTUP_ITERATIONS)
    landing = after.landing_state
    shot = dataclasses.replace(
        shot, frame_landing_displacement=float(landing[kin.FRAME + kin.X]),
        frame_landing_velocity=float(landing[kin.FRAME + kin.VX]),
        max_frame_speed=max(shot.max_frame_speed, largest_speed(kin.column(after.states, kin.FRAME, kin.VX))))
    diagnostics = diagnose_after_release(design, after_dt, iterations, after, diagnostics)
    if machine_after_release:
        shot = _with_machine_after_release(shot, after, design)
    return shot, diagnostics, (float(after_dt) if after_steps else 0.0)


def _with_machine_after_release(shot: Shot, after, design: Design) -> Shot:
    """``shot`` with the machine's motion after release (``AfterRelease``) in its history."""
    q = kin.coordinates(after.states, design, shot.history.q[-1])[0]
    # A sling with mass or a pouch swings on with the machine: its angle psi too.
    history = dataclasses.replace(shot.history, machine_t=after.t,
                                  machine_q=q if kin.sling_swings(design) else q[:, :2],
                                  machine_frame_x=kin.column(after.states, kin.FRAME, kin.X).copy())
    return dataclasses.replace(shot, history=history)


def _peaks(loads: np.ndarray, times: np.ndarray, run: stepping.Run) -> dict[str, float]:
    """``Shot``'s peak loads and their times (``analytic.result.PEAK_NAMES``) over stages 1-2 from the
    (n, 5) ``loads`` on ``times``; none for a machine that never fired (its one row is at rest)."""
    if run.status is Status.NEVER_FIRES:
        return {}
    fields = {}
    joined = fr.smooth(run.friction_slips, len(times))
    for name, (value, time) in zip(PEAK_NAMES, engine_loads.peaks(loads, times, joined), strict=True):
        fields[name], fields[f"{name}_time"] = value, time
    return fields


def _friction_work(run: stepping.Run, sync: np.ndarray, design: Design) -> np.ndarray:
    """(n, 3) the work each friction had taken by each row's instant, J (``friction.dissipated_work``)."""
    if not run.friction_impulse:
        return np.zeros((len(sync), len(fr.JOINTS)))
    qdot = kin.coordinates(sync, design, initial_angles(design.machine, design.base.trough_height))[1]
    return fr.dissipated_work(np.array(run.friction_impulse), fr.rates(sync, qdot, design))


def _friction_steps(run: stepping.Run, dt: float) -> dict[str, np.ndarray] | None:
    """``EngineDiagnostics.friction_steps`` from the run's records (None without friction)."""
    if not run.friction_limit:
        return None
    steps = _step_lengths(len(run.friction_impulse), dt)[:, None]
    count = len(run.friction_limit)
    return {"limit": np.array(run.friction_limit), "applied": np.array(run.friction_impulse)[:count] / steps[:count],
            "load": np.array(run.friction_load)}


def _frame(state: np.ndarray, quantity: int, design: Design) -> float:
    """The frame's ``quantity`` (``kin.X`` or ``kin.VX``) in a row: 0.0 for a fixed frame; a floating
    arm's axle's on its track, its carriage's (as ``analytic.result.Shot`` holds it for that kind)."""
    return float(state[kin.FRAME + quantity]) if kin.origin_carried(design) else 0.0


def _assemble(design: Design, run: stepping.Run, times: np.ndarray, sync: np.ndarray,
              tension: np.ndarray, fields: dict) -> Shot:
    """The ``Shot`` from the synchronised rows (the release instant, if any, is the last row)."""
    q, qdot = kin.coordinates(sync, design, initial_angles(design.machine, design.base.trough_height))
    machine_energy, projectile_energy = kin.energy_budget(sync, design)
    energy = EnergyBudget(projectile=projectile_energy, machine=machine_energy,
                          total=machine_energy + projectile_energy)
    lifted = run.liftoff_time is not None
    stage = np.where(lifted & (times >= (run.liftoff_time if lifted else 0.0)), Stage.SWING, Stage.SLIDE)
    status = run.status or Status.OK
    message = run.message
    released = None
    if status is Status.OK:
        message = outcome.thrown_message(float(fields["landing_position"][0]))
    if "release_time" in fields:
        potential = kin.potential_energies(sync[[0, -1]], design)[0]
        fields["sling_energy_at_release"] = 0.0
        if kin.sling_swings(design):   # the counterweight's and the arm's alone; the sling's named apart
            kinetic, sling_potential = kin.sling_energies(sync[[0, -1]], design)
            potential = potential - sling_potential
            fields["sling_energy_at_release"] = float(kinetic[1] + sling_potential[1] - sling_potential[0])
        released = float(potential[0] - potential[1])
        fields["projectile_energy_at_release"] = float(projectile_energy[-1])
    history = History(t=times, stage=stage.astype(int), q=q, qdot=qdot, path=kin.position(sync, kin.PROJECTILE).copy(),
                      sling_tension=tension, energy=energy, frame_x=kin.column(sync, kin.FRAME, kin.X).copy(),
                      flight_t=fields.pop("flight_t", np.empty(0)), flight_path=fields.pop("flight_path", np.empty((0, 2))))
    return Shot(design, status, message, history=history, counterweight_energy_released=released, **fields)


def smallest_sample(values: np.ndarray) -> float:
    """The minimum of a sampled smooth curve: the vertex of the parabola through the
    smallest sample and its neighbours (the last sample, off the regular grid, is taken as is).

    A sharp dip falls between samples: the rigid sling's tension dip before
    release is about a millisecond wide, and the smallest sample alone misses
    its bottom by up to 1e-3 of it at the default step; the vertex, by about
    1e-6. Only for smooth curves: a rope's tension jumps when it snaps taut.
    """
    i = int(np.argmin(values))
    if not 0 < i < len(values) - 2:
        return float(values[i])
    before, at, after = values[i - 1], values[i], values[i + 1]
    curvature = before - 2.0 * at + after
    if curvature <= 0.0:
        return float(at)
    return float(at - (after - before) ** 2 / (8.0 * curvature))


def largest_speed(velocity: np.ndarray) -> float:
    """The largest |value| of a sampled smooth velocity (each sign's extreme as in ``smallest_sample``)."""
    return max(-smallest_sample(velocity), -smallest_sample(-velocity), 0.0)
