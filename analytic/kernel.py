"""The compiled shot: all three stages, their events and every drag model, in numba.

Two kinds of function live here.

* The equations, written once for both paths: ``terms`` (the entries of M and
  f, ``docs/derivation.md`` [3]) and ``slide_constraint`` (the base
  constraint's psi and its rates [4]). The reference path (``analytic.eom``)
  runs their Python source (``.py_func``) under CPython; this module runs the
  same source compiled. ``tests/test_analytic_fast.py`` checks both against
  each other, and every other function here against its reference
  counterpart, at random states.
* The machinery of a whole shot: the right-hand sides, the events, an
  embedded Dormand-Prince 8(5,3) pair with its 7th-order dense output (the
  algorithm of ``scipy.integrate.DOP853``, whose published coefficient arrays
  it is handed at run time), Brent's root finder on the dense output, and the
  three stages, for one design (``shot``) or an array of them on every core
  (``shots``).

Everything is compiled with ``cache=True``: the first call in a fresh checkout
compiles (seconds) and writes the machine code to ``__pycache__``; later
processes load it from there. numba's cache is keyed on this file only, so
every number that comes from elsewhere (the DOP853 coefficients, the drag
tables) is passed in as an argument rather than read as a global, where a
stale cache could keep an old value.

Inputs and outputs are flat float64 arrays laid out by the index constants
below; ``analytic.fast`` packs designs into them and reads results out.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit, prange

# error_model="numpy": a division by zero gives inf/nan (a rejected step)
# instead of raising, as in NumPy; no fastmath, so IEEE arithmetic is kept
# and the compiled equations round exactly as the Python ones do.
_JIT = dict(cache=True, nogil=True, error_model="numpy")


class Params(NamedTuple):
    """The design's numbers in the symbols of ``analytic.eom`` (SI)."""

    La: float
    Lb: float
    d: float
    mA: float
    IA: float
    mW: float
    Lw: float
    IW: float
    Ls: float
    mP: float
    h: float
    g: float


# --------------------------------------------------------------------------- #
# Layout of a design row (``analytic.fast.pack``)
# --------------------------------------------------------------------------- #
# 0-11: Params in order, then:
ALPHA, RULE, DRAG, CD, DIAMETER, RHO, MU, WIND, AREA, T_LIMIT, THETA0, PHI0, PSI0 = range(12, 25)
N_DESIGN = 25
RULE_VELOCITY, RULE_SLING = 0, 1
DRAG_NONE, DRAG_CONSTANT, DRAG_SMOOTH, DRAG_GOLF = 0, 1, 2, 3

# Layout of the drag table (``analytic.fast.drag_table``): smooth sphere
# [Oseen end, low end, intermediate end, 6 piece breaks], then the golf ball
# [Re and Cd at the table's two ends, 8 log10 Re nodes, 7 x 4 cubic
# coefficients (highest power first)].
_OSEEN_END, _LOW_END, _INTERMEDIATE_END, _SMOOTH_BREAKS = 0, 1, 2, 3
_N_SMOOTH_BREAKS = 6
_GOLF_RE_MIN, _GOLF_RE_MAX, _GOLF_CD_LOW, _GOLF_CD_HIGH = range(9, 13)
_GOLF_NODES = 13
_N_GOLF_NODES = 8
_GOLF_COEFFS = _GOLF_NODES + _N_GOLF_NODES
N_DRAG_TABLE = _GOLF_COEFFS + 4 * (_N_GOLF_NODES - 1)

# Layout of a result row.
(STATUS, DETAIL, LIFTOFF_T, RELEASE_T, RELEASE_X, RELEASE_Y, RELEASE_VX, RELEASE_VY,
 LANDING_T, LANDING_X, APEX, END_T, VALUE, STEPS, EVALS) = range(15)
N_RESULT = 15
# STATUS codes (``analytic.fast`` maps them to ``Status`` and errors).
OK, NEVER_FIRES, NEVER_LIFTS_OFF, HITS_BASE, NEVER_RELEASES, STEP_FAILED, NO_LANDING = range(7)
# DETAIL of NEVER_LIFTS_OFF: which stage-1 event (or the time limit) ended it.
UNDER_TIP, ARM_BACK, TIME_LIMIT = 1, 2, 3

# Stages, as in ``analytic.result.Stage``.
SLIDE, SWING, FLIGHT = 1, 2, 3

#: Stage 1 ends as never_lifts_off at this |sin beta| (``analytic.simulate``).
SLING_VERTICAL_LIMIT = 1e-2
#: Event roots are located to this absolute time tolerance, s (``analytic.integrate``).
ROOT_TIME_TOLERANCE = 1e-14
_EPS = np.finfo(np.float64).eps

# DOP853 step-size control (Hairer, Norsett & Wanner, "Solving Ordinary
# Differential Equations I", 2nd ed., II.4 and II.10; the values scipy uses).
_SAFETY, _MIN_FACTOR, _MAX_FACTOR = 0.9, 0.2, 10.0
_ERROR_ORDER = 7
_N_STAGES = 12


# --------------------------------------------------------------------------- #
# The equations (shared with the reference path)
# --------------------------------------------------------------------------- #

@njit(inline='always', **_JIT)
def terms(theta, phi, psi, dtheta, dphi, dpsi, p):
    """Entries of M (M23 = 0) and f, eqs. (3.3)-(3.4): the one place they are written.

    Returns ``(m11, m12, m13, m22, m33, f1, f2, f3)``.
    """
    s_phi, c_phi = math.sin(phi), math.cos(phi)
    s_psi, c_psi = math.sin(psi), math.cos(psi)
    s_th, c_th = math.sin(theta), math.cos(theta)
    s_w = s_th * c_phi + c_th * s_phi   # sin(theta + phi): five sines and cosines, not seven
    s_b = s_th * c_psi + c_th * s_psi   # sin(theta + psi) = sin(beta)
    m12 = p.IW + p.mW * (p.Lw * p.Lw + p.Lb * p.Lw * c_phi)
    m13 = p.mP * (p.Ls * p.Ls + p.La * p.Ls * c_psi)
    m22 = p.IW + p.mW * p.Lw * p.Lw
    m33 = p.mP * p.Ls * p.Ls
    m11 = (p.IA + p.mA * p.d * p.d + p.IW
           + p.mW * (p.Lb * p.Lb + p.Lw * p.Lw + 2.0 * p.Lb * p.Lw * c_phi)
           + p.mP * (p.La * p.La + p.Ls * p.Ls + 2.0 * p.La * p.Ls * c_psi))
    f1 = (p.g * (p.mA * p.d * s_th - p.mW * (p.Lb * s_th + p.Lw * s_w)
                 + p.mP * (p.La * s_th + p.Ls * s_b))
          + p.mW * p.Lb * p.Lw * s_phi * dphi * (2.0 * dtheta + dphi)
          + p.mP * p.La * p.Ls * s_psi * dpsi * (2.0 * dtheta + dpsi))
    f2 = -p.mW * p.Lw * (p.g * s_w + p.Lb * s_phi * dtheta * dtheta)
    f3 = p.mP * p.Ls * (p.g * s_b - p.La * s_psi * dtheta * dtheta)
    return m11, m12, m13, m22, m33, f1, f2, f3


@njit(inline='always', **_JIT)
def slide_constraint(theta, dtheta, p):
    """psi and its rates from the base constraint ``La cos(theta) + Ls cos(beta) = -h``, eqs. (4.1)-(4.2).

    Returns ``(psi, psi', s, c, sin beta)`` with ``psi' = s theta'`` and
    ``psi'' = s theta'' + c``; all NaN where the long-arm tip is higher above
    the base than the sling is long (out of reach).
    """
    cos_beta = -(p.h + p.La * math.cos(theta)) / p.Ls
    if abs(cos_beta) > 1.0 + 1e-12:
        return math.nan, math.nan, math.nan, math.nan, math.nan
    # Clamp only round-off, so that acos is defined at the reach's very edge.
    beta = -math.acos(min(1.0, max(-1.0, cos_beta)))
    sin_beta = math.sin(beta)
    s = -(p.La * math.sin(theta) + p.Ls * sin_beta) / (p.Ls * sin_beta)
    dpsi = s * dtheta
    dbeta = dtheta + dpsi
    c = -(p.La * math.cos(theta) * dtheta * dtheta + p.Ls * cos_beta * dbeta * dbeta) / (p.Ls * sin_beta)
    return beta - theta, dpsi, s, c, sin_beta


# --------------------------------------------------------------------------- #
# Accelerations, kinematics, release and drag (reference: eom, design, aero)
# --------------------------------------------------------------------------- #

@njit(**_JIT)
def params(P):
    """The ``Params`` of a design row."""
    return Params(P[0], P[1], P[2], P[3], P[4], P[5], P[6], P[7], P[8], P[9], P[10], P[11])


@njit(inline='always', **_JIT)
def swing_accelerations(theta, phi, psi, dtheta, dphi, dpsi, p):
    """Stage 2: M q'' = f by block elimination (M23 = 0), as ``eom.swing_accelerations``."""
    m11, m12, m13, m22, m33, f1, f2, f3 = terms(theta, phi, psi, dtheta, dphi, dpsi, p)
    ddtheta = (f1 - m12 * f2 / m22 - m13 * f3 / m33) / (m11 - m12 * m12 / m22 - m13 * m13 / m33)
    return ddtheta, (f2 - m12 * ddtheta) / m22, (f3 - m13 * ddtheta) / m33


@njit(inline='always', **_JIT)
def slide_accelerations(theta, phi, dtheta, dphi, p):
    """Stage 1: theta'', phi'' and the base's normal force, as ``eom.slide_accelerations``."""
    psi, dpsi, s, c, sin_beta = slide_constraint(theta, dtheta, p)
    m11, m12, m13, m22, m33, f1, f2, f3 = terms(theta, phi, psi, dtheta, dphi, dpsi, p)
    a = m11 + 2.0 * s * m13 + s * s * m33
    r1 = f1 + s * f3 - (m13 + s * m33) * c
    det = a * m22 - m12 * m12
    ddtheta = (r1 * m22 - f2 * m12) / det
    ddphi = (f2 * a - r1 * m12) / det
    ddpsi = s * ddtheta + c
    normal = (m13 * ddtheta + m33 * ddpsi - f3) / (-p.Ls * sin_beta)
    return ddtheta, ddphi, normal


@njit(**_JIT)
def projectile_state(theta, psi, dtheta, dpsi, p):
    """Projectile (x, y, vx, vy) from the pivot, as ``eom.projectile_state``."""
    beta, dbeta = theta + psi, dtheta + dpsi
    return (-p.La * math.sin(theta) - p.Ls * math.sin(beta),
            p.La * math.cos(theta) + p.Ls * math.cos(beta),
            -p.La * dtheta * math.cos(theta) - p.Ls * dbeta * math.cos(beta),
            -p.La * dtheta * math.sin(theta) - p.Ls * dbeta * math.sin(beta))


@njit(**_JIT)
def release_value(rule, alpha, theta, psi, vx, vy):
    """The release event ``(value, armed)``, as ``design.release_function``."""
    if rule == RULE_VELOCITY:
        along = math.cos(alpha) * vx + math.sin(alpha) * vy
        return math.sin(alpha) * vx - math.cos(alpha) * vy, along > 0.0
    ax, ay = -math.sin(theta), math.cos(theta)
    beta = theta + psi
    sx, sy = -math.sin(beta), math.cos(beta)
    gamma = -math.atan2(ax * sy - ay * sx, ax * sx + ay * sy)
    return math.sin(gamma - alpha), math.cos(gamma - alpha) > 0.0


@njit(**_JIT)
def _smooth_sphere_stokes_ratio(re, table):
    """Cd Re / 24 below the intermediate range's end (``aero._smooth_sphere_stokes_ratio``)."""
    if re < table[_OSEEN_END]:
        return 1.0 + 3.0 * re / 16.0
    if re < table[_LOW_END]:
        return 1.0 + 0.1315 * re ** (0.82 - 0.05 * math.log10(re))
    return 1.0 + 0.1935 * re ** 0.6305


@njit(**_JIT)
def _smooth_sphere_cd(re, table):
    """Cd of a smooth sphere above the intermediate range (``aero._CD_PIECES``)."""
    i = 0
    while i < _N_SMOOTH_BREAKS and table[_SMOOTH_BREAKS + i] <= re:
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


@njit(**_JIT)
def _golf_ball_cd(re, table):
    """Cd of a non-spinning golf ball, clamped outside its table (``aero._golf_ball_cd``)."""
    if re <= table[_GOLF_RE_MIN]:
        return table[_GOLF_CD_LOW]
    if re >= table[_GOLF_RE_MAX]:
        return table[_GOLF_CD_HIGH]
    w = math.log10(re)
    # The last interval also takes a w that rounds onto the last node.
    i = 0
    while i + 2 < _N_GOLF_NODES and table[_GOLF_NODES + i + 1] <= w:
        i += 1
    k = _GOLF_COEFFS + 4 * i
    dw = w - table[_GOLF_NODES + i]
    return ((table[k] * dw + table[k + 1]) * dw + table[k + 2]) * dw + table[k + 3]


@njit(**_JIT)
def drag_force_factor(speed, P, table):
    """``Cd(Re) |v|`` for the design's drag model, as ``aero.drag_force_factor``."""
    model = int(P[DRAG])
    rho = P[RHO]
    if model == DRAG_NONE or rho == 0.0:
        return 0.0
    if model == DRAG_CONSTANT:
        return P[CD] * speed
    re = rho * speed * P[DIAMETER] / P[MU]
    if model == DRAG_GOLF:
        return _golf_ball_cd(re, table) * speed
    if re < table[_INTERMEDIATE_END]:
        return 24.0 * P[MU] / (rho * P[DIAMETER]) * _smooth_sphere_stokes_ratio(re, table)
    return _smooth_sphere_cd(re, table) * speed


# --------------------------------------------------------------------------- #
# Right-hand sides and events of the three stages
# --------------------------------------------------------------------------- #

@njit(inline='always', **_JIT)
def rhs(stage, y, p, P, table, out):
    """Write the state derivative of ``stage`` at ``y`` into ``out``.

    Stage 1: y = [theta, phi, theta', phi'] (NaN past the sling's reach, so
    the step is rejected); stage 2: y = [theta, phi, psi, theta', phi', psi'];
    flight: y = [x, y, vx, vy] with quadratic drag on the air-relative velocity.
    """
    if stage == SLIDE:
        ddtheta, ddphi, _ = slide_accelerations(y[0], y[1], y[2], y[3], p)
        out[0], out[1], out[2], out[3] = y[2], y[3], ddtheta, ddphi
    elif stage == SWING:
        a, b, c = swing_accelerations(y[0], y[1], y[2], y[3], y[4], y[5], p)
        out[0], out[1], out[2], out[3], out[4], out[5] = y[3], y[4], y[5], a, b, c
    else:
        vx_rel = y[2] - P[WIND]
        vy = y[3]
        speed = math.hypot(vx_rel, vy)
        k = P[RHO] * P[AREA] / (2.0 * p.mP) * drag_force_factor(speed, P, table)
        out[0], out[1], out[2], out[3] = y[2], vy, -k * vx_rel, -p.g - k * vy


@njit(**_JIT)
def n_events(stage):
    return 3 if stage == SLIDE else 2


@njit(**_JIT)
def event_value(stage, k, y, p, P):
    """Value of event ``k`` of ``stage`` at ``y`` (the order and meaning of ``analytic.simulate``'s).

    Stage 1: under_tip (|sin beta| - limit), liftoff (normal force), arm_back
    (tip height). Stage 2: release, hits_base (projectile height). Flight:
    landing (height above the base), apex (vertical velocity).
    """
    if stage == SLIDE:
        cos_beta = -(p.h + p.La * math.cos(y[0])) / p.Ls
        off_vertical = math.sqrt(max(0.0, 1.0 - cos_beta * cos_beta)) - SLING_VERTICAL_LIMIT
        if k == 0:
            return off_vertical
        if k == 1:
            if off_vertical <= 0.0:
                return 1.0
            return slide_accelerations(y[0], y[1], y[2], y[3], p)[2]
        return p.La * math.cos(y[0]) + p.h
    if stage == SWING:
        if k == 0:
            _, _, vx, vy = projectile_state(y[0], y[2], y[3], y[5], p)
            return release_value(int(P[RULE]), P[ALPHA], y[0], y[2], vx, vy)[0]
        return p.La * math.cos(y[0]) + p.Ls * math.cos(y[0] + y[2]) + p.h
    if k == 0:
        return y[1] + p.h
    return y[3]


@njit(**_JIT)
def event_direction(stage, k):
    return 1 if (stage == SWING and k == 0) else -1


@njit(**_JIT)
def event_terminal(stage, k):
    return not (stage == FLIGHT and k == 1)


@njit(**_JIT)
def event_armed(stage, k, y, p, P):
    if stage == SWING and k == 0:
        _, _, vx, vy = projectile_state(y[0], y[2], y[3], y[5], p)
        return release_value(int(P[RULE]), P[ALPHA], y[0], y[2], vx, vy)[1]
    return True


# --------------------------------------------------------------------------- #
# DOP853 with dense output, events located by Brent's method
# --------------------------------------------------------------------------- #
# ``coef`` is ``(A, B, C, E3, E5, D, A_EXTRA, C_EXTRA)``, scipy's DOP853 class
# arrays: stages 0-11 of the 8th-order step, the 5th- and 3rd-order error
# estimators, and the dense output's three extra stages and its 4 x 16 matrix.

@njit(**_JIT)
def _rk_step(stage, t, y, f, h, coef, K, y_new, f_new, tmp, p, P, table):
    """One DOP853 step of size h from (t, y) with y'(t) = f; fills K[0:13]."""
    A, B = coef[0], coef[1]
    n = y.shape[0]
    K[0, :n] = f
    for s in range(1, _N_STAGES):
        for j in range(n):
            acc = 0.0
            for q in range(s):
                acc += K[q, j] * A[s, q]
            tmp[j] = y[j] + acc * h
        rhs(stage, tmp, p, P, table, K[s])
    for j in range(n):
        acc = 0.0
        for q in range(_N_STAGES):
            acc += K[q, j] * B[q]
        y_new[j] = y[j] + h * acc
    rhs(stage, y_new, p, P, table, f_new)
    K[_N_STAGES, :n] = f_new


@njit(**_JIT)
def _error_norm(h, y, y_new, K, coef, rtol, atol):
    """DOP853's blended 5th/3rd-order error estimate, scaled by the tolerances (< 1: accept)."""
    E3, E5 = coef[3], coef[4]
    n = y.shape[0]
    err5, err3 = 0.0, 0.0
    for j in range(n):
        scale = atol + max(abs(y[j]), abs(y_new[j])) * rtol
        e5, e3 = 0.0, 0.0
        for q in range(_N_STAGES + 1):
            e5 += K[q, j] * E5[q]
            e3 += K[q, j] * E3[q]
        err5 += (e5 / scale) ** 2
        err3 += (e3 / scale) ** 2
    if err5 == 0.0 and err3 == 0.0:
        return 0.0
    return abs(h) * err5 / math.sqrt((err5 + 0.01 * err3) * n)


@njit(**_JIT)
def _rms(x, scale):
    total = 0.0
    for j in range(x.shape[0]):
        total += (x[j] / scale[j]) ** 2
    return math.sqrt(total / x.shape[0])


@njit(**_JIT)
def _initial_step(stage, t0, y0, f0, t_bound, rtol, atol, p, P, table):
    """Starting step: Hairer, Norsett & Wanner (1993), II.4, as in scipy's ``select_initial_step``."""
    interval = abs(t_bound - t0)
    if interval == 0.0:
        return 0.0
    n = y0.shape[0]
    scale = atol + np.abs(y0) * rtol
    d0, d1 = _rms(y0, scale), _rms(f0, scale)
    h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    h0 = min(h0, interval)
    y1 = y0 + h0 * f0
    f1 = np.empty(n)
    rhs(stage, y1, p, P, table, f1)
    d2 = _rms(f1 - f0, scale) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / (_ERROR_ORDER + 1))
    return min(100.0 * h0, h1, interval)


@njit(**_JIT)
def _dense_prepare(stage, t_old, h, y_old, y_new, f_new, coef, K, F, tmp, p, P, table):
    """The step's 7th-order interpolant: three more stages into K, then F (7, n)."""
    D, AX = coef[5], coef[6]
    n = y_old.shape[0]
    for e in range(3):
        s = _N_STAGES + 1 + e
        for j in range(n):
            acc = 0.0
            for q in range(s):
                acc += K[q, j] * AX[e, q]
            tmp[j] = y_old[j] + acc * h
        rhs(stage, tmp, p, P, table, K[s])  # autonomous: the stage's node C_EXTRA[e] is not needed
    for j in range(n):
        dy = y_new[j] - y_old[j]
        F[0, j] = dy
        F[1, j] = h * K[0, j] - dy
        F[2, j] = 2.0 * dy - h * (f_new[j] + K[0, j])
        for i in range(4):
            acc = 0.0
            for q in range(_N_STAGES + 4):
                acc += D[i, q] * K[q, j]
            F[3 + i, j] = h * acc


@njit(**_JIT)
def _dense_eval(t, t_old, h, y_old, F, out):
    """The interpolant at t (Horner-like in x and 1 - x, highest term first)."""
    x = (t - t_old) / h
    n = y_old.shape[0]
    for j in range(n):
        out[j] = 0.0
    for i in range(7):
        row = 6 - i
        factor = x if i % 2 == 0 else 1.0 - x
        for j in range(n):
            out[j] = (out[j] + F[row, j]) * factor
    for j in range(n):
        out[j] += y_old[j]


@njit(**_JIT)
def _event_at(t, stage, k, t_old, h, y_old, F, tmp, p, P):
    _dense_eval(t, t_old, h, y_old, F, tmp)
    return event_value(stage, k, tmp, p, P)


@njit(**_JIT)
def _brent(stage, k, xa, xb, fa, fb, t_old, h, y_old, F, tmp, p, P):
    """Root of the event between xa and xb (values fa, fb of opposite sign): Brent (1973).

    Stops when the bracket is within ``ROOT_TIME_TOLERANCE + 4 eps |t|``,
    as ``scipy.optimize.brentq`` with the reference path's tolerances.
    """
    xtol, rtol = ROOT_TIME_TOLERANCE, 4.0 * _EPS
    xpre, xcur, fpre, fcur = xa, xb, fa, fb
    if fpre == 0.0:
        return xpre
    if fcur == 0.0:
        return xcur
    xblk, fblk, spre, scur = 0.0, 0.0, 0.0, 0.0
    for _ in range(100):
        if fpre != 0.0 and fcur != 0.0 and (fpre < 0.0) != (fcur < 0.0):
            xblk, fblk = xpre, fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):
            xpre, xcur, xblk = xcur, xblk, xcur
            fpre, fcur, fblk = fcur, fblk, fcur
        delta = (xtol + rtol * abs(xcur)) / 2.0
        sbis = (xblk - xcur) / 2.0
        if fcur == 0.0 or abs(sbis) < delta:
            return xcur
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:   # secant
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:              # inverse quadratic
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            if 2.0 * abs(stry) < min(abs(spre), 3.0 * abs(sbis) - delta):
                spre, scur = scur, stry
            else:
                spre = scur = sbis
        else:
            spre = scur = sbis
        xpre, fpre = xcur, fcur
        if abs(scur) > delta:
            xcur += scur
        else:
            xcur += delta if sbis > 0.0 else -delta
        fcur = _event_at(xcur, stage, k, t_old, h, y_old, F, tmp, p, P)
    return xcur


# integrate()'s outcome codes besides an event index.
_REACHED_END, _FAILED = -1, -2


@njit(**_JIT)
def integrate(stage, t0, y0, t_bound, coef, rtol, atol, p, P, table, counts):
    """Integrate ``stage`` from (t0, y0) until a terminal event or ``t_bound``.

    Returns ``(code, t_end, y_end, apex)``: code is the index of the terminal
    event that ended it, ``_REACHED_END`` or ``_FAILED`` (step size underflow
    or a non-finite state); apex is the largest y[1] at a counted apex root
    (flight only; -inf if none). ``counts`` accumulates [steps, evaluations].
    """
    n = y0.shape[0]
    ne = n_events(stage)
    K = np.empty((_N_STAGES + 4, n))
    F = np.empty((7, n))
    y, y_new = y0.copy(), np.empty(n)
    f, f_new = np.empty(n), np.empty(n)
    tmp, y_root = np.empty(n), np.empty(n)
    previous = np.empty(ne)
    rhs(stage, y, p, P, table, f)
    for k in range(ne):
        previous[k] = event_value(stage, k, y, p, P)
    t = t0
    h_abs = _initial_step(stage, t0, y, f, t_bound, rtol, atol, p, P, table)
    counts[1] += 2
    apex = -math.inf
    apex_t, apex_y = np.empty(4), np.empty(4)   # counted apex roots within one step
    exponent = -1.0 / (_ERROR_ORDER + 1)
    while t < t_bound:
        min_step = 10.0 * abs(np.nextafter(t, math.inf) - t)
        if h_abs < min_step:
            h_abs = min_step
        rejected = False
        while True:
            if h_abs < min_step:
                return _FAILED, t, y, apex
            t_new = t + h_abs
            if t_new > t_bound:
                t_new = t_bound
            h = t_new - t
            h_abs = abs(h)
            _rk_step(stage, t, y, f, h, coef, K, y_new, f_new, tmp, p, P, table)
            counts[1] += _N_STAGES
            error = _error_norm(h, y, y_new, K, coef, rtol, atol)
            if error < 1.0:
                factor = _MAX_FACTOR if error == 0.0 else min(_MAX_FACTOR, _SAFETY * error ** exponent)
                if rejected:
                    factor = min(1.0, factor)
                h_abs *= factor
                break
            if math.isfinite(error):
                h_abs *= max(_MIN_FACTOR, _SAFETY * error ** exponent)
            else:   # a non-finite trial stage (e.g. past the sling's reach): shrink hard
                h_abs *= _MIN_FACTOR
            rejected = True
        counts[0] += 1
        for j in range(n):
            if not math.isfinite(y_new[j]):
                return _FAILED, t_new, y_new, apex
        t_old = t

        # Events on the accepted step [t_old, t_new].
        dense_ready = False
        hit_t, hit_k = math.inf, -1
        n_apex = 0
        for k in range(ne):
            after = event_value(stage, k, y_new, p, P)
            direction = event_direction(stage, k)
            start, v_start = t_old, previous[k]
            previous[k] = after
            while True:
                rising = v_start < 0.0 <= after
                falling = v_start > 0.0 >= after
                if not ((rising and direction >= 0) or (falling and direction <= 0)):
                    break
                if not dense_ready:
                    _dense_prepare(stage, t_old, h, y, y_new, f_new, coef, K, F, tmp, p, P, table)
                    counts[1] += 3
                    dense_ready = True
                if after == 0.0:
                    t_root = t_new
                else:
                    t_root = _brent(stage, k, start, t_new, v_start, after, t_old, h, y, F, tmp, p, P)
                _dense_eval(t_root, t_old, h, y, F, y_root)
                if event_armed(stage, k, y_root, p, P):
                    if event_terminal(stage, k):
                        if t_root < hit_t:
                            hit_t, hit_k = t_root, k
                        break
                    if n_apex < 4:
                        apex_t[n_apex], apex_y[n_apex] = t_root, y_root[1]
                        n_apex += 1
                # Not counted: look for a later root in the same step, past this one.
                nudge = max(ROOT_TIME_TOLERANCE * 10.0, (t_new - t_root) * 1e-9)
                if t_root + nudge >= t_new:
                    break
                start = t_root + nudge
                v_start = _event_at(start, stage, k, t_old, h, y, F, tmp, p, P)
        for i in range(n_apex):
            if apex_t[i] <= hit_t:
                apex = max(apex, apex_y[i])
        if hit_k >= 0:
            y_hit = np.empty(n)
            _dense_eval(hit_t, t_old, h, y, F, y_hit)
            return hit_k, hit_t, y_hit, apex
        t = t_new
        y[:] = y_new
        f[:] = f_new
    return _REACHED_END, t, y, apex


# --------------------------------------------------------------------------- #
# A whole shot
# --------------------------------------------------------------------------- #

@njit(**_JIT)
def shot(P, table, coef, rtol, atol, out):
    """Simulate the design row ``P`` through all three stages into the result row ``out``.

    The stages and their ends are those of ``analytic.simulate.simulate``;
    ``out[STATUS]`` names how it ended and the other entries hold what was
    reached (NaN otherwise).
    """
    out[:] = math.nan
    counts = np.zeros(2)
    p = params(P)
    t_limit = P[T_LIMIT]
    theta0, phi0 = P[THETA0], P[PHI0]
    ddtheta0, _, normal0 = slide_accelerations(theta0, phi0, 0.0, 0.0, p)
    if not ddtheta0 < 0.0:
        out[STATUS], out[VALUE], out[END_T] = NEVER_FIRES, ddtheta0, 0.0
        out[STEPS], out[EVALS] = 0.0, 1.0
        return

    # Stage 1: slide on the base until the normal force vanishes.
    y1 = np.array([theta0, phi0, 0.0, 0.0])
    if normal0 > 0.0:
        code, t1, y1, _ = integrate(SLIDE, 0.0, y1, t_limit, coef, rtol, atol, p, P, table, counts)
    else:   # the sling already pulls harder than the projectile's weight
        code, t1 = 1, 0.0
    out[STEPS], out[EVALS] = counts[0], counts[1]
    if code != 1:
        out[END_T] = t1
        if code == _FAILED:
            out[STATUS] = STEP_FAILED
            return
        out[STATUS] = NEVER_LIFTS_OFF
        out[DETAIL] = UNDER_TIP if code == 0 else (ARM_BACK if code == 2 else TIME_LIMIT)
        return
    out[LIFTOFF_T] = t1

    # Stage 2: free swing until release.
    psi, dpsi, _, _, _ = slide_constraint(y1[0], y1[2], p)
    y2 = np.array([y1[0], y1[1], psi, y1[2], y1[3], dpsi])
    code, t2, y2, _ = integrate(SWING, t1, y2, t_limit, coef, rtol, atol, p, P, table, counts)
    out[STEPS], out[EVALS], out[END_T] = counts[0], counts[1], t2
    if code != 0:
        out[STATUS] = STEP_FAILED if code == _FAILED else (HITS_BASE if code == 1 else NEVER_RELEASES)
        return
    x, y, vx, vy = projectile_state(y2[0], y2[2], y2[3], y2[5], p)
    out[RELEASE_T], out[RELEASE_X], out[RELEASE_Y], out[RELEASE_VX], out[RELEASE_VY] = t2, x, y, vx, vy

    # Stage 3: flight, bounded as in analytic.simulate._fly.
    vacuum_time = (vy + math.sqrt(vy * vy + 2.0 * p.g * (y + p.h))) / p.g
    t_max = t2 + 100.0 * vacuum_time + 60.0
    code, t3, y3, apex = integrate(FLIGHT, t2, np.array([x, y, vx, vy]), t_max, coef, rtol, atol,
                                   p, P, table, counts)
    out[STEPS], out[EVALS], out[END_T] = counts[0], counts[1], t3
    if code != 0:
        out[STATUS] = STEP_FAILED if code == _FAILED else NO_LANDING
        return
    out[STATUS] = OK
    out[LANDING_T], out[LANDING_X], out[APEX] = t3, y3[0], max(y, apex) + p.h


@njit(parallel=True, **_JIT)
def shots(designs, table, coef, rtol, atol, out):
    """``shot`` for every row of ``designs`` (S, N_DESIGN) into ``out`` (S, N_RESULT), on all threads."""
    for i in prange(designs.shape[0]):
        shot(designs[i], table, coef, rtol, atol, out[i])
