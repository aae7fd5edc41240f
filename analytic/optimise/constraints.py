"""The size constraints of the optimisation, defined on the machine at rest before firing.

The paper (section II.A) limits "the footprint" and "the overall height" to
61 cm and requires that "the weight did not rest against the axle before
releasing the trebuchet". It does not say what is measured; here:

* **footprint**: the horizontal span, at rest before firing, of the pivot,
  the long-arm tip, the projectile's centre (lying on the base at the end of
  the sling, stretched forward), the short-arm tip and the counterweight's
  centre (hanging plumb below the short-arm tip). Centres, not outlines: the
  paper's Table III optimum spans exactly its 61 cm sling from the long-arm tip
  to the ball's centre, so the paper did not add the ball's radius.
* **height**: the pivot height. The raised short arm stands higher at rest
  (the Table III optimum's short-arm tip is at 79.8 cm) and the arm sweeps
  higher still while swinging, so the paper's 61 cm can only be the frame.
* **axle clearance**: at rest the counterweight hangs plumb from the short-arm
  tip, its link a vertical segment from the tip down to the weight's centre.
  The weight (a sphere of radius ``r_w``) keeps off the axle (a cylinder of
  radius ``r_a`` on the pivot) when that segment stays at least
  ``r_w + r_a`` from the pivot: with the weight's centre below the axle's level
  that is the horizontal offset ``Lb cos(theta0)``, above it the distance to
  the centre. The distance is continuous with a continuous derivative, so a
  gradient-based optimiser can follow it.

Every constraint is a component of a vector ``g`` that is feasible when
``g >= 0`` (m); ``constraint_values`` gives it, ``CONSTRAINT_NAMES`` names it.
"""

from __future__ import annotations

import math

import numpy as np

from analytic.design import Machine
from analytic.design_space import Problem

#: Components of ``constraint_values``. The long-arm tip is always the rearmost
#: point at rest (every other point is at or ahead of the pivot, or, for the
#: projectile, a sling length ahead of the tip), so the footprint is at most
#: the limit exactly when each other point is within the limit of the tip.
CONSTRAINT_NAMES = ("footprint (tip to projectile)", "footprint (tip to pivot)",
                    "footprint (tip to short-arm tip)", "height (pivot)", "axle clearance")

#: A constraint counts as met down to ``g >= -FEASIBILITY_TOLERANCE`` (m): a design
#: exactly at a limit (the paper's 61 cm sling at the 61 cm footprint) computes
#: to within rounding of zero on either side.
FEASIBILITY_TOLERANCE = 1e-9


def feasible(problem: Problem, machine: Machine) -> bool:
    """Whether ``machine`` meets every constraint of ``problem`` (to ``FEASIBILITY_TOLERANCE``), on the
    problem's base (its trough)."""
    return bool(np.all(constraint_values(problem, machine) >= -FEASIBILITY_TOLERANCE))


def rest_points(machine: Machine, trough_height: float = 0.0) -> dict[str, np.ndarray]:
    """Points of the machine at rest before firing, each shape (2,), m from the pivot (x forward, y up).

    The long-arm tip rests behind the pivot on the trough ``trough_height`` (m) above the base (0:
    on the base), the sling lies forward along it, the short arm points up and forward at the arm's
    angle at rest (the starting angle on the base, ``asin((h - trough_height) / arm_long)`` on a
    trough) and the counterweight hangs plumb from its tip.
    """
    theta0 = (machine.starting_angle if trough_height == 0.0
              else math.asin((machine.pivot_height - trough_height) / machine.arm_long))
    tip = np.array([-machine.arm_long * math.cos(theta0), -(machine.pivot_height - trough_height)])
    short_tip = machine.arm_short * np.array([math.cos(theta0), math.sin(theta0)])
    return {"pivot": np.zeros(2),
            "long_tip": tip,
            "projectile": tip + np.array([machine.sling_length, 0.0]),
            "short_tip": short_tip,
            "counterweight": short_tip - np.array([0.0, machine.counterweight_link])}


def footprint(machine: Machine, trough_height: float = 0.0) -> float:
    """Horizontal span of ``rest_points``, m."""
    xs = [point[0] for point in rest_points(machine, trough_height).values()]
    return max(xs) - min(xs)


def axle_distance(machine: Machine, trough_height: float = 0.0) -> float:
    """Closest approach of the counterweight's hanging link (short-arm tip to weight centre) to the pivot, m."""
    points = rest_points(machine, trough_height)
    offset = points["short_tip"][0]
    above = max(points["counterweight"][1], 0.0)  # the link always starts above the axle
    return math.hypot(offset, above)


def constraint_values(problem: Problem, machine: Machine) -> np.ndarray:
    """The constraint vector ``g`` (m), shape (5,), feasible when every component is >= 0.

    Order as ``CONSTRAINT_NAMES``: the limit minus each point's distance ahead of
    the long-arm tip (three components), the height limit minus the pivot height,
    and the axle distance minus ``counterweight radius + axle radius``; at rest on the problem's
    trough (``problem.base.trough_height``).
    """
    trough = problem.base.trough_height
    points = rest_points(machine, trough)
    rear = points["long_tip"][0]
    spans = [points[name][0] - rear for name in ("projectile", "pivot", "short_tip")]
    return np.array([problem.max_footprint - spans[0],
                     problem.max_footprint - spans[1],
                     problem.max_footprint - spans[2],
                     problem.max_height - machine.pivot_height,
                     axle_distance(machine, trough) - problem.counterweight_radius - problem.axle_radius])
