"""The floating arm's swing equations (``analytic.floating_arm``, derivation section 12) against the
sympy Lagrangian of ``tests/sympy_model.py``'s ``machine("floating-arm")``, at random designs and states.

Only the equations; the machine the paths simulate is checked in tests/test_analytic_floating.py.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from analytic import eom, floating_arm
from analytic.design_file import default_design
from analytic.parameters import params

#: Agreement with the sympy reference, relative to the largest entry compared: closed forms in a few
#: dozen double operations (round-off ~1e-14), room for the 2x2 solve (as tests/test_analytic_fixed.py).
REL_TOL = 1e-10
SEED = 28_012


def _samples(n: int):
    rng = np.random.default_rng(SEED)
    base = params(default_design())._replace(Lw=0.0, rolling=0.0, Mf=0.0)
    for _ in range(n):
        p = base._replace(mA=rng.uniform(0.1, 3.0), d=rng.uniform(-0.2, 0.6), mP=rng.uniform(0.02, 2.0),
                          IW=rng.uniform(0.0, 0.1), IA=rng.uniform(0.0, 0.1), mW=rng.uniform(1.0, 50.0),
                          g=rng.uniform(1.0, 25.0), Lb=rng.uniform(0.1, 0.5), La=rng.uniform(0.6, 2.0),
                          Ls=rng.uniform(0.3, 1.5))
        yield p, rng.uniform(-math.pi, math.pi, 3), rng.normal(0.0, 6.0, 3)


SAMPLES = list(_samples(12))


@pytest.fixture(scope="module")
def floating():
    from sympy_model import machine

    return machine("floating-arm")


def _close(got, expected, what):
    got, expected = np.asarray(got, dtype=float), np.asarray(expected, dtype=float)
    scale = float(np.max(np.abs(expected)))
    assert float(np.max(np.abs(got - expected))) <= REL_TOL * scale, f"{what}: {got} vs sympy {expected}"


@pytest.mark.parametrize("i", range(len(SAMPLES)))
def test_mass_matrix_forcing_and_accelerations_are_the_lagrangians(floating, i):
    p, q, qd = SAMPLES[i]
    q, qd = (q[0], 0.0, q[2]), (qd[0], 0.0, qd[2])
    m11, m13, m33, f1, f3 = floating_arm.terms(q[0], q[2], qd[0], qd[2], p)
    m, f = floating.mass(p, q, qd), floating.forcing(p, q, qd)
    _close([m11, m13, m33], [m[0, 0], m[0, 2], m[2, 2]], "M over (theta, psi)")
    _close([f1, f3], [f[0], f[2]], "f over (theta, psi)")
    acc = floating.accelerations(p, q, qd)
    _close(floating_arm.swing_accelerations(q[0], q[2], qd[0], qd[2], p), [acc[0], acc[2]], "theta'', psi''")


@pytest.mark.parametrize("i", range(len(SAMPLES)))
def test_the_base_constraint_is_the_hinged_machines(floating, i):
    """The tip's height is La cos(theta) as on the hinged machine, so stage 1's psi(theta) is
    ``eom.slide_constraint``'s: the Lagrangian's projectile sits on the base there."""
    p, _, qd = SAMPLES[i]
    theta = math.acos(-p.h / p.La) - 0.2 if p.La > p.h else None
    if theta is None:
        pytest.skip("long arm shorter than the pivot height")
    psi, dpsi, _, _, _ = eom.slide_constraint(theta, qd[0], p)
    if math.isnan(psi):
        pytest.skip("out of the sling's reach")
    position, velocity = floating.projectile(p, (theta, 0.0, psi), (qd[0], 0.0, dpsi))
    assert abs(position[1] + p.h) <= REL_TOL * p.La and abs(velocity[1]) <= REL_TOL * p.La * abs(qd[0])


@pytest.mark.parametrize("i", range(len(SAMPLES)))
def test_the_track_and_guide_forces_are_the_machines_momentum_change(floating, i):
    """In the swing (sympy's accelerations) and on the base (its accelerations and push N): the guide
    gives sum m a_x, the track sum m (a_y + g) - N, with the accelerations sympy differentiates."""
    p, q, qd = SAMPLES[i]
    q, qd = (q[0], 0.0, q[2]), (qd[0], 0.0, qd[2])
    states = [(q, qd, floating.accelerations(p, q, qd), 0.0)]
    theta = math.acos(-p.h / p.La) - 0.2
    psi, dpsi, _, _, _ = eom.slide_constraint(theta, qd[0], p)
    if not math.isnan(psi):
        on_base = ((theta, 0.0, psi), (qd[0], 0.0, dpsi))
        states.append((*on_base, *floating.on_base(p, *on_base)))
    for q, qd, acc, normal in states:
        rate = floating.momentum_rate(p, q, qd, acc)
        weight = (p.mA + p.mW + p.mP) * p.g
        expected = [rate[1] + weight - normal, rate[0]]
        got = floating_arm.support_forces(q[0], q[2], qd[0], qd[2], acc[0], acc[2], normal, p)
        scale = max(float(np.max(np.abs(rate))), weight)
        assert np.max(np.abs(np.subtract(got, expected))) <= REL_TOL * scale, (got, expected)
