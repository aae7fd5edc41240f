"""Run one design through both models and compare what they report, quantity by quantity."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from analytic.design import Design
from analytic.fast import simulate_fast
from analytic.reference import simulate
from analytic.result import LOSS_NAMES, PEAK_NAMES, Shot
from crosscheck import tolerances as tol
from crosscheck.cases import Case
import engine_model
from engine_model import DEFAULT_DT, EngineError


def engine_simulate(design: Design, dt: float) -> Shot:
    """The pymunk model's shot at step ``dt`` (s), its ``EngineDiagnostics`` in ``shot.diagnostics``."""
    return engine_model.simulate(design, dt=dt)


#: Units of ``PEAK_NAMES``' rows.
PEAK_UNITS = ("N", "N", "N", "m/s^2", "N m")
#: The relative tolerance of each of ``PEAK_NAMES``.
PEAK_TOLERANCES = (tol.PEAK_LOAD_REL,) * 4 + (tol.ARM_BENDING_MOMENT_REL,)


def with_dissipated_work(shot: Shot) -> Shot:
    """``shot`` with what only the reference path reports, from its summary of the design, where the
    shot threw but lacks it (the fast path leaves it out): the work each loss took
    (``Shot.energy_dissipated``) and the frame at landing (``frame_landing_displacement``, the machine
    swung on after release).

    The reference summary (``analytic.reference.simulate(histories=False, after_release=True)``,
    without the peak loads, which the shot has) integrates the same model; its numbers are taken only
    where it threw too.
    """
    if not shot.ok or (shot.energy_dissipated is not None and shot.frame_landing_displacement is not None):
        return shot
    reference = simulate(shot.design, histories=False, loads=False, after_release=True)
    if not reference.ok:
        return shot
    return dataclasses.replace(shot, energy_dissipated=reference.energy_dissipated,
                               frame_landing_displacement=reference.frame_landing_displacement,
                               frame_landing_velocity=reference.frame_landing_velocity)


@dataclass(frozen=True)
class Row:
    """One compared quantity (SI units, angles in rad); ``ok`` when ``|difference| <= tolerance``."""

    quantity: str
    unit: str
    analytic: float | str
    engine: float | str
    difference: float | None
    tolerance: float | None
    ok: bool


@dataclass(frozen=True)
class Comparison:
    """Both models' verdict on one case."""

    case: str
    group: str
    analytic_status: str
    engine_status: str
    rows: tuple[Row, ...]
    max_joint_drift: float | None = None
    error: str | None = None
    engine_dt: float | None = None
    engine_energy_error: float | None = None
    kind: str = "hinged"

    @property
    def agree(self) -> bool:
        return self.error is None and all(row.ok for row in self.rows)

    def to_json(self) -> dict:
        """The comparison as ``python -m crosscheck --json`` prints it: the machine's ``kind`` on the
        design's record and on each of its quantity's rows."""
        return {"case": self.case, "group": self.group, "kind": self.kind, "agree": self.agree,
                "analytic_status": self.analytic_status, "engine_status": self.engine_status,
                "max_joint_drift": self.max_joint_drift, "error": self.error,
                "engine_dt": self.engine_dt, "engine_energy_error": self.engine_energy_error,
                "rows": [{**row.__dict__, "kind": self.kind} for row in self.rows]}


def _numeric(quantity: str, unit: str, a: float, e: float, tolerance: float) -> Row:
    a, e, tolerance = float(a), float(e), float(tolerance)
    difference = e - a
    ok = math.isfinite(difference) and abs(difference) <= tolerance
    return Row(quantity, unit, a, e, difference, tolerance, bool(ok))


def compare_shots(a: Shot, e: Shot) -> tuple[Row, ...]:
    """Rows for every quantity both shots reached; the outcome row first."""
    rows = [Row("outcome", "", a.status.value, e.status.value, None, None, bool(a.status is e.status))]
    if a.liftoff_time is not None and e.liftoff_time is not None:
        rows.append(_numeric("liftoff_time", "s", a.liftoff_time, e.liftoff_time, tol.EVENT_TIME))
    if not (a.ok and e.ok):
        return tuple(rows)
    speed = a.release_speed
    range_tolerance = tol.RANGE_REL * max(abs(a.range), tol.RANGE_FLOOR)
    rows += [
        _numeric("release_time", "s", a.release_time, e.release_time, tol.EVENT_TIME),
        _numeric("release_x", "m", a.release_position[0], e.release_position[0], tol.RELEASE_POSITION),
        _numeric("release_y", "m", a.release_position[1], e.release_position[1], tol.RELEASE_POSITION),
        _numeric("release_vx", "m/s", a.release_velocity[0], e.release_velocity[0], tol.RELEASE_VELOCITY_REL * speed),
        _numeric("release_vy", "m/s", a.release_velocity[1], e.release_velocity[1], tol.RELEASE_VELOCITY_REL * speed),
        _numeric("release_speed", "m/s", speed, e.release_speed, tol.RELEASE_SPEED_REL * speed),
        _numeric("launch_angle", "rad", a.launch_angle, e.launch_angle, tol.LAUNCH_ANGLE),
        _numeric("range", "m", a.range, e.range, range_tolerance),
        _numeric("apex_height", "m", a.apex_height, e.apex_height, tol.APEX_HEIGHT_REL * a.apex_height),
    ]
    rows += [_numeric(name, unit, getattr(a, name), getattr(e, name), relative * abs(getattr(a, name)))
             for name, unit, relative in zip(PEAK_NAMES, PEAK_UNITS, PEAK_TOLERANCES, strict=True)
             if getattr(a, name) is not None and getattr(e, name) is not None]
    if a.frame_release_displacement is not None and e.frame_release_displacement is not None:
        shift = a.frame_release_displacement
        rows.append(_numeric("frame_release_displacement", "m", shift, e.frame_release_displacement,
                             tol.FRAME_DISPLACEMENT_REL * max(abs(shift), tol.FRAME_DISPLACEMENT_FLOOR)))
    if a.energy_dissipated is not None and e.energy_dissipated is not None:
        # Never zero (1 J's worth at least): rows are plotted as difference / tolerance. A summary
        # (no histories) has no energy released; the engine's, the same to its error, scales it then.
        released = a.counterweight_energy_released or e.counterweight_energy_released or 0.0
        floor = tol.ENERGY_DISSIPATED_FLOOR * max(abs(released), 1.0)
        rows += [_numeric(f"dissipated_{name}", "J", a.energy_dissipated[name], e.energy_dissipated[name],
                          max(tol.ENERGY_DISSIPATED_REL * abs(a.energy_dissipated[name]), floor))
                 for name in LOSS_NAMES]
    if a.frame_landing_displacement is not None and e.frame_landing_displacement is not None:
        rows.append(_numeric("frame_landing_displacement", "m", a.frame_landing_displacement,
                             e.frame_landing_displacement, tol.FRAME_LANDING_DISPLACEMENT))
    return tuple(rows)


def compare(case: Case, dt: float = DEFAULT_DT, engine: Callable[[Design, float], Shot] = engine_simulate,
            analytic: Callable[[Design], Shot] = simulate_fast,
            analytic_shot: Shot | None = None) -> Comparison:
    """Simulate ``case`` in both models and compare.

    The analytic side is the compiled fast path by default (the same numbers as
    ``analytic.reference.simulate`` to round-off or the integrator's own error,
    ``tests/test_analytic_fast.py``); pass ``analytic=simulate`` for the scipy
    reference, or ``analytic_shot``, already simulated (``crosscheck.run`` shoots
    all cases in one batch). Either way a valid design gives a ``Shot``, whose
    status names any failure. A thrown shot without the work each loss took
    (the fast path's) gets it from the reference summary (``with_dissipated_work``,
    in the worker that runs its engine: 2.3 s for the default suite's 57 thrown designs).

    The engine runs at ``dt``; where its own diagnostics say the run is not
    accurate enough (energy error above ``ENGINE_ENERGY_TRUST``, or an
    ``EngineError``: unstable, joints apart, a flight gone non-finite), the step
    is halved, at most ``MAX_STEP_HALVINGS`` times, and the step used is
    reported. An engine that still cannot be trusted is a disagreement with its
    message (``Comparison.error``), not an exception.

    Parameters
    ----------
    case : the design, its name and group.
    dt : the engine's first step, s.
    engine : ``(design, dt) -> Shot`` with ``EngineDiagnostics`` in ``shot.diagnostics``.
    analytic : ``design -> Shot``, used when ``analytic_shot`` is None.
    """
    a = with_dissipated_work(analytic(case.design) if analytic_shot is None else analytic_shot)
    step = dt
    for halvings in range(tol.MAX_STEP_HALVINGS + 1):
        last = halvings == tol.MAX_STEP_HALVINGS
        try:
            e = engine(case.design, step)
        except EngineError as error:
            if last:
                return Comparison(case.name, case.group, a.status.value, "error", (), None,
                                  f"{type(error).__name__}: {error}", engine_dt=step, kind=case.design.machine.kind)
            step /= 2.0
            continue
        if e.diagnostics.energy_error <= tol.ENGINE_ENERGY_TRUST or last:
            break
        step /= 2.0
    return Comparison(case.name, case.group, a.status.value, e.status.value, compare_shots(a, e),
                      float(e.diagnostics.max_joint_drift), engine_dt=step,
                      engine_energy_error=float(e.diagnostics.energy_error), kind=case.design.machine.kind)


@dataclass(frozen=True)
class StepStudy:
    """Engine error against step size on one design.

    Attributes
    ----------
    dt : (k,) steps, s.
    speed_error, range_error : (k,) ``|engine - analytic| / analytic``.
    speed_order, range_order : fitted slope of log(error) against log(dt).
    """

    design: str
    dt: np.ndarray
    speed_error: np.ndarray
    range_error: np.ndarray
    speed_order: float
    range_order: float

    def to_json(self) -> dict:
        return {"design": self.design, "dt": self.dt.tolist(), "speed_error": self.speed_error.tolist(),
                "range_error": self.range_error.tolist(), "speed_order": self.speed_order,
                "range_order": self.range_order}


def step_study(design: Design, dts: tuple[float, ...] = (4e-4, 2e-4, 1e-4, 5e-5),
               engine: Callable[[Design, float], Shot] = engine_simulate,
               analytic: Callable[[Design], Shot] = simulate_fast) -> StepStudy:
    """Measure the engine's convergence order against the analytic model."""
    reference = analytic(design)
    speed, rng = [], []
    for dt in dts:
        shot = engine(design, dt)
        speed.append(abs(shot.release_speed / reference.release_speed - 1.0))
        rng.append(abs(shot.range / reference.range - 1.0))
    log_dt = np.log(dts)
    return StepStudy(design.name, np.array(dts), np.array(speed), np.array(rng),
                     float(np.polyfit(log_dt, np.log(speed), 1)[0]),
                     float(np.polyfit(log_dt, np.log(rng), 1)[0]))
