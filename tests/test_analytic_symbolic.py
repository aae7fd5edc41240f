"""analytic.eom against the sympy Lagrangian: M, f, the constrained slide, energies, sling force.

The reference is ``tests/sympy_model.py``, derived from nothing but the
geometry in the module docstring of ``analytic.design``. Stage 1 is not
reduced by hand: the full system carries the base constraint ``y_P = -h``
with its multiplier N (the normal force on the projectile, positive up),

    [[M, -J^T], [J, 0]] [q'', N] = [f, -J' q'],   J = d y_P / d q,

and the 4x4 is solved numerically. The sling tension comes from the
projectile's own Newton equation, not from the Lagrangian.

States and parameters are random (seeded) so that no term can hide behind a
special value (a zero angle, equal lengths, g = 9.81).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from analytic import eom, stages, states
from analytic.design import initial_angles
from analytic.design_file import default_design
from analytic.aero import DRAG_TABLE
from analytic.geometry import part_positions, projectile_state
from analytic.parameters import Params, params

#: Agreement asked of analytic.eom and the sympy reference, relative to the
#: largest entry of the quantity compared. Both sides evaluate the same closed
#: form in a few dozen double-precision operations on O(1)-O(1e3) numbers, so
#: they differ by round-off (~1e-14); 1e-10 leaves room for the cancellation in
#: solving the 4x4 constrained system while still catching any wrong term.
REL_TOL = 1e-10

#: The machine's numbers in ``Params``, the only ones the equations of motion read.
MECHANICS = ("La", "Lb", "d", "mA", "IA", "mW", "Lw", "IW", "Ls", "mP", "h", "g")

#: Seed of the random states and parameters (any fixed value; fixed so a
#: failure reproduces).
SEED = 20_240_611
#: Random (parameters, state) samples per stage.
N_SAMPLES = 8


def swing(lagrangian, p, q, qd):
    """(M (3, 3), f (3,), q'' (3,)) of the free 3-DOF system."""
    return lagrangian.mass(p, q, qd)[:3, :3], lagrangian.forcing(p, q, qd)[:3], lagrangian.accelerations(p, q, qd)[:3]


# --------------------------------------------------------------------------- #
# Random parameters and states
# --------------------------------------------------------------------------- #

def random_params(rng: np.random.Generator) -> Params:
    """A plausible machine with every parameter distinct and none at a special value."""
    La = rng.uniform(0.8, 4.0)
    Lb = La * rng.uniform(0.15, 0.5)
    h = La * rng.uniform(0.4, 0.9)
    mA = math.exp(rng.uniform(math.log(0.3), math.log(50.0)))
    mW = math.exp(rng.uniform(math.log(5.0), math.log(2000.0)))
    # The equations read only the machine's numbers: the rest stay NaN, so a term
    # that wrongly reads one of them shows up as NaN.
    rest = dict.fromkeys(set(Params._fields) - set(MECHANICS), math.nan)
    rest.update(rolling=0.0, Mf=0.0,   # a fixed frame: the switch the equations read (NaN is true)
                mS=0.0, mQ=0.0)    # a massless sling and pouch, which the equations test likewise
    return Params(La=La, Lb=Lb, d=rng.uniform(-Lb, La), mA=mA,
                  IA=mA * (La + Lb) ** 2 / 12.0 * rng.uniform(0.5, 1.5), mW=mW,
                  Lw=h * rng.uniform(0.2, 0.8), IW=mW * rng.uniform(0.0, 0.05),
                  Ls=La * rng.uniform(0.5, 1.3),
                  mP=math.exp(rng.uniform(math.log(0.04), math.log(20.0))), h=h,
                  g=rng.uniform(1.0, 25.0), **rest)


def swing_samples():
    rng = np.random.default_rng(SEED)
    out = []
    for _ in range(N_SAMPLES):
        p = random_params(rng)
        out.append((p, rng.uniform(-math.pi, math.pi, 3), rng.normal(0.0, 4.0, 3)))
    return out


def slide_state(p: Params, rng: np.random.Generator):
    """``(theta, phi, dtheta, dphi)`` of ``p``'s machine with the projectile on the base and the sling
    not near vertical, or None where the drawn sling angle leaves the arm near vertical (draw again)."""
    beta = rng.uniform(-math.pi + 0.25, -0.25)
    cos_theta = (-p.h - p.Ls * math.cos(beta)) / p.La
    if abs(cos_theta) > 0.98:
        return None
    theta = math.acos(cos_theta) * rng.choice([-1.0, 1.0])
    return (theta, rng.uniform(-math.pi, math.pi), *rng.normal(0.0, 4.0, 2))


def slide_samples():
    """(params, theta, phi, dtheta, dphi) with the projectile on the base, sling not near vertical."""
    rng = np.random.default_rng(SEED + 1)
    out = []
    while len(out) < N_SAMPLES:
        p = random_params(rng)
        state = slide_state(p, rng)
        if state is not None:
            out.append((p, *state))
    return out


SWING = swing_samples()
SLIDE = slide_samples()
SWING_IDS = [f"swing{i}" for i in range(len(SWING))]
SLIDE_IDS = [f"slide{i}" for i in range(len(SLIDE))]


def assert_close(actual, expected, what: str, scale: float | None = None) -> float:
    """|actual - expected| <= REL_TOL * scale (default: the largest |expected| entry); returns the error."""
    actual, expected = np.asarray(actual, dtype=float), np.asarray(expected, dtype=float)
    if scale is None:
        scale = float(np.max(np.abs(expected)))
    error = float(np.max(np.abs(actual - expected)))
    assert error <= REL_TOL * scale, (
        f"{what}: analytic.eom {actual!r} vs sympy {expected!r}; "
        f"max |diff| {error:.3g} > {REL_TOL:g} x scale {scale:.3g}")
    return error / scale


# --------------------------------------------------------------------------- #
# The reference checks itself (so agreement with it means something)
# --------------------------------------------------------------------------- #

@pytest.mark.parametrize("sample", SWING, ids=SWING_IDS)
def test_reference_conserves_energy_in_the_swing(lagrangian, sample):
    p, q, qd = sample
    _, _, qdd = swing(lagrangian, p, q, qd)
    scale = float(np.max(np.abs(swing(lagrangian, p, q, qd)[0]))) * float(np.max(np.abs(qd))) * float(np.max(np.abs(qdd)))
    assert abs(lagrangian.power(p, q, qd, qdd)) <= REL_TOL * scale


@pytest.mark.parametrize("sample", SLIDE, ids=SLIDE_IDS)
def test_reference_slide_keeps_the_projectile_on_the_base_and_conserves_energy(lagrangian, sample):
    p, theta, phi, dtheta, dphi = sample
    sol = lagrangian.base_reduction(p, theta, phi, dtheta, dphi)
    (position, velocity) = lagrangian.projectile(p, sol["q"], sol["qd"])
    assert position[1] == pytest.approx(-p.h, rel=REL_TOL)
    assert velocity[1] == pytest.approx(0.0, abs=REL_TOL * np.max(np.abs(velocity)))
    # The normal force does no work (the projectile moves along the base).
    scale = float(np.max(np.abs(sol["m"]))) * float(np.max(np.abs(sol["qd"]))) * float(np.max(np.abs(sol["qdd"])))
    assert abs(lagrangian.power(p, sol["q"], sol["qd"], sol["qdd"])) <= REL_TOL * scale


@pytest.mark.parametrize("sample", SWING, ids=SWING_IDS)
def test_reference_newton_across_the_sling_matches_the_lagrangian(lagrangian, sample):
    p, q, qd = sample
    _, _, qdd = swing(lagrangian, p, q, qd)
    scale = p.mP * (p.g + p.La * float(np.max(np.abs(qdd))) + p.La * float(np.max(qd**2)))
    assert abs(lagrangian.sling(p, q, qd, qdd, 0.0)[1]) <= REL_TOL * scale


# --------------------------------------------------------------------------- #
# Stage 2
# --------------------------------------------------------------------------- #

@pytest.mark.parametrize("sample", SWING, ids=SWING_IDS)
def test_mass_matrix(lagrangian, sample):
    p, q, qd = sample
    m11, m12, m13, m22, m33, *_ = eom.terms(*q, *qd, p)
    mass_matrix = [[m11, m12, m13], [m12, m22, 0.0], [m13, 0.0, m33]]
    assert_close(mass_matrix, swing(lagrangian, p, q, qd)[0], "M(q)")


@pytest.mark.parametrize("sample", SWING, ids=SWING_IDS)
def test_forcing(lagrangian, sample):
    p, q, qd = sample
    assert_close(eom.terms(*q, *qd, p)[5:], swing(lagrangian, p, q, qd)[1], "f(q, q')")


@pytest.mark.parametrize("sample", SWING, ids=SWING_IDS)
def test_swing_accelerations(lagrangian, sample):
    p, q, qd = sample
    assert_close(eom.swing_accelerations(*q, *qd, p), swing(lagrangian, p, q, qd)[2], "q''")


@pytest.mark.parametrize("sample", SWING, ids=SWING_IDS)
def test_swing_derivative_stacks_rates_and_accelerations(lagrangian, sample):
    p, q, qd = sample
    out = np.empty(6)
    stages.derivative(states.SWING, np.concatenate([q, qd]), p, DRAG_TABLE, out)
    assert_close(out, np.concatenate([qd, swing(lagrangian, p, q, qd)[2]]), "stage-2 derivative")


# --------------------------------------------------------------------------- #
# Stage 1
# --------------------------------------------------------------------------- #

@pytest.mark.parametrize("sample", SLIDE, ids=SLIDE_IDS)
def test_slide_kinematics(lagrangian, sample):
    p, theta, phi, dtheta, dphi = sample
    sol = lagrangian.base_reduction(p, theta, phi, dtheta, dphi)
    psi, dpsi, s, c, sin_beta = eom.slide_constraint(theta, dtheta, p)
    assert_close(psi, sol["q"][2], "psi", scale=math.pi)
    assert_close(s, sol["s"], "s = dpsi/dtheta", scale=max(1.0, abs(sol["s"])))
    assert_close(dpsi, sol["qd"][2], "psi'", scale=max(abs(dtheta), abs(sol["qd"][2])))
    assert_close(c, sol["c"], "c", scale=max(dtheta**2, abs(sol["c"])))
    assert_close(sin_beta, math.sin(theta + sol["q"][2]), "sin beta", scale=1.0)
    assert sin_beta < 0.0


@pytest.mark.parametrize("sample", SLIDE, ids=SLIDE_IDS)
def test_slide_system_is_the_reduced_lagrangian(lagrangian, sample):
    p, theta, phi, dtheta, dphi = sample
    sol = lagrangian.base_reduction(p, theta, phi, dtheta, dphi)
    a, b, e, r1, r2, *_ = eom.slide_system(theta, phi, dtheta, dphi, p)
    assert_close([[a, b], [b, e]], sol["m_r"], "M_r = B^T M B")
    assert_close([r1, r2], sol["r"], "r = B^T (f - M [0, 0, c])")


@pytest.mark.parametrize("sample", SLIDE, ids=SLIDE_IDS)
def test_slide_accelerations_and_normal_force(lagrangian, sample):
    p, theta, phi, dtheta, dphi = sample
    sol = lagrangian.base_reduction(p, theta, phi, dtheta, dphi)
    ddtheta, ddphi, normal = eom.slide_accelerations(theta, phi, dtheta, dphi, p)
    assert_close([ddtheta, ddphi], sol["qdd"][:2], "theta'', phi''")
    # N is a difference of forces of size mP g and mP La theta'^2 etc.
    scale = max(abs(sol["normal"]), p.mP * p.g,
                p.mP * p.La * max(dtheta**2, float(np.max(np.abs(sol["qdd"])))))
    assert_close(normal, sol["normal"], "N", scale=scale)


@pytest.mark.parametrize("sample", SLIDE, ids=SLIDE_IDS)
def test_slide_derivative_and_full_state(lagrangian, sample):
    p, theta, phi, dtheta, dphi = sample
    sol = lagrangian.base_reduction(p, theta, phi, dtheta, dphi)
    out = np.empty(4)
    stages.derivative(states.SLIDE, np.array([theta, phi, dtheta, dphi]), p, DRAG_TABLE, out)
    assert_close(out, [dtheta, dphi, *sol["qdd"][:2]], "stage-1 derivative")
    full = eom.slide_state(theta, phi, dtheta, dphi, p)
    assert_close(full[:3], sol["q"], "q", scale=math.pi)
    assert_close(full[3:], sol["qd"], "q'")


def test_normal_force_is_the_projectiles_weight_at_rest_with_the_sling_flat():
    # Closed-form limit: at rest with the sling along the base (theta + psi = -pi/2)
    # the projectile has no vertical acceleration and the sling pulls horizontally,
    # so the base carries exactly mP g (design.initial_angles, Table III design).
    p = params(default_design())
    theta, phi, psi = initial_angles(default_design().machine)
    assert eom.slide_constraint(theta, 0.0, p)[0] == pytest.approx(psi, abs=REL_TOL)
    _, _, normal = eom.slide_accelerations(theta, phi, 0.0, 0.0, p)
    assert normal == pytest.approx(p.mP * p.g, rel=REL_TOL)


# --------------------------------------------------------------------------- #
# Energies, projectile state, sling tension
# --------------------------------------------------------------------------- #

@pytest.mark.parametrize("sample", SWING, ids=SWING_IDS)
def test_energies(lagrangian, sample):
    p, q, qd = sample
    t_machine, t_proj, v_machine, v_proj = lagrangian.energies(p, q, qd)
    t_scale = float(np.max(np.abs(swing(lagrangian, p, q, qd)[0]))) * float(np.max(qd**2))
    v_scale = p.g * (p.mA * abs(p.d) + p.mW * (p.Lb + p.Lw) + p.mP * (p.La + p.Ls))
    assert_close(eom.kinetic_energy(*q, *qd, p), [t_machine, t_proj], "kinetic (machine, projectile)", t_scale)
    assert_close(eom.potential_energy(*q, p), [v_machine, v_proj], "potential (machine, projectile)", v_scale)


@pytest.mark.parametrize("sample", SWING, ids=SWING_IDS)
def test_projectile_state(lagrangian, sample):
    p, q, qd = sample
    position, velocity = lagrangian.projectile(p, q, qd)
    x, y, vx, vy = projectile_state(q[0], q[2], qd[0], qd[2], p.La, p.Ls)
    pos, vel = (x, y), (vx, vy)
    assert_close(pos, np.ravel(position), "projectile position", scale=p.La + p.Ls)
    assert_close(vel, np.ravel(velocity), "projectile velocity",
                 scale=(p.La + p.Ls) * float(np.max(np.abs(qd))))


@pytest.mark.parametrize("sample", SWING, ids=SWING_IDS)
def test_part_positions_match_the_lagrangians_points(lagrangian, sample):
    p, q, qd = sample
    position, _ = lagrangian.projectile(p, q, qd)
    parts = part_positions(*q, p.La, p.Lb, p.d, p.Lw, p.Ls)
    assert_close(parts[8:10], np.ravel(position), "projectile from part_positions", scale=p.La + p.Ls)
    # The long tip is La from the pivot and the projectile Ls from the tip.
    assert math.hypot(*parts[0:2]) == pytest.approx(p.La, rel=REL_TOL)
    assert math.hypot(parts[8] - parts[0], parts[9] - parts[1]) == pytest.approx(p.Ls, rel=REL_TOL)


@pytest.mark.parametrize("sample", SWING, ids=SWING_IDS)
def test_sling_tension_in_the_swing(lagrangian, sample):
    p, q, qd = sample
    _, _, qdd = swing(lagrangian, p, q, qd)
    expected = lagrangian.sling(p, q, qd, qdd, 0.0)[0]
    scale = p.mP * (p.g + (p.La + p.Ls) * max(float(np.max(qd**2)), float(np.max(np.abs(qdd)))))
    assert_close(eom.loads(*q, *qd, *qdd, 0.0, p)[2], expected, "T (stage 2)", scale)


@pytest.mark.parametrize("sample", SLIDE, ids=SLIDE_IDS)
def test_sling_tension_on_the_base(lagrangian, sample):
    p, theta, phi, dtheta, dphi = sample
    sol = lagrangian.base_reduction(p, theta, phi, dtheta, dphi)
    q, qd, qdd, normal = sol["q"], sol["qd"], sol["qdd"], sol["normal"]
    expected = lagrangian.sling(p, q, qd, qdd, normal)[0]
    scale = p.mP * (p.g + (p.La + p.Ls) * max(float(np.max(qd**2)), float(np.max(np.abs(qdd))))) + abs(normal)
    assert_close(eom.loads(*q, *qd, *qdd, normal, p)[2], expected, "T (stage 1)", scale)
    # Newton across the sling holds too with the reference's N and q''.
    assert abs(lagrangian.sling(p, q, qd, qdd, normal)[1]) <= REL_TOL * scale
