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

import hashlib
import math
import os
from importlib import metadata
from pathlib import Path

import numpy as np

DRAG_MODELS = ("none", "constant", "smooth-sphere", "golf-ball")
#: Codes of the drag models in the compiled path (their positions in ``DRAG_MODELS``).
NO_DRAG, CONSTANT_DRAG, SMOOTH_SPHERE, GOLF_BALL = range(4)

# Lyu et al. (2018) Fig. 3a, non-spinning 13-ball average (see above).
GOLF_BALL_REYNOLDS = (5.0e4, 7.5e4, 1.0e5, 1.26e5, 1.5e5, 1.75e5, 2.2e5, 2.5e5)
GOLF_BALL_DRAG_COEFFICIENT = (0.477, 0.302, 0.215, 0.205, 0.196, 0.199, 0.199, 0.210)

# --------------------------------------------------------------------------- #
# The curves, written once
# --------------------------------------------------------------------------- #
# Plain math on floats and a table of constants (``DRAG_TABLE``, built below):
# the reference path runs these functions, the compiled path compiles the
# same source and receives the table as an argument, so a cached build can
# never keep an old constant. Layout of the table: the smooth sphere's
# [Oseen end, low end, intermediate end, 6 piece breaks], then the golf
# ball's [Re and Cd at its table's two ends, 8 log10 Re nodes, 7 x 4 cubic
# coefficients, highest power first].
OSEEN_END, LOW_END, INTERMEDIATE_END, SMOOTH_BREAKS = 0, 1, 2, 3
N_SMOOTH_BREAKS = 6
GOLF_RE_MIN, GOLF_RE_MAX, GOLF_CD_LOW, GOLF_CD_HIGH = range(9, 13)
GOLF_NODES = 13
N_GOLF_NODES = len(GOLF_BALL_REYNOLDS)
GOLF_COEFFS = GOLF_NODES + N_GOLF_NODES
N_DRAG_TABLE = GOLF_COEFFS + 4 * (N_GOLF_NODES - 1)


def stokes_ratio(re, table):
    """Cd Re / 24 of a smooth sphere below the intermediate range's end (finite at Re = 0).

    Clift, Grace & Weber Table 5.2: Oseen's 24/Re (1 + 3 Re/16), then the
    low and intermediate correlations.
    """
    if re < table[OSEEN_END]:
        return 1.0 + 3.0 * re / 16.0
    if re < table[LOW_END]:
        return 1.0 + 0.1315 * re ** (0.82 - 0.05 * math.log10(re))
    return 1.0 + 0.1935 * re ** 0.6305


def smooth_sphere_cd_above(re, table):
    """Cd of a smooth sphere from the intermediate range's end on (pieces in w = log10 Re)."""
    i = 0
    while i < N_SMOOTH_BREAKS and table[SMOOTH_BREAKS + i] <= re:
        i += 1
    w = math.log10(re)
    if i == 0:
        return 10.0 ** (1.6435 - 1.1242 * w + 0.1558 * w * w)
    if i == 1:
        return 10.0 ** (-2.4571 + 2.5558 * w - 0.9295 * w * w + 0.1049 * w * w * w)
    if i == 2:
        return 10.0 ** (-1.9181 + 0.6370 * w - 0.0636 * w * w)
    if i == 3:
        return 10.0 ** (-4.3390 + 1.5809 * w - 0.1546 * w * w)
    if i == 4:
        return 29.78 - 5.3 * w
    if i == 5:
        return 0.1 * w - 0.49
    return 0.19 - 8.0e4 / 10.0 ** w


def smooth_sphere_cd(re, table):
    """Cd of a smooth sphere for re > 0."""
    if re < table[INTERMEDIATE_END]:
        return 24.0 / re * stokes_ratio(re, table)
    return smooth_sphere_cd_above(re, table)


def golf_ball_cd(re, table):
    """Cd of a non-spinning golf ball: PCHIP in log10 Re, clamped to the end values outside."""
    if re <= table[GOLF_RE_MIN]:
        return table[GOLF_CD_LOW]
    if re >= table[GOLF_RE_MAX]:
        return table[GOLF_CD_HIGH]
    w = math.log10(re)
    # The last interval also takes a w that rounds onto the last node.
    i = 0
    while i + 2 < N_GOLF_NODES and table[GOLF_NODES + i + 1] <= w:
        i += 1
    k = GOLF_COEFFS + 4 * i
    dw = w - table[GOLF_NODES + i]
    return ((table[k] * dw + table[k + 1]) * dw + table[k + 2]) * dw + table[k + 3]


def force_factor(model, speed, diameter, air_density, air_viscosity, constant, table):
    """``Cd(Re) |v|`` of drag model code ``model`` (``NO_DRAG`` ...): finite as the speed goes to 0.

    For the smooth sphere the Stokes term is ``24 mu / (rho d)`` times the
    Stokes ratio rather than ``24/Re |v|``, so at zero speed the factor is
    finite and the force ``3 pi mu d v`` goes to zero linearly.
    """
    if model == NO_DRAG or air_density == 0.0:
        return 0.0
    if model == CONSTANT_DRAG:
        return constant * speed
    re = air_density * speed * diameter / air_viscosity
    if model == GOLF_BALL:
        return golf_ball_cd(re, table) * speed
    if re < table[INTERMEDIATE_END]:
        return 24.0 * air_viscosity / (air_density * diameter) * stokes_ratio(re, table)
    return smooth_sphere_cd_above(re, table) * speed


def drag_rate(model, vx_rel, vy, diameter, air_density, air_viscosity, constant, area, mass, table):
    """``k`` in the projectile's drag acceleration ``-k v_rel``, 1/s: ``rho A Cd(Re) |v_rel| / (2 m)``.

    ``(vx_rel, vy)`` is the velocity relative to the air, m/s; ``area`` the drag area
    (m^2) and ``mass`` the projectile's (kg); the rest as ``force_factor``. ``1 / k`` is
    the time in which drag alone would stop the projectile. Both models' flights use it.
    """
    # Not math.hypot: CPython's own algorithm and the C library's (which
    # compiled code calls) may differ in the last bit; sqrt is correctly rounded in both.
    speed = math.sqrt(vx_rel * vx_rel + vy * vy)
    return air_density * area / (2.0 * mass) * force_factor(model, speed, diameter, air_density, air_viscosity,
                                                            constant, table)


# --------------------------------------------------------------------------- #
# The table of constants
# --------------------------------------------------------------------------- #
_TABLE_BREAKS = (1.5e3, 1.2e4, 4.4e4, 3.38e5, 4.0e5, 1.0e6)   # tabulated breaks between pieces


def _crossing(left, right, nominal: float) -> float:
    """Re near ``nominal`` (within 10 %) where two neighbouring pieces give the same Cd."""
    w0 = math.log10(nominal)
    if left(w0) == right(w0):
        return nominal
    from scipy.optimize import brentq

    return 10.0 ** brentq(lambda w: left(w) - right(w), w0 - 0.04, w0 + 0.04, xtol=1e-13)


def _build_table() -> np.ndarray:
    from scipy.interpolate import PchipInterpolator

    table = np.zeros(N_DRAG_TABLE)
    table[OSEEN_END], table[LOW_END] = 0.01, 20.0
    table[INTERMEDIATE_END] = math.inf
    # Each piece as a function of w, evaluated by the curve itself away from every break.
    def piece(i):
        return lambda w: _piece_cd(i, w)
    table[INTERMEDIATE_END] = _crossing(lambda w: 24.0 / 10.0 ** w * stokes_ratio(10.0 ** w, table),
                                        piece(0), 260.0)
    for i, nominal in enumerate(_TABLE_BREAKS):
        table[SMOOTH_BREAKS + i] = _crossing(piece(i), piece(i + 1), nominal)
    log_re = np.log10(GOLF_BALL_REYNOLDS)
    pchip = PchipInterpolator(log_re, np.array(GOLF_BALL_DRAG_COEFFICIENT))
    table[GOLF_RE_MIN], table[GOLF_RE_MAX] = GOLF_BALL_REYNOLDS[0], GOLF_BALL_REYNOLDS[-1]
    table[GOLF_CD_LOW], table[GOLF_CD_HIGH] = GOLF_BALL_DRAG_COEFFICIENT[0], GOLF_BALL_DRAG_COEFFICIENT[-1]
    table[GOLF_NODES:GOLF_COEFFS] = [math.log10(r) for r in GOLF_BALL_REYNOLDS]
    table[GOLF_COEFFS:] = np.ravel(pchip.c.T)
    return table


def _piece_cd(i: int, w: float) -> float:
    """Piece ``i`` of ``smooth_sphere_cd_above`` at w, whatever the breaks: the table whose
    breaks put every Re in piece ``i`` (all breaks at 0 up to it, infinite after it)."""
    selector = np.zeros(N_DRAG_TABLE)
    selector[SMOOTH_BREAKS:SMOOTH_BREAKS + N_SMOOTH_BREAKS] = [0.0 if j < i else math.inf
                                                             for j in range(N_SMOOTH_BREAKS)]
    return smooth_sphere_cd_above(10.0 ** w, selector)


def _table_cache() -> Path:
    """Where the built table is kept: beside this module's bytecode, named by what it is built
    from (this file's bytes, and the scipy and numpy that build it)."""
    key = hashlib.sha256(Path(__file__).read_bytes())
    for package in ("scipy", "numpy"):
        key.update(metadata.version(package).encode())
    return Path(__file__).parent / "__pycache__" / f"drag_table-{key.hexdigest()[:16]}.npy"


def _load_table() -> np.ndarray:
    """``_build_table()``, from its cache file if there is a sound one (the same doubles).

    Building it imports scipy's interpolation and root finding: 0.6-1.8 s of
    every command's start-up (here, on a 2-core machine), most of the frames'
    and the engine's whole import, which need nothing else of scipy's. The
    cache is a data file, written (atomically) whether or not Python writes
    its bytecode, as numba's is; one that cannot be read or written is
    rebuilt, silently.
    """
    cache = _table_cache()
    try:
        table = np.load(cache, allow_pickle=False)
        if table.shape == (N_DRAG_TABLE,) and table.dtype == np.float64:
            return table
    except (OSError, ValueError, EOFError):
        pass
    table = _build_table()
    partial = cache.with_name(f"{cache.name}.{os.getpid()}.partial")
    try:
        cache.parent.mkdir(exist_ok=True)
        with open(partial, "wb") as file:
            np.save(file, table, allow_pickle=False)
        os.replace(partial, cache)
    except OSError:
        try:
            partial.unlink(missing_ok=True)
        except OSError:   # under a file, say: there is nothing to remove
            pass
    return table


#: The drag curves' constants (``N_DRAG_TABLE``,), in the layout above.
DRAG_TABLE = _load_table()
DRAG_TABLE.flags.writeable = False


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
        return golf_ball_cd(reynolds, DRAG_TABLE)
    if reynolds == 0.0:
        return math.inf
    return smooth_sphere_cd(reynolds, DRAG_TABLE)


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
    reynolds_number(speed, projectile_diameter, air_density, air_viscosity)   # validates the inputs
    return force_factor(DRAG_MODELS.index(model), speed, projectile_diameter, air_density, air_viscosity,
                        math.nan if constant is None else constant, DRAG_TABLE)
