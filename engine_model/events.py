"""Locate an event between fixed steps and interpolate the state there (quadratic, no step shortening).

The engine steps at a fixed ``dt`` (a shortened step upsets pymunk's joint
correction with ``error_bias = 0``), so an event such as lift-off or release is
found after the fact: its value changed sign between the last two samples.
Through the last three samples (equally spaced) a quadratic locates the root
and interpolates every other quantity with an error of O(dt^3), below the
engine's own O(dt^2).
"""

from __future__ import annotations

import math

import numpy as np


def crossing_fraction(values: tuple[float, ...]) -> float:
    """Where in the last interval a sampled value crosses zero, as a fraction in [0, 1].

    Parameters
    ----------
    values : the last two or three samples at equal spacing, oldest first; the
        last two must differ in sign (or the last be zero).

    Returns
    -------
    s such that the crossing is at ``t[-2] + s * (t[-1] - t[-2])``.
    """
    if len(values) < 2:
        raise ValueError("need at least two samples to locate a crossing")
    before, after = values[-2], values[-1]
    linear = before / (before - after) if before != after else 1.0
    if len(values) < 3:
        return min(max(linear, 0.0), 1.0)
    oldest = values[-3]
    # p(s) = before + b s + a s^2 through s = -1, 0, 1.
    b = 0.5 * (after - oldest)
    a = 0.5 * (after - 2.0 * before + oldest)
    if abs(a) <= 1e-12 * (abs(b) + abs(before)):
        return min(max(linear, 0.0), 1.0)
    disc = b * b - 4.0 * a * before
    if disc < 0.0:
        return min(max(linear, 0.0), 1.0)
    root = math.sqrt(disc)
    # The numerically stable pair of roots of a s^2 + b s + before = 0.
    q = -0.5 * (b + math.copysign(root, b))
    candidates = [r for r in ((q / a) if a else math.inf, (before / q) if q else math.inf)
                  if -1e-9 <= r <= 1.0 + 1e-9]
    if not candidates:
        return min(max(linear, 0.0), 1.0)
    return min(max(min(candidates, key=lambda r: abs(r - linear)), 0.0), 1.0)


def interpolate(samples: np.ndarray, fraction: float) -> np.ndarray:
    """Values at ``fraction`` of the way through the last interval of 2 or 3 equally spaced samples.

    Parameters
    ----------
    samples : (2 or 3, ...) samples, oldest first.
    fraction : s in [0, 1] from ``crossing_fraction``.

    Returns
    -------
    (...) the quadratic (or, with two samples, linear) interpolant at s.
    """
    samples = np.asarray(samples, dtype=float)
    s = fraction
    if len(samples) == 2:
        return (1.0 - s) * samples[0] + s * samples[1]
    oldest, before, after = samples[-3], samples[-2], samples[-1]
    # Lagrange weights for the nodes s = -1, 0, 1.
    return (0.5 * s * (s - 1.0)) * oldest + (1.0 - s * s) * before + (0.5 * s * (s + 1.0)) * after


def highest(times: np.ndarray, heights: np.ndarray) -> float:
    """The highest point of a sampled path: the vertex of the parabola through the highest
    sample and its neighbours (any spacing), or the highest sample at either end.

    Parameters
    ----------
    times, heights : (k,) sample instants (s) and heights (m).
    """
    i = int(np.argmax(heights))
    if i == 0 or i == len(heights) - 1:
        return float(heights[i])
    # Newton's form about the middle sample, in times relative to it.
    t0, t2 = times[i - 1] - times[i], times[i + 1] - times[i]
    y0, y1, y2 = heights[i - 1], heights[i], heights[i + 1]
    slope0, slope2 = (y1 - y0) / -t0, (y2 - y1) / t2
    curvature = (slope2 - slope0) / (t2 - t0)
    if not curvature < 0.0:
        return float(y1)
    # y(t) = y1 + slope0 (t) + curvature t (t - t0); its vertex:
    t_top = (curvature * t0 - slope0) / (2.0 * curvature)
    return float(y1 + slope0 * t_top + curvature * t_top * (t_top - t0))
