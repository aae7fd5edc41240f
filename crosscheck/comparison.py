"""Run one design through both models and compare what they report, quantity by quantity."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from analytic.design import Design
from analytic.outcome import Status
from analytic.fast import simulate_fast
from analytic.reference import simulate
from analytic.result import LOSS_NAMES, PEAK_NAMES, Shot
from crosscheck import tolerances as tol
from crosscheck.cases import Case
import engine_model
from crosscheck.sensitivity import spread
from engine_model import DEFAULT_DT, EngineError
from engine_model.flight import FLIGHT_STEP_LIMIT


def engine_simulate(design: Design, dt: float) -> Shot:
    """The pymunk model's shot at step ``dt`` (s), its ``EngineDiagnostics`` in ``shot.diagnostics``,
    within the cross-check's step budget (``tolerances.REFINEMENT_STEP_LIMIT``)."""
    return engine_model.simulate(design, dt=dt, step_limit=tol.REFINEMENT_STEP_LIMIT)


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


#: A case's verdicts (``Comparison.verdict``), as ``python -m crosscheck --json`` names them: the
#: models agree; they differ; the design amplifies a difference of a few parts in 1e9 in its own
#: inputs past a tolerance, so a difference there says nothing (``crosscheck.sensitivity``); the
#: engine could not run it (it raised, or its worker died); the engine's error could not be brought
#: under the tolerance within its budget (``tolerances.MAX_REFINEMENTS``).
AGREE, DISAGREE, SENSITIVE, ENGINE_FAILED, ENGINE_UNTRUSTED = (
    "agree", "disagree", "sensitive", "engine_failed", "engine_untrusted")
VERDICTS = (AGREE, DISAGREE, SENSITIVE, ENGINE_FAILED, ENGINE_UNTRUSTED)
#: The verdicts that count as agreement (``Comparison.agree``): a sensitive case is neither a pass
#: nor a failure, and is listed as such, but it is no evidence against either model.
AGREEING = (AGREE, SENSITIVE)


@dataclass(frozen=True)
class Comparison:
    """Both models' verdict on one case.

    Attributes
    ----------
    verdict : one of ``VERDICTS``; when not given, ``engine_failed`` with an ``error``, else
        ``agree`` or ``disagree`` by the rows.
    sensitivity : where the models differed, the spread of each compared quantity when the design's
        inputs move by a few parts in 1e9 (``crosscheck.sensitivity.spread``), in its unit; None
        where they agreed at once (nothing to explain).
    engine_error : where the engine's step was refined (``refinements`` halvings past
        ``engine_dt``'s first trusted step), its estimated error on each quantity compared, from
        its last two steps (``tolerances.ENGINE_ORDER``); None otherwise.
    extrapolated : the quantities whose engine value is the Richardson extrapolation of its last
        two steps (``refine``), their ``engine_error`` that of the extrapolation; empty otherwise.
    """

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
    verdict: str = ""
    sensitivity: dict[str, float] | None = None
    engine_error: dict[str, float] | None = None
    refinements: int = 0
    extrapolated: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if not self.verdict:
            verdict = (ENGINE_FAILED if self.error is not None
                       else AGREE if all(row.ok for row in self.rows) else DISAGREE)
            object.__setattr__(self, "verdict", verdict)
        elif self.verdict not in VERDICTS:
            raise ValueError(f"verdict = {self.verdict!r}: must be one of {', '.join(VERDICTS)}")

    @property
    def agree(self) -> bool:
        """Whether the case counts as agreement: verdict ``agree`` or ``sensitive``."""
        return self.verdict in AGREEING

    def to_json(self) -> dict:
        """The comparison as ``python -m crosscheck --json`` prints it: the machine's ``kind`` on the
        design's record and on each of its quantity's rows; ``sensitivity`` where it was measured,
        ``engine_error`` where the engine's step was refined, ``extrapolated`` where it was used."""
        record = {"case": self.case, "group": self.group, "kind": self.kind, "agree": self.agree,
                  "verdict": self.verdict,
                  "analytic_status": self.analytic_status, "engine_status": self.engine_status,
                  "max_joint_drift": self.max_joint_drift, "error": self.error,
                  "engine_dt": self.engine_dt, "engine_energy_error": self.engine_energy_error,
                  "refinements": self.refinements,
                  "rows": [{**row.__dict__, "kind": self.kind} for row in self.rows]}
        if self.sensitivity is not None:
            record["sensitivity"] = dict(self.sensitivity)
        if self.engine_error is not None:
            record["engine_error"] = dict(self.engine_error)
        if self.extrapolated:
            record["extrapolated"] = list(self.extrapolated)
        return record


def verdict_counts(comparisons) -> dict[str, int]:
    """How many of ``comparisons`` have each verdict, every verdict listed (0 where none)."""
    counts = dict.fromkeys(VERDICTS, 0)
    for c in comparisons:
        counts[c.verdict] += 1
    return counts


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
    if a.status is e.status is Status.SHORT_OF_TARGET:   # how far short: the apex below the target
        rows.append(_numeric("apex_height", "m", a.apex_height, e.apex_height, tol.APEX_HEIGHT_REL * a.apex_height))
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
            analytic_shot: Shot | None = None,
            sensitivity: Callable[[Design, Callable], dict[str, float]] = spread) -> Comparison:
    """Simulate ``case`` in both models, compare, and say what a difference means.

    The analytic side is the compiled fast path by default (the same numbers as
    ``analytic.reference.simulate`` to round-off or the integrator's own error,
    ``tests/test_analytic_fast.py``); pass ``analytic=simulate`` for the scipy
    reference, or ``analytic_shot``, already simulated (``crosscheck.run`` shoots
    all cases in one batch). Either way a valid design gives a ``Shot``, whose
    status names any failure. A thrown shot without the work each loss took
    (the fast path's) gets it from the reference summary (``with_dissipated_work``,
    in the worker that runs its engine).

    The engine runs at ``dt``; where its own diagnostics say the run is not
    accurate enough (energy error above ``ENGINE_ENERGY_TRUST``, or an
    ``EngineError``: unstable, joints apart, a flight gone non-finite), the step
    is halved, at most ``MAX_STEP_HALVINGS`` times. An engine that raises at
    every step is ``engine_failed``, with its message (``Comparison.error``).

    Where every quantity agrees, that is the verdict. Where one differs, the
    difference is explained before it is called a disagreement:

    1. the design's own sensitivity is measured (``sensitivity``: the analytic
       model on copies of the design moved by parts in 1e9); a quantity whose
       spread alone exceeds its tolerance cannot be compared;
    2. the engine's step is halved while its error on a differing quantity
       that can be compared, estimated from its last two steps, is over
       ``ENGINE_ERROR_SHARE`` of the tolerance (``refine``), within its budget.

    The verdict is then ``agree`` (the refined engine agrees), ``sensitive``
    (every quantity still apart is one the design amplifies), ``engine_untrusted``
    (the budget ran out with the engine's error still too large for one of them)
    or ``disagree``.

    Parameters
    ----------
    case : the design, its name and group.
    dt : the engine's first step, s.
    engine : ``(design, dt) -> Shot`` with ``EngineDiagnostics`` in ``shot.diagnostics``.
    analytic : ``design -> Shot``, used when ``analytic_shot`` is None.
    sensitivity : ``(design, compare_rows) -> {quantity: spread}`` (``crosscheck.sensitivity.spread``).
    """
    a = with_dissipated_work(analytic(case.design) if analytic_shot is None else analytic_shot)
    kind = case.design.machine.kind
    e, step, error = _trusted_run(case.design, dt, engine)
    if e is None:
        return Comparison(case.name, case.group, a.status.value, "error", (), None, error, engine_dt=step,
                          kind=kind, verdict=ENGINE_FAILED)
    rows = compare_shots(a, e)
    measured = estimates = None
    refined = 0
    extrapolated: tuple[str, ...] = ()
    verdict, error = AGREE, None
    if not all(row.ok for row in rows):
        measured = sensitivity(case.design, compare_shots)
        amplified = {row.quantity for row in rows if _amplified(row, measured)}
        refinement = refine(case.design, a, e, step, engine, amplified)
        e, step, rows, estimates, refined = (refinement.shot, refinement.dt, refinement.rows,
                                             refinement.estimates, refinement.halvings)
        extrapolated = tuple(sorted(refinement.extrapolated))
        apart = [row for row in rows if not row.ok]
        unexplained = [row for row in apart if row.quantity not in amplified]
        unresolved = [row for row in unexplained if row.quantity in refinement.unresolved]
        if not apart:
            verdict = AGREE
        elif not unexplained:
            verdict = SENSITIVE
        elif unresolved:
            verdict, error = ENGINE_UNTRUSTED, _untrusted_message(unresolved, estimates, step, refinement.stopped)
        else:
            verdict = DISAGREE
    return Comparison(case.name, case.group, a.status.value, e.status.value, rows,
                      float(e.diagnostics.max_joint_drift), error, engine_dt=step,
                      engine_energy_error=float(e.diagnostics.energy_error), kind=kind, verdict=verdict,
                      sensitivity=measured, engine_error=estimates, refinements=refined,
                      extrapolated=extrapolated)


def _trusted_run(design: Design, dt: float, engine: Callable[[Design, float], Shot]):
    """``(shot, step, None)``: the engine's shot at ``dt``, or at ``dt`` halved up to
    ``MAX_STEP_HALVINGS`` times while its energy error is over ``ENGINE_ENERGY_TRUST`` or it raises
    (the last run is kept whatever its energy error); ``(None, step, message)`` when it raised at
    every step."""
    step = dt
    for halvings in range(tol.MAX_STEP_HALVINGS + 1):
        last = halvings == tol.MAX_STEP_HALVINGS
        try:
            e = engine(design, step)
        except EngineError as error:
            if last:
                return None, step, f"{type(error).__name__}: {error}"
            step /= 2.0
            continue
        if e.diagnostics.energy_error <= tol.ENGINE_ENERGY_TRUST or last:
            return e, step, None
        step /= 2.0
    raise AssertionError("unreachable: the last halving returns")


def _amplified(row: Row, measured: dict[str, float]) -> bool:
    """Whether the design's own spread of ``row``'s quantity is over its tolerance (the outcome's
    tolerance is none: any other status in a perturbed copy is over it)."""
    if row.quantity not in measured:
        return False
    return measured[row.quantity] > (0.0 if row.tolerance is None else row.tolerance)


@dataclass(frozen=True)
class Refinement:
    """``refine``'s result: the engine's last ``shot`` at step ``dt`` (s) after ``halvings`` halvings,
    its ``rows`` against the analytic shot, its estimated error on each quantity (``estimates``,
    None before any halving), the differing quantities it could not resolve (``unresolved``),
    those whose row holds the extrapolation of the last two steps (``extrapolated``), and why it
    stopped (``stopped``: ``"resolved"``, ``"halvings"``, ``"steps"`` or the engine's error)."""

    shot: Shot
    dt: float
    rows: tuple[Row, ...]
    estimates: dict[str, float] | None
    halvings: int
    unresolved: frozenset[str]
    stopped: str
    extrapolated: frozenset[str] = frozenset()


def refine(design: Design, a: Shot, e: Shot, dt: float, engine: Callable[[Design, float], Shot],
           skip: set[str] = frozenset()) -> Refinement:
    """Halve the engine's step until its estimated error on every quantity that differs from the
    analytic shot ``a`` (but those in ``skip``) is at most ``ENGINE_ERROR_SHARE`` of its tolerance.

    A run's error is estimated from it and the run at twice its step: ``|q(h/2) - q(h)| / (2**p - 1)``
    with ``p`` the quantity's order (``tolerances.ENGINE_ORDER``); the outcome's is 0 where both
    runs end alike, unbounded where they do not. Where that estimate is still too large, the
    Richardson extrapolation of the last two runs, ``q(h/2) + (q(h/2) - q(h)) / (2**p - 1)``, is
    compared instead once its own error can be estimated, as its change from the extrapolation one
    halving earlier (three runs at least): a slow, long swing whose error shrinks as ``h**2`` is
    then resolved two halvings (16x the steps) sooner. The budget: at most ``MAX_REFINEMENTS``
    halvings, and no run past ``engine_budget``'s steps.
    """
    rows = compare_shots(a, e)
    estimates: dict[str, float] | None = None
    previous: dict[str, float] = {}
    extrapolated: frozenset[str] = frozenset()
    halvings = 0
    stopped = "resolved"
    while True:
        unresolved = frozenset(row.quantity for row in rows if not row.ok and row.quantity not in skip
                               and not _resolved(row, estimates))
        if not unresolved:
            stopped = "resolved"
            break
        if halvings == tol.MAX_REFINEMENTS:
            stopped = "halvings"
            break
        if not engine_budget(e):
            stopped = "steps"
            break
        try:
            finer = engine(design, dt / 2.0)
        except EngineError as error:
            stopped = f"{type(error).__name__}: {error}"
            break
        estimates = error_estimates(e, finer)
        values = extrapolations(e, finer)
        e, dt, halvings = finer, dt / 2.0, halvings + 1
        rows, estimates, extrapolated = _extrapolated_rows(compare_shots(a, e), estimates, values, previous)
        previous = values
    return Refinement(e, dt, rows, estimates, halvings, unresolved, stopped, extrapolated)


def extrapolations(coarse: Shot, fine: Shot) -> dict[str, float]:
    """The Richardson extrapolation to a zero step of each quantity both runs reach (``fine`` at
    half ``coarse``'s step), in its unit: ``q(h/2) + (q(h/2) - q(h)) / (2**p - 1)``
    (``tolerances.ENGINE_ORDER``)."""
    values = {}
    for row in compare_shots(fine, coarse):
        if row.difference is not None:
            order = tol.ENGINE_ORDER.get(row.quantity, tol.ENGINE_DEFAULT_ORDER)
            values[row.quantity] = row.analytic - row.difference / (2.0**order - 1.0)
    return values


def _extrapolated_rows(rows: tuple[Row, ...], estimates: dict[str, float], values: dict[str, float],
                       previous: dict[str, float]) -> tuple[tuple[Row, ...], dict[str, float], frozenset[str]]:
    """``rows`` with the extrapolated engine value (``values``) in every differing row whose own
    run's error is too large but whose extrapolation's (its change from ``previous``, the
    extrapolation one halving earlier) is within ``ENGINE_ERROR_SHARE`` of the tolerance; the
    estimates with the extrapolation's error for those rows, and their quantities."""
    estimates = dict(estimates)
    kept, extrapolated = [], set()
    for row in rows:
        quantity = row.quantity
        if (not row.ok and not _resolved(row, estimates) and quantity in values and quantity in previous
                and row.tolerance):
            error = abs(values[quantity] - previous[quantity])
            if error <= tol.ENGINE_ERROR_SHARE * row.tolerance:
                row = _numeric(quantity, row.unit, row.analytic, values[quantity], row.tolerance)
                estimates[quantity] = error
                extrapolated.add(quantity)
        kept.append(row)
    return tuple(kept), estimates, frozenset(extrapolated)


def _resolved(row: Row, estimates: dict[str, float] | None) -> bool:
    if estimates is None or row.quantity not in estimates:
        return False
    allowed = 0.0 if row.tolerance is None else tol.ENGINE_ERROR_SHARE * row.tolerance
    return estimates[row.quantity] <= allowed


def error_estimates(coarse: Shot, fine: Shot) -> dict[str, float]:
    """The engine's estimated error of ``fine`` (a run at half ``coarse``'s step) on each quantity
    both reach, in its unit: ``|fine - coarse| / (2**p - 1)`` (``tolerances.ENGINE_ORDER``); the
    outcome's is 0 where both end alike, ``inf`` where they do not."""
    estimates = {}
    for row in compare_shots(fine, coarse):
        if row.quantity == "outcome":
            estimates["outcome"] = 0.0 if row.ok else math.inf
        elif row.difference is not None:
            order = tol.ENGINE_ORDER.get(row.quantity, tol.ENGINE_DEFAULT_ORDER)
            estimates[row.quantity] = abs(row.difference) / (2.0**order - 1.0)
    return estimates


def engine_budget(shot: Shot) -> bool:
    """Whether a run at half ``shot``'s step stays within the cross-check's step limits (about twice
    its steps in each stage): ``tolerances.REFINEMENT_STEP_LIMIT`` for the swing and a rolling
    machine's run after release, ``engine_model.flight.FLIGHT_STEP_LIMIT`` for the flight."""
    d = shot.diagnostics
    return (2 * d.machine_steps <= tol.REFINEMENT_STEP_LIMIT and 2 * d.after_release_steps <= tol.REFINEMENT_STEP_LIMIT
            and 2 * d.flight_steps <= FLIGHT_STEP_LIMIT)


def _untrusted_message(rows: list[Row], estimates: dict[str, float] | None, dt: float, stopped: str) -> str:
    """What the engine reached where it could not resolve a difference, and why it stopped."""
    why = {"halvings": f"after {tol.MAX_REFINEMENTS} halvings of its step (MAX_REFINEMENTS)",
           "steps": "within its step limits"}.get(stopped, f"it raised {stopped}")
    parts = []
    for row in rows:
        estimate = None if estimates is None else estimates.get(row.quantity)
        if estimate is None:
            parts.append(f"{row.quantity}: no estimate")
        elif row.tolerance:
            parts.append(f"{row.quantity}: {estimate / row.tolerance:.3g} of its tolerance")
        else:
            parts.append(f"{row.quantity}: {'changed' if estimate else 'unchanged'} with the step")
    return (f"the engine's error could not be brought under {tol.ENGINE_ERROR_SHARE:g} of the tolerance "
            f"{why}: at dt = {dt:.3g} s its estimated error is " + "; ".join(parts))


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
               analytic: Callable[[Design], Shot] = simulate_fast) -> StepStudy | None:
    """Measure the engine's convergence order against the analytic model; None where the design
    does not throw in the analytic model, or fewer than two of the engine's steps throw it with an
    error to take the logarithm of (an order needs two points)."""
    reference = analytic(design)
    if not reference.ok:
        return None
    kept, speed, rng = [], [], []
    for dt in dts:
        try:
            shot = engine(design, dt)
        except EngineError:
            continue
        if not shot.ok:
            continue
        errors = (abs(shot.release_speed / reference.release_speed - 1.0), abs(shot.range / reference.range - 1.0))
        if min(errors) > 0.0:
            kept.append(dt)
            speed.append(errors[0])
            rng.append(errors[1])
    if len(kept) < 2:
        return None
    log_dt = np.log(kept)
    return StepStudy(design.name, np.array(kept), np.array(speed), np.array(rng),
                     float(np.polyfit(log_dt, np.log(speed), 1)[0]),
                     float(np.polyfit(log_dt, np.log(rng), 1)[0]))
