"""The page's optimiser: around the design on screen (or the paper's problem, a preset problem), and the
front of range against peak axle load.

Around the design (``analytic.optimise.around``) each design variable lies within bounds about its
value, which the page shows (``around_bounds``) and the user may change; the machine's kind, losses,
frame, projectile and release rule are kept, and its own footprint and pivot height are the size
limits unless the user gives others. Each optimum comes with ``changes``, the optimised fields only,
which the page's "Adopt" writes into the design on screen. The paper's problem (``default_problem``)
gives the paper's table-top machines, adopted whole.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from analytic import fast
from analytic.design import Design, DesignError
from analytic.design_file import design_to_dict
from analytic.design_space import ANGLE_VARIABLES, VARIABLE_NAMES, Problem, default_problem, design_at
from analytic.optimise.around import (OPTIMISED_FIELDS, adopted, default_bounds, fixed_variables, problem_around,
                                      start_values)
from analytic.optimise.constraints import CONSTRAINT_NAMES, FEASIBILITY_TOLERANCE, constraint_values, footprint

from workbench.jobs import Job

#: The axle-load caps of the range-against-axle-load front, as fractions of the peak axle load
#: of the unconstrained optimum (1: that optimum itself); the start design's own load is a cap too.
FRONT_FRACTIONS = (1.0, 0.85, 0.7, 0.55, 0.4)
#: Problems the page offers: around the design on screen, and the paper's (a preset problem).
PROBLEMS = ("around", "paper")
#: Global-stage generations a page search runs unless asked (``search.Settings.maxiter``), and the most.
PAGE_GENERATIONS = 8
MAX_GENERATIONS = 40
#: The limits the page may set (m; N for the axle load).
LIMITS = ("max_footprint", "max_height", "axle_radius", "max_axle_load")
#: How the page's table names each design variable and each limit (with its unit's kind).
VARIABLE_LABELS = {"arm_short": "short arm", "counterweight_link": "weight link", "clearance": "clearance",
                   "sling_length": "sling", "starting_angle": "starting angle", "release_angle": "release angle"}
LIMIT_LABELS = {"max_footprint": ("footprint at most", "length"), "max_height": ("pivot height at most", "length"),
                "axle_radius": ("axle radius", "length"), "max_axle_load": ("peak axle load at most", "force")}


def _number(name: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise DesignError(name, value, "must be a finite number")
    return float(value)


def around_bounds(design: Design, inputs: dict[str, Any], job: Job) -> dict[str, Any]:
    """The default bounds and limits around ``design`` in file units (m, deg), for the page to show:
    ``variables`` (name, label, unit kind, value, lower, upper; fixed ones flagged), ``limits`` and
    ``limit_rows`` (each limit's name, label and unit kind, in the table's order)."""
    bounds = default_bounds(design)
    rows = []
    for name, value in zip(VARIABLE_NAMES, start_values(design), strict=True):
        angle = name in ANGLE_VARIABLES
        shown = (lambda v: math.degrees(v)) if angle else (lambda v: v)
        low, high = bounds.get(name, (value, value))
        rows.append({"name": name, "kind": "angle" if angle else "length", "value": shown(value),
                     "lower": shown(low), "upper": shown(high), "fixed": name in fixed_variables(design),
                     "label": VARIABLE_LABELS[name]})
    m = design.machine
    return {"variables": rows,
            "limit_rows": [{"name": name, "label": label, "kind": kind} for name, (label, kind) in LIMIT_LABELS.items()],
            "limits": {"max_footprint": footprint(m, design.base.trough_height), "max_height": m.pivot_height,
                       "axle_radius": design.losses.axle_radius or 0.0, "max_axle_load": None}}


def problem_of(design: Design, inputs: dict[str, Any]) -> Problem:
    """The problem a request asks for: ``inputs["problem"]`` ``"around"`` (the default: its
    ``bounds``, name -> [lower, upper] in m and deg, and ``limits``, ``LIMITS`` -> m or N or null)
    or ``"paper"``."""
    kind = inputs.get("problem", "around")
    if kind not in PROBLEMS:
        raise DesignError("problem", kind, f"must be one of {', '.join(PROBLEMS)}")
    if kind == "paper":
        return default_problem()
    given = inputs.get("bounds") or {}
    if not isinstance(given, dict):
        raise DesignError("bounds", given, "must be an object: variable -> [lower, upper]")
    bounds = {}
    for name, pair in given.items():
        if not (isinstance(pair, list) and len(pair) == 2):
            raise DesignError(f"bounds.{name}", pair, "must be [lower, upper]")
        low, high = (_number(f"bounds.{name}", v) for v in pair)
        bounds[name] = (math.radians(low), math.radians(high)) if name in ANGLE_VARIABLES else (low, high)
    limits = inputs.get("limits") or {}
    if not isinstance(limits, dict):
        raise DesignError("limits", limits, "must be an object")
    for name in set(limits) - set(LIMITS):
        raise DesignError(f"limits.{name}", limits[name], f"not a limit; expected one of {', '.join(LIMITS)}")
    chosen = {name: _number(f"limits.{name}", limits[name]) for name in LIMITS if limits.get(name) is not None}
    load = chosen.pop("max_axle_load", None)
    return problem_around(design, bounds, load_limits=() if load is None else (("axle_load", load),), **chosen)


def generations_of(inputs: dict[str, Any]) -> int:
    generations = inputs.get("generations", PAGE_GENERATIONS)
    if isinstance(generations, bool) or not isinstance(generations, int) or not 1 <= generations <= MAX_GENERATIONS:
        raise DesignError("generations", generations, f"must be a whole number from 1 to {MAX_GENERATIONS}")
    return generations


def _changes(design: Design) -> dict[str, float]:
    """The optimised fields of ``design`` as the page's design holds them (file units, deg)."""
    m = design.machine
    return {f"machine.{name}": (math.degrees(getattr(m, name)) if name == "release_angle" else getattr(m, name))
            for name in OPTIMISED_FIELDS if getattr(m, name) is not None
            and not (name == "counterweight_link" and m.kind != "hinged")}


def optimise_design(design: Design, inputs: dict[str, Any], job: Job) -> dict[str, Any]:
    """``analytic.optimise.optimise`` around the design (or on the paper's problem); with ``"front": true``
    also the longest range under axle-load caps: ``FRONT_FRACTIONS`` of the optimum's peak axle load
    and the design's own (range against peak axle load). Each point carries its design to adopt
    (``changes``: only the optimised fields; the paper's problem: ``design``, whole). ``start`` is
    the design on screen: its range, its peak axle load and the limits it breaks."""
    from analytic.optimise import optimise
    from analytic.optimise.search import Settings

    problem = problem_of(design, inputs)
    settings = Settings(maxiter=generations_of(inputs))
    around = inputs.get("problem", "around") == "around"
    start = start_values(design) if around else None
    shot = fast.simulate_fast(design, loads=True)
    violated = [name for name, g in zip(CONSTRAINT_NAMES, constraint_values(problem, design.machine), strict=True)
                if g < -FEASIBILITY_TOLERANCE] if around else []
    limit = dict(problem.load_limits).get("axle_load", math.inf)
    if around and shot.ok and shot.peak_axle_load > limit:
        violated.append("peak axle load")
    start_row = {"range": shot.range if shot.ok else None, "status": shot.status.value,
                 "peak_axle_load": shot.peak_axle_load if shot.ok else None, "violates": violated}

    runs = [None]
    points: list[dict[str, Any]] = []
    index = 0
    while index < len(runs):
        job.check()
        cap = runs[index]
        limited = problem if cap is None else dataclasses.replace(
            problem, load_limits=tuple(p for p in problem.load_limits if p[0] != "axle_load") + (("axle_load", cap),))
        result = optimise(limited, workers=1, start=start, settings=settings, check=job.check)
        values, load = result.optimum.values, result.peaks["optimum"].get("peak_axle_load")
        reach = None if load is None else result.ranges["optimum"]   # no peaks: nothing found throws
        points.append({"axle_limit": cap, "range": reach, "peak_axle_load": load, "values": values,
                       "problem": limited})
        if cap is None and inputs.get("front") and load is not None:
            caps = [fraction * load for fraction in FRONT_FRACTIONS[1:]]
            if around and start_row["peak_axle_load"] is not None and start_row["peak_axle_load"] < 0.99 * load:
                caps.append(start_row["peak_axle_load"])
            runs += sorted((min(c, limit) for c in caps), reverse=True)
        index += 1
        job.progress = min(1.0, index / (1 + len(FRONT_FRACTIONS) * bool(inputs.get("front"))))
    _keep_the_front(points)
    return {"problem": problem.name, "start": start_row,
            "points": [_point(design, p, around) for p in points]}


def _keep_the_front(points: list[dict[str, Any]]) -> None:
    """A design found under a tighter cap meets every looser one: where it throws farther than the
    looser cap's own optimum, it is that cap's answer too (the front never falls as a cap loosens)."""
    best = None
    for point in sorted(points, key=lambda p: math.inf if p["axle_limit"] is None else p["axle_limit"]):
        if best is not None and best["range"] is not None and (point["range"] is None
                                                               or best["range"] > point["range"]):
            point.update({k: best[k] for k in ("range", "peak_axle_load", "values")})
        best = point


def _point(design: Design, point: dict[str, Any], around: bool) -> dict[str, Any]:
    problem, values = point["problem"], point["values"]
    cap = point["axle_limit"]
    name = "optimum" if cap is None else f"optimum-axle-{cap:.4g}"
    if around:
        found = dataclasses.replace(adopted(design, problem, values), name=f"{design.name}-{name}")
        changes = _changes(found)
    else:
        found, changes = design_at(problem, values, name=name), None
    return {"axle_limit": cap, "range": point["range"], "peak_axle_load": point["peak_axle_load"],
            "design": design_to_dict(found), "changes": changes}
