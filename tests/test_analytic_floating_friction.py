"""A floating arm's guide and track friction (``docs/derivation.md`` 12.8-12.12), in both paths.

The friction's generalised force, the supports' normal forces and Coulomb's law on each are
checked against ``tests/sympy_model.py``'s ``machine("floating-arm")`` (virtual work of the two
friction forces by sympy's Jacobians, Newton's law for the whole machine by its accelerations)
at random states, slipping either way and held; whole shots by the energy audit, by the two
paths' agreement and by a machine the friction holds at rest.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from analytic import friction, stages, states
from analytic.design import Losses
from analytic.design_file import load_design
from analytic.fast import simulate_fast
from analytic.parameters import params
from analytic.result import Status

from support import TABLE3_FLOATING_FILE
from test_analytic_floating import REL_TOL, SLIDE, SWING, _close

#: The coefficients of the random states: large enough that a wrong term shows at O(1) of the
#: friction, small enough that every Coulomb system has one solution.
COEFFICIENTS = dict(mua=0.3, ra=0.02, mug=0.25, mut=0.35, mua_s=0.4, mug_s=0.3, mut_s=0.45)


@pytest.fixture(scope="module")
def lagrangian():
    from sympy_model import machine

    return machine("floating-arm")


def _supports(lagrangian, p, q4, qd4, acc, normal, fg, ft):
    """Newton's law for the whole machine: the guide's and the track's normal forces (G, T), N, less
    the other support's friction (the track's ft is horizontal, the guide's fg vertical)."""
    rate = lagrangian.momentum_rate(p, q4, qd4, acc)
    weight = (p.mA + p.mW + p.mP + p.mS + p.mQ) * p.g   # every part, the sling and the pouch too
    return rate[0] - ft, rate[1] + weight - normal - fg


def _limit(lagrangian, p, q4, qd4, acc, normal, sa):
    """Every friction at its static limit against turning with sign ``sa``, at the held arm's
    accelerations: Coulomb's law by fixed-point iteration on sympy's forces (independent of the
    model's Newton solve). Returns ``(ta, fg, ft)``."""
    _, v_weight, v_axle = lagrangian.slides(p, q4, (sa, 0.0, 0.0, 0.0), 0.0, 0.0)   # the sliding's signs
    sg, st = np.sign(v_weight[1]), np.sign(v_axle[0])
    fg = ft = 0.0
    for _ in range(200):
        guide, track = _supports(lagrangian, p, q4, qd4, acc, normal, fg, ft)
        fg, ft = -sg * p.mug_s * abs(guide), -st * p.mut_s * abs(track)
    _, track = _supports(lagrangian, p, q4, qd4, acc, normal, fg, ft)
    return -sa * p.mua_s * p.ra * math.hypot(ft, track), fg, ft


@pytest.mark.parametrize("i", range(len(SWING)))
@pytest.mark.parametrize("mode", [-1.0, 1.0, 0.0], ids=["slipping-back", "slipping-forward", "stuck"])
def test_guide_and_track_friction_is_coulombs_law_and_the_motion_the_lagrangians(lagrangian, i, mode):
    """Stage 2: M q'' = f + Q over (theta, psi), Q on theta alone; slipping, each friction is its
    coefficient times its normal force against its sliding, and Q their virtual work; held,
    theta'' = 0 and the hold is every friction at its static limit."""
    p, q, qd = SWING[i]
    p = p._replace(**COEFFICIENTS)
    qd = (mode * abs(qd[0]), 0.0, qd[2])   # the arm turning the way it slips (held: still)
    ddtheta, ddphi, ddpsi, q_theta, fg, hold, ft = friction.swing_friction(*q, *qd, mode, 0.0, p)
    assert ddphi == 0.0
    acc = np.array([ddtheta, 0.0, ddpsi, 0.0])
    q4, qd4 = (*q, 0.0), (*qd, 0.0)
    m, f = lagrangian.mass(p, q4, qd4), lagrangian.forcing(p, q4, qd4)
    residual = (m @ acc - f)[[0, 2]] - [q_theta, 0.0]
    _close(residual, np.zeros(2), "M q'' - f - Q", float(np.max(np.abs(f))) + abs(q_theta))
    guide, track = _supports(lagrangian, p, q4, qd4, acc, 0.0, fg, ft)
    slides, v_weight, v_axle = lagrangian.slides(p, q4, qd4, fg, ft)
    scale = (p.mA + p.mW + p.mP) * p.g + abs(guide) + abs(track)
    if mode == 0.0:
        assert ddtheta == 0.0
        ta, fg_limit, ft_limit = _limit(lagrangian, p, q4, qd4, acc, 0.0, -1.0 if q_theta > 0.0 else 1.0)
        limit = ta + lagrangian.slides(p, q4, qd4, fg_limit, ft_limit)[0][0]
        _close(hold, abs(limit), "the hold", abs(limit))
        return
    _close(fg, -np.sign(v_weight[1]) * p.mug * abs(guide), "guide friction fg", scale)
    _close(ft, -np.sign(v_axle[0]) * p.mut * abs(track), "track friction ft", scale)
    ta = -mode * p.mua * p.ra * math.hypot(ft, track)   # the axle's pin carries the carriage's (ft, T)
    _close(hold, math.hypot(ft, track), "|A|", scale)
    _close(q_theta, ta + slides[0], "Q: the axle's torque and the slides' virtual work", scale * p.Lb)
    assert slides[1] == slides[2] == 0.0   # neither slide moves with phi or psi


@pytest.mark.parametrize("i", range(len(SLIDE)))
def test_on_the_base_the_friction_is_coulombs_law_and_n_the_lagrangians(lagrangian, i):
    """Stage 1, slipping clockwise: the reduced system's theta'' and N with Q on theta, against
    sympy's constrained Lagrangian (``base_reduction``) and Newton's law."""
    p, theta, dtheta = SLIDE[i]
    p = p._replace(**COEFFICIENTS)
    dtheta = -abs(dtheta)
    ddtheta, _, normal, q_theta, fg, ft, _, _, _ = friction.slide_friction(theta, 0.0, dtheta, 0.0, -1.0, 0.0,
                                                                             0.0, p)
    psi, dpsi, s, c, _ = stages.slide_constraint(theta, dtheta, p)
    acc = np.array([ddtheta, 0.0, s * ddtheta + c, 0.0])
    q4, qd4 = (theta, 0.0, psi, 0.0), (dtheta, 0.0, dpsi, 0.0)
    m, f = lagrangian.mass(p, q4, qd4), lagrangian.forcing(p, q4, qd4)
    jacobian = lagrangian.base_jacobian(p, q4)
    residual = (m @ acc - f - jacobian * normal)[[0, 2]] - [q_theta, 0.0]
    _close(residual, np.zeros(2), "M q'' - f - J^T N - Q", float(np.max(np.abs(f))) + abs(q_theta))
    guide, track = _supports(lagrangian, p, q4, qd4, acc, normal, fg, ft)
    _, v_weight, v_axle = lagrangian.slides(p, q4, qd4, fg, ft)
    scale = (p.mA + p.mW + p.mP) * p.g + abs(guide) + abs(track)
    _close(fg, -np.sign(v_weight[1]) * p.mug * abs(guide), "guide friction fg", scale)
    _close(ft, -np.sign(v_axle[0]) * p.mut * abs(track), "track friction ft", scale)


@pytest.mark.parametrize("i", range(len(SWING)))
def test_the_supports_and_the_loads_carry_the_friction(lagrangian, i):
    """``stages.floating_supports`` and ``stages.loads_at`` in stage 2: the guide's and the track's
    normal forces are Newton's less the other's friction, the axle carries the carriage's (ft, T),
    the counterweight's mount its Newton force less the guide's (G, fg)."""
    p, q, qd = SWING[i]
    p = p._replace(**COEFFICIENTS)
    qd = (-abs(qd[0]), 0.0, qd[2])
    y = [q[0], 0.0, q[2], qd[0], 0.0, qd[2], 0.0, 0.0, 0.0, -1.0, 0.0, 0.0]
    ddtheta, _, ddpsi, _, fg, _, ft = friction.swing_friction(*q, *qd, -1.0, 0.0, p)
    acc = np.array([ddtheta, 0.0, ddpsi, 0.0])
    q4, qd4 = (*q, 0.0), (*qd, 0.0)
    guide, track = _supports(lagrangian, p, q4, qd4, acc, 0.0, fg, ft)
    scale = (p.mA + p.mW + p.mP) * p.g + abs(guide) + abs(track)
    _close(stages.floating_supports(states.SWING, y, p), [track, guide], "(T, G)", scale)
    weight = lagrangian.joint_forces(p, q4, qd4, acc)[1]
    loads = stages.loads_at(states.SWING, y, p)
    _close(loads[0], math.hypot(ft, track), "axle load |(ft, T)|", scale)
    _close(loads[1], math.hypot(weight[0] - guide, weight[1] - fg), "mount load", scale)


# --------------------------------------------------------------------------- #
# Whole shots
# --------------------------------------------------------------------------- #

#: The energy audit closes to this, relative to the counterweight's released energy: the axle's
#: friction's tolerance (tests/test_analytic_floating.py's AUDIT_TOL).
AUDIT_TOL = 1e-8


def _with_losses(**losses):
    design = load_design(TABLE3_FLOATING_FILE)
    return dataclasses.replace(design, losses=Losses(**losses), name="floating-" + "-".join(losses))


#: Designs of the sample floating arm with its slides' friction (and the axle's).
LOSSY = {"guide": _with_losses(guide_friction=0.3),
         "track": _with_losses(track_friction=0.3),
         "all": _with_losses(guide_friction=0.2, track_friction=0.25, axle_friction=0.2, axle_radius=0.02,
                             guide_static_friction=0.4, track_static_friction=0.3, axle_static_friction=0.3)}


def _audited(design):
    """The reference path's shot of ``design``, its energy audit closed, each friction's work taken
    where the design has that friction (and reported as the history's last); the hinge's none."""
    from analytic.reference import simulate

    shot = simulate(design)
    assert shot.ok
    e = shot.history.energy
    assert np.max(np.abs(e.total + e.lost)) <= AUDIT_TOL * shot.counterweight_energy_released
    for loss in ("axle", "guide", "track", "base"):
        assert (shot.energy_dissipated[loss] > 0.0) == (getattr(design.losses, f"{loss}_friction") > 0.0), loss
        assert shot.energy_dissipated[loss] == (e.dissipated[loss][-1] if loss in e.dissipated else 0.0), loss
    assert shot.energy_dissipated["hinge"] == 0.0
    return shot


@pytest.mark.parametrize("name", LOSSY)
def test_the_energy_audit_closes_with_the_guides_and_the_tracks_friction(name):
    _audited(LOSSY[name])


def test_more_friction_takes_more_and_throws_shorter():
    from analytic.reference import simulate

    shots = [simulate(_with_losses(guide_friction=mu, track_friction=mu), histories=False) for mu in (0.0, 0.1, 0.2)]
    ranges = [shot.range for shot in shots]
    taken = [shot.energy_dissipated["guide"] + shot.energy_dissipated["track"] for shot in shots]
    assert ranges[0] > ranges[1] > ranges[2] and taken[0] == 0.0 < taken[1] < taken[2]


#: Friction that holds the sample machine: gravity turns its arm with 7.8 N m at rest, and its
#: slides hold 10.8 N m at a coefficient of 5 (``friction.rest_balance``; 7.1 N m at 0.5: it fires).
HELD = _with_losses(guide_friction=5.0, track_friction=5.0)


@pytest.mark.parametrize("name", [*LOSSY, "held"])
def test_the_two_paths_agree_with_the_slides_friction(name):
    from test_analytic_fast import _assert_agree

    _assert_agree(HELD if name == "held" else LOSSY[name])


def test_a_machine_its_slides_hold_at_rest_never_fires_and_says_why():
    from analytic.reference import simulate

    for shot in (simulate(HELD), simulate_fast(HELD)):
        assert shot.status is Status.NEVER_FIRES
        # The words of either model, naming the frictions the design has (no axle friction here).
        assert "the guide's and the track's friction holds it at rest" in shot.message, shot.message
    drive, hold, base = friction.rest_balance(params(HELD))
    assert 0.0 < drive <= hold and base == 0.0


def test_simulate_reports_the_guides_and_the_tracks_work(tmp_path, capsys):
    import json

    from analytic.cli import EXIT_OK, main
    from analytic.design_file import save_design

    path = tmp_path / "floating.toml"
    save_design(LOSSY["all"], path)
    assert main(["simulate", "--json", str(path)]) == EXIT_OK
    taken = json.loads(capsys.readouterr().out)["energy_dissipated"]
    assert taken["guide"] > 0.0 and taken["track"] > 0.0 and taken["hinge"] == taken["base"] == 0.0
    assert main(["simulate", str(path)]) == EXIT_OK
    table = capsys.readouterr().out
    rows = [line.split()[0] for line in table.splitlines() if line.strip().endswith("% of it)")]
    assert rows == ["axle", "guide", "track", "air"]   # the friction first, then the drag in flight


@pytest.mark.parametrize("mu", [0.5, 0.6])
def test_the_slides_hold_at_rest_decides_whether_it_fires(mu):
    """Either side of the balance on the sample machine (``friction.rest_balance``: the hold is
    7.15 N m at 0.5 and 8.26 N m at 0.6 against gravity's 7.76 N m), on both paths."""
    from analytic.reference import simulate

    design = _with_losses(guide_friction=mu, track_friction=mu)
    drive, hold, _ = friction.rest_balance(params(design))
    for shot in (simulate(design, histories=False), simulate_fast(design)):
        assert (shot.status is Status.NEVER_FIRES) == (hold >= drive), (mu, shot.status)
    assert (hold >= drive) == (mu == 0.6)


def _slipping_solutions(theta, psi, dtheta, dpsi, sa, p):
    """The guide's and the track's friction ``(fg, ft)`` of every slipping solution of (12.10) without
    the axle's friction, found by trying each sign of G and T: the system is then linear (numpy)."""
    from analytic import eom
    from analytic.floating_arm import support_forces

    m11, m12, m13, m22, m33, f1, f2, f3 = eom.terms(theta, 0.0, psi, dtheta, 0.0, dpsi, p)
    a1, _, a3 = eom.solve_symmetric(m11, m12, m13, m22, 0.0, m33, f1, f2, f3)
    u1, _, u3 = eom.solve_symmetric(m11, m12, m13, m22, 0.0, m33, 1.0, 0.0, 0.0)
    track0, guide0 = support_forces(theta, psi, dtheta, dpsi, a1, a3, 0.0, p)
    track_u, guide_u = support_forces(theta, psi, 0.0, 0.0, u1, u3, 0.0, p)
    track_u -= (p.mA + p.mW + p.mP) * p.g
    ls, lc = p.Lb * math.sin(theta), p.Lb * math.cos(theta)
    sg, st = sa * np.sign(ls), -sa * np.sign(lc)
    found = []
    for eg in (-1.0, 1.0):
        for et in (-1.0, 1.0):   # unknowns fg, ft, G, T with sign(G) = eg, sign(T) = et
            system = np.array([[1.0, 0.0, sg * p.mug * eg, 0.0], [0.0, 1.0, 0.0, st * p.mut * et],
                               [-guide_u * ls, guide_u * lc + 1.0, 1.0, 0.0],
                               [1.0 - track_u * ls, track_u * lc, 0.0, 1.0]])
            fg, ft, guide, track = np.linalg.solve(system, [0.0, 0.0, guide0, track0])
            if guide * eg >= 0.0 and track * et >= 0.0:
                found.append((fg, ft))
    return found


def test_a_jam_gives_nan_and_a_unique_slip_is_found():
    """Large coefficients can leave Coulomb's law with no slipping motion (the guide and the track
    jam) or several; the model's solve gives NaN where there is none (the integrator then rejects
    the step), and the one solution where there is exactly one."""
    from test_analytic_floating import _samples

    rng = np.random.default_rng(SEED_JAM)
    outcomes = {"none": 0, "one": 0}
    for p, q, qd in _samples(150, SEED_JAM):
        mu = rng.uniform(0.0, 2.0, 2)
        p = p._replace(mug=mu[0], mut=mu[1], mug_s=mu[0], mut_s=mu[1])
        qd = (abs(qd[0]), 0.0, qd[2])
        solutions = _slipping_solutions(q[0], q[2], qd[0], qd[2], 1.0, p)
        _, _, _, _, fg, _, ft = friction.swing_friction(*q, *qd, 1.0, 0.0, p)
        if not solutions:
            assert math.isnan(fg) and math.isnan(ft)
            outcomes["none"] += 1
        elif len(solutions) == 1:
            _close([fg, ft], solutions[0], "the one slipping solution", max(1.0, *np.abs(solutions[0])))
            outcomes["one"] += 1
    assert outcomes["none"] > 0 and outcomes["one"] > 0, outcomes   # both cases met


#: Draws of ``test_a_jam_gives_nan_and_a_unique_slip_is_found``.
SEED_JAM = 28_128


def test_a_held_machine_whose_slides_would_jam_slipping_is_held_not_failed():
    """A 20 kg counterweight and coefficients of 1.2 on the sample machine: its friction holds it at
    rest (``rest_balance``: 35.0 N m against 24.6), and slipping from rest the guide and the track
    would jam (no solution, NaN): the shot never fires, on both paths, rather than failing."""
    from analytic.reference import simulate

    design = _with_losses(guide_friction=1.2, track_friction=1.2)
    design = dataclasses.replace(design, machine=dataclasses.replace(design.machine, counterweight_mass=20.0))
    p = params(design)
    drive, hold, _ = friction.rest_balance(p)
    assert 0.0 < drive < hold
    assert math.isnan(friction.slide_friction(p.theta0, p.phi0, 0.0, 0.0, -1.0, 0.0, 0.0, p)[0])
    for shot in (simulate(design), simulate_fast(design)):
        assert shot.status is Status.NEVER_FIRES, shot.message


# --------------------------------------------------------------------------- #
# The base's friction on a floating arm [12.13]
# --------------------------------------------------------------------------- #

#: The base's coefficients, alone and with the axle's, the guide's and the track's (``COEFFICIENTS``),
#: and those with a sling and a pouch with mass (kg; the base then carries them too, derivation 14).
BASE_COEFFICIENTS = {"base": dict(mub=0.4, mub_s=0.55),
                     "base-and-slides": dict(COEFFICIENTS, mub=0.4, mub_s=0.55),
                     "base-slides-heavy-sling": dict(COEFFICIENTS, mub=0.4, mub_s=0.55, mS=0.03, mQ=0.01)}


def _on_base(lagrangian, p, theta, dtheta):
    """A stage-1 state ``(q4, qd4, s)`` from the base constraint, and the slide's rate ``D``: the
    projectile's ground x velocity per unit theta' along the constraint, by sympy."""
    psi, dpsi, s, _, _ = stages.slide_constraint(theta, dtheta, p)
    q4 = (theta, 0.0, psi, 0.0)
    slide = lagrangian.projectile(p, q4, (1.0, 0.0, s, 0.0))[1][0]
    return q4, (dtheta, 0.0, dpsi, 0.0), s, slide


def _base_residual(lagrangian, p, q4, qd4, acc, normal, q_theta, base_force):
    """``M q'' - f - J^T N - Q`` over (theta, psi), Q the slides' on theta and the base's friction's virtual
    work on the projectile's ground position (sympy's Jacobian, the axle's travel in it)."""
    m, f = lagrangian.mass(p, q4, qd4), lagrangian.forcing(p, q4, qd4)
    jacobian = lagrangian.base_jacobian(p, q4)
    base = lagrangian.force_on_projectile(p, q4, (base_force, 0.0))
    residual = (m @ acc - f - jacobian * normal - base)[[0, 2]] - [q_theta, 0.0]
    return residual, float(np.max(np.abs(f))) + abs(q_theta) + abs(base_force) * (p.La + p.Lb + p.Ls)


@pytest.mark.parametrize("i", range(len(SLIDE)))
@pytest.mark.parametrize("losses", BASE_COEFFICIENTS)
def test_the_bases_friction_is_coulombs_law_on_the_projectiles_ground_slide(lagrangian, i, losses):
    """Stage 1, slipping clockwise, with the base's friction: ``F = -mub sb N`` against the projectile's
    slide on the ground (the axle's travel included), its virtual work in the motion, the guide's normal
    force less it, and the slides' Coulomb's law as before, against sympy."""
    p, theta, dtheta = SLIDE[i]
    p = p._replace(**BASE_COEFFICIENTS[losses])
    dtheta = -abs(dtheta)
    q4, qd4, s, slide = _on_base(lagrangian, p, theta, dtheta)
    sb = float(np.sign(slide * dtheta))
    solved = friction.slide_friction(theta, 0.0, dtheta, 0.0, -1.0, 0.0, sb, p)
    ddtheta, _, normal, q_theta, fg, ft, _, base_force, dx = solved
    _close(dx, slide, "D = dx_P/dtheta", p.La + p.Lb + p.Ls)
    psi_rates = stages.slide_constraint(theta, dtheta, p)
    acc = np.array([ddtheta, 0.0, s * ddtheta + psi_rates[3], 0.0])
    residual, scale = _base_residual(lagrangian, p, q4, qd4, acc, normal, q_theta, base_force)
    _close(residual, np.zeros(2), "M q'' - f - J^T N - Q", scale)
    _close(base_force, -sb * p.mub * normal, "base friction F", abs(normal))
    guide, track = _supports(lagrangian, p, q4, qd4, acc, normal, fg, ft)
    guide -= base_force   # the base pushes the whole machine along x too
    _, v_weight, v_axle = lagrangian.slides(p, q4, qd4, fg, ft)
    scale = (p.mA + p.mW + p.mP) * p.g + abs(guide) + abs(track)
    _close(fg, -np.sign(v_weight[1]) * p.mug * abs(guide), "guide friction fg", scale)
    _close(ft, -np.sign(v_axle[0]) * p.mut * abs(track), "track friction ft", scale)
    y = [theta, 0.0, dtheta, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, sb, 0.0]
    _close(stages.floating_supports(states.SLIDE, y, p), [track, guide], "(T, G)", scale)


@pytest.mark.parametrize("i", range(len(SLIDE)))
@pytest.mark.parametrize("losses", BASE_COEFFICIENTS)
def test_held_on_the_base_every_friction_is_at_its_static_limit(lagrangian, i, losses):
    """Stage 1 held (the arm still, ``sa`` 0): theta'' = 0, the base's friction at its static limit
    ``mub_s N`` against the clockwise slide, the slides' hold at their static limits with the guide's
    force less F, and the friction's Q what holds the arm; against sympy."""
    p, theta, _ = SLIDE[i]
    p = p._replace(**BASE_COEFFICIENTS[losses])
    q4, qd4, s, slide = _on_base(lagrangian, p, theta, 0.0)
    sb = -float(np.sign(slide))   # the way a clockwise start slides it
    ddtheta, _, normal, q_theta, _, _, hold, base_force, _ = friction.slide_friction(theta, 0.0, 0.0, 0.0, 0.0,
                                                                                      0.0, sb, p)
    assert ddtheta == 0.0
    acc = np.array([0.0, 0.0, stages.slide_constraint(theta, 0.0, p)[3], 0.0])
    residual, scale = _base_residual(lagrangian, p, q4, qd4, acc, normal, q_theta, base_force)
    _close(residual, np.zeros(2), "M q'' - f - J^T N - Q held", scale)
    _close(base_force, -sb * p.mub_s * normal, "F at its static limit", abs(normal))
    if p.mug_s == 0.0 and p.mut_s == 0.0 and p.mua_s == 0.0:
        return
    # The slides' static limits at the held arm's forces, the guide's less F (fixed point, as ``_limit``).
    sa = -1.0 if q_theta > 0.0 else 1.0
    _, v_weight, v_axle = lagrangian.slides(p, q4, (sa, 0.0, 0.0, 0.0), 0.0, 0.0)
    sg, st = np.sign(v_weight[1]), np.sign(v_axle[0])
    fg = ft = 0.0
    for _ in range(200):
        guide, track = _supports(lagrangian, p, q4, qd4, acc, normal, fg, ft)
        fg, ft = -sg * p.mug_s * abs(guide - base_force), -st * p.mut_s * abs(track)
    _, track = _supports(lagrangian, p, q4, qd4, acc, normal, fg, ft)
    limit = -sa * p.mua_s * p.ra * math.hypot(ft, track) + lagrangian.slides(p, q4, qd4, fg, ft)[0][0]
    _close(hold, abs(limit), "the hold", abs(limit))


@pytest.mark.parametrize("losses", BASE_COEFFICIENTS)
def test_at_rest_the_base_holds_its_static_limit_through_the_flat_sling(lagrangian, losses):
    """``rest_balance`` of a floating arm: gravity's drive as without the base, the base's hold
    ``mub_s N |D|`` with D the projectile's ground slide per radian (sympy; the axle's travel in it),
    and the slides' hold the held arm's (``slide_friction`` held)."""
    p = params(load_design(TABLE3_FLOATING_FILE))._replace(**BASE_COEFFICIENTS[losses])
    q4, _, _, slide = _on_base(lagrangian, p, p.theta0, 0.0)
    drive, hold, base_hold = friction.rest_balance(p)
    without = friction.rest_balance(p._replace(mub=0.0, mub_s=0.0))
    assert drive == without[0]
    held = friction.slide_friction(p.theta0, p.phi0, 0.0, 0.0, 0.0, 0.0, -float(np.sign(slide)), p)
    _close(base_hold, p.mub_s * held.normal * abs(slide), "mub_s N |D|", abs(base_hold))
    assert hold == held.axle_load
    # The base carries the projectile, the pouch and, of a flat uniform sling held at both ends
    # (the arm's tip and the projectile, both at the base's level), half (derivation 14).
    carried = (p.mP + p.mQ + p.mS / 2) * p.g
    _close(held.normal, carried, "N at rest", carried)


#: Designs of the sample floating arm with the base's friction: alone, with every other friction,
#: and with a static coefficient above its kinetic one.
BASE_LOSSY = {"base": _with_losses(base_friction=0.3),
              "base-static": _with_losses(base_friction=0.3, base_static_friction=0.6),
              "base-and-slides": _with_losses(base_friction=0.3, guide_friction=0.2, track_friction=0.25,
                                            axle_friction=0.2, axle_radius=0.02, guide_static_friction=0.4,
                                            track_static_friction=0.3, axle_static_friction=0.3)}


@pytest.mark.parametrize("name", BASE_LOSSY)
def test_the_energy_audit_closes_with_the_bases_friction(name):
    _audited(BASE_LOSSY[name])


def test_more_base_friction_takes_more_on_the_base():
    from analytic.reference import simulate

    shots = [simulate(_with_losses(base_friction=mu), histories=False) for mu in (0.0, 0.3, 0.6)]
    taken = [shot.energy_dissipated["base"] for shot in shots]
    assert taken[0] == 0.0 < taken[1] < taken[2]


def _heavy(design):
    """``design`` throwing a 1.5 kg stone: a base can hold its arm through the flat sling at rest."""
    return dataclasses.replace(design, projectile=dataclasses.replace(design.projectile, mass=1.5))


#: A base that holds the sample machine throwing a 1.5 kg stone: gravity turns its arm with 7.8 N m
#: at rest, and its base holds ``mub_s N |D|`` through the flat sling, 11.8 N m at a static coefficient
#: of 1 and 5.9 N m at the kinetic 0.5 (``friction.rest_balance``; the test reads both).
BASE_HELD = _heavy(_with_losses(base_friction=0.5, base_static_friction=1.0))


@pytest.mark.parametrize("name", [*BASE_LOSSY, "held"])
def test_the_two_paths_agree_with_the_bases_friction(name):
    from test_analytic_fast import _assert_agree

    _assert_agree(BASE_HELD if name == "held" else BASE_LOSSY[name])


def test_a_machine_its_base_holds_at_rest_never_fires_and_says_why():
    from analytic.reference import simulate

    drive, hold, base = friction.rest_balance(params(BASE_HELD))
    assert hold == 0.0 < drive <= base
    for shot in (simulate(BASE_HELD), simulate_fast(BASE_HELD)):
        assert shot.status is Status.NEVER_FIRES
        assert "base" in shot.message, shot.message
    # Its kinetic coefficient alone would not hold it: with the static one equal to it, it fires.
    fires = _heavy(_with_losses(base_friction=0.5))
    drive, _, base = friction.rest_balance(params(fires))
    assert base < drive
    assert simulate_fast(fires).status is not Status.NEVER_FIRES
