"""Equations of motion ``M(q) q'' = f(q, q')`` for stages 1 and 2, and the forces they imply.

Symbols (``docs/derivation.md``, section numbers in brackets):

=========  =================================================  ============
symbol     meaning                                             design field
=========  =================================================  ============
theta      arm angle from the upward vertical, CCW  [1]        --
phi        counterweight link angle relative to the arm [1]    --
psi        sling angle relative to the long arm [1]            --
beta       theta + psi, absolute sling angle [1]               --
La, Lb     long and short arm                                  arm_long, arm_short
d          pivot to arm centre of mass (long side positive)    arm_cg
mA, IA     arm mass, inertia about its centre                  arm_mass, arm_inertia
mW, Lw, IW counterweight mass, link, inertia about its centre  counterweight_*
Ls         sling                                               sling_length
mP         projectile mass                                     projectile.mass
h, g       pivot height, gravity                               pivot_height, gravity
=========  =================================================  ============

Stage 2 [3] has the full 3x3 system. Stage 1 [4] keeps the projectile on the
base, ``La cos(theta) + Ls cos(beta) = -h``; psi is then a function of theta
(``beta = -arccos(-(h + La cos theta) / Ls)``, the sling pointing forward and
down), leaving (theta, phi) with the reduced system ``B^T M B``; the base's
normal force is the constraint's Lagrange multiplier [4.3].
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from analytic import kernel
from analytic.design import Design
from analytic.kernel import Params


class OutOfReach(ValueError):
    """Stage-1 state with the long-arm tip higher above the base than the sling is long."""


def params(design: Design) -> Params:
    """Extract the equation parameters from a design."""
    m = design.machine
    return Params(m.arm_long, m.arm_short, m.arm_cg, m.arm_mass, m.arm_inertia,
                  m.counterweight_mass, m.counterweight_link, m.counterweight_inertia,
                  m.sling_length, design.projectile.mass, m.pivot_height,
                  design.environment.gravity)


# --------------------------------------------------------------------------- #
# Stage 2: three degrees of freedom [3]
# --------------------------------------------------------------------------- #

#: Entries of M (M23 = 0) and f, eqs. (3.3)-(3.4): written once, in
#: ``analytic.kernel.terms``; this is its Python source run by CPython (the
#: fast path runs the same source compiled).
_terms = kernel.terms.py_func
_slide_constraint = kernel.slide_constraint.py_func


def mass_matrix(q: np.ndarray, p: Params) -> np.ndarray:
    """Stage-2 mass matrix M(q), shape (3, 3), for q = [theta, phi, psi]."""
    m11, m12, m13, m22, m33, *_ = _terms(*q, 0.0, 0.0, 0.0, p)
    return np.array([[m11, m12, m13], [m12, m22, 0.0], [m13, 0.0, m33]])


def forcing(q: np.ndarray, qdot: np.ndarray, p: Params) -> np.ndarray:
    """Stage-2 forcing f(q, q') = -(dM/dt) q' + dT/dq - dV/dq, shape (3,)."""
    *_, f1, f2, f3 = _terms(*q, *qdot, p)
    return np.array([f1, f2, f3])


def swing_accelerations(q: np.ndarray, qdot: np.ndarray, p: Params) -> tuple[float, float, float]:
    """Solve M q'' = f in stage 2 (block elimination, M23 = 0), rad/s^2."""
    m11, m12, m13, m22, m33, f1, f2, f3 = _terms(*q, *qdot, p)
    ddtheta = (f1 - m12 * f2 / m22 - m13 * f3 / m33) / (m11 - m12 * m12 / m22 - m13 * m13 / m33)
    return ddtheta, (f2 - m12 * ddtheta) / m22, (f3 - m13 * ddtheta) / m33


def swing_rhs(t: float, y: np.ndarray, p: Params) -> np.ndarray:
    """Stage-2 state derivative for y = [theta, phi, psi, theta', phi', psi'], shape (6,)."""
    ddq = swing_accelerations(y[:3], y[3:], p)
    return np.array([y[3], y[4], y[5], *ddq])


# --------------------------------------------------------------------------- #
# Stage 1: projectile on the base, two degrees of freedom [4]
# --------------------------------------------------------------------------- #

class SlideKinematics(NamedTuple):
    """The constraint's consequences at (theta, theta'): eqs. (4.1)-(4.2)."""

    psi: float       # sling angle that keeps the projectile on the base
    dpsi: float      # psi' = s theta'
    s: float         # d psi / d theta
    c: float         # psi'' = s theta'' + c
    sin_beta: float  # sin(theta + psi) (< 0: the sling points forward-down)


def slide_kinematics(theta: float, dtheta: float, p: Params) -> SlideKinematics:
    """psi and its rates from the base constraint ``La cos(theta) + Ls cos(beta) = -h``.

    Defined while the sling is not vertical (``|sin beta| > 0``); the caller
    stops stage 1 before it gets there (``never_lifts_off``).
    """
    kin = SlideKinematics(*_slide_constraint(theta, dtheta, p))
    if math.isnan(kin.psi):
        raise OutOfReach(f"theta = {theta!r}: the long-arm tip is {p.La * math.cos(theta) + p.h:.6g} m "
                         f"above the base, out of the sling's reach ({p.Ls:.6g} m)")
    return kin


def _slide(theta, phi, dtheta, dphi, p: Params):
    kin = slide_kinematics(theta, dtheta, p)
    terms = _terms(theta, phi, kin.psi, dtheta, dphi, kin.dpsi, p)
    m11, m12, m13, m22, m33, f1, f2, f3 = terms
    s, c = kin.s, kin.c
    reduced = (m11 + 2.0 * s * m13 + s * s * m33, m12, m22,
               f1 + s * f3 - (m13 + s * m33) * c, f2)
    return reduced, kin, terms


def slide_system(theta: float, phi: float, dtheta: float, dphi: float, p: Params):
    """Reduced stage-1 system ``M_r [theta'', phi''] = r`` (eq. 4.4).

    Returns
    -------
    m_r : (2, 2) reduced mass matrix ``B^T M B``.
    r : (2,) reduced forcing ``B^T (f - M [0, 0, c])``.
    kin : SlideKinematics at this state.
    """
    (a, b, e, r1, r2), kin, _ = _slide(theta, phi, dtheta, dphi, p)
    return np.array([[a, b], [b, e]]), np.array([r1, r2]), kin


def slide_accelerations(theta: float, phi: float, dtheta: float, dphi: float, p: Params):
    """theta'', phi'' in stage 1 and the normal force N of the base on the projectile (N).

    N is the Lagrange multiplier of the constraint (eq. 4.6):
    ``N = (M31 theta'' + M33 psi'' - f3) / (-Ls sin beta)``; positive pushes up.
    """
    (a, b, e, r1, r2), kin, terms = _slide(theta, phi, dtheta, dphi, p)
    m13, m33, f3 = terms[2], terms[4], terms[7]
    det = a * e - b * b
    ddtheta = (r1 * e - r2 * b) / det
    ddphi = (r2 * a - r1 * b) / det
    ddpsi = kin.s * ddtheta + kin.c
    normal = (m13 * ddtheta + m33 * ddpsi - f3) / (-p.Ls * kin.sin_beta)
    return ddtheta, ddphi, normal


def slide_rhs(t: float, y: np.ndarray, p: Params) -> np.ndarray:
    """Stage-1 state derivative for y = [theta, phi, theta', phi'], shape (4,)."""
    ddtheta, ddphi, _ = slide_accelerations(y[0], y[1], y[2], y[3], p)
    return np.array([y[2], y[3], ddtheta, ddphi])


def slide_full_state(y: np.ndarray, p: Params) -> tuple[np.ndarray, np.ndarray]:
    """Stage-1 state [theta, phi, theta', phi'] to full (q, q'), each shape (3,)."""
    kin = slide_kinematics(y[0], y[2], p)
    return np.array([y[0], y[1], kin.psi]), np.array([y[2], y[3], kin.dpsi])


# --------------------------------------------------------------------------- #
# Kinematics, energy and the sling force [2], [5]
# --------------------------------------------------------------------------- #

def projectile_state(q: np.ndarray, qdot: np.ndarray, p: Params) -> tuple[np.ndarray, np.ndarray]:
    """Projectile position and velocity, each shape (2,), m and m/s from the pivot (eqs. 2.3, 5.1)."""
    theta, _, psi = q
    dtheta, _, dpsi = qdot
    beta, dbeta = theta + psi, dtheta + dpsi
    position = np.array([-p.La * math.sin(theta) - p.Ls * math.sin(beta),
                         p.La * math.cos(theta) + p.Ls * math.cos(beta)])
    velocity = np.array([-p.La * dtheta * math.cos(theta) - p.Ls * dbeta * math.cos(beta),
                         -p.La * dtheta * math.sin(theta) - p.Ls * dbeta * math.sin(beta)])
    return position, velocity


def arm_direction(q: np.ndarray) -> np.ndarray:
    """Unit vector from the pivot to the long-arm tip, shape (2,)."""
    return np.array([-math.sin(q[0]), math.cos(q[0])])


def sling_direction(q: np.ndarray) -> np.ndarray:
    """Unit vector from the long-arm tip to the projectile, shape (2,)."""
    beta = q[0] + q[2]
    return np.array([-math.sin(beta), math.cos(beta)])


def potential_energy(q: np.ndarray, p: Params) -> tuple[float, float]:
    """Potential energy (machine, projectile), J, zero at the pivot's height (eq. 2.5)."""
    theta, phi, psi = q
    machine = p.g * (p.mA * p.d * math.cos(theta)
                     - p.mW * (p.Lb * math.cos(theta) + p.Lw * math.cos(theta + phi)))
    projectile = p.mP * p.g * (p.La * math.cos(theta) + p.Ls * math.cos(theta + psi))
    return machine, projectile


def kinetic_energy(q: np.ndarray, qdot: np.ndarray, p: Params) -> tuple[float, float]:
    """Kinetic energy (machine, projectile), J (eq. 2.4)."""
    theta, phi, psi = q
    dtheta, dphi, dpsi = qdot
    dw = dtheta + dphi
    machine = 0.5 * ((p.IA + p.mA * p.d * p.d) * dtheta * dtheta + p.IW * dw * dw
                     + p.mW * (p.Lb * p.Lb * dtheta * dtheta + p.Lw * p.Lw * dw * dw
                               + 2.0 * p.Lb * p.Lw * dtheta * dw * math.cos(phi)))
    dbeta = dtheta + dpsi
    projectile = 0.5 * p.mP * (p.La * p.La * dtheta * dtheta + p.Ls * p.Ls * dbeta * dbeta
                               + 2.0 * p.La * p.Ls * dtheta * dbeta * math.cos(psi))
    return machine, projectile


def sling_tension(q: np.ndarray, qdot: np.ndarray, ddq: np.ndarray, normal: float, p: Params) -> float:
    """Tension in the rigid sling, N (negative: the sling pushes), eq. (5.2).

    From the projectile's equation of motion along the sling,
    ``T = (N - mP g) cos(beta) + mP (Ls beta'^2 + La theta'^2 cos(psi) - La theta'' sin(psi))``.
    """
    theta, _, psi = q
    dbeta = qdot[0] + qdot[2]
    return ((normal - p.mP * p.g) * math.cos(theta + psi)
            + p.mP * (p.Ls * dbeta * dbeta + p.La * qdot[0] ** 2 * math.cos(psi)
                      - p.La * ddq[0] * math.sin(psi)))
