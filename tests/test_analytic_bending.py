"""The arm's bending moment at the axle (``analytic.eom.arm_bending_moment``) against Newton-Euler in sympy.

The reference takes the long side as its own body: a uniform rod from the axle
point A(t) along ``(-sin theta(t), cos theta(t))``, its points' accelerations
differentiated by sympy from their positions, and the moment about A of every
force on it (the tip's pull, gravity, and the cut's moment M) set equal to the
moment of its mass times acceleration, integrated along the rod. Nothing of
the hand derivation (``docs/derivation.md`` eqs. 9.4-9.6) is reused but the
mass split ``geometry.arm_long_side``, which the split's own test checks.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from analytic import eom, stages, states
from analytic.design_file import default_design
from analytic.geometry import arm_long_side
from analytic.parameters import params

#: Agreement with the sympy reference, relative to the largest term: both sides
#: evaluate a closed form of a few dozen operations on O(1)-O(1e3) numbers, so they
#: differ by round-off (~1e-15); 1e-10 still catches any wrong term.
REL_TOL = 1e-10


@pytest.fixture(scope="module")
def newton_euler():
    """The cut's moment M as a function of (theta, theta', theta'', a_Ax, a_Ay, S_x, S_y, La, m_L, g)."""
    t, s = sp.symbols("t s", real=True)
    La, mass, g = sp.symbols("La m_L g", positive=True)
    dth, ddth, ax, ay, sx, sy, th0, moment = sp.symbols("dth ddth ax ay sx sy th0 M", real=True)
    theta = sp.Function("theta")(t)
    x_a, y_a = sp.Function("x_A")(t), sp.Function("y_A")(t)
    along = sp.Matrix([-sp.sin(theta), sp.cos(theta)])
    point = sp.Matrix([x_a, y_a]) + s * along
    accel = point.diff(t, 2)
    relative = s * along
    cross = lambda r, f: r[0] * f[1] - r[1] * f[0]   # noqa: E731 -- z of a planar cross product
    density = mass / La
    inertial = sp.integrate(cross(relative, accel) * density, (s, 0, La))
    weight = sp.integrate(cross(relative, sp.Matrix([0, -g])) * density, (s, 0, La))
    pull = cross(La * along, sp.Matrix([-sx, -sy]))   # the sling pulls the tip with -S
    balance = moment + weight + pull - inertial
    values = {theta.diff(t, 2): ddth, theta.diff(t): dth, x_a.diff(t, 2): ax, y_a.diff(t, 2): ay}
    balance = balance.subs(values).subs(theta, th0)
    solved = sp.solve(balance, moment)[0]
    return sp.lambdify((th0, dth, ddth, ax, ay, sx, sy, La, mass, g), solved, "math")


def random_cases(count: int = 12):
    rng = np.random.default_rng(20261127)
    base = params(default_design())
    for _ in range(count):
        La, Lb = rng.uniform(0.3, 3.0), rng.uniform(0.05, 1.0)
        p = base._replace(La=La, Lb=Lb, d=rng.uniform(-Lb / 2, La / 2), mA=rng.uniform(0.1, 20.0),
                          g=rng.uniform(1.0, 20.0))
        state = (rng.uniform(-math.pi, math.pi), rng.uniform(-30, 30), rng.uniform(-500, 500),
                 rng.uniform(-50, 50), rng.uniform(-50, 50), rng.uniform(-300, 300), rng.uniform(-300, 300))
        yield p, state


@pytest.mark.parametrize("case", list(random_cases()), ids=lambda case: f"La={case[0].La:.3f}")
def test_bending_moment_matches_newton_euler_on_the_long_side(newton_euler, case):
    p, (theta, dtheta, ddtheta, ax, ay, sx, sy) = case
    mass, _, _ = arm_long_side(p.La, p.Lb, p.mA, p.d)
    expected = newton_euler(theta, dtheta, ddtheta, ax, ay, sx, sy, p.La, mass, p.g)
    actual = eom.arm_bending_moment(theta, ddtheta, ax, ay, sx, sy, p)
    scale = max(abs(expected), p.La * math.hypot(sx, sy), mass * p.La * p.La * abs(ddtheta))
    assert abs(actual - expected) <= REL_TOL * scale, f"M: {actual!r} against Newton-Euler's {expected!r}"


@pytest.mark.parametrize("d_share", [-0.5, 0.0, 0.3, 0.5], ids=lambda v: f"d={v}La")
def test_long_side_split_keeps_the_arms_mass_and_centre(d_share):
    """Two uniform rods of masses m_L (over La) and mA - m_L (over Lb) put the centre at d."""
    La, Lb, mA = 1.7, 0.45, 3.2
    d = d_share * La if d_share >= 0 else d_share * Lb
    mass, first, second = arm_long_side(La, Lb, mA, d)
    short = mA - mass
    assert 0.0 <= mass <= mA
    assert first - short * Lb / 2 == pytest.approx(mA * d, rel=1e-12, abs=1e-12)
    assert second == pytest.approx(mass * La**2 / 3, rel=1e-12)


def test_static_horizontal_arm_carries_its_weight_and_the_tip_load():
    """At rest, the long arm horizontal forward (theta = -pi/2), a weight W hanging from the tip:
    the cantilever's root moment is W La + m_L g La / 2, turning the long side down (clockwise)."""
    p = params(default_design())
    mass, _, _ = arm_long_side(p.La, p.Lb, p.mA, p.d)
    weight = 40.0   # N; the sling's force on the load is up, S = (0, W)
    moment = eom.arm_bending_moment(-math.pi / 2, 0.0, 0.0, 0.0, 0.0, weight, p)
    # The short side holds the long side up: a counter-clockwise moment on it at the cut.
    assert moment == pytest.approx(weight * p.La + mass * p.g * p.La / 2, rel=1e-12)


def test_loads_report_the_magnitude_at_a_stage_two_state():
    """``loads_at``'s fifth value is |M| from the stage's own accelerations and the sling's force."""
    p = params(default_design())
    y = (0.4, -1.2, 2.1, -6.0, 3.0, -9.0)
    ddtheta, ddphi, ddpsi = eom.swing_accelerations(*y, p)
    forces = eom.joint_forces(*y, ddtheta, ddphi, ddpsi, 0.0, p)
    expected = abs(eom.arm_bending_moment(y[0], ddtheta, 0.0, 0.0, forces[4], forces[5], p))
    assert stages.LOAD_NAMES[4] == "arm_bending_moment"
    assert stages.loads_at(states.SWING, np.array(y), p)[4] == pytest.approx(expected, rel=1e-14)
