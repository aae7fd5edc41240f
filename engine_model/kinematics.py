"""Pure functions of recorded body states: coordinates, joint drift, energies and contact forces.

A state row (shape (24,)) holds, for the arm, the counterweight, the
projectile and the frame in turn, six numbers read from pymunk: the body
origin ``x, y`` (m), its ``angle`` (rad), the velocity ``vx, vy`` of the
origin (m/s) and the angular velocity ``w`` (rad/s). The body frames are
those of ``engine_model.build``: the arm's and the frame's origins are at the
pivot, the others' at their centres; a fixed frame's six numbers are zeros.
Positions and velocities are ground ones (origin: the pivot at rest), so
for a rolling frame the frame's ``x`` is its displacement X. A floating arm's
rows hold its carriage (the axle on the track) in the frame's columns and its
slider (the counterweight's centre on the guide, with the arm's angle and
spin) in the counterweight's (``stepping.row_bodies``). Nothing here
depends on where pymunk puts a body's centre of gravity (the arm may carry
ballast at the pivot). A table of rows has shape (n, 24).

pymunk integrates with symplectic Euler: after a step to ``t`` the positions
belong to ``t`` and the velocities to ``t + dt/2``. ``synchronise`` turns such
raw rows into rows whose velocities belong to the same instant as the
positions (the mean of the two half-step velocities around it, second-order
accurate). Functions of velocities expect synchronised rows, except
``contact_forces`` and ``constraint_residuals``, which are about one step and
take raw ones.
"""

from __future__ import annotations

import math

import numpy as np

from analytic.design import Design
from analytic.result import ideal_range

ARM, COUNTERWEIGHT, PROJECTILE, FRAME = 0, 6, 12, 18
BODIES = (ARM, COUNTERWEIGHT, PROJECTILE, FRAME)
ROW_LENGTH = 24
X, Y, ANGLE, VX, VY, W = range(6)


def column(states: np.ndarray, body: int, quantity: int) -> np.ndarray:
    """One quantity of one body over a table of rows, shape (n,)."""
    return states[:, body + quantity]


def synchronise(raw: np.ndarray, rolling: bool = False) -> np.ndarray:
    """Rows with positions at t_k and velocities at t_k, shape (n, 24).

    Parameters
    ----------
    raw : (n, 24) rows read after each step: positions at t_k, velocities at
        t_k + dt/2. Row 0 is the state after the opening half step from rest,
        so its velocities belong to dt/2 and those at -dt/2 are their mirror
        image (motion from rest is even in time to second order).
    rolling : the body in the frame's columns moves (``origin_carried``: a
        rolling frame, or a floating arm's carriage); the arm's origin then
        takes its velocity.

    Notes
    -----
    The arm's origin velocity as read is the pivot joint's correction speed
    ``-error / dt`` relative to the frame, and the pivot's error is the step's
    chord error, ``(omega dt)^2 arm_cg / 2`` outward along the arm: so the
    origin seems to move at ``omega^2 arm_cg dt / 2`` toward the pivot, a first-order
    artefact. Along the arm it is at right angles to the arm's own motion and
    drops out of energies to first order, but on a rolling frame it would
    enter the horizontal momentum (and the frame's share of it) directly, so
    there the origin gets the velocity the pivot joint holds it to, the
    frame's. A floating arm's axle moves too, so the artefact there enters
    the energies at first order, against the axle's own velocity (3e-4 of the
    available energy at a 2.5e-5 s step on the paper's floating arm, against
    1.5e-7 with the carriage's velocity): its origin likewise takes the
    carriage's. A fixed frame keeps the velocity as read, which leaves its
    results exactly as they have always been reported.
    """
    sync = raw.copy()
    velocity_columns = [body + q for body in BODIES for q in (VX, VY, W)]
    half = raw[:, velocity_columns]
    before = np.vstack([-half[:1], half[:-1]])
    sync[:, velocity_columns] = 0.5 * (before + half)
    if rolling:
        sync[:, ARM + VX: ARM + VY + 1] = sync[:, FRAME + VX: FRAME + VY + 1]
    return sync


def arm_point(states: np.ndarray, distance: float) -> np.ndarray:
    """Position of the arm's point ``distance`` from the pivot along the long arm
    (negative: along the short arm), shape (n, 2), m."""
    theta = column(states, ARM, ANGLE)
    return np.column_stack([column(states, ARM, X) - distance * np.sin(theta),
                            column(states, ARM, Y) + distance * np.cos(theta)])


def long_tip(states: np.ndarray, design: Design) -> np.ndarray:
    """Long-arm tip (sling end) position, shape (n, 2), m."""
    return arm_point(states, design.machine.arm_long)


def short_tip(states: np.ndarray, design: Design) -> np.ndarray:
    """Short-arm tip (counterweight hinge) position on the arm, shape (n, 2), m."""
    return arm_point(states, -design.machine.arm_short)


def arm_centre(states: np.ndarray, design: Design) -> np.ndarray:
    """Arm centre of mass position, shape (n, 2), m."""
    return arm_point(states, design.machine.arm_cg)


def position(states: np.ndarray, body: int) -> np.ndarray:
    """Origin of ``body`` (the centre, for counterweight and projectile), shape (n, 2), m."""
    return states[:, body + X: body + Y + 1]


def velocity(states: np.ndarray, body: int) -> np.ndarray:
    """Velocity of the origin of ``body``, shape (n, 2), m/s."""
    return states[:, body + VX: body + VY + 1]


def point_velocity(states: np.ndarray, body: int, point: np.ndarray) -> np.ndarray:
    """Velocity of the point of ``body`` that is at world position ``point`` (n, 2), m/s."""
    offset = point - position(states, body)
    spin = column(states, body, W)
    return velocity(states, body) + np.column_stack([-spin * offset[:, 1], spin * offset[:, 0]])


def _direction_angle_and_rate(offset: np.ndarray, rate: np.ndarray, zero_direction: float):
    """Angle of ``offset`` measured CCW from ``zero_direction`` (rad) and its rate (rad/s)."""
    angle = np.arctan2(offset[:, 1], offset[:, 0]) - zero_direction
    cross = offset[:, 0] * rate[:, 1] - offset[:, 1] * rate[:, 0]
    return angle, cross / np.sum(offset**2, axis=1)


def _unwrap_from(angle: np.ndarray, start: float) -> np.ndarray:
    angle = np.unwrap(angle)
    return angle - 2.0 * math.pi * round((angle[0] - start) / (2.0 * math.pi))


def coordinates(states: np.ndarray, design: Design, start: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The generalised coordinates [theta, phi, psi] and their rates, each shape (n, 3).

    theta is the arm body's angle; phi and psi are reconstructed from where the
    counterweight and projectile actually are (the hinge and sling directions),
    so they mean the same for every counterweight and sling model; a fixed
    machine's phi is constant, its value at rest. ``start``
    (shape (3,), ``analytic.design.initial_angles``) picks the 2 pi branch of
    the first row; later rows are unwrapped continuously.
    """
    theta = column(states, ARM, ANGLE)
    theta_rate = column(states, ARM, W)
    hinge, tip = short_tip(states, design), long_tip(states, design)
    hinge_rate = point_velocity(states, ARM, hinge)
    tip_rate = point_velocity(states, ARM, tip)
    # The link hangs at theta + phi from the downward vertical; the sling
    # points at theta + psi from the upward vertical.
    if design.machine.kind == "hinged":
        link, link_rate = _direction_angle_and_rate(position(states, COUNTERWEIGHT) - hinge,
                                                    velocity(states, COUNTERWEIGHT) - hinge_rate,
                                                    -0.5 * math.pi)
    sling, sling_rate = _direction_angle_and_rate(position(states, PROJECTILE) - tip,
                                                  velocity(states, PROJECTILE) - tip_rate,
                                                  0.5 * math.pi)
    sling = _unwrap_from(sling, start[0] + start[2])
    if design.machine.kind != "hinged":
        # No link: phi keeps its value at rest (``docs/derivation.md``, section 11).
        phi, phi_rate = np.full_like(theta, start[1]), np.zeros_like(theta)
    else:
        phi = _unwrap_from(link, start[0] + start[1]) - theta
        phi_rate = link_rate - theta_rate
    q = np.column_stack([theta, phi, sling - theta])
    qdot = np.column_stack([theta_rate, phi_rate, sling_rate - theta_rate])
    return q, qdot


def joint_drift(states: np.ndarray, design: Design, sling: str, on_base: np.ndarray) -> dict[str, np.ndarray]:
    """How far each joint has come apart, m, each shape (n,).

    Parameters
    ----------
    states : (n, 24) rows (positions only are used, so raw rows do as well).
    sling : ``"rigid"`` or ``"rope"`` (a rope may be shorter than its length).
    on_base : (n,) bool, rows where the groove holds the projectile.

    Returns
    -------
    dict with ``pivot`` (arm origin from the frame's pivot), ``hinge`` (hinged machines only: short
    tip to the counterweight's hinge point, or the link's length error for a
    point counterweight), ``sling`` (length error, or stretch of a rope),
    ``groove`` (height of the projectile centre off the base or its trough, 0 off it)
    and, for a rolling frame only, ``rail`` (height of the frame off its rest
    height: it must neither lift nor sink); for a floating arm, ``track`` and ``guide`` (the
    carriage off its track, the slider off its guide) and ``mount`` (the slider from the arm's
    short tip).
    """
    m = design.machine
    frame_x, frame_y = column(states, FRAME, X), column(states, FRAME, Y)
    base_y = frame_y if design.base.rolling else 0.0   # a floating arm's frame columns are its carriage's
    pivot = np.hypot(column(states, ARM, X) - frame_x, column(states, ARM, Y) - frame_y)
    sling_length = np.hypot(*(position(states, PROJECTILE) - long_tip(states, design)).T)
    stretch = sling_length - m.sling_length
    sling_drift = np.maximum(stretch, 0.0) if sling == "rope" else np.abs(stretch)
    level = m.pivot_height - design.base.trough_height   # the trough's (the base's) depth below the pivot
    groove = np.where(on_base, np.abs(column(states, PROJECTILE, Y) - base_y + level), 0.0)
    drift = {"pivot": pivot, "sling": sling_drift, "groove": groove}
    if m.kind == "floating-arm":   # the carriage on the track y = 0, the slider on the guide x = 0
        drift["track"] = np.abs(frame_y)
        drift["guide"] = np.abs(column(states, COUNTERWEIGHT, X))
        drift["mount"] = np.hypot(*(position(states, COUNTERWEIGHT) - short_tip(states, design)).T)
    if m.kind == "hinged":
        drift["hinge"] = _hinge_drift(states, design)
    if design.base.rolling:
        drift["rail"] = np.abs(frame_y)
    return drift


def _hinge_drift(states: np.ndarray, design: Design) -> np.ndarray:
    """How far the hinge has come apart, m, (n,): the short tip from the counterweight's hinge point,
    or the link's length error for a point counterweight."""
    m = design.machine
    hinge = short_tip(states, design)
    centre = position(states, COUNTERWEIGHT)
    if m.counterweight_inertia == 0.0:
        return np.abs(np.hypot(*(centre - hinge).T) - m.counterweight_link)
    beta = column(states, COUNTERWEIGHT, ANGLE)
    hinge_point = centre + m.counterweight_link * np.column_stack([-np.sin(beta), np.cos(beta)])
    return np.hypot(*(hinge_point - hinge).T)


def origin_carried(design: Design) -> bool:
    """Whether the arm's origin is pinned to a moving body in the frame's columns: a rolling frame,
    or a floating arm's carriage on its track (``stepping.row_bodies``)."""
    return design.base.rolling or design.machine.kind == "floating-arm"


def carried_mass(design: Design) -> float:
    """The mass at the sling's end until release, kg: the projectile's, and the pouch's with it
    (one pymunk body, ``engine_model.build``)."""
    pouch = design.machine.pouch_mass
    return design.projectile.mass + pouch if pouch > 0.0 else design.projectile.mass


def sling_swings(design: Design) -> bool:
    """The sling has mass or a pouch: something stays on the long tip and swings on after release."""
    return design.machine.sling_mass > 0.0 or design.machine.pouch_mass > 0.0


def sling_energies(states: np.ndarray, design: Design) -> tuple[np.ndarray, np.ndarray]:
    """Kinetic and potential energy of the sling (a uniform rod) and the pouch (a point mass at its
    end), J, each (n,): the rod from the long tip A to its end B, the projectile's columns (the
    projectile's centre until release; the end as it swings on after it, ``engine_model.after_release``).

    A rigid rod's points move with velocities linear along it, so its kinetic energy is
    ``m (v_A^2 + v_A . v_B + v_B^2) / 6`` and its potential ``m g (y_A + y_B) / 2``.
    """
    m, g = design.machine, design.environment.gravity
    tip, end = long_tip(states, design), position(states, PROJECTILE)
    v_tip, v_end = point_velocity(states, ARM, tip), velocity(states, PROJECTILE)
    end_squared = np.sum(v_end**2, axis=1)
    kinetic = (m.sling_mass / 6.0 * (np.sum(v_tip**2, axis=1) + np.sum(v_tip * v_end, axis=1) + end_squared)
               + 0.5 * m.pouch_mass * end_squared)
    potential = g * (0.5 * m.sling_mass * (tip[:, 1] + end[:, 1]) + m.pouch_mass * end[:, 1])
    return kinetic, potential


def potential_energies(states: np.ndarray, design: Design) -> tuple[np.ndarray, np.ndarray]:
    """Gravitational potential energy (machine: arm + counterweight, with the sling and the pouch,
    ``sling_energies``; projectile), J, each (n,).

    Measured from the pivot's height; only differences matter.
    """
    g = design.environment.gravity
    m = design.machine
    machine = g * (m.arm_mass * arm_centre(states, design)[:, 1]
                   + m.counterweight_mass * column(states, COUNTERWEIGHT, Y))
    if sling_swings(design):
        machine = machine + sling_energies(states, design)[1]
    projectile = g * design.projectile.mass * column(states, PROJECTILE, Y)
    return machine, projectile


def kinetic_energies(states: np.ndarray, design: Design) -> tuple[np.ndarray, np.ndarray]:
    """Kinetic energy (machine: arm + counterweight, a rolling frame, the sling and the pouch; projectile),
    J, each (n,).

    Uses the design's masses and inertias, not the pymunk bodies' (which may
    carry ballast at the pivot or, for a point counterweight, a placeholder
    moment; a rolling frame's body is lighter by that ballast).
    """
    m = design.machine

    def translation(speed: np.ndarray, mass: float) -> np.ndarray:
        return 0.5 * mass * np.sum(speed**2, axis=1)

    arm_centre_velocity = point_velocity(states, ARM, arm_centre(states, design))
    machine = (translation(arm_centre_velocity, m.arm_mass) + 0.5 * m.arm_inertia * column(states, ARM, W)**2
               + translation(velocity(states, COUNTERWEIGHT), m.counterweight_mass)
               + 0.5 * m.counterweight_inertia * column(states, COUNTERWEIGHT, W)**2)
    if design.base.rolling:
        machine = machine + translation(velocity(states, FRAME), design.base.mass)
    if sling_swings(design):
        machine = machine + sling_energies(states, design)[0]
    return machine, translation(velocity(states, PROJECTILE), design.projectile.mass)


def horizontal_momentum(states: np.ndarray, design: Design) -> np.ndarray:
    """Horizontal momentum of frame, arm, counterweight, sling, pouch and projectile, kg m/s, shape (n,).

    No horizontal force acts on a rolling machine as a whole (the rail only
    pushes up), so this is conserved through stages 1 and 2. Design masses, as
    in ``kinetic_energies``; a fixed frame's own is taken as 0 (the ground
    holds it, so the sum is not conserved then).
    """
    m = design.machine
    arm_centre_velocity = point_velocity(states, ARM, arm_centre(states, design))[:, 0]
    momentum = (m.arm_mass * arm_centre_velocity + m.counterweight_mass * column(states, COUNTERWEIGHT, VX)
                + design.projectile.mass * column(states, PROJECTILE, VX))
    if design.base.rolling:
        momentum = momentum + design.base.mass * column(states, FRAME, VX)
    if sling_swings(design):   # the rod's centre moves at the mean of its ends; the pouch with the end
        end = column(states, PROJECTILE, VX)
        tip = point_velocity(states, ARM, long_tip(states, design))[:, 0]
        momentum = momentum + 0.5 * m.sling_mass * (tip + end) + m.pouch_mass * end
    return momentum


def energy_budget(states: np.ndarray, design: Design) -> tuple[np.ndarray, np.ndarray]:
    """Mechanical energy of machine and projectile relative to the first row, J, each (n,)."""
    v_machine, v_projectile = potential_energies(states, design)
    k_machine, k_projectile = kinetic_energies(states, design)
    return (k_machine + v_machine - v_machine[0] - k_machine[0],
            k_projectile + v_projectile - v_projectile[0] - k_projectile[0])


def available_energy(design: Design) -> float:
    """Potential energy the counterweight can give up at most, J (scales energy errors).

    From its start to the lowest point it can reach, as in
    ``analytic.result.ideal_range``: that range is ``2 E / (m_p g)``.
    """
    return 0.5 * ideal_range(design) * design.projectile.mass * design.environment.gravity


def contact_forces(velocity_before: tuple[float, float], velocity_after: tuple[float, float],
                   tip: tuple[float, float], centre: tuple[float, float], on_base: bool,
                   design: Design, dt: float, base_friction: float = 0.0,
                   drag_force: tuple[float, float] = (0.0, 0.0), shear: float = 0.0) -> tuple[float, float]:
    """Sling tension and base normal force on the projectile (with the pouch it sits in) over one step, N.

    pymunk reports only the size of a joint's impulse; the signs follow from
    the projectile's momentum: over the step at t_k the constraints gave it the
    impulse ``m (v[k+1/2] - v[k-1/2]) + m g dt``, which is the sling's pull
    along the unit vector from the projectile to the tip plus, on the base,
    the groove's push along +y and the base's friction along x (``base_friction``,
    which pymunk's friction constraint reports, ``engine_model.friction``), less the air's
    drag in the step (``drag_force``, N, with ``projectile.drag_during_swing``). The mass is the
    projectile's and the pouch's (``carried_mass``). A sling with mass also pushes across itself,
    ``shear`` (N, along the unit vector ``n`` a quarter turn counter-clockwise from ``u``, the sling's
    direction from the projectile to the tip; ``sling_shear``).

    Parameters
    ----------
    velocity_before, velocity_after : projectile velocity at t_k - dt/2 and t_k + dt/2, m/s.
    tip, centre : long-arm tip and projectile centre at t_k, m.
    on_base : whether the groove acted in this step.
    base_friction : the base's friction force on the projectile in this step, N, signed (+x).

    Returns
    -------
    (tension, normal) : positive when the sling pulls and when the base pushes
    up; ``normal`` is 0 off the base.
    """
    mass = carried_mass(design)
    force_x = mass * (velocity_after[0] - velocity_before[0]) / dt - drag_force[0]
    force_y = mass * (velocity_after[1] - velocity_before[1]) / dt + mass * design.environment.gravity - drag_force[1]
    offset_x, offset_y = tip[0] - centre[0], tip[1] - centre[1]
    length = math.hypot(offset_x, offset_y)
    unit_x, unit_y = offset_x / length, offset_y / length
    if not on_base:
        return force_x * unit_x + force_y * unit_y, 0.0
    # Only the sling and the base's friction pull sideways; near a vertical sling
    # this is ill-conditioned, but stage 1 ends (never_lifts_off) well before that.
    if shear:   # the shear pushes along n = (-u_y, u_x)
        tension = (force_x - base_friction + shear * unit_y) / unit_x
        return tension, force_y - tension * unit_y - shear * unit_x
    tension = (force_x - base_friction) / unit_x
    return tension, force_y - tension * unit_y


def sling_shear(before, after, design: Design, dt: float) -> float:
    """The force a sling with mass pushes across itself on the projectile over a step, N: along ``n``,
    a quarter turn counter-clockwise from ``u`` (the unit vector from the projectile B to the long
    tip A); 0 for a massless sling.

    ``after`` is the raw row the step produced (24 numbers), ``before`` the row of the step before
    (velocities half a step either side of the step, each with its own row's positions, as
    ``loads.accelerations`` takes them: the tip's centripetal acceleration is in their change). The
    rod (mass ``m``, length ``L``, centre ``c``, moment ``m L^2 / 12`` about it) turns at
    ``w = (B - A) x (v_B - v_A) / L^2``; its moments about A (the pin force on it at B is
    ``-(T u + S n)``, ``c - A = -u L / 2``) give ``L S = I w' - m (L / 2) u x (a_c + g e_y)``, with
    ``a_c`` the mean of its ends' accelerations (``docs/guide/engine.md``, "A sling with mass, and
    the pouch"). Plain floats: the stepping loop calls it every step on the base.
    """
    m = design.machine
    if not m.sling_mass > 0.0:
        return 0.0
    span_x, span_y, centre_x, centre_y, spin = _rod_motion(after, m.arm_long)
    _, _, before_x, before_y, spin_before = _rod_motion(before, m.arm_long)
    length = math.hypot(span_x, span_y)
    ux, uy = -span_x / length, -span_y / length
    ax, ay = (centre_x - before_x) / dt, (centre_y - before_y) / dt + design.environment.gravity
    return m.sling_mass * (m.sling_length * (spin - spin_before) / dt / 12.0 - 0.5 * (ux * ay - uy * ax))


def _rod_motion(row, arm_long: float) -> tuple[float, float, float, float, float]:
    """A sling rod's span B - A (m), its centre's velocity (m/s) and its spin (rad/s) in a row: from the
    long tip A (the arm's point ``arm_long`` along it) to the projectile's centre B."""
    theta, spin = row[ARM + ANGLE], row[ARM + W]
    sin, cos = math.sin(theta), math.cos(theta)
    tip_vx, tip_vy = row[ARM + VX] - spin * arm_long * cos, row[ARM + VY] - spin * arm_long * sin
    span_x = row[PROJECTILE + X] - (row[ARM + X] - arm_long * sin)
    span_y = row[PROJECTILE + Y] - (row[ARM + Y] + arm_long * cos)
    end_vx, end_vy = row[PROJECTILE + VX], row[PROJECTILE + VY]
    turn = (span_x * (end_vy - tip_vy) - span_y * (end_vx - tip_vx)) / (span_x * span_x + span_y * span_y)
    return span_x, span_y, 0.5 * (tip_vx + end_vx), 0.5 * (tip_vy + end_vy), turn


def constraint_residuals(raw: np.ndarray, design: Design, sling: str, on_base: np.ndarray,
                         steps: np.ndarray) -> dict[str, np.ndarray]:
    """How far each joint's velocity misses what pymunk's solver aims for, m/s, each (n,).

    With ``error_bias = 0`` a converged step leaves each joint's anchors with
    the relative velocity that removes its whole position error in the step:
    ``-error / step`` (``max_bias`` is infinite). An unconverged solver (too
    few iterations for the mass ratios) misses it; the miss times the step is
    joint error it adds, first order in the step.

    Parameters
    ----------
    raw : (n, 24) raw rows: positions at t_k, velocities after the step's solve.
    on_base : (n,) bool, rows whose step had the groove.
    steps : (n,) step length that produced each row, s.

    Returns
    -------
    dict with ``pivot``, ``hinge`` (hinged machines only), ``sling``, ``groove``
    and, for a rolling frame, ``rail``; for a floating arm ``track``, ``guide`` and ``mount``
    (``joint_drift``'s keys). A rope only counts where it is
    stretched and still stretching faster than it is being pulled in.
    """
    m = design.machine
    frame_y, frame_vy = column(raw, FRAME, Y), column(raw, FRAME, VY)
    pivot = _joined(position(raw, ARM), velocity(raw, ARM), position(raw, FRAME), velocity(raw, FRAME), steps)
    tip = long_tip(raw, design)
    projectile = position(raw, PROJECTILE)
    sling_miss = _distance_miss(tip, point_velocity(raw, ARM, tip), projectile,
                                velocity(raw, PROJECTILE), m.sling_length, steps)
    if sling == "rope":
        stretched = np.hypot(*(projectile - tip).T) > m.sling_length
        sling_miss = np.where(stretched, np.maximum(sling_miss, 0.0), 0.0)
    else:
        sling_miss = np.abs(sling_miss)
    base_y, base_vy = (frame_y, frame_vy) if design.base.rolling else (0.0, 0.0)
    height = column(raw, PROJECTILE, Y) - base_y + m.pivot_height - design.base.trough_height   # above the trough
    groove = np.where(on_base, np.abs(column(raw, PROJECTILE, VY) - base_vy + height / steps), 0.0)
    residual = {"pivot": pivot, "sling": sling_miss, "groove": groove}
    if m.kind == "floating-arm":   # the carriage's and the slider's grooves, the slider's pivot on the arm
        residual["track"] = np.abs(frame_vy + frame_y / steps)
        residual["guide"] = np.abs(column(raw, COUNTERWEIGHT, VX) + column(raw, COUNTERWEIGHT, X) / steps)
        mount = short_tip(raw, design)
        residual["mount"] = _joined(mount, point_velocity(raw, ARM, mount), position(raw, COUNTERWEIGHT),
                                    velocity(raw, COUNTERWEIGHT), steps)
    if m.kind == "hinged":
        residual["hinge"] = _hinge_residual(raw, design, steps)
    if design.base.rolling:
        residual["rail"] = np.abs(frame_vy + frame_y / steps)
    return residual


def _joined(a: np.ndarray, velocity_a: np.ndarray, b: np.ndarray, velocity_b: np.ndarray,
            steps: np.ndarray) -> np.ndarray:
    """(n,) how far a pivot joining points ``a`` and ``b`` (positions and velocities, (n, 2) each) missed
    its target over each step, m/s: the relative velocity that would close their gap in the step."""
    return np.hypot(*(velocity_a - velocity_b + (a - b) / steps[:, None]).T)


def _hinge_residual(raw: np.ndarray, design: Design, steps: np.ndarray) -> np.ndarray:
    """The hinge's miss of its target velocity (``constraint_residuals``), m/s, (n,)."""
    m = design.machine
    short = short_tip(raw, design)
    centre = position(raw, COUNTERWEIGHT)
    if m.counterweight_inertia == 0.0:
        return np.abs(_distance_miss(short, point_velocity(raw, ARM, short), centre,
                                     velocity(raw, COUNTERWEIGHT), m.counterweight_link, steps))
    beta = column(raw, COUNTERWEIGHT, ANGLE)
    hinge_point = centre + m.counterweight_link * np.column_stack([-np.sin(beta), np.cos(beta)])
    relative = point_velocity(raw, COUNTERWEIGHT, hinge_point) - point_velocity(raw, ARM, short)
    return np.hypot(*(relative + (hinge_point - short) / steps[:, None]).T)


def _distance_miss(a: np.ndarray, velocity_a: np.ndarray, b: np.ndarray, velocity_b: np.ndarray,
                   length: float, steps: np.ndarray) -> np.ndarray:
    """Signed miss of a distance joint: separation speed minus its target ``-(distance - length) / step``."""
    offset = b - a
    distance = np.hypot(*offset.T)
    separating = np.sum((velocity_b - velocity_a) * offset, axis=1) / distance
    return separating + (distance - length) / steps
