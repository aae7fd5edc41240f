"""Equations of motion ``M(q) q'' = f(q, q')`` for stages 1 and 2, and the forces and energies they imply.

The one place these equations are written. Plain ``math`` on floats: the
reference path (``analytic.reference``) runs these functions as they are, the
compiled path compiles the same source (``analytic.fast.compiled``). ``p`` is the
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
mua, ra    axle's Coulomb coefficient and radius [10]          losses.axle_*
muh, rh    hinge's Coulomb coefficient and radius [10]         losses.hinge_*
mub        base's Coulomb coefficient (stage 1) [10]           losses.base_friction
ta, th, F  friction torques on the arm (axle) and the link     --
           (hinge), the base's friction force on the
           projectile along x [10.1]
kind       the machine's kind code; ``FIXED``: the             machine.kind
           counterweight bolted to the arm (Lw = 0) [11]
D          the air's drag on the projectile in stages 1-2,     projectile.drag_during_swing
           when ``p.drag_swing`` is on [13]
=========  =================================================  ============

(the full table of ``Params`` is in ``analytic.parameters``).

Stage 2 [3] has the full 3x3 system. Stage 1 [4] keeps the projectile on the
base, ``La cos(theta) + Ls cos(beta) = -h``; psi is then a function of theta
(``beta = -arccos(-(h + La cos theta) / Ls)``, the sling pointing forward and
down), leaving (theta, phi) with the reduced system ``B^T M B``; the base's
normal force is the constraint's Lagrange multiplier [4.3]. The forces at the
joints (axle, hinge, sling) follow from the motion by Newton's law for each
body [9] (``joint_forces``, ``loads``). Friction [10] (``analytic.friction``)
makes the equations implicit, ``M q'' = f + Q(q'')``; the forces here take
the base's friction force (``joint_forces_sliding``, ``loads_sliding``).
A fixed machine [11] (the counterweight bolted to the arm, ``p.kind == FIXED``,
``Lw = 0``) is the hinged one with phi held at rest: ``terms`` gives its phi row
as ``phi'' = 0``, uncoupled, and every function here and in ``analytic.friction``
then moves theta and psi by the fixed machine's equations; the "hinge" force is
the counterweight's mount's. With ``p.drag_swing`` on, the projectile's drag
[13] is a generalised force ``J^T D`` in f (``terms``), so every system built
from f carries it, and the sling's force in ``joint_forces_sliding`` is net of it.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from analytic.scope import FLOATING_ARM, ROLLING, SLING, SWING_DRAG   # what this copy handles (analytic.scope)
from analytic.aero import DRAG_TABLE, drag_rate
from analytic.floating_arm import sling_terms as floating_sling_terms
from analytic.floating_arm import sling_weighs, sling_weights
from analytic.floating_arm import support_forces as floating_support_forces
from analytic.floating_arm import terms as floating_terms
from analytic.geometry import arm_long_side

#: ``Params.kind`` of a machine whose counterweight is bolted to the arm (``design.KINDS.index("fixed")``).
FIXED = 1.0
#: ``Params.kind`` of a floating-arm machine (``design.KINDS.index("floating-arm")``).
FLOATING = 2.0


# What the equations return where a caller reads less than the whole: named tuples, which numba
# compiles as the plain tuples they extend (the same machine code), and both paths read by name.
# The equations' inner products stay plain tuples (``sines``, ``terms``, ``frame_coupling``,
# ``slide_constraint``, ``machine_terms``, ``joint_forces``, the cofactors): their callers take
# them whole, or nearly, in the order the derivation writes them, and the reference path builds
# them on every evaluation of the right-hand side, where constructing a named tuple costs Python
# several times a plain tuple's.

class SwingSystem(NamedTuple):
    """The swing's mass matrix (symmetric: its upper triangle) and forces, ``M q'' = f`` over
    (theta, phi, psi) [3], [8]: kg m^2 and N m."""

    m11: float
    m12: float
    m13: float
    m22: float
    m23: float
    m33: float
    f1: float
    f2: float
    f3: float


class SlideSystem(NamedTuple):
    """The reduced stage-1 system ``[[a, b], [b, e]] [theta'', phi''] = [r1, r2]`` (eq. 4.4), then what
    the base's normal force needs: the psi row's ``m13``, ``m23``, ``m33``, ``f3``, and the
    constraint's ``psi'' = s theta'' + c`` with ``sin_beta`` (``slide_constraint``)."""

    a: float
    b: float
    e: float
    r1: float
    r2: float
    m13: float
    m23: float
    m33: float
    f3: float
    s: float
    c: float
    sin_beta: float


class SlideAccelerations(NamedTuple):
    """Stage 1's accelerations, rad/s^2, and the base's normal force on the projectile, N (up positive)."""

    ddtheta: float
    ddphi: float
    normal: float


class Loads(NamedTuple):
    """What a builder sizes the machine for (``loads_sliding``): N, N, N, m/s^2, N m."""

    axle_load: float
    hinge_load: float
    sling_tension: float
    projectile_acceleration: float
    arm_bending_moment: float


# --------------------------------------------------------------------------- #
# Stage 2: three degrees of freedom [3]
# --------------------------------------------------------------------------- #


def sines(theta, phi, psi):
    """``(sin, cos)`` of theta, phi, psi, theta + phi (w, the link's angle) and theta + psi (beta,
    the sling's), in that order: three sines and cosines, the sums' by the addition formulas
    (each a function the right-hand side calls takes the same products, which the compiled
    path then computes once: with friction the joint forces need no sine of their own)."""
    s_th, c_th = math.sin(theta), math.cos(theta)
    s_phi, c_phi = math.sin(phi), math.cos(phi)
    s_psi, c_psi = math.sin(psi), math.cos(psi)
    return (s_th, c_th, s_phi, c_phi, s_psi, c_psi, s_th * c_phi + c_th * s_phi, c_th * c_phi - s_th * s_phi,
            s_th * c_psi + c_th * s_psi, c_th * c_psi - s_th * s_psi)


def terms(theta, phi, psi, dtheta, dphi, dpsi, p):
    """Entries of M (M23 = 0) and f = -(dM/dt) q' + dT/dq - dV/dq, eqs. (3.3)-(3.4).

    Returns ``(m11, m12, m13, m22, m33, f1, f2, f3)``; for a fixed machine ``m12 = 0``, ``m22 = 1``
    (eq. 11.4), as for a floating arm, whose (theta, psi) entries are ``analytic.floating_arm.terms``'s [12].
    """
    # First, on every machine: compiled, the sines then serve whatever follows at these angles (the
    # joint forces), which a copy past the floating arm's branch would not.
    s_th, c_th, s_phi, c_phi, s_psi, c_psi, s_w, _, s_b, _ = sines(theta, phi, psi)
    if FLOATING_ARM and p.kind == FLOATING:
        m11, m13, m33, f1, f3 = floating_terms(theta, psi, dtheta, dpsi, p)
        if SLING and sling_weighs(p):
            d11, d13, d33, d1, d3 = floating_sling_terms(theta, psi, dtheta, dpsi, p)
            m11, m13, m33, f1, f3 = m11 + d11, m13 + d13, m33 + d33, f1 + d1, f3 + d3
        if SWING_DRAG and p.drag_swing > 0.0:
            q1, q3 = drag_generalised(theta, psi, dtheta, dpsi, p)
            f1 += q1
            f3 += q3
        return m11, 0.0, m13, 1.0, m33, f1, 0.0, f3
    # Each number of the design read once (the reference path runs this in Python, where
    # reading a field costs more than the product it enters; the arithmetic is unchanged).
    IW, mW, Lw, Lb, mP, Ls, La, g = p.IW, p.mW, p.Lw, p.Lb, p.mP, p.Ls, p.La, p.g
    m12 = IW + mW * (Lw * Lw + Lb * Lw * c_phi)
    m13 = mP * (Ls * Ls + La * Ls * c_psi)
    m22 = IW + mW * Lw * Lw
    if p.kind == FIXED:
        # Bolted (Lw = 0, so f2 = 0): phi is held at rest, its row phi'' = 0 uncoupled from the rest [11.4].
        m12, m22 = 0.0, 1.0
    m33 = mP * Ls * Ls
    m11 = (p.IA + p.mA * p.d * p.d + IW
           + mW * (Lb * Lb + Lw * Lw + 2.0 * Lb * Lw * c_phi)
           + mP * (La * La + Ls * Ls + 2.0 * La * Ls * c_psi))
    f1 = (g * (p.mA * p.d * s_th - mW * (Lb * s_th + Lw * s_w)
               + mP * (La * s_th + Ls * s_b))
          + mW * Lb * Lw * s_phi * dphi * (2.0 * dtheta + dphi)
          + mP * La * Ls * s_psi * dpsi * (2.0 * dtheta + dpsi))
    f2 = -mW * Lw * (g * s_w + Lb * s_phi * dtheta * dtheta)
    f3 = mP * Ls * (g * s_b - La * s_psi * dtheta * dtheta)
    if SLING and sling_weighs(p):
        # The sling (a uniform rod from the tip to the projectile) and the pouch (a point at the
        # projectile): the projectile's terms with its mass weighted n0, n1, n2 [14.3].
        n0, n1, n2 = sling_weights(p)
        m11 += n0 * La * La + n2 * Ls * Ls + 2.0 * n1 * La * Ls * c_psi
        m13 += n2 * Ls * Ls + n1 * La * Ls * c_psi
        m33 += n2 * Ls * Ls
        f1 += g * (n0 * La * s_th + n1 * Ls * s_b) + n1 * La * Ls * s_psi * dpsi * (2.0 * dtheta + dpsi)
        f3 += n1 * Ls * (g * s_b - La * s_psi * dtheta * dtheta)
    if SWING_DRAG and p.drag_swing > 0.0:
        q1, q3 = drag_generalised(theta, psi, dtheta, dpsi, p)
        f1 += q1
        f3 += q3
    return m11, m12, m13, m22, m33, f1, f2, f3


# --------------------------------------------------------------------------- #
# The projectile's drag during the swing [13]
# --------------------------------------------------------------------------- #

def swing_drag(theta, psi, dtheta, dpsi, p):
    """The air's drag on the projectile ``(Dx, Dy)``, N, at a stage-1 or stage-2 state (eq. 13.1):
    the flight's law (``aero.drag_rate``) on its velocity relative to the air, ``v - (wind, 0)``
    (a floating arm's projectile moves with its axle too, eq. 13.5)."""
    s_th, c_th = math.sin(theta), math.cos(theta)
    s_b, c_b = math.sin(theta + psi), math.cos(theta + psi)
    dbeta = dtheta + dpsi
    vx_rel = -swing_drag_reach(p) * c_th * dtheta - p.Ls * c_b * dbeta - p.wind
    vy = -p.La * s_th * dtheta - p.Ls * s_b * dbeta
    k = drag_rate(int(p.drag), vx_rel, vy, p.diameter, p.rho, p.mu, p.cd, p.area, p.mP, DRAG_TABLE)
    return -p.mP * k * vx_rel, -p.mP * k * vy


def drag_generalised(theta, psi, dtheta, dpsi, p):
    """The drag's generalised forces ``(Q_theta, Q_psi)``, N m: ``J^T D`` with ``J`` the Jacobian of the
    projectile's position ``La u(theta) + Ls u(theta + psi)`` (eq. 13.2; a floating arm's adds its
    axle's ``(-Lb sin(theta), 0)``, eq. 13.5); Q_phi is 0."""
    dx, dy = swing_drag(theta, psi, dtheta, dpsi, p)
    s_th, c_th = math.sin(theta), math.cos(theta)
    s_b, c_b = math.sin(theta + psi), math.cos(theta + psi)
    q_psi = -p.Ls * (c_b * dx + s_b * dy)
    return -swing_drag_reach(p) * c_th * dx - p.La * s_th * dy + q_psi, q_psi


def floating_supports_in_air(theta, psi, dtheta, dpsi, ddtheta, ddpsi, normal, p):
    """A floating arm's ``(track_y, guide_x)``, N, before friction: ``floating_arm.support_forces``
    less the drag during the swing, which pushes the machine too (eq. 13.5)."""
    track_y, guide_x = floating_support_forces(theta, psi, dtheta, dpsi, ddtheta, ddpsi, normal, p)
    if SWING_DRAG and p.drag_swing > 0.0:
        drag_x, drag_y = swing_drag(theta, psi, dtheta, dpsi, p)
        track_y, guide_x = track_y - drag_y, guide_x - drag_x
    return track_y, guide_x


def swing_drag_reach(p):
    """``-dx_P/dtheta`` of the long arm's tip over ``cos(theta)``, m: ``La``; a floating arm's
    ``La + Lb``, its axle at ``x_A = -Lb sin(theta)`` carrying the tip (eq. 13.5)."""
    return p.La + p.Lb if FLOATING_ARM and p.kind == FLOATING else p.La


def swing_accelerations(theta, phi, psi, dtheta, dphi, dpsi, p):
    """Stage 2: ``(theta'', phi'', psi'')``, rad/s^2.

    Fixed frame: M q'' = f by block elimination (M23 = 0). Rolling frame:
    the reduced system of ``rolling_terms`` (M23 != 0), solved whole.
    """
    if ROLLING and p.rolling:
        m11, m12, m13, m22, m23, m33, f1, f2, f3 = rolling_terms(theta, phi, psi, dtheta, dphi, dpsi, p)
        return solve_symmetric(m11, m12, m13, m22, m23, m33, f1, f2, f3)
    m11, m12, m13, m22, m33, f1, f2, f3 = terms(theta, phi, psi, dtheta, dphi, dpsi, p)
    ddtheta = (f1 - m12 * f2 / m22 - m13 * f3 / m33) / (m11 - m12 * m12 / m22 - m13 * m13 / m33)
    return ddtheta, (f2 - m12 * ddtheta) / m22, (f3 - m13 * ddtheta) / m33


def solve_symmetric(a11, a12, a13, a22, a23, a33, r1, r2, r3):
    """``x`` with ``A x = r`` for the symmetric positive definite 3x3 ``A`` (cofactors; A is well
    conditioned here: a mass matrix restricted to motions of zero momentum)."""
    c11, c12, c13, c22, c23, c33, det = symmetric_cofactors(a11, a12, a13, a22, a23, a33)
    return ((c11 * r1 + c12 * r2 + c13 * r3) / det, (c12 * r1 + c22 * r2 + c23 * r3) / det,
            (c13 * r1 + c23 * r2 + c33 * r3) / det)


def symmetric_cofactors(a11, a12, a13, a22, a23, a33):
    """The cofactors ``(c11, c12, c13, c22, c23, c33)`` and the determinant of the symmetric 3x3 ``A``:
    ``A^-1 = C / det``, so its columns are the solutions for the unit vectors."""
    c11 = a22 * a33 - a23 * a23
    c12 = a13 * a23 - a12 * a33
    c13 = a12 * a23 - a13 * a22
    c22 = a11 * a33 - a13 * a13
    c23 = a12 * a13 - a11 * a23
    c33 = a11 * a22 - a12 * a12
    return c11, c12, c13, c22, c23, c33, a11 * c11 + a12 * c12 + a13 * c13


# --------------------------------------------------------------------------- #
# A rolling frame [8]
# --------------------------------------------------------------------------- #
# The frame translates by X with nothing pushing it sideways, so the whole
# machine's horizontal momentum, Mt X' + S', stays zero from rest: X is
# cyclic and X = (S(q0) - S(q)) / Mt follows from the configuration. S is
# the moving parts' horizontal mass moment about the pivot and Mt the total
# mass. Eliminating X from M q'' + b X'' = f and Mt X'' + b.q'' + c = 0
# (b = dS/dq, c = q'^T (d2S/dq2) q') leaves (M - b b^T / Mt) q'' = f + b c / Mt.

def total_mass(p):
    """Frame, arm, counterweight and projectile, kg (and the sling and the pouch [14.5])."""
    if SLING and sling_weighs(p):
        return p.Mf + p.mA + p.mW + p.mP + p.mS + p.mQ
    return p.Mf + p.mA + p.mW + p.mP


def horizontal_moment(theta, phi, psi, p):
    """S = sum of m x over arm, counterweight and projectile (and the sling and the pouch [14.5]), x from
    the pivot, kg m."""
    moment = (-p.mA * p.d * math.sin(theta) + p.mW * (p.Lb * math.sin(theta) + p.Lw * math.sin(theta + phi))
              - p.mP * (p.La * math.sin(theta) + p.Ls * math.sin(theta + psi)))
    if SLING and sling_weighs(p):
        n0, n1, _ = sling_weights(p)
        moment -= n0 * p.La * math.sin(theta) + n1 * p.Ls * math.sin(theta + psi)
    return moment


def frame_coupling(theta, phi, psi, dtheta, dphi, dpsi, p):
    """``(b1, b2, b3, c)``: ``b = dS/dq`` and ``c = q'^T (d2S/dq2) q'``, so that ``S'' = b.q'' + c``."""
    s_th, c_th, _, _, _, _, s_w, c_w, s_b, c_b = sines(theta, phi, psi)
    b1 = -p.mA * p.d * c_th + p.mW * (p.Lb * c_th + p.Lw * c_w) - p.mP * (p.La * c_th + p.Ls * c_b)
    b2 = p.mW * p.Lw * c_w
    b3 = -p.mP * p.Ls * c_b
    dw, db = dtheta + dphi, dtheta + dpsi
    c = ((p.mA * p.d - p.mW * p.Lb + p.mP * p.La) * s_th * dtheta * dtheta
         - p.mW * p.Lw * s_w * dw * dw + p.mP * p.Ls * s_b * db * db)
    if SLING and sling_weighs(p):   # [14.5]
        n0, n1, _ = sling_weights(p)
        b1 -= n0 * p.La * c_th + n1 * p.Ls * c_b
        b3 -= n1 * p.Ls * c_b
        c += n0 * p.La * s_th * dtheta * dtheta + n1 * p.Ls * s_b * db * db
    return b1, b2, b3, c


def rolling_terms(theta, phi, psi, dtheta, dphi, dpsi, p):
    """The swing's system with the frame eliminated: ``M - b b^T / Mt`` and ``f + b c / Mt``, a
    ``SwingSystem`` (M23 is no longer 0).
    """
    m11, m12, m13, m22, m33, f1, f2, f3 = terms(theta, phi, psi, dtheta, dphi, dpsi, p)
    return frame_eliminated(m11, m12, m13, m22, m33, f1, f2, f3, theta, phi, psi, dtheta, dphi, dpsi, p)


def frame_eliminated(m11, m12, m13, m22, m33, f1, f2, f3, theta, phi, psi, dtheta, dphi, dpsi, p):
    """``terms``' system ``(m11, m12, m13, m22, m33, f1, f2, f3)`` with the rolling frame eliminated
    (``rolling_terms``): a ``SwingSystem``."""
    b1, b2, b3, c = frame_coupling(theta, phi, psi, dtheta, dphi, dpsi, p)
    k = 1.0 / total_mass(p)
    return SwingSystem(m11 - k * b1 * b1, m12 - k * b1 * b2, m13 - k * b1 * b3, m22 - k * b2 * b2, -k * b2 * b3,
                       m33 - k * b3 * b3, f1 + k * b1 * c, f2 + k * b2 * c, f3 + k * b3 * c)


def swing_terms(theta, phi, psi, dtheta, dphi, dpsi, p):
    """The swing's ``SwingSystem`` on the design's frame: ``terms`` (M23 = 0) on a fixed one,
    ``rolling_terms`` on a rolling one.

    ``terms`` comes first on both, outside the frame's test: compiled, its sines then serve the
    joint forces that friction takes at the same angles (``sines``), which a copy inside one
    branch would not.
    """
    m11, m12, m13, m22, m33, f1, f2, f3 = terms(theta, phi, psi, dtheta, dphi, dpsi, p)
    if ROLLING and p.rolling:
        return frame_eliminated(m11, m12, m13, m22, m33, f1, f2, f3, theta, phi, psi, dtheta, dphi, dpsi, p)
    return SwingSystem(m11, m12, m13, m22, 0.0, m33, f1, f2, f3)


def machine_terms(theta, phi, dtheta, dphi, m):
    """After release [10.9]: the swing's system of the arm and counterweight alone,
    ``(m11, m12, m22, f1, f2)``.

    ``m`` is the design's numbers without the projectile (mP = 0,
    ``stages.machine_params``): the psi row and column vanish, and on a rolling
    frame ``rolling_terms`` takes the machine's own mass and moment. A momentum
    the frame keeps from release changes nothing here (section 10.9).
    """
    m11, m12, _, m22, _, _, f1, f2, _ = swing_terms(theta, phi, 0.0, dtheta, dphi, 0.0, m)
    return m11, m12, m22, f1, f2


def solve_pair(a11, a12, a22, r1, r2):
    """``x`` with ``A x = r`` for the symmetric positive definite 2x2 ``A``."""
    det = a11 * a22 - a12 * a12
    return (r1 * a22 - r2 * a12) / det, (r2 * a11 - r1 * a12) / det


def machine_accelerations(theta, phi, dtheta, dphi, m):
    """After release, without friction: ``(theta'', phi'')``, rad/s^2 (``m`` as in ``machine_terms``)."""
    m11, m12, m22, f1, f2 = machine_terms(theta, phi, dtheta, dphi, m)
    return solve_pair(m11, m12, m22, f1, f2)


def ground_force(theta, phi, psi, dtheta, dphi, dpsi, ddtheta, ddphi, ddpsi, p):
    """The ground's vertical push on the frame, N: ``Mt g + d2/dt2 (sum m y)`` over the moving parts.

    The whole system's vertical momentum changes only by gravity and this
    push (the base's push on the projectile is internal to it). The frame
    stays down only while it is positive; ``Mt`` includes the frame only when
    it rolls (a fixed frame is bolted down and its own weight is not counted).
    """
    s_th, c_th = math.sin(theta), math.cos(theta)
    s_w, c_w = math.sin(theta + phi), math.cos(theta + phi)
    s_b, c_b = math.sin(theta + psi), math.cos(theta + psi)
    turn_arm = s_th * ddtheta + c_th * dtheta * dtheta        # -y'' / L of a point along the arm
    turn_weight = s_w * (ddtheta + ddphi) + c_w * (dtheta + dphi) ** 2
    turn_sling = s_b * (ddtheta + ddpsi) + c_b * (dtheta + dpsi) ** 2
    lift = (-p.mA * p.d * turn_arm + p.mW * (p.Lb * turn_arm + p.Lw * turn_weight)
            - p.mP * (p.La * turn_arm + p.Ls * turn_sling))
    if SLING and sling_weighs(p):   # [14.5]
        n0, n1, _ = sling_weights(p)
        lift -= n0 * p.La * turn_arm + n1 * p.Ls * turn_sling
        return (p.mA + p.mW + p.mP + p.mS + p.mQ + (p.Mf if ROLLING and p.rolling else 0.0)) * p.g + lift
    return (p.mA + p.mW + p.mP + (p.Mf if ROLLING and p.rolling else 0.0)) * p.g + lift


def frame_velocity(theta, phi, psi, dtheta, dphi, dpsi, p):
    """X', m/s: ``-S' / Mt`` (zero momentum); 0 for a fixed frame; a floating arm's axle's x_A' [12]."""
    if not (ROLLING and p.rolling):
        return -p.Lb * math.cos(theta) * dtheta if FLOATING_ARM and p.kind == FLOATING else 0.0
    b1, b2, b3, _ = frame_coupling(theta, phi, psi, dtheta, dphi, dpsi, p)
    return -(b1 * dtheta + b2 * dphi + b3 * dpsi) / total_mass(p)


def frame_displacement(theta, phi, psi, p):
    """X, m from the frame's place at rest: ``(S(q0) - S(q)) / Mt``; 0 for a fixed frame.

    A floating arm's axle moves as a frame would: its ``x_A = -Lb sin(theta)`` from the guide [12], so that
    every position and velocity on the ground adds it as a rolling frame's.
    """
    if not (ROLLING and p.rolling):
        return -p.Lb * math.sin(theta) if FLOATING_ARM and p.kind == FLOATING else 0.0
    rest = horizontal_moment(p.theta0, p.phi0, -0.5 * math.pi - p.theta0, p)   # the sling along the base
    return (rest - horizontal_moment(theta, phi, psi, p)) / total_mass(p)


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
    Jacobian. Returns a ``SlideSystem``: the system, then what the normal force
    needs (``slide_accelerations``). With a rolling frame M and f are those of
    ``rolling_terms`` (M23 != 0).
    """
    psi, dpsi, s, c, sin_beta = slide_constraint(theta, dtheta, p)
    m11, m12, m13, m22, m23, m33, f1, f2, f3 = swing_terms(theta, phi, psi, dtheta, dphi, dpsi, p)
    a = m11 + 2.0 * s * m13 + s * s * m33
    r1 = f1 + s * f3 - (m13 + s * m33) * c
    if ROLLING and p.rolling:
        return SlideSystem(a, m12 + s * m23, m22, r1, f2 - m23 * c, m13, m23, m33, f3, s, c, sin_beta)
    return SlideSystem(a, m12, m22, r1, f2, m13, 0.0, m33, f3, s, c, sin_beta)


def slide_accelerations(theta, phi, dtheta, dphi, p):
    """Stage 1: ``SlideAccelerations`` ``(theta'', phi'', N)``, N the base's normal force on the projectile.

    N is the Lagrange multiplier of the constraint (eq. 4.6):
    ``N = (M31 theta'' + M32 phi'' + M33 psi'' - f3) / (-Ls sin beta)``, M32 = 0
    for a fixed frame. The base moves only sideways, so its push stays vertical.
    """
    a, b, e, r1, r2, m13, m23, m33, f3, s, c, sin_beta = slide_system(theta, phi, dtheta, dphi, p)
    det = a * e - b * b
    ddtheta = (r1 * e - r2 * b) / det
    ddphi = (r2 * a - r1 * b) / det
    ddpsi = s * ddtheta + c
    if ROLLING and p.rolling:
        normal = (m13 * ddtheta + m23 * ddphi + m33 * ddpsi - f3) / (-p.Ls * sin_beta)
    else:
        normal = (m13 * ddtheta + m33 * ddpsi - f3) / (-p.Ls * sin_beta)
    return SlideAccelerations(ddtheta, ddphi, normal)


def slide_state(theta, phi, dtheta, dphi, p):
    """The full coordinates and rates ``(theta, phi, psi, theta', phi', psi')`` of a stage-1 state."""
    psi, dpsi, _, _, _ = slide_constraint(theta, dtheta, p)
    return theta, phi, psi, dtheta, dphi, dpsi


# --------------------------------------------------------------------------- #
# Energy [2]
# --------------------------------------------------------------------------- #

def potential_energy(theta, phi, psi, p):
    """Potential energy ``(machine, projectile)``, J, zero at the pivot's height (eq. 2.5); the machine's
    includes the sling's and the pouch's (``sling_energy``)."""
    machine = p.g * (p.mA * p.d * math.cos(theta)
                     - p.mW * (p.Lb * math.cos(theta) + p.Lw * math.cos(theta + phi)))
    projectile = p.mP * p.g * (p.La * math.cos(theta) + p.Ls * math.cos(theta + psi))
    if SLING and sling_weighs(p):   # the sling and the pouch stay with the machine [14.7]
        machine += sling_energy(theta, phi, psi, 0.0, 0.0, 0.0, p)[1]
    return machine, projectile


def kinetic_energy(theta, phi, psi, dtheta, dphi, dpsi, p):
    """Kinetic energy ``(machine, projectile)`` on the ground, J (eq. 2.4; [8] with a rolling frame,
    whose own kinetic energy is counted with the machine's, as the sling's and the pouch's are [14.7])."""
    dw = dtheta + dphi
    machine = 0.5 * ((p.IA + p.mA * p.d * p.d) * dtheta * dtheta + p.IW * dw * dw
                     + p.mW * (p.Lb * p.Lb * dtheta * dtheta + p.Lw * p.Lw * dw * dw
                               + 2.0 * p.Lb * p.Lw * dtheta * dw * math.cos(phi)))
    dbeta = dtheta + dpsi
    projectile = 0.5 * p.mP * (p.La * p.La * dtheta * dtheta + p.Ls * p.Ls * dbeta * dbeta
                               + 2.0 * p.La * p.Ls * dtheta * dbeta * math.cos(psi))
    if (ROLLING and p.rolling) or (FLOATING_ARM and p.kind == FLOATING):
        # On the ground every part moves with X' (a floating arm's: its axle's) besides: the projectile
        # gains mP X' vx + mP X'^2 / 2, and the frame (counted with the machine) Mf X'^2 / 2.
        b1, b2, b3, _ = frame_coupling(theta, phi, psi, dtheta, dphi, dpsi, p)
        moment_rate = b1 * dtheta + b2 * dphi + b3 * dpsi        # S'
        dx = frame_velocity(theta, phi, psi, dtheta, dphi, dpsi, p)   # X'
        vx = -p.La * dtheta * math.cos(theta) - p.Ls * dbeta * math.cos(theta + psi)
        projectile += p.mP * dx * (vx + 0.5 * dx)
        carried = total_mass(p) - p.mP if ROLLING and p.rolling else p.mA + p.mW
        if SLING and sling_weighs(p) and not (ROLLING and p.rolling):
            carried += p.mS + p.mQ
        machine += dx * (moment_rate - p.mP * vx) + 0.5 * carried * dx * dx
    if SLING and sling_weighs(p):   # their motion relative to the frame; the frame's share is above
        n0, n1, n2 = sling_weights(p)
        machine += 0.5 * (n0 * p.La * p.La * dtheta * dtheta + n2 * p.Ls * p.Ls * dbeta * dbeta
                          + 2.0 * n1 * p.La * p.Ls * dtheta * dbeta * math.cos(psi))
    return machine, projectile


def sling_energy(theta, phi, psi, dtheta, dphi, dpsi, p):
    """The sling's and the pouch's ``(kinetic, potential)`` energy, J, on the ground, the potential zero
    at the pivot's height [14.7]: the part of the machine's (``kinetic_energy``, ``potential_energy``)
    that stays in them at release, not the projectile's."""
    n0, n1, n2 = sling_weights(p)
    dbeta = dtheta + dpsi
    kinetic = 0.5 * (n0 * p.La * p.La * dtheta * dtheta + n2 * p.Ls * p.Ls * dbeta * dbeta
                     + 2.0 * n1 * p.La * p.Ls * dtheta * dbeta * math.cos(psi))
    if (ROLLING and p.rolling) or (FLOATING_ARM and p.kind == FLOATING):
        dx = frame_velocity(theta, phi, psi, dtheta, dphi, dpsi, p)
        moment_rate = -(n0 * p.La * math.cos(theta) * dtheta + n1 * p.Ls * math.cos(theta + psi) * dbeta)
        kinetic += dx * moment_rate + 0.5 * (p.mS + p.mQ) * dx * dx
    return kinetic, p.g * (n0 * p.La * math.cos(theta) + n1 * p.Ls * math.cos(theta + psi))


# --------------------------------------------------------------------------- #
# Joint forces [9]
# --------------------------------------------------------------------------- #
# Newton's second law for each body in the ground frame, given the motion
# (q, q', q'') and the base's push N: the counterweight is driven only by the
# hinge and gravity, the projectile only by the sling, the base and gravity,
# and the arm by the axle, the hinge's and the (massless) sling's reactions
# and gravity. A rolling frame adds its acceleration X'' to every x.

def frame_acceleration(theta, phi, psi, dtheta, dphi, dpsi, ddtheta, ddphi, ddpsi, p):
    """X'', m/s^2: ``-(b.q'' + c) / Mt`` (zero momentum, [8]); 0 for a fixed frame; a floating arm's x_A''."""
    if not (ROLLING and p.rolling):
        if FLOATING_ARM and p.kind == FLOATING:
            return -p.Lb * (math.cos(theta) * ddtheta - math.sin(theta) * dtheta * dtheta)
        return 0.0
    b1, b2, b3, c = frame_coupling(theta, phi, psi, dtheta, dphi, dpsi, p)
    return -(b1 * ddtheta + b2 * ddphi + b3 * ddpsi + c) / total_mass(p)


def joint_forces(theta, phi, psi, dtheta, dphi, dpsi, ddtheta, ddphi, ddpsi, normal, p):
    """The forces at the machine's joints, N, in the ground frame (x forward, y up), eq. (9.2),
    with no friction on the base: ``joint_forces_sliding`` with ``base_force = 0``."""
    return joint_forces_sliding(theta, phi, psi, dtheta, dphi, dpsi, ddtheta, ddphi, ddpsi, normal, 0.0, p)


def joint_forces_sliding(theta, phi, psi, dtheta, dphi, dpsi, ddtheta, ddphi, ddpsi, normal, base_force, p):
    """The forces at the machine's joints, N, in the ground frame (x forward, y up), eq. (9.2), (10.6).

    Returns ``(axle_x, axle_y, hinge_x, hinge_y, sling_x, sling_y)``:

    * axle: the force of the frame on the arm at the axle,
      ``mA (a_A + g) + H + S`` (the arm's Newton equation);
    * hinge: the force of the arm on the counterweight at the hinge,
      ``mW (a_W + g)`` (the counterweight's);
    * sling: the force of the sling on the projectile,
      ``mP (a_P + g) - N e_y`` (the projectile's); the sling pulls the arm's
      tip with the opposite force.

    ``a_*`` are the ground accelerations of the arm's and the counterweight's
    centres and of the projectile, ``g = (0, g)``; ``normal`` is the base's
    push on the projectile (0 off the base) and ``base_force`` the base's
    friction on it along x (``mP a_P = S + N e_y + F e_x - mP g e_y``, so
    ``S = mP (a_P + g) - N e_y - F e_x``). Friction torques at the axle and
    the hinge change no force: a torque has no resultant. With ``p.drag_swing``
    on, the drag ``D`` [13] acts on the projectile too: ``S`` is net of it.
    """
    axle_x, axle_y, hinge_x, hinge_y, sling_x, sling_y = joint_forces_in_gravity(
        theta, phi, psi, dtheta, dphi, dpsi, ddtheta, ddphi, ddpsi, normal, base_force, p.g, p)
    if SWING_DRAG and p.drag_swing > 0.0:
        dx, dy = swing_drag(theta, psi, dtheta, dpsi, p)
        sling_x, sling_y = sling_x - dx, sling_y - dy
        if FLOATING_ARM and p.kind == FLOATING:   # the guide's push is the machine's less D_x; the mount carries D_x back [13.5]
            hinge_x, axle_y = hinge_x + dx, axle_y - dy
        else:
            axle_x, axle_y = axle_x - dx, axle_y - dy
    return axle_x, axle_y, hinge_x, hinge_y, sling_x, sling_y


def joint_forces_in_gravity(theta, phi, psi, dtheta, dphi, dpsi, ddtheta, ddphi, ddpsi, normal, base_force, gravity,
                            p):
    """``joint_forces_sliding`` with ``gravity`` for ``p.g`` (0: the part linear in the accelerations and
    in N and F, which ``analytic.friction`` builds its affine maps from)."""
    s_th, c_th, _, _, _, _, s_w, c_w, s_b, c_b = sines(theta, phi, psi)
    dw, db = dtheta + dphi, dtheta + dpsi
    ddw, ddb = ddtheta + ddphi, ddtheta + ddpsi
    ddx = frame_acceleration(theta, phi, psi, dtheta, dphi, dpsi, ddtheta, ddphi, ddpsi, p)
    # d2/dt2 of the unit vector along the long arm, (-sin theta, cos theta) [2.1].
    arm_x = -c_th * ddtheta + s_th * dtheta * dtheta
    arm_y = -s_th * ddtheta - c_th * dtheta * dtheta
    # ... of (sin w, -cos w) along the link [2.2] and of (-sin beta, cos beta) along the sling [2.3].
    link_x = c_w * ddw - s_w * dw * dw
    link_y = s_w * ddw + c_w * dw * dw
    sling_ux = -c_b * ddb + s_b * db * db
    sling_uy = -s_b * ddb - c_b * db * db
    hinge_x = p.mW * (ddx - p.Lb * arm_x + p.Lw * link_x)
    hinge_y = p.mW * (gravity - p.Lb * arm_y + p.Lw * link_y)
    sling_x = p.mP * (ddx + p.La * arm_x + p.Ls * sling_ux) - base_force
    sling_y = p.mP * (gravity + p.La * arm_y + p.Ls * sling_uy) - normal
    axle_x = p.mA * (ddx + p.d * arm_x) + hinge_x + sling_x
    axle_y = p.mA * (gravity + p.d * arm_y) + hinge_y + sling_y
    if SLING and sling_weighs(p):
        # The pouch moves with the projectile, so the sling pulls both; the arm carries the sling's own
        # mass too, its first moment along it half the pouch's [14.6].
        n0, n1, _ = sling_weights(p)
        sling_x += p.mQ * (ddx + p.La * arm_x + p.Ls * sling_ux)
        sling_y += p.mQ * (gravity + p.La * arm_y + p.Ls * sling_uy)
        axle_x += n0 * (ddx + p.La * arm_x) + n1 * p.Ls * sling_ux
        axle_y += n0 * (gravity + p.La * arm_y) + n1 * p.Ls * sling_uy
    if FLOATING_ARM and p.kind == FLOATING:
        # The supports: the track's vertical push at the axle and the guide's horizontal push on the
        # counterweight (axle_x above, the whole machine's), which its mount on the arm does not carry [12].
        return 0.0, axle_y, hinge_x - axle_x, hinge_y, sling_x, sling_y
    return axle_x, axle_y, hinge_x, hinge_y, sling_x, sling_y


def arm_bending_moment(theta, ddtheta, axle_ax, axle_ay, sling_x, sling_y, p):
    """The bending moment in the arm's cross-section at the axle, N m (CCW positive), eq. (9.6).

    The moment of the short side on the long side across the cut just on the long
    side of the axle (the axle's force and friction torque act on the short side),
    from the long side's Euler equation about the axle point O:
    ``M = J_L theta'' + s_L u x (a_O + g e_y) + La u x S``, with ``u`` the unit vector
    along the long arm, ``m_L, s_L = m_L La / 2, J_L`` the long side's mass and first
    and second moments about O (``geometry.arm_long_side``), ``(axle_ax, axle_ay)``
    the axle's own acceleration in the ground frame (m/s^2; 0 on a fixed frame) and
    ``(sling_x, sling_y)`` the sling's force on the projectile (N; it pulls the tip
    with ``-S``). The rod's centripetal accelerations point along ``u``: no moment.
    """
    _, first, second = arm_long_side(p.La, p.Lb, p.mA, p.d)
    ux, uy = -math.sin(theta), math.cos(theta)
    return (second * ddtheta + first * (ux * (axle_ay + p.g) - uy * axle_ax)
            + p.La * (ux * sling_y - uy * sling_x))


def loads(theta, phi, psi, dtheta, dphi, dpsi, ddtheta, ddphi, ddpsi, normal, p):
    """``loads_sliding`` without friction on the base."""
    return loads_sliding(theta, phi, psi, dtheta, dphi, dpsi, ddtheta, ddphi, ddpsi, normal, 0.0, p)


def loads_sliding(theta, phi, psi, dtheta, dphi, dpsi, ddtheta, ddphi, ddpsi, normal, base_force, p):
    """What a builder sizes the machine for, from ``joint_forces``, eq. (9.3).

    Returns ``Loads`` ``(axle_load, hinge_load, sling_tension, projectile_acceleration, arm_bending_moment)``:

    * ``axle_load = |axle force|``, N: what the axle's bearings carry; a
      bearing's friction torque is ``mu r |F|`` with this ``|F|``;
    * ``hinge_load = |hinge force|``, N: likewise for the counterweight's hinge;
    * ``sling_tension``, N: the sling's pull on the projectile along the sling
      (negative: a rigid sling pushes);
    * ``projectile_acceleration``, m/s^2: what the projectile feels, the force
      of the sling and the base on it divided by its mass (gravity excluded;
      divide by g for "g"s), and the air's drag with ``p.drag_swing`` on;
    * ``arm_bending_moment = |arm_bending_moment|``, N m: what the arm's
      cross-section at the axle carries (the axle moves with the frame).

    ``base_force``: the base's friction on the projectile along x (stage 1), N.
    """
    axle_x, axle_y, hinge_x, hinge_y, sling_x, sling_y = joint_forces_sliding(
        theta, phi, psi, dtheta, dphi, dpsi, ddtheta, ddphi, ddpsi, normal, base_force, p)
    beta = theta + psi
    tension = sling_x * math.sin(beta) - sling_y * math.cos(beta)   # -S . (-sin beta, cos beta)
    felt_x = sling_x + base_force
    felt_y = sling_y + normal
    if SWING_DRAG and p.drag_swing > 0.0:   # an accelerometer in the projectile feels the air's push too
        dx, dy = swing_drag(theta, psi, dtheta, dpsi, p)
        felt_x, felt_y = felt_x + dx, felt_y + dy
    ddx = frame_acceleration(theta, phi, psi, dtheta, dphi, dpsi, ddtheta, ddphi, ddpsi, p)
    carried = p.mP
    tip_x, tip_y = sling_x, sling_y
    if SLING and sling_weighs(p):   # the tip pulls the sling's own mass too [14.6]
        carried = p.mP + p.mQ
        rod_x, rod_y = sling_rod_force(theta, psi, dtheta, dpsi, ddtheta, ddpsi, ddx, p)
        tip_x, tip_y = sling_x + rod_x, sling_y + rod_y
    bending = arm_bending_moment(theta, ddtheta, ddx, 0.0, tip_x, tip_y, p)
    return Loads(math.sqrt(axle_x * axle_x + axle_y * axle_y), math.sqrt(hinge_x * hinge_x + hinge_y * hinge_y),
                 tension, math.sqrt(felt_x * felt_x + felt_y * felt_y) / carried, abs(bending))


def sling_rod_force(theta, psi, dtheta, dpsi, ddtheta, ddpsi, ddx, p):
    """``mS (a_S + G)``, N: what the sling's own mass asks of its ends beyond the pull on the projectile
    and the pouch, ``a_S`` its centre's ground acceleration (the frame's, or the axle's, ``ddx``) [14.6]."""
    s_th, c_th = math.sin(theta), math.cos(theta)
    s_b, c_b = math.sin(theta + psi), math.cos(theta + psi)
    db, ddb = dtheta + dpsi, ddtheta + ddpsi
    return (p.mS * (ddx - p.La * (c_th * ddtheta - s_th * dtheta * dtheta) - 0.5 * p.Ls * (c_b * ddb - s_b * db * db)),
            p.mS * (p.g - p.La * (s_th * ddtheta + c_th * dtheta * dtheta) - 0.5 * p.Ls * (s_b * ddb + c_b * db * db)))
