"""Where the machine's parts are and how fast they move, and the release rule: written once.

Scalar functions of the coordinates (theta, phi, psi) and their rates in the
conventions of ``analytic.design`` and ``docs/derivation.md``: the reference
path runs them as they are, the compiled path compiles the same source
(``analytic.fast.compiled``), and the engine model and the plots use them too (they
hold no dynamics, so the engine may import this module).

``machine_points`` is the array form for plots and rendering.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

#: Release rules, in the order of their codes in the compiled path.
RELEASE_RULES = ("velocity", "sling", "ideal")
VELOCITY_RULE, SLING_RULE, IDEAL_RULE = 0, 1, 2


def projectile_state(theta: float, psi: float, dtheta: float, dpsi: float,
                     arm_long: float, sling_length: float) -> tuple[float, float, float, float]:
    """Projectile centre ``(x, y)`` (m) and velocity ``(vx, vy)`` (m/s) from the pivot (eqs. 2.3, 5.1)."""
    beta, dbeta = theta + psi, dtheta + dpsi
    return (-arm_long * math.sin(theta) - sling_length * math.sin(beta),
            arm_long * math.cos(theta) + sling_length * math.cos(beta),
            -arm_long * dtheta * math.cos(theta) - sling_length * dbeta * math.cos(beta),
            -arm_long * dtheta * math.sin(theta) - sling_length * dbeta * math.sin(beta))


def part_positions(theta: float, phi: float, psi: float, arm_long: float, arm_short: float,
                   arm_cg: float, counterweight_link: float, sling_length: float) -> tuple[float, ...]:
    """Positions from the pivot, m: long tip, short tip, arm centre, counterweight, projectile.

    Returns ten floats, ``(x, y)`` of each in that order.
    """
    ax, ay = -math.sin(theta), math.cos(theta)          # unit vector pivot -> long tip
    wx, wy = math.sin(theta + phi), -math.cos(theta + phi)  # hinge -> counterweight centre
    sx, sy = -math.sin(theta + psi), math.cos(theta + psi)  # long tip -> projectile
    long_x, long_y = arm_long * ax, arm_long * ay
    short_x, short_y = -arm_short * ax, -arm_short * ay
    return (long_x, long_y, short_x, short_y, arm_cg * ax, arm_cg * ay,
            short_x + counterweight_link * wx, short_y + counterweight_link * wy,
            long_x + sling_length * sx, long_y + sling_length * sy)


def arm_long_side(arm_long: float, arm_short: float, arm_mass: float, arm_cg: float) -> tuple[float, float, float]:
    """The arm's long side, from the axle to the long tip, as a uniform rod (``docs/derivation.md`` eq. 9.4).

    The arm is taken as two uniform rods meeting at the axle, the long side's
    mass ``m_L`` and the short side's chosen so that together they have the
    arm's mass and centre of mass: ``m_L La / 2 - (mA - m_L) Lb / 2 = mA d``,
    ``m_L = mA (2 d + Lb) / (La + Lb)``. An arm whose centre lies beyond the
    middle of a side (``d > La / 2`` or ``d < -Lb / 2``) cannot be so split; its
    long side then takes all the mass or none (the share clipped to [0, 1]).

    Returns ``(mass, first_moment, second_moment)`` about the axle: kg,
    ``m_L La / 2`` kg m, ``m_L La^2 / 3`` kg m^2.
    """
    share = min(max((2.0 * arm_cg + arm_short) / (arm_long + arm_short), 0.0), 1.0)
    mass = arm_mass * share
    return mass, 0.5 * mass * arm_long, mass * arm_long * arm_long / 3.0


#: Names of the pairs ``part_positions`` returns, in order.
PARTS = ("long_tip", "short_tip", "arm_centre", "counterweight", "projectile")


def machine_points(q: np.ndarray, machine) -> dict[str, np.ndarray]:
    """``part_positions`` over a history: each part's position, m from the pivot.

    Parameters
    ----------
    q : (3,) or (n, 3) coordinates [theta, phi, psi], rad.
    machine : an ``analytic.design.Machine``.

    Returns
    -------
    dict of part name (``PARTS``, plus ``pivot``) to (2,) or (n, 2) positions.
    """
    q = np.asarray(q, dtype=float)
    rows = np.array([part_positions(theta, phi, psi, machine.arm_long, machine.arm_short, machine.arm_cg,
                                    machine.counterweight_link, machine.sling_length)
                     for theta, phi, psi in q.reshape(-1, 3)]).reshape(*q.shape[:-1], len(PARTS), 2)
    points = {name: rows[..., i, :] for i, name in enumerate(PARTS)}
    points["pivot"] = np.zeros_like(points["long_tip"])
    return points


def sling_arm_angle(ax: float, ay: float, sx: float, sy: float) -> float:
    """Sling-to-arm angle, rad in (-pi, pi]: clockwise from the long arm (unit vector
    ``(ax, ay)``, pivot to tip) to the sling (``(sx, sy)``, tip to projectile).

    Zero with the sling straight in line with the arm; negative while the sling
    trails the clockwise-swinging arm (it starts at ``starting_angle - pi``),
    positive once it has whipped ahead. In the coordinates it is ``-psi``
    wrapped to (-pi, pi].
    """
    return -math.atan2(ax * sy - ay * sx, ax * sx + ay * sy)


class Release(NamedTuple):
    """The release rule as an event (``release_value``): release when ``value`` rises through zero
    while ``armed``."""

    value: float
    armed: bool


def release_value(rule: int, release_angle: float, ax: float, ay: float, sx: float, sy: float,
                  vx: float, vy: float) -> Release:
    """The release rule as an event: ``Release(value, armed)``; release when ``value`` rises
    through zero while ``armed``.

    * ``VELOCITY_RULE``: ``value = |v| sin(alpha - angle(v))``, smooth in the
      state. The velocity direction sweeps clockwise through the swing, so it
      rises through zero when the direction passes the release angle alpha
      clockwise, and also when it passes ``alpha + 180 deg`` anticlockwise;
      ``armed`` (a positive velocity component along alpha) rejects the latter.
    * ``SLING_RULE``: ``value = sin(gamma - alpha)`` with gamma the
      ``sling_arm_angle`` of the arm ``(ax, ay)`` and sling ``(sx, sy)`` unit
      vectors, rising as the sling whips ahead; ``armed`` is ``cos(gamma - alpha) > 0``.
    """
    if rule == VELOCITY_RULE:
        along = math.cos(release_angle) * vx + math.sin(release_angle) * vy
        return Release(math.sin(release_angle) * vx - math.cos(release_angle) * vy, along > 0.0)
    gamma = sling_arm_angle(ax, ay, sx, sy)
    return Release(math.sin(gamma - release_angle), math.cos(gamma - release_angle) > 0.0)


def ideal_release(arm_angle: float, theta: float, dtheta: float) -> Release:
    """The ideal rule's release as an event (``docs/derivation.md``, the release section):
    ``value = max(arm_angle - theta, theta')`` rises through zero when the arm, swinging
    forward (theta falling), passes ``arm_angle``, or when it stops (theta' rising through
    zero), whichever comes first; always armed.

    ``analytic.ideal`` chooses ``arm_angle``: ``-inf`` for the search pass, which runs
    the free swing to the arm's stop, then the arm angle of the best candidate.
    """
    return Release(max(arm_angle - theta, dtheta), True)


def release_at(rule: int, release_angle: float, theta: float, psi: float, vx: float,
               vy: float) -> Release:
    """``release_value`` at coordinates: arm angle theta, sling angle psi (rad), projectile velocity (m/s)."""
    beta = theta + psi
    return release_value(rule, release_angle, -math.sin(theta), math.cos(theta),
                         -math.sin(beta), math.cos(beta), vx, vy)
