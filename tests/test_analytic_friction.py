"""Friction in the analytic model (``docs/derivation.md`` section 10): the equations against the
sympy Lagrangian, the implicit solve, stick and slip, never firing, the ideal machine unchanged, the
range against each coefficient, and the energy audit.

The reference is ``tests/sympy_model.py`` (built from the geometry alone, with
the frame's displacement X as a fourth coordinate, so a rolling frame is
covered): Lagrange's equations; the friction's generalised forces from the
virtual power of the torques and the force at their joints,
``P = ta (w_arm - w_frame) + th (w_link - w_arm) + F (x_P' - X')``,
``Q = dP/dq'``; the joint forces from Newton's law for each body with
accelerations that sympy differentiates. Nothing of ``analytic.eom`` is used
to build it.
"""

from __future__ import annotations

import dataclasses
import math
from functools import partial

import numpy as np
import pytest

from analytic import eom, friction, stages, states
from analytic.design import Base, Losses
from analytic.design_file import default_design, design_from_dict, design_to_dict
from analytic.parameters import Params, params
from analytic.reference import simulate
from analytic.result import LOSS_NAMES, Status

#: Agreement asked of analytic.eom's friction and the sympy model, relative to
#: the largest term compared: both evaluate closed forms in double precision
#: (round-off ~1e-14); 1e-10 leaves room for the 4x4 and 5x5 solves while any
#: wrong term (a sign, a missing coupling) shows at O(1).
REL_TOL = 1e-10
#: The implicit friction equations are solved to this, relative to the friction
#: (Newton's method stops at a few units in the last place; 1e-13 allows for
#: the |force| it is evaluated through).
IMPLICIT_TOL = 1e-13
#: Energy audit: initial = current mechanical energy + dissipated work, to this
#: fraction of the energy the counterweight released. The ideal machine's own
#: energy drifts by 6e-10 of it on the paper's design at the default
#: tolerances (rtol = atol = 1e-10, measured); 1e-8 is that with room.
AUDIT_TOL = 1e-8
SEED = 20_261_123

#: Typical values (README, "Losses"): a steel axle in a plain bearing, a
#: hinge pin, and a sled on a wooden base.
AXLE = dict(axle_friction=0.15, axle_radius=0.0064)
HINGE = dict(hinge_friction=0.15, hinge_radius=0.005)
BASE = dict(base_friction=0.3)
ALL = {**AXLE, **HINGE, **BASE}


def with_losses(design, **losses):
    return dataclasses.replace(design, losses=Losses(**losses))


def random_params(rng: np.random.Generator, rolling: bool) -> Params:
    """A plausible machine with every number distinct, and friction everywhere."""
    La = rng.uniform(0.8, 4.0)
    Lb = La * rng.uniform(0.15, 0.5)
    h = La * rng.uniform(0.4, 0.9)
    mA = math.exp(rng.uniform(math.log(0.3), math.log(50.0)))
    mW = math.exp(rng.uniform(math.log(5.0), math.log(2000.0)))
    rest = dict.fromkeys(Params._fields, math.nan)
    rest.update(La=La, Lb=Lb, d=rng.uniform(-Lb, La), mA=mA, IA=mA * (La + Lb) ** 2 / 12.0 * rng.uniform(0.5, 1.5),
                mW=mW, Lw=h * rng.uniform(0.2, 0.8), IW=mW * rng.uniform(0.0, 0.05), Ls=La * rng.uniform(0.5, 1.3),
                mP=math.exp(rng.uniform(math.log(0.04), math.log(20.0))), h=h, g=rng.uniform(1.0, 25.0),
                rolling=float(rolling), Mf=(mW * rng.uniform(0.5, 5.0)) if rolling else 0.0, mS=0.0, mQ=0.0,
                # Large coefficients and pins, so that friction is O(1) of the forcing and nothing hides.
                mua=rng.uniform(0.1, 0.8), ra=La * rng.uniform(0.01, 0.1), muh=rng.uniform(0.1, 0.8),
                rh=La * rng.uniform(0.01, 0.1), mub=rng.uniform(0.1, 0.8))
    # Static coefficients above the kinetic ones, so that a slipping joint taking the static shows.
    rest.update(mua_s=1.25 * rest["mua"], muh_s=1.25 * rest["muh"], mub_s=1.25 * rest["mub"])
    return Params(**rest)


def swing_samples(n=10):
    rng = np.random.default_rng(SEED)
    modes = [(-1.0, -1.0), (-1.0, 1.0), (1.0, 0.0), (0.0, -1.0), (0.0, 0.0)]
    return [(random_params(rng, rolling=bool(i % 2)), rng.uniform(-math.pi, math.pi, 3), rng.normal(0.0, 4.0, 3),
             modes[i % len(modes)]) for i in range(n)]


def slide_samples(n=10):
    rng = np.random.default_rng(SEED + 1)
    out = []
    while len(out) < n:
        p = random_params(rng, rolling=bool(len(out) % 2))
        beta = rng.uniform(-math.pi + 0.25, -0.25)
        cos_theta = (-p.h - p.Ls * math.cos(beta)) / p.La
        if abs(cos_theta) > 0.98:
            continue
        theta = math.acos(cos_theta) * rng.choice([-1.0, 1.0])
        modes = [(-1.0, -1.0, 1.0), (-1.0, 1.0, -1.0), (-1.0, 0.0, 1.0), (1.0, 0.0, -1.0)][len(out) % 4]
        out.append((p, theta, rng.uniform(-math.pi, math.pi), *rng.normal(0.0, 4.0, 2), modes))
    return out


SWING = swing_samples()
SLIDE = slide_samples()


def _full_rates(p, q3, qd3, qdd3):
    """q, q', q'' with X: X from the zero-momentum relation, X'' from eom (checked by the X row)."""
    x = eom.frame_displacement(*q3, p)
    dx = eom.frame_velocity(*q3, *qd3, p)
    ddx = eom.frame_acceleration(*q3, *qd3, *qdd3, p)
    return np.array([*q3, x]), np.array([*qd3, dx]), np.array([*qdd3, ddx])


def _check_equations(lagrangian, p, q, qd, qdd, ta, th, fb, normal):
    """The residual of the sympy model's M q'' - f - Q - J^T N (X row only on a rolling frame)."""
    m, f = lagrangian.mass(p, q, qd), lagrangian.forcing(p, q, qd)
    generalised = lagrangian.generalised(p, q, qd, ta, th, fb)
    jac = lagrangian.base_jacobian(p, q)
    rows = 4 if p.rolling else 3
    residual = (m @ qdd - f - generalised - jac * normal)[:rows]
    scale = max(np.max(np.abs(f[:rows])), np.max(np.abs((m @ qdd)[:rows])))
    assert np.max(np.abs(residual)) <= REL_TOL * scale, f"residual {residual} vs scale {scale:.3g}"


@pytest.mark.parametrize("sample", SWING, ids=[f"swing{i}" for i in range(len(SWING))])
def test_swing_friction_satisfies_the_sympy_equations_and_coulombs_law(lagrangian, sample):
    p, q3, qd3, (sa, sh) = sample
    if sa == 0.0:
        qd3 = qd3 * np.array([0.0, 1.0, 1.0])
    if sh == 0.0:
        qd3 = qd3 * np.array([1.0, 0.0, 1.0])
    ddtheta, ddphi, ddpsi, ta, th, axle, hinge = friction.swing_friction(*q3, *qd3, sa, sh, p)
    q, qd, qdd = _full_rates(p, q3, qd3, (ddtheta, ddphi, ddpsi))
    _check_equations(lagrangian, p, q, qd, qdd, ta, th, 0.0, 0.0)
    axle_f, hinge_f, _ = lagrangian.joint_forces(p, q, qd, qdd)
    assert axle == pytest.approx(np.linalg.norm(axle_f), rel=REL_TOL)
    assert hinge == pytest.approx(np.linalg.norm(hinge_f), rel=REL_TOL)
    if sa != 0.0:
        assert abs(ta + p.mua * p.ra * sa * axle) <= IMPLICIT_TOL * abs(ta)
    else:
        assert ddtheta == 0.0
    if sh != 0.0:
        assert abs(th + p.muh * p.rh * sh * hinge) <= IMPLICIT_TOL * abs(th)
    else:
        assert ddphi == 0.0


@pytest.mark.parametrize("sample", SLIDE, ids=[f"slide{i}" for i in range(len(SLIDE))])
def test_slide_friction_satisfies_the_sympy_equations_and_coulombs_law(lagrangian, sample):
    p, theta, phi, dtheta, dphi, (sa, sh, sb) = sample
    if sh == 0.0:
        dphi = 0.0
    ddtheta, ddphi, normal, ta, th, fb, axle, hinge, dx = friction.slide_friction(theta, phi, dtheta, dphi, sa, sh,
                                                                             sb, p)
    psi, dpsi, s, c, _ = eom.slide_constraint(theta, dtheta, p)
    q, qd, qdd = _full_rates(p, (theta, phi, psi), (dtheta, dphi, dpsi), (ddtheta, ddphi, s * ddtheta + c))
    _check_equations(lagrangian, p, q, qd, qdd, ta, th, fb, normal)
    axle_f, hinge_f, _ = lagrangian.joint_forces(p, q, qd, qdd, fb, normal)
    assert axle == pytest.approx(np.linalg.norm(axle_f), rel=REL_TOL)
    assert hinge == pytest.approx(np.linalg.norm(hinge_f), rel=REL_TOL)
    assert abs(ta + p.mua * p.ra * sa * axle) <= IMPLICIT_TOL * abs(ta)
    assert abs(fb + p.mub * sb * normal) <= IMPLICIT_TOL * abs(fb)
    if sh != 0.0:
        assert abs(th + p.muh * p.rh * sh * hinge) <= IMPLICIT_TOL * abs(th)
    else:
        assert ddphi == 0.0
    # The projectile's slide over the base is dx_P/dtheta theta' (sympy's x_P' - X').
    slide_velocity = float(lagrangian.generalised(p, q, qd, 0.0, 0.0, 1.0) @ qd)
    assert dx * dtheta == pytest.approx(slide_velocity, rel=REL_TOL, abs=REL_TOL * abs(p.La * dtheta))


@pytest.mark.parametrize("sample", SWING[:4], ids=[f"swing{i}" for i in range(4)])
def test_generalised_forces_by_virtual_work_are_the_torques_on_theta_and_phi(lagrangian, sample):
    """Derivation 10.1: the axle's torque acts on theta alone, the hinge's on phi alone, the base's force
    through the projectile's x (and never on X: its reaction pushes the frame back)."""
    p, q3, qd3, _ = sample
    q, qd = np.array([*q3, 0.0]), np.array([*qd3, 0.0])
    ta, th, fb = 1.7, -0.6, 2.3
    got = lagrangian.generalised(p, q, qd, ta, th, fb)
    beta = q3[0] + q3[2]
    expected = [ta + fb * (-p.La * math.cos(q3[0]) - p.Ls * math.cos(beta)), th, fb * (-p.Ls * math.cos(beta)), 0.0]
    np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-12)


def test_without_friction_the_equations_are_the_ideal_machines_bit_for_bit():
    """Zero coefficients take the ideal machine's arithmetic (friction.lossy is false)."""
    p = params(default_design())
    assert not friction.lossy(p)
    y = np.empty(states.state_size(states.SLIDE, p))
    stages.slide_start(p, y)
    assert y.shape == (4,)
    out = np.empty(4)
    stages.derivative(states.SLIDE, y, p, None, out)
    assert out[2] == eom.slide_accelerations(p.theta0, p.phi0, 0.0, 0.0, p)[0]


# --------------------------------------------------------------------------- #
# Whole shots
# --------------------------------------------------------------------------- #

@pytest.fixture(scope="module")
def paper():
    return default_design()


#: The ideal machine's shot before friction existed: ``simulate`` on main at commit ec7c46c (the
#: design contract for losses, no friction in the model), printed with repr: range (m), release
#: time (s), peak axle load (N).
BEFORE_FRICTION = {"fixed": (45.30764693266705, 0.38245542059704923, 1552.537901418316),
                   "rolling": (45.373430817773624, 0.3824156525138763, 1546.1442218373957)}
#: ... held to this, relative: the integrator's own error. DOP853 at rtol = atol = 1e-10 (the
#: default) is 1.8e-10 in range, 9.4e-11 in the peak axle load and 3.6e-13 in release time from
#: a run 100x tighter (measured on both frames); another CPU's libm moves the range by 3e-11
#: (docs/contributing.md, "Testing on another CPU"). Any change to the ideal equations moves
#: these by far more.
BEFORE_FRICTION_REL = 1e-8
#: ``[losses]`` tables without friction: zero coefficients, a frictionless bearing of known size
#: at each joint, and both.
ZERO_LOSSES = {"zero-coefficients": dict(axle_friction=0.0, hinge_friction=0.0, base_friction=0.0),
               "radii-alone": dict(axle_radius=0.0064, hinge_radius=0.005),
               "zero-coefficients-with-radii": dict(axle_friction=0.0, axle_radius=0.0064, hinge_friction=0.0,
                                                    hinge_radius=0.005, base_friction=0.0)}
#: What two shots of the same arithmetic share, sample for sample.
SHOT_NUMBERS = ("liftoff_time", "release_time", "landing_time", "range", "apex_height", "min_sling_tension",
                "peak_axle_load", "peak_hinge_load", "peak_sling_tension", "peak_projectile_acceleration")
SHOT_HISTORIES = ("t", "q", "qdot", "path", "sling_tension", "flight_path", "axle_load")   # ``History`` fields


def on_frame(design, frame):
    return design if frame == "fixed" else dataclasses.replace(design, base=Base(mobility="rolling", mass=300.0))


def assert_same_shot(got, expected):
    """Bit for bit: every summary number and every history (shots of one run)."""
    for name in SHOT_NUMBERS:
        assert getattr(got, name) == getattr(expected, name), name
    for name in SHOT_HISTORIES:
        assert np.array_equal(getattr(got.history, name), getattr(expected.history, name)), name


def test_losses_are_ideal_exactly_when_every_coefficient_is_zero():
    assert all(Losses(**table).ideal for table in ZERO_LOSSES.values())
    for table in (AXLE, HINGE, BASE, ALL, dict(axle_friction=1e-12, axle_radius=0.0064)):
        assert not Losses(**table).ideal, table


@pytest.mark.parametrize("table", ZERO_LOSSES, ids=list(ZERO_LOSSES))
@pytest.mark.parametrize("frame", ["fixed", "rolling"])
def test_zero_coefficients_give_the_ideal_shot_bit_for_bit(paper, frame, table):
    """In one run: a design file's ``[losses]`` table without friction (a radius alone included)
    takes the ideal machine's arithmetic, the same shot as the file without the table."""
    data = design_to_dict(on_frame(paper, frame))
    assert "losses" not in data
    ideal = simulate(design_from_dict(data))
    design = design_from_dict({**data, "losses": ZERO_LOSSES[table]})
    assert design.losses.ideal and not friction.lossy(params(design))
    zero = simulate(design)
    assert zero.status is Status.OK
    assert_same_shot(zero, ideal)
    assert zero.energy_dissipated == ideal.energy_dissipated
    assert zero.energy_dissipated["axle"] == zero.energy_dissipated["hinge"] == zero.energy_dissipated["base"] == 0.0
    # The drag's work in flight: the ideal machine's projectile loses energy to the air only.
    assert zero.energy_dissipated["drag"] > 0.0


@pytest.mark.parametrize("frame", ["fixed", "rolling"])
def test_the_ideal_shot_is_the_one_before_friction_and_a_vanishing_coefficient_tends_to_it(paper, frame):
    design = on_frame(paper, frame)
    ideal = simulate(design, histories=False)
    got = (ideal.range, ideal.release_time, ideal.peak_axle_load)
    assert got == pytest.approx(BEFORE_FRICTION[frame], rel=BEFORE_FRICTION_REL), f"{got!r}"
    tiny = simulate(with_losses(design, axle_friction=1e-12, axle_radius=0.0064), histories=False)
    assert friction.lossy(params(tiny.design))
    # The friction path at a vanishing coefficient: other arithmetic, so other steps, within the
    # integrator's error (measured 5.1e-11 fixed, 9.6e-11 rolling).
    assert tiny.range == pytest.approx(ideal.range, rel=1e-9)


def test_a_frictionless_bearing_gives_the_ideal_shot_on_the_fast_path_bit_for_bit(paper):
    from analytic.fast import shoot

    designs = [paper] + [with_losses(paper, **table) for table in ZERO_LOSSES.values()]
    shots = shoot(designs, loads=True)
    for name in ("range", "release_time", "peak_axle_load", "peak_hinge_load"):
        values = getattr(shots, name)
        assert np.all(values == values[0]), name


@pytest.mark.parametrize("name, coefficient, radius, top", [
    ("axle", "axle_friction", dict(axle_radius=0.0064), 0.6),
    ("hinge", "hinge_friction", dict(hinge_radius=0.005), 0.6),
    ("base", "base_friction", {}, 1.0),
])
def test_range_falls_smoothly_as_each_coefficient_grows_from_zero(paper, name, coefficient, radius, top):
    mus = np.linspace(0.0, top, 7)
    ranges = []
    for mu in mus:
        design = paper if mu == 0.0 else with_losses(paper, **{coefficient: float(mu)}, **radius)
        ranges.append(simulate(design, histories=False).range)
    ranges = np.array(ranges)
    drops = -np.diff(ranges)
    assert np.all(drops > 0.0), f"{name}: ranges {ranges}"
    # Smooth: no jump at 0 (the first step is like the next) and the slope changes gently.
    assert drops[0] < 2.0 * drops[1] and drops[1] < 2.0 * drops[0], f"{name}: drops {drops}"
    assert np.all(np.abs(np.diff(drops)) < 0.5 * drops[:-1]), f"{name}: drops {drops}"


def _audit(shot):
    e = shot.history.energy
    scale = shot.counterweight_energy_released
    return float(np.max(np.abs(e.total + e.lost))) / scale


#: Static coefficients 1.3 times the kinetic ones (section 10.9).
STATIC = dict(axle_static_friction=0.195, hinge_static_friction=0.195, base_static_friction=0.39)
AUDIT_CASES = {"axle": AXLE, "hinge": HINGE, "base": BASE, "all": ALL,
               "sticking-hinge": dict(hinge_friction=1.0, hinge_radius=0.1),
               "stalling-axle": dict(axle_friction=1.0, axle_radius=0.1),
               "all-static": {**ALL, **STATIC},
               "sticking-hinge-static": dict(hinge_friction=1.0, hinge_radius=0.1, hinge_static_friction=1.3),
               "stalling-axle-static": dict(axle_friction=1.0, axle_radius=0.1, axle_static_friction=1.15)}
#: (1.15: below the 1.16 whose hold at rest balances gravity on that axle, so that it fires.)


@pytest.mark.parametrize("case", AUDIT_CASES, ids=list(AUDIT_CASES))
def test_energy_audit_closes_at_every_sample(paper, case):
    shot = simulate(with_losses(paper, **AUDIT_CASES[case]))
    assert shot.status is Status.OK
    assert _audit(shot) <= AUDIT_TOL
    for name in LOSS_NAMES[:3]:
        w = shot.history.energy.dissipated[name]
        assert np.all(np.diff(w) >= -1e-12), f"{name}'s work must not decrease"
        assert shot.energy_dissipated[name] == w[-1]
        assert (w[-1] > 0.0) == (AUDIT_CASES[case].get(f"{name}_friction", 0.0) > 0.0)
    # Flight: the projectile's mechanical energy at release = at landing + the drag's work.
    m, g = paper.projectile.mass, paper.environment.gravity
    v0 = shot.release_velocity
    released = 0.5 * m * v0 @ v0 + m * g * (shot.release_position[1] + paper.machine.pivot_height)
    summary = simulate(with_losses(paper, **AUDIT_CASES[case]), histories=False)
    assert summary.energy_dissipated == shot.energy_dissipated
    assert released > shot.energy_dissipated["drag"] > 0.0


def test_energy_audit_closes_on_sampled_designs_with_random_losses():
    """Designs over the paper's Table II with random coefficients and pins up to three times the
    typical ones, every third on a rolling frame (measured: at worst 4.1e-9 on 40 of them; the
    first 10 here)."""
    from support import table_ii_sample

    rng = np.random.default_rng(5)
    for i, design in enumerate(table_ii_sample(10, seed=21)):
        losses = Losses(axle_friction=float(rng.uniform(0, 0.6)), axle_radius=float(rng.uniform(0.003, 0.03)),
                        hinge_friction=float(rng.uniform(0, 0.6)), hinge_radius=float(rng.uniform(0.003, 0.03)),
                        base_friction=float(rng.uniform(0, 1)))
        mass = float(rng.uniform(5, 100)) if i % 3 == 0 else None
        design = dataclasses.replace(design, losses=losses)
        if mass is not None:
            design = dataclasses.replace(design, base=Base(mobility="rolling", mass=mass))
        shot = simulate(design)
        if shot.status is not Status.NEVER_FIRES:
            assert _audit(shot) <= AUDIT_TOL, design.name


def test_energy_audit_closes_and_the_paths_agree_with_random_static_coefficients():
    """Sampled designs with random losses whose static coefficients are 1 to 3 times the kinetic ones,
    every other one on a rolling frame: nothing is dissipated while a joint is stuck, so the audit
    closes as without them (10.9), and the fast path agrees with the reference (FAST_TOL)."""
    from support import table_ii_sample

    from analytic.fast import simulate_fast

    rng = np.random.default_rng(9)
    fired = 0
    for i, design in enumerate(table_ii_sample(6, seed=23)):
        kinetic = dict(axle_friction=float(rng.uniform(0, 0.6)), hinge_friction=float(rng.uniform(0, 0.6)),
                       base_friction=float(rng.uniform(0, 1)))
        losses = Losses(**kinetic, axle_radius=float(rng.uniform(0.003, 0.03)),
                        hinge_radius=float(rng.uniform(0.003, 0.03)),
                        **{f"{k.removesuffix('_friction')}_static_friction": v * float(rng.uniform(1, 3))
                           for k, v in kinetic.items()})
        design = dataclasses.replace(design, losses=losses)
        if i % 2:
            design = dataclasses.replace(design, base=Base(mobility="rolling", mass=float(rng.uniform(5, 100))))
        shot, fast = simulate(design), simulate_fast(design)
        assert fast.status is shot.status, design.name
        if shot.status is not Status.NEVER_FIRES:
            fired += 1
            assert _audit(shot) <= AUDIT_TOL, design.name
        if shot.range is not None:
            assert abs(fast.range - shot.range) <= FAST_TOL * abs(shot.range), design.name
    assert fired >= 3


def test_energy_audit_closes_on_a_rolling_frame(paper):
    design = dataclasses.replace(with_losses(paper, **ALL), base=Base(mobility="rolling", mass=300.0))
    shot = simulate(design)
    assert shot.status is Status.OK
    assert _audit(shot) <= AUDIT_TOL
    # Every loss but the drag before release, which acts only with projectile.drag_during_swing, and a
    # floating arm's guide's and track's.
    absent = ("swing_drag", "guide", "track")
    assert all(shot.energy_dissipated[name] > 0.0 for name in LOSS_NAMES if name not in absent)
    assert all(shot.energy_dissipated[name] == 0.0 for name in absent)


def test_the_drag_work_is_the_flights_loss_of_mechanical_energy(paper):
    """Integrated on the flight's steps, it balances the energies at release and at landing (the
    flight's velocity at landing comes from a separate run of the flight alone)."""
    from analytic import reference
    from analytic.aero import DRAG_TABLE
    from analytic.reference.ode import integrate

    design = with_losses(paper, **ALL)
    shot = simulate(design, histories=False)
    p = params(design)
    start = np.array([*shot.release_position, *shot.release_velocity])

    def rhs(t, y):
        out = np.empty(4)
        stages.derivative(states.FLIGHT, y, p, DRAG_TABLE, out)
        return out

    flight = integrate(rhs, shot.release_time, start, shot.landing_time, (), rtol=1e-12, atol=1e-12,
                       output_step=None)
    m, g = p.mP, p.g

    def energy(y):
        return 0.5 * m * (y[2] ** 2 + y[3] ** 2) + m * g * y[1]

    lost = energy(start) - energy(flight.y_end)
    assert shot.energy_dissipated["drag"] == pytest.approx(lost, rel=1e-8)
    assert shot.energy_dissipated["drag"] == reference.drag_work(
        reference._run(states.FLIGHT, p, shot.release_time, start, shot.landing_time + 1.0, 1e-10, 1e-10, None, True), p)


# --------------------------------------------------------------------------- #
# Stick and slip, never firing
# --------------------------------------------------------------------------- #

def test_a_hinge_that_sticks_is_held_within_its_friction_and_slips_against_its_rate(paper):
    """With a large hinge pin the counterweight's link sticks on the arm for a while: stuck, its rate is
    exactly 0 and the holding torque within mu r |H|; slipping, the torque is -mu r |H| sign(phi')."""
    design = with_losses(paper, hinge_friction=1.0, hinge_radius=0.1)
    shot = simulate(design)
    p = params(design)
    assert shot.status is Status.OK
    stuck = shot.history.qdot[:, 1] == 0.0
    assert stuck.sum() > 10 and (~stuck).sum() > 10
    kh = p.muh * p.rh
    for i in np.flatnonzero(shot.history.stage == states.SWING)[::7]:
        y = np.concatenate([shot.history.q[i], shot.history.qdot[i], np.zeros(3), [-1.0, 0.0 if stuck[i] else np.sign(shot.history.qdot[i, 1]),
                                                                    0.0]])
        _, _, _, _, _, th, _, _, hinge, _ = states.friction_solution(states.SWING, y, p)
        if stuck[i]:
            assert abs(th) <= kh * hinge * (1 + 1e-12)
        else:
            assert th == pytest.approx(-kh * hinge * np.sign(shot.history.qdot[i, 1]), rel=1e-12)


def test_the_hinge_reverses_and_the_axle_stops_under_heavy_friction(paper, monkeypatch):
    """Each mode switch is an event of the stage: record them."""
    switched = []
    original = states.switch_mode

    def spy(stage, k, y, p):
        before = y.copy()
        original(stage, k, y, p)
        switched.append((states.EVENT_NAMES[stage][k], before[-3:].tolist(), y[-3:].tolist()))

    monkeypatch.setattr(states, "switch_mode", spy)
    simulate(with_losses(paper, hinge_friction=0.15, hinge_radius=0.005), histories=False)
    assert [name for name, _, _ in switched] == ["hinge_stops"]
    assert switched[0][1][1] == -1.0 and switched[0][2][1] == 1.0          # slipping back the other way
    switched.clear()
    simulate(with_losses(paper, axle_friction=1.0, axle_radius=0.1), histories=False)
    assert [name for name, _, _ in switched] == ["axle_stops", "axle_stops"]
    assert switched[0][2][0] == 1.0 and switched[1][2][0] == 0.0             # reverses, then sticks


def test_joints_at_rest_together_get_consistent_modes_and_the_audit_converges(monkeypatch):
    """Both joints stick and slip again and again as a weak machine on a rolling frame swings for 6 s
    before release (48 switches). Chosen one joint at a time, a joint could slip the way its own
    friction pushed it, which made energy: the audit stayed at 5e-6 of the counterweight's energy
    at any tolerance. Chosen together, every switch leaves consistent modes and the audit
    closes (measured 1.6e-10 at the default tolerance)."""
    from support import table_ii_sample

    design = dataclasses.replace(table_ii_sample(28, seed=21)[27], base=Base(mobility="rolling", mass=87.75),
                                 losses=Losses(axle_friction=0.2254, axle_radius=0.0221, hinge_friction=0.205,
                                               hinge_radius=0.0252, base_friction=0.2306))
    original, switches = states.switch_mode, []

    def checked(stage, k, y, p):
        original(stage, k, y, p)
        name = states.EVENT_NAMES[stage][k]
        switches.append(name)
        core = states.STATE_SIZE[stage]
        free = [y[core // 2 + joint] == 0.0 for joint in range(2)]
        must_slip = states.switched_joint(stage, k) if name.endswith("_slips") else -1
        assert states.consistent(stage, y, p, *free, must_slip), (name, y[-3:])

    monkeypatch.setattr(states, "switch_mode", checked)
    shot = simulate(design)
    assert shot.status is Status.OK and len(switches) > 40
    assert {"axle_stops", "axle_slips", "hinge_stops", "hinge_slips"} <= set(switches)
    assert _audit(shot) <= 1e-9


def test_friction_events_watch_the_rates_and_are_inert_without_their_friction(paper):
    """The events' values on a stage-1 state (whole shots through both: test_crosscheck.py's
    ``stage-1-events`` group): arm_stalls is -theta', slide_reverses the slide's direction with
    the arm turning clockwise, -D, times its sign (not D theta', which would reach 0 with the
    arm's stall too), and a switch at slide_reverses flips the sign."""
    names = states.EVENT_NAMES[states.SLIDE]
    ideal = params(paper)
    y4 = np.array([ideal.theta0 - 0.2, ideal.phi0 + 0.1, -3.0, 1.5])
    assert all(stages.event_value(states.SLIDE, k, y4, ideal) == 1.0 for k in range(states.SLIDE_ARM_STALLS, len(names)))
    p = params(with_losses(paper, **ALL))
    y = np.concatenate([y4, [0.1, 0.2, 0.3, -1.0, 1.0, -1.0]])
    _, _, s, _, sin_beta = eom.slide_constraint(y[0], y[2], p)
    slide = friction.slide_rate(y[0], s, sin_beta, p)
    assert stages.event_value(states.SLIDE, names.index("arm_stalls"), y, p) == 3.0
    assert stages.event_value(states.SLIDE, names.index("slide_reverses"), y, p) == pytest.approx(slide)
    assert stages.event_value(states.SLIDE, names.index("hinge_stops"), y, p) == 1.5      # phi' times +1
    assert stages.event_value(states.SLIDE, names.index("hinge_slips"), y, p) == 1.0      # not stuck: inert
    states.switch_mode(states.SLIDE, names.index("slide_reverses"), y, p)
    assert y[-1] == 1.0 and y[-3] == -1.0 and y[3] == 1.5
    # Only friction events switch modes; arm_stalls ends stage 1 as a lift-off failure.
    assert states.FIRST_SWITCH[states.SLIDE] == names.index("hinge_stops") > names.index("arm_stalls")


def test_never_fires_when_axle_friction_holds_the_arm_and_says_the_torque_balance(paper):
    drive, _, _ = friction.rest_balance(params(with_losses(paper, axle_friction=1.0, axle_radius=0.1)))
    _, axle_unit, _ = friction.rest_balance(params(with_losses(paper, axle_friction=1.0, axle_radius=1.0)))
    # The hold scales with mu r: the coefficient that balances gravity at this radius.
    radius = 0.1
    balance = drive / (axle_unit * radius)
    held = simulate(with_losses(paper, axle_friction=balance * 1.001, axle_radius=radius))
    assert held.status is Status.NEVER_FIRES
    assert f"{drive:.4g} N m" in held.message and "friction holds" in held.message
    fired = simulate(with_losses(paper, axle_friction=balance * 0.999, axle_radius=radius), histories=False)
    assert fired.status is not Status.NEVER_FIRES
    assert drive > 0.0


def _held_by_static_friction(paper, name, radius):
    """The paper's design with ``name``'s kinetic coefficient 0.9 times the one that balances gravity at
    rest and its static one 1.1 times it, and the same design with the static one left out (kinetic)."""
    unit = dict(axle_radius=1.0) if name == "axle" else {}
    unit_design = with_losses(paper, **{f"{name}_friction": 1.0}, **unit)
    drive, axle_unit, base_unit = friction.rest_balance(params(unit_design))
    balance = drive / (axle_unit * radius if name == "axle" else base_unit)
    sized = dict(axle_radius=radius) if name == "axle" else {}
    kinetic = {f"{name}_friction": 0.9 * balance, **sized}
    return (with_losses(paper, **kinetic, **{f"{name}_static_friction": 1.1 * balance}),
            with_losses(paper, **kinetic))


@pytest.mark.parametrize("name", ["axle", "base"])
def test_static_friction_holds_at_rest_what_the_kinetic_would_let_fire_on_both_paths(paper, name):
    """Between the kinetic and the static limits the machine stays at rest (10.7, 10.9); the same design
    with the static coefficient left out (equal to the kinetic) fires."""
    from analytic.fast import simulate_fast

    static, kinetic = _held_by_static_friction(paper, name, radius=0.1)
    for run in (partial(simulate, histories=False), simulate_fast):
        held, fired = run(static), run(kinetic)
        assert held.status is Status.NEVER_FIRES, f"{run}: {held.message}"
        assert fired.status is not Status.NEVER_FIRES, f"{run}: {fired.message}"


def test_a_stuck_hinge_slips_at_its_static_limit_then_gives_the_kinetic_torque(paper, monkeypatch):
    """The hinge sticks at rest and again later; its ``hinge_slips`` root is where the torque holding it
    reaches mu_s r |H|, 1.3 times the kinetic limit, and the slipping joint then gets -mu r |H| sign(phi')."""
    design = with_losses(paper, hinge_friction=1.0, hinge_radius=0.1, hinge_static_friction=1.3)
    p = params(design)
    original, slips = states.switch_mode, []

    def spy(stage, k, y, p_):
        if states.EVENT_NAMES[stage][k] == "hinge_slips":
            slips.append((stage, y.copy()))
        original(stage, k, y, p_)
        if states.EVENT_NAMES[stage][k] == "hinge_slips":
            slips[-1] += (y.copy(),)

    monkeypatch.setattr(states, "switch_mode", spy)
    shot = simulate(design, histories=False)
    assert shot.status is Status.OK and slips
    for stage, held, slipping in slips:
        solution = states.friction_solution(stage, held, p)
        th, hinge = solution[5], solution[8]
        # The root is located to ROOT_TIME_TOLERANCE on the dense output: the hold's margin there is
        # round-off of the torques (~1e-13 of them), far below the 30 % gap between the two limits.
        assert abs(th) == pytest.approx(friction.static_arm(1, p) * hinge, rel=1e-9)
        assert abs(th) > 1.25 * friction.kinetic_arm(1, p) * hinge
        after = states.friction_solution(stage, slipping, p)
        mode = slipping[-2]
        assert mode == -np.sign(th)
        assert after[5] == pytest.approx(-friction.kinetic_arm(1, p) * after[8] * mode, rel=1e-12)


def test_base_friction_alone_can_hold_the_machine(paper):
    drive, _, base_unit = friction.rest_balance(params(with_losses(paper, base_friction=1.0)))
    held = simulate(with_losses(paper, base_friction=1.001 * drive / base_unit), histories=False)
    assert held.status is Status.NEVER_FIRES and "base" in held.message


# --------------------------------------------------------------------------- #
# The compiled path
# --------------------------------------------------------------------------- #

#: Fast against reference, relative in range: the fast path's specification (``test_analytic_fast.RANGE_REL``),
#: held on friction designs too. Both run
#: the same stage functions and the same DOP853 steps, so they agree to round-off unless a
#: rounding sends the step control another way (measured: 1.7e-10 at worst here, on "all").
FAST_TOL = 1e-7


def _friction_designs():
    from support import table_ii_sample

    paper = default_design()
    cases = {"axle": with_losses(paper, **AXLE), "hinge": with_losses(paper, **HINGE),
             "base": with_losses(paper, **BASE), "all": with_losses(paper, **ALL),
             "sticking-hinge": with_losses(paper, hinge_friction=1.0, hinge_radius=0.1),
             "stalling-axle": with_losses(paper, axle_friction=1.0, axle_radius=0.1),
             "held": with_losses(paper, axle_friction=1.0, axle_radius=0.4),
             "all-static": with_losses(paper, **ALL, **STATIC),
             "sticking-hinge-static": with_losses(paper, hinge_friction=1.0, hinge_radius=0.1,
                                                  hinge_static_friction=1.3),
             "stalling-axle-static": with_losses(paper, axle_friction=1.0, axle_radius=0.1, axle_static_friction=1.15),
             "rolling-all": dataclasses.replace(with_losses(paper, **ALL), base=Base(mobility="rolling", mass=300.0))}
    for i, design in enumerate(table_ii_sample(4, seed=11)):
        cases[f"table-ii-{i}"] = dataclasses.replace(design, losses=Losses(**ALL))
    return cases


FRICTION_DESIGNS = _friction_designs()


@pytest.mark.parametrize("name", FRICTION_DESIGNS, ids=list(FRICTION_DESIGNS))
def test_fast_and_reference_paths_agree_on_friction_designs(name):
    from analytic.fast import simulate_fast

    design = FRICTION_DESIGNS[name]
    reference = simulate(design, histories=False)
    fast = simulate_fast(design)
    assert fast.status is reference.status, f"{name}: {fast.message} vs {reference.message}"
    assert fast.message == reference.message
    if reference.range is not None:
        assert abs(fast.range - reference.range) <= FAST_TOL * abs(reference.range), (
            f"{name}: range fast {fast.range!r} vs reference {reference.range!r}")
        assert fast.release_time == pytest.approx(reference.release_time, abs=1e-9)
        assert fast.peak_axle_load == pytest.approx(reference.peak_axle_load, rel=1e-7)
    # The fast path leaves the energy audit to the reference path (README, "Losses").
    assert fast.energy_dissipated is None


# --------------------------------------------------------------------------- #
# Bad input: exit 2 naming the field
# --------------------------------------------------------------------------- #

@pytest.mark.parametrize("table, field, reason", [
    ("axle_friction = -0.1\naxle_radius = 0.01", "losses.axle_friction", "negative"),
    ("hinge_friction = 0.2\nhinge_radius = nan", "losses.hinge_radius", "nan"),
    ("base_friction = inf", "losses.base_friction", "inf"),
    ('axle_friction = "high"\naxle_radius = 0.01', "losses.axle_friction", "text"),
    ("hinge_friction = 0.2", "losses.hinge_friction", "coefficient without its radius"),
    ("axle_friction = 0.1\naxle_radius = 0.0", "losses.axle_friction", "coefficient without its radius"),
], ids=["negative", "nan", "inf", "text", "coefficient-alone", "coefficient-with-a-zero-radius"])
def test_a_bad_losses_table_exits_2_naming_the_field(tmp_path, capsys, table, field, reason):
    from analytic.cli import EXIT_INVALID, main
    from analytic.design_file import dumps_design

    path = tmp_path / "bad.toml"
    path.write_text(dumps_design(default_design()) + f"\n[losses]\n{table}\n")
    assert main(["simulate", str(path)]) == EXIT_INVALID
    err = capsys.readouterr().err
    assert field in err, f"{reason}: {err!r}"


@pytest.mark.parametrize("table, field, value, reason", [
    ("axle_friction = 0.2\naxle_radius = 0.01\naxle_static_friction = 0.15", "losses.axle_static_friction", "0.15",
     "below the kinetic coefficient losses.axle_friction = 0.2"),
    ("base_friction = 0.3\nbase_static_friction = 0.25", "losses.base_static_friction", "0.25",
     "below the kinetic coefficient losses.base_friction = 0.3"),
    ("hinge_static_friction = 0.2", "losses.hinge_static_friction", "0.2", "a coefficient without its radius"),
    ("hinge_friction = 0.2\nhinge_radius = 0.01\nhinge_static_friction = -1", "losses.hinge_static_friction", "-1",
     "must not be negative"),
], ids=["axle-below-kinetic", "base-below-kinetic", "static-without-radius", "negative"])
def test_a_bad_static_coefficient_exits_2_naming_the_field_the_value_and_the_reason(tmp_path, capsys, table, field,
                                                                                     value, reason):
    from analytic.cli import EXIT_INVALID, main
    from analytic.design_file import dumps_design

    path = tmp_path / "bad.toml"
    path.write_text(dumps_design(default_design()) + f"\n[losses]\n{table}\n")
    assert main(["simulate", str(path)]) == EXIT_INVALID
    err = capsys.readouterr().err
    assert field in err and value in err and reason in err, err


def test_static_coefficients_default_to_the_kinetic_and_are_written_back_only_when_given(tmp_path):
    from analytic.design_file import load_design, save_design

    given = with_losses(default_design(), **ALL, axle_static_friction=0.2)
    assert (given.losses.static("axle"), given.losses.static("hinge"), given.losses.static("base")) == (0.2, 0.15, 0.3)
    p = params(given)
    assert (p.mua_s, p.muh_s, p.mub_s) == (0.2, 0.15, 0.3)
    from analytic.fields import field

    assert field("losses.hinge_static_friction").get(given) == 0.15   # not given: the kinetic one
    path = tmp_path / "static.toml"
    save_design(given, path)
    assert load_design(path).losses == given.losses
    assert "hinge_static_friction" not in path.read_text() and "axle_static_friction = 0.2" in path.read_text()


def test_a_radius_with_a_zero_coefficient_is_read_and_throws_the_ideal_shot(tmp_path, capsys):
    import json

    from analytic.cli import EXIT_OK, main
    from analytic.design_file import dumps_design

    outputs = []
    for name, table in (("ideal", ""), ("bearing", "\n[losses]\naxle_friction = 0\naxle_radius = 0.0064\n")):
        path = tmp_path / f"{name}.toml"
        path.write_text(dumps_design(default_design()) + table)
        assert main(["simulate", "--json", str(path)]) == EXIT_OK, capsys.readouterr().err
        outputs.append(json.loads(capsys.readouterr().out))
    ideal, bearing = outputs
    assert bearing["range"] == ideal["range"] and bearing["peak_axle_load"] == ideal["peak_axle_load"]
    assert bearing["energy_dissipated"] == ideal["energy_dissipated"]


def test_a_frictionless_bearing_keeps_its_radius_through_a_design_file(tmp_path):
    from analytic.design_file import load_design, save_design

    bearing = with_losses(default_design(), axle_radius=0.0064)
    save_design(bearing, tmp_path / "bearing.toml")
    assert load_design(tmp_path / "bearing.toml") == bearing


def test_a_losses_table_is_read_and_simulated(tmp_path, capsys):
    import json

    from analytic.cli import EXIT_OK, main
    from analytic.design_file import dumps_design

    path = tmp_path / "real.toml"
    path.write_text(dumps_design(default_design()) + "\n[losses]\n" + "\n".join(f"{k} = {v}" for k, v in ALL.items()))
    assert main(["simulate", "--json", str(path)]) == EXIT_OK
    out = json.loads(capsys.readouterr().out)
    expected = simulate(with_losses(default_design(), **ALL), histories=False)
    assert out["range"] == pytest.approx(expected.range, rel=1e-12)
    assert set(out["energy_dissipated"]) == set(LOSS_NAMES) and out["energy_dissipated"]["axle"] > 0.0


def test_compiled_friction_is_bit_identical_to_the_python_one():
    """The compiled path runs the same friction functions: right-hand sides, events and mode switches
    give the same bits at random states in every mode, on a fixed and a rolling frame."""
    from analytic.fast import compiled
    from analytic.aero import DRAG_TABLE

    rng = np.random.default_rng(SEED + 2)
    paper = default_design()
    for design in (with_losses(paper, **ALL),
                   dataclasses.replace(with_losses(paper, **ALL), base=Base(mobility="rolling", mass=30.0))):
        p = params(design)
        reach = math.acos(-p.h / p.La)
        for _ in range(40):
            sa, sh = rng.choice([-1.0, 0.0, 1.0], size=2)
            q = rng.uniform(-math.pi, math.pi, 3)
            qd = rng.normal(0.0, 4.0, 3) * [sa != 0.0, sh != 0.0, 1.0]
            work = rng.uniform(0.0, 1.0, 3)
            slide = np.array([reach - abs(q[0]) / 3.0, q[1], qd[0] if sa else -1.0, qd[1], *work,
                              -1.0, sh, rng.choice([-1.0, 1.0])])
            swing = np.array([*q, *qd, *work, sa, sh, 0.0])
            for stage, y in ((states.SLIDE, slide), (states.SWING, swing)):
                got, expected = np.empty(len(y)), np.empty(len(y))
                compiled.stages_.derivative(stage, y, p, DRAG_TABLE, got)
                stages.derivative(stage, y, p, DRAG_TABLE, expected)
                np.testing.assert_array_equal(got, expected)
                for k in range(len(states.EVENT_NAMES[stage])):
                    a, b = compiled.stages_.event_value(stage, k, y, p), stages.event_value(stage, k, y, p)
                    assert a == b or (math.isnan(a) and math.isnan(b)), (stage, states.EVENT_NAMES[stage][k], a, b)
                for k in range(states.FIRST_SWITCH[stage], len(states.EVENT_NAMES[stage])):
                    y_got, y_expected = y.copy(), y.copy()
                    compiled.states_.switch_mode(stage, k, y_got, p)
                    states.switch_mode(stage, k, y_expected, p)
                    np.testing.assert_array_equal(y_got, y_expected)
        assert compiled.stages_.fires(p) == stages.fires(p)
        assert compiled.friction_.rest_balance(p) == friction.rest_balance(p)


@pytest.mark.slow
def test_energy_audit_closes_on_every_friction_case_of_the_cross_check():
    """Every shot of the cross-check's friction group (crosscheck.cases.friction_cases) that moves,
    on the reference path: energy at rest = mechanical energy + the friction's work at every
    sample, to AUDIT_TOL of the counterweight's energy."""
    from crosscheck.cases import friction_cases

    checked = 0
    for case in friction_cases():
        shot = simulate(case.design)
        if shot.status is Status.NEVER_FIRES:
            continue
        assert _audit(shot) <= AUDIT_TOL, case.name
        checked += 1
    assert checked >= 8


def _coulomb_root(base, unit_a, unit_h, unit_b, sa, sh, sb, p, start):
    """The root of ``friction_newton``'s equations in 40 digits (mpmath's own Newton's method from
    ``start``): the rows as its docstring states them, nothing of the module's arithmetic."""
    import mpmath   # (sympy's own dependency)

    mp = mpmath.mp.clone()
    mp.dps = 40
    ka, kh = mp.mpf(p.mua) * p.ra, mp.mpf(p.muh) * p.rh

    def combine(x, i):
        return base[i] + x[0] * unit_a[i] + x[1] * unit_h[i] + x[2] * unit_b[i]

    def rows(ta, th, fb):
        x = (ta, th, fb)
        axle = combine(x, 5) if sa == 0.0 else ta + ka * sa * mp.sqrt(combine(x, 0) ** 2 + combine(x, 1) ** 2)
        hinge = combine(x, 6) if sh == 0.0 else th + kh * sh * mp.sqrt(combine(x, 2) ** 2 + combine(x, 3) ** 2)
        return axle, hinge, fb + p.mub * sb * combine(x, 4)

    return tuple(float(v) for v in mp.findroot(rows, tuple(mp.mpf(v) for v in start), tol=mp.mpf(10) ** -35))


def test_newtons_method_stops_within_its_tolerance_of_the_root():
    """``friction_newton`` stops once a bound on its next update is below its tolerance (most
    often after 2 updates instead of 3): its unknowns are the root's to that tolerance.

    Random affine systems of the shape the machine gives (``_joints``, ``slide_friction``): loads
    of kN, a few N per N m of friction, the stuck rows' accelerations of O(1) per kN m; every mode.
    Reference: the same equations solved in 40 digits by mpmath. Allowed: 1e-14 of the unknowns,
    the tolerance (1e-15) with room for the round-off of the loads (1e-16 of kN) through J^-1.
    A stop that came an update early (after the first, say) would miss by 1e-4 of them or more.
    """
    rng = np.random.default_rng(SEED)
    p = params(dataclasses.replace(default_design(), losses=Losses(
        axle_friction=0.4, axle_radius=0.02, hinge_friction=0.4, hinge_radius=0.02, base_friction=0.3)))
    worst = 0.0
    for sa, sh, sb in [(sa, sh, sb) for sa in (-1.0, 0.0, 1.0) for sh in (-1.0, 0.0, 1.0) for sb in (-1.0, 0.0, 1.0)]:
        for _ in range(12):
            base = (*rng.uniform(-3e3, 3e3, 4), rng.uniform(5e2, 3e3), *rng.uniform(-20.0, 20.0, 2))
            unit_a, unit_h = (tuple(np.concatenate([rng.uniform(-5.0, 5.0, 5), rng.uniform(-1e-2, 1e-2, 2)]))
                              for _ in range(2))
            unit_b = tuple(np.concatenate([rng.uniform(-2.0, 2.0, 5), rng.uniform(-1e-2, 1e-2, 2)])
                           ) if sb != 0.0 else (0.0,) * 7
            solved = friction.friction_newton(base, unit_a, unit_h, unit_b, sa, sh, sb, p)
            root = _coulomb_root(base, unit_a, unit_h, unit_b, sa, sh, sb, p, solved)
            error = sum(abs(a - b) for a, b in zip(solved, root)) / sum(abs(b) for b in root)
            worst = max(worst, error)
    assert worst <= 1e-14, worst
