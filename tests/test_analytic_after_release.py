"""The machine after release (``docs/derivation.md`` section 10.9): its equations with the joints'
friction against the sympy Lagrangian (``tests/sympy_model.py``) with the projectile gone, its
stick and slip and energy over a whole run, and the frame's place at landing that it gives.

The sympy model has the frame's X as a coordinate, so the momentum the
machine keeps from release is an Ẋ like any other: the equations are checked
at an Ẋ of any momentum, which the derivation says changes nothing but X.
"""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

from analytic import eom, friction, reference, stages, states
from analytic.cli import main as analytic_main
from analytic.design import Base, Losses
from analytic.design_file import default_design, save_design
from analytic.parameters import params
from analytic.reference import simulate
from analytic.result import Status
from crosscheck.tolerances import FRAME_LANDING_DISPLACEMENT
from engine_model.cli import main as engine_main
from test_analytic_friction import IMPLICIT_TOL, REL_TOL, SEED, _check_equations, random_params

#: Energy audit of the machine after release, as a fraction of its kinetic energy at
#: release: the same budget as the shot's audit in ``test_analytic_friction``
#: (1e-8 of the counterweight's energy; the integrator's tolerance is 1e-10).
AUDIT_TOL = 1e-8
#: The paper's machine on wheels with the cross-check's typical losses
#: (``crosscheck.cases.REALISTIC_LOSSES``): its arm and counterweight swing
#: to and fro for the 3.3 s of the flight, the axle and the hinge stopping
#: at every turn.
LOSSES = Losses(axle_friction=0.15, axle_radius=0.0064, hinge_friction=0.15, hinge_radius=0.005,
                base_friction=0.3)


def _samples(n=10):
    """(machine params, (theta, phi), (theta', phi'), momentum P, (sa, sh), an unused psi and psi')."""
    rng = np.random.default_rng(SEED + 7)
    modes = [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (0.0, 1.0), (1.0, 0.0), (0.0, 0.0)]
    out = []
    for i in range(n):
        p = random_params(rng, rolling=bool(i % 2))
        momentum = rng.normal(0.0, 3.0) * p.mP * math.sqrt(p.g * p.La)   # of the size a projectile leaves
        out.append((stages.machine_params(p), rng.uniform(-math.pi, math.pi, 2), rng.normal(0.0, 4.0, 2),
                    momentum, modes[i % len(modes)], rng.uniform(-math.pi, math.pi, 2)))
    return out


SAMPLES = _samples()


def _sympy_state(m, angles, rates, momentum, ddtheta, ddphi, spare):
    """q, q', q'' of the sympy model: psi and psi' arbitrary (no mass hangs on them), X' from the
    momentum (``stages.machine_frame``), X'' from ``eom`` (checked by the X row)."""
    y = np.array([*angles, *rates])
    _, dx = stages.machine_frame(y, m, momentum, 0.0, y, 0.0, 0.0) if m.rolling else (0.0, 0.0)
    ddx = eom.frame_acceleration(angles[0], angles[1], 0.0, *rates, 0.0, ddtheta, ddphi, 0.0, m)
    return (np.array([*angles, spare[0], 0.37]), np.array([*rates, spare[1], dx]),
            np.array([ddtheta, ddphi, 0.0, ddx]))


@pytest.mark.parametrize("sample", SAMPLES, ids=[f"machine{i}" for i in range(len(SAMPLES))])
def test_machine_friction_satisfies_the_sympy_equations_at_any_momentum(lagrangian, sample):
    m, angles, rates, momentum, (sa, sh), spare = sample
    rates = rates * np.array([sa != 0.0, sh != 0.0])   # a stuck joint's rate is 0
    ddtheta, ddphi, ta, th, axle, hinge = friction.machine_friction(*angles, *rates, sa, sh, m)
    q, qd, qdd = _sympy_state(m, angles, rates, momentum, ddtheta, ddphi, spare)
    _check_equations(lagrangian, m, q, qd, qdd, ta, th, 0.0, 0.0)
    if m.rolling:   # the momentum dT/dX' at machine_frame's X' is the one kept
        kept = lagrangian.momentum(m, q, qd)
        assert kept == pytest.approx(momentum, rel=REL_TOL, abs=REL_TOL * m.Mf * abs(qd[3]))
    axle_f, hinge_f, _ = lagrangian.joint_forces(m, q, qd, qdd)
    assert axle == pytest.approx(np.linalg.norm(axle_f), rel=REL_TOL)
    assert hinge == pytest.approx(np.linalg.norm(hinge_f), rel=REL_TOL)
    if sa != 0.0:
        assert abs(ta + m.mua * m.ra * sa * axle) <= IMPLICIT_TOL * abs(ta)
    else:
        assert ddtheta == 0.0
    if sh != 0.0:
        assert abs(th + m.muh * m.rh * sh * hinge) <= IMPLICIT_TOL * abs(th)
    else:
        assert ddphi == 0.0


@pytest.mark.parametrize("sample", SAMPLES[:4], ids=[f"machine{i}" for i in range(4)])
def test_the_machine_without_friction_satisfies_the_sympy_equations(lagrangian, sample):
    m, angles, rates, momentum, _, spare = sample
    ideal = m._replace(mua=0.0, muh=0.0, mub=0.0, mua_s=0.0, muh_s=0.0, mub_s=0.0)
    y, out = np.array([*angles, *rates]), np.empty(4)
    stages.derivative(states.MACHINE, y, ideal, None, out)
    q, qd, qdd = _sympy_state(ideal, angles, rates, momentum, out[2], out[3], spare)
    _check_equations(lagrangian, ideal, q, qd, qdd, 0.0, 0.0, 0.0, 0.0)


def test_compiled_machine_after_release_is_bit_identical_to_the_python_one():
    """Stage 4 is compiled into the fast path's kernel with the rest of ``analytic.stages`` (which runs
    none of it): its right-hand side, events and mode switches give the Python bits."""
    from analytic.fast import compiled
    from analytic.aero import DRAG_TABLE

    rng = np.random.default_rng(SEED + 8)
    for base in (Base(), Base(mobility="rolling", mass=30.0)):
        m = stages.machine_params(params(dataclasses.replace(default_design(), base=base, losses=LOSSES)))
        for _ in range(30):
            sa, sh = rng.choice([-1.0, 0.0, 1.0], size=2)
            y = np.array([*rng.uniform(-math.pi, math.pi, 2), *(rng.normal(0.0, 4.0, 2) * [sa != 0.0, sh != 0.0]),
                          *rng.uniform(0.0, 1.0, 3), sa, sh, 0.0])
            got, expected = np.empty(len(y)), np.empty(len(y))
            compiled.stages_.derivative(states.MACHINE, y, m, DRAG_TABLE, got)
            stages.derivative(states.MACHINE, y, m, DRAG_TABLE, expected)
            np.testing.assert_array_equal(got, expected)
            for k in range(len(states.EVENT_NAMES[states.MACHINE])):
                assert compiled.stages_.event_value(states.MACHINE, k, y, m) == stages.event_value(states.MACHINE, k,
                                                                                                   y, m)
                y_got, y_expected = y.copy(), y.copy()
                compiled.states_.switch_mode(states.MACHINE, k, y_got, m)
                states.switch_mode(states.MACHINE, k, y_expected, m)
                np.testing.assert_array_equal(y_got, y_expected)


# --------------------------------------------------------------------------- #
# A whole run after release
# --------------------------------------------------------------------------- #

def _rolling(design, mass=10.0):
    return dataclasses.replace(design, base=Base(mobility="rolling", mass=mass))


def _after_release(design):
    """The stage-4 run from a shot's release to its landing, sampled: ``(machine params, segment, pieces)``."""
    shot = simulate(design, histories=False)
    p = params(design)
    swing = []
    original = reference._merge

    def keep(pieces):   # the stage-2 run's end state, as simulate hands it on
        merged = original(pieces)
        swing.append(merged)
        return merged

    try:
        reference._merge = keep
        simulate(design, histories=False, loads=False)
    finally:
        reference._merge = original
    m = stages.machine_params(p)
    start = np.empty(states.state_size(states.MACHINE, m))
    stages.machine_start(swing[-1].y_end, m, start)
    pieces, _, _, _ = reference._run_modes(states.MACHINE, m, shot.release_time, start, shot.landing_time,
                                           reference.DEFAULT_RTOL, reference.DEFAULT_ATOL, 1e-3, False, [0])
    return m, reference._merge(pieces), pieces


def _machine_energy(lagrangian, m, y, dx):
    """``(T, V)`` on the ground of the arm, counterweight and frame, T from the sympy model's mass matrix."""
    q, qd = np.array([y[0], y[1], 0.0, 0.0]), np.array([y[2], y[3], 0.0, dx])
    kinetic = 0.5 * qd @ lagrangian.mass(m, q, qd) @ qd
    return kinetic, eom.potential_energy(y[0], y[1], 0.0, m)[0]


def test_after_release_the_joints_stick_and_slip_and_the_energy_audit_closes(lagrangian):
    """The machine's energy at release less its energy at each sample is the work its friction did
    since; the axle and the hinge stop and turn back many times on the way."""
    design = dataclasses.replace(_rolling(default_design()), losses=LOSSES)
    shot = simulate(design, histories=False)
    m, machine, pieces = _after_release(design)
    events = {piece.event for piece in pieces[:-1]}
    assert len(pieces) > 10 and {"axle_stops", "hinge_stops"} <= events
    momentum = -params(design).mP * shot.release_velocity[0]
    y0 = machine.y[0]
    kinetic, potential = np.array([_machine_energy(lagrangian, m, y, stages.machine_frame(y, m, momentum, 0.0, y0, 0.0,
                                                                                      0.0)[1])
                                   for y in machine.y]).T
    energies, scale = kinetic + potential, kinetic[0]
    work = machine.y[:, 4] + machine.y[:, 5] - (y0[4] + y0[5])
    assert work[-1] > 0.1 * scale   # the friction takes a visible share
    assert np.max(np.abs(energies[0] - energies - work)) <= AUDIT_TOL * scale


def test_friction_after_release_changes_where_the_rolling_frame_lands():
    """The same shot (to release: the friction is the same) with the joints' friction after
    release and without it: the frame at release is the same, at landing it is not."""
    design = dataclasses.replace(_rolling(default_design()), losses=LOSSES)
    shot = simulate(design, histories=False, after_release=True)
    m, machine, _ = _after_release(design)
    ideal = m._replace(mua=0.0, muh=0.0, mub=0.0, mua_s=0.0, muh_s=0.0, mub_s=0.0)
    start = machine.y[0, :4].copy()
    frictionless = reference._run(states.MACHINE, ideal, shot.release_time, start, shot.landing_time,
                                  reference.DEFAULT_RTOL, reference.DEFAULT_ATOL, None, False)
    momentum = -params(design).mP * shot.release_velocity[0]
    x_free = stages.machine_frame(frictionless.y_end, ideal, momentum, shot.release_time, start,
                                  shot.frame_release_displacement, shot.landing_time)[0]
    assert abs(shot.frame_landing_displacement - x_free) > 0.05 * abs(x_free)


def test_a_summary_asked_for_the_frame_at_landing_gives_the_full_shots_number():
    design = dataclasses.replace(_rolling(default_design()), losses=LOSSES)
    full = simulate(design)
    assert simulate(design, histories=False).frame_landing_displacement is None   # a summary costs what it did
    summary = simulate(design, histories=False, after_release=True)
    assert summary.frame_landing_displacement == full.frame_landing_displacement
    assert simulate(design, after_release=False).frame_landing_displacement is None
    fixed = simulate(dataclasses.replace(design, base=Base()), histories=False)
    assert fixed.status is Status.OK and fixed.frame_landing_displacement == 0.0


@pytest.mark.parametrize("base", [Base(), Base(mobility="rolling", mass=10.0)], ids=["fixed", "rolling"])
def test_both_models_simulate_json_report_the_frame_at_landing_alike(tmp_path, capsys, base):
    """The frame's displacement from its place at rest at the projectile's landing time: 0 bolted
    down, and on wheels the same number in both models within the cross-check's tolerance."""
    design = dataclasses.replace(default_design(), base=base, losses=LOSSES)
    path = tmp_path / "design.toml"
    save_design(design, path)
    reported = []
    for main in (analytic_main, engine_main):
        assert main(["simulate", str(path), "--json"]) == 0
        reported.append(json.loads(capsys.readouterr().out)["frame_landing_displacement"])
    analytic, engine = reported
    assert analytic == simulate(design).frame_landing_displacement
    if base.rolling:
        assert abs(engine - analytic) <= FRAME_LANDING_DISPLACEMENT and abs(analytic) > 0.05
    else:
        assert analytic == engine == 0.0


def test_a_failed_run_after_release_leaves_the_frame_at_landing_unreported_with_a_warning(monkeypatch):
    """The shot itself stands (it landed); only what the run after release gives is missing."""
    design = dataclasses.replace(_rolling(default_design()), losses=LOSSES)
    limits = list(reference.STAGE_STEP_LIMITS)
    limits[states.MACHINE] = 3
    monkeypatch.setattr(reference, "STAGE_STEP_LIMITS", tuple(limits))
    shot = simulate(design)
    assert shot.status is Status.OK and shot.range is not None
    assert shot.frame_landing_displacement is None and shot.max_frame_speed is None
    assert any("after release could not be integrated" in warning for warning in shot.warnings)
    assert shot.to_json()["frame_landing_displacement"] is None
