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

import numpy as np

from analytic import outcome
from analytic.design import Design, initial_angles
from analytic.result import PEAK_NAMES, EnergyBudget, History, Shot, Stage, Status
from engine_model import floating
from engine_model import friction as fr
from engine_model import kinematics as kin
from engine_model import loads as engine_loads
from engine_model import stepping
from engine_model.after_release import after_release_steps, run_after_release
from engine_model.budget import after_release_step, flight_step_base, run_within_budget
from engine_model.build import DEFAULT_ITERATIONS, EngineError
from engine_model.diagnostics import diagnose, diagnose_after_release
from engine_model.events import interpolate
from engine_model.flight import FLIGHT_STEP_LIMIT, FLIGHT_STEP_MULTIPLE, fly


def simulate(design: Design, *, dt: float | None = None, iterations: int = DEFAULT_ITERATIONS,
             sling: str = "rigid", machine_after_release: bool = False) -> Shot:
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
        is kept whatever it costs (up to ``stepping.MACHINE_STEP_LIMIT`` steps).
    iterations : pymunk solver iterations per step (at least about 20).
    sling : ``"rigid"`` (PinJoint) or ``"rope"`` (SlideJoint, pulls only).
    machine_after_release : also step a fixed frame's machine on from release to landing (a
        rolling one's always is) and keep its motion in ``history.machine_t``, ``machine_q`` and
        ``machine_frame_x``, for drawing it swinging on (``engine_model.render``).

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
    discarded = 0
    if budget:
        dt, run, rig, discarded = run_within_budget(design, iterations, sling)
    elif not (math.isfinite(dt) and dt > 0.0):
        raise ValueError(f"dt = {dt!r}: must be a positive number of seconds")
    else:
        run, rig = stepping.run_machine(design, dt, iterations, sling, stepping.MACHINE_STEP_LIMIT)
    raw = np.array(run.raw)
    on_base = np.array(run.on_base)
    sync = kin.synchronise(raw, kin.origin_carried(design))
    drift = kin.joint_drift(raw, design, sling, on_base)
    steps = np.full(len(raw), dt)
    steps[0] = 0.5 * dt
    residual = kin.constraint_residuals(raw, design, sling, on_base, steps)
    times = dt * np.arange(len(raw))
    tension = np.array(run.tension)
    slide_friction = fr.slide_forces(np.array(run.friction_impulse).reshape(-1, len(fr.JOINTS)), raw, design, steps)
    loads = engine_loads.load_histories(raw, tension, design, dt, slide_friction)
    # A floating arm's guide's and track's push: the supports' force less their friction.
    supports = (engine_loads.support_force(raw, engine_loads.sling_force(raw, tension, design), design, dt)
                - slide_friction)
    axle_x = None
    dissipated = _friction_work(run, sync, design)
    swing_drag = np.array(run.drag_work) if len(run.drag_work) == len(raw) else np.zeros(len(raw))

    fields: dict = {"liftoff_time": run.liftoff_time}
    flight_steps = 0
    drag_work = 0.0
    if run.release_fraction is not None:
        s = run.release_fraction
        release_time = times[-2] + s * dt
        release_state = interpolate(sync[-3:], s)
        # A rope's tension jumps when it snaps taut: no parabola through a jump.
        release_tension = interpolate(tension[-3:] if sling == "rigid" else tension[-2:], s)
        sync = np.vstack([sync[:-1], release_state])
        dissipated = np.vstack([dissipated[:-1], interpolate(dissipated[-3:], s)])
        swing_drag = np.append(swing_drag[:-1], interpolate(swing_drag[-3:], s))
        tension = np.append(tension[:-1], release_tension)
        loads = np.vstack([loads[:-1], interpolate(loads[-3:], s)])
        supports = np.vstack([supports[:-1], interpolate(supports[-3:], s)])
        axle_x = float(release_state[kin.ARM + kin.X])
        times = np.append(times[:-1], release_time)
        position = kin.position(release_state[None, :], kin.PROJECTILE)[0]
        velocity = kin.velocity(release_state[None, :], kin.PROJECTILE)[0]
        # Within the budget the flight steps at the default's multiple (a lone body's steps are
        # cheap), lengthened only for a flight far longer than anything buildable throws.
        flight_base = flight_step_base(design, position, velocity) if budget else dt
        flight = fly(design, release_time, position, velocity, flight_base)
        flight_steps = flight.steps
        drag_work = flight.drag_work
        fields.update(release_time=release_time, release_position=position,
                      release_velocity=velocity, flight_t=flight.t, flight_path=flight.path,
                      frame_release_displacement=_frame(release_state, kin.X, design),
                      frame_release_velocity=_frame(release_state, kin.VX, design))
        if flight.landed:
            fields.update(landing_time=flight.landing_time, landing_position=flight.landing_position,
                          apex_height=flight.apex + design.machine.pivot_height)
        elif flight.out_of_steps:
            run.status = Status.STEP_FAILED
            run.message = stepping.step_limit_message("the flight", flight.steps, FLIGHT_STEP_MULTIPLE * flight_base,
                                                      flight.limit, FLIGHT_STEP_LIMIT)
        else:
            run.status, run.message = Status.NO_LANDING, outcome.no_landing_message(flight.limit)
    fields["min_sling_tension"] = (smallest_sample(tension) if sling == "rigid"
                                   else float(tension.min()))
    fields["max_frame_speed"] = largest_speed(kin.column(sync, kin.FRAME, kin.VX)) if design.base.rolling else 0.0
    fields.update(_peaks(loads, times, run))
    fields["energy_dissipated"] = {**dict(zip(fr.JOINTS, (float(w) for w in dissipated[-1]), strict=True)),
                                   "drag": float(drag_work), "swing_drag": float(swing_drag[-1])}
    shot = _assemble(design, run, times, sync, tension, fields)
    diagnostics = diagnose(design, dt, iterations, sling, len(raw), flight_steps, drift, residual, shot, sync,
                            dissipated, swing_drag)
    after_dt = dt
    if budget and shot.landing_time is not None and design.base.rolling:
        after_dt = after_release_step(dt, shot.release_time, shot.landing_time, len(raw), discarded)
    after_steps = (0 if shot.landing_time is None or not design.base.rolling
                   else after_release_steps(shot.release_time, shot.landing_time, after_dt))
    if after_steps > stepping.MACHINE_STEP_LIMIT:
        time_bound = shot.landing_time - shot.release_time
        shot = dataclasses.replace(shot, status=Status.STEP_FAILED, message=stepping.step_limit_message(
            "the rolling machine's run after release", after_steps, dt, time_bound, ahead=True))
    elif shot.landing_time is not None:
        if not design.base.rolling:
            shot = dataclasses.replace(shot, frame_landing_displacement=0.0, frame_landing_velocity=0.0)
            if machine_after_release:
                after_dt = after_release_step(dt, shot.release_time, shot.landing_time, len(raw), discarded)
                after = run_after_release(design, shot.release_time, release_state, shot.landing_time, after_dt,
                                          iterations, stepping.STARTUP_ITERATIONS)
                shot = _with_machine_after_release(shot, after, design)
        else:
            # The machine was trusted up to release; only then is it worth stepping on.
            after = run_after_release(design, shot.release_time, release_state, shot.landing_time, after_dt,
                                      iterations, stepping.STARTUP_ITERATIONS)
            landing = after.landing_state
            shot = dataclasses.replace(
                shot, frame_landing_displacement=float(landing[kin.FRAME + kin.X]),
                frame_landing_velocity=float(landing[kin.FRAME + kin.VX]),
                max_frame_speed=max(shot.max_frame_speed,
                                    largest_speed(kin.column(after.states, kin.FRAME, kin.VX))))
            diagnostics = diagnose_after_release(design, after_dt, iterations, after, diagnostics)
            if machine_after_release:
                shot = _with_machine_after_release(shot, after, design)
    diagnostics = dataclasses.replace(diagnostics, friction_steps=_friction_steps(run, dt),
                                      after_release_dt=float(after_dt) if after_steps else 0.0,
                                      discarded_steps=discarded if budget else 0)
    if design.machine.kind == "floating-arm":
        diagnostics = dataclasses.replace(diagnostics,
                                          support_loads=floating.support_loads(supports, times, axle_x))
    return dataclasses.replace(shot, diagnostics=diagnostics)


def _with_machine_after_release(shot: Shot, after, design: Design) -> Shot:
    """``shot`` with the machine's motion after release (``AfterRelease``) in its history."""
    q = kin.coordinates(after.states, design, shot.history.q[-1])[0]
    history = dataclasses.replace(shot.history, machine_t=after.t, machine_q=q[:, :2],
                                  machine_frame_x=kin.column(after.states, kin.FRAME, kin.X).copy())
    return dataclasses.replace(shot, history=history)


def _peaks(loads: np.ndarray, times: np.ndarray, run: stepping.Run) -> dict[str, float]:
    """``Shot``'s peak loads and their times (``analytic.result.PEAK_NAMES``) over stages 1-2 from the
    (n, 4) ``loads`` on ``times``; none for a machine that never fired (its one row is at rest)."""
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
    qdot = kin.coordinates(sync, design, initial_angles(design.machine))[1]
    return fr.dissipated_work(np.array(run.friction_impulse), fr.rates(sync, qdot, design))


def _friction_steps(run: stepping.Run, dt: float) -> dict[str, np.ndarray] | None:
    """``EngineDiagnostics.friction_steps`` from the run's records (None without friction)."""
    if not run.friction_limit:
        return None
    steps = np.full((len(run.friction_impulse), 1), dt)
    steps[0] = 0.5 * dt
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
    q, qdot = kin.coordinates(sync, design, initial_angles(design.machine))
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
