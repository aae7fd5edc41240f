"""DOP853 for the compiled shot: the step, its error, the first step, the dense output and Brent's root.

The algorithm of ``scipy.integrate.DOP853`` (an embedded Dormand-Prince 8(5,3)
pair with its 7th-order dense output), whose published coefficient arrays
the kernel is handed at run time (``coef``: ``(A, B, C, E3, E5, D, A_EXTRA,
C_EXTRA)``, scipy's class arrays), and Brent's root finder on the dense
output with ``scipy.optimize.brentq``'s stopping rule. The right-hand side is
the model's (``stages.derivative``); ``analytic.fast.kernel.integrate`` drives the
steps. ``analytic.fast.compiled.internal`` functions: compiled for compiled callers
only.
"""

from __future__ import annotations

import math

import numpy as np

from analytic.fast.marks import internal
from analytic.stages import ROOT_RELATIVE_TOLERANCE, ROOT_TIME_TOLERANCE, derivative, event_value

# DOP853 step-size control (Hairer, Norsett & Wanner, "Solving Ordinary
# Differential Equations I", 2nd ed., II.4 and II.10; the values scipy uses).
SAFETY, MIN_FACTOR, MAX_FACTOR = 0.9, 0.2, 10.0
ERROR_ORDER = 7
N_STAGES = 12


@internal
def derivative_call(stage, y, p, table, out):
    """``stages.derivative`` as a call, for the sites that run it once per stretch or per event
    (the first step's trial, the dense output's three extra stages, a stretch's start).

    LLVM inlines the right-hand side into every caller (``analytic.fast.compiled.INLINE``), and
    unrolls the dense output's loop of three: seven copies of the whole model in the machine
    code, five of them at sites a shot passes a few times. Called here, they are one copy,
    and only ``rk_step`` inlines it: a smaller optimised module and a shorter cold compile
    (``python -m benchmarks --cold``, key ``compile_s``), the shots as fast (``fast_median_shot_s``)
    and bit-identical on the bench's designs, ideal and with typical losses.
    """
    derivative(stage, y, p, table, out)


# --------------------------------------------------------------------------- #
# DOP853 with dense output, events located by Brent's method
# --------------------------------------------------------------------------- #
# ``coef`` is ``(A, B, C, E3, E5, D, A_EXTRA, C_EXTRA)``, scipy's DOP853 class
# arrays: stages 0-11 of the 8th-order step, the 5th- and 3rd-order error
# estimators, and the dense output's three extra stages and its 4 x 16 matrix.

@internal
def rk_step(stage, t, y, f, h, coef, K, y_new, f_new, tmp, p, table):
    """One DOP853 step of size h from (t, y) with y'(t) = f; fills K[0:13].

    The right-hand side is called at two sites, the 11 stages' and the step's
    end (LLVM inlines it at each, ``analytic.fast.compiled.INLINE``): one site in
    the loop for both, through an array chosen at run time, made a smaller function
    but every shot longer (``python -m benchmarks``, key ``fast_median_shot_s``,
    and the batch's throughput on one thread).
    """
    A, B = coef[0], coef[1]
    n = y.shape[0]
    for j in range(n):
        K[0, j] = f[j]
    for s in range(1, N_STAGES):
        for j in range(n):
            acc = 0.0
            for q in range(s):
                acc += K[q, j] * A[s, q]
            tmp[j] = y[j] + acc * h
        derivative(stage, tmp, p, table, K[s])
    for j in range(n):
        acc = 0.0
        for q in range(N_STAGES):
            acc += K[q, j] * B[q]
        y_new[j] = y[j] + h * acc
    derivative(stage, y_new, p, table, f_new)
    for j in range(n):
        K[N_STAGES, j] = f_new[j]


@internal
def error_norm(h, y, y_new, K, coef, rtol, atol):
    """DOP853's blended 5th/3rd-order error estimate, scaled by the tolerances (< 1: accept)."""
    E3, E5 = coef[3], coef[4]
    n = y.shape[0]
    err5, err3 = 0.0, 0.0
    for j in range(n):
        scale = atol + max(abs(y[j]), abs(y_new[j])) * rtol
        e5, e3 = 0.0, 0.0
        for q in range(N_STAGES + 1):
            e5 += K[q, j] * E5[q]
            e3 += K[q, j] * E3[q]
        err5 += (e5 / scale) ** 2
        err3 += (e3 / scale) ** 2
    if err5 == 0.0 and err3 == 0.0:
        return 0.0
    return abs(h) * err5 / math.sqrt((err5 + 0.01 * err3) * n)


@internal
def rms(x, scale):
    total = 0.0
    for j in range(x.shape[0]):
        total += (x[j] / scale[j]) ** 2
    return math.sqrt(total / x.shape[0])


@internal(allocates=True)
def initial_step(stage, t0, y0, f0, t_bound, rtol, atol, p, table):
    """Starting step: Hairer, Norsett & Wanner (1993), II.4, as in scipy's ``select_initial_step``."""
    interval = abs(t_bound - t0)
    if interval == 0.0:
        return 0.0
    n = y0.shape[0]
    scale, y1, f1 = np.empty(n), np.empty(n), np.empty(n)
    for j in range(n):
        scale[j] = atol + abs(y0[j]) * rtol
    d0, d1 = rms(y0, scale), rms(f0, scale)
    h0 = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
    h0 = min(h0, interval)
    for j in range(n):
        y1[j] = y0[j] + h0 * f0[j]
    derivative_call(stage, y1, p, table, f1)
    for j in range(n):
        f1[j] -= f0[j]
    d2 = rms(f1, scale) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / (ERROR_ORDER + 1))
    return min(100.0 * h0, h1, interval)


@internal
def dense_prepare(stage, t_old, h, y_old, y_new, f_new, coef, K, F, tmp, p, table):
    """The step's 7th-order interpolant: three more stages into K, then F (7, n)."""
    D, AX = coef[5], coef[6]
    n = y_old.shape[0]
    for e in range(3):
        s = N_STAGES + 1 + e
        for j in range(n):
            acc = 0.0
            for q in range(s):
                acc += K[q, j] * AX[e, q]
            tmp[j] = y_old[j] + acc * h
        derivative_call(stage, tmp, p, table, K[s])  # autonomous: the stage's node C_EXTRA[e] is not needed
    for j in range(n):
        dy = y_new[j] - y_old[j]
        F[0, j] = dy
        F[1, j] = h * K[0, j] - dy
        F[2, j] = 2.0 * dy - h * (f_new[j] + K[0, j])
        for i in range(4):
            acc = 0.0
            for q in range(N_STAGES + 4):
                acc += D[i, q] * K[q, j]
            F[3 + i, j] = h * acc


@internal
def dense_eval(t, t_old, h, y_old, F, out):
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


@internal
def event_at(t, stage, k, t_old, h, y_old, F, tmp, p):
    dense_eval(t, t_old, h, y_old, F, tmp)
    return event_value(stage, k, tmp, p)


@internal
def brent(stage, k, xa, xb, fa, fb, t_old, h, y_old, F, tmp, p):
    """Root of the event between xa and xb (values fa, fb of opposite sign): Brent (1973).

    Stops when the bracket is within ``ROOT_TIME_TOLERANCE + 4 eps |t|``,
    as ``scipy.optimize.brentq`` with the reference path's tolerances.
    """
    xtol, rtol = ROOT_TIME_TOLERANCE, ROOT_RELATIVE_TOLERANCE
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
        fcur = event_at(xcur, stage, k, t_old, h, y_old, F, tmp, p)
    return xcur
