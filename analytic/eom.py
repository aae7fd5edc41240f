"""Equations of motion ``M(q) q'' = f(q, q')`` for stages 1 and 2, and the forces and energies they imply.

The one place these equations are written. Plain ``math`` on floats: the
reference path (``analytic.reference``) runs these functions as they are, the
compiled path compiles the same source (``analytic.compiled``). ``p`` is the
design's ``analytic.parameters.Params``.

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

(the full table of ``Params`` is in ``analytic.parameters``).

Stage 2 [3] has the full 3x3 system. Stage 1 [4] keeps the projectile on the
base, ``La cos(theta) + Ls cos(beta) = -h``; psi is then a function of theta
(``beta = -arccos(-(h + La cos theta) / Ls)``, the sling pointing forward and
down), leaving (theta, phi) with the reduced system ``B^T M B``; the base's
normal force is the constraint's Lagrange multiplier [4.3].
"""

from __future__ import annotations

import math

# --------------------------------------------------------------------------- #
# Stage 2: three degrees of freedom [3]
# --------------------------------------------------------------------------- #


def terms(theta, phi, psi, dtheta, dphi, dpsi, p):
    """Entries of M (M23 = 0) and f = -(dM/dt) q' + dT/dq - dV/dq, eqs. (3.3)-(3.4).

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


def swing_accelerations(theta, phi, psi, dtheta, dphi, dpsi, p):
    """Stage 2: ``(theta'', phi'', psi'')`` from M q'' = f by block elimination (M23 = 0), rad/s^2."""
    m11, m12, m13, m22, m33, f1, f2, f3 = terms(theta, phi, psi, dtheta, dphi, dpsi, p)
    ddtheta = (f1 - m12 * f2 / m22 - m13 * f3 / m33) / (m11 - m12 * m12 / m22 - m13 * m13 / m33)
    return ddtheta, (f2 - m12 * ddtheta) / m22, (f3 - m13 * ddtheta) / m33


# --------------------------------------------------------------------------- #
# Stage 1: projectile on the base, two degrees of freedom [4]
# --------------------------------------------------------------------------- #

def slide_constraint(theta, dtheta, p):
    """psi and its rates from the base constraint ``La cos(theta) + Ls cos(beta) = -h``, eqs. (4.1)-(4.2).

    Returns ``(psi, psi', s, c, sin beta)`` with ``psi' = s theta'`` and
    ``psi'' = s theta'' + c``, the sling pointing forward and down
    (``beta = -arccos(-(h + La cos theta) / Ls)``); all NaN where the long-arm
    tip is higher above the base than the sling is long (out of reach), so
    that an integrator step reaching there is rejected.
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


def slide_system(theta, phi, dtheta, dphi, p):
    """The reduced stage-1 system ``[[a, b], [b, e]] [theta'', phi''] = [r1, r2]`` (eq. 4.4).

    ``B^T M B`` and ``B^T (f - M [0, 0, c])`` with ``B`` the constraint's
    Jacobian. Returns ``(a, b, e, r1, r2, m13, m33, f3, s, c, sin_beta)``:
    the system, then what the normal force needs (``slide_accelerations``).
    """
    psi, dpsi, s, c, sin_beta = slide_constraint(theta, dtheta, p)
    m11, m12, m13, m22, m33, f1, f2, f3 = terms(theta, phi, psi, dtheta, dphi, dpsi, p)
    a = m11 + 2.0 * s * m13 + s * s * m33
    r1 = f1 + s * f3 - (m13 + s * m33) * c
    return a, m12, m22, r1, f2, m13, m33, f3, s, c, sin_beta


def slide_accelerations(theta, phi, dtheta, dphi, p):
    """Stage 1: ``(theta'', phi'', N)``, N the base's normal force on the projectile, N (up positive).

    N is the Lagrange multiplier of the constraint (eq. 4.6):
    ``N = (M31 theta'' + M33 psi'' - f3) / (-Ls sin beta)``.
    """
    a, b, e, r1, r2, m13, m33, f3, s, c, sin_beta = slide_system(theta, phi, dtheta, dphi, p)
    det = a * e - b * b
    ddtheta = (r1 * e - r2 * b) / det
    ddphi = (r2 * a - r1 * b) / det
    ddpsi = s * ddtheta + c
    normal = (m13 * ddtheta + m33 * ddpsi - f3) / (-p.Ls * sin_beta)
    return ddtheta, ddphi, normal


def slide_state(theta, phi, dtheta, dphi, p):
    """The full coordinates and rates ``(theta, phi, psi, theta', phi', psi')`` of a stage-1 state."""
    psi, dpsi, _, _, _ = slide_constraint(theta, dtheta, p)
    return theta, phi, psi, dtheta, dphi, dpsi


# --------------------------------------------------------------------------- #
# Energy and the sling force [2], [5]
# --------------------------------------------------------------------------- #

def potential_energy(theta, phi, psi, p):
    """Potential energy ``(machine, projectile)``, J, zero at the pivot's height (eq. 2.5)."""
    machine = p.g * (p.mA * p.d * math.cos(theta)
                     - p.mW * (p.Lb * math.cos(theta) + p.Lw * math.cos(theta + phi)))
    projectile = p.mP * p.g * (p.La * math.cos(theta) + p.Ls * math.cos(theta + psi))
    return machine, projectile


def kinetic_energy(theta, phi, psi, dtheta, dphi, dpsi, p):
    """Kinetic energy ``(machine, projectile)``, J (eq. 2.4)."""
    dw = dtheta + dphi
    machine = 0.5 * ((p.IA + p.mA * p.d * p.d) * dtheta * dtheta + p.IW * dw * dw
                     + p.mW * (p.Lb * p.Lb * dtheta * dtheta + p.Lw * p.Lw * dw * dw
                               + 2.0 * p.Lb * p.Lw * dtheta * dw * math.cos(phi)))
    dbeta = dtheta + dpsi
    projectile = 0.5 * p.mP * (p.La * p.La * dtheta * dtheta + p.Ls * p.Ls * dbeta * dbeta
                               + 2.0 * p.La * p.Ls * dtheta * dbeta * math.cos(psi))
    return machine, projectile


def sling_tension(theta, psi, dtheta, dpsi, ddtheta, normal, p):
    """Tension in the rigid sling, N (negative: the sling pushes), eq. (5.2).

    From the projectile's equation of motion along the sling,
    ``T = (N - mP g) cos(beta) + mP (Ls beta'^2 + La theta'^2 cos(psi) - La theta'' sin(psi))``;
    ``normal`` is the base's push (0 off the base).
    """
    dbeta = dtheta + dpsi
    return ((normal - p.mP * p.g) * math.cos(theta + psi)
            + p.mP * (p.Ls * dbeta * dbeta + p.La * dtheta * dtheta * math.cos(psi)
                      - p.La * ddtheta * math.sin(psi)))
