"""The projectile's drag during the swing (``docs/derivation.md`` section 13) against the sympy Lagrangian.

With ``projectile.drag_during_swing`` the drag of the flight's law acts on the projectile in
stages 1-2 as a generalised force ``Q = J^T D``. The sympy model (``tests/sympy_model.py``) gives
``J`` from the projectile's position and the projectile's velocity; the drag's size comes from
``analytic.aero.drag_coefficient`` (the public curve), so ``eom.swing_drag`` is checked against
``-(rho A / 2) Cd(Re) |v - w| (v - w)`` built here, and the equations of motion against
``M q'' = f + Q`` (+ ``J_base^T N`` on the base) solved by numpy.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from analytic import eom, reference
from analytic.aero import DRAG_MODELS, drag_coefficient
from analytic.design import DesignError
from analytic.design_file import default_design, design_from_dict, design_to_dict
from analytic.parameters import params
from analytic import stages, states
from test_analytic_friction import AUDIT_TOL
from test_analytic_symbolic import SEED, assert_close, random_params, slide_state

#: Random (parameters, state) samples per check.
N_SAMPLES = 6
#: The kinds whose counterweight is rigid on the arm (phi held at 0), by their ``Params.kind`` code.
RIGID_KINDS = {"fixed": eom.FIXED, "floating-arm": eom.FLOATING}
#: The drag models with a curve; each sample takes one in turn.
MODELS = ("constant", "smooth-sphere", "golf-ball")


def with_drag(p, rng, model):
    """``p`` with the drag during the swing on: a projectile's size, air and a wind, all random.

    The diameter is scaled so that the drag is a large part of the projectile's weight at the
    sampled speeds (a wrong term in Q then shows far above round-off)."""
    diameter = rng.uniform(0.05, 0.3)
    return p._replace(drag_swing=1.0, drag=float(DRAG_MODELS.index(model)),
                      cd=rng.uniform(0.2, 1.0) if model == "constant" else math.nan,
                      diameter=diameter, area=math.pi * diameter**2 / 4.0 * rng.uniform(0.5, 2.0),
                      rho=rng.uniform(0.8, 1.4), mu=1.8e-5, wind=rng.uniform(-10.0, 10.0), rolling=0.0, Mf=0.0,
                      kind=0.0, mua_s=0.0, muh_s=0.0, mub_s=0.0)


def swing_samples(kind):
    rng = np.random.default_rng(SEED + 7)
    out = []
    for i in range(N_SAMPLES):
        p = with_drag(random_params(rng), rng, MODELS[i % len(MODELS)])
        if kind != "hinged":
            p = p._replace(kind=RIGID_KINDS[kind], Lw=0.0)
        q = (rng.uniform(-math.pi, math.pi), 0.0 if kind != "hinged" else rng.uniform(-math.pi, math.pi),
             rng.uniform(-math.pi, math.pi))
        qd = (*rng.normal(0.0, 4.0, 1), 0.0 if kind != "hinged" else rng.normal(0.0, 4.0), rng.normal(0.0, 4.0))
        out.append((p, q, qd))
    return out


def slide_samples():
    rng = np.random.default_rng(SEED + 8)
    out = []
    while len(out) < N_SAMPLES:
        p = with_drag(random_params(rng), rng, MODELS[len(out) % len(MODELS)])
        state = slide_state(p, rng)
        if state is not None:
            out.append((p, *state))
    return out


SWING = [(kind, *sample) for kind in ("hinged", "fixed", "floating-arm") for sample in swing_samples(kind)]
SWING_IDS = [f"{kind}-swing{i}" for i, (kind, *_) in enumerate(SWING)]
SLIDE = slide_samples()
SLIDE_IDS = [f"slide{i}" for i in range(len(SLIDE))]


def expected_drag(lagrangian, p, q, qd):
    """The flight's law on the projectile's velocity from the sympy model, N, (2,)."""
    _, velocity = lagrangian.projectile(p, q, qd)
    relative = velocity - np.array([p.wind, 0.0])
    speed = float(np.linalg.norm(relative))
    model = DRAG_MODELS[int(p.drag)]
    cd = drag_coefficient(model, p.rho * speed * p.diameter / p.mu, None if model != "constant" else p.cd)
    return -0.5 * p.rho * p.area * cd * speed * relative


@pytest.mark.parametrize("sample", SWING, ids=SWING_IDS)
def test_drag_is_the_flights_law_on_the_projectiles_velocity(sample):
    from sympy_model import machine

    kind, p, q, qd = sample
    assert_close(eom.swing_drag(q[0], q[2], qd[0], qd[2], p), expected_drag(machine(kind), p, q, qd), "drag")


@pytest.mark.parametrize("sample", SWING, ids=SWING_IDS)
def test_swing_accelerations_with_drag_solve_the_lagrangian_with_its_generalised_force(sample):
    from sympy_model import machine

    kind, p, q, qd = sample
    lagrangian = machine(kind)
    rows = [0, 2] if kind != "hinged" else [0, 1, 2]
    m = lagrangian.mass(p, q, qd)[np.ix_(rows, rows)]
    f = lagrangian.forcing(p, q, qd)[rows]
    force = lagrangian.force_on_projectile(p, q, expected_drag(lagrangian, p, q, qd))[rows]
    expected = np.zeros(3)
    expected[rows] = np.linalg.solve(m, f + force)
    assert_close(eom.swing_accelerations(*q, *qd, p), expected, f"{kind} swing with drag")


@pytest.mark.parametrize("sample", SLIDE, ids=SLIDE_IDS)
def test_slide_with_drag_keeps_the_projectile_on_the_base_with_the_drags_vertical_part_in_n(lagrangian, sample):
    p, theta, phi, dtheta, dphi = sample
    r = lagrangian.base_reduction(p, theta, phi, dtheta, dphi, solve=False)
    q, qd = r["q"], r["qd"]
    force = lagrangian.force_on_projectile(p, q, expected_drag(lagrangian, p, q, qd))[:3]
    jac = r["jac"]
    system = np.block([[r["m"], -jac[:, None]], [jac[None, :], np.zeros((1, 1))]])
    c_rhs = r["c"] * jac[2]   # -J' q', from the reduction's c = -J' q' / J_psi
    solution = np.linalg.solve(system, np.append(r["f"] + force, c_rhs))
    ddtheta, ddphi, normal = eom.slide_accelerations(theta, phi, dtheta, dphi, p)
    assert_close((ddtheta, ddphi), solution[:2], "slide with drag")
    assert_close(normal, solution[3], "normal force with drag", scale=p.mP * p.g + float(np.max(np.abs(force))))


@pytest.mark.parametrize("sample", SWING[:N_SAMPLES], ids=SWING_IDS[:N_SAMPLES])
def test_sling_force_is_newtons_net_of_the_drag(lagrangian, sample):
    _, p, q, qd = sample
    qdd = eom.swing_accelerations(*q, *qd, p)
    forces = eom.joint_forces(*q, *qd, *qdd, 0.0, p)
    axle, _, sling = lagrangian.joint_forces(p, q, qd, qdd)
    drag = expected_drag(lagrangian, p, q, qd)
    assert_close(forces[4:], sling - drag, "sling force")
    assert_close(forces[:2], axle - drag, "axle force")


FLOATING_SWING = [sample for sample in SWING if sample[0] == "floating-arm"]


@pytest.mark.parametrize("sample", FLOATING_SWING, ids=[f"floating{i}" for i in range(len(FLOATING_SWING))])
def test_a_floating_arms_supports_push_the_machines_momentum_change_less_the_drag(sample):
    """Derivation (13.5): the guide's push is sum m a_x - D_x, the track's sum m (a_y + g) - D_y; the
    counterweight's mount carries its own force less the guide's; the sling's is net of the drag."""
    from sympy_model import machine

    _, p, q, qd = sample
    lagrangian = machine("floating-arm")
    qdd = eom.swing_accelerations(*q, *qd, p)
    total, weight, sling = lagrangian.joint_forces(p, (*q, 0.0), (*qd, 0.0), (*qdd, 0.0))
    drag = expected_drag(lagrangian, p, q, qd)
    guide, track = total[0] - drag[0], total[1] - drag[1]
    forces = eom.joint_forces(*q, *qd, *qdd, 0.0, p)
    scale = max(float(np.max(np.abs(np.concatenate([total, weight, sling])))), (p.mA + p.mW + p.mP) * p.g)
    assert_close(forces[:2], (0.0, track), "track force on the axle", scale=scale)
    assert_close(forces[2:4], (weight[0] - guide, weight[1]), "mount force on the counterweight", scale=scale)
    assert_close(forces[4:], sling - drag, "sling force", scale=scale)
    y = np.array([*q, *qd])
    assert_close(stages.floating_supports(states.SWING, y, p), (track, guide), "supports", scale=scale)


@pytest.mark.parametrize("sample", FLOATING_SWING, ids=[f"floating{i}" for i in range(len(FLOATING_SWING))])
def test_a_floating_arms_slide_with_drag_solves_the_lagrangian_on_the_base(sample):
    """Stage 1 of a floating arm with the drag: ``[[M, -J^T], [J, 0]] [q'', N] = [f + Q_D, -J' q']``
    over (theta, psi), sympy's ``on_base`` plus the drag's part of the same linear system."""
    from sympy_model import machine

    _, p, _, qd = sample
    lagrangian = machine("floating-arm")
    theta = math.acos(-p.h / p.La) - 0.2   # the tip 0.2 rad above the base (random_params: La > h)
    psi, dpsi, s, c, _ = eom.slide_constraint(theta, qd[0], p)
    if math.isnan(psi):
        pytest.skip("out of the sling's reach")
    q, q_rate = (theta, 0.0, psi), (qd[0], 0.0, dpsi)
    rows = [0, 2]
    acc, normal = lagrangian.on_base(p, q, q_rate)
    m = lagrangian.mass(p, q, q_rate)[np.ix_(rows, rows)]
    jac = lagrangian.base_jacobian(p, (*q, 0.0))[rows]
    force = lagrangian.force_on_projectile(p, q, expected_drag(lagrangian, p, q, q_rate))[rows]
    system = np.block([[m, -jac[:, None]], [jac[None, :], np.zeros((1, 1))]])
    extra = np.linalg.solve(system, np.append(force, 0.0))
    ddtheta, _, got_normal = eom.slide_accelerations(theta, 0.0, qd[0], 0.0, p)
    assert_close(ddtheta, acc[0] + extra[0], "theta'' on the base with drag")
    assert_close(got_normal, normal + extra[2], "base push with drag",
                 scale=(p.mA + p.mW + p.mP) * p.g + float(np.max(np.abs(force))))


def test_the_flag_off_is_the_papers_model_to_the_bit():
    design = default_design()
    design = dataclasses.replace(design, projectile=dataclasses.replace(design.projectile, drag="golf-ball"),
                                 environment=dataclasses.replace(design.environment, wind_speed=5.0))
    p = params(design)
    assert p.drag_swing == 0.0
    state = (p.theta0 + 0.4, p.phi0 - 0.3, -1.0, -6.0, 3.0, 9.0)
    assert eom.terms(*state, p) == eom.terms(*state, p._replace(drag=0.0, wind=0.0))


def test_design_file_reads_writes_and_checks_the_flag():
    layout = design_to_dict(default_design())
    assert "drag_during_swing" not in layout["projectile"]   # the default is left out
    layout["projectile"]["drag_during_swing"] = True
    design = design_from_dict(layout)
    assert design.projectile.drag_during_swing is True
    assert params(design).drag_swing == 1.0
    assert design_to_dict(design)["projectile"]["drag_during_swing"] is True
    layout["projectile"]["drag_during_swing"] = "yes"
    with pytest.raises(DesignError, match=r"projectile\.drag_during_swing.*'yes'.*true or false"):
        design_from_dict(layout)
    layout["projectile"]["drag_during_swing"] = True
    layout["base"] = {"mobility": "rolling", "mass": 50.0}
    with pytest.raises(DesignError, match=r"projectile\.drag_during_swing.*rolling frame"):
        design_from_dict(layout)



def _swinging(wind, losses=None):
    design = default_design()
    return dataclasses.replace(
        design, projectile=dataclasses.replace(design.projectile, drag_during_swing=True),
        environment=dataclasses.replace(design.environment, wind_speed=wind),
        **({} if losses is None else {"losses": losses}))


@pytest.mark.parametrize("wind", [-12.0, 0.0, 12.0], ids=["headwind", "still", "tailwind"])
def test_energy_audit_closes_at_release_with_the_drags_work_before_it(wind):
    from analytic.design import Losses
    from analytic.fast.motion import simulate_motion

    design = _swinging(wind, Losses(axle_friction=0.15, axle_radius=0.0064, base_friction=0.3))
    shot = reference.simulate(design)
    lost = shot.energy_dissipated
    closing = shot.history.energy.total[-1] + lost["axle"] + lost["hinge"] + lost["base"] + lost["swing_drag"]
    assert abs(closing) <= AUDIT_TOL * shot.counterweight_energy_released
    # A tailwind pushes the projectile forward while it is slower than the wind (it gives work).
    assert lost["swing_drag"] != 0.0 and (lost["swing_drag"] > 0.0 or wind > 0.0)
    assert reference.simulate(design, histories=False).energy_dissipated == lost
    # The compiled path's motion takes the drag's work from the energy deficit: the same number.
    motion_lost = simulate_motion(design)[0].energy_dissipated["swing_drag"]
    assert motion_lost == pytest.approx(lost["swing_drag"], abs=AUDIT_TOL * shot.counterweight_energy_released)


def test_the_reports_show_the_drags_work_before_release_only_with_the_flag():
    from analytic.report import format_shot
    from engine_model import shot as engine_shot
    from engine_model.report import format_shot as engine_format_shot

    on, off = _swinging(0.0), default_design()
    assert "air drag before release" in format_shot(reference.simulate(on))
    assert "air drag before release" not in format_shot(reference.simulate(off))
    assert "drag before release" in engine_format_shot(engine_shot.simulate(on))


@pytest.mark.parametrize("wind", [-12.0, 12.0], ids=["headwind", "tailwind"])
def test_a_floating_arms_audit_closes_with_the_drag_before_release_and_the_paths_agree(wind):
    """The drag's power on the projectile's ground velocity, the axle's motion in it (eq. 13.5):
    the audit closes as the hinged machine's does, and the compiled path gives the same shot."""
    from support import TABLE3_FLOATING_FILE
    from test_analytic_fast import _assert_agree

    from analytic.design import Losses
    from analytic.design_file import load_design

    floating = load_design(TABLE3_FLOATING_FILE)
    design = dataclasses.replace(_swinging(wind, Losses(axle_friction=0.15, axle_radius=0.0064)),
                                 machine=floating.machine, name=floating.name)
    shot = reference.simulate(design)
    assert shot.ok, shot.message
    lost = shot.energy_dissipated
    closing = shot.history.energy.total[-1] + lost["axle"] + lost["swing_drag"]
    assert abs(closing) <= AUDIT_TOL * shot.counterweight_energy_released
    assert lost["swing_drag"] != 0.0 and lost["axle"] > 0.0
    _assert_agree(design)


@pytest.mark.parametrize("mode", [-1.0, 1.0], ids=["slipping-back", "slipping-forward"])
@pytest.mark.parametrize("sample", FLOATING_SWING, ids=[f"floating{i}" for i in range(len(FLOATING_SWING))])
def test_a_floating_arms_slides_rub_on_normal_forces_net_of_the_drag(sample, mode):
    """Guide and track friction with the drag (derivations 12.10, 13.5): Coulomb's law on the normal
    forces of Newton's law for the whole machine, the drag among its outside forces, and
    ``M q'' = f + Q_friction + J^T D`` over (theta, psi), all from sympy."""
    from sympy_model import machine

    from analytic import friction

    _, p, q, qd = sample
    p = p._replace(mua=0.3, ra=0.02, mug=0.25, mut=0.35, mua_s=0.4, mug_s=0.3, mut_s=0.45)
    qd = (mode * abs(qd[0]), 0.0, qd[2])
    lagrangian = machine("floating-arm")
    ddtheta, _, ddpsi, q_theta, fg, _, ft = friction.swing_friction(*q, *qd, mode, 0.0, p)
    q4, qd4, acc = (*q, 0.0), (*qd, 0.0), np.array([ddtheta, 0.0, ddpsi, 0.0])
    drag = expected_drag(lagrangian, p, q, qd)
    m, f = lagrangian.mass(p, q4, qd4), lagrangian.forcing(p, q4, qd4)
    pushed = lagrangian.force_on_projectile(p, q, drag)
    residual = (m @ acc - f - pushed)[[0, 2]] - [q_theta, 0.0]
    assert_close(residual, np.zeros(2), "M q'' - f - J^T D - Q", scale=float(np.max(np.abs(f))) + abs(q_theta))
    rate = lagrangian.momentum_rate(p, q4, qd4, acc)
    guide = rate[0] - drag[0] - ft
    track = rate[1] + (p.mA + p.mW + p.mP) * p.g - drag[1] - fg
    _, v_weight, v_axle = lagrangian.slides(p, q4, qd4, fg, ft)
    scale = (p.mA + p.mW + p.mP) * p.g + abs(guide) + abs(track)
    assert_close(fg, -np.sign(v_weight[1]) * p.mug * abs(guide), "guide friction", scale=scale)
    assert_close(ft, -np.sign(v_axle[0]) * p.mut * abs(track), "track friction", scale=scale)
