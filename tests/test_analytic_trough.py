"""A raised trough (``base.trough_height``): stage 1 on it against the sympy Lagrangian for each kind,
ideal, with friction and on a rolling frame; the start at rest on it; a trough as a lowered pivot
until release and a longer fall after; both paths; the energy audit; and bad values refused.

The reference is ``tests/sympy_model.py``, whose trough is the constraint ``y_P + h - ht = 0``
(``docs/derivation.md`` 4.7): the analytic model's accelerations, its trough's push N (the
multiplier) and its friction must satisfy ``M q'' = f + Q + J^T N`` with sympy's M, f, J and Q at
random stage-1 states, the projectile on the trough.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

import analytic
from analytic import eom, friction
from analytic.design import Base, DesignError, Losses, initial_angles
from analytic.design_file import default_design, design_from_dict, design_to_dict, load_design
from analytic.parameters import params
from analytic.reference import simulate
from analytic.result import Status
from crosscheck.cases import floating_design, trough_cases

#: Agreement with the sympy reference, relative to the largest term of the equation: closed forms
#: in a few dozen double operations (round-off ~1e-14), room for the 2x2 solve and the Coulomb
#: iterations' own tolerance (as ``tests/test_analytic_friction.py``).
REL_TOL = 1e-9
SEED = 46_071
FIXED_FILE = Path(analytic.__file__).with_name("data") / "paper_table3_fixed.toml"

#: Friction of every joint a kind has, large enough that a wrong term shows at O(1) (static above kinetic).
FRICTIONS = {
    "hinged": Losses(axle_friction=0.3, axle_radius=0.02, hinge_friction=0.25, hinge_radius=0.015,
                     base_friction=0.4, base_static_friction=0.5),
    "fixed": Losses(axle_friction=0.3, axle_radius=0.02, base_friction=0.4, base_static_friction=0.5),
    "floating-arm": Losses(axle_friction=0.3, axle_radius=0.02, guide_friction=0.25, track_friction=0.35),
}


def _machine(kind: str):
    return {"hinged": default_design, "fixed": lambda: load_design(FIXED_FILE),
            "floating-arm": lambda: floating_design(default_design(), "table3-floating-arm")}[kind]()


#: (kind, mode): every kind ideal and with its friction, the two that roll on a rolling frame with it.
CASES = [(kind, mode) for kind in ("hinged", "fixed", "floating-arm") for mode in ("ideal", "friction")]
CASES += [(kind, "rolling") for kind in ("hinged", "fixed")]


def _samples(kind: str, mode: str, n: int = 6):
    """(p, theta, phi, theta', phi') on a random trough with random masses; theta a random way past rest,
    within the sling's reach."""
    rng = np.random.default_rng([SEED, CASES.index((kind, mode))])
    design = _machine(kind)
    if mode != "ideal":
        design = dataclasses.replace(design, losses=FRICTIONS[kind])
    out = []
    while len(out) < n:
        trough = design.machine.pivot_height * rng.uniform(0.05, 0.7)
        base = Base("rolling", rng.uniform(2.0, 50.0), trough) if mode == "rolling" else Base(trough_height=trough)
        p = params(dataclasses.replace(design, base=base))
        p = p._replace(mA=rng.uniform(0.1, 3.0), d=rng.uniform(-0.2, 0.6), mP=rng.uniform(0.02, 2.0),
                       IA=rng.uniform(0.0, 0.1), mW=rng.uniform(1.0, 50.0), g=rng.uniform(1.0, 25.0))
        theta = p.theta0 - rng.uniform(0.05, 0.8)
        if math.isnan(eom.slide_constraint(theta, 0.0, p)[0]):
            continue
        dphi = rng.normal(0.0, 4.0) if kind == "hinged" else 0.0
        out.append((p, theta, rng.uniform(-0.5, 0.5) - theta if kind == "hinged" else -p.theta0,
                    -abs(rng.normal(0.0, 4.0)), dphi))
    return out


@pytest.fixture(scope="module")
def lagrangians():
    from sympy_model import machine

    return {kind: machine(kind) for kind in ("hinged", "fixed", "floating-arm")}


def _four(p, kind, q3, qd3, qdd3):
    """q, q', q'' with the sympy model's X: a rolling frame's from zero momentum (X'' from eom, which
    the X row then checks); a floating arm's guide stays at X = 0 (its axle's motion is in its positions)."""
    if not p.rolling:
        return np.array([*q3, 0.0]), np.array([*qd3, 0.0]), np.array([*qdd3, 0.0])
    return (np.array([*q3, eom.frame_displacement(*q3, p)]), np.array([*qd3, eom.frame_velocity(*q3, *qd3, p)]),
            np.array([*qdd3, eom.frame_acceleration(*q3, *qd3, *qdd3, p)]))


@pytest.mark.parametrize("kind, mode", CASES, ids=[f"{k}-{m}" for k, m in CASES])
def test_on_the_trough_the_motion_and_its_push_satisfy_the_lagrangian(lagrangians, kind, mode):
    sympy = lagrangians[kind]
    rows = [0] + ([1] if kind == "hinged" else []) + [2] + ([3] if mode == "rolling" else [])
    for p, theta, phi, dtheta, dphi in _samples(kind, mode):
        psi, dpsi, s, c, _ = eom.slide_constraint(theta, dtheta, p)
        generalised = np.zeros(4)
        if mode == "ideal":
            ddtheta, ddphi, normal = eom.slide_accelerations(theta, phi, dtheta, dphi, p)
        elif kind == "floating-arm":   # slipping clockwise; Q on theta (the axle's and the slides')
            ddtheta, ddphi, normal, q_theta, *_ = friction.slide_friction(theta, phi, dtheta, dphi, -1.0, 0.0, 0.0, p)
            generalised[0] = q_theta
        else:   # slipping: the arm clockwise, the link either way, the projectile back along the trough
            sh = (1.0 if dphi > 0.0 else -1.0) if kind == "hinged" else 0.0
            sb = -1.0 if friction.slide_rate(theta, s, 0.0, p) * dtheta < 0.0 else 1.0
            ddtheta, ddphi, normal, ta, th, fb, *_ = friction.slide_friction(theta, phi, dtheta, dphi, -1.0, sh, sb, p)
            assert abs(fb + p.mub * sb * normal) <= 1e-8 * abs(fb), "the trough's friction is mub N against the slide"
        q, qd, qdd = _four(p, kind, (theta, phi, psi), (dtheta, dphi, dpsi), (ddtheta, ddphi, s * ddtheta + c))
        if mode != "ideal" and kind != "floating-arm":
            generalised = sympy.generalised(p, q, qd, ta, th, fb)
        # The projectile is on the trough, moving along it.
        position, velocity = sympy.projectile(p, q, qd)
        assert abs(sympy.gaps(p, q)[0]) <= REL_TOL * p.La and abs(position[1] + p.h - p.ht) <= REL_TOL * p.La
        assert abs(velocity[1]) <= REL_TOL * p.La * abs(dtheta)
        m, f = sympy.mass(p, q, qd), sympy.forcing(p, q, qd)
        residual = (m @ qdd - f - generalised - sympy.base_jacobian(p, q) * normal)[rows]
        scale = max(float(np.max(np.abs(f[rows]))), float(np.max(np.abs((m @ qdd)[rows]))), p.mP * p.g * p.La)
        assert float(np.max(np.abs(residual))) <= REL_TOL * scale, f"{kind} {mode}: residual {residual}, scale {scale:.3g}"
        if kind != "hinged":
            assert ddphi == 0.0


@pytest.mark.parametrize("kind", ["hinged", "fixed", "floating-arm"])
def test_at_rest_the_tip_and_the_flat_sling_lie_on_the_trough(lagrangians, kind):
    design = _machine(kind)
    trough = 0.4 * design.machine.pivot_height
    p = params(dataclasses.replace(design, base=Base(trough_height=trough)))
    theta, phi, psi = initial_angles(design.machine, trough)
    assert (p.theta0, p.phi0) == (theta, phi)
    q = (theta, phi, psi, 0.0)
    projectile_gap, tip_gap = lagrangians[kind].gaps(p, q)
    assert abs(projectile_gap) <= REL_TOL * p.La and abs(tip_gap) <= REL_TOL * p.La
    assert math.sin(theta + psi) == pytest.approx(-1.0, abs=1e-15)   # flat, pointing forward
    assert eom.slide_accelerations(theta, phi, 0.0, 0.0, p).normal == pytest.approx(p.mP * p.g, rel=REL_TOL)


# --------------------------------------------------------------------------- #
# Whole shots
# --------------------------------------------------------------------------- #

def _vacuum(design):
    return dataclasses.replace(design, projectile=dataclasses.replace(design.projectile, drag="none"))


@pytest.mark.parametrize(("kind", "rolling"), [(kind, rolling) for kind in ("hinged", "fixed", "floating-arm")
                                                for rolling in (False, True)
                                                if not (kind == "floating-arm" and rolling)],   # its frame does not roll
                         ids=lambda v: {False: "fixed-frame", True: "rolling-frame"}.get(v, v) if isinstance(v, bool) else v)
def test_a_trough_is_a_lowered_pivot_until_release_and_a_longer_fall_after(kind, rolling):
    """Nothing before release depends on h but through h - ht (derivation 4.7): a machine ht lower with
    no trough releases at the same instant in the same state, to the bit; the flight then falls
    ht further, to the base (vacuum: in closed form)."""
    design = _vacuum(dataclasses.replace(_machine(kind), losses=FRICTIONS[kind]))
    trough = 0.15
    frame = dict(mobility="rolling", mass=20.0) if rolling else {}
    raised = dataclasses.replace(design, base=Base(**frame, trough_height=trough))
    lowered = dataclasses.replace(design, base=Base(**frame),
                                  machine=dataclasses.replace(design.machine,
                                                              pivot_height=design.machine.pivot_height - trough))
    a, b = simulate(raised, histories=False), simulate(lowered, histories=False)
    assert a.status is b.status is Status.OK
    assert (a.liftoff_time, a.release_time) == (b.liftoff_time, b.release_time)
    np.testing.assert_array_equal(a.release_position, b.release_position)
    np.testing.assert_array_equal(a.release_velocity, b.release_velocity)
    g, h = design.environment.gravity, design.machine.pivot_height
    (x, y), (vx, vy) = a.release_position, a.release_velocity   # on the ground, from the pivot's mark
    fall = (vy + math.sqrt(vy * vy + 2.0 * g * (y + h))) / g     # y + h above the base at release
    assert a.range == pytest.approx(x + vx * fall, rel=1e-9)
    assert a.range > b.range and a.apex_height == pytest.approx(b.apex_height + trough, rel=1e-12)


FAST_TOL = 1e-7   # tests/test_analytic_friction.py's: the two paths' step control diverges by round-off


@pytest.mark.parametrize("case", trough_cases(), ids=lambda case: case.name)
def test_both_paths_agree_on_the_trough_group(case):
    from analytic.fast import simulate_fast

    reference, fast = simulate(case.design, histories=False), simulate_fast(case.design)
    assert fast.status is reference.status is Status.OK, f"{fast.message} vs {reference.message}"
    assert abs(fast.range - reference.range) <= FAST_TOL * abs(reference.range)
    assert fast.liftoff_time == pytest.approx(reference.liftoff_time, abs=1e-9)
    assert fast.release_time == pytest.approx(reference.release_time, abs=1e-9)


@pytest.mark.parametrize("case", [c for c in trough_cases() if c.design.losses != Losses()], ids=lambda c: c.name)
def test_the_energy_audit_closes_on_a_trough(case):
    shot = simulate(case.design)
    e = shot.history.energy
    assert float(np.max(np.abs(e.total + e.lost))) <= 1e-8 * shot.counterweight_energy_released
    assert shot.energy_dissipated["base"] > 0.0 or case.design.losses.base_friction == 0.0


# --------------------------------------------------------------------------- #
# Design files
# --------------------------------------------------------------------------- #

def _file(**base):
    data = design_to_dict(default_design())
    data["base"] = base
    return data


def test_a_trough_is_read_with_units_and_written_back_only_when_raised():
    design = design_from_dict(_file(trough_height="20 cm"))
    assert design.base.trough_height == pytest.approx(0.2)
    assert design_to_dict(design)["base"] == {"mobility": "fixed", "trough_height": design.base.trough_height}
    assert "base" not in design_to_dict(dataclasses.replace(design, base=Base(trough_height=0.0)))


@pytest.mark.parametrize("value, written, reason", [
    (-0.1, "-0.1", "must not be negative"), ("-10 cm", '"-10 cm"', "must not be negative"),
    ("1 m", '"1 m"', "cannot come down to a trough at or above the pivot: it must be less than pivot_height (0.5942 m)"),
    (0.5942, "0.5942", "cannot come down to a trough at or above the pivot"), ("high", "'high'", "must be a number, or a length with a unit"),
    (math.nan, "nan", "must be finite")])
def test_a_trough_out_of_reach_is_refused_naming_the_field_and_the_value_as_written(value, written, reason):
    # (The Table III machine's pivot is 0.5942 m over the base: a trough there or higher is out of reach.)
    with pytest.raises(DesignError) as raised:
        design_from_dict(_file(trough_height=value))
    message = str(raised.value)
    assert message.startswith(f"base.trough_height = {written}") and reason in message
