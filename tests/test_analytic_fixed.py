"""The fixed (bolted) counterweight (``docs/derivation.md`` section 11) against its own sympy Lagrangian.

The reference is ``tests/sympy_model.py``'s ``machine("fixed")``: the counterweight's centre
and spin written from the geometry (11.1), so phi appears nowhere in it and only theta, psi
(and a rolling frame's X) are solved for. ``analytic.eom`` builds the fixed machine as the
hinged one with ``Lw = 0`` and phi held (section 11); every check here compares the two at
random states and designs, fixed and rolling frames, stages 1 and 2, with and without the
axle's friction.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from analytic import eom, friction
from analytic.design import Base, Losses
from analytic.design_file import load_design
from analytic.parameters import Params, params

#: Agreement with the sympy reference at one state, relative to the largest entry compared:
#: both sides evaluate closed forms in a few dozen double operations (round-off ~1e-14); the
#: constrained systems' solutions leave room up to 1e-10 (as tests/test_analytic_symbolic.py),
#: while a wrong term is O(1).
REL_TOL = 1e-10
SEED = 28_011
#: The sample fixed design, the paper's Table III machine with its counterweight bolted.
FIXED_FILE = "analytic/data/paper_table3_fixed.toml"


@pytest.fixture(scope="module")
def bolted():
    """The fixed machine's sympy Lagrangian."""
    from sympy_model import machine

    return machine("fixed")


def _fixed_params(rng, frame_mass=None) -> Params:
    """The sample fixed design's numbers with a random arm, projectile and counterweight inertia."""
    design = load_design(FIXED_FILE)
    if frame_mass is not None:
        design = dataclasses.replace(design, base=Base("rolling", frame_mass))
    return params(design)._replace(mA=rng.uniform(0.1, 3.0), d=rng.uniform(-0.2, 0.6), mP=rng.uniform(0.02, 2.0),
                                   IW=rng.uniform(0.0, 0.1), IA=rng.uniform(0.0, 0.1),
                                   mW=rng.uniform(1.0, 50.0), g=rng.uniform(1.0, 25.0))


def _samples(n: int, seed: int):
    """(p, q, q') of random fixed machines, every other one on a rolling frame of random mass."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n):
        frame = None if i % 2 == 0 else math.exp(rng.uniform(math.log(0.5), math.log(500.0)))
        out.append((_fixed_params(rng, frame), rng.uniform(-math.pi, math.pi, 3), rng.normal(0.0, 6.0, 3)))
    return out


SWING = _samples(10, SEED)
#: Stage 1: theta within the sling's reach (psi from the base constraint).
SLIDE = [(p, math.acos(-p.h / p.La) - u, q[1], qd[0], qd[1])
         for (p, q, qd), u in zip(_samples(10, SEED + 1), np.random.default_rng(SEED + 2).uniform(0.05, 0.6, 10))]


def _ids(samples):
    return [f"{'rolling' if s[0].rolling else 'fixed'}-{i}" for i, s in enumerate(samples)]


def _four(bolted, p, q, qd):
    """q and q' with the frame's X (0) and X' (zero horizontal momentum on a rolling frame; 0 on a fixed one)."""
    dx = bolted.zero_momentum_rate(p, (*q, 0.0), qd) if p.rolling else 0.0
    return (*q, 0.0), (*qd, dx)


def _close(got, expected, what, scale=None):
    got, expected = np.asarray(got, dtype=float), np.asarray(expected, dtype=float)
    scale = float(np.max(np.abs(expected))) if scale is None else scale
    error = float(np.max(np.abs(got - expected)))
    assert error <= REL_TOL * scale, f"{what}: analytic {got} vs sympy {expected} (error {error:.3g}, scale {scale:.3g})"


def test_the_reference_has_no_phi():
    """The reference itself: phi's row and column of M and its forcing are 0, so it is not a
    hinged machine in disguise (and eom's uncoupled phi row is a choice, not the reference's)."""
    from sympy_model import machine

    p, q, qd = SWING[1]
    m, f = machine("fixed").mass(p, q, qd), machine("fixed").forcing(p, q, qd)
    assert np.all(m[1, :] == 0.0) and np.all(m[:, 1] == 0.0) and f[1] == 0.0
    assert machine("hinged").mass(p, q, qd)[1, 1] > 0.0


@pytest.mark.parametrize("sample", SWING[::2], ids=_ids(SWING[::2]))
def test_mass_matrix_and_forcing_are_the_lagrangians_with_phi_uncoupled(bolted, sample):
    p, q, qd = sample
    m11, m12, m13, m22, m33, f1, f2, f3 = eom.terms(*q, *qd, p)
    m, f = bolted.mass(p, q, qd), bolted.forcing(p, q, qd)
    _close([m11, m13, m33], [m[0, 0], m[0, 2], m[2, 2]], "M over (theta, psi)")
    _close([f1, f3], [f[0], f[2]], "f over (theta, psi)")
    assert (m12, m22, f2) == (0.0, 1.0, 0.0)


@pytest.mark.parametrize("sample", SWING, ids=_ids(SWING))
def test_swing_accelerations_and_joint_forces_are_the_lagrangians(bolted, sample):
    p, q, qd = sample
    qdd = eom.swing_accelerations(*q, *qd, p)
    q4, qd4 = _four(bolted, p, q, qd)
    acc = bolted.accelerations(p, q4, qd4)
    _close(qdd, acc[:3], "theta'', phi'', psi''", float(np.max(np.abs(acc))))
    assert qdd[1] == 0.0
    axle, mount, sling = bolted.joint_forces(p, q4, qd4, acc)
    scale = max(float(np.max(np.abs(np.concatenate([axle, mount, sling])))), (p.mA + p.mW + p.mP) * p.g)
    got = eom.joint_forces(*q, *qd, *qdd, 0.0, p)
    _close(got[0:2], axle, "axle force on the arm", scale)
    _close(got[2:4], mount, "mount force on the counterweight", scale)
    _close(got[4:6], sling, "sling force on the projectile", scale)
    if p.rolling:
        _close(eom.frame_acceleration(*q, *qd, *qdd, p), acc[3], "X''", float(np.max(np.abs(acc))))


@pytest.mark.parametrize("sample", SLIDE, ids=_ids(SLIDE))
def test_slide_accelerations_base_push_and_joint_forces_are_the_lagrangians(bolted, sample):
    p, theta, phi, dtheta, dphi = sample
    dphi = 0.0   # phi does not move on a fixed machine
    ddtheta, ddphi, normal = eom.slide_accelerations(theta, phi, dtheta, dphi, p)
    psi, dpsi, s, c, _ = eom.slide_constraint(theta, dtheta, p)
    q, qd, qdd = (theta, phi, psi), (dtheta, dphi, dpsi), (ddtheta, ddphi, s * ddtheta + c)
    q4, qd4 = _four(bolted, p, q, qd)
    acc, normal_ref = bolted.on_base(p, q4, qd4)
    _close(qdd, acc[:3], "theta'', phi'', psi''", float(np.max(np.abs(acc))))
    assert ddphi == 0.0
    axle, mount, sling = bolted.joint_forces(p, q4, qd4, acc, 0.0, normal_ref)
    scale = max(float(np.max(np.abs(np.concatenate([axle, mount, sling])))), (p.mA + p.mW + p.mP) * p.g)
    _close(normal, normal_ref, "base push", scale)
    got = eom.joint_forces(*q, *qd, *qdd, normal, p)
    _close(got[0:2], axle, "axle force on the arm", scale)
    _close(got[2:4], mount, "mount force on the counterweight", scale)
    _close(got[4:6], sling, "sling force on the projectile", scale)


@pytest.mark.parametrize("sample", SWING, ids=_ids(SWING))
def test_energies_and_the_frames_motion_are_the_lagrangians(bolted, sample):
    p, q, qd = sample
    qd = (qd[0], 0.0, qd[2])
    q4, qd4 = _four(bolted, p, q, qd)
    kinetic_machine, kinetic_projectile, potential_machine, potential_projectile = bolted.energies(p, q4, qd4)
    scale = float(np.max(np.abs(bolted.energies(p, q4, qd4))))
    _close(eom.kinetic_energy(*q, *qd, p), [kinetic_machine, kinetic_projectile], "T", scale)
    _close(eom.potential_energy(*q, p), [potential_machine, potential_projectile], "V", scale)
    if p.rolling:
        _close(eom.frame_velocity(*q, *qd, p), qd4[3], "X'", abs(qd4[3]) + float(np.max(np.abs(qd))))
        _close(eom.horizontal_moment(*q, p), bolted.moment(p, q4), "S", eom.total_mass(p) * (p.La + p.Ls))


@pytest.mark.parametrize("sample", SWING, ids=_ids(SWING))
def test_a_point_counterweight_has_no_nan(bolted, sample):
    """IW = 0: the hinged M22 = IW + mW Lw^2 would be 0 at Lw = 0; the fixed machine never divides by it."""
    p, q, qd = sample
    p = p._replace(IW=0.0)
    q4, qd4 = _four(bolted, p, q, qd)
    _close(eom.swing_accelerations(*q, *qd, p), bolted.accelerations(p, q4, qd4)[:3], "q''")
    m = p._replace(mP=0.0)
    ddtheta, ddphi = eom.machine_accelerations(q[0], q[1], qd[0], 0.0, m)
    assert ddphi == 0.0 and math.isfinite(ddtheta)


@pytest.mark.parametrize("sample", SWING, ids=_ids(SWING))
@pytest.mark.parametrize("mode", [-1.0, 1.0, 0.0], ids=["slipping-back", "slipping-forward", "stuck"])
def test_axle_friction_is_coulombs_law_and_the_motion_the_lagrangians(bolted, sample, mode):
    """The fixed machine's equations with the axle's torque as a generalised force: M q'' = f + Q
    over (theta, psi[, X]); slipping, |ta| = mua ra |A|; stuck, theta'' = 0."""
    p, q, qd = sample
    p = p._replace(mua=0.3, ra=0.02, mua_s=0.4)
    qd = (qd[0], 0.0, qd[2])
    ddtheta, ddphi, ddpsi, ta, th, axle, _ = friction.swing_friction(*q, *qd, mode, 0.0, p)
    assert ddphi == 0.0 and th == 0.0
    q4, qd4 = _four(bolted, p, q, qd)
    acc = np.array([ddtheta, 0.0, ddpsi, 0.0])
    if p.rolling:
        acc[3] = eom.frame_acceleration(*q, *qd, ddtheta, 0.0, ddpsi, p)
    rows = bolted.rows(p)
    m, f = bolted.mass(p, q4, qd4), bolted.forcing(p, q4, qd4)
    residual = m @ acc - f - bolted.generalised(p, q4, qd4, ta, 0.0, 0.0)
    _close(residual[rows], np.zeros(len(rows)), "M q'' - f - Q", float(np.max(np.abs(f))) + abs(ta))
    force = bolted.joint_forces(p, q4, qd4, acc)[0]
    _close(axle, np.hypot(*force), "|A|", float(np.max(np.abs(force))))
    if mode == 0.0:
        assert ddtheta == 0.0
    else:
        _close(ta, -mode * p.mua * p.ra * axle, "ta", abs(ta))


# --------------------------------------------------------------------------- #
# Whole shots (the paths' agreement on fixed designs: tests/test_analytic_fast.py, test_analytic_loads.py)
# --------------------------------------------------------------------------- #

#: The ideal machine's energy is conserved through stages 1-2 to the integrator's error, relative to
#: the counterweight's released energy (as tests/test_analytic_physics.py holds the hinged one).
ENERGY_DRIFT = 1e-8
#: The energy audit (friction's work + the machine's energy change) closes to this, relative
#: (as tests/test_analytic_friction.py's AUDIT_TOL).
AUDIT_TOL = 1e-8


def test_an_ideal_fixed_shot_conserves_energy_and_holds_phi():
    from analytic.reference import simulate

    from support import with_environment

    design = with_environment(load_design(FIXED_FILE), air_density=0.0)
    shot = simulate(design)
    assert shot.ok
    assert np.max(np.abs(shot.history.energy.total)) <= ENERGY_DRIFT * shot.counterweight_energy_released
    theta0, phi0 = params(design).theta0, params(design).phi0
    assert np.all(shot.history.q[:, 1] == phi0) and np.all(shot.history.qdot[:, 1] == 0.0)
    assert shot.history.q[0, 0] == theta0


@pytest.mark.parametrize("name", ["fixed-lossy", "fixed-rolling-lossy"])
def test_the_energy_audit_closes_and_no_hinge_dissipates(name):
    from analytic.reference import simulate

    from support import fixed_designs

    shot = simulate(fixed_designs()[name])
    assert shot.ok
    e = shot.history.energy
    assert np.max(np.abs(e.total + e.lost)) <= AUDIT_TOL * shot.counterweight_energy_released
    assert shot.energy_dissipated["axle"] > 0.0 and shot.energy_dissipated["base"] > 0.0
    assert shot.energy_dissipated["hinge"] == 0.0


def test_simulate_json_of_a_fixed_design_has_the_hinged_keys_and_no_nan(capsys):
    import json

    from analytic.cli import EXIT_OK, main

    assert main(["simulate", "--json"]) == EXIT_OK
    hinged = json.loads(capsys.readouterr().out)
    assert main(["simulate", "--json", FIXED_FILE]) == EXIT_OK
    fixed = json.loads(capsys.readouterr().out)
    assert set(fixed) == set(hinged) and fixed["design"] == "paper-table3-fixed" and fixed["status"] == "ok"
    numbers = [v for v in fixed.values() if isinstance(v, float)]
    assert numbers and all(math.isfinite(v) for v in numbers)
    # The mount's load holds at least the counterweight's weight at some instant (it starts at rest).
    assert fixed["peak_hinge_load"] >= 6.5 * 9.81
