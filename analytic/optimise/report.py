"""Text tables of an optimisation beside the paper's Tables III and IV (cm, deg, m at this edge)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from analytic.design import FRICTIONS
from analytic.optimise.constraints import (CONSTRAINT_NAMES, axle_distance, constraint_values,
                                           footprint)
from analytic.design_space import ANGLE_VARIABLES, FRAME_MASS, LOADS, Problem, design_at
from analytic.optimise.robust import Scatter, expected, spread
from analytic.optimise.search import Optimum

if TYPE_CHECKING:
    from analytic.optimise import Optimisation

#: Range of the paper's optimum, m (Corie, Park & Standring, section III and Table III).
PAPER_RANGE = 35.9
#: Column of the paper's Table III design shot under the problem and our model.
PAPER_LABEL = "paper, ours"
#: L_Al:L_As, L_S:L_Al, m_W:m_P "purported optimal" (the paper's Table I).
PURPORTED_RATIOS = (3.75, 1.0, 133.0)
#: The same ratios of the paper's optimum as published (the paper's Table IV).
PAPER_RATIOS = (2.91, 0.87, 143.0)

#: Rows of the Table III analogue: label, machine attribute or variable, display unit.
_DIMENSIONS = (("L_Al  long arm", "arm_long", "cm"), ("L_As  short arm", "arm_short", "cm"),
               ("L_S   sling", "sling_length", "cm"), ("L_W   weight link", "counterweight_link", "cm"),
               ("h     pivot height", "pivot_height", "cm"), ("      clearance", "clearance", "cm"),
               ("theta0 starting angle", "starting_angle", "deg"),
               ("theta release angle", "release_angle", "deg"))


def display(name: str, value):
    """A design variable's value(s) in the units of tables and plots: cm for lengths, deg for angles,
    kg for the frame's mass."""
    if name == FRAME_MASS:
        return np.asarray(value)
    return np.degrees(value) if name in ANGLE_VARIABLES else 100.0 * np.asarray(value)


def dimensions(problem: Problem, values: np.ndarray) -> dict[str, float]:
    """The design's Table III quantities in cm and deg, keyed as ``_DIMENSIONS``."""
    machine = design_at(problem, values).machine
    not_in_machine = {"clearance": values[2], "starting_angle": machine.starting_angle}
    result = {}
    for _, key, unit in _DIMENSIONS:
        value = not_in_machine[key] if key in not_in_machine else getattr(machine, key)
        result[key] = math.degrees(value) if unit == "deg" else 100.0 * value
    return result


def ratios(problem: Problem, values: np.ndarray) -> tuple[float, float, float]:
    """The paper's Table IV ratios: long:short arm, sling:long arm, counterweight:projectile mass."""
    machine = design_at(problem, values).machine
    return (machine.arm_long / machine.arm_short, machine.sling_length / machine.arm_long,
            machine.counterweight_mass / problem.projectile.mass)


def format_tables(problem: Problem, columns: list[tuple[str, np.ndarray, float]]) -> str:
    """Tables III and IV side by side for several designs.

    Parameters
    ----------
    columns : (heading, (6,) design variables in m and rad, range in m) per column.
    """
    width = 16
    head = f"{'':<24}" + "".join(f"{c[0]:>{width}}" for c in columns)
    lines = ["Table III (optimisation results; lengths cm, angles deg)", head]
    if not problem.losses.ideal:
        losses = problem.losses
        static = [f"{name} {losses.static(name):g}" for name in FRICTIONS
                  if losses.static(name) != getattr(losses, f"{name}_friction")]
        lines.insert(1, f"with losses: axle {losses.axle_friction:g} x {1000 * losses.axle_radius:g} mm, "
                        f"hinge {losses.hinge_friction:g} x {1000 * losses.hinge_radius:g} mm, "
                        f"base {losses.base_friction:g} (Coulomb coefficients x pin radii)"
                        + (f"; static: {', '.join(static)}" if static else ""))
    dims = [dimensions(problem, values) for _, values, _ in columns]
    for label, key, unit in _DIMENSIONS:
        digits = 1 if unit == "deg" and key == "release_angle" else 2
        lines.append(f"{label:<24}" + "".join(f"{d[key]:>{width}.{digits}f}" for d in dims))
    lines.append(f"{'range (m)':<24}" + "".join(f"{r:>{width}.2f}" for _, _, r in columns))
    lines += ["", "Table IV (ratios)",
              f"{'':<24}{'Table I':>{width}}{'Table IV':>{width}}"
              + "".join(f"{c[0]:>{width}}" for c in columns)]
    all_ratios = [ratios(problem, values) for _, values, _ in columns]
    for k, label in enumerate(("L_Al : L_As", "L_S : L_Al", "m_W : m_P")):
        digits = 0 if k == 2 else 2
        lines.append(f"{label:<24}{PURPORTED_RATIOS[k]:>{width}.{digits}f}{PAPER_RATIOS[k]:>{width}.{digits}f}"
                     + "".join(f"{r[k]:>{width}.{digits}f}" for r in all_ratios))
    return "\n".join(lines)


def format_constraints(problem: Problem, columns: list[tuple[str, np.ndarray, float]]) -> str:
    """Footprint, height and axle clearance of each design at rest, with the limits (cm)."""
    width = 16
    clearance_needed = 100.0 * (problem.counterweight_radius + problem.axle_radius)
    lines = ["Constraints at rest (cm; a negative margin violates)",
             f"{'':<34}{'limit':>10}" + "".join(f"{c[0]:>{width}}" for c in columns)]
    machines = [design_at(problem, values).machine for _, values, _ in columns]
    lines.append(f"{'footprint (horizontal span)':<34}{'<= ' + format(100 * problem.max_footprint, '.2f'):>10}"
                 + "".join(f"{100 * footprint(m):>{width}.2f}" for m in machines))
    lines.append(f"{'height (pivot)':<34}{'<= ' + format(100 * problem.max_height, '.2f'):>10}"
                 + "".join(f"{100 * m.pivot_height:>{width}.2f}" for m in machines))
    lines.append(f"{'counterweight link to axle':<34}{'>= ' + format(clearance_needed, '.2f'):>10}"
                 + "".join(f"{100 * axle_distance(m):>{width}.2f}" for m in machines))
    margins = [constraint_values(problem, m) for m in machines]
    for j, name in enumerate(CONSTRAINT_NAMES):
        lines.append(f"{'  margin: ' + name:<44}" + "".join(f"{100 * g[j]:>{width}.3f}" for g in margins))
    return "\n".join(lines)


def format_first_order(optimum: Optimum) -> str:
    """Active bounds and constraints with their multipliers, and the stationarity residual."""
    fo = optimum.first_order
    lines = [("First-order optimality (KKT, finite differences; a multiplier is the range gained per unit"
              " the bound or limit is relaxed)")]
    for name, side in fo.active_bounds.items():
        per, scale = (("deg", math.radians(1.0)) if name in ANGLE_VARIABLES
                      else ("kg", 1.0) if name == FRAME_MASS else ("cm", 0.01))
        lines.append(f"  bound {side:<5} {name:<20} multiplier {fo.bound_multipliers[name] * scale:10.4f} m per {per}")
    for name in fo.active_constraints:
        if name in CONSTRAINT_NAMES:
            lines.append(f"  constraint {name:<32} multiplier {fo.constraint_multipliers[name] * 0.01:10.4f} m per cm")
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


def format_search(label: str, optimum: Optimum) -> str:
    """Shots, failures by kind, the stages' results and the time taken."""
    failures = ", ".join(f"{kind} {count}" for kind, count in sorted(optimum.failures.items())) or "none"
    global_stage = ("skipped (started from the optimum)" if math.isnan(optimum.global_score)
                    else f"best {optimum.global_score:.4f} m")
    lines = [f"Search ({label})",
             f"  shots {optimum.shots}" + (" (each quadrature node one)" if optimum.scatter.nodes > 1 else "")
             + f", failed to throw: {failures}",
             f"  global stage {global_stage}; local stage: {optimum.local_message}",
             (f"  optimum {optimum.score:.6f} m" if optimum.problem.minimise is None else
              f"  optimum peak {optimum.problem.minimise.replace('_', ' ')} {-optimum.score:.6f}")
             + f" at integrator tolerance {optimum.settings.final_tolerance:g}",
             f"  wall time {optimum.seconds:.1f} s"]
    return "\n".join(lines)


def format_scatter(scatter: Scatter, rows: list[tuple[str, float, np.ndarray]]) -> str:
    """Each design's nominal range beside its expected range and spread under release-angle scatter.

    Parameters
    ----------
    rows : (label, nominal range in m, (n_nodes,) ranges at the scatter's nodes in m) per design.
    """
    sigma = math.degrees(scatter.sigma)
    lines = [f"Release-angle scatter: normal, sigma = {sigma:g} deg ({scatter.nodes}-node Gauss-Hermite)",
             f"{'':<24}{'nominal (m)':>14}{'expected (m)':>14}{'std dev (m)':>14}{'loss (m)':>12}"]
    for label, nominal, ranges in rows:
        mean, sd = float(expected(scatter, ranges)), float(spread(scatter, ranges))
        lines.append(f"{label:<24}{nominal:>14.4f}{mean:>14.4f}{sd:>14.4f}{nominal - mean:>12.4f}")
    return "\n".join(lines)


def format_peaks(problem: Problem, peaks: dict[str, dict[str, float]]) -> str:
    """Each design's peak loads through stages 1-2 beside the problem's limits."""
    labels = list(peaks)
    width = max(16, *(len(label) + 2 for label in labels))
    limits = dict(problem.load_limits)
    lines = ["Peak loads (stages 1-2)" + ("; limits: " + ", ".join(f"{load} {limit:g}" for load, limit in
                                                                  problem.load_limits) if limits else ""),
             f"{'':<34}" + "".join(f"{label:>{width}}" for label in labels)]
    for load, name in LOADS.items():
        unit = "m/s^2" if load == "projectile_acceleration" else "N"
        row = "".join(f"{peaks[label][name]:>{width}.2f}" if name in peaks[label] else f"{'-':>{width}}"
                      for label in labels)
        lines.append(f"{'  ' + load.replace('_', ' ') + ' (' + unit + ')':<34}{row}")
    return "\n".join(lines)


def format_report(result: Optimisation) -> str:
    """The whole report: the problem, Tables III and IV, the limits, each search and its first-order
    check, the release-angle scatter (if any) and the wall time."""
    problem, optima, ranges, scatter = result.problem, result.optima, result.ranges, result.scatter
    columns = [("paper", result.paper, PAPER_RANGE), (PAPER_LABEL, result.paper, ranges[PAPER_LABEL])]
    columns += [(label, optimum.values, ranges[label]) for label, optimum in optima.items()]
    goal = ("maximise range" if problem.minimise is None else
            f"minimise the peak {problem.minimise.replace('_', ' ')} with a range of at least {problem.min_range:g} m")
    if problem.load_limits:
        goal += "; peak loads at most " + ", ".join(f"{load.replace('_', ' ')} {limit:g}"
                                                    for load, limit in problem.load_limits)
    sections = [f"Problem {problem.name!r}: {goal}"
                + ("" if scatter is None else f"; robust variant: maximise the expected range when the "
                   f"release angle scatters, sigma {math.degrees(scatter.sigma):g} deg (local stage "
                   f"from the optimum)"),
                "Columns: the paper's published Table III optimum; the same design under this problem "
                "and our model; " + "; ".join(f"our {label}" for label in optima),
                format_tables(problem, columns), format_constraints(problem, columns),
                format_peaks(problem, {label: result.peaks[label] for label in [PAPER_LABEL, *optima]})]
    for label, optimum in optima.items():
        sections += [format_search(label, optimum), format_first_order(optimum)]
    if scatter is not None:
        sections.append(format_scatter(scatter, [(label, ranges[label], result.node_ranges[label])
                                                 for label in ranges]))
    sections.append(f"Total wall time {result.seconds:.1f} s ({result.path} path)")
    return "\n\n".join(sections)
