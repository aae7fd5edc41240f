"""The loads a builder sizes the machine for, from the engine's bodies: each one's momentum change over a step.

The same four as the analytic model's (``analytic.eom.loads``, in the order of
``analytic.stages.LOAD_NAMES``): the force of the frame on the arm at the axle,
the force between the arm and the counterweight at the hinge, the sling's
tension, and the projectile's felt acceleration (the sling's and the base's
force on it over its mass, gravity excluded).

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
  centre of mass, the design's, without ballast.
"""

from __future__ import annotations

import numpy as np

from analytic.design import Design
from engine_model import kinematics as kin


def accelerations(raw: np.ndarray, body_velocity: np.ndarray, dt: float) -> np.ndarray:
    """(n, 2) accelerations over each raw row's step, m/s^2, from (n, 2) velocities at t_k + dt/2.

    Row 0's velocities belong to dt/2 after the opening half step from rest;
    those at -dt/2 are their mirror image (``kinematics.synchronise``).
    """
    before = np.vstack([-body_velocity[:1], body_velocity[:-1]])
    return (body_velocity - before) / dt


def load_histories(raw: np.ndarray, tension: np.ndarray, design: Design, dt: float) -> np.ndarray:
    """The loads over each raw row's step, shape (n, 4): axle (N), hinge (N), sling tension (N) and
    the projectile's felt acceleration (m/s^2).

    Parameters
    ----------
    raw : (n, 24) rows as read after each step of stages 1-2 (``kinematics``).
    tension : (n,) the sling's tension over each row's step, N (``kinematics.contact_forces``).
    dt : the step, s.
    """
    m, g = design.machine, design.environment.gravity
    up = np.array([0.0, g])
    arm_velocity = kin.point_velocity(raw, kin.ARM, kin.arm_centre(raw, design))
    hinge = m.counterweight_mass * (accelerations(raw, kin.velocity(raw, kin.COUNTERWEIGHT), dt) + up)
    felt = accelerations(raw, kin.velocity(raw, kin.PROJECTILE), dt) + up
    offset = kin.long_tip(raw, design) - kin.position(raw, kin.PROJECTILE)
    sling = tension[:, None] * offset / np.linalg.norm(offset, axis=1)[:, None]
    axle = m.arm_mass * (accelerations(raw, arm_velocity, dt) + up) + hinge + sling
    return np.column_stack([np.linalg.norm(axle, axis=1), np.linalg.norm(hinge, axis=1), tension,
                            np.linalg.norm(felt, axis=1)])


#: Steps after the opening half step whose loads are left out of the peaks: pymunk's solver starts
#: each step from the impulses of the step before, and after the opening half step (converged from
#: nothing, ``shot.STARTUP_ITERATIONS``) it rings for about a dozen steps on a machine with a light
#: arm (ballast at the pivot), whatever the step: the counterweight's load swung by 2 % at 5e-5 s
#: and at 2.5e-5 s alike on ``sample-0-015-light`` of the cross-check, whose largest hinge and
#: axle loads are at rest, and fell to 1e-6 by the 12th step and 1e-7 by the 14th (compared with
#: runs at half and a quarter of the step). The machine's velocities move by a fraction of a
#: step's change, which no other quantity shows. The load at rest (the opening half step's) is kept.
SETTLING_STEPS = 20


def peaks(loads: np.ndarray, times: np.ndarray) -> list[tuple[float, float]]:
    """Each column's largest value and its time (``peak``), on (n, k) ``loads`` at (n,) ``times``: over
    the rest state and the rows from ``SETTLING_STEPS`` on (all rows of a shot that short)."""
    found = []
    for values in loads.T:
        if len(values) <= SETTLING_STEPS:
            found.append(peak(values, times))
            continue
        later = peak(values[SETTLING_STEPS:], times[SETTLING_STEPS:])
        found.append(later if later[0] >= values[0] else (float(values[0]), float(times[0])))
    return found


def peak(values: np.ndarray, times: np.ndarray) -> tuple[float, float]:
    """The largest value of a sampled load and its time, s: the vertex of the parabola through the
    largest sample and its neighbours on the regular grid (the last sample, the release instant off
    the grid, is taken as is), or the sample itself where that is not a maximum."""
    i = int(np.argmax(values))
    if not 0 < i < len(values) - 2:
        return float(values[i]), float(times[i])
    before, at, after = values[i - 1], values[i], values[i + 1]
    curvature = before - 2.0 * at + after
    if curvature >= 0.0:
        return float(at), float(times[i])
    shift = 0.5 * (before - after) / curvature
    step = times[i + 1] - times[i]
    return float(at + 0.25 * (after - before) * shift), float(times[i] + shift * step)
