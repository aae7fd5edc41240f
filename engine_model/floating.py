"""The floating arm's supports in pymunk: a carriage on the axle's track and a slider on the counterweight's guide.

Chipmunk's GrooveJoint solves its anchor as a point-to-point pair and then
projects the accumulated impulse onto the groove's normal. That converges to
the true constraint (no velocity across the groove) only where the anchor's
effective mass is the same in every direction: a point of a body that never
turns, at its centre of gravity. On a turning arm it converges to the wrong
constraint (the axle drifted off its track by 40 % of its speed on the paper's
machine, and the arm's start-up acceleration came out 48 % high). So each groove
holds a body with an infinite moment at its centre (exact), and a PivotJoint
(exact) joins that body to the arm:

* the guide's slider carries the counterweight's mass: its centre is the
  counterweight's, and a point mass there moves as the counterweight's centre
  does; the counterweight's own inertia stays in the arm's body, which turns
  with it;
* the track's carriage carries part of the arm's mass (``carriage_mass``) at
  the axle; the arm's body keeps the rest, with its centre of gravity moved
  out so that the arm's weight torque ``arm_mass * arm_cg`` and its inertia
  about the axle are the design's. As for the hinged machine's ballast at the
  pivot, a mass at the axle of a body pinned there changes only how the axle
  point's own momentum is split, which the carriage carries.
"""

from __future__ import annotations

import math

import numpy as np
import pymunk

from analytic.design import Design, largest_length
from engine_model.loads import peaks

#: Half length of the track and the guide, in units of the machine's largest length: pymunk's groove
#: stops a body at its ends, which the axle and the counterweight never reach.
SUPPORT_HALF_LENGTH_FACTOR = 10.0
#: The carriage's share of the largest mass the axle can carry while the arm's body keeps a positive
#: moment about its centre of gravity (``carriage_mass``): half, so the arm's moment stays at least
#: half its own and its counterweight's.
CARRIAGE_SHARE = 0.5
#: Solver iterations of a floating arm's opening half step (in place of
#: ``engine_model.stepping.STARTUP_ITERATIONS``, 1000) and of the steps ``resolves`` names. Its small
#: carriage (``carriage_mass``) slows the solver's convergence: on the paper's machine held at rest by
#: its track's friction (three times the coefficient that just holds it) the arm's angular
#: acceleration read from the opening half step (against ``friction.HELD_ACCELERATION``) was
#: -2.8e-2 rad/s^2 after 1000 iterations, -2.2e-7 after 4000 and the same after 16000, at 5e-5 s; at
#: 1.25e-5 s -3.5e-6 from 4000 on. Without friction, 1000 left the track's push at rest on the
#: cross-check's ``sample-8-004-wooden-floating-arm`` (seed 8) 1.0 % low: 65.100 N, against 65.735 N
#: after 4000 or 16000 and from the analytic model.
STARTUP_ITERATIONS = 8000


def resolves(steps_taken: int, modes: list[tuple[bool, ...]]) -> bool:
    """Whether a floating arm's coming step is solved with ``STARTUP_ITERATIONS``, after ``steps_taken``
    whole steps, ``modes`` the friction joints' modes of each step (``engine_model.friction.limits``'
    ``slips``, the coming step's last; empty without friction).

    Chipmunk starts each step's solver from the impulses of the step before, applied scaled by the
    ratio of the steps but kept unscaled: after the opening half step (a ratio of 2) the first whole
    step keeps half the impulse it applied, and the second starts from that half. The floating arm's
    solver, slowed by the carriage, took about 95 steps of 200 iterations to make it up, and the loads
    read from the bodies' momentum rang for as long: on the cross-check's
    ``sample-8-004-wooden-floating-arm`` the axle's swung between 52 and 80 N about its 65.7 N, and
    its 70.21 N at the 20th step, the first the peaks are taken from
    (``engine_model.loads.SETTLING_STEPS``), was the peak, 4.9 % above the analytic model's 66.93 N.
    A friction joint that sticks, breaks free or turns back moves every support's impulse within a
    step as well, and the solver rang after it the same way: on
    ``sample-8-000-wooden-floating-arm-all-losses``, where its guide's sliding turns back, the axle's
    load rang up to 1.6 N above the analytic model's peak (102.47 N) even with the limits' lines
    stopped (``friction.steady``). So the step whose modes differ from the step before's too.
    """
    return steps_taken == 1 or (len(modes) > 1 and modes[-1] != modes[-2])


def carriage_mass(design: Design) -> float:
    """The mass the track's carriage takes from the arm, kg.

    Moving ``c`` of the arm's mass to the axle leaves a body of ``mA - c`` with its centre at
    ``mA d / (mA - c)``; its moment about that centre, ``J - mA^2 d^2 / (mA - c)`` with ``J`` the
    arm's and counterweight's inertia about the axle, is positive while
    ``c < mA (IA + IW) / J``. The carriage takes ``CARRIAGE_SHARE`` of that bound.
    """
    m = design.machine
    about_axle = m.arm_inertia + m.counterweight_inertia + m.arm_mass * m.arm_cg**2
    own = m.arm_inertia + m.counterweight_inertia
    return CARRIAGE_SHARE * m.arm_mass * own / about_axle if about_axle > 0.0 else 0.0


def arm_properties(design: Design) -> tuple[float, float, float]:
    """Mass (kg), centre of gravity along the long arm (m) and moment about it (kg m^2) of a floating
    arm's pymunk arm body: the arm less its carriage, turning with the counterweight's inertia."""
    m = design.machine
    mass = m.arm_mass - carriage_mass(design)
    cg = m.arm_mass * m.arm_cg / mass if mass > 0.0 else 0.0
    about_axle = m.arm_inertia + m.counterweight_inertia + m.arm_mass * m.arm_cg**2
    return mass, cg, about_axle - mass * cg**2


def supports(design: Design, frame: pymunk.Body, arm: pymunk.Body, axle: tuple[float, float]):
    """The carriage and slider bodies and the joints of the track and the guide.

    Returns ``(pivot, bodies, joints)``: the PivotJoint of the arm on the carriage at the axle, the
    (carriage, slider) bodies and the other joints (the two grooves and the slider's pivot). The
    arm's body must already be posed (its origin at ``axle``, the axle's start, its angle theta0).
    """
    m = design.machine
    reach = SUPPORT_HALF_LENGTH_FACTOR * largest_length(m)
    carriage = pymunk.Body(carriage_mass(design), math.inf)
    carriage.position = axle
    slider = pymunk.Body(m.counterweight_mass, math.inf)
    slider.position = arm.local_to_world((0.0, -m.arm_short))
    track = pymunk.GrooveJoint(frame, carriage, (-reach, 0.0), (reach, 0.0), (0.0, 0.0))
    guide = pymunk.GrooveJoint(frame, slider, (0.0, -reach), (0.0, reach), (0.0, 0.0))
    pivot = pymunk.PivotJoint(carriage, arm, (0.0, 0.0), (0.0, 0.0))
    mount = pymunk.PivotJoint(slider, arm, (0.0, 0.0), (0.0, -m.arm_short))
    return pivot, (carriage, slider), (track, guide, mount)


#: The floating arm's loads (``support_loads``), as ``simulate --json`` names them.
SUPPORT_LOAD_NAMES = ("min_track_force", "max_track_force", "max_guide_force", "axle_displacement_at_release")


def support_loads(force: np.ndarray, times: np.ndarray, axle_x: float | None) -> dict[str, float | None]:
    """The floating arm's support loads over stages 1-2 (``SUPPORT_LOAD_NAMES``).

    Parameters
    ----------
    force : (n, 2) the guide's push on the counterweight (x) and the track's on the axle (y), N,
        over each row's step (``engine_model.loads.support_force``).
    times : (n,) the rows' times, s.
    axle_x : the axle's x at release, m from the origin (None: no release).

    The track's least and largest vertical force (negative: it pulls the axle down), the guide's
    largest horizontal force in magnitude, each as ``engine_model.loads.peaks`` takes a peak
    (past the solver's settling), and the axle's displacement at release.
    """
    track, guide = force[:, 1], force[:, 0]
    (largest, _), (least, _), (sideways, _) = peaks(np.column_stack([track, -track, np.abs(guide)]), times)
    return dict(zip(SUPPORT_LOAD_NAMES, (-least, largest, sideways, axle_x), strict=True))
