"""The floating-arm trebuchet's swing equations over (theta, psi) and its supports' forces (derivation section 12).

Derived and checked against the sympy Lagrangian (``tests/test_analytic_floating_arm.py``); both
paths simulate the kind through ``analytic.eom.terms`` (``p.kind == eom.FLOATING``). Plain ``math``
on floats in ``analytic.eom``'s symbols; ``p`` is a ``analytic.parameters.Params`` (the machine's
numbers La, Lb, d, mA, IA, mW, IW, Ls, mP, g are read).

The axle A rides the track y = 0 at ``x_A = -Lb sin(theta)``; the counterweight, rigid on the short
end, stays on the guide x = 0 at ``(0, -Lb cos theta)``; the long tip is at
``(-(La + Lb) sin theta, La cos theta)``, so the base constraint of stage 1 (the tip's height
plus the sling's) is the hinged machine's, ``analytic.eom.slide_constraint``.
"""

from __future__ import annotations

import math

from analytic.scope import SLING   # what this copy handles (analytic.scope)


def sling_weighs(p):
    """Whether the sling or the pouch has mass (``machine.sling_mass``, ``pouch_mass``): with both 0 no
    term of theirs is computed, so that a massless sling's arithmetic is the model's without them."""
    return p.mS > 0.0 or p.mQ > 0.0


def sling_weights(p):
    """``(n0, n1, n2)``, kg: the sling's and the pouch's weights in the projectile's terms [14.2]. The
    pouch is a point at the projectile, the sling a uniform rod from the tip to it, so together they
    add ``n0`` to the projectile's mass where its terms hold the tip's motion alone, ``n1`` where they
    hold the sling's first moment, ``n2`` where they hold its second: ``mQ + mS``, ``mQ + mS / 2``,
    ``mQ + mS / 3``."""
    return p.mQ + p.mS, p.mQ + 0.5 * p.mS, p.mQ + p.mS / 3.0


def terms(theta, psi, dtheta, dpsi, p):
    """Entries of M and f over (theta, psi), eqs. (12.3)-(12.5): ``(m11, m13, m33, f1, f3)``."""
    s_th, c_th = math.sin(theta), math.cos(theta)
    beta = theta + psi
    s_b, c_b = math.sin(beta), math.cos(beta)
    reach = p.La + p.Lb                 # the tip's x lever: x_T = -(La + Lb) sin theta
    arm_x = p.Lb + p.d                  # the arm centre's: x = -(Lb + d) sin theta
    inertia = (p.IA + p.IW + p.mA * (arm_x * arm_x * c_th * c_th + p.d * p.d * s_th * s_th)
               + p.mW * p.Lb * p.Lb * s_th * s_th + p.mP * (reach * reach * c_th * c_th + p.La * p.La * s_th * s_th))
    inertia_rate = 2.0 * s_th * c_th * (p.mA * (p.d * p.d - arm_x * arm_x) + p.mW * p.Lb * p.Lb
                                        + p.mP * (p.La * p.La - reach * reach))    # dJ/dtheta
    coupling = reach * c_th * c_b + p.La * s_th * s_b                                # K
    coupling_theta = -reach * s_th * c_b + p.La * c_th * s_b                         # dK/dtheta
    coupling_beta = -reach * c_th * s_b + p.La * s_th * c_b                          # dK/dbeta
    dbeta = dtheta + dpsi
    sling = p.mP * p.Ls
    force_beta = -sling * coupling_theta * dtheta * dtheta + p.g * sling * s_b
    force_theta = (-0.5 * inertia_rate * dtheta * dtheta - sling * coupling_beta * dbeta * dbeta
                   + p.g * s_th * (p.mA * p.d - p.mW * p.Lb + p.mP * p.La))
    m33 = sling * p.Ls
    m13 = m33 + sling * coupling
    return inertia + m33 + 2.0 * sling * coupling, m13, m33, force_theta + force_beta, force_beta


def sling_terms(theta, psi, dtheta, dpsi, p):
    """The sling's and the pouch's part of ``terms``, ``(m11, m13, m33, f1, f3)``: the projectile's with
    its mass weighted by ``sling_weights`` [14.4]."""
    n0, n1, n2 = sling_weights(p)
    s_th, c_th = math.sin(theta), math.cos(theta)
    beta = theta + psi
    s_b, c_b = math.sin(beta), math.cos(beta)
    reach = p.La + p.Lb
    inertia = n0 * (reach * reach * c_th * c_th + p.La * p.La * s_th * s_th)
    inertia_rate = 2.0 * s_th * c_th * n0 * (p.La * p.La - reach * reach)
    coupling = reach * c_th * c_b + p.La * s_th * s_b
    coupling_theta = -reach * s_th * c_b + p.La * c_th * s_b
    coupling_beta = -reach * c_th * s_b + p.La * s_th * c_b
    dbeta = dtheta + dpsi
    first = n1 * p.Ls
    force_beta = -first * coupling_theta * dtheta * dtheta + p.g * first * s_b
    force_theta = (-0.5 * inertia_rate * dtheta * dtheta - first * coupling_beta * dbeta * dbeta
                   + p.g * s_th * n0 * p.La)
    m33 = n2 * p.Ls * p.Ls
    return (inertia + m33 + 2.0 * first * coupling, m33 + first * coupling, m33, force_theta + force_beta,
            force_beta)


def moving_mass(p):
    """The mass the track and the guide carry, kg: arm, counterweight, projectile (and the sling and
    the pouch [14.5])."""
    if SLING and sling_weighs(p):
        return p.mA + p.mW + p.mP + p.mS + p.mQ
    return p.mA + p.mW + p.mP


def swing_accelerations(theta, psi, dtheta, dpsi, p):
    """Stage 2: ``(theta'', psi'')``, rad/s^2, from ``terms`` (eq. 12.5)."""
    m11, m13, m33, f1, f3 = terms(theta, psi, dtheta, dpsi, p)
    ddtheta = (f1 - m13 * f3 / m33) / (m11 - m13 * m13 / m33)
    return ddtheta, (f3 - m13 * ddtheta) / m33


def support_forces(theta, psi, dtheta, dpsi, ddtheta, ddpsi, normal, p):
    """The track's vertical push on the axle and the guide's horizontal push on the counterweight, N
    (eq. 12.6): ``(track_y, guide_x)``, given the motion and the base's push ``normal`` on the
    projectile (0 off the base).

    The track and the guide are the only supports besides the base (the sling is internal), so
    the whole machine's momentum changes by them and gravity:
    ``guide_x = sum m a_x``, ``track_y = sum m (a_y + g) - normal``.
    """
    s_th, c_th = math.sin(theta), math.cos(theta)
    beta = theta + psi
    s_b, c_b = math.sin(beta), math.cos(beta)
    dbeta, ddbeta = dtheta + dpsi, ddtheta + ddpsi
    turn_x = c_th * ddtheta - s_th * dtheta * dtheta        # d2/dt2 of sin(theta)
    turn_y = s_th * ddtheta + c_th * dtheta * dtheta        # -d2/dt2 of cos(theta)
    sling_x = c_b * ddbeta - s_b * dbeta * dbeta
    sling_y = s_b * ddbeta + c_b * dbeta * dbeta
    guide_x = (-p.mA * (p.Lb + p.d) * turn_x
               - p.mP * ((p.La + p.Lb) * turn_x + p.Ls * sling_x))
    lift = -p.mA * p.d * turn_y + p.mW * p.Lb * turn_y - p.mP * (p.La * turn_y + p.Ls * sling_y)
    if SLING and sling_weighs(p):   # [14.5]
        n0, n1, _ = sling_weights(p)
        guide_x -= n0 * (p.La + p.Lb) * turn_x + n1 * p.Ls * sling_x
        lift -= n0 * p.La * turn_y + n1 * p.Ls * sling_y
    return lift + moving_mass(p) * p.g - normal, guide_x
