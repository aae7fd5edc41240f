"""The page's tools, each a function of (design, inputs, job) over the library: best pin, aim, what-if, cross-check,
optimise (``workbench.optimising``)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from analytic import fast
from analytic.aim import aim, check_inputs, default_bounds
from analytic.design import Design, DesignError
from analytic.fields import Field, field
from analytic.result import PEAK_NAMES

from workbench.jobs import Job
from workbench.optimising import around_bounds, optimise_design
from workbench.shot import PAGE_FLIGHT_SAMPLE_STEP, PAGE_SAMPLE_STEP, history_json

#: Release angles the best-pin scan shoots over the rule's span (then refined between the best's neighbours).
BEST_PIN_POINTS = 89
#: Shots a what-if sweep may ask for, and shots per progress step of the scans.
MAX_SWEEP_STEPS = 201
CHUNK = 16


def _number(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise DesignError(name, value, "must be a finite number")
    return float(value)


def _ranges(design: Design, target: Field, values: np.ndarray, job: Job, loads: bool = False):
    """Each setting's fast shot, in chunks with progress: (range (NaN: no throw), status, peak loads)."""
    designs, valid = [], []
    for value in values:
        try:
            designs.append(target.replace(design, float(value)))
            valid.append(True)
        except DesignError:
            valid.append(False)
    ranges = np.full(len(values), np.nan)
    status = np.array(["design_error"] * len(values), dtype=object)
    peaks = {name: np.full(len(values), np.nan) for name in PEAK_NAMES}
    where = np.flatnonzero(valid)
    for start in range(0, len(designs), CHUNK):
        job.check()
        shots = fast.shoot(designs[start:start + CHUNK], loads=loads, threads=1)
        index = where[start:start + CHUNK]
        ranges[index] = np.where(shots.ok, shots.range, np.nan)
        status[index] = [s.value for s in shots.status]
        for name in PEAK_NAMES:
            peaks[name][index] = getattr(shots, name)
        job.progress = min(1.0, (start + CHUNK) / max(len(designs), 1))
    return ranges, status, peaks


def best_pin(design: Design, inputs: dict[str, Any], job: Job) -> dict[str, Any]:
    """The release angle of the longest range: a scan over the rule's span, then a bounded refinement.

    A design whose ``release_rule`` is ``ideal`` needs no scan: it already releases at its longest
    throw, and its shot's launch angle is the velocity rule's best pin (``docs/guide/design-files.md``).
    The answer then says so (``"ideal": true``, ``value`` that launch angle, deg) and scans nothing.
    """
    from scipy.optimize import minimize_scalar

    target = field("machine.release_angle")
    if design.machine.release_rule == "ideal":
        shot = fast.simulate_fast(design, loads=False)
        angle = shot.launch_angle if shot.ok else None
        return {"field": target.name, "ideal": True, "value": None if angle is None else math.degrees(angle),
                "range": shot.range if shot.ok else None, "values": [], "ranges": []}
    low, high = default_bounds(target, design)
    values = np.linspace(low, high, BEST_PIN_POINTS)
    ranges, _, _ = _ranges(design, target, values, job)
    if not np.isfinite(ranges).any():
        return {"field": target.name, "value": None, "range": None, "values": values.tolist(),
                "ranges": [None] * len(values)}
    best = int(np.nanargmax(ranges))
    a, b = values[max(best - 1, 0)], values[min(best + 1, len(values) - 1)]

    def negative_range(angle: float) -> float:
        job.check()
        shot = fast.simulate_fast(target.replace(design, angle), loads=False)
        return -shot.range if shot.ok else math.inf

    found = minimize_scalar(negative_range, bounds=(a, b), method="bounded", options={"xatol": 1e-3})
    value, reach = (float(found.x), -float(found.fun)) if -found.fun >= ranges[best] else (values[best], ranges[best])
    return {"field": target.name, "value": float(value), "range": float(reach), "values": values.tolist(),
            "ranges": [None if math.isnan(r) else float(r) for r in ranges]}


def aim_at(design: Design, inputs: dict[str, Any], job: Job) -> dict[str, Any]:
    """``analytic.aim.aim``: the settings of one field that land on a target distance (m)."""
    target_field = field(inputs.get("field", "machine.release_angle"))
    target_field.check(design)
    target = _number("target", inputs.get("target"))
    bounds = default_bounds(target_field, design)
    check_inputs(target, bounds, None)
    job.check()
    return aim(design, target_field.name, target, bounds=bounds, check=job.check).to_json()


def what_if(design: Design, inputs: dict[str, Any], job: Job) -> dict[str, Any]:
    """One field swept from ``low`` to ``high`` (file units): each setting's range and one peak load."""
    target = field(inputs.get("field", ""))
    target.check(design)
    low, high = _number("low", inputs.get("low")), _number("high", inputs.get("high"))
    if not low < high:
        raise DesignError("low", low, f"must be below high ({high:g})")
    steps = inputs.get("steps", 41)
    if isinstance(steps, bool) or not isinstance(steps, int) or not 3 <= steps <= MAX_SWEEP_STEPS:
        raise DesignError("steps", steps, f"must be a whole number from 3 to {MAX_SWEEP_STEPS}")
    load = inputs.get("load", "peak_axle_load")
    if load not in PEAK_NAMES:
        raise DesignError("load", load, f"must be one of {', '.join(PEAK_NAMES)}")
    values = np.linspace(low, high, steps)
    ranges, status, peaks = _ranges(design, target, values, job, loads=True)

    def listed(array: np.ndarray) -> list:
        return [None if math.isnan(v) else float(v) for v in array]

    return {"field": target.name, "load": load, "values": values.tolist(), "ranges": listed(ranges),
            "loads": listed(peaks[load]), "status": status.tolist(), **shown_load(load, peaks[load], design)}


def shown_load(load: str, values: np.ndarray, design: Design) -> dict[str, Any]:
    """How the page shows a peak load's ``values``: ``load_label`` (a fixed machine's mount load),
    ``load_kind`` (its unit's kind) and ``loads_shown`` in that kind's file unit (the projectile's
    acceleration in g, as the shot's summary gives it: ``analytic.summary``)."""
    from analytic.summary import G, SHOWN_PEAK_UNITS, in_g, peak_label
    from analytic.units import SHOWN_KINDS

    unit = SHOWN_PEAK_UNITS[load]
    shown = in_g(values, design) if unit == G else values
    return {"load_label": peak_label(load, design), "load_kind": SHOWN_KINDS[unit],
            "loads_shown": [None if math.isnan(v) else float(v) for v in shown]}


def cross_check(design: Design, inputs: dict[str, Any], job: Job) -> dict[str, Any]:
    """The pymunk twin on this design beside the analytic model (``crosscheck.compare``): the
    agreement table and, under ``engine``, the engine's shot as the stage draws one (its swing
    and flight, ``history_json``)."""
    import engine_model
    from crosscheck import Case, compare

    engine_shots = []

    def engine(design: Design, dt: float):
        """The engine as ``compare`` runs it, each shot kept (the last is the one compared)."""
        job.check()
        engine_shots.append(engine_model.simulate(design, dt=dt))
        return engine_shots[-1]

    comparison = compare(Case(design.name, design, "workbench"), engine=engine)
    shot = engine_shots[-1] if engine_shots else None
    drawn = None if shot is None or shot.history is None else {
        "status": shot.status.value, "range": shot.range,
        # the engine samples every step (0.1 ms): thinned to the stage's own spacing
        "history": history_json(shot, PAGE_SAMPLE_STEP, PAGE_FLIGHT_SAMPLE_STEP)}
    return {**comparison.to_json(), "engine": drawn}


#: The tools by the name the page asks for.
TOOLS = {"best_pin": best_pin, "aim": aim_at, "what_if": what_if, "crosscheck": cross_check,
         "optimise": optimise_design, "around_bounds": around_bounds}


#: Most targets and projectile masses a firing table on the page may ask for.
MAX_FIRING_TARGETS, MAX_FIRING_MASSES = 25, 5


def firing(design: Design, inputs: dict[str, Any], job: Job) -> dict[str, Any]:
    """``analytic.firing.firing_table``: ``targets`` (m) and ``masses`` (kg, or none: the design's own)
    as ``[from, to, steps]``; each row's settings in file units (``values``), a mass at a time."""
    from analytic.firing.table import steps_of

    target_field = field(inputs.get("field", "machine.release_angle"))
    target_field.check(design)
    ranges = {}
    for name, most in (("targets", MAX_FIRING_TARGETS), ("masses", MAX_FIRING_MASSES)):
        given = inputs.get(name)
        if given is None and name == "masses":
            continue
        if not (isinstance(given, list) and len(given) == 3):
            raise DesignError(name, given, "must be [from, to, steps]")
        steps = given[2]
        if isinstance(steps, bool) or not isinstance(steps, int) or not 1 <= steps <= most:
            raise DesignError(name, given, f"steps must be a whole number from 1 to {most}")
        ranges[name] = steps_of(name, _number(name, given[0]), _number(name, given[1]), steps)
    from analytic.firing import firing_table

    masses = ranges.get("masses")
    rows = []
    for index, mass in enumerate([None] if masses is None else masses):
        job.check()
        table = firing_table(design, target_field.name, ranges["targets"], None if mass is None else [mass],
                             check=job.check)
        rows += [{"target": e.target, "projectile_mass": e.projectile_mass, "values": list(e.settings),
                  "status": e.status} for e in table.entries]
        job.progress = (index + 1) / (1 if masses is None else len(masses))
    return {"field": target_field.name, "unit": target_field.unit, "rows": rows}


TOOLS["firing_table"] = firing
