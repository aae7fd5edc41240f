"""How well the engine kept to the constraints: ``EngineDiagnostics``, and the checks that refuse a run gone wrong.

A run whose solver did not converge (``RESIDUAL_LIMIT``), whose energy jumped
(``ENERGY_LIMIT``) or whose joints came apart (``DRIFT_LIMIT``) raises
``EngineError``, in stages 1-2 (``diagnose``) or in a rolling machine's run
after release (``diagnose_after_release``).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from analytic.design import Design, largest_length
from analytic.result import Shot
from engine_model import kinematics as kin
from engine_model.after_release import MACHINE_JOINTS, AfterRelease
from engine_model.build import EngineError

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
        ``hinge`` (hinged machines only), ``sling``, ``groove``, and ``rail`` for a rolling frame).
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
    dissipated_history : (n, 5) the work each friction
        (``engine_model.friction.JOINTS``) had taken by each
        sample of ``shot.history.t``, J; zeros for an ideal design. ``energy_error``
        counts it: mechanical energy plus dissipated work is what is conserved.
    friction_steps : with friction only (None for an ideal design), on the
        steps of stages 1-2 (``machine_steps`` rows, each (n, 5) for the
        axle, the hinge, the base, the guide and the track): ``limit``, the friction each could
        give in the step (N m, N m, N, N, N), set from the loads of the two steps
        before (``friction.predicted_loads``); ``applied``, what it gave (its
        impulse over the step); ``load``, each joint's load (N) measured in the step.
    after_release_dt : rolling frame only (0 otherwise): the step of the run
        after release, s; ``dt`` unless the shot's step budget lengthened it.
    discarded_steps : steps of stages 1-2 taken within the step budget by
        runs whose results were not kept (``engine_model.budget.run_within_budget``; 0 when the
        first run at the default step finished).
    support_loads : a floating arm's track and guide loads (``engine_model.floating.support_loads``,
        keys ``SUPPORT_LOAD_NAMES``: N, N, N and m); None for the other kinds.
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
    support_loads: dict[str, float | None] | None = None


def diagnose(design: Design, dt: float, iterations: int, sling: str, machine_steps: int,
              flight_steps: int, drift: dict[str, np.ndarray], residual: dict[str, np.ndarray],
              shot: Shot, sync: np.ndarray, dissipated: np.ndarray,
              swing_drag: np.ndarray | None = None) -> EngineDiagnostics:
    """Summarise drift, solver residual and energy; raise ``EngineError`` if any shows a run gone wrong.

    ``swing_drag``: (n,) the work the air's drag had taken from the projectile by each row
    (``projectile.drag_during_swing``), added back like the friction's; None: none."""
    advice = f"with dt = {dt:g} s and {iterations} iterations: use a smaller dt or more iterations"
    largest_miss = {name: float(values.max()) for name, values in residual.items()}
    _require_converged(design, largest_miss, advice)
    # A rope that snaps taut loses energy, as a real one would; it must never gain any.
    # Friction's work is energy the machine lost, not an error: it is added back.
    total = shot.history.energy.total
    kept = total if design.losses.ideal else total + dissipated.sum(axis=1)
    if swing_drag is not None:
        kept = kept + swing_drag
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


def diagnose_after_release(design: Design, dt: float, iterations: int, after: AfterRelease,
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
    # A sling with mass or a pouch swings on: its joint to the tip holds its end at the sling's length.
    joints = MACHINE_JOINTS + (("sling",) if kin.sling_swings(design) else ())
    miss = {name: float(residual[name].max()) for name in joints if name in residual}
    _require_converged(design, miss, advice)
    kept = kin.energy_budget(after.states, design)[0] + after.dissipated.sum(axis=1)
    energy_error = float(np.abs(_relative_energy(kept, design)).max())
    _require_energy_kept(energy_error, energy_error, advice)
    drift = kin.joint_drift(after.raw, design, "rigid", on_base)
    largest = dict(diagnostics.joint_drift)
    for name in (name for name in joints if name in drift):
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
