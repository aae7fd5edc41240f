"""The step budget of a shot at the default step: ``DEFAULT_DT``, and the longer steps a slow machine gets.

At a fixed step the engine's work grows with the machine's time scale; within
the budget (``simulate(dt=None)``) a swing, a flight or a rolling machine's
run after release that would need more steps is run at a longer step
(``run_within_budget``, ``flight_step_base``, ``after_release_step``).
"""

from __future__ import annotations

import math

import numpy as np

from analytic.design import Design, largest_length
from analytic.limits import swing_time_limit
from analytic.result import Status
from engine_model.build import EngineError, Rig
from engine_model.flight import FLIGHT_STEP_MULTIPLE
from engine_model.stepping import Run, run_machine

#: Default fixed step, s. At 5e-5 s release speed and range agree with the
#: analytic model to 1.6e-6 and 2.7e-6 on the paper's design
#: (tests/test_engine_accuracy.py) and the joints' one-step chord error stays
#: under 1e-6 m (8.5e-7 m); at 1e-4 s the agreement is 7e-6 / 1.1e-5 but the
#: chord error is 3.4e-6 m. A whole shot takes about 0.8 s.
DEFAULT_DT = 5e-5
#: The step budget of a shot at the default step (``simulate(dt=None)``),
#: which keeps every valid design's shot within about 4 s. A fixed step makes
#: the engine's work grow with the machine's time scale, and the swing's time
#: bound (``analytic.limits.swing_time_limit``: three pendulum periods) is
#: what a design that never releases runs to: 147,168 steps (5.3 s) for the
#: cross-check's, 1/sqrt(gravity) more on Mars or the Moon (8.6 s, 13.0 s);
#: one with every loss ran 80,913 steps (5.5 s) to a late release, and a
#: rolling machine 10 times the paper's size with every loss 12 s.
#: ``run_within_budget``: stages 1-2 take ``MACHINE_FINE_STEPS`` steps of
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


def run_within_budget(design: Design, iterations: int, sling: str) -> tuple[float, Run, Rig, int]:
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
        found["coarse"] = run_machine(design, coarse, iterations, sling, MACHINE_COARSE_STEPS + 10)
        outline = found["coarse"][0]
        if outline.status not in (None, Status.HITS_BASE_BEFORE_RELEASE):
            return None
        found["fitted"] = max(DEFAULT_DT, REFINE_MARGIN * len(outline.raw) * coarse / MACHINE_REFINED_STEPS)
        return MACHINE_REFINED_STEPS if found["fitted"] == DEFAULT_DT else None

    run, rig = run_machine(design, DEFAULT_DT, iterations, sling, MACHINE_FINE_STEPS, probe)
    if "coarse" not in found:
        return DEFAULT_DT, run, rig, 0
    outline, outline_rig = found["coarse"]
    if not run.out_of_steps:   # went on at the default step, and ended
        return DEFAULT_DT, run, rig, len(outline.raw)
    fitted = found.get("fitted", DEFAULT_DT)
    if fitted == DEFAULT_DT:   # the coarse verdict is final, or the run went on and ran out
        return coarse, outline, outline_rig, len(run.raw)
    refined, refined_rig = run_machine(design, fitted, iterations, sling, MACHINE_REFINED_STEPS)
    if refined.out_of_steps:
        return coarse, outline, outline_rig, len(run.raw) + len(refined.raw)
    return fitted, refined, refined_rig, len(run.raw) + len(outline.raw)


def flight_step_base(design: Design, position: np.ndarray, velocity: np.ndarray) -> float:
    """The flight's step over ``FLIGHT_STEP_MULTIPLE`` within the step budget, s: ``DEFAULT_DT``, or
    longer, so that a flight in vacuum from ``position`` (m, over the pivot) at ``velocity`` (m/s)
    would take ``FLIGHT_BUDGET_STEPS``."""
    g = design.environment.gravity
    height = float(position[1]) + design.machine.pivot_height - design.environment.target_height   # above the target
    vy = float(velocity[1])
    vacuum = (vy + math.sqrt(max(vy * vy + 2.0 * g * height, 0.0))) / g
    return max(DEFAULT_DT, vacuum / (FLIGHT_STEP_MULTIPLE * FLIGHT_BUDGET_STEPS))


def coarse_step(design: Design) -> float:
    """The step of a run at the default step that outlasted ``MACHINE_FINE_STEPS``, s: the swing's
    time bound over ``MACHINE_COARSE_STEPS``."""
    return swing_time_limit(largest_length(design.machine), design.environment.gravity) / MACHINE_COARSE_STEPS


def after_release_step(dt: float, release_time: float, landing_time: float, machine_steps: int,
                       discarded: int) -> float:
    """The step of a rolling machine's run after release within the budget, s: ``dt``, or longer, so that
    the run from ``release_time`` to ``landing_time`` (s) fits in what stages 1-2 (``machine_steps``, and
    ``discarded`` steps of runs not kept) left of ``SHOT_STEP_BUDGET``, in at least ``AFTER_RELEASE_MIN_STEPS``."""
    allowed = max(SHOT_STEP_BUDGET - discarded - machine_steps, AFTER_RELEASE_MIN_STEPS)
    # Whole steps, less the opening half step and one for the rounding of ceil(time / step).
    return max(dt, (landing_time - release_time) / (allowed - 2))
