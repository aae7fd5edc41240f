"""Simulate one shot in pymunk: fire, slide, swing, release, fly -> ``Shot`` (with ``EngineDiagnostics``).

The machine is stepped at a fixed ``dt`` from rest. Events (lift-off, release,
landing, failures) are watched after every step and located between steps by
quadratic interpolation (``engine_model.events``). pymunk's velocities run
half a step ahead of its positions; every quantity reported pairs a position
with the velocity of the same instant (``engine_model.kinematics.synchronise``).

A rolling frame is one more body (``engine_model.build``); after release its
machine is stepped on to the landing instant (``engine_model.after_release``)
for the frame's position there.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from analytic import outcome
from analytic.design import Design, Machine, initial_angles, largest_length
from analytic.geometry import RELEASE_RULES, release_value
from analytic.limits import SLING_VERTICAL_LIMIT, swing_time_limit
from analytic.outcome import LiftoffFailure
from analytic.result import PEAK_NAMES, EnergyBudget, History, Shot, Stage, Status
from engine_model import friction as fr
from engine_model import kinematics as kin
from engine_model import loads as engine_loads
from engine_model.after_release import MACHINE_JOINTS, AfterRelease, after_release_steps, run_after_release
from engine_model.build import DEFAULT_ITERATIONS, EngineError, Rig, build
from engine_model.events import crossing_fraction, interpolate
from engine_model.flight import FLIGHT_STEP_LIMIT, FLIGHT_STEP_MULTIPLE, fly
from engine_model.readout import rig_row, row_reader, stepper

#: Default fixed step, s. At 5e-5 s release speed and range agree with the
#: analytic model to 1.6e-6 and 2.7e-6 on the paper's design
#: (tests/test_engine_accuracy.py) and the joints' one-step chord error stays
#: under 1e-6 m (8.5e-7 m); at 1e-4 s the agreement is 7e-6 / 1.1e-5 but the
#: chord error is 3.4e-6 m. A whole shot takes about 0.8 s.
DEFAULT_DT = 5e-5
#: The projectile (in stage 2) or the long-arm tip (in stage 1) counts as back
#: on the base once this far below base level, m: far above the round-off
#: (1e-15 m) they leave it with, far below any real dip.
BASE_TOLERANCE = 1e-9
#: Solver iterations of the opening step, which has no previous impulses to start from.
STARTUP_ITERATIONS = 1000
#: Most pymunk steps in stages 1-2 (and in a rolling machine's run after
#: release), after which the run ends as ``STEP_FAILED``: the analogue of the
#: analytic paths' ``STAGE_STEP_LIMITS``. The engine's step is fixed, so a
#: slow machine needs more of them: the swing's time bound grows as
#: 1/sqrt(gravity), and at 1e-6 m/s^2 the paper's machine would need 1e9
#: steps (hours). The most any design of the cross-check's suite takes is
#: 147,168 (its never-releasing design, run to the bound at the default
#: step); 400,000 is about 16 s of stepping.
MACHINE_STEP_LIMIT = 400_000
#: The step budget of a shot at the default step (``simulate(dt=None)``),
#: which keeps every valid design's shot within about 4 s. A fixed step makes
#: the engine's work grow with the machine's time scale, and the swing's time
#: bound (``analytic.limits.swing_time_limit``: three pendulum periods) is
#: what a design that never releases runs to: 147,168 steps (5.3 s) for the
#: cross-check's, 1/sqrt(gravity) more on Mars or the Moon (8.6 s, 13.0 s);
#: one with every loss ran 80,913 steps (5.5 s) to a late release, and a
#: rolling machine 10 times the paper's size with every loss 12 s.
#: ``_run_within_budget``: stages 1-2 take ``MACHINE_FINE_STEPS`` steps of
#: ``DEFAULT_DT`` (1 s of motion: the paper's design releases at 0.38 s),
#: then the swing is run over its whole time bound in
#: ``MACHINE_COARSE_STEPS`` steps to find its outcome, and an event at time
#: t (a release, or the projectile hitting the base) is swung again at the
#: step that spreads ``REFINE_MARGIN`` t over ``MACHINE_REFINED_STEPS``
#: steps, or ``DEFAULT_DT`` if that is longer (t up to 1.6 s: the run at the
#: default step goes on, with the numbers an unbudgeted run gives). A
#: machine that slow moves slowly: the cross-check's latest release (3.5 s)
#: keeps its release speed to 1e-6 at 4.6e-4 s. The budget's worst cost was
#: measured on the slowest kind of step, with every loss: 55 us in stages
#: 1-2, 46 us after release.
MACHINE_FINE_STEPS = 20_000
MACHINE_COARSE_STEPS = 15_000
MACHINE_REFINED_STEPS = 35_000
REFINE_MARGIN = 1.1
#: A shot at the default step takes at most this many machine steps, the
#: rolling machine's run after release included (its step is lengthened to
#: fit what stages 1-2 left of the budget, but never to fewer than
#: ``AFTER_RELEASE_MIN_STEPS``). Two of the cross-check's rolling designs
#: (the paper's on 2 kg and 5 kg frames: 7,581 + 70,504 and 7,610 + 68,068
#: steps) get a step 12 % and 8 % longer after release.
SHOT_STEP_BUDGET = 70_000
AFTER_RELEASE_MIN_STEPS = 10_000
#: Within the budget the flight's step is ``FLIGHT_STEP_MULTIPLE`` times
#: ``DEFAULT_DT`` (2 ms), or the step that fits the flight in vacuum into
#: this many steps if longer: a flight over 40 s in vacuum (the paper's
#: takes 3.4 s; on the Moon 8.3 s). At a gravity of 1e-3 m/s^2 the paper's
#: design flew 158,771 steps (5 s with its stages 1-2); at 1e-4, 400,000
#: steps and ``step_failed``.
FLIGHT_BUDGET_STEPS = 20_000
#: A run whose joints come apart by more than this fraction of the machine's
#: largest length is rejected: at 4x the default step the drift is about 1e-5
#: of it, and above this the reported numbers would be off by more than that.
DRIFT_LIMIT = 1e-4
#: A run whose stage 1-2 mechanical energy changes by more than this fraction
#: of the energy available from the counterweight is rejected as unstable
#: (a sound run conserves it to 3e-5 at the default step and 5e-4 at 4x it).
#: With the rope only a gain counts: on the paper's design it loses 9e-4 when
#: it snaps taut.
ENERGY_LIMIT = 1e-3
#: A run whose solver leaves a joint's velocity this far (as a fraction of the
#: machine's speed scale sqrt(g L), L its largest length) from what removes the
#: joint's error is rejected as unconverged: sound runs stay below 2e-5 of it
#: (the paper's design even at 20 iterations); runs that went wrong (a light
#: arm between the frame and a heavy counterweight, too few iterations) showed
#: 7e-4 and more, with lift-off times off by a factor of three.
RESIDUAL_LIMIT = 1e-4


@dataclass(frozen=True)
class EngineDiagnostics:
    """How well the engine kept to the design's constraints in one run.

    Attributes
    ----------
    dt : fixed step of stages 1-2, s (the flight's is ``FLIGHT_STEP_MULTIPLE`` times it, or times
        ``DEFAULT_DT`` for a step the step budget lengthened).
    iterations : pymunk solver iterations per step.
    sling : ``"rigid"`` or ``"rope"``.
    machine_steps, flight_steps : pymunk steps in stages 1-2 and in flight.
    joint_drift : largest separation of each joint's anchors, m (keys ``pivot``,
        ``hinge``, ``sling``, ``groove``, and ``rail`` for a rolling frame).
    max_joint_drift : the largest of those, m.
    energy_error : largest change of mechanical energy plus the work friction
        took (``dissipated_history``) through stages 1-2, as a fraction of the
        energy the counterweight can give up (it is conserved there; a rope
        that snaps taut loses some, as a real one would).
    solver_residual : largest miss of a joint's target velocity, m/s
        (``engine_model.kinematics.constraint_residuals``).
    momentum_error : rolling frame only (0 for a fixed one): largest change of
        the whole machine's horizontal momentum through stages 1-2, as a
        fraction of the largest momentum the frame takes up (no horizontal
        force acts, so it is conserved).
    after_release_steps : rolling frame only: pymunk steps of the machine from
        release to landing (``engine_model.after_release``); its drift and
        solver residual are in ``joint_drift`` and ``solver_residual`` too.
    after_release_energy_error : its largest change of the machine's energy
        (with the work its friction took), as a fraction of the energy the
        counterweight can give up.
    dissipated_history : (n, 3) the work the axle's, the hinge's and the
        base's friction (``engine_model.friction.JOINTS``) had taken by each
        sample of ``shot.history.t``, J; zeros for an ideal design. ``energy_error``
        counts it: mechanical energy plus dissipated work is what is conserved.
    friction_steps : with friction only (None for an ideal design), on the
        steps of stages 1-2 (``machine_steps`` rows, each (n, 3) for the
        axle, the hinge and the base): ``limit``, the friction each could
        give in the step (N m, N m, N), set from the loads of the two steps
        before (``friction.predicted_loads``); ``applied``, what it gave (its
        impulse over the step); ``load``, each joint's load (N) measured in the step.
    after_release_dt : rolling frame only (0 otherwise): the step of the run
        after release, s; ``dt`` unless the shot's step budget lengthened it.
    discarded_steps : steps of stages 1-2 taken within the step budget by
        runs whose results were not kept (``_run_within_budget``; 0 when the
        first run at the default step finished).
    """

    dt: float
    iterations: int
    sling: str
    machine_steps: int
    flight_steps: int
    joint_drift: dict[str, float] = field(default_factory=dict)
    max_joint_drift: float = 0.0
    energy_error: float = 0.0
    solver_residual: float = 0.0
    momentum_error: float = 0.0
    after_release_steps: int = 0
    after_release_energy_error: float = 0.0
    dissipated_history: np.ndarray | None = None
    friction_steps: dict[str, np.ndarray] | None = None
    after_release_dt: float = 0.0
    discarded_steps: int = 0


@dataclass
class _Run:
    """What the stepping loop gathers (internal, mutable while it runs)."""

    raw: list = field(default_factory=list)
    on_base: list = field(default_factory=list)
    tension: list = field(default_factory=list)
    normal: list = field(default_factory=list)
    release_value: list = field(default_factory=list)
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
    return rig_row(rig.arm, rig.counterweight, rig.projectile, rig.frame)


def simulate(design: Design, *, dt: float | None = None, iterations: int = DEFAULT_ITERATIONS,
             sling: str = "rigid") -> Shot:
    """Simulate a shot of ``design`` in pymunk through all three stages.

    A valid design that fails to throw is not an error: ``Shot.status`` names
    the failure and ``Shot.message`` explains it (a flight that does not come
    down within ``analytic.limits.flight_time_limit`` is ``NO_LANDING``).

    Parameters
    ----------
    design : a validated ``Design``.
    dt : fixed step, s. None (the default): ``DEFAULT_DT`` within the shot's
        step budget (``MACHINE_FINE_STEPS``, ``SHOT_STEP_BUDGET``), lengthened
        for a swing or a rolling machine's run after release that would
        need more; ``shot.diagnostics`` gives the steps taken. A step given
        is kept whatever it costs (up to ``MACHINE_STEP_LIMIT`` steps).
    iterations : pymunk solver iterations per step (at least about 20).
    sling : ``"rigid"`` (PinJoint) or ``"rope"`` (SlideJoint, pulls only).

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
        non-finite values, the solver unconverged (``RESIDUAL_LIMIT``; a
        rolling frame far lighter than the counterweight), an energy jump
        (``ENERGY_LIMIT``) or joints apart (``DRIFT_LIMIT``), in stages 1-2 or
        in a rolling machine's run after release; use a smaller ``dt`` or more
        ``iterations``.
    """
    budget = dt is None
    discarded = 0
    if budget:
        dt, run, rig, discarded = _run_within_budget(design, iterations, sling)
    elif not (math.isfinite(dt) and dt > 0.0):
        raise ValueError(f"dt = {dt!r}: must be a positive number of seconds")
    else:
        run, rig = _run_machine(design, dt, iterations, sling, MACHINE_STEP_LIMIT)
    raw = np.array(run.raw)
    on_base = np.array(run.on_base)
    sync = kin.synchronise(raw, design.base.rolling)
    drift = kin.joint_drift(raw, design, sling, on_base)
    steps = np.full(len(raw), dt)
    steps[0] = 0.5 * dt
    residual = kin.constraint_residuals(raw, design, sling, on_base, steps)
    times = dt * np.arange(len(raw))
    tension = np.array(run.tension)
    loads = engine_loads.load_histories(raw, tension, design, dt)
    dissipated = _friction_work(run, sync, design)

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
        tension = np.append(tension[:-1], release_tension)
        loads = np.vstack([loads[:-1], interpolate(loads[-3:], s)])
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
            run.message = step_limit_message("the flight", flight.steps, FLIGHT_STEP_MULTIPLE * flight_base, flight.limit,
                                             FLIGHT_STEP_LIMIT)
        else:
            run.status, run.message = Status.NO_LANDING, outcome.no_landing_message(flight.limit)
    fields["min_sling_tension"] = (smallest_sample(tension) if sling == "rigid"
                                   else float(tension.min()))
    fields["max_frame_speed"] = largest_speed(kin.column(sync, kin.FRAME, kin.VX)) if design.base.rolling else 0.0
    fields.update(_peaks(loads, times, run))
    fields["energy_dissipated"] = {**dict(zip(fr.JOINTS, (float(w) for w in dissipated[-1]), strict=True)),
                                   "drag": float(drag_work)}
    shot = _assemble(design, run, times, sync, tension, fields)
    diagnostics = _diagnose(design, dt, iterations, sling, len(raw), flight_steps, drift, residual, shot, sync,
                            dissipated)
    after_dt = dt
    if budget and shot.landing_time is not None and design.base.rolling:
        allowed = max(SHOT_STEP_BUDGET - discarded - len(raw), AFTER_RELEASE_MIN_STEPS)
        # Whole steps, less the opening half step and one for the rounding of ceil(time / step).
        after_dt = max(dt, (shot.landing_time - shot.release_time) / (allowed - 2))
    after_steps = (0 if shot.landing_time is None or not design.base.rolling
                   else after_release_steps(shot.release_time, shot.landing_time, after_dt))
    if after_steps > MACHINE_STEP_LIMIT:
        time_bound = shot.landing_time - shot.release_time
        shot = dataclasses.replace(shot, status=Status.STEP_FAILED, message=step_limit_message(
            "the rolling machine's run after release", after_steps, dt, time_bound, ahead=True))
    elif shot.landing_time is not None:
        if not design.base.rolling:
            shot = dataclasses.replace(shot, frame_landing_displacement=0.0, frame_landing_velocity=0.0)
        else:
            # The machine was trusted up to release; only then is it worth stepping on.
            after = run_after_release(design, shot.release_time, release_state, shot.landing_time, after_dt,
                                      iterations, STARTUP_ITERATIONS)
            landing = after.landing_state
            shot = dataclasses.replace(
                shot, frame_landing_displacement=float(landing[kin.FRAME + kin.X]),
                frame_landing_velocity=float(landing[kin.FRAME + kin.VX]),
                max_frame_speed=max(shot.max_frame_speed,
                                    largest_speed(kin.column(after.states, kin.FRAME, kin.VX))))
            diagnostics = _diagnose_after_release(design, after_dt, iterations, after, diagnostics)
    diagnostics = dataclasses.replace(diagnostics, friction_steps=_friction_steps(run, dt),
                                      after_release_dt=float(after_dt) if after_steps else 0.0,
                                      discarded_steps=discarded if budget else 0)
    return dataclasses.replace(shot, diagnostics=diagnostics)


def _peaks(loads: np.ndarray, times: np.ndarray, run: _Run) -> dict[str, float]:
    """``Shot``'s peak loads and their times (``analytic.result.PEAK_NAMES``) over stages 1-2 from the
    (n, 4) ``loads`` on ``times``; none for a machine that never fired (its one row is at rest)."""
    if run.status is Status.NEVER_FIRES:
        return {}
    fields = {}
    joined = fr.smooth(run.friction_slips, len(times))
    for name, (value, time) in zip(PEAK_NAMES, engine_loads.peaks(loads, times, joined), strict=True):
        fields[name], fields[f"{name}_time"] = value, time
    return fields


def _friction_work(run: _Run, sync: np.ndarray, design: Design) -> np.ndarray:
    """(n, 3) the work each friction had taken by each row's instant, J (``friction.dissipated_work``)."""
    if not run.friction_impulse:
        return np.zeros((len(sync), len(fr.JOINTS)))
    qdot = kin.coordinates(sync, design, initial_angles(design.machine))[1]
    return fr.dissipated_work(np.array(run.friction_impulse), fr.rates(sync, qdot, design))


def _friction_steps(run: _Run, dt: float) -> dict[str, np.ndarray] | None:
    """``EngineDiagnostics.friction_steps`` from the run's records (None without friction)."""
    if not run.friction_limit:
        return None
    steps = np.full((len(run.friction_impulse), 1), dt)
    steps[0] = 0.5 * dt
    count = len(run.friction_limit)
    return {"limit": np.array(run.friction_limit), "applied": np.array(run.friction_impulse)[:count] / steps[:count],
            "load": np.array(run.friction_load)}


def _frame(state: np.ndarray, quantity: int, design: Design) -> float:
    """The frame's ``quantity`` (``kin.X`` or ``kin.VX``) in a row: 0.0 for a fixed frame."""
    return float(state[kin.FRAME + quantity]) if design.base.rolling else 0.0


def _run_within_budget(design: Design, iterations: int, sling: str) -> tuple[float, _Run, Rig, int]:
    """Stages 1-2 at the default step within the step budget (``MACHINE_FINE_STEPS``): the step
    used, the run, its rig, and the steps of the runs discarded on the way.

    A run at ``DEFAULT_DT`` that reaches ``MACHINE_FINE_STEPS`` steps pauses
    while the swing is run over its whole time bound at ``coarse_step``. That
    verdict stands where it ran to the bound (never releases, never lifts
    off). Where it released or hit the base at time t, the step fitted to it
    is ``max(DEFAULT_DT, REFINE_MARGIN t / MACHINE_REFINED_STEPS)``: the
    default step (t up to 1.6 s) lets the paused run go on to
    ``MACHINE_REFINED_STEPS`` steps, a longer one swings it once more. Either
    result replaces the coarse one unless it runs out of steps first.
    """
    coarse = coarse_step(design)
    if not math.isfinite(coarse):   # gravity so weak the swing has no time scale a float holds
        raise EngineError(f"gravity = {design.environment.gravity:g} m/s^2 gives the swing no finite time bound "
                          "to choose the engine's step from")
    found: dict = {}

    def probe(steps: int) -> int | None:
        """At the default step's limit: the outcome at the coarse step, and the new limit (None: stop)."""
        found["coarse"] = _run_machine(design, coarse, iterations, sling, MACHINE_COARSE_STEPS + 10)
        outline = found["coarse"][0]
        if outline.status not in (None, Status.HITS_BASE_BEFORE_RELEASE):
            return None
        found["fitted"] = max(DEFAULT_DT, REFINE_MARGIN * len(outline.raw) * coarse / MACHINE_REFINED_STEPS)
        return MACHINE_REFINED_STEPS if found["fitted"] == DEFAULT_DT else None

    run, rig = _run_machine(design, DEFAULT_DT, iterations, sling, MACHINE_FINE_STEPS, probe)
    if "coarse" not in found:
        return DEFAULT_DT, run, rig, 0
    outline, outline_rig = found["coarse"]
    if not run.out_of_steps:   # went on at the default step, and ended
        return DEFAULT_DT, run, rig, len(outline.raw)
    fitted = found.get("fitted", DEFAULT_DT)
    if fitted == DEFAULT_DT:   # the coarse verdict is final, or the run went on and ran out
        return coarse, outline, outline_rig, len(run.raw)
    refined, refined_rig = _run_machine(design, fitted, iterations, sling, MACHINE_REFINED_STEPS)
    if refined.out_of_steps:
        return coarse, outline, outline_rig, len(run.raw) + len(refined.raw)
    return fitted, refined, refined_rig, len(run.raw) + len(outline.raw)


def flight_step_base(design: Design, position: np.ndarray, velocity: np.ndarray) -> float:
    """The flight's step over ``FLIGHT_STEP_MULTIPLE`` within the step budget, s: ``DEFAULT_DT``, or
    longer, so that a flight in vacuum from ``position`` (m, over the pivot) at ``velocity`` (m/s)
    would take ``FLIGHT_BUDGET_STEPS``."""
    g = design.environment.gravity
    height, vy = float(position[1]) + design.machine.pivot_height, float(velocity[1])
    vacuum = (vy + math.sqrt(max(vy * vy + 2.0 * g * height, 0.0))) / g
    return max(DEFAULT_DT, vacuum / (FLIGHT_STEP_MULTIPLE * FLIGHT_BUDGET_STEPS))


def coarse_step(design: Design) -> float:
    """The step of a run at the default step that outlasted ``MACHINE_FINE_STEPS``, s: the swing's
    time bound over ``MACHINE_COARSE_STEPS``."""
    return swing_time_limit(largest_length(design.machine), design.environment.gravity) / MACHINE_COARSE_STEPS


def _run_machine(design: Design, dt: float, iterations: int, sling: str, limit: int = MACHINE_STEP_LIMIT,
                 at_limit: Callable[[int], int | None] | None = None) -> tuple[_Run, Rig]:
    """Step stages 1 and 2 until release, a failure, or ``limit`` steps (``STEP_FAILED``, and
    ``run.out_of_steps``); the loop behind ``simulate``. At the limit, ``at_limit(steps)`` may
    give a new one, and the run goes on as if that had been its limit all along."""
    m = design.machine
    h, g = m.pivot_height, design.environment.gravity
    t_limit = swing_time_limit(largest_length(design.machine), g)
    rule = RELEASE_RULES.index(m.release_rule)
    run = _Run()

    rig = build(design, sling=sling, iterations=iterations)
    friction = _attach_friction(rig, design, True, dt)
    row = _opening_step(rig, dt, iterations)
    # From rest the opening half step gives the arm omega = alpha dt/2 (pymunk
    # updates velocities first), so this is its angular acceleration at rest.
    arm_acceleration = row[kin.ARM + kin.W] / (0.5 * dt)
    if friction is not None:
        balance = fr.static_balance(design, np.array(row))
        held = abs(arm_acceleration) <= fr.HELD_ACCELERATION
        if (friction.axle is not None and balance.holds) or held:
            run.raw.append(row)
            run.on_base.append(True)
            run.tension.append(0.0)
            run.friction_impulse.append(fr.impulses(friction, True))
            run.status = Status.NEVER_FIRES
            run.message = outcome.never_fires_message(arm_acceleration, -balance.gravity_torque,
                                                      balance.holding_torque)
            return run, rig
    if not arm_acceleration < 0.0:
        run.raw.append(row)
        run.on_base.append(True)
        run.tension.append(0.0)
        if friction is not None:
            run.friction_impulse.append(fr.impulses(friction, True))
        run.status = Status.NEVER_FIRES
        run.message = outcome.never_fires_message(arm_acceleration)
        return run, rig
    geometry = _row_geometry(row, m)
    base_force = _base_friction(friction, rig, 0.5 * dt, geometry, True)
    tension, normal = _forces(row, row, geometry, True, design, dt, base_force)
    on_base = True
    if normal < 0.0:
        # The sling lifts the projectile at rest: start again without the base.
        rig = build(design, sling=sling, iterations=iterations, on_base=False)
        friction = _attach_friction(rig, design, False, dt)
        row = _opening_step(rig, dt, iterations)
        geometry = _row_geometry(row, m)
        base_force = 0.0
        tension, normal = _forces(row, row, geometry, False, design, dt)
        on_base = False
        run.liftoff_time = 0.0
    opening_loads = fr.static_loads(design)
    if friction is not None:
        # The loads at rest are the weights, but the moving machine's are not (the
        # axle's is half of it on the paper's design): the opening half step is
        # taken again with the limits its loads give (its range moved by 1.2e-5 m).
        opening_loads = _loads(friction, rig, _mirrored(row), row, design,
                               (base_force, normal if on_base else 0.0), dt, 0.5 * dt)
        # The joints that broke free of their static hold slip from the start: kinetic limits.
        rates = fr.joint_rates(row, design)
        slips = fr.slipping(friction, 0.5 * dt, rates, fr.AT_REST)
        rig = build(design, sling=sling, iterations=iterations, on_base=on_base)
        friction = _attach_friction(rig, design, on_base, dt, opening_loads, slips)
        row = _opening_step(rig, dt, iterations)
        geometry = _row_geometry(row, m)
        base_force = _base_friction(friction, rig, 0.5 * dt, geometry, on_base)
        tension, normal = _forces(row, row, geometry, on_base, design, dt, base_force)
    run.raw.append(row)
    run.on_base.append(on_base)
    run.tension.append(tension)
    run.normal.append(normal)
    run.release_value.append(_release(row, row, geometry, rule, m.release_angle)[0])
    if friction is not None:
        run.friction_impulse.append(fr.impulses(friction, on_base))
        loads = _loads(friction, rig, _mirrored(row), row, design, (base_force, normal if on_base else 0.0),
                       dt, 0.5 * dt)
        run.friction_limit.append(fr.limits(design, opening_loads, slips))
        run.friction_slips.append(slips)
        run.friction_load.append(loads)
        rates = fr.joint_rates(row, design)
        slips = fr.slipping(friction, 0.5 * dt, rates, fr.AT_REST)
        friction = fr.renew(friction, rig)

    step = stepper(rig.space)
    read = row_reader(rig.arm, rig.counterweight, rig.projectile, rig.frame)
    # The loop runs up to hundreds of thousands of times: its lists' appends and the row's
    # indices are looked up once.
    keep_row, keep_on_base, keep_tension = run.raw.append, run.on_base.append, run.tension.append
    keep_normal, keep_value = run.normal.append, run.release_value.append
    y_index, vy_index, alpha = kin.PROJECTILE + kin.Y, kin.PROJECTILE + kin.VY, m.release_angle
    previous = row
    previous_value = run.release_value[-1]
    # The axle's or the base's friction can stop the arm before lift-off (its clockwise turn
    # ends): the shot ends there, as in the analytic model (``docs/derivation.md``, 10.4).
    stalls = friction is not None and (design.losses.axle_friction > 0.0 or design.losses.base_friction > 0.0)
    spin_index = kin.ARM + kin.W
    earlier_loads = None
    k = 0
    while True:
        if friction is not None:
            predicted = fr.predicted_loads(loads, earlier_loads, fr.steady(run.friction_slips, slips))
            run.friction_limit.append(fr.set_limits(friction, predicted, slips))
            run.friction_slips.append(slips)
            fr.aim(friction, rig, dt)
        if k >= limit:
            more = None if at_limit is None else at_limit(k)
            if more is None or more <= k:
                run.out_of_steps = True
                return _fail(run, rig, Status.STEP_FAILED, step_limit_message("stages 1-2", k, dt, t_limit, limit))
            limit = more
        step(dt)
        k += 1
        row = read()
        if not math.isfinite(sum(row)):
            raise EngineError(f"the engine went unstable (non-finite state) at t = {k * dt:.5g} s "
                              f"with dt = {dt:g} s and {iterations} iterations: use a smaller dt "
                              f"or more iterations")
        geometry = _row_geometry(row, m)
        if friction is None:
            tension, normal = _forces(previous, row, geometry, on_base, design, dt)
        else:
            base_force = _base_friction(friction, rig, dt, geometry, on_base)
            tension, normal = _forces(previous, row, geometry, on_base, design, dt, base_force)
            run.friction_impulse.append(fr.impulses(friction, on_base))
            rates, earlier_rates = fr.joint_rates(row, design), rates
            slips = fr.slipping(friction, dt, rates, earlier_rates)
            earlier_loads = loads
            if k > 1:
                loads = _loads(friction, rig, previous, row, design, (base_force, normal if on_base else 0.0),
                               dt, dt)
            if k == 2:   # the line from the opening half step's loads, two steps back
                earlier_loads = tuple(0.5 * (a + b) for a, b in zip(earlier_loads, loads, strict=True))
            # At k = 1 pymunk's joints misreport the first whole step after the half step
            # (``friction.renew``): the opening half step's loads stand in.
            run.friction_load.append(loads)
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
                fraction = crossing_fraction(tuple(run.normal[-3:]))
                run.liftoff_time = (k - 1 + fraction) * dt
                rig.space.remove(rig.groove)
                if friction is not None:
                    fr.remove_base(friction, rig.space)
                on_base = False
            elif stalls and row[spin_index] >= 0.0:
                return _fail(run, rig, Status.NEVER_LIFTS_OFF,
                             outcome.never_lifts_off_message(LiftoffFailure.STALLED, t_limit))
            elif geometry[2] < SLING_VERTICAL_LIMIT:
                return _fail(run, rig, Status.NEVER_LIFTS_OFF,
                             outcome.never_lifts_off_message(LiftoffFailure.UNDER_TIP, t_limit))
            elif geometry[1] + h < -BASE_TOLERANCE:
                return _fail(run, rig, Status.NEVER_LIFTS_OFF,
                             outcome.never_lifts_off_message(LiftoffFailure.ARM_BACK, t_limit))
            elif t > t_limit:
                return _fail(run, rig, Status.NEVER_LIFTS_OFF,
                             outcome.never_lifts_off_message(LiftoffFailure.TIME_LIMIT, t_limit))
            continue

        if row[y_index] + h < -BASE_TOLERANCE and row[vy_index] < 0.0:
            return _fail(run, rig, Status.HITS_BASE_BEFORE_RELEASE, outcome.hits_base_message(t))
        if earlier_value < 0.0 <= value and armed:
            run.release_fraction = crossing_fraction(tuple(run.release_value[-3:]))
            return run, rig
        if t > t_limit:
            return _fail(run, rig, Status.NEVER_RELEASES,
                         outcome.never_releases_message(m.release_rule, m.release_angle, t_limit))

def _attach_friction(rig: Rig, design: Design, on_base: bool, dt: float,
                     loads: tuple[float, float, float] | None = None,
                     slips: tuple[bool, bool, bool] = fr.STUCK) -> fr.Friction | None:
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
           base_force: tuple[float, float], dt: float, step: float) -> tuple[float, float, float]:
    """Each friction joint's load in the step of ``step`` s that produced ``row``, N: the next step's limits.

    ``before`` is the row before (for the opening half step, ``_mirrored(row)``,
    whose velocity change over ``dt`` is the half step's over ``dt / 2``).
    """
    if friction.axle is None:
        axle = 0.0
    elif friction.ballast > 0.0:
        axle = fr.axle_load_from_momentum(before, row, design, base_force, dt)
    else:
        axle = fr.impulse(rig.pivot) / step
    hinge = fr.impulse(rig.hinge) / step
    if friction.point_hinge:
        hinge = math.hypot(hinge, fr.impulse(friction.hinge) / step)
    base = fr.impulse(rig.groove) / step if friction.base is not None else 0.0
    return axle, hinge, base


def _opening_step(rig: Rig, dt: float, iterations: int) -> tuple[float, ...]:
    """Half a step from rest: the positions stay at t = 0, the velocities reach dt/2 (leapfrog start).

    Later steps start their solver from the previous step's impulses; this one
    starts from nothing, so it gets ``STARTUP_ITERATIONS`` to converge (with
    the usual count the sling tension rings by 10 % for a dozen steps).
    """
    rig.space.iterations = max(STARTUP_ITERATIONS, iterations)
    rig.space.step(0.5 * dt)
    rig.space.iterations = iterations
    return read_state(rig)


def step_limit_message(part: str, steps: int, dt: float, time_bound: float, limit: int = MACHINE_STEP_LIMIT,
                       ahead: bool = False) -> str:
    """``analytic.outcome.step_budget_message``, the machine's ``MACHINE_STEP_LIMIT`` by default."""
    return outcome.step_budget_message(part, steps, dt, time_bound, limit, ahead)


def _fail(run: _Run, rig: Rig, status: Status, message: str) -> tuple[_Run, Rig]:
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
            dt: float, base_friction: float = 0.0) -> tuple[float, float]:
    """Sling tension and base normal force over the step that produced ``row`` (``kin.contact_forces``;
    ``base_friction``, N, the base's friction force on the projectile)."""
    p = kin.PROJECTILE
    if before is row:  # the opening half step: the velocity before it is the mirror image
        v_before = (-row[p + kin.VX], -row[p + kin.VY])
    else:
        v_before = (before[p + kin.VX], before[p + kin.VY])
    return kin.contact_forces(v_before, (row[p + kin.VX], row[p + kin.VY]), geometry[:2],
                              (row[p + kin.X], row[p + kin.Y]), on_base, design, dt, base_friction)


def _release(before: tuple, row: tuple, geometry: tuple, rule: int, release_angle: float) -> tuple[float, bool]:
    """``analytic.geometry.release_value`` at the row's instant (mean of the half-step velocities)."""
    p = kin.PROJECTILE
    if before is row:
        velocity = (0.0, 0.0)
    else:
        velocity = (0.5 * (before[p + kin.VX] + row[p + kin.VX]), 0.5 * (before[p + kin.VY] + row[p + kin.VY]))
    theta = row[kin.ARM + kin.ANGLE]
    return release_value(rule, release_angle, -math.sin(theta), math.cos(theta), *geometry[2:4], *velocity)


def _assemble(design: Design, run: _Run, times: np.ndarray, sync: np.ndarray,
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


def _diagnose(design: Design, dt: float, iterations: int, sling: str, machine_steps: int,
              flight_steps: int, drift: dict[str, np.ndarray], residual: dict[str, np.ndarray],
              shot: Shot, sync: np.ndarray, dissipated: np.ndarray) -> EngineDiagnostics:
    """Summarise drift, solver residual and energy; raise ``EngineError`` if any shows a run gone wrong."""
    advice = f"with dt = {dt:g} s and {iterations} iterations: use a smaller dt or more iterations"
    largest_miss = {name: float(values.max()) for name, values in residual.items()}
    _require_converged(design, largest_miss, advice)
    # A rope that snaps taut loses energy, as a real one would; it must never gain any.
    # Friction's work is energy the machine lost, not an error: it is added back.
    total = shot.history.energy.total
    kept = total if design.losses.ideal else total + dissipated.sum(axis=1)
    change = _relative_energy(kept, design)
    energy_error = float(np.abs(change).max())
    _require_energy_kept(energy_error if sling == "rigid" else float(change.max()), energy_error, advice)
    largest = {name: float(values.max()) for name, values in drift.items()}
    _require_together(design, largest, advice)
    momentum_error = 0.0
    if design.base.rolling:
        momentum = kin.horizontal_momentum(sync, design)
        taken_up = float(np.abs(design.base.mass * kin.column(sync, kin.FRAME, kin.VX)).max())
        if taken_up > 0.0:
            momentum_error = float(np.abs(momentum - momentum[0]).max()) / taken_up
    return EngineDiagnostics(dt=dt, iterations=iterations, sling=sling, machine_steps=machine_steps,
                             flight_steps=flight_steps, joint_drift=largest,
                             max_joint_drift=max(largest.values()), energy_error=energy_error,
                             solver_residual=max(largest_miss.values()), momentum_error=momentum_error,
                             dissipated_history=dissipated)


def _diagnose_after_release(design: Design, dt: float, iterations: int, after: AfterRelease,
                            diagnostics: EngineDiagnostics) -> EngineDiagnostics:
    """``diagnostics`` with the run after release's drift, residual and energy; raise ``EngineError``
    (with the same limits as stages 1-2) if any shows it gone wrong."""
    advice = (f"after release, with dt = {dt:g} s and {iterations} iterations: use a smaller dt or "
              f"more iterations")
    if not np.all(np.isfinite(after.raw)):
        raise EngineError(f"the engine went unstable (non-finite state) {advice}")
    on_base = np.zeros(len(after.raw), dtype=bool)
    steps = np.full(len(after.raw), dt)
    steps[0] = 0.5 * dt
    residual = kin.constraint_residuals(after.raw, design, "rigid", on_base, steps)
    miss = {name: float(residual[name].max()) for name in MACHINE_JOINTS}
    _require_converged(design, miss, advice)
    kept = kin.energy_budget(after.states, design)[0] + after.dissipated.sum(axis=1)
    energy_error = float(np.abs(_relative_energy(kept, design)).max())
    _require_energy_kept(energy_error, energy_error, advice)
    drift = kin.joint_drift(after.raw, design, "rigid", on_base)
    largest = dict(diagnostics.joint_drift)
    for name in MACHINE_JOINTS:
        largest[name] = max(largest[name], float(drift[name].max()))
    _require_together(design, largest, advice)
    return dataclasses.replace(diagnostics, joint_drift=largest, max_joint_drift=max(largest.values()),
                               solver_residual=max(diagnostics.solver_residual, *miss.values()),
                               after_release_steps=after.steps, after_release_energy_error=energy_error)


def _require_converged(design: Design, largest_miss: dict[str, float], advice: str) -> None:
    """Raise ``EngineError`` if a joint's largest miss of its target velocity is over ``RESIDUAL_LIMIT``,
    naming the light bodies that make pymunk's iterative solver converge slowly."""
    joint = max(largest_miss, key=largest_miss.get)
    limit = RESIDUAL_LIMIT * math.sqrt(design.environment.gravity * largest_length(design.machine))
    if largest_miss[joint] <= limit:
        return
    m = design.machine
    light = (f"a light arm ({m.arm_mass:g} kg) or a light rolling frame ({design.base.mass:g} kg)"
             if design.base.rolling else "a light arm")
    raise EngineError(f"the solver did not converge, so the result cannot be trusted: the {joint} joint "
                      f"missed its target velocity by {largest_miss[joint]:.3g} m/s (limit {limit:.3g} m/s) "
                      f"{advice} ({light} joined to a heavy counterweight ({m.counterweight_mass:g} kg) "
                      f"needs many iterations)")


def _require_energy_kept(change: float, energy_error: float, advice: str) -> None:
    """Raise ``EngineError`` if the energy ``change`` (a fraction of the available energy) is over
    ``ENERGY_LIMIT``; the message gives ``energy_error``, its size."""
    if not change <= ENERGY_LIMIT:
        raise EngineError(f"the engine went unstable: the machine's energy changed by "
                          f"{energy_error:.3g} of the counterweight's available energy {advice}")


def _require_together(design: Design, largest_drift: dict[str, float], advice: str) -> None:
    """Raise ``EngineError`` if a joint came apart by more than ``DRIFT_LIMIT`` of the machine's length."""
    joint = max(largest_drift, key=largest_drift.get)
    limit = DRIFT_LIMIT * largest_length(design.machine)
    if not largest_drift[joint] <= limit:
        raise EngineError(f"the {joint} joint came apart by {largest_drift[joint]:.3g} m (limit {limit:.3g} m) "
                          f"{advice}")


def _relative_energy(energy: np.ndarray, design: Design) -> np.ndarray:
    """``energy`` as a fraction of the counterweight's available energy (``kin.available_energy``).

    An available energy that underflows to 0 (a machine of denormal lengths
    and masses) leaves no scale: an energy of exactly 0 is then no error, any
    other an infinite one (so the run is refused, never a 0/0 NaN).
    """
    available = kin.available_energy(design)
    if available > 0.0:
        return energy / available
    return np.where(energy == 0.0, 0.0, np.copysign(np.inf, energy))
