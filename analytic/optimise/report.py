"""Text tables of an optimisation beside the paper's Tables III and IV (cm, deg, m at this edge; in, ft, lb, lbf
with ``units="imperial"``)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from analytic.design import FRICTIONS, SLIDES
from analytic.optimise.constraints import (CONSTRAINT_NAMES, axle_distance, constraint_values,
                                           footprint)
from analytic.design_space import ANGLE_VARIABLES, FRAME_MASS, LOADS, Problem, design_at
from analytic.optimise.robust import Scatter, expected, spread
from analytic.optimise.search import Optimum
from analytic.data.strength import bending_stress, safety_factor
from analytic.units import display as shown_as

if TYPE_CHECKING:
    from analytic.optimise import Optimisation

#: Range of the paper's optimum, m (Corie, Park & Standring, section III and Table III).
PAPER_RANGE = 35.9
#: Column of the paper's Table III design shot under the problem and our model.
PAPER_LABEL = "paper, ours"
#: Column of the paper's published Table III optimum (its numbers, not ours).
PUBLISHED_LABEL = "paper"
#: Column of the design a problem around it started from (``analytic.optimise.around``).
START_LABEL = "start"
#: L_Al:L_As, L_S:L_Al, m_W:m_P "purported optimal" (the paper's Table I).
PURPORTED_RATIOS = (3.75, 1.0, 133.0)
#: The same ratios of the paper's optimum as published (the paper's Table IV).
PAPER_RATIOS = (2.91, 0.87, 143.0)

#: What the report says of a problem under the ideal rule.
IDEAL_NOTE = ("Release rule 'ideal': each design releases at its longest throw, so the release angle is no "
              "variable (dropped from the search; each optimum's shot gives its launch angle, the pin to set "
              "under the velocity rule: python -m analytic simulate optimum.toml)")
#: Rows of the Table III analogue: label, machine attribute or variable, display unit.
_DIMENSIONS = (("L_Al  long arm", "arm_long", "cm"), ("L_As  short arm", "arm_short", "cm"),
               ("L_S   sling", "sling_length", "cm"), ("L_W   weight link", "counterweight_link", "cm"),
               ("h     pivot height", "pivot_height", "cm"), ("      clearance", "clearance", "cm"),
               ("theta0 starting angle", "starting_angle", "deg"),
               ("theta release angle", "release_angle", "deg"))


class Scales(NamedTuple):
    """The report's units in one system: each a (label, shown units per SI unit) pair."""

    short: tuple[str, float]       # a machine's lengths: cm, or in
    distance: tuple[str, float]    # ranges: m, or ft
    force: tuple[str, float]
    acceleration: tuple[str, float]
    mass: tuple[str, float]
    moment: tuple[str, float]      # N m, or ft lbf

    @classmethod
    def of(cls, system: str = "metric") -> Scales:
        """``metric`` (cm, m, N, m/s^2, kg, N m) or ``imperial`` (in, ft, lbf, ft/s^2, lb, ft lbf), through
        ``analytic.units``."""
        def pair(unit: str) -> tuple[str, float]:
            factor, label = shown_as(1.0, unit, system)
            return label, factor

        feet = pair("m")
        short = ("cm", 100.0) if feet[0] == "m" else ("in", 12.0 * feet[1])
        return cls(short, feet, pair("N"), pair("m/s^2"), pair("kg"), pair("N m"))


def display(name: str, value):
    """A design variable's value(s) in the units of tables and plots: cm for lengths, deg for angles,
    kg for the frame's mass."""
    if name == FRAME_MASS:
        return np.asarray(value)
    return np.degrees(value) if name in ANGLE_VARIABLES else 100.0 * np.asarray(value)


def dimensions(problem: Problem, values: np.ndarray) -> dict[str, float]:
    """The design's Table III quantities in cm and deg, keyed as ``_DIMENSIONS`` (the release angle
    NaN under the ideal rule, which has none)."""
    machine = design_at(problem, values).machine
    not_in_machine = {"clearance": values[2], "starting_angle": machine.starting_angle}
    result = {}
    for _, key, unit in _DIMENSIONS:
        value = not_in_machine[key] if key in not_in_machine else getattr(machine, key)
        if value is None:   # the ideal rule's release angle: none, it finds its own release
            result[key] = math.nan
            continue
        result[key] = math.degrees(value) if unit == "deg" else 100.0 * value
    return result


def ratios(problem: Problem, values: np.ndarray) -> tuple[float, float, float]:
    """The paper's Table IV ratios: long:short arm, sling:long arm, counterweight:projectile mass."""
    machine = design_at(problem, values).machine
    return (machine.arm_long / machine.arm_short, machine.sling_length / machine.arm_long,
            machine.counterweight_mass / problem.projectile.mass)


def as_built(problem: Problem, scales: Scales) -> str:
    """The problem's fixed parts of the machine as built, in ``scales``' units: the sling's and the pouch's
    mass, the trough's height, the target's level (where the range is measured); "" for none."""
    (mass, per_kg), (short, per_m_short), (distance, per_m) = scales.mass, scales.short, scales.distance
    parts = [f"{label} {value * per_kg:.3g} {mass}" for label, value in (("sling", problem.sling_mass),
                                                                           ("pouch", problem.pouch_mass)) if value]
    if problem.base.trough_height:
        parts.append(f"trough {problem.base.trough_height * per_m_short:.3g} {short} up")
    target = problem.environment.target_height
    if target:
        parts.append(f"target {abs(target) * per_m:.3g} {distance} {'above' if target > 0.0 else 'below'} the base "
                     "(the range measured there)")
    return "as built: " + ", ".join(parts) if parts else ""


def format_tables(problem: Problem, columns: list[tuple[str, np.ndarray, float]], system: str = "metric") -> str:
    """Tables III and IV side by side for several designs.

    Parameters
    ----------
    columns : (heading, (6,) design variables in m and rad, range in m) per column.
    system : the units shown (``Scales.of``).
    """
    scales = Scales.of(system)
    (short, per_cm), (distance, per_m) = (scales.short[0], scales.short[1] / 100.0), scales.distance
    width = max(16, *(len(c[0]) + 2 for c in columns))
    head = f"{'':<24}" + "".join(f"{c[0]:>{width}}" for c in columns)
    lines = [f"Table III (optimisation results; lengths {short}, angles deg)", head]
    if not problem.losses.ideal:
        losses = problem.losses
        static = [f"{name} {losses.static(name):g}" for name in FRICTIONS
                  if losses.static(name) != getattr(losses, f"{name}_friction")]
        lines.insert(1, f"with losses: axle {losses.axle_friction:g} x {1000 * losses.axle_radius:g} mm, "
                        f"hinge {losses.hinge_friction:g} x {1000 * losses.hinge_radius:g} mm, "
                        f"base {losses.base_friction:g} (Coulomb coefficients x pin radii)"
                        + "".join(f", {slide} {getattr(losses, f'{slide}_friction'):g}" for slide in SLIDES
                                  if losses.static(slide) > 0.0)
                        + (f"; static: {', '.join(static)}" if static else ""))
    built = as_built(problem, scales)
    if built:
        lines.insert(1, built)
    dims = [dimensions(problem, values) for _, values, _ in columns]
    for label, key, unit in _DIMENSIONS:
        if key == "release_angle" and problem.release_rule == "ideal":   # the published optimum's is its own
            lines.append(f"{label:<24}" + "".join(f"{math.degrees(values[5]):>{width}.1f}" if heading == PUBLISHED_LABEL
                                                  else f"{'(ideal)':>{width}}" for heading, values, _ in columns))
            continue
        digits = 1 if unit == "deg" and key == "release_angle" else 2
        scale = 1.0 if unit == "deg" else per_cm
        lines.append(f"{label:<24}" + "".join(f"{d[key] * scale:>{width}.{digits}f}" for d in dims))
    lines.append(f"{f'range ({distance})':<24}" + "".join(f"{r * per_m:>{width}.2f}" for _, _, r in columns))
    lines += ["", "Table IV (ratios)",
              f"{'':<24}{'Table I':>{width}}{'Table IV':>{width}}"
              + "".join(f"{c[0]:>{width}}" for c in columns)]
    all_ratios = [ratios(problem, values) for _, values, _ in columns]
    for k, label in enumerate(("L_Al : L_As", "L_S : L_Al", "m_W : m_P")):
        digits = 0 if k == 2 else 2
        lines.append(f"{label:<24}{PURPORTED_RATIOS[k]:>{width}.{digits}f}{PAPER_RATIOS[k]:>{width}.{digits}f}"
                     + "".join(f"{r[k]:>{width}.{digits}f}" for r in all_ratios))
    return "\n".join(lines)


def format_constraints(problem: Problem, columns: list[tuple[str, np.ndarray, float]],
                       system: str = "metric") -> str:
    """Footprint, height and axle clearance of each design at rest, with the limits (cm, or in)."""
    short, per_m = Scales.of(system).short
    width = max(16, *(len(c[0]) + 2 for c in columns))
    clearance_needed = per_m * (problem.counterweight_radius + problem.axle_radius)
    lines = [f"Constraints at rest ({short}; a negative margin violates)",
             f"{'':<34}{'limit':>10}" + "".join(f"{c[0]:>{width}}" for c in columns)]
    machines = [design_at(problem, values).machine for _, values, _ in columns]
    lines.append(f"{'footprint (horizontal span)':<34}{'<= ' + format(per_m * problem.max_footprint, '.2f'):>10}"
                 + "".join(f"{per_m * footprint(m, problem.base.trough_height):>{width}.2f}" for m in machines))
    lines.append(f"{'height (pivot)':<34}{'<= ' + format(per_m * problem.max_height, '.2f'):>10}"
                 + "".join(f"{per_m * m.pivot_height:>{width}.2f}" for m in machines))
    lines.append(f"{'counterweight link to axle':<34}{'>= ' + format(clearance_needed, '.2f'):>10}"
                 + "".join(f"{per_m * axle_distance(m, problem.base.trough_height):>{width}.2f}" for m in machines))
    margins = [constraint_values(problem, m) for m in machines]
    for j, name in enumerate(CONSTRAINT_NAMES):
        lines.append(f"{'  margin: ' + name:<44}" + "".join(f"{per_m * g[j]:>{width}.3f}" for g in margins))
    return "\n".join(lines)


def format_first_order(optimum: Optimum, system: str = "metric") -> str:
    """Active bounds and constraints with their multipliers, and the stationarity residual."""
    scales = Scales.of(system)
    (short, per_m), (distance, range_per_m), (mass, per_kg) = scales.short, scales.distance, scales.mass
    fo = optimum.first_order
    lines = [("First-order optimality (KKT, finite differences; a multiplier is the range gained per unit"
              " the bound or limit is relaxed)")]
    for name, side in fo.active_bounds.items():
        per, scale = (("deg", math.radians(1.0)) if name in ANGLE_VARIABLES
                      else (mass, 1.0 / per_kg) if name == FRAME_MASS else (short, 1.0 / per_m))
        lines.append(f"  bound {side:<5} {name:<20} multiplier "
                     f"{fo.bound_multipliers[name] * scale * range_per_m:10.4f} {distance} per {per}")
    for name in fo.active_constraints:
        if name in CONSTRAINT_NAMES:
            lines.append(f"  constraint {name:<32} multiplier "
                         f"{fo.constraint_multipliers[name] * range_per_m / per_m:10.4f} {distance} per {short}")
        else:   # an outcome constraint: a relative margin
            lines.append(f"  constraint {name:<32} multiplier {fo.constraint_multipliers[name] * 0.01:10.4f}"
                         f" of the score per 1 % of the limit")
    if not fo.active_bounds and not fo.active_constraints:
        lines.append("  nothing active: an interior maximum")
    lines.append(f"  stationarity residual {fo.residual:.1e} (range still to gain per bound width, relative)")
    if fo.degenerate:
        lines.append("  the active gradients are linearly dependent, so how the multipliers split between"
                     " them is not unique (e.g. the footprint's tip-to-projectile span is the sling length,"
                     " so at a sling bound equal to the footprint limit the two coincide; or a constraint"
                     " set by fixed variables alone)")
    return "\n".join(lines)


def format_search(label: str, optimum: Optimum, system: str = "metric") -> str:
    """Shots, failures by kind, the stages' results and the time taken."""
    distance, per_m = Scales.of(system).distance
    failures = ", ".join(f"{kind} {count}" for kind, count in sorted(optimum.failures.items())) or "none"
    global_stage = ("skipped (started from the optimum)" if math.isnan(optimum.global_score)
                    else f"best {optimum.global_score * per_m:.4f} {distance}")
    lines = [f"Search ({label})",
             f"  shots {optimum.shots}" + (" (each quadrature node one)" if optimum.scatter.nodes > 1 else "")
             + f", failed to throw: {failures}",
             f"  global stage {global_stage}; local stage: {optimum.local_message}",
             (f"  optimum {optimum.score * per_m:.6f} {distance}" if optimum.problem.minimise is None else
              f"  optimum peak {optimum.problem.minimise.replace('_', ' ')} {-optimum.score:.6f}")
             + f" at integrator tolerance {optimum.settings.final_tolerance:g}",
             f"  wall time {optimum.seconds:.1f} s"]
    return "\n".join(lines)


def format_scatter(scatter: Scatter, rows: list[tuple[str, float, np.ndarray]], system: str = "metric") -> str:
    """Each design's nominal range beside its expected range and spread under release-angle scatter.

    Parameters
    ----------
    rows : (label, nominal range in m, (n_nodes,) ranges at the scatter's nodes in m) per design.
    """
    sigma = math.degrees(scatter.sigma)
    unit, per_m = Scales.of(system).distance
    lines = [f"Release-angle scatter: normal, sigma = {sigma:g} deg ({scatter.nodes}-node Gauss-Hermite)",
             f"{'':<24}{f'nominal ({unit})':>14}{f'expected ({unit})':>14}{f'std dev ({unit})':>14}"
             f"{f'loss ({unit})':>12}"]
    for label, nominal, ranges in rows:
        mean, sd = float(expected(scatter, ranges)), float(spread(scatter, ranges))
        lines.append(f"{label:<24}{nominal * per_m:>14.4f}{mean * per_m:>14.4f}{sd * per_m:>14.4f}"
                     f"{(nominal - mean) * per_m:>12.4f}")
    return "\n".join(lines)


def format_peaks(problem: Problem, peaks: dict[str, dict[str, float]], system: str = "metric") -> str:
    """Each design's peak loads through stages 1-2 beside the problem's limits."""
    scales = Scales.of(system)
    labels = list(peaks)
    width = max(16, *(len(label) + 2 for label in labels))
    limits = dict(problem.load_limits)
    lines = ["Peak loads (stages 1-2)" + ("; limits: " + ", ".join(f"{load} {_limit(load, limit, scales)}"
                                                                  for load, limit in problem.load_limits)
                                          if limits else ""),
             f"{'':<34}" + "".join(f"{label:>{width}}" for label in labels)]
    for load, name in LOADS.items():
        unit, scale = _load_scale(load, scales)
        row = "".join(f"{peaks[label][name] * scale:>{width}.2f}" if name in peaks[label] else f"{'-':>{width}}"
                      for label in labels)
        said = "mount load" if load == "hinge_load" and problem.kind != "hinged" else load.replace("_", " ")
        lines.append(f"{'  ' + said + ' (' + unit + ')':<34}{row}")
    lines += _breaking_rows(problem, peaks, width)
    return "\n".join(lines)


def _breaking_rows(problem: Problem, peaks: dict[str, dict[str, float]], width: int) -> list[str]:
    """Each design's arm safety factor (with a rated arm) and whether its projectile survives (with a
    limit), from its peak loads (``analytic.data.strength``)."""
    arm, limit = problem.arm, problem.projectile.acceleration_limit
    lines = []
    if arm.rated:
        factors = {label: safety_factor(bending_stress(loads["peak_arm_bending_moment"], arm.width, arm.depth),
                                        arm.section.bending_strength)
                   for label, loads in peaks.items() if "peak_arm_bending_moment" in loads}
        lines.append(f"{'  arm safety factor':<34}" + "".join(
            f"{factors[label]:>{width}.2f}" if label in factors else f"{'-':>{width}}" for label in peaks))
    if limit is not None:
        verdicts = {label: "survives" if loads["peak_projectile_acceleration"] <= limit else "breaks"
                    for label, loads in peaks.items() if "peak_projectile_acceleration" in loads}
        lines.append(f"{'  projectile':<34}" + "".join(f"{verdicts.get(label, '-'):>{width}}" for label in peaks))
    return lines


def _load_scale(load: str, scales: Scales) -> tuple[str, float]:
    """A load's unit and scale: an acceleration's, a moment's or a force's."""
    return {"projectile_acceleration": scales.acceleration, "arm_bending_moment": scales.moment}.get(load, scales.force)


def _limit(load: str, limit: float, scales: Scales) -> str:
    """A load limit with its unit (``200 N``)."""
    unit, scale = _load_scale(load, scales)
    return f"{limit * scale:g} {unit}"


def format_report(result: Optimisation, system: str = "metric") -> str:
    """The whole report: the problem, Tables III and IV, the limits, each search and its first-order
    check, the release-angle scatter (if any) and the wall time; in ``system``'s units (``Scales.of``)."""
    problem, optima, ranges, scatter = result.problem, result.optima, result.ranges, result.scatter
    if result.compared != PAPER_LABEL:   # the design the search started from
        paper_heading = result.compared
        columns = [(paper_heading, result.paper, ranges[paper_heading])]
    elif problem.kind == "hinged":
        paper_heading = PAPER_LABEL
        columns = [(PUBLISHED_LABEL, result.paper, PAPER_RANGE), (PAPER_LABEL, result.paper, ranges[PAPER_LABEL])]
    else:   # the paper's machine, its counterweight bolted to the arm (``design_space.bolted``)
        paper_heading = f"paper, {problem.kind}"
        columns = [(paper_heading, result.paper, ranges[PAPER_LABEL])]
    columns += [(label, optimum.values, ranges[label]) for label, optimum in optima.items()]
    goal = ("maximise range" if problem.minimise is None else
            f"minimise the peak {problem.minimise.replace('_', ' ')} with a range of at least "
            f"{problem.min_range * Scales.of(system).distance[1]:g} {Scales.of(system).distance[0]}")
    if problem.load_limits:
        goal += "; peak loads at most " + ", ".join(f"{load.replace('_', ' ')} {_limit(load, limit, Scales.of(system))}"
                                                    for load, limit in problem.load_limits)
    if problem.min_arm_safety_factor is not None:
        goal += f"; arm safety factor at least {problem.min_arm_safety_factor:g}"
    sections = [f"Problem {problem.name!r}: {goal}"
                + ("" if scatter is None else f"; robust variant: maximise the expected range when the "
                   f"release angle scatters, sigma {math.degrees(scatter.sigma):g} deg (local stage "
                   f"from the optimum)"),
                (f"Machine: {problem.kind}. Columns: the design the search started from; "
                 if result.compared != PAPER_LABEL else
                 "Columns: the paper's published Table III optimum; the same design under this problem "
                 "and our model; " if problem.kind == "hinged" else
                 f"Machine: {problem.kind}. Columns: the paper's Table III machine with its counterweight "
                 f"bolted to the arm's end (the link's length added to the clearance), under this problem "
                 f"and our model; ") + "; ".join(f"our {label}" for label in optima),
                *([IDEAL_NOTE] if problem.release_rule == "ideal" else []),
                format_tables(problem, columns, system), format_constraints(problem, columns, system),
                format_peaks(problem, {heading: result.peaks[label] for heading, label in
                                       [(paper_heading, result.compared), *((label, label) for label in optima)]},
                             system)]
    for label, optimum in optima.items():
        sections += [format_search(label, optimum, system), format_first_order(optimum, system)]
    if scatter is not None:
        sections.append(format_scatter(scatter, [(label, ranges[label], result.node_ranges[label])
                                                 for label in ranges], system))
    sections.append(f"Total wall time {result.seconds:.1f} s ({result.path} path)")
    return "\n\n".join(sections)
