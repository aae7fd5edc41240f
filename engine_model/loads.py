"""The loads a builder sizes the machine for, from the engine's bodies: each one's momentum change over a step.

The same five as the analytic model's (``analytic.eom.loads``, in the order of
``analytic.stages.LOAD_NAMES``): the force of the frame on the arm at the axle,
the force between the arm and the counterweight at the hinge, the sling's
tension, the projectile's felt acceleration (the sling's and the base's
force on it over its mass, gravity excluded) and the bending moment the arm's
cross-section at the axle carries.

pymunk reports only the size of a joint's impulse, and the pivot joint also
carries any ballast the engine put at the pivot (``engine_model.build``), which
the real axle does not. So each load is taken from Newton's law on the design's
own bodies instead: over the step at t_k a body's velocity changes from
t_k - dt/2 to t_k + dt/2 (raw rows, ``engine_model.kinematics``), and

* hinge: ``H = m_W (a_W + g e_y)``, the counterweight's only outside force
  but its weight (the hinge's friction is a pure torque, or for a point
  counterweight a force through the hinge, part of H);
* projectile: ``m_P (a_P + g e_y)``, the sling's and the base's force on it;
* axle: ``A = m_A (a_A + g e_y) + H + S``, the arm's own balance, with
  ``-H`` and the sling's pull ``-S`` on it, ``S = T u`` the sling's force on the
  projectile (``T`` the tension the shot measured, ``u`` the unit vector from
  the projectile to the long tip); ``a_A`` is the acceleration of the arm's
  centre of mass, the design's, without ballast;
* a sling with mass (a uniform rod, ``machine.sling_mass``) and the pouch: the
  projectile's body carries the pouch until release, so ``S`` is the sling's force on
  both, ``T u + S_n n`` with the rod's push across itself ``S_n``
  (``kinematics.sling_shear``; 0 for a massless sling), and the long tip pulls on the
  rod with ``S_A = S + m_s (a_c + g e_y)``, ``a_c`` the rod centre's acceleration (the
  mean of its ends'): ``S_A`` takes the place of ``S`` on the arm below;
* bending moment at the axle: the long side (axle to long tip, a uniform
  rod of mass ``m_L``, ``analytic.geometry.arm_long_side``) as a body of its
  own, Newton-Euler about its centre C:
  ``M = I_C w' + m_L (C - O) x (a_C + g e_y) + (tip - O) x S``, O the axle, with ``w'``
  the arm body's angular acceleration, ``a_C`` the acceleration of the arm
  body's point at C (whatever the axle does) and ``I_C = m_L La^2 / 12``.
"""

from __future__ import annotations

import numpy as np

from analytic.design import Design
from analytic.geometry import arm_long_side
from engine_model import kinematics as kin


def accelerations(raw: np.ndarray, body_velocity: np.ndarray, dt: float) -> np.ndarray:
    """(n, 2) accelerations over each raw row's step, m/s^2, from (n, 2) velocities at t_k + dt/2.

    Row 0's velocities belong to dt/2 after the opening half step from rest;
    those at -dt/2 are their mirror image (``kinematics.synchronise``).
    """
    before = np.vstack([-body_velocity[:1], body_velocity[:-1]])
    return (body_velocity - before) / dt


def load_histories(raw: np.ndarray, tension: np.ndarray, design: Design, dt: float,
                   slide_friction: np.ndarray | None = None) -> np.ndarray:
    """The loads over each raw row's step, shape (n, 5): axle (N), hinge (N), sling tension (N),
    the projectile's felt acceleration (m/s^2) and the arm's bending moment at the axle (N m).

    Parameters
    ----------
    raw : (n, 24) rows as read after each step of stages 1-2 (``kinematics``).
    tension : (n,) the sling's tension over each row's step, N (``kinematics.contact_forces``).
    dt : the step, s.
    slide_friction : a floating arm's (n, 2) friction of its track (x, on the axle) and its guide
        (y, on the counterweight), N (``engine_model.friction.slide_forces``); None: none.
    """
    up = np.array([0.0, design.environment.gravity])
    hinge = design.machine.counterweight_mass * (accelerations(raw, kin.velocity(raw, kin.COUNTERWEIGHT), dt) + up)
    felt = accelerations(raw, kin.velocity(raw, kin.PROJECTILE), dt) + up
    sling = tip_force(raw, sling_force(raw, tension, design, dt), design, dt)
    axle = support_force(raw, sling, design, dt)
    bending = bending_moment(raw, sling, design, dt)
    if design.machine.kind == "floating-arm":
        # The axle's force is the track's, its push (y) and its friction (x); the guide's push (x) and
        # friction (y) act on the counterweight, so its mount carries the counterweight's force less
        # the guide's (``analytic.eom.joint_forces``).
        friction = np.zeros_like(axle) if slide_friction is None else slide_friction
        normal = axle - friction
        hinge = hinge - np.column_stack([normal[:, 0], friction[:, 1]])
        axle = np.column_stack([friction[:, 0], normal[:, 1]])
    return np.column_stack([np.linalg.norm(axle, axis=1), np.linalg.norm(hinge, axis=1), tension,
                            np.linalg.norm(felt, axis=1), np.abs(bending)])


def bending_moment(raw: np.ndarray, sling: np.ndarray, design: Design, dt: float) -> np.ndarray:
    """The moment of the short side on the long side across the arm's section at the axle over each
    raw row's step, (n,) N m (counter-clockwise positive), from (n, 2) ``sling``, the sling's force
    on the projectile, N (the module's docstring)."""
    m, g = design.machine, design.environment.gravity
    mass, _, second = arm_long_side(m.arm_long, m.arm_short, m.arm_mass, m.arm_cg)
    axle = kin.arm_point(raw, 0.0)
    centre = kin.arm_point(raw, 0.5 * m.arm_long) - axle
    tip = kin.long_tip(raw, design) - axle
    centre_acceleration = accelerations(raw, kin.point_velocity(raw, kin.ARM, centre + axle), dt)
    spin = accelerations(raw, kin.column(raw, kin.ARM, kin.W)[:, None], dt)[:, 0]
    inertia = second - mass * (0.5 * m.arm_long) ** 2
    return (inertia * spin + mass * _cross(centre, centre_acceleration + np.array([0.0, g]))
            + _cross(tip, sling))


def _cross(r: np.ndarray, f: np.ndarray) -> np.ndarray:
    """The z components of (n, 2) x (n, 2) planar cross products."""
    return r[:, 0] * f[:, 1] - r[:, 1] * f[:, 0]


def sling_force(raw: np.ndarray, tension: np.ndarray, design: Design, dt: float | None = None) -> np.ndarray:
    """(n, 2) the sling's force on the projectile (and the pouch) over each raw row's step, N: its
    ``tension`` along the sling, towards the long arm's tip; a sling with mass also pushes across
    itself (``kinematics.sling_shear``, from the rows' steps of ``dt``)."""
    offset = kin.long_tip(raw, design) - kin.position(raw, kin.PROJECTILE)
    if not design.machine.sling_mass > 0.0:
        return tension[:, None] * offset / np.linalg.norm(offset, axis=1)[:, None]
    unit = offset / np.linalg.norm(offset, axis=1)[:, None]
    shear = np.array([kin.sling_shear(before, row, design, dt) for before, row in zip(_before(raw), raw)])
    return tension[:, None] * unit + shear[:, None] * np.column_stack([-unit[:, 1], unit[:, 0]])


def tip_force(raw: np.ndarray, sling: np.ndarray, design: Design, dt: float) -> np.ndarray:
    """(n, 2) the long tip's pull on the sling over each raw row's step, N: ``sling`` (its force on the
    projectile, ``sling_force``) for a massless sling; with mass, that and the rod's own momentum
    change and weight, ``m_s (a_c + g e_y)``."""
    m = design.machine
    if not m.sling_mass > 0.0:
        return sling
    tip = kin.long_tip(raw, design)
    centre = 0.5 * (kin.point_velocity(raw, kin.ARM, tip) + kin.velocity(raw, kin.PROJECTILE))
    return sling + m.sling_mass * (accelerations(raw, centre, dt) + np.array([0.0, design.environment.gravity]))


def _before(raw: np.ndarray) -> np.ndarray:
    """Each raw row's row before (the opening half step's: its mirror image, velocities reversed;
    ``accelerations``)."""
    mirrored = raw[:1].copy()
    velocity_columns = [body + q for body in kin.BODIES for q in (kin.VX, kin.VY, kin.W)]
    mirrored[:, velocity_columns] *= -1.0
    return np.vstack([mirrored, raw[:-1]])


def support_force(raw: np.ndarray, sling: np.ndarray, design: Design, dt: float) -> np.ndarray:
    """(n, 2) force of the supports on the arm and its counterweight over each raw row's step, N:
    ``m_A (a_A + g e_y) + m_W (a_W + g e_y) + S_A`` (the module's notes; ``sling`` from
    ``tip_force``). For a hinged or fixed machine the axle's force; for a floating arm the
    guide's push (x) and the track's (y) together, the only supports of the arm and counterweight
    besides the sling."""
    m = design.machine
    up = np.array([0.0, design.environment.gravity])
    arm_velocity = kin.point_velocity(raw, kin.ARM, kin.arm_centre(raw, design))
    hinge = m.counterweight_mass * (accelerations(raw, kin.velocity(raw, kin.COUNTERWEIGHT), dt) + up)
    return m.arm_mass * (accelerations(raw, arm_velocity, dt) + up) + hinge + sling


#: Steps after the opening half step whose loads are left out of the peaks: pymunk's solver starts
#: each step from the impulses of the step before, and after the opening half step (converged from
#: nothing, ``shot.STARTUP_ITERATIONS``) it rings for about a dozen steps on a machine with a light
#: arm (ballast at the pivot), whatever the step: the counterweight's load swung by 2 % at 5e-5 s
#: and at 2.5e-5 s alike on ``sample-0-015-light`` of the cross-check, whose largest hinge and
#: axle loads are at rest, and fell to 1e-6 by the 12th step and 1e-7 by the 14th (compared with
#: runs at half and a quarter of the step). The machine's velocities move by a fraction of a
#: step's change, which no other quantity shows. The load at rest (the opening half step's) is kept.
SETTLING_STEPS = 20


def peaks(loads: np.ndarray, times: np.ndarray, joined: np.ndarray | None = None) -> list[tuple[float, float]]:
    """Each column's largest value and its time (``peak``), on (n, k) ``loads`` at (n,) ``times``: over
    the rest state and the rows from ``SETTLING_STEPS`` on (all rows of a shot that short).

    ``joined``: (n - 1,) whether rows i and i + 1 lie on one smooth stretch of the loads (None: all
    do); a friction joint that sticks or breaks free makes them jump between two (``friction.smooth``).
    """
    joined = np.ones(max(len(times) - 1, 0), dtype=bool) if joined is None else joined
    found = []
    for values in loads.T:
        if len(values) <= SETTLING_STEPS:
            found.append(peak(values, times, joined))
            continue
        later = peak(values[SETTLING_STEPS:], times[SETTLING_STEPS:], joined[SETTLING_STEPS:])
        found.append(later if later[0] >= values[0] else (float(values[0]), float(times[0])))
    return found


def peak(values: np.ndarray, times: np.ndarray, joined: np.ndarray | None = None) -> tuple[float, float]:
    """The largest value of a sampled load and its time, s: the vertex of the parabola through the
    largest sample and its neighbours on the regular grid, where all three lie on one smooth stretch
    (``joined``, (n - 1,): rows i and i + 1 do; None: all do); at the end of a stretch that a jump
    ends, its line carried on to the jump (``stretch_end``); otherwise the sample itself, as where it
    is not a maximum or is the last sample (the release instant, off the grid).

    A parabola through a jump has its vertex far above both sides: a load falling by ``J`` between
    two samples after a flat top gives one ``J / 8`` over the top, a peak no machine has.
    """
    i = int(np.argmax(values))
    if joined is not None and 0 < i < len(values) - 2 and joined[i - 1] and not joined[i]:
        return stretch_end(values[i - 1:i + 3], times[i], times[i + 1] - times[i])
    if not (0 < i < len(values) - 2 and (joined is None or (joined[i - 1] and joined[i]))):
        return float(values[i]), float(times[i])
    before, at, after = values[i - 1], values[i], values[i + 1]
    curvature = before - 2.0 * at + after
    if curvature >= 0.0:
        return float(at), float(times[i])
    shift = 0.5 * (before - after) / curvature
    step = times[i + 1] - times[i]
    return float(at + 0.25 * (after - before) * shift), float(times[i] + shift * step)


def stretch_end(values: np.ndarray, time: float, step: float) -> tuple[float, float]:
    """A load's value and time where its stretch ends in a jump, from the (4,) samples: the stretch's
    last two (the second at ``time``), the step in which it jumps, and the next stretch's first.

    The jump's step holds the load over the step (a momentum change): the old stretch's up to the
    jump, the new one's after it. With the old stretch's line ``A`` at that step and the new one's
    first sample ``B``, the sample is ``f A + (1 - f) B``, ``f`` the step's fraction before the jump.
    The stretch's last sample alone misses the value at the jump by up to 1.5 steps of its slope.
    """
    before, at, mixed, new = values
    old = 2.0 * at - before
    fraction = float(np.clip((mixed - new) / (old - new), 0.0, 1.0)) if old != new else 0.0
    reach = 0.5 + fraction   # steps from ``time``: the jump's step starts half a step after it
    return float(at + (at - before) * reach), float(time + reach * step)
