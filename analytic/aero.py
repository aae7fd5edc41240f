"""Drag on a sphere: the drag models and their drag coefficient against Reynolds number."""

# Sources
# -------
# "smooth-sphere": R. Clift, J. R. Grace & M. E. Weber, "Bubbles, Drops, and
#   Particles", Academic Press, New York, 1978, Table 5.2 (p. 112): the
#   recommended piecewise correlations of the standard drag curve, w = log10 Re,
#   from the Oseen limit to past the drag crisis. The coefficients below agree
#   with several independent public transcriptions of that table. Two changes,
#   both ours. (1) Each break between pieces above Re = 20 is moved to where the
#   neighbouring pieces actually cross (all within 2 % of the tabulated break),
#   so Cd has no jump there; at the tabulated 4e5 break it would jump by 21 %.
#   The breaks at Re = 0.01 and 20 stay, with jumps of 0.003 % and 0.8 % (inside
#   the table's accuracy), as those pieces do not cross nearby. (2) The first
#   row is transcribed as Cd = 3/16 + 24/Re; we use Oseen's 24/Re (1 + 3 Re/16)
#   = 24/Re + 9/2, which it evidently means: that joins the next row to 0.003 %
#   at Re = 0.01, where 3/16 + 24/Re would leave a 0.2 % jump.
#   Not chosen: F. A. Morrison's correlation ("An Introduction to Fluid
#   Mechanics", Cambridge University Press, 2013; Eq. 1 of her note "Data
#   Correlation for Drag Coefficient for Sphere", Michigan Tech, 2016), which
#   lies 13-16 % below this curve for 3e4 < Re < 2e5, the trebuchet's range.
#
# "golf-ball": B. Lyu, J. Kensrud, L. Smith & T. Tosaya, "Aerodynamics of Golf
#   Balls in Still Air", Proceedings 2(6), 238 (2018), doi:10.3390/
#   proceedings2060238, section 3.1.1 and Fig. 3a: the average over 13 production
#   balls fired without spin through still air, 18-91 m/s. The text states
#   Cd ~ 0.5 at Re = 5e4 and ~ 0.2 at Re = 1e5; the abstract, that the ball
#   models differ by more than 0.1 in Cd below Re = 1e5 and by less than 0.05
#   above. The table values are NOT our own reading: Fig. 3a is a raster image
#   we could not view; the numbers are a third party's visual digitisation of it
#   (in a public repository's research notes, quoting +-0.01 in Cd and +-3 % in
#   Re), checked here only against the two values the text states. Trust them
#   to about +-0.02 as an average; a particular ball can differ by 0.1 in the
#   crisis. The seed paper's own source (its ref. [10]) is not known to us.
#
# Outside the golf-ball table we clamp to its end values: below Re = 5e4 (about
# 17 m/s for a 42.67 mm ball in sea-level air) Cd stays 0.477, close to the
# subcritical value 0.49 at Re = 4.3e4 of J. Li's LES of a non-spinning golf
# ball (PhD thesis, Hokkaido University, 2016, section 3.1); above 2.5e5 (about
# 87 m/s) it stays 0.21. The smooth-sphere curve needs no clamp: it is defined
# for every Re > 0, tends to the Oseen law as Re -> 0 and stays below 0.19
# beyond Re = 1e6.

from __future__ import annotations

import bisect
import math

import numpy as np
from scipy.interpolate import PchipInterpolator
from scipy.optimize import brentq

DRAG_MODELS = ("none", "constant", "smooth-sphere", "golf-ball")

# Lyu et al. (2018) Fig. 3a, non-spinning 13-ball average (see above).
GOLF_BALL_REYNOLDS = (5.0e4, 7.5e4, 1.0e5, 1.26e5, 1.5e5, 1.75e5, 2.2e5, 2.5e5)
GOLF_BALL_DRAG_COEFFICIENT = (0.477, 0.302, 0.215, 0.205, 0.196, 0.199, 0.199, 0.210)


# --------------------------------------------------------------------------- #
# Smooth sphere: Clift, Grace & Weber (1978), Table 5.2
# --------------------------------------------------------------------------- #
# The first three pieces are written as Cd Re / 24, which is finite at Re = 0,
# so that the drag force factor Cd |v| = (24 mu / rho d) (Cd Re / 24) needs no
# division by the speed.

def _stokes_ratio_oseen(re: float) -> float:
    return 1.0 + 3.0 * re / 16.0                 # Oseen: Cd = 24/Re + 9/2


def _stokes_ratio_low(re: float) -> float:
    return 1.0 + 0.1315 * re ** (0.82 - 0.05 * math.log10(re))


def _stokes_ratio_intermediate(re: float) -> float:
    return 1.0 + 0.1935 * re ** 0.6305


# The remaining pieces give Cd itself as a function of w = log10 Re.
_CD_PIECES = (
    lambda w: 10.0 ** (1.6435 - 1.1242 * w + 0.1558 * w * w),
    lambda w: 10.0 ** (-2.4571 + 2.5558 * w - 0.9295 * w * w + 0.1049 * w * w * w),
    lambda w: 10.0 ** (-1.9181 + 0.6370 * w - 0.0636 * w * w),
    lambda w: 10.0 ** (-4.3390 + 1.5809 * w - 0.1546 * w * w),
    lambda w: 29.78 - 5.3 * w,
    lambda w: 0.1 * w - 0.49,
    lambda w: 0.19 - 8.0e4 / 10.0 ** w,
)
_TABLE_BREAKS = (1.5e3, 1.2e4, 4.4e4, 3.38e5, 4.0e5, 1.0e6)   # between the pieces above

_OSEEN_END = 0.01
_LOW_END = 20.0


def _crossing(left, right, nominal: float) -> float:
    """Re near ``nominal`` (within 10 %) where two neighbouring pieces give the same Cd."""
    w0 = math.log10(nominal)
    if left(w0) == right(w0):
        return nominal
    return 10.0 ** brentq(lambda w: left(w) - right(w), w0 - 0.04, w0 + 0.04, xtol=1e-13)


_INTERMEDIATE_END = _crossing(lambda w: 24.0 / 10.0 ** w * _stokes_ratio_intermediate(10.0 ** w),
                              _CD_PIECES[0], 260.0)
_CD_BREAKS = tuple(_crossing(_CD_PIECES[i], _CD_PIECES[i + 1], b) for i, b in enumerate(_TABLE_BREAKS))


def _smooth_sphere_stokes_ratio(re: float) -> float:
    """Cd Re / 24 for 0 <= re < _INTERMEDIATE_END (finite at re = 0)."""
    if re < _OSEEN_END:
        return _stokes_ratio_oseen(re)
    if re < _LOW_END:
        return _stokes_ratio_low(re)
    return _stokes_ratio_intermediate(re)


def _smooth_sphere_cd(re: float) -> float:
    """Cd of a smooth sphere for re > 0."""
    if re < _INTERMEDIATE_END:
        return 24.0 / re * _smooth_sphere_stokes_ratio(re)
    w = math.log10(re)
    return _CD_PIECES[bisect.bisect_right(_CD_BREAKS, re)](w)


# --------------------------------------------------------------------------- #
# Golf ball: shape-preserving cubic (PCHIP) in log10 Re through the table
# --------------------------------------------------------------------------- #
# scipy builds the interpolant once; calling it costs ~4 us per scalar, and this
# runs in every flight right-hand side, so its breakpoints and cubic
# coefficients are copied into plain floats and evaluated by hand (same
# numbers, ~0.2 us; a whole drag_force_factor call measures ~0.8 us).

_GOLF_LOG_RE = tuple(math.log10(r) for r in GOLF_BALL_REYNOLDS)
_golf_pchip = PchipInterpolator(np.array(_GOLF_LOG_RE), np.array(GOLF_BALL_DRAG_COEFFICIENT))
_GOLF_COEFFS = tuple(tuple(float(c) for c in _golf_pchip.c[:, i]) for i in range(len(_GOLF_LOG_RE) - 1))
_GOLF_RE_MIN, _GOLF_RE_MAX = GOLF_BALL_REYNOLDS[0], GOLF_BALL_REYNOLDS[-1]
_GOLF_CD_MIN_RE, _GOLF_CD_MAX_RE = GOLF_BALL_DRAG_COEFFICIENT[0], GOLF_BALL_DRAG_COEFFICIENT[-1]
del _golf_pchip


def _golf_ball_cd(re: float) -> float:
    """Cd of a non-spinning golf ball, clamped to the table's end values outside it."""
    if re <= _GOLF_RE_MIN:
        return _GOLF_CD_MIN_RE
    if re >= _GOLF_RE_MAX:
        return _GOLF_CD_MAX_RE
    w = math.log10(re)
    # min(): log10 may round a Re just below the last node onto it.
    i = min(bisect.bisect_right(_GOLF_LOG_RE, w) - 1, len(_GOLF_COEFFS) - 1)
    c3, c2, c1, c0 = _GOLF_COEFFS[i]
    dw = w - _GOLF_LOG_RE[i]
    return ((c3 * dw + c2) * dw + c1) * dw + c0


# --------------------------------------------------------------------------- #
# Public interface
# --------------------------------------------------------------------------- #

def _require(name: str, value: float, *, positive: bool) -> None:
    # `not (value > 0)` also rejects NaN, which every comparison fails.
    ok = (value > 0.0) if positive else (value >= 0.0)
    if not ok or value == math.inf:
        kind = "positive" if positive else "non-negative"
        raise ValueError(f"{name} must be a finite {kind} number, got {value!r}")


def _check_model(model: str, constant: float | None) -> None:
    if model not in DRAG_MODELS:
        raise ValueError(f"drag model must be one of {', '.join(DRAG_MODELS)}, got {model!r}")
    if model == "constant":
        if constant is None:
            raise ValueError('constant: a drag coefficient is required with drag model "constant", got None')
        _require("constant", constant, positive=False)
    elif constant is not None:
        raise ValueError(f'constant: only used with drag model "constant", not {model!r}; got {constant!r}')


def reynolds_number(speed: float, diameter: float, air_density: float, air_viscosity: float) -> float:
    """Reynolds number of a sphere moving through air.

    Parameters
    ----------
    speed : float
        Speed relative to the air, m/s (>= 0).
    diameter : float
        Sphere diameter, m (> 0).
    air_density : float
        Air density, kg/m^3 (>= 0).
    air_viscosity : float
        Dynamic viscosity of the air, Pa s (> 0).

    Returns
    -------
    float
        ``Re = rho |v| d / mu``.

    Raises
    ------
    ValueError
        If an argument is negative, NaN or infinite, or diameter or viscosity is zero.
    """
    _require("speed", speed, positive=False)
    _require("diameter", diameter, positive=True)
    _require("air_density", air_density, positive=False)
    _require("air_viscosity", air_viscosity, positive=True)
    return air_density * speed * diameter / air_viscosity


def drag_coefficient(model: str, reynolds: float, constant: float | None = None) -> float:
    """Drag coefficient of the projectile under ``model`` at Reynolds number ``reynolds``.

    Parameters
    ----------
    model : str
        One of `DRAG_MODELS`: ``"none"`` (Cd = 0), ``"constant"`` (Cd = ``constant``),
        ``"smooth-sphere"`` (Clift, Grace & Weber 1978, Table 5.2) or ``"golf-ball"``
        (non-spinning golf ball, Lyu et al. 2018, Fig. 3a, PCHIP in log10 Re,
        clamped to 0.477 below Re = 5e4 and to 0.21 above Re = 2.5e5).
    reynolds : float
        Reynolds number, finite and >= 0.
    constant : float or None
        The drag coefficient for ``"constant"`` (required there, >= 0); must be
        None for the other models.

    Returns
    -------
    float
        The drag coefficient. For ``"smooth-sphere"`` at ``reynolds == 0`` this is
        ``math.inf`` (the Stokes limit 24/Re); use `drag_force_factor` in the
        dynamics, which stays finite there.

    Raises
    ------
    ValueError
        For an unknown model, a negative, NaN or infinite Reynolds number, or a
        missing, invalid or superfluous ``constant``.
    """
    _check_model(model, constant)
    _require("reynolds", reynolds, positive=False)
    if model == "none":
        return 0.0
    if model == "constant":
        return float(constant)
    if model == "golf-ball":
        return _golf_ball_cd(reynolds)
    if reynolds == 0.0:
        return math.inf
    return _smooth_sphere_cd(reynolds)


def drag_force_factor(model: str, speed: float, projectile_diameter: float, air_density: float,
                      air_viscosity: float, constant: float | None) -> float:
    """``Cd(Re) |v|``, the drag factor that stays finite as the speed goes to zero.

    The drag acceleration is ``-(rho A / 2 m) * factor * v_rel``, with ``v_rel``
    the velocity relative to the air and ``A = pi d^2 / 4``. For the smooth
    sphere the Stokes term is evaluated as ``24 mu / (rho d)`` instead of
    ``24/Re * |v|``, so at zero speed the factor is that finite constant and the
    force ``3 pi mu d v`` goes to zero linearly; for the other models it goes to
    zero with the speed.

    Parameters
    ----------
    model : str
        One of `DRAG_MODELS` (see `drag_coefficient`).
    speed : float
        Speed relative to the air ``|v_rel|``, m/s (>= 0).
    projectile_diameter : float
        Sphere diameter, m (> 0).
    air_density : float
        Air density, kg/m^3 (>= 0). At 0 (vacuum) the factor is 0: there is no air
        and the continuum correlations do not apply.
    air_viscosity : float
        Dynamic viscosity of the air, Pa s (> 0).
    constant : float or None
        The drag coefficient for ``"constant"``; None for the other models.

    Returns
    -------
    float
        ``Cd(Re) * speed`` in m/s, finite and >= 0.

    Raises
    ------
    ValueError
        For an unknown model, an invalid argument or a missing or superfluous ``constant``.
    """
    _check_model(model, constant)
    re = reynolds_number(speed, projectile_diameter, air_density, air_viscosity)
    if model == "none" or air_density == 0.0:
        return 0.0
    if model == "constant":
        return constant * speed
    if model == "golf-ball":
        return _golf_ball_cd(re) * speed
    if re < _INTERMEDIATE_END:
        return 24.0 * air_viscosity / (air_density * projectile_diameter) * _smooth_sphere_stokes_ratio(re)
    return _smooth_sphere_cd(re) * speed
