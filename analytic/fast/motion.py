"""A shot's motion from the compiled path: ``simulate_fast``'s summary with the motion sampled to draw it.

The compiled shot (``analytic.fast.kernel``) records its state on a grid of times
as it integrates: each sample read off the integrator's own interpolant of
the step that holds it, as the reference path samples its histories
(``analytic.reference.simulate``: the same DOP853 steps, the same
interpolants). This module turns those samples into a ``Motion``, the
coordinates a picture needs, and completes the summary with what the samples
give: the energy the counterweight and arm released and how it was shared,
and each loss's work.

For a caller that draws the shot (the workbench's stage) at a fraction of the
reference path's cost. The sling tension, the ground's push and the loads are
not sampled (the reference path's ``History`` holds them), and a rolling
frame's place at landing (stage 4) is not computed.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from analytic import eom, fast, stages, states
from analytic.fast import kernel
from analytic.outcome import Status, dissipated, friction_work_names
from analytic.design import Design
from analytic.floating_arm import sling_weighs
from analytic.friction import lossy
from analytic.limits import DEFAULT_ATOL, DEFAULT_RTOL
from analytic.parameters import params
from analytic.reference import FLIGHT_OUTPUT_STEP, HISTORY_SAMPLE_LIMIT, SWING_OUTPUT_STEP, spacing_argument
from analytic.result import Shot
from analytic.states import FLIGHT, FLIGHT_VX, FLIGHT_VY, FLIGHT_X, FLIGHT_Y, SLIDE, STATE_SIZE, SWING

#: Rows of a recording beyond its grids': each stage's first and last sample.
_EDGE_ROWS = 8


@dataclass(frozen=True)
class Motion:
    """A shot's motion sampled through stages 1-2 and its flight, for drawing.

    Positions are in ground coordinates, m from the pivot's position at rest, as
    ``Shot``'s and ``History``'s: the same samples ``History`` holds on the same grid.

    Attributes
    ----------
    t : (n,) sample times through stages 1-2, s from firing; the last is the release
        instant, or the failure's.
    stage : (n,) int, the ``Stage`` of each sample (1 or 2).
    q, qdot : (n, 3) coordinates [theta, phi, psi] (rad) and their rates (rad/s).
    frame_x : (n,) the frame's X, m (zeros for a fixed frame).
    flight_t : (k,) flight sample times, s from firing; (0,) if the projectile never flew.
    flight_path : (k, 2) projectile centre in flight, m.
    machine_energy_at_release : J, the arm's, counterweight's (and a rolling frame's, the sling's and
        the pouch's) kinetic and potential energy at release over their energy at rest
        (``History.energy.machine``'s last sample); None if not released.
    """

    t: np.ndarray
    stage: np.ndarray
    q: np.ndarray
    qdot: np.ndarray
    frame_x: np.ndarray
    flight_t: np.ndarray
    flight_path: np.ndarray
    machine_energy_at_release: float | None = None


def simulate_motion(design: Design, *, sample_step: float | None = None, flight_sample_step: float | None = None,
                    rtol: float = DEFAULT_RTOL, atol: float = DEFAULT_ATOL, loads: bool = True) -> tuple[Shot, Motion]:
    """The compiled shot of ``design`` and its motion sampled ``sample_step`` (stages 1-2) and
    ``flight_sample_step`` (flight) apart, s (None: the reference path's ``SWING_OUTPUT_STEP`` and
    ``FLIGHT_OUTPUT_STEP``; widened, as there, to keep within ``HISTORY_SAMPLE_LIMIT`` samples).

    Returns
    -------
    (Shot, Motion)
        ``simulate_fast``'s shot (the same numbers) with ``counterweight_energy_released``,
        ``projectile_energy_at_release`` and ``energy_dissipated`` filled in (the drag's work from
        the projectile's energy at release and at landing, which ``analytic.reference.drag_work``
        integrates step by step: they agree to the integrator's tolerance), and the ``Motion``.
    """
    spacing = spacing_argument("sample_step", sample_step, SWING_OUTPUT_STEP)
    flight_spacing = spacing_argument("flight_sample_step", flight_sample_step, FLIGHT_OUTPUT_STEP)
    fast.check_tolerances(rtol, atol)
    p = params(design)
    spacing = max(spacing, p.t_limit / HISTORY_SAMPLE_LIMIT)
    rec = np.zeros(1, kernel.RECORDING_DTYPE)
    rec["spacing"], rec["flight_spacing"], rec["sample_limit"] = spacing, flight_spacing, HISTORY_SAMPLE_LIMIT
    samples = np.empty(int(p.t_limit / spacing) + HISTORY_SAMPLE_LIMIT + _EDGE_ROWS, kernel.SAMPLE_DTYPE)
    out = fast.shoot_one(design, rtol, atol, loads, rec, samples)
    if rec["ran_out"][0]:   # the buffer holds every grid the kernel can ask for: a fault, not a design's failure
        raise RuntimeError(f"the compiled shot's recording of {design.name!r} ran out of rows")
    rows = int(rec["rows"][0])
    if rows == 0:   # it never moved (it never fires, or its equations fail at rest): the state at rest
        stages.slide_start(p, samples["state"][0, :states.state_size(SLIDE, p)])
        samples["t"][0], samples["stage"][0] = 0.0, SLIDE
        rows = 1
    shot = fast.to_shot(design, out)
    motion = _motion(samples[:rows], p, shot.ok or shot.status is Status.SHORT_OF_TARGET)
    shot = _completed(shot, motion, samples[:rows], p)
    if shot.release_time is not None:
        moving, _ = eom.kinetic_energy(*motion.q[-1], *motion.qdot[-1], p)
        machine = moving - shot.counterweight_energy_released
        if sling_weighs(p):   # the machine's potential energy holds the sling's and the pouch's rise too
            _, risen = eom.sling_energy(*motion.q[-1], 0.0, 0.0, 0.0, p)
            _, at_rest = eom.sling_energy(*motion.q[0], 0.0, 0.0, 0.0, p)
            machine += risen - at_rest
        motion = dataclasses.replace(motion, machine_energy_at_release=machine)
    return shot, motion


def _motion(samples: np.ndarray, p, landed: bool) -> Motion:
    """The ``Motion`` of a recording's samples (``analytic.fast.kernel.SAMPLE_DTYPE``); the flight's only if
    it ``landed``, or flew to its apex short of its target (as the reference path's ``History``)."""
    t, stage = samples["t"], samples["stage"]
    lifted = (stage[1:] == SWING) & (stage[:-1] == SLIDE) & (t[1:] == t[:-1])
    samples = samples[np.concatenate([[True], ~lifted])]   # lift-off once, as the slide's last
    stage = samples["stage"]
    swing, flight = samples[stage != FLIGHT], samples[(stage == FLIGHT) & landed]
    coordinates = np.array([eom.slide_state(*y[:STATE_SIZE[SLIDE]], p) if k == SLIDE else y[:STATE_SIZE[k]]
                            for k, y in zip(stage[stage != FLIGHT], swing["state"], strict=True)])
    frame_x = (np.array([eom.frame_displacement(*q, p) for q in coordinates[:, :3]])
               if p.rolling or p.kind == eom.FLOATING else np.zeros(len(swing)))
    return Motion(t=swing["t"].copy(), stage=stage[stage != FLIGHT], q=coordinates[:, :3], qdot=coordinates[:, 3:],
                  frame_x=frame_x, flight_t=flight["t"].copy(),
                  flight_path=flight["state"][:, FLIGHT_X:FLIGHT_Y + 1].copy())


def _completed(shot: Shot, motion: Motion, samples: np.ndarray, p) -> Shot:
    """``shot`` with the energies its recording gives (``simulate_motion``)."""
    last = samples[samples["stage"] != FLIGHT][-1]
    floating_base = states.floating_base(p)
    work = (states.friction_work(int(last["stage"]), last["state"], p) if lossy(p)
            else (0.0,) * len(friction_work_names(p.kind == eom.FLOATING, floating_base)))
    fields = {}
    drag = 0.0
    if shot.release_time is not None:
        machine0, projectile0 = eom.potential_energy(*motion.q[0], p)
        machine, projectile = eom.potential_energy(*motion.q[-1], p)
        _, moving = eom.kinetic_energy(*motion.q[-1], *motion.qdot[-1], p)
        fields.update(counterweight_energy_released=machine0 - machine,
                      projectile_energy_at_release=moving + projectile - projectile0, sling_energy_at_release=0.0)
        if sling_weighs(p):   # the machine's potential energy holds theirs: the counterweight's is the rest
            at_rest = eom.sling_energy(*motion.q[0], *motion.qdot[0], p)
            at_release = eom.sling_energy(*motion.q[-1], *motion.qdot[-1], p)
            fields.update(counterweight_energy_released=machine0 - machine - (at_rest[1] - at_release[1]),
                          sling_energy_at_release=at_release[0] + at_release[1] - at_rest[1])
        if samples["stage"][-1] == FLIGHT:   # the drag's work: the projectile's energy lost over the flight
            release = samples[samples["stage"] == FLIGHT]["state"][0, :STATE_SIZE[FLIGHT]]
            drag = float(_flight_energy(release, p) - _flight_energy(samples["state"][-1, :STATE_SIZE[FLIGHT]], p))
    if shot.ok and not p.rolling:
        fields.update(frame_landing_displacement=0.0, frame_landing_velocity=0.0)
    losses = dissipated(work, drag, _swing_drag(motion, p, work), p.kind == eom.FLOATING, floating_base)
    return dataclasses.replace(shot, energy_dissipated=losses, **fields)


def _swing_drag(motion: Motion, p, work) -> float:
    """The drag's work before release (or the failure), J: the mechanical energy the machine and the
    projectile lost in stages 1-2 beyond the friction's ``work`` (drag and friction are all that take it)."""
    if not p.drag_swing > 0.0:
        return 0.0

    def energy(i):
        return sum(eom.potential_energy(*motion.q[i], p)) + sum(eom.kinetic_energy(*motion.q[i], *motion.qdot[i], p))

    return float(energy(0) - energy(-1) - sum(work))


def _flight_energy(y: np.ndarray, p) -> float:
    """The projectile's kinetic and potential energy in flight state ``y`` (x, y, vx, vy), J."""
    return 0.5 * p.mP * (y[FLIGHT_VX] * y[FLIGHT_VX] + y[FLIGHT_VY] * y[FLIGHT_VY]) + p.mP * p.g * y[FLIGHT_Y]
