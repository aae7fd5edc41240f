"""The stepping loop of stages 1-2 in pymunk: fire, slide, swing, up to release or a failure.

``run_machine`` steps the machine at a fixed ``dt`` from rest and watches
for lift-off, release and the failures after every step, with the friction
joints' limits set from the loads of the steps before; ``engine_model.shot``
turns what it gathers (``Run``) into a ``Shot``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from analytic import outcome
from analytic.design import Design, Machine, largest_length
from analytic.geometry import IDEAL_RULE, RELEASE_RULES, ideal_release, release_value
from analytic.limits import SLING_VERTICAL_LIMIT, swing_time_limit
from analytic.outcome import LiftoffFailure
from analytic.result import Status
from engine_model import floating
from engine_model import friction as fr
from engine_model import kinematics as kin
from engine_model.build import EngineError, Rig, build, trough_level
from engine_model.events import crossing_fraction
from engine_model.flight import swing_drag_function
from engine_model.readout import impulse, rig_row, row_reader, set_force, stepper

#: The projectile (in stage 2) or the long-arm tip (in stage 1) counts as back
#: on the base once this far below base level, m: far above the round-off
#: (1e-15 m) they leave it with, far below any real dip.
BASE_TOLERANCE = 1e-9
#: Solver iterations of the opening step, which has no previous impulses to start from.
STARTUP_ITERATIONS = 1000
#: Solver iterations of the opening step taken again, with friction, to tell whether the machine is
#: held at rest: where the base's friction holds it through a light sling (a rod of a few per cent
#: of the projectile's mass), the solver's stuck joints converge slowly from nothing (the arm's
#: acceleration at rest read -0.015 rad/s^2 after 1,000 iterations, -8e-5 after 3,000 and round-off
#: after 10,000 on a 3.9 g sling on a trough); a machine that fires keeps its first opening step.
HOLD_ITERATIONS = 30_000
#: Most pymunk steps in stages 1-2 (and in a rolling machine's run after
#: release), after which the run ends as ``STEP_FAILED``: the analogue of the
#: analytic paths' ``STAGE_STEP_LIMITS``. The engine's step is fixed, so a
#: slow machine needs more of them: the swing's time bound grows as
#: 1/sqrt(gravity), and at 1e-6 m/s^2 the paper's machine would need 1e9
#: steps (hours). The most any design of the cross-check's suite takes is
#: 147,168 (its never-releasing design, run to the bound at the default
#: step); 400,000 is about 16 s of stepping.
MACHINE_STEP_LIMIT = 400_000


@dataclass
class Run:
    """What the stepping loop gathers (internal, mutable while it runs)."""

    raw: list = field(default_factory=list)
    on_base: list = field(default_factory=list)
    tension: list = field(default_factory=list)
    normal: list = field(default_factory=list)
    release_value: list = field(default_factory=list)
    drag_work: list = field(default_factory=list)
    friction_impulse: list = field(default_factory=list)
    friction_limit: list = field(default_factory=list)
    friction_load: list = field(default_factory=list)
    friction_slips: list = field(default_factory=list)
    liftoff_time: float | None = None
    status: Status | None = None
    message: str = ""
    release_fraction: float | None = None
    out_of_steps: bool = False


def read_state(rig: Rig) -> tuple[float, ...]:
    """The 24 numbers of a state row (``engine_model.kinematics``) read from the bodies."""
    return rig_row(*row_bodies(rig))


def row_bodies(rig: Rig) -> tuple:
    """What a state row is read from (``readout.rig_row``'s arguments): a floating arm's carriage
    stands in the frame's columns (the arm's origin is pinned to it, as to a rolling frame) and its
    slider in the counterweight's (the counterweight's centre, held on the guide)."""
    if rig.supports:
        carriage, slider = rig.supports[:2]
        return rig.arm, None, rig.projectile, carriage, None, slider
    return rig.arm, rig.counterweight, rig.projectile, rig.frame, rig.mount


class _Take(NamedTuple):
    """One take of the opening half step: the machine built with its friction limits set from
    ``loads`` (N) and ``slips`` (each joint's mode), and the row read after the half step."""

    rig: Rig
    friction: fr.Friction | None
    row: tuple[float, ...]
    loads: tuple[float, ...]
    slips: tuple[bool, ...]


class _Forces(NamedTuple):
    """The forces on the projectile over a step, N: the base's friction (signed, +x), the sling's
    tension and the base's normal force (``_forces``)."""

    base_friction: float
    tension: float
    normal: float


@dataclass
class _Joints:
    """The friction joints as the stepping loop carries them from step to step (internal, mutable):
    each joint's mode (``slips``, ``friction.slipping``) and rate, and the loads of the last two
    steps, from which the coming step's limits are extrapolated (``friction.predicted_loads``)."""

    friction: fr.Friction
    slips: tuple[bool, ...]
    rates: tuple[float, ...]
    loads: tuple[float, ...]
    earlier_loads: tuple[float, ...] | None = None


@dataclass(frozen=True)
class _Opening:
    """The machine after its opening half step, as the stepping loop takes it over (``joints`` None
    without friction; ``startup``, the solver iterations of a step that starts from nothing)."""

    rig: Rig
    row: tuple[float, ...]
    on_base: bool
    joints: _Joints | None
    startup: int


def run_machine(design: Design, dt: float, iterations: int, sling: str, limit: int = MACHINE_STEP_LIMIT,
                at_limit: Callable[[int], int | None] | None = None) -> tuple[Run, Rig]:
    """Step stages 1 and 2 until release, a failure, or ``limit`` steps (``STEP_FAILED``, and
    ``run.out_of_steps``); the loop behind ``simulate``. At the limit, ``at_limit(steps)`` may
    give a new one, and the run goes on as if that had been its limit all along."""
    run = Run()
    drag = swing_drag_function(design)
    rig, opening = _open(design, dt, iterations, sling, drag, run)
    if opening is None:
        return run, rig
    return _step_to_release(design, dt, iterations, limit, at_limit, drag, run, opening)


def _open(design: Design, dt: float, iterations: int, sling: str, drag, run: Run) -> tuple[Rig, _Opening | None]:
    """Build the machine and take its opening half step from rest, recorded as ``run``'s first row.

    No ``_Opening`` where the machine does not fire (``run.status`` then says why). A sling
    that lifts the projectile at rest starts again without the base; with friction, the half
    step is taken again with the limits its own loads give (``_retake_opening``). Friction's verdict
    at rest is read from a half step solved to convergence (``HOLD_ITERATIONS``) where the first
    one's arm still moves.
    """
    startup = floating.STARTUP_ITERATIONS if design.machine.kind == "floating-arm" else STARTUP_ITERATIONS
    resting = fr.static_loads(design)
    take = _take_opening(design, dt, iterations, sling, drag, startup, True, resting, fr.STUCK)
    message = _never_fires_message(design, take.friction, take.row, dt)
    if message is None and take.friction is not None:
        held, message = _held_at_rest(design, dt, iterations, sling, drag, resting)
        if message is not None:
            take = held
    if message is not None:
        run.raw.append(take.row)
        run.on_base.append(True)
        run.tension.append(0.0)
        if take.friction is not None:
            run.friction_impulse.append(fr.impulses(take.friction, True))
        run.status, run.message = Status.NEVER_FIRES, message
        return take.rig, None
    on_base = True
    forces = _opening_forces(take, on_base, design, dt, drag)
    if forces.normal < 0.0:
        # The sling lifts the projectile at rest: start again without the base.
        on_base = False
        take = _take_opening(design, dt, iterations, sling, drag, startup, on_base, resting, fr.STUCK)
        forces = _opening_forces(take, on_base, design, dt, drag)
        run.liftoff_time = 0.0
    if take.friction is not None:
        take, forces = _retake_opening(design, dt, iterations, sling, drag, startup, on_base, take, forces)
    row, m = take.row, design.machine
    run.raw.append(row)
    run.on_base.append(on_base)
    run.tension.append(forces.tension)
    run.normal.append(forces.normal)
    run.release_value.append(_release(row, row, _row_geometry(row, m), *_rule(m))[0])
    run.drag_work.append(_drag_work(_rest_drag(drag), (0.0, 0.0), row, 0.5 * dt))
    joints = None
    if take.friction is not None:
        joints = _record_opening_joints(run, take, design, dt, on_base,
                                        (forces.base_friction, forces.normal if on_base else 0.0))
    return take.rig, _Opening(take.rig, row, on_base, joints, startup)


def _held_at_rest(design: Design, dt: float, iterations: int, sling: str, drag,
                  loads: tuple[float, ...]) -> tuple[_Take, str | None]:
    """Whether friction holds the machine at rest, from opening half steps solved to convergence
    (``HOLD_ITERATIONS``) with every joint stuck: the take, and why it never fires (None: it fires).

    The limits start from the weights (``friction.static_loads``); with a floating arm's slides they
    are taken again from the loads each take measures until those settle (the guide carries nothing
    at rest until the track's friction asks it to push), as ``_retake_opening`` does for a machine
    that fires.
    """
    for _ in range(fr.OPENING_RETAKES):
        take = _take_opening(design, dt, iterations, sling, drag, HOLD_ITERATIONS, True, loads, fr.STUCK)
        message = _never_fires_message(design, take.friction, take.row, dt)
        if message is not None or not fr.slides(take.friction):
            break
        forces = _opening_forces(take, True, design, dt, drag)
        measured = _loads(take.friction, take.rig, _mirrored(take.row), take.row, design,
                          (forces.base_friction, forces.normal), dt, 0.5 * dt)
        if fr.settled(measured, loads):
            break
        loads = measured
    return take, message


def _take_opening(design: Design, dt: float, iterations: int, sling: str, drag, startup: int, on_base: bool,
                  loads: tuple[float, ...], slips: tuple[bool, ...]) -> _Take:
    """Build the machine (its projectile held on the base or not), its friction's limits set from
    ``loads`` and ``slips`` (``_attach_friction``), and take the opening half step."""
    rig = build(design, sling=sling, iterations=iterations, on_base=on_base)
    friction = _attach_friction(rig, design, on_base, dt, loads, slips)
    return _Take(rig, friction, _opening_step(rig, dt, iterations, drag, startup), loads, slips)


def _opening_forces(take: _Take, on_base: bool, design: Design, dt: float, drag) -> _Forces:
    """The forces on the projectile over the opening half step of ``take`` (the wind's drag on it at rest)."""
    geometry = _row_geometry(take.row, design.machine)
    base_force = _base_friction(take.friction, take.rig, 0.5 * dt, geometry, on_base)
    return _Forces(base_force, *_forces(take.row, take.row, geometry, on_base, design, dt, base_force,
                                        _rest_drag(drag)))


def _never_fires_message(design: Design, friction: fr.Friction | None, row: tuple[float, ...],
                         dt: float) -> str | None:
    """Why the machine stays at rest (``analytic.outcome.never_fires_message``), read from the opening
    half step's ``row``; None where it fires.

    From rest the opening half step gives the arm omega = alpha dt/2 (pymunk updates velocities
    first), so that is its angular acceleration at rest. Friction holds it where the axle's static
    friction balances the weights' torque, or where the arm hardly moves at all.
    """
    arm_acceleration = row[kin.ARM + kin.W] / (0.5 * dt)
    if friction is not None:
        balance = fr.static_balance(design, np.array(row))
        held = abs(arm_acceleration) <= fr.HELD_ACCELERATION
        if (friction.axle is not None and balance.holds) or held:
            if fr.slides(friction):
                return outcome.never_fires_message(arm_acceleration, held_by=fr.holders(friction))
            return outcome.never_fires_message(arm_acceleration, -balance.gravity_torque, balance.holding_torque)
    if not arm_acceleration < 0.0:
        return outcome.never_fires_message(arm_acceleration)
    return None


def _retake_opening(design: Design, dt: float, iterations: int, sling: str, drag, startup: int, on_base: bool,
                    take: _Take, forces: _Forces) -> tuple[_Take, _Forces]:
    """The opening half step taken again with the friction limits its own loads give, and its forces.

    The loads at rest are the weights, but the moving machine's are not (the axle's is half of it
    on the paper's design): the half step is taken again once with the limits its loads give (its
    range moved by 1.2e-5 m); with a floating arm's slides, until its loads settle
    (``friction.settled``). The joints that broke free of their static hold slip from the start:
    kinetic limits.
    """
    for retake in range(fr.OPENING_RETAKES if fr.slides(take.friction) else 1):
        measured = _loads(take.friction, take.rig, _mirrored(take.row), take.row, design,
                          (forces.base_friction, forces.normal if on_base else 0.0), dt, 0.5 * dt)
        if retake and fr.settled(measured, take.loads):
            break
        slips = fr.slipping(take.friction, 0.5 * dt, fr.joint_rates(take.row, design), fr.AT_REST)
        take = _take_opening(design, dt, iterations, sling, drag, startup, on_base, measured, slips)
        forces = _opening_forces(take, on_base, design, dt, drag)
    return take, forces


def _record_opening_joints(run: Run, take: _Take, design: Design, dt: float, on_base: bool,
                           base_loads: tuple[float, float]) -> _Joints:
    """Record the friction joints of the opening half step in ``run`` (impulses, limits, modes,
    loads) and renew them for the first whole step (``friction.renew``); ``base_loads``: the base's
    friction and normal force, N (``_loads``)."""
    friction, rig, row = take.friction, take.rig, take.row
    run.friction_impulse.append(fr.impulses(friction, on_base))
    loads = _loads(friction, rig, _mirrored(row), row, design, base_loads, dt, 0.5 * dt)
    run.friction_limit.append(fr.limits(design, take.loads, take.slips))
    run.friction_slips.append(take.slips)
    run.friction_load.append(loads)
    rates = fr.joint_rates(row, design)
    slips = fr.slipping(friction, 0.5 * dt, rates, fr.AT_REST)
    return _Joints(fr.renew(friction, rig), slips, rates, loads)


def _step_to_release(design: Design, dt: float, iterations: int, limit: int,
                     at_limit: Callable[[int], int | None] | None, drag, run: Run,
                     opening: _Opening) -> tuple[Run, Rig]:
    """Step the machine on from its opening half step, recording each step in ``run``, and watch for
    lift-off, release and the failures after each (``run_machine``)."""
    m = design.machine
    # The projectile slides on the trough (the base without one), and falls back onto it in the swing.
    h, t_limit = trough_level(design), swing_time_limit(largest_length(m), design.environment.gravity)
    rule, alpha = _rule(m)
    rig, joints, on_base, startup = opening.rig, opening.joints, opening.on_base, opening.startup
    floating_arm = bool(rig.supports)
    step = stepper(rig.space)
    read = row_reader(*row_bodies(rig))
    # The loop runs up to hundreds of thousands of times: its lists' appends and the row's
    # indices are looked up once.
    keep_row, keep_on_base, keep_tension = run.raw.append, run.on_base.append, run.tension.append
    keep_normal, keep_value = run.normal.append, run.release_value.append
    y_index, vy_index = kin.PROJECTILE + kin.Y, kin.PROJECTILE + kin.VY
    previous, previous_value, force = opening.row, run.release_value[-1], _rest_drag(drag)
    # The axle's or the base's friction can stop the arm before lift-off (its clockwise turn
    # ends): the shot ends there, as in the analytic model (``docs/derivation.md``, 10.4).
    stalls = joints is not None and (design.losses.axle_friction > 0.0 or design.losses.base_friction > 0.0)
    k = 0
    while True:
        if joints is not None:
            _limit_coming_step(joints, run, rig, dt, floating_arm)
        if k >= limit:
            more = None if at_limit is None else at_limit(k)
            if more is None or more <= k:
                run.out_of_steps = True
                return _fail(run, rig, Status.STEP_FAILED, step_limit_message("stages 1-2", k, dt, t_limit, limit))
            limit = more
        if drag is not None:
            force = _push_drag(drag, rig, previous, run.raw[-2] if len(run.raw) > 1 else previous)
        _step(rig, step, dt, iterations, startup, floating_arm and floating.resolves(k, run.friction_slips))
        k += 1
        row = read()
        if not math.isfinite(sum(row)):
            raise _unstable(k, dt, iterations)
        geometry = _row_geometry(row, m)
        if drag is not None:
            run.drag_work.append(run.drag_work[-1] + _drag_work(force, _velocity(previous), row, dt))
        if joints is None:
            tension, normal = _forces(previous, row, geometry, on_base, design, dt, drag_force=force)
        else:
            tension, normal = _forces_and_joints(joints, run, rig, previous, row, geometry, on_base, design, dt, k,
                                                 force)
        value, armed = _release(previous, row, geometry, rule, alpha)
        keep_row(row)
        keep_on_base(on_base)
        keep_tension(tension)
        keep_normal(normal)
        keep_value(value)
        previous = row
        earlier_value, previous_value = previous_value, value
        t = k * dt

        if on_base:
            if normal < 0.0:
                _lift_off(run, rig, joints, k, dt)
                on_base = False
            elif (failure := _slide_failure(row, geometry, t, stalls, h, t_limit)) is not None:
                return _fail(run, rig, Status.NEVER_LIFTS_OFF, outcome.never_lifts_off_message(failure, t_limit))
            continue

        if row[y_index] + h < -BASE_TOLERANCE and row[vy_index] < 0.0:
            return _fail(run, rig, Status.HITS_BASE_BEFORE_RELEASE, outcome.hits_base_message(t))
        if earlier_value < 0.0 <= value and armed:
            run.release_fraction = crossing_fraction(tuple(run.release_value[-3:]))
            return run, rig
        if t > t_limit:
            return _fail(run, rig, Status.NEVER_RELEASES,
                         outcome.never_releases_message(m.release_rule, m.release_angle, t_limit))


def _limit_coming_step(joints: _Joints, run: Run, rig: Rig, dt: float, coupled: bool) -> None:
    """Set each friction joint's limit for the coming step from its loads extrapolated (where its mode
    held, ``friction.steady``; ``coupled`` for a floating arm), record the limits and modes in ``run``,
    and aim the joints (``friction.aim``)."""
    steady = fr.steady(run.friction_slips, joints.slips, coupled=coupled)
    predicted = fr.predicted_loads(joints.loads, joints.earlier_loads, steady)
    run.friction_limit.append(fr.set_limits(joints.friction, predicted, joints.slips))
    run.friction_slips.append(joints.slips)
    fr.aim(joints.friction, rig, dt)


def _step(rig: Rig, step: Callable[[float], None], dt: float, iterations: int, startup: int, resolve: bool) -> None:
    """One step of ``dt``; with ``resolve`` (a floating arm's, ``floating.resolves``) solved with
    ``startup`` iterations instead of ``iterations``."""
    if resolve:
        rig.space.iterations = startup
    step(dt)
    if resolve:
        rig.space.iterations = iterations


def _unstable(steps: int, dt: float, iterations: int) -> EngineError:
    """The error of a run whose state went non-finite after ``steps`` steps."""
    return EngineError(f"the engine went unstable (non-finite state) at t = {steps * dt:.5g} s "
                       f"with dt = {dt:g} s and {iterations} iterations: use a smaller dt "
                       f"or more iterations")


def _forces_and_joints(joints: _Joints, run: Run, rig: Rig, before: tuple, row: tuple, geometry: tuple,
                       on_base: bool, design: Design, dt: float, k: int,
                       drag_force: tuple[float, float]) -> tuple[float, float]:
    """The sling's tension and the base's normal force over the ``k``-th step (``_forces``) with
    friction, and the friction joints after it: their impulses recorded in ``run``, their modes,
    rates and loads (the coming steps' limits) in ``joints``."""
    friction = joints.friction
    base_force = _base_friction(friction, rig, dt, geometry, on_base)
    tension, normal = _forces(before, row, geometry, on_base, design, dt, base_force, drag_force)
    run.friction_impulse.append(fr.impulses(friction, on_base))
    rates, earlier_rates = fr.joint_rates(row, design), joints.rates
    joints.rates, joints.slips = rates, fr.slipping(friction, dt, rates, earlier_rates)
    joints.earlier_loads = joints.loads
    if k > 1:
        joints.loads = _loads(friction, rig, before, row, design, (base_force, normal if on_base else 0.0), dt, dt)
    if k == 2:   # the line from the opening half step's loads, two steps back
        joints.earlier_loads = tuple(0.5 * (a + b) for a, b in zip(joints.earlier_loads, joints.loads, strict=True))
    # At k = 1 pymunk's joints misreport the first whole step after the half step
    # (``friction.renew``): the opening half step's loads stand in.
    run.friction_load.append(joints.loads)
    return tension, normal


def _lift_off(run: Run, rig: Rig, joints: _Joints | None, k: int, dt: float) -> None:
    """The projectile leaves the base in the ``k``-th step: its instant where the normal force crosses
    zero (``events.crossing_fraction``), and the base (its groove, its friction) taken away."""
    fraction = crossing_fraction(tuple(run.normal[-3:]))
    run.liftoff_time = (k - 1 + fraction) * dt
    rig.space.remove(rig.groove)
    if joints is not None:
        fr.remove_base(joints.friction, rig.space)


def _slide_failure(row: tuple, geometry: tuple, t: float, stalls: bool, pivot_height: float,
                   t_limit: float) -> LiftoffFailure | None:
    """Why a projectile still on the base at ``t`` can no longer lift off, or None: the arm stopped
    by friction (where it ``stalls``), the sling under the tip, the tip back on the base (on the
    trough, ``pivot_height`` the trough's level below the pivot), or the swing's time bound passed."""
    if stalls and row[kin.ARM + kin.W] >= 0.0:
        return LiftoffFailure.STALLED
    if geometry[2] < SLING_VERTICAL_LIMIT:
        return LiftoffFailure.UNDER_TIP
    if geometry[1] + pivot_height < -BASE_TOLERANCE:
        return LiftoffFailure.ARM_BACK
    if t > t_limit:
        return LiftoffFailure.TIME_LIMIT
    return None


def _attach_friction(rig: Rig, design: Design, on_base: bool, dt: float,
                     loads: tuple[float, ...] | None = None,
                     slips: tuple[bool, ...] = fr.STUCK) -> fr.Friction | None:
    """``engine_model.friction.attach``, its limits set for the opening half step from ``loads`` (N;
    default: the loads at rest, ``friction.static_loads``) and the joints' ``slips`` (default: each
    held at rest, its static limit)."""
    friction = fr.attach(rig, design, on_base)
    if friction is not None:
        fr.set_limits(friction, fr.static_loads(design) if loads is None else loads, slips)
        fr.aim(friction, rig, 0.5 * dt)
    return friction


def _mirrored(row: tuple) -> tuple:
    """The row with its velocities reversed: the half step before rest (``kinematics.synchronise``)."""
    return tuple(-v if i % 6 >= kin.VX else v for i, v in enumerate(row))


def _base_friction(friction: fr.Friction | None, rig: Rig, step: float, geometry: tuple,
                   on_base: bool) -> float:
    """The base's friction force on the projectile in the last step of ``step`` s, N, signed (0 off the base)."""
    if friction is None or not on_base:
        return 0.0
    return fr.base_friction_force(friction, rig, step, -geometry[2])


def _loads(friction: fr.Friction, rig: Rig, before: tuple, row: tuple, design: Design,
           base_force: tuple[float, float], dt: float, step: float) -> tuple[float, ...]:
    """Each friction joint's load (``friction.JOINTS``) in the step of ``step`` s that produced ``row``, N:
    the next step's limits.

    ``before`` is the row before (for the opening half step, ``_mirrored(row)``,
    whose velocity change over ``dt`` is the half step's over ``dt / 2``).
    """
    if friction.axle is None:
        axle = 0.0
    elif rig.supports:
        axle = fr.track_axle_load(friction, rig, step)
    elif friction.ballast > 0.0:
        axle = fr.axle_load_from_momentum(before, row, design, base_force, dt)
    else:
        axle = impulse(rig.pivot) / step
    hinge = 0.0 if rig.hinge is None else impulse(rig.hinge) / step
    if friction.point_hinge:
        hinge = math.hypot(hinge, impulse(friction.hinge) / step)
    base = impulse(rig.groove) / step if friction.base is not None else 0.0
    return axle, hinge, base, *fr.slide_loads(friction, rig, step)


def _rest_drag(drag) -> tuple[float, float]:
    """The drag on the projectile at rest (the wind's push), N; 0 without drag in stages 1-2."""
    return (0.0, 0.0) if drag is None else drag(0.0, 0.0)


def _velocity(row: tuple) -> tuple[float, float]:
    """The projectile's velocity in a state row, m/s."""
    return row[kin.PROJECTILE + kin.VX], row[kin.PROJECTILE + kin.VY]


def _push_drag(drag, rig: Rig, row: tuple, before: tuple) -> tuple[float, float]:
    """Set the drag on the projectile for the next step, and return it (N): the flight's law at its
    velocity at the step's start, ``t_k``, extrapolated from the leapfrog's half-step velocities
    ``v[k-1/2]`` (``row``) and ``v[k-3/2]`` (``before``)."""
    (vx, vy), (bx, by) = _velocity(row), _velocity(before)
    force = drag(1.5 * vx - 0.5 * bx, 1.5 * vy - 0.5 * by)
    set_force(rig.projectile, *force)
    return force


def _drag_work(force: tuple[float, float], velocity_before: tuple[float, float], row: tuple, step: float) -> float:
    """The work the drag ``force`` (N) took from the projectile over a step of ``step`` s that ended in
    ``row``: ``-F . v`` with ``v`` the mean of the velocities either side of the kick, J."""
    vx, vy = _velocity(row)
    return -(force[0] * 0.5 * (velocity_before[0] + vx) + force[1] * 0.5 * (velocity_before[1] + vy)) * step


def _opening_step(rig: Rig, dt: float, iterations: int, drag=None,
                  startup: int = STARTUP_ITERATIONS) -> tuple[float, ...]:
    """Half a step from rest: the positions stay at t = 0, the velocities reach dt/2 (leapfrog start);
    ``drag`` (``flight.swing_drag_function``, or None): the drag at rest (the wind's) acts over it.

    Later steps start their solver from the previous step's impulses; this one
    starts from nothing, so it gets ``startup`` iterations to converge (``STARTUP_ITERATIONS``: with
    the usual count the sling tension rings by 10 % for a dozen steps; more for a floating arm,
    ``floating.STARTUP_ITERATIONS``).
    """
    rig.space.iterations = max(startup, iterations)
    if drag is not None:
        set_force(rig.projectile, *_rest_drag(drag))
    rig.space.step(0.5 * dt)
    rig.space.iterations = iterations
    return read_state(rig)


def step_limit_message(part: str, steps: int, dt: float, time_bound: float, limit: int = MACHINE_STEP_LIMIT,
                       ahead: bool = False) -> str:
    """``analytic.outcome.step_budget_message``, the machine's ``MACHINE_STEP_LIMIT`` by default."""
    return outcome.step_budget_message(part, steps, dt, time_bound, limit, ahead)


def _fail(run: Run, rig: Rig, status: Status, message: str) -> tuple[Run, Rig]:
    run.status, run.message = status, message
    return run, rig


def _row_geometry(row: tuple[float, ...], machine: Machine) -> tuple[float, float, float, float, float]:
    """Long tip (x, y), sling unit vector (x, y) from tip to projectile, and the sling's length."""
    theta = row[kin.ARM + kin.ANGLE]
    tip_x = row[kin.ARM + kin.X] - machine.arm_long * math.sin(theta)
    tip_y = row[kin.ARM + kin.Y] + machine.arm_long * math.cos(theta)
    dx, dy = row[kin.PROJECTILE + kin.X] - tip_x, row[kin.PROJECTILE + kin.Y] - tip_y
    length = math.hypot(dx, dy)
    return tip_x, tip_y, dx / length, dy / length, length


def _forces(before: tuple, row: tuple, geometry: tuple, on_base: bool, design: Design,
            dt: float, base_friction: float = 0.0,
            drag_force: tuple[float, float] = (0.0, 0.0)) -> tuple[float, float]:
    """Sling tension and base normal force over the step that produced ``row`` (``kin.contact_forces``;
    ``base_friction``, N, the base's friction force on the projectile; ``drag_force``, N, the air's; a
    sling with mass, its shear, ``kin.sling_shear``)."""
    p = kin.PROJECTILE
    if before is row:  # the opening half step: the velocity before it is the mirror image
        v_before = (-row[p + kin.VX], -row[p + kin.VY])
    else:
        v_before = (before[p + kin.VX], before[p + kin.VY])
    shear = 0.0
    if on_base and design.machine.sling_mass > 0.0:   # off the base the tension is the pull along u alone
        shear = kin.sling_shear(_mirrored(row) if before is row else before, row, design, dt)
    return kin.contact_forces(v_before, (row[p + kin.VX], row[p + kin.VY]), geometry[:2],
                              (row[p + kin.X], row[p + kin.Y]), on_base, design, dt, base_friction, drag_force,
                              shear)


def _rule(machine: Machine) -> tuple[int, float]:
    """The release rule's code and angle. The ideal rule's angle is the arm angle at release that
    ``engine_model.ideal`` puts in the machine's ``release_angle``; None (its search pass): ``-inf``,
    which the arm never passes, so the swing runs on to the arm's stop."""
    rule = RELEASE_RULES.index(machine.release_rule)
    if rule == IDEAL_RULE and machine.release_angle is None:
        return rule, -math.inf
    return rule, machine.release_angle


def _release(before: tuple, row: tuple, geometry: tuple, rule: int, release_angle: float) -> tuple[float, bool]:
    """``analytic.geometry.release_value`` (the ideal rule's: ``ideal_release``) at the row's instant (mean of
    the half-step velocities)."""
    p = kin.PROJECTILE
    theta = row[kin.ARM + kin.ANGLE]
    if rule == IDEAL_RULE:
        spin = 0.0 if before is row else 0.5 * (before[kin.ARM + kin.W] + row[kin.ARM + kin.W])
        return ideal_release(release_angle, theta, spin)
    if before is row:
        velocity = (0.0, 0.0)
    else:
        velocity = (0.5 * (before[p + kin.VX] + row[p + kin.VX]), 0.5 * (before[p + kin.VY] + row[p + kin.VY]))
    return release_value(rule, release_angle, -math.sin(theta), math.cos(theta), *geometry[2:4], *velocity)
