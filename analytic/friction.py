"""Friction in the machine: the implicit equations ``M q'' = f + Q(q'')`` and their exact solution.

Coulomb friction at the axle (torque ``ta`` on the arm, relative rate
theta'), at the counterweight's hinge (``th`` on the link, ``-th`` on the arm,
relative rate phi') and on the base in stage 1 (force ``F`` along x on the
projectile), each a coefficient times a reaction that depends on the
accelerations (``docs/derivation.md``, section 10; the equations of sections
3, 4, 8 and the joint forces of section 9 are ``analytic.eom``'s). Plain
``math`` on floats, like ``analytic.eom``: the reference path runs these
functions as they are and the compiled path compiles the same source
(``analytic.fast.compiled``). ``p`` is the design's ``analytic.parameters.Params``.

Symbols (``docs/derivation.md`` section 10):

=========  =================================================  ============
symbol     meaning                                             design field
=========  =================================================  ============
mua, ra    axle's Coulomb coefficient and radius               losses.axle_*
muh, rh    hinge's Coulomb coefficient and radius              losses.hinge_*
mub        base's Coulomb coefficient (stage 1)                losses.base_friction
mua_s,     the static coefficients: what holds a joint stuck    losses.*_static_friction
muh_s,     (and the machine at rest); at least the kinetic
mub_s      ones above, which act while it slips [10.9]
ta, th     friction torques on the arm (axle) and on the       --
           link (hinge), N m [10.1]
F (fb)     the base's friction force on the projectile, N      --
sa, sh     joint modes: +1/-1 slipping with the rate's sign,   --
           0 stuck [10.4]
sb         the sign of the projectile's slide over the base    --
D          dx_P/dtheta along the base constraint, m [10.3]     --
=========  =================================================  ============
"""

from __future__ import annotations

import math
from typing import NamedTuple

from analytic.scope import FLOATING_ARM   # what this copy handles (analytic.scope)
from analytic.eom import (FLOATING, floating_supports_in_air, joint_forces, joint_forces_in_gravity,
                          joint_forces_sliding, machine_terms, slide_constraint, slide_system, solve_pair,
                          solve_symmetric, swing_terms, symmetric_cofactors)
from analytic.floating_arm import moving_mass, support_forces


# Coulomb friction at the axle (torque ta on the arm, relative rate theta'),
# at the hinge (torque th on the link, -th on the arm, relative rate phi') and
# on the base in stage 1 (force F along x on the projectile, relative rate its
# slide over the base). By virtual work their generalised forces are
# (ta, th, 0) and F (dx_P/dtheta, 0, dx_P/dpsi) [10.1]. Each friction's size
# is a coefficient times a reaction (|axle force|, |hinge force|, N) that is
# itself affine in the accelerations, which are affine in (ta, th, F): the
# equations are implicit, M q'' = f + Q(q''). They are solved exactly by
# Newton's method on the three unknowns (ta, th, F), on affine maps built
# once per evaluation [10.3]. A joint is slipping with sign +1 or -1 (its
# rate's sign; the friction opposes it) or stuck (0: its rate and
# acceleration are 0, and its torque is whatever holds it) [10.4].

#: The joints whose friction the functions here take by number (``joint``): the axle (theta'), the
#: hinge (phi'), and the base (the projectile's slide in stage 1), in the order of a state's friction
#: entries (``analytic.states``).
AXLE, HINGE, BASE = 0, 1, 2


class SwingFriction(NamedTuple):
    """Stage 2 with friction (``swing_friction``): the accelerations, rad/s^2; the friction torques at
    the axle and the hinge, N m; the loads on their bearings ``|A|``, ``|H|``, N. A floating arm's
    [12.10]: ``axle_torque`` the generalised force on theta of the axle's, the guide's and the track's
    friction, ``hinge_torque`` the guide's friction force, N, ``axle_load`` its hold
    (``slides_friction``), and ``hinge_load`` the track's friction force, N."""

    ddtheta: float
    ddphi: float
    ddpsi: float
    axle_torque: float
    hinge_torque: float
    axle_load: float
    hinge_load: float


class MachineFriction(NamedTuple):
    """The machine after release with friction (``machine_friction``): ``SwingFriction`` without psi."""

    ddtheta: float
    ddphi: float
    axle_torque: float
    hinge_torque: float
    axle_load: float
    hinge_load: float


class SlideFriction(NamedTuple):
    """Stage 1 with friction (``slide_friction``): the accelerations, rad/s^2; the base's normal force
    on the projectile, N; the friction torques at the axle and the hinge, N m, and the base's friction
    force, N; the loads on the bearings ``|A|``, ``|H|``, N; ``slide_ratio`` dx_P/dtheta, m/rad. A
    floating arm's [12.10]: ``axle_torque`` as in ``SwingFriction``, ``hinge_torque`` and
    ``base_force`` the guide's and the track's friction forces, N, ``axle_load`` the hold."""

    ddtheta: float
    ddphi: float
    normal: float
    axle_torque: float
    hinge_torque: float
    base_force: float
    axle_load: float
    hinge_load: float
    slide_ratio: float


#: Newton's method on the friction unknowns stops when an update, or a bound on
#: the next one, is this small relative to the unknowns (a few units in the
#: last place), or after ``FRICTION_ITERATIONS`` (the maps are affine and the
#: friction small, so it takes a few).
FRICTION_STEP_TOLERANCE = 1e-15
FRICTION_ITERATIONS = 30


def lossy(p):
    """Whether the design has any friction (otherwise every function runs the ideal machine's arithmetic):
    a static coefficient is never below its kinetic one, so the static ones tell."""
    return p.mua_s > 0.0 or p.muh_s > 0.0 or p.mub_s > 0.0 or p.mug_s > 0.0 or p.mut_s > 0.0


def kinetic_arm(joint, p):
    """``mu r`` of the joint (0 axle, 1 hinge), m: its friction torque slipping, per newton of load [10.2]."""
    return p.mua * p.ra if joint == AXLE else p.muh * p.rh


def static_arm(joint, p):
    """``mu_s r`` of the joint (0 axle, 1 hinge), m: the most friction torque that holds it stuck, per
    newton of load [10.9]; 0 for a joint without friction. A floating arm's axle with any friction
    on theta (the axle's, the guide's, the track's): 1, its load being the hold itself, N m [12.11]."""
    if joint == AXLE and FLOATING_ARM and p.kind == FLOATING:
        return 1.0 if (p.mua_s * p.ra > 0.0 or slides_lossy(p)) else 0.0
    return p.mua_s * p.ra if joint == AXLE else p.muh_s * p.rh


def _linearisation_error(curve, inverse_k2, lx, ly, dx, dy):
    """The most a row ``r + k s |L|`` (``curve = k / |L|``, ``inverse_k2 = 1 / k^2``) can err after
    Newton's update changed its load ``L = (lx, ly)`` by ``-(dx, dy)`` [10.3]: ``k |dL_across|^2 / |L|``,
    valid while the change takes at most half of the load away along it (else inf). 0 for an affine row
    (curve 0)."""
    if curve == 0.0:
        return 0.0
    if lx * dx + ly * dy > 0.5 * (lx * lx + ly * ly):
        return math.inf
    across = (lx * dy - ly * dx) * curve   # k |dL_across|: the cross product over |L|, times k
    return curve * across * across * inverse_k2


def _cofactors3(a11, a12, a13, a21, a22, a23, a31, a32, a33):
    """The cofactors of a general 3x3 ``A``'s first two rows and its determinant:
    ``(c11, c12, c13, c21, c22, c23, det)`` (``A^-1`` is the cofactors' transpose over det)."""
    c11 = a22 * a33 - a23 * a32
    c12 = a23 * a31 - a21 * a33
    c13 = a21 * a32 - a22 * a31
    c21 = a13 * a32 - a12 * a33
    c22 = a11 * a33 - a13 * a31
    c23 = a12 * a31 - a11 * a32
    return c11, c12, c13, c21, c22, c23, a11 * c11 + a12 * c12 + a13 * c13


def _solve3(a11, a12, a13, a21, a22, a23, a31, a32, a33, r1, r2, r3):
    """``x`` with ``A x = r`` for a general 3x3 ``A`` (Cramer's rule; A is a small
    perturbation of the identity or has acceleration rows of O(1))."""
    c11, c12, c13, _, _, _, det = _cofactors3(a11, a12, a13, a21, a22, a23, a31, a32, a33)
    x1 = (r1 * c11 + a12 * (r3 * a23 - r2 * a33) + a13 * (r2 * a32 - r3 * a22)) / det
    x2 = (a11 * (r2 * a33 - r3 * a23) + r1 * c12 + a13 * (r3 * a21 - r2 * a31)) / det
    x3 = (a11 * (r3 * a22 - r2 * a32) + a12 * (r2 * a31 - r3 * a21) + r1 * c13) / det
    return x1, x2, x3


def _solve2(a11, a12, a21, a22, r1, r2):
    """``x`` with ``A x = r`` for a general 2x2 ``A``: ``_solve3``'s arithmetic with the third row and
    column those of the identity and ``r3 = 0``, term for term, so the same bits."""
    det = a11 * a22 - a12 * a21
    return (r1 * a22 - a12 * r2) / det, (a11 * r2 - r1 * a21) / det


def _force_response(theta, phi, psi, ddtheta, ddphi, ddpsi, normal, base_force, p):
    """The part of ``joint_forces_sliding`` linear in (accelerations, N, F): the forces at zero
    rates and without gravity. Returns ``(axle_x, axle_y, hinge_x, hinge_y)``."""
    ax, ay, hx, hy, _, _ = joint_forces_in_gravity(theta, phi, psi, 0.0, 0.0, 0.0, ddtheta, ddphi, ddpsi, normal, base_force,
                                   0.0, p)
    return ax, ay, hx, hy


def friction_newton(base, unit_a, unit_h, unit_b, sa, sh, sb, p):
    """The friction unknowns ``(ta, th, F)`` of an affine system, by Newton's method [10.3].

    Each of ``base`` (at ta = th = F = 0) and ``unit_*`` (the change per unit of
    ta, th, F) is ``(axle_x, axle_y, hinge_x, hinge_y, N, theta'', phi'')``.
    The equations, by mode (``sa``, ``sh``: +1/-1 slipping, 0 stuck; ``sb``:
    the slide's sign, 0 off the base):

    * axle: ``ta + mua ra sa |A| = 0`` slipping, ``theta'' = 0`` stuck, ``ta = 0`` without friction;
    * hinge: ``th + muh rh sh |H| = 0`` slipping, ``phi'' = 0`` stuck, ``th = 0`` without friction;
    * base: ``F + mub sb N = 0`` on the base (N > 0 there), ``F = 0`` otherwise.

    A joint can be stuck when it has static friction (``static_arm``); slipping
    it gives the kinetic friction (``kinetic_arm``, which may be 0).
    """
    ka, kh = kinetic_arm(AXLE, p), kinetic_arm(HINGE, p)
    stuck_a = sa == 0.0 and static_arm(AXLE, p) > 0.0
    stuck_h = sh == 0.0 and static_arm(HINGE, p) > 0.0
    on_base = p.mub > 0.0 and sb != 0.0
    inverse_ka2 = 1.0 / (ka * ka) if ka > 0.0 else 0.0
    inverse_kh2 = 1.0 / (kh * kh) if kh > 0.0 else 0.0
    ta, th, fb = 0.0, 0.0, 0.0
    for iteration in range(FRICTION_ITERATIONS):
        ax = base[0] + ta * unit_a[0] + th * unit_h[0] + fb * unit_b[0]
        ay = base[1] + ta * unit_a[1] + th * unit_h[1] + fb * unit_b[1]
        hx = base[2] + ta * unit_a[2] + th * unit_h[2] + fb * unit_b[2]
        hy = base[3] + ta * unit_a[3] + th * unit_h[3] + fb * unit_b[3]
        # curve_a, curve_h: a slipping row's k / |load|, its curvature (inf at a zero load, where it
        # is not smooth); 0 for an affine row (stuck, or without friction).
        curve_a, curve_h = 0.0, 0.0
        if stuck_a:
            r1 = base[5] + ta * unit_a[5] + th * unit_h[5] + fb * unit_b[5]
            j11, j12, j13 = unit_a[5], unit_h[5], unit_b[5]
        elif ka > 0.0:
            size = math.sqrt(ax * ax + ay * ay)
            r1 = ta + ka * sa * size
            g = ka * sa / size if size > 0.0 else 0.0
            curve_a = ka / size if size > 0.0 else math.inf
            j11 = 1.0 + g * (ax * unit_a[0] + ay * unit_a[1])
            j12 = g * (ax * unit_h[0] + ay * unit_h[1])
            j13 = g * (ax * unit_b[0] + ay * unit_b[1])
        else:
            r1, j11, j12, j13 = ta, 1.0, 0.0, 0.0
        if stuck_h:
            r2 = base[6] + ta * unit_a[6] + th * unit_h[6] + fb * unit_b[6]
            j21, j22, j23 = unit_a[6], unit_h[6], unit_b[6]
        elif kh > 0.0:
            size = math.sqrt(hx * hx + hy * hy)
            r2 = th + kh * sh * size
            g = kh * sh / size if size > 0.0 else 0.0
            curve_h = kh / size if size > 0.0 else math.inf
            j21 = g * (hx * unit_a[2] + hy * unit_a[3])
            j22 = 1.0 + g * (hx * unit_h[2] + hy * unit_h[3])
            j23 = g * (hx * unit_b[2] + hy * unit_b[3])
        else:
            r2, j21, j22, j23 = th, 0.0, 1.0, 0.0
        if on_base:
            normal = base[4] + ta * unit_a[4] + th * unit_h[4] + fb * unit_b[4]
            r3 = fb + p.mub * sb * normal
            j31, j32, j33 = p.mub * sb * unit_a[4], p.mub * sb * unit_h[4], 1.0 + p.mub * sb * unit_b[4]
            da, dh, db = _solve3(j11, j12, j13, j21, j22, j23, j31, j32, j33, r1, r2, r3)
            # |J^-1 e|_1 <= sum over j of e_j |row j of J's cofactors| / |det J|, for e = (e1, e2, 0)
            c11, c12, c13, c21, c22, c23, det = _cofactors3(j11, j12, j13, j21, j22, j23, j31, j32, j33)
            c1, c2, det = abs(c11) + abs(c12) + abs(c13), abs(c21) + abs(c22) + abs(c23), abs(det)
        else:   # F = 0: _solve3 with the row (0, 0, 1) and r3 = 0, term for term (the same bits)
            da, dh = _solve2(j11, j12, j21, j22, r1, r2)
            db = 0.0
            c1, c2, det = abs(j22) + abs(j21), abs(j12) + abs(j11), abs(j11 * j22 - j12 * j21)
        ta, th, fb = ta - da, th - dh, fb - db
        scale = FRICTION_STEP_TOLERANCE * (abs(ta) + abs(th) + abs(fb))
        if abs(da) + abs(dh) + abs(db) <= scale:
            break
        if iteration == 0:   # (the first update, from 0, is never the last but in an affine system)
            continue
        # The next update, bounded [10.3]: at the new unknowns each affine row's residual is 0, and a
        # slipping row's is k (|L + dL| - |L| - L.dL / |L|) for its load L and the load's change dL:
        # between 0 and k |dL_across|^2 / |L| while L.dL >= -|L|^2 / 2 (|dL_across|: dL's part across
        # L). The next update is J^-1 of those residuals; twice the bound allows for J at the new
        # unknowns (its slipping rows turn with L, by |dL_across| / |L|, 1e-7 or less where this
        # test can pass). Below the tolerance, that update is not taken: the unknowns are already
        # those it would give, to within the tolerance.
        dax = da * unit_a[0] + dh * unit_h[0] + db * unit_b[0]
        day = da * unit_a[1] + dh * unit_h[1] + db * unit_b[1]
        dhx = da * unit_a[2] + dh * unit_h[2] + db * unit_b[2]
        dhy = da * unit_a[3] + dh * unit_h[3] + db * unit_b[3]
        e1 = _linearisation_error(curve_a, inverse_ka2, ax, ay, dax, day)
        e2 = _linearisation_error(curve_h, inverse_kh2, hx, hy, dhx, dhy)
        if 2.0 * (c1 * e1 + c2 * e2) <= scale * det:
            break
    return ta, th, fb


def _size(x, y):
    """|(x, y)|; not math.hypot, whose last bit may differ between CPython and the C library."""
    return math.sqrt(x * x + y * y)


def _combine(base, unit_a, unit_h, unit_b, ta, th, fb, i):
    return base[i] + ta * unit_a[i] + th * unit_h[i] + fb * unit_b[i]


def swing_friction(theta, phi, psi, dtheta, dphi, dpsi, sa, sh, p):
    """Stage 2 with friction [10.3]: a ``SwingFriction`` ``(theta'', phi'', psi'', ta, th, |A|, |H|)``.

    ``sa``, ``sh``: the axle's and the hinge's modes (+1/-1 slipping with the
    rate's sign, 0 stuck). A stuck joint's acceleration is exactly 0 and its
    torque (``ta``, ``th``) is the one that holds it.
    """
    m11, m12, m13, m22, m23, m33, f1, f2, f3 = swing_terms(theta, phi, psi, dtheta, dphi, dpsi, p)
    a1, a2, a3 = solve_symmetric(m11, m12, m13, m22, m23, m33, f1, f2, f3)
    # The responses to a unit torque at the axle and at the hinge: M^-1's first two columns.
    c11, c12, c13, c22, c23, _, det = symmetric_cofactors(m11, m12, m13, m22, m23, m33)
    ua1, ua2, ua3 = c11 / det, c12 / det, c13 / det
    if FLOATING_ARM and p.kind == FLOATING:
        slides = slides_friction(theta, psi, dtheta, dpsi, a1, a3, 0.0, ua1, ua3, 0.0, sa, p)
        return SwingFriction(slides.ddtheta, 0.0, slides.ddpsi, slides.generalised_force, slides.guide_force,
                             slides.hold, slides.track_force)
    uh1, uh2, uh3 = c12 / det, c22 / det, c23 / det
    return _joints(theta, phi, psi, dtheta, dphi, dpsi, a1, a2, a3, ua1, ua2, ua3, uh1, uh2, uh3, sa, sh, p)


def machine_friction(theta, phi, dtheta, dphi, sa, sh, m):
    """After release, with friction [10.9]: a ``MachineFriction`` ``(theta'', phi'', ta, th, |A|, |H|)``.

    ``m`` is the design's numbers without the projectile (``stages.machine_params``):
    ``swing_friction`` with the psi row and column gone (``eom.machine_terms``)
    and no sling force. ``sa``, ``sh`` as in ``swing_friction``.
    """
    m11, m12, m22, f1, f2 = machine_terms(theta, phi, dtheta, dphi, m)
    a1, a2 = solve_pair(m11, m12, m22, f1, f2)
    ua1, ua2 = solve_pair(m11, m12, m22, 1.0, 0.0)
    if FLOATING_ARM and m.kind == FLOATING:
        slides = slides_friction(theta, 0.0, dtheta, 0.0, a1, 0.0, 0.0, ua1, 0.0, 0.0, sa, m)
        return MachineFriction(slides.ddtheta, 0.0, slides.generalised_force, slides.guide_force, slides.hold,
                               slides.track_force)
    uh1, uh2 = solve_pair(m11, m12, m22, 0.0, 1.0)
    ddtheta, ddphi, _, ta, th, axle, hinge = _joints(theta, phi, 0.0, dtheta, dphi, 0.0, a1, a2, 0.0, ua1, ua2,
                                                     0.0, uh1, uh2, 0.0, sa, sh, m)
    return MachineFriction(ddtheta, ddphi, ta, th, axle, hinge)


def _joints(theta, phi, psi, dtheta, dphi, dpsi, a1, a2, a3, ua1, ua2, ua3, uh1, uh2, uh3, sa, sh, p):
    """The axle's and the hinge's friction off the base [10.3], from the accelerations without
    friction ``a`` and per unit of ta (``ua``) and th (``uh``): a ``SwingFriction``."""
    bx, by, bhx, bhy, _, _ = joint_forces(theta, phi, psi, dtheta, dphi, dpsi, a1, a2, a3, 0.0, p)
    rax, ray, rahx, rahy = _force_response(theta, phi, psi, ua1, ua2, ua3, 0.0, 0.0, p)
    rhx, rhy, rhhx, rhhy = _force_response(theta, phi, psi, uh1, uh2, uh3, 0.0, 0.0, p)
    base = (bx, by, bhx, bhy, 0.0, a1, a2)
    unit_a = (rax, ray, rahx, rahy, 0.0, ua1, ua2)
    unit_h = (rhx, rhy, rhhx, rhhy, 0.0, uh1, uh2)
    unit_b = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    ta, th, _ = friction_newton(base, unit_a, unit_h, unit_b, sa, sh, 0.0, p)
    ddtheta = a1 + ta * ua1 + th * uh1
    ddphi = a2 + ta * ua2 + th * uh2
    ddpsi = a3 + ta * ua3 + th * uh3
    if sa == 0.0 and static_arm(AXLE, p) > 0.0:
        ddtheta = 0.0
    if sh == 0.0 and static_arm(HINGE, p) > 0.0:
        ddphi = 0.0
    axle = _size(_combine(base, unit_a, unit_h, unit_b, ta, th, 0.0, 0),
                  _combine(base, unit_a, unit_h, unit_b, ta, th, 0.0, 1))
    hinge = _size(_combine(base, unit_a, unit_h, unit_b, ta, th, 0.0, 2),
                  _combine(base, unit_a, unit_h, unit_b, ta, th, 0.0, 3))
    return SwingFriction(ddtheta, ddphi, ddpsi, ta, th, axle, hinge)


def slide_rate(theta, s, sin_beta, p):
    """``dx_P/dtheta`` along the base constraint: the projectile's slide over the base per
    radian of the arm, m (its velocity over the base is this times theta') [10.5]."""
    cos_beta = -(p.h + p.La * math.cos(theta)) / p.Ls
    return -(p.La * math.cos(theta) + p.Ls * cos_beta) - s * p.Ls * cos_beta


def _slide_response(a, b, e, det, m13, m23, m33, s, c, lever, q1, q2, q_psi):
    """Stage 1's ``(theta'', phi'', psi'', N)`` for reduced generalised forces ``(q1, q2)`` and
    psi-row force ``q_psi`` (eqs. 4.4, 4.6); ``c`` 0 for the part linear in the forces."""
    ddtheta = (q1 * e - q2 * b) / det
    ddphi = (q2 * a - q1 * b) / det
    ddpsi = s * ddtheta + c
    return ddtheta, ddphi, ddpsi, (m13 * ddtheta + m23 * ddphi + m33 * ddpsi - q_psi) / lever


def slide_friction(theta, phi, dtheta, dphi, sa, sh, sb, p):
    """Stage 1 with friction [10.3], [10.5]: a ``SlideFriction``
    ``(theta'', phi'', N, ta, th, F, |A|, |H|, dx_P/dtheta)``.

    ``sa``, ``sh`` as in ``swing_friction``; ``sb`` the sign of the
    projectile's slide over the base (the base's friction ``F = -mub sb N``
    opposes it). N is the multiplier of the base constraint from the psi row
    of ``M q'' = f + Q + J^T N``, Q including the friction's ``F dx_P/dpsi``.
    """
    a, b, e, r1, r2, m13, m23, m33, f3, s, c, sin_beta = slide_system(theta, phi, dtheta, dphi, p)
    psi, dpsi, _, _, _ = slide_constraint(theta, dtheta, p)
    dx = slide_rate(theta, s, sin_beta, p)
    dx_dpsi = -p.Ls * math.cos(theta + psi)
    det = a * e - b * b
    lever = -p.Ls * sin_beta

    a1, a2, a3, n0 = _slide_response(a, b, e, det, m13, m23, m33, s, c, lever, r1, r2, f3)
    ua1, ua2, ua3, uan = _slide_response(a, b, e, det, m13, m23, m33, s, 0.0, lever, 1.0, 0.0, 0.0)
    if FLOATING_ARM and p.kind == FLOATING:
        slides = slides_friction(theta, psi, dtheta, dpsi, a1, a3, n0, ua1, ua3, uan, sa, p)
        return SlideFriction(slides.ddtheta, 0.0, slides.normal, slides.generalised_force, slides.guide_force,
                             slides.track_force, slides.hold, 0.0, dx)
    uh1, uh2, uh3, uhn = _slide_response(a, b, e, det, m13, m23, m33, s, 0.0, lever, 0.0, 1.0, 0.0)
    ub1, ub2, ub3, ubn = _slide_response(a, b, e, det, m13, m23, m33, s, 0.0, lever, dx, 0.0, dx_dpsi)
    bx, by, bhx, bhy, _, _ = joint_forces(theta, phi, psi, dtheta, dphi, dpsi, a1, a2, a3, n0, p)
    rax, ray, rahx, rahy = _force_response(theta, phi, psi, ua1, ua2, ua3, uan, 0.0, p)
    rhx, rhy, rhhx, rhhy = _force_response(theta, phi, psi, uh1, uh2, uh3, uhn, 0.0, p)
    rbx, rby, rbhx, rbhy = _force_response(theta, phi, psi, ub1, ub2, ub3, ubn, 1.0, p)
    base = (bx, by, bhx, bhy, n0, a1, a2)
    unit_a = (rax, ray, rahx, rahy, uan, ua1, ua2)
    unit_h = (rhx, rhy, rhhx, rhhy, uhn, uh1, uh2)
    unit_b = (rbx, rby, rbhx, rbhy, ubn, ub1, ub2)
    ta, th, fb = friction_newton(base, unit_a, unit_h, unit_b, sa, sh, sb, p)
    ddtheta = a1 + ta * ua1 + th * uh1 + fb * ub1
    ddphi = a2 + ta * ua2 + th * uh2 + fb * ub2
    if sa == 0.0 and static_arm(AXLE, p) > 0.0:
        ddtheta = 0.0
    if sh == 0.0 and static_arm(HINGE, p) > 0.0:
        ddphi = 0.0
    normal = _combine(base, unit_a, unit_h, unit_b, ta, th, fb, 4)
    axle = _size(_combine(base, unit_a, unit_h, unit_b, ta, th, fb, 0),
                  _combine(base, unit_a, unit_h, unit_b, ta, th, fb, 1))
    hinge = _size(_combine(base, unit_a, unit_h, unit_b, ta, th, fb, 2),
                  _combine(base, unit_a, unit_h, unit_b, ta, th, fb, 3))
    return SlideFriction(ddtheta, ddphi, normal, ta, th, fb, axle, hinge, dx)


def rest_balance(p):
    """The torques on the arm at rest, held still, N m [10.7]: ``(drive, axle_hold, base_hold)``.

    ``drive`` is gravity's generalised force turning the arm clockwise (the
    reduced stage-1 ``-r1`` at rest: the counterweight's and the arm's
    weights; the projectile's cancels on the base). The most friction can
    hold against it, static friction at rest [10.9]: the base's
    ``mub_s N |dx_P/dtheta|`` (its friction on the projectile at its limit,
    pulled along the flat sling) and the axle's ``mua_s ra |A|`` with the
    axle's load ``A`` at rest under that friction. The machine fires when
    ``drive > axle_hold + base_hold``.
    """
    theta, phi = p.theta0, p.phi0
    system = slide_system(theta, phi, 0.0, 0.0, p)
    r1 = system.r1
    psi, _, _, _, _ = slide_constraint(theta, 0.0, p)
    if FLOATING_ARM and p.kind == FLOATING:   # the axle's, the guide's and the track's hold together; no base friction [12.11]
        return -r1, slide_friction(theta, phi, 0.0, 0.0, 0.0, 0.0, 0.0, p).axle_load, 0.0
    normal = -system.f3 / (-p.Ls * system.sin_beta)
    dx = slide_rate(theta, system.s, system.sin_beta, p)
    base_force = p.mub_s * normal if dx >= 0.0 else -p.mub_s * normal
    ax, ay, _, _, _, _ = joint_forces_sliding(theta, phi, psi, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, normal,
                                              base_force, p)
    return -r1, static_arm(AXLE, p) * _size(ax, ay), base_force * dx


# --------------------------------------------------------------------------- #
# The floating arm's guide and track [12.8]
# --------------------------------------------------------------------------- #
# The guide's friction fg acts vertically on the counterweight (its sliding is
# y_W' = Lb sin(theta) theta'), the track's ft horizontally on the axle
# (x_A' = -Lb cos(theta) theta'): both slide exactly when the arm turns, so they
# share the axle's mode sa. By virtual work all three act on theta alone, with
# Q = ta + Lb sin(theta) fg - Lb cos(theta) ft [12.9]; the supports' normal forces
# are the momentum balance (12.6) less the other support's friction,
# G = sum m a_x - ft and T = sum m (a_y + g) - N - fg, and the axle's pin carries the
# (massless) carriage's load (ft, T) [12.10].

class SlidesFriction(NamedTuple):
    """A floating arm's friction and motion (``slides_friction``): theta'' and psi'', rad/s^2; the base's
    push N, N; the friction's generalised force on theta, N m; the axle's torque, N m; the guide's and
    the track's friction forces, N; and the hold (slipping: the carriage's load ``|(ft, T)|``, N; stuck:
    the most static friction can hold, N m)."""

    ddtheta: float
    ddpsi: float
    normal: float
    generalised_force: float
    axle_torque: float
    guide_force: float
    track_force: float
    hold: float


#: ``slides_newton`` takes a sign choice's solution when its equations' residual is within this of the
#: forces: a solution leaves round-off times the 3x3 Jacobian's condition (at most 2e-14 of the forces
#: over 800 random stage-2 states with coefficients up to 2), Newton's cycling where there is none O(1).
SLIDES_RESIDUAL = 1e-9


def slides_lossy(p):
    """Whether a floating arm has friction on its guide or its track (static coefficients tell)."""
    return p.mug_s > 0.0 or p.mut_s > 0.0


def holders(p):
    """``(axle, guide, track)``: which joints' static friction holds the arm at rest, for the message
    that says so (``outcome.friction_holders``); a hinged or fixed machine's is its axle's (the base's
    is weighed apart)."""
    if not slides_lossy(p):
        return True, False, False
    return p.mua_s > 0.0, p.mug_s > 0.0, p.mut_s > 0.0


def _sign(x):
    return 1.0 if x > 0.0 else (-1.0 if x < 0.0 else 0.0)


def slides_newton(theta, sa, guide0, guide_u, track0, track_u, ka, kg, kt, p):
    """The floating arm's friction ``(ta, fg, ft)`` slipping with mode ``sa`` (+1/-1) [12.10]:
    ``ta + ka sa |(ft, T)| = 0``, ``fg + kg sg |G| = 0``, ``ft + kt st |T| = 0``.

    ``sg = sa sign(sin theta)`` and ``st = -sa sign(cos theta)`` are the signs of the counterweight's
    and the axle's sliding; ``G = guide0 + Q guide_u - ft`` and ``T = track0 + Q track_u - fg`` with
    ``Q = ta + Lb sin(theta) fg - Lb cos(theta) ft``: the supports' forces without the slides'
    friction at ``Q = 0`` and their change per unit of Q (0 for a held arm). ``ka = mu r`` of the
    axle, ``kg``, ``kt`` the guide's and the track's coefficients (kinetic, or static for the hold).

    With the signs of G and T chosen the system is smooth (linear but for ``|(ft, T)|``): each
    choice is solved by Newton's method, the frictionless forces' signs first, and the first whose
    solution has the signs it assumed is taken. None has with large coefficients, where the guide
    and the track jam (Coulomb's law has no slipping motion): NaN, so that the integrator rejects
    the step, and the shot fails if it cannot pass.
    """
    first_g = -1.0 if guide0 < 0.0 else 1.0
    first_t = -1.0 if track0 < 0.0 else 1.0
    for k in range(4):
        eg = first_g if k % 2 == 0 else -first_g
        et = first_t if k < 2 else -first_t
        ta, fg, ft, guide, track = _slides_signed(theta, sa, guide0, guide_u, track0, track_u, ka, kg, kt, eg,
                                                  et, p)
        if (kg == 0.0 or eg * guide >= 0.0) and (kt == 0.0 or et * track >= 0.0):
            return ta, fg, ft
    return math.nan, math.nan, math.nan


def _slides_signed(theta, sa, guide0, guide_u, track0, track_u, ka, kg, kt, eg, et, p):
    """``slides_newton``'s system with G's sign ``eg`` and T's ``et`` given: ``(ta, fg, ft, G, T)``,
    NaN if Newton's method leaves a residual beyond ``SLIDES_RESIDUAL``."""
    ls, lc = p.Lb * math.sin(theta), p.Lb * math.cos(theta)
    wg, wt = kg * sa * _sign(ls) * eg, -kt * sa * _sign(lc) * et   # fg + wg G = 0, ft + wt T = 0
    # d(G, T)/d(ta, fg, ft): through Q, and each less the other support's friction.
    g1, g2, g3 = guide_u, ls * guide_u, -lc * guide_u - 1.0
    t1, t2, t3 = track_u, ls * track_u - 1.0, -lc * track_u
    ta, fg, ft = 0.0, 0.0, 0.0
    for _ in range(FRICTION_ITERATIONS):
        q = ta + ls * fg - lc * ft
        guide = guide0 + q * guide_u - ft
        track = track0 + q * track_u - fg
        axle = _size(ft, track)
        wa = ka * sa / axle if axle > 0.0 else 0.0
        da, dg, dt = _solve3(1.0 + wa * track * t1, wa * track * t2, wa * (ft + track * t3),
                             wg * g1, 1.0 + wg * g2, wg * g3,
                             wt * t1, wt * t2, 1.0 + wt * t3,
                             ta + ka * sa * axle, fg + wg * guide, ft + wt * track)
        ta, fg, ft = ta - da, fg - dg, ft - dt
        if abs(da) + abs(dg) + abs(dt) <= FRICTION_STEP_TOLERANCE * (abs(ta) + abs(fg) + abs(ft)):
            break
    q = ta + ls * fg - lc * ft
    guide = guide0 + q * guide_u - ft
    track = track0 + q * track_u - fg
    residual = abs(ta + ka * sa * _size(ft, track)) + abs(fg + wg * guide) + abs(ft + wt * track)
    if not residual <= SLIDES_RESIDUAL * (abs(guide0) + abs(track0) + abs(ta) + abs(fg) + abs(ft)):
        return math.nan, math.nan, math.nan, math.nan, math.nan
    return ta, fg, ft, guide, track


def slides_friction(theta, psi, dtheta, dpsi, a1, a3, n0, ua1, ua3, uan, sa, p):
    """A floating arm's friction and motion [12.10] from its accelerations without friction
    ``(a1, a3, n0)`` (theta'', psi'', the base's push N) and their change per unit of Q on theta
    ``(ua1, ua3, uan)``; ``sa`` is the mode.

    Returns a ``SlidesFriction`` ``(theta'', psi'', N, Q, ta, fg, ft, hold)``: Q the friction's generalised force on theta
    (N m), ta the axle's torque, fg and ft the guide's and the track's forces (N). Slipping,
    ``hold`` is |(ft, T)|. Stuck (``sa`` 0), theta'' = 0, Q holds the arm, and ``hold`` is the most
    static friction can (N m, ``static_arm`` being 1): every friction at its static limit against
    the way Q's absence would turn the arm, at the held arm's forces; the three share the hold in
    those proportions [12.11].
    """
    total_g = moving_mass(p) * p.g
    track_u, guide_u = support_forces(theta, psi, 0.0, 0.0, ua1, ua3, uan, p)   # per unit Q: no drag
    track_u -= total_g
    if sa != 0.0:
        track0, guide0 = floating_supports_in_air(theta, psi, dtheta, dpsi, a1, a3, n0, p)
        ta, fg, ft = slides_newton(theta, sa, guide0, guide_u, track0, track_u, kinetic_arm(AXLE, p), p.mug,
                                   p.mut, p)
        q = ta + p.Lb * math.sin(theta) * fg - p.Lb * math.cos(theta) * ft
        track = track0 + q * track_u - fg
        return SlidesFriction(a1 + q * ua1, a3 + q * ua3, n0 + q * uan, q, ta, fg, ft, _size(ft, track))
    q = -a1 / ua1
    ddpsi, normal = a3 + q * ua3, n0 + q * uan
    track0, guide0 = floating_supports_in_air(theta, psi, dtheta, dpsi, 0.0, ddpsi, normal, p)
    ta, fg, ft = slides_newton(theta, 1.0 if q < 0.0 else -1.0, guide0, 0.0, track0, 0.0,
                               p.mua_s * p.ra, p.mug_s, p.mut_s, p)
    hold = ta + p.Lb * math.sin(theta) * fg - p.Lb * math.cos(theta) * ft
    share = q / hold if hold != 0.0 else 0.0
    return SlidesFriction(0.0, ddpsi, normal, q, share * ta, share * fg, share * ft, abs(hold))
