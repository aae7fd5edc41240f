"""Aim: the setting of one design field that lands the projectile on a target distance.

The target stands at the design's ``environment.target_height`` above the base (a pit below it):
the range aimed at is measured where the flight comes down to that level, and a setting whose
flight never rises to it (``short_of_target``) does not throw.

A competitor declares a distance and adjusts one thing on the machine (the
release pin, the counterweight, the sling). ``aim`` scans the field over its
bounds on the fast path (``analytic.fast.shoot``, one batch), finds every
crossing of the target (a low and a high throw, where there are two),
locates each on the fast path, and re-simulates it on the reference path,
refining there until the reference lands within ``AIM_TOLERANCE`` of the
target. It reports how many metres a unit of the setting moves the landing
point, the band of settings that stays within a tolerance, and the span of
ranges the bounds can reach. Values are in design-file units (SI, angles in
degrees) throughout.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from analytic.design import Design, DesignError
from analytic.fields import Field, field

#: The reference path's range must land this close to the target, m.
AIM_TOLERANCE = 1e-3
#: Settings scanned over the bounds before the crossings are located: enough that a low and a
#: high throw 1/80 of the span apart are told apart.
SCAN_POINTS = 161
#: Relative step of the central difference for metres per unit, of the bounds' span: the range
#: is smooth to ~1e-9 m at the default tolerances, so the difference's noise is ~1e-3 of 1 mm.
SLOPE_STEP = 1e-6
#: Widening of a field's value for default bounds (value / factor .. value x factor).
DEFAULT_SPREAD = 4.0
#: Most reference refinements (secant steps) after the fast path's root.
MAX_REFERENCE_STEPS = 8
#: What a setting that does not throw counts as in the root and extreme searches, m: farther
#: than any throw, and finite (the searches' arithmetic must not meet infinities).
NO_THROW = 1e9


@dataclass(frozen=True)
class Solution:
    """One setting that lands on the target.

    Attributes
    ----------
    value : the field's setting, file units.
    range : the reference path's range there, m (within ``AIM_TOLERANCE`` of the target).
    metres_per_unit : d range / d setting, m per file unit (m/deg for angles).
    band : (2,) the settings around ``value`` whose range stays within ``within`` of the
        target (file units), or None when no tolerance was asked for.
    """

    value: float
    range: float
    metres_per_unit: float
    band: tuple[float, float] | None


@dataclass(frozen=True)
class Aim:
    """The result of ``aim``.

    Attributes
    ----------
    field : the field adjusted (``analytic.fields.Field``).
    target : m, at ``target_height`` (m above the base: the design's ``environment.target_height``).
    bounds : (2,) the settings searched, file units.
    within : the tolerance of the bands, m, or None.
    solutions : every setting that lands on the target, in increasing order (empty: out of reach).
    reachable : (2,) the smallest and largest range over the bounds, m (None if nothing throws).
    values : (N,) the scanned settings; ranges : (N,) their ranges (NaN where a shot failed);
    status : (N,) each scanned shot's status (``Status`` value, or ``design_error``).
    """

    field: Field
    target: float
    bounds: tuple[float, float]
    within: float | None
    solutions: tuple[Solution, ...]
    reachable: tuple[float, float] | None
    values: np.ndarray
    ranges: np.ndarray
    status: np.ndarray
    target_height: float = 0.0

    @property
    def reached(self) -> bool:
        return bool(self.solutions)

    def to_json(self) -> dict:
        """The ``aim --json`` object (file units; m)."""
        return {"field": self.field.name, "unit": self.field.unit, "target": self.target,
                "target_height": self.target_height,
                "bounds": list(self.bounds), "within": self.within,
                "solutions": [{"value": s.value, "range": s.range, "metres_per_unit": s.metres_per_unit,
                               "band": None if s.band is None else list(s.band)} for s in self.solutions],
                "reachable": None if self.reachable is None else list(self.reachable)}


def default_bounds(target_field: Field, design: Design) -> tuple[float, float]:
    """Bounds to search when the user gives none, file units.

    The release angle spans the rule's whole range (less a degree at each end);
    a positive quantity spans ``value / DEFAULT_SPREAD`` to ``value * DEFAULT_SPREAD``;
    anything else (the arm's centre of mass, the wind) +-3 x its size or 1 unit.
    """
    value = target_field.check(design)
    if target_field.key == "release_angle":
        limit = 89.0 if design.machine.release_rule == "velocity" else 179.0
        return -limit, limit
    if value > 0.0 and target_field.key not in ("arm_cg", "wind_speed"):
        return value / DEFAULT_SPREAD, value * DEFAULT_SPREAD
    span = 3.0 * max(abs(value), 1.0)
    return value - span, value + span


def check_inputs(target: float, bounds: tuple[float, float], within: float | None) -> None:
    """``DesignError`` naming the bad input: a target that is no positive distance, bounds not
    increasing, a tolerance that is no positive distance."""
    if not (isinstance(target, (int, float)) and math.isfinite(target) and target > 0.0):
        raise DesignError("target", target, "must be a positive distance (m)")
    low, high = bounds
    if not (math.isfinite(low) and math.isfinite(high)):
        raise DesignError("bounds", list(bounds), "must be finite")
    if low > high:
        raise DesignError("bounds", list(bounds), "inverted: the lower bound is above the upper")
    if low == high:
        raise DesignError("bounds", list(bounds), "empty: the lower and upper bound are equal")
    if within is not None and not (math.isfinite(within) and within > 0.0):
        raise DesignError("within", within, "must be a positive distance (m)")


def aim(design: Design, field_name: str, target: float, *, bounds: tuple[float, float] | None = None,
        within: float | None = None, points: int = SCAN_POINTS,
        scanned: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
        check: Callable[[], None] | None = None) -> Aim:
    """The settings of ``field_name`` that land ``design``'s projectile ``target`` metres from the pivot.

    Parameters
    ----------
    design : the design; every other field keeps its value.
    field_name : a numeric design field, dotted (``machine.release_angle``, ``projectile.mass``)
        or a bare machine name (``analytic.fields.field``).
    target : m, > 0.
    bounds : (low, high) settings to search, file units (SI, degrees); default ``default_bounds``.
    within : m; also report the band of settings landing within this of the target.
    points : settings scanned, >= 3.
    scanned : ``(values, ranges, status)`` of an earlier ``scan`` of this design and field over
        ``np.linspace(*bounds, points)``, reused instead of shooting the scan again (a firing
        table aims at many targets from one scan).
    check : called before every shot after the scan; what it raises ends the search there and is
        raised again (the workbench stops a cancelled job so).

    Returns
    -------
    Aim
        Every solution (each re-simulated on the reference path, within ``AIM_TOLERANCE``)
        and the reachable span; no solutions when the target is out of reach.

    Raises
    ------
    DesignError
        for an unknown or non-numeric field, a bad target, bounds or tolerance (named),
        before anything is shot.
    """
    from analytic import fast

    target_field = field(field_name)
    target_field.check(design)
    bounds = default_bounds(target_field, design) if bounds is None else (float(bounds[0]), float(bounds[1]))
    check_inputs(target, bounds, within)
    if points < 3:
        raise ValueError(f"points = {points!r}: need at least 3")

    values = np.linspace(bounds[0], bounds[1], points)
    if scanned is None:
        ranges, status = scan(design, target_field, values)
    else:
        if not np.array_equal(scanned[0], values):
            raise ValueError("scanned: its settings are not np.linspace(*bounds, points)")
        ranges, status = scanned[1], scanned[2]
    ok = np.isfinite(ranges)

    stop = (lambda: None) if check is None else check

    def fast_range(value: float) -> float:
        stop()
        try:
            shot = fast.simulate_fast(target_field.replace(design, value), loads=False)
        except DesignError:
            return math.nan
        return shot.range if shot.ok else math.nan

    reachable = None
    brackets = []
    if ok.any():
        low_v, low_r = _extreme(fast_range, values, ranges, -1.0)
        high_v, high_r = _extreme(fast_range, values, ranges, +1.0)
        reachable = (low_r, high_r)
        brackets = _brackets(values, ranges, target)
        # A peak (or trough) between two scanned settings can hold two crossings the scan misses.
        for extreme_v, extreme_r, sign in ((high_v, high_r, 1.0), (low_v, low_r, -1.0)):
            i = int(np.argmin(np.abs(values - extreme_v)))
            if sign * (extreme_r - target) > 0.0 and all(sign * (ranges[j] - target) < 0.0
                                                         for j in (i - 1, i, i + 1) if 0 <= j < points and ok[j]):
                brackets += [(values[max(i - 1, 0)], extreme_v), (extreme_v, values[min(i + 1, points - 1)])]
    solutions = []
    for a, b in sorted(set(brackets)):
        stop()
        found = _solve(design, target_field, fast_range, a, b, target, bounds, within, values, ranges)
        if found is not None:
            solutions.append(found)
    return Aim(target_field, float(target), bounds, within, tuple(solutions), reachable, values, ranges, status,
               design.environment.target_height)


def scan(design: Design, target_field: Field, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Ranges (N,) (NaN where no throw) and statuses (N,) of ``design`` at each setting, one fast batch."""
    from analytic import fast

    built, status = [], np.full(len(values), "design_error", dtype=object)
    designs = []
    for i, value in enumerate(values):
        try:
            designs.append(target_field.replace(design, float(value)))
            built.append(i)
        except DesignError:
            pass
    ranges = np.full(len(values), math.nan)
    if designs:
        shots = fast.shoot(designs, loads=False)
        ranges[built] = shots.range
        status[built] = shots.status
    return ranges, status.astype(str)


def _brackets(values: np.ndarray, ranges: np.ndarray, target: float) -> list[tuple[float, float]]:
    """Neighbouring scanned settings, both throwing, whose ranges straddle the target."""
    out = []
    for i in range(len(values) - 1):
        a, b = ranges[i] - target, ranges[i + 1] - target
        if math.isfinite(a) and math.isfinite(b) and (a == 0.0 or a * b < 0.0):
            out.append((float(values[i]), float(values[i + 1])))
    if math.isfinite(ranges[-1]) and ranges[-1] == target:
        out.append((float(values[-2]), float(values[-1])))
    return out


def _extreme(fast_range, values, ranges, sign: float) -> tuple[float, float]:
    """The setting and range of the largest (sign +1) or smallest (-1) range, refined between
    the scanned settings beside the best one."""
    scores = np.where(np.isfinite(ranges), sign * ranges, -np.inf)
    i = int(np.argmax(scores))
    best_v, best_r = float(values[i]), float(ranges[i])
    low, high = values[max(i - 1, 0)], values[min(i + 1, len(values) - 1)]
    if high > low:
        found = minimize_scalar(lambda v: -sign * _or(fast_range(v), -sign * NO_THROW), bounds=(low, high),
                                method="bounded", options={"xatol": 1e-9 * (values[-1] - values[0])})
        if abs(found.fun) < NO_THROW and -found.fun > sign * best_r:
            best_v, best_r = float(found.x), -sign * float(found.fun)
    return best_v, best_r


def _or(value: float, instead: float) -> float:
    return instead if math.isnan(value) else value


def _solve(design, target_field, fast_range, a, b, target, bounds, within, values, ranges) -> Solution | None:
    """One crossing: located on the fast path in [a, b], confirmed (and refined) on the reference path."""
    from analytic.reference import simulate

    span = bounds[1] - bounds[0]
    try:
        root = brentq(lambda v: _or(fast_range(v), NO_THROW) - target, a, b, xtol=1e-13 * span,
                      rtol=4 * np.finfo(float).eps)
    except ValueError:   # a failure inside the bracket: no crossing to locate there
        return None
    step = SLOPE_STEP * span
    slope = (fast_range(root + step) - fast_range(root - step)) / (2.0 * step)

    def reference_range(value: float) -> float:
        shot = simulate(target_field.replace(design, value), histories=False, loads=False)
        return shot.range if shot.ok else math.nan

    value, landed = root, reference_range(root)
    for _ in range(MAX_REFERENCE_STEPS):   # the paths agree to ~1e-9: this is a safeguard
        if not math.isfinite(landed) or abs(landed - target) <= AIM_TOLERANCE or slope == 0.0:
            break
        value = float(np.clip(value - (landed - target) / slope, a, b))
        landed = reference_range(value)
    if not (math.isfinite(landed) and abs(landed - target) <= AIM_TOLERANCE):
        return None
    band = None if within is None else _band(fast_range, value, target, within, values, ranges)
    return Solution(value=float(value), range=float(landed), metres_per_unit=float(slope), band=band)


def _band(fast_range, value, target, within, values, ranges) -> tuple[float, float]:
    """The settings around ``value`` whose range stays within ``within`` of ``target``: walked out
    over the scan to the first setting outside, then located between it and the last inside."""
    edges = []
    for direction in (-1, +1):
        inside = value
        order = values[values < value][::-1] if direction < 0 else values[values > value]
        range_of = dict(zip(values.tolist(), ranges.tolist()))
        edge = float(order[-1]) if len(order) else value
        for v in order.tolist():
            r = range_of[v]
            if not math.isfinite(r):          # a failure: the band ends at the last throw
                edge = inside
                break
            if abs(r - target) > within:
                level = target + math.copysign(within, r - target)
                try:
                    edge = brentq(lambda s: _or(fast_range(s), NO_THROW) - level, min(inside, v), max(inside, v),
                                  xtol=1e-12 * abs(values[-1] - values[0]))
                except ValueError:
                    edge = inside
                break
            inside = v
        edges.append(float(edge))
    return edges[0], edges[1]


def format_aim(result: Aim, system: str = "metric") -> str:
    """The result as text for a builder, lengths, masses and speeds in ``system``'s units
    (``analytic.units.display``); angles in degrees."""
    from analytic.units import display

    file_unit = result.field.unit
    scale, unit = display(1.0, file_unit, system)   # shown units per file unit
    per_metre, length = display(1.0, "m", system)

    def metres(value: float) -> str:
        return f"{value * per_metre:.4f} {length}"

    def setting(value: float) -> str:
        return f"{value * scale:.6f}"

    height = (f", {metres(abs(result.target_height))} {'above' if result.target_height > 0.0 else 'below'} the base"
              if result.target_height != 0.0 else "")
    lines = [f"aim {result.field.name} at {metres(result.target)}{height} "
             f"(searched {setting(result.bounds[0])} .. {setting(result.bounds[1])} {unit})"]
    if result.reachable is not None:
        lines.append(f"  reachable: {metres(result.reachable[0])} .. {metres(result.reachable[1])}")
    if not result.solutions:
        lines.append("  out of reach: no setting within the bounds lands on the target"
                     + ("" if result.reachable is not None else " (no setting throws at all)"))
    short = int(np.count_nonzero(result.status == "short_of_target"))
    if short:
        lines.append(f"  {short} of the {len(result.status)} settings scanned fall short of the target's height")
    for i, s in enumerate(result.solutions, 1):
        lines.append(f"  solution {i}: {result.field.key} = {setting(s.value)} {unit}  -> {metres(s.range)} "
                     f"(reference path)")
        lines.append(f"    {s.metres_per_unit * per_metre / scale:+.4f} {length} per {unit}")
        if s.band is not None:
            lines.append(f"    within {metres(result.within)}: {setting(s.band[0])} .. {setting(s.band[1])} {unit}")
    return "\n".join(lines)
