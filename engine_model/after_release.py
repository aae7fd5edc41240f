"""The machine after release: a rolling frame, arm and counterweight stepped on, without the projectile.

A fixed frame stays where it is, but a rolling one keeps moving while the
projectile flies: the arm and counterweight swing on and push it to and fro,
its centre of mass drifting at the speed the release left it. Where the frame
is when the projectile lands is part of the result, so the machine is stepped
on from the release instant to the landing instant in a space of its own.

It starts from the interpolated state at the release instant, not from the
last stage 2 step (which had the sling still pulling for part of a step):
pymunk moves positions with the velocities it holds before it updates them,
so placing each body half a step back along its velocity and stepping half a
step puts the positions at the release instant and the velocities half a step
on, the leapfrog start the machine had at firing.

A sling with mass and the pouch stay on the arm and swing on (``build(released=True)``):
the rows' projectile columns then hold the sling's end (the pouch), read each step,
in place of the projectile's state at release.

The axle's and the hinge's friction act on (``engine_model.friction``), their
limits from the loads of the steps before; the opening half step takes the
loads at rest (the weights), the only step whose loads are not measured.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pymunk

from analytic.design import Design
from engine_model import friction as fr
from engine_model import kinematics as kin
from engine_model.build import Rig, build
from engine_model.events import interpolate
from engine_model.readout import impulse, mounted_row, origin_reader, stepper

#: The joints that remain after release (``engine_model.kinematics.joint_drift``'s keys; a fixed
#: machine has no hinge).
MACHINE_JOINTS = ("pivot", "hinge", "rail")


@dataclass(frozen=True)
class AfterRelease:
    """The machine stepped from the release instant to the landing instant.

    Attributes
    ----------
    t : (k,) s from firing: the release instant, every step, and the landing instant last.
    states : (k, 24) synchronised rows (``engine_model.kinematics``) on ``t``;
        the projectile's columns hold its state at release (it is not in the space), or where a
        sling with mass or a pouch swings on (``kinematics.sling_swings``), the sling's end.
    raw : (k - 1, 24) rows as read after each step (velocities half a step on).
    steps : pymunk steps taken (the opening half step counted as one).
    dissipated : (k, 5) the work each friction (``friction.JOINTS``; the base's
        is 0) had taken since release, J, on ``t``.
    """

    t: np.ndarray
    states: np.ndarray
    raw: np.ndarray
    steps: int
    dissipated: np.ndarray | None = None

    @property
    def landing_state(self) -> np.ndarray:
        """(24,) the synchronised row at the landing instant."""
        return self.states[-1]


def place(body: pymunk.Body, row: np.ndarray, part: int, lead: float) -> None:
    """Put ``body`` where pymunk's next step of ``lead`` s brings it to the row's position and angle.

    Parameters
    ----------
    row : (24,) synchronised state; ``part`` the body's column offset in it.
    lead : s; the body is set back by its velocity times ``lead`` (0 places it as is).
    """
    x, y, angle, vx, vy, spin = (float(v) for v in row[part: part + 6])
    body.angle = angle
    body.position = (x, y)
    # pymunk's velocity is its centre of gravity's; the row holds the origin's.
    offset = body.local_to_world(body.center_of_gravity) - body.position
    centre_velocity = (vx - spin * offset.y, vy + spin * offset.x)
    body.velocity = centre_velocity
    body.angular_velocity = spin
    if lead:
        # Setting the angle turns the body about its centre of gravity; moving
        # the origin then moves that centre by as much.
        body.angle = angle - spin * lead
        body.position = body.position - pymunk.Vec2d(*centre_velocity) * lead


def run_after_release(design: Design, release_time: float, release_state: np.ndarray,
                      landing_time: float, dt: float, iterations: int, startup_iterations: int) -> AfterRelease:
    """Step the machine of a rolling ``design`` without its projectile from release to landing.

    Parameters
    ----------
    release_time, landing_time : s from firing.
    release_state : (24,) synchronised row at the release instant.
    dt : the fixed step, s (the stage 1-2 step).
    iterations : solver iterations per step; ``startup_iterations`` for the
        opening half step, which has no previous impulses to start from.

    Returns
    -------
    AfterRelease, the landing instant interpolated (quadratic) between the
    last steps. The caller checks its drift, residual and energy.
    """
    rig = build(design, sling="rigid", iterations=iterations, on_base=False, released=True)
    rig.space.remove(rig.sling, rig.projectile)
    bodies = _bodies(rig)
    for part, body in bodies.items():
        if body is not None:
            place(body, release_state, part, 0.5 * dt if part != kin.PROJECTILE else 0.0)
    if rig.sling_body is not None:
        place(rig.sling_body, sling_row(release_state, design), 0, 0.5 * dt)
    friction = fr.attach(rig, design, on_base=False)
    impulses = []
    modes = []   # each step's joints' modes (``friction.steady``)
    if friction is not None:
        # A joint turning at release slips (kinetic limit); one at rest holds (static).
        qdot = kin.coordinates(release_state[None, :], design, np.zeros(3))[1]
        slips = tuple(bool(rate > 0.0) for rate in fr.rates(release_state[None, :], qdot, design)[0])
        fr.set_limits(friction, fr.static_loads(design), slips)
        modes.append(slips)
        fr.aim(friction, rig, 0.5 * dt)
    rig.space.iterations = max(startup_iterations, iterations)
    rig.space.step(0.5 * dt)
    rig.space.iterations = iterations
    read = origin_reader(*bodies.values(), rig.mount)
    if rig.sling_body is not None:
        read = _with_sling_end(read, rig.sling_body, _sling_end(design))
    raw = [read()]
    if friction is not None:
        impulses.append(fr.impulses(friction, False))
        opening_loads = _loads(friction, rig, None, raw[-1], design, 0.5 * dt)
        rates = fr.joint_rates(raw[-1], design)
        slips = fr.slipping(friction, 0.5 * dt, rates, rates)
        friction = fr.renew(friction, rig)
    count = after_release_steps(release_time, landing_time, dt)
    loads = None
    step = stepper(rig.space)
    for i in range(count):
        if friction is not None:
            # The first whole step's readings are off (``friction.renew``): the half step's stand in.
            measured = _loads(friction, rig, raw[-2], raw[-1], design, dt) if i > 1 else opening_loads
            earlier, loads = loads, measured
            steady = fr.steady(modes, slips, coupled=bool(rig.supports))
            fr.set_limits(friction, fr.predicted_loads(loads, earlier, steady), slips)
            modes.append(slips)
            fr.aim(friction, rig, dt)
        step(dt)
        raw.append(read())
        if friction is not None:
            impulses.append(fr.impulses(friction, False))
            rates, earlier_rates = fr.joint_rates(raw[-1], design), rates
            slips = fr.slipping(friction, dt, rates, earlier_rates)
    raw = np.array(raw)
    states = _synchronise(raw, release_state)
    times = release_time + dt * np.arange(len(raw))
    fraction = (landing_time - times[-2]) / dt
    landing = interpolate(states[-3:], fraction)
    dissipated = np.zeros((len(raw), len(fr.JOINTS)))
    if friction is not None:
        qdot = kin.coordinates(states, design, np.zeros(3))[1]   # rates do not depend on the angles' branch
        dissipated = fr.dissipated_work(np.array(impulses), fr.rates(states, qdot, design))
        dissipated = dissipated - dissipated[0]
    dissipated = np.vstack([dissipated[:-1], interpolate(dissipated[-3:], fraction)])
    return AfterRelease(np.append(times[:-1], landing_time), np.vstack([states[:-1], landing]), raw,
                        len(raw), dissipated)


def sling_row(state: np.ndarray, design: Design) -> np.ndarray:
    """(6,) the row (``place``) of what stays on the long tip (``build.released_sling``) at the
    synchronised ``state``: a rod's origin at the tip, turned to the sling's direction and turning with
    it; a pouch alone, at the sling's end (the projectile's centre) with its velocity."""
    rows = state[None, :]
    end, v_end = kin.position(rows, kin.PROJECTILE)[0], kin.velocity(rows, kin.PROJECTILE)[0]
    if not design.machine.sling_mass > 0.0:
        return np.array([end[0], end[1], 0.0, v_end[0], v_end[1], 0.0])
    tip = kin.long_tip(rows, design)
    v_tip = kin.point_velocity(rows, kin.ARM, tip)[0]
    span, relative = end - tip[0], v_end - v_tip
    spin = (span[0] * relative[1] - span[1] * relative[0]) / float(span @ span)
    # The sling points at theta + psi from the upward vertical: (-sin, cos) of its angle.
    return np.array([tip[0, 0], tip[0, 1], math.atan2(-span[0], span[1]), v_tip[0], v_tip[1], spin])


def _sling_end(design: Design) -> tuple[float, float]:
    """The sling's end in the local frame of what stays on the tip (``build.released_sling``), m."""
    return (0.0, design.machine.sling_length) if design.machine.sling_mass > 0.0 else (0.0, 0.0)


def _with_sling_end(read, body: pymunk.Body, end: tuple[float, float]):
    """``read`` with the sling's ``end`` (a local point of ``body``: its position and velocity, the body's
    angle and spin, ``readout.mounted_row``) in the projectile's columns."""
    def with_end() -> tuple[float, ...]:
        row = read()
        return (*row[:kin.PROJECTILE], *mounted_row(body, end), *row[kin.PROJECTILE + 6:])
    return with_end


def after_release_steps(release_time: float, landing_time: float, dt: float) -> int:
    """Whole steps from release to landing: at least two, so that the landing is interpolated through three rows."""
    return max(int(np.ceil((landing_time - release_time) / dt)), 2)


def _loads(friction: fr.Friction, rig: Rig, before: tuple | None, row: tuple, design: Design,
           step: float) -> tuple[float, ...]:
    """The joints' loads (``friction.JOINTS``) in the last step of ``step`` s, N (as in stages 1-2, without a
    projectile: the base's is 0)."""
    if friction.axle is None:
        axle = 0.0
    elif rig.supports:
        axle = fr.track_axle_load(friction, rig, step)
    elif friction.ballast > 0.0 and before is not None:
        axle = fr.axle_load_from_momentum(before, row, design, (0.0, 0.0), step, projectile=False)
    else:
        # The opening half step (no row before it) takes the pivot's own reading, ballast and all.
        axle = impulse(rig.pivot) / step
    hinge = 0.0 if rig.hinge is None else impulse(rig.hinge) / step
    if friction.point_hinge:
        hinge = math.hypot(hinge, impulse(friction.hinge) / step)
    return axle, hinge, 0.0, *fr.slide_loads(friction, rig, step)


def _bodies(rig: Rig) -> dict[int, pymunk.Body | None]:
    """The rig's bodies by their columns in a state row (the counterweight None where bolted to the arm)."""
    return {kin.ARM: rig.arm, kin.COUNTERWEIGHT: rig.counterweight, kin.PROJECTILE: rig.projectile,
            kin.FRAME: rig.frame}


def _synchronise(raw: np.ndarray, start: np.ndarray) -> np.ndarray:
    """``kinematics.synchronise`` for a run that starts moving: row 0 takes the start's velocities.

    The velocity half a step before row 0 is the one whose mean with row 0's
    half-step velocity is the release state's own.
    """
    velocity_columns = [body + q for body in kin.BODIES for q in (kin.VX, kin.VY, kin.W)]
    sync = kin.synchronise(raw, rolling=True)
    sync[0, velocity_columns] = start[velocity_columns]
    return sync
