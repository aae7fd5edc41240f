"""The distributions a sweep draws from: uniform and (optionally truncated) normal, by inverse CDF.

A sample is drawn as unit numbers in [0, 1) (pseudo-random or Sobol') and
mapped through each distribution's inverse CDF (``ppf``), so that every
method of drawing serves every distribution, and the extremes a sampler can
produce are known in advance (``support``): what the sweep's up-front
validity check of its designs relies on.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import ndtr, ndtri

#: Unit numbers are clipped to [UNIT_EPS, 1 - UNIT_EPS] before the inverse CDF:
#: 0 can be drawn (k / 2^53 with k = 0) and maps a normal to -inf. 2^-53 is
#: the gap below 1 in double precision, so the clip is symmetric; a normal
#: reaches 8.2 sd at it.
UNIT_EPS = 2.0**-53
#: Smallest probability a truncated normal's window may hold: below it the
#: inverse CDF has no digits left to resolve the window.
MIN_WINDOW_PROBABILITY = 1e-9


@dataclass(frozen=True)
class Uniform:
    """Uniform on [low, high]; values in the field's file unit."""

    low: float
    high: float

    def ppf(self, unit: np.ndarray) -> np.ndarray:
        """Values for unit numbers ``unit`` (shape (m,)), shape (m,)."""
        return self.low + np.asarray(unit, dtype=float) * (self.high - self.low)

    @property
    def support(self) -> tuple[float, float]:
        """The smallest and largest values the sampler can produce."""
        return self.low, self.high

    def describe(self) -> dict:
        return {"distribution": "uniform", "from": self.low, "to": self.high}


@dataclass(frozen=True)
class Normal:
    """Normal with ``mean`` and standard deviation ``sd``, truncated to [low, high] if given."""

    mean: float
    sd: float
    low: float | None = None
    high: float | None = None

    def _window(self) -> tuple[float, float]:
        """The CDF at the truncation limits (0 and 1 without them)."""
        below = 0.0 if self.low is None else float(ndtr((self.low - self.mean) / self.sd))
        above = 1.0 if self.high is None else float(ndtr((self.high - self.mean) / self.sd))
        return below, above

    @property
    def window_probability(self) -> float:
        below, above = self._window()
        return above - below

    def ppf(self, unit: np.ndarray) -> np.ndarray:
        """Values for unit numbers ``unit`` (shape (m,)), shape (m,)."""
        below, above = self._window()
        probability = below + np.clip(np.asarray(unit, dtype=float), UNIT_EPS, 1.0 - UNIT_EPS) * (above - below)
        values = self.mean + self.sd * ndtri(np.clip(probability, UNIT_EPS, 1.0 - UNIT_EPS))
        # Round-off in the CDF can step a hair outside the window: keep inside it.
        return np.clip(values, -math.inf if self.low is None else self.low,
                       math.inf if self.high is None else self.high)

    @property
    def support(self) -> tuple[float, float]:
        """The smallest and largest values the sampler can produce."""
        extremes = self.ppf(np.array([0.0, 1.0]))
        return float(extremes[0]), float(extremes[1])

    def describe(self) -> dict:
        described = {"distribution": "normal", "mean": self.mean, "sd": self.sd}
        if self.low is not None:
            described["from"] = self.low
        if self.high is not None:
            described["to"] = self.high
        return described


Distribution = Uniform | Normal
