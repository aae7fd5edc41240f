"""The floating-arm machine as both paths simulate it (``docs/derivation.md`` section 12).

``analytic.eom`` builds it as the fixed machine with phi held, its (theta, psi) equations
``analytic.floating_arm.terms``'s and its axle's motion ``x_A = -Lb sin(theta)`` carried as a
frame's (``eom.frame_displacement`` and its rates). Every check of the equations compares them
with ``tests/sympy_model.py``'s ``machine("floating-arm")`` at random designs and states, stages
1 and 2; the whole shots with each other (the two paths) and with the conservation of energy.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from analytic import eom, friction, stages
from analytic.design import Base, DesignError, Losses
from analytic.design_file import load_design
from analytic.parameters import params

from support import TABLE3_FLOATING_FILE, floating_designs, floating_failure_designs, with_environment

#: Agreement with the sympy reference at one state, relative to the largest entry compared: closed
#: forms in a few dozen double operations (round-off ~1e-14), room for the solves (as
#: tests/test_analytic_fixed.py's REL_TOL); a wrong term is O(1).
REL_TOL = 1e-10
SEED = 28_013


def _samples(n: int, seed: int):
    """(p, q, q') of random floating-arm machines: the sample file's with a random arm, projectile,
    counterweight and gravity."""
    rng = np.random.default_rng(seed)
    base = params(load_design(TABLE3_FLOATING_FILE))
    out = []
    for _ in range(n):
        p = base._replace(mA=rng.uniform(0.1, 3.0), d=rng.uniform(-0.2, 0.6), mP=rng.uniform(0.02, 2.0),
                          IW=rng.uniform(0.0, 0.1), IA=rng.uniform(0.0, 0.1), mW=rng.uniform(1.0, 50.0),
                          g=rng.uniform(1.0, 25.0), Lb=rng.uniform(0.1, 0.5))
        q, qd = rng.uniform(-math.pi, math.pi, 3), rng.normal(0.0, 6.0, 3)
        out.append((p, (q[0], 0.0, q[2]), (qd[0], 0.0, qd[2])))
    return out


SWING = _samples(8, SEED)
#: Stage 1: theta within the sling's reach (psi from the base constraint).
SLIDE = [(p, math.acos(-p.h / p.La) - u, qd[0])
         for (p, _, qd), u in zip(_samples(8, SEED + 1), np.random.default_rng(SEED + 2).uniform(0.05, 0.6, 8))]


@pytest.fixture(scope="module")
def lagrangian():
    from sympy_model import machine

    return machine("floating-arm")


def _close(got, expected, what, scale=None):
    got, expected = np.asarray(got, dtype=float), np.asarray(expected, dtype=float)
    scale = float(np.max(np.abs(expected))) if scale is None else scale
    error = float(np.max(np.abs(got - expected)))
    assert error <= REL_TOL * scale, f"{what}: analytic {got} vs sympy {expected} (error {error:.3g})"


def _check_forces(lagrangian, p, q, qd, qdd, normal):
    """eom's joint forces against Newton's law on sympy's motion: the axle's is the track's vertical
    push (no horizontal: the track is smooth), the mount's the counterweight's force less the guide's."""
    acc = (*qdd, 0.0)
    total, weight, sling = lagrangian.joint_forces(p, (*q, 0.0), (*qd, 0.0), acc, 0.0, normal)
    guide = total[0]   # the whole machine's horizontal force: only the guide pushes sideways
    got = eom.joint_forces(*q, *qd, *qdd, normal, p)
    scale = max(float(np.max(np.abs(np.concatenate([total, weight, sling])))), (p.mA + p.mW + p.mP) * p.g)
    _close(got[0:2], [0.0, total[1]], "track force on the axle", scale)
    _close(got[2:4], [weight[0] - guide, weight[1]], "mount force on the counterweight", scale)
    _close(got[4:6], sling, "sling force on the projectile", scale)


@pytest.mark.parametrize("i", range(len(SWING)))
def test_the_swing_is_the_lagrangians(lagrangian, i):
    p, q, qd = SWING[i]
    m11, m12, m13, m22, m33, f1, f2, f3 = eom.terms(*q, *qd, p)
    m, f = lagrangian.mass(p, q, qd), lagrangian.forcing(p, q, qd)
    _close([m11, m13, m33], [m[0, 0], m[0, 2], m[2, 2]], "M over (theta, psi)")
    _close([f1, f3], [f[0], f[2]], "f over (theta, psi)")
    assert (m12, m22, f2) == (0.0, 1.0, 0.0)
    qdd = eom.swing_accelerations(*q, *qd, p)
    acc = lagrangian.accelerations(p, q, qd)
    _close(qdd, acc[:3], "theta'', phi'', psi''")
    _check_forces(lagrangian, p, q, qd, qdd, 0.0)


@pytest.mark.parametrize("i", range(len(SLIDE)))
def test_the_slide_and_the_base_push_are_the_lagrangians(lagrangian, i):
    p, theta, dtheta = SLIDE[i]
    ddtheta, ddphi, normal = eom.slide_accelerations(theta, 0.0, dtheta, 0.0, p)
    psi, dpsi, s, c, _ = eom.slide_constraint(theta, dtheta, p)
    q, qd, qdd = (theta, 0.0, psi), (dtheta, 0.0, dpsi), (ddtheta, ddphi, s * ddtheta + c)
    acc, normal_ref = lagrangian.on_base(p, q, qd)
    _close(qdd, acc[:3], "theta'', phi'', psi''")
    _close(normal, normal_ref, "base push", (p.mA + p.mW + p.mP) * p.g + abs(normal_ref))
    _check_forces(lagrangian, p, q, qd, qdd, normal)


@pytest.mark.parametrize("i", range(len(SWING)))
def test_energies_and_the_projectile_on_the_ground_are_the_lagrangians(lagrangian, i):
    """Kinetic and potential energy, and the flight's start: position and velocity from the origin
    where the guide meets the track, the axle's motion included."""
    p, q, qd = SWING[i]
    energies = lagrangian.energies(p, (*q, 0.0), (*qd, 0.0))
    scale = float(np.max(np.abs(energies)))
    _close(eom.kinetic_energy(*q, *qd, p), energies[:2], "T", scale)
    _close(eom.potential_energy(*q, p), energies[2:], "V", scale)
    position, velocity = lagrangian.projectile(p, (*q, 0.0), (*qd, 0.0))
    x, y, vx, vy = stages.flight_start(np.array([*q, *qd]), p)
    _close([x, y], position, "projectile position", p.La + p.Lb + p.Ls)
    _close([vx, vy], velocity, "projectile velocity", (p.La + p.Lb + p.Ls) * float(np.max(np.abs(qd))))


def test_the_axle_starts_behind_the_guide_and_moves_with_the_arm():
    p = params(load_design(TABLE3_FLOATING_FILE))
    assert eom.frame_displacement(p.theta0, 0.0, 0.0, p) == -p.Lb * math.sin(p.theta0) < 0.0
    assert eom.frame_velocity(p.theta0, 0.0, 0.0, 2.0, 0.0, 0.0, p) == -p.Lb * math.cos(p.theta0) * 2.0


@pytest.mark.parametrize("i", range(len(SWING)))
@pytest.mark.parametrize("mode", [-1.0, 1.0, 0.0], ids=["slipping-back", "slipping-forward", "stuck"])
def test_axle_friction_is_coulombs_law_on_the_tracks_force_and_the_motion_the_lagrangians(lagrangian, i, mode):
    """``analytic.friction``'s axle torque as a generalised force on theta: M q'' = f + Q over
    (theta, psi); slipping, |ta| = mua ra |A| with A the track's push (the axle's only reaction);
    stuck, theta'' = 0."""
    p, q, qd = SWING[i]
    p = p._replace(mua=0.3, ra=0.02, mua_s=0.4)
    ddtheta, ddphi, ddpsi, ta, th, axle, _ = friction.swing_friction(*q, *qd, mode, 0.0, p)
    assert ddphi == 0.0 and th == 0.0
    acc = np.array([ddtheta, 0.0, ddpsi, 0.0])
    q4, qd4 = (*q, 0.0), (*qd, 0.0)
    m, f = lagrangian.mass(p, q4, qd4), lagrangian.forcing(p, q4, qd4)
    residual = (m @ acc - f - lagrangian.generalised(p, q4, qd4, ta, 0.0, 0.0))[[0, 2]]
    _close(residual, np.zeros(2), "M q'' - f - Q", float(np.max(np.abs(f))) + abs(ta))
    track = lagrangian.joint_forces(p, q4, qd4, acc)[0][1]
    if mode == 0.0:   # held: the most the axle's static friction holds (friction.slides_friction)
        assert ddtheta == 0.0
        _close(axle, p.mua_s * p.ra * abs(track), "mua_s ra |A|", p.mua_s * p.ra * abs(track))
    else:
        _close(axle, abs(track), "|A|", abs(track))
        _close(ta, -mode * p.mua * p.ra * axle, "ta", abs(ta))


# --------------------------------------------------------------------------- #
# Whole shots
# --------------------------------------------------------------------------- #

#: The ideal machine's energy is conserved through stages 1-2 to the integrator's error, relative to
#: the counterweight's released energy (as tests/test_analytic_fixed.py's ENERGY_DRIFT).
ENERGY_DRIFT = 1e-8


@pytest.mark.parametrize("name", ["floating", "floating-large", "floating-sample-1"])
def test_an_ideal_floating_shot_conserves_energy(name):
    from analytic.reference import simulate

    design = with_environment(floating_designs()[name], air_density=0.0)
    shot = simulate(design)
    assert shot.ok
    assert np.max(np.abs(shot.history.energy.total)) <= ENERGY_DRIFT * shot.counterweight_energy_released
    assert np.all(shot.history.qdot[:, 1] == 0.0)


#: The energy audit (the axle's work + the machine's energy change) closes to this, relative
#: (as tests/test_analytic_fixed.py's AUDIT_TOL).
AUDIT_TOL = 1e-8


def test_the_energy_audit_closes_with_the_axles_friction():
    from analytic.reference import simulate

    shot = simulate(floating_designs()["floating-axle-friction"])
    assert shot.ok
    e = shot.history.energy
    assert np.max(np.abs(e.total + e.lost)) <= AUDIT_TOL * shot.counterweight_energy_released
    assert shot.energy_dissipated["axle"] > 0.0
    assert shot.energy_dissipated["hinge"] == 0.0 and shot.energy_dissipated["base"] == 0.0


@pytest.mark.parametrize("name", floating_designs())
def test_the_two_paths_agree_on_floating_designs(name):
    """The hinged designs' targets (tests/test_analytic_fast.py's ``_assert_agree``)."""
    from test_analytic_fast import _assert_agree

    _assert_agree(floating_designs()[name])


@pytest.mark.parametrize("status", floating_failure_designs(), ids=lambda s: s.value)
def test_every_failure_status_on_a_floating_arm(status):
    from test_analytic_fast import _assert_agree

    _, got = _assert_agree(floating_failure_designs()[status])
    assert got.status is status


def test_the_release_is_measured_from_the_guide():
    """The release position is the projectile's from the origin: the pivot-relative one plus x_A."""
    from analytic.reference import simulate

    shot = simulate(load_design(TABLE3_FLOATING_FILE))
    p = params(shot.design)
    theta, psi = shot.history.q[-1, 0], shot.history.q[-1, 2]
    assert shot.frame_release_displacement == pytest.approx(-p.Lb * math.sin(theta), abs=1e-12)
    x = -(p.La + p.Lb) * math.sin(theta) - p.Ls * math.sin(theta + psi)
    assert shot.release_position[0] == pytest.approx(x, abs=1e-12)


def test_a_rolling_floating_arm_is_refused_naming_the_field():
    import dataclasses

    design = load_design(TABLE3_FLOATING_FILE)
    with pytest.raises(DesignError) as error:
        dataclasses.replace(design, base=Base("rolling", 5.0))
    assert error.value.field == "base.mobility"
    assert "rolling" in str(error.value)


def test_a_floating_arm_takes_the_bases_friction():
    import dataclasses

    design = load_design(TABLE3_FLOATING_FILE)
    losses = Losses(base_friction=0.3, base_static_friction=0.4)
    assert dataclasses.replace(design, losses=losses).losses.base_static_friction == 0.4


# --------------------------------------------------------------------------- #
# The supports' loads
# --------------------------------------------------------------------------- #

#: The supports' forces against the whole machine's momentum differentiated numerically over the
#: history's stage-2 rows (second-order differences at the 0.5 ms output step, one-sided at the
#: ends: error ~ dt^2 |P'''| / 3, well under 1e-3 of the forces here), relative to the largest force.
MOMENTUM_TOL = 1e-3


def _momentum(q, qd, p):
    """The whole machine's momentum (x, y), kg m/s, from the positions of derivation (12.1)."""
    theta, beta = q[:, 0], q[:, 0] + q[:, 2]
    dtheta, dbeta = qd[:, 0], qd[:, 0] + qd[:, 2]
    c, s = np.cos(theta), np.sin(theta)
    px = (-p.mA * (p.Lb + p.d) * c * dtheta
          - p.mP * ((p.La + p.Lb) * c * dtheta + p.Ls * np.cos(beta) * dbeta))
    py = (-p.mA * p.d * s * dtheta + p.mW * p.Lb * s * dtheta
          - p.mP * (p.La * s * dtheta + p.Ls * np.sin(beta) * dbeta))
    return px, py


@pytest.mark.parametrize("name", ["floating", "floating-large", "floating-axle-friction"])
def test_the_track_and_guide_loads_are_the_momentums_rate(name):
    from analytic.reference import simulate

    shot = simulate(floating_designs()[name])
    p = params(shot.design)
    h = shot.history
    swing = h.stage == 2
    px, py = _momentum(h.q[swing], h.qdot[swing], p)
    t = h.t[swing]
    guide = np.gradient(px, t, edge_order=2)
    track = np.gradient(py, t, edge_order=2) + (p.mA + p.mW + p.mP) * p.g
    scale = max(np.abs(track).max(), np.abs(guide).max())
    assert abs(shot.max_guide_force - np.abs(guide).max()) <= MOMENTUM_TOL * scale
    assert abs(shot.max_track_force - track.max()) <= MOMENTUM_TOL * scale
    assert shot.min_track_force <= track.min() + MOMENTUM_TOL * scale
    # The track is the axle's only support: its largest push is the peak axle load (located between samples).
    assert shot.max_track_force <= shot.peak_axle_load * (1.0 + 1e-12)


def test_simulate_json_has_the_floating_keys_and_other_kinds_do_not(capsys):
    import json

    from analytic.cli import EXIT_OK, main
    from analytic.result import FLOATING_JSON_KEYS

    assert main(["simulate", "--json", str(TABLE3_FLOATING_FILE)]) == EXIT_OK
    out = json.loads(capsys.readouterr().out)
    p = params(load_design(TABLE3_FLOATING_FILE))
    assert all(isinstance(out[key], float) and math.isfinite(out[key]) for key in FLOATING_JSON_KEYS)
    assert out["min_track_force"] < out["max_track_force"] and out["max_guide_force"] > 0.0
    assert -p.Lb < out["axle_displacement_at_release"] < p.Lb
    for other in ([], ["analytic/data/paper_table3_fixed.toml"]):
        assert main(["simulate", "--json", *other]) == EXIT_OK
        assert not set(FLOATING_JSON_KEYS) & set(json.loads(capsys.readouterr().out))


def test_the_table_measures_from_the_guide_and_lists_the_supports(capsys):
    from analytic.cli import EXIT_OK, main

    assert main(["simulate", str(TABLE3_FLOATING_FILE)]) == EXIT_OK
    table = capsys.readouterr().out
    assert "m from guide" in table and "range (from guide)" in table and "pivot" not in table
    assert "track force, max" in table and "max guide force" in table and "axle at release" in table
    assert main(["simulate"]) == EXIT_OK
    hinged = capsys.readouterr().out
    assert "range (from pivot)" in hinged and "track" not in hinged and "guide" not in hinged
