"""The rolling frame (section 8 of ``docs/derivation.md``) against the sympy Lagrangian with X.

The reference (``tests/sympy_model.py``) keeps the frame's displacement X as a
fourth coordinate (``analytic.eom`` eliminates it through the zero horizontal
momentum), and gives the mass matrix and forcing, the base's reaction as the
multiplier of the stage-1 constraint, the momentum and the energy. A whole
shot is also integrated from it here (scipy, stage 1 as a constrained system,
vacuum flight in closed form), which must give the model's range and release
speed to 1e-6.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from analytic import eom, stages, states
from analytic.aero import DRAG_TABLE
from analytic.design import Base
from analytic.design_file import default_design
from analytic.parameters import params
from analytic.reference import simulate

#: Agreement of the model's equations with the sympy reference at one state,
#: relative to the largest entry compared: both evaluate closed forms in a few
#: dozen double operations (round-off ~1e-14); the cancellations of solving the
#: constrained 5x5 system leave room up to 1e-10, and any wrong term is O(1).
REL_TOL = 1e-10
#: Whole shots: the model (DOP853 at rtol = atol = 1e-10) against the independent integration below
#: (1e-12) agree to 1.5e-11 in range and 8e-12 in release speed (measured 2026-11-26, frames of 2,
#: 20 and 200 kg): the bound leaves the integrators' errors room, and a wrong term moves the range more.
SHOT_REL = 1e-6
SEED = 61_820


def _rolling(frame_mass: float, design=None):
    design = design or default_design()
    return dataclasses.replace(design, base=Base("rolling", frame_mass))


def _random_states(n: int):
    rng = np.random.default_rng(SEED)
    for _ in range(n):
        p = params(_rolling(math.exp(rng.uniform(math.log(0.5), math.log(500.0)))))
        p = p._replace(mA=rng.uniform(0.1, 3.0), d=rng.uniform(-0.2, 0.6), mP=rng.uniform(0.02, 2.0),
                       IW=rng.uniform(0.0, 0.1))
        yield p, rng.uniform(-math.pi, math.pi, 3), rng.normal(0.0, 6.0, 3)


STATES = list(_random_states(12))


def _close(a, b, what, scale=None):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    scale = float(np.max(np.abs(b))) if scale is None else scale
    assert np.max(np.abs(a - b)) <= REL_TOL * max(scale, 1e-300), f"{what}: {a} vs {b}"


@pytest.mark.parametrize("i", range(len(STATES)))
def test_swing_accelerations_equal_the_four_coordinate_lagrangian(lagrangian, i):
    p, q, qd = STATES[i]
    dx = lagrangian.zero_momentum_rate(p, (*q, 0.0), qd)
    expected = lagrangian.accelerations(p, (*q, 0.0), (*qd, dx))
    _close(eom.swing_accelerations(*q, *qd, p), expected[:3], "q''")


@pytest.mark.parametrize("i", range(len(STATES)))
def test_frame_velocity_makes_the_momentum_zero_and_the_moment_is_the_lagrangians(lagrangian, i):
    p, q, qd = STATES[i]
    dx = eom.frame_velocity(*q, *qd, p)
    scale = eom.total_mass(p) * (abs(dx) + float(np.max(np.abs(qd))))
    assert abs(lagrangian.momentum(p, (*q, 0.3), (*qd, dx))) <= REL_TOL * scale
    _close(eom.horizontal_moment(*q, p), lagrangian.moment(p, (*q, 0.3)), "S")


@pytest.mark.parametrize("i", range(len(STATES)))
def test_kinetic_energy_on_the_ground_is_the_lagrangians(lagrangian, i):
    p, q, qd = STATES[i]
    dx = eom.frame_velocity(*q, *qd, p)
    _close(sum(eom.kinetic_energy(*q, *qd, p)), sum(lagrangian.energies(p, (*q, 0.0), (*qd, dx))[:2]), "T")


def _on_base_states(n: int):
    """States with the projectile on the base: theta within the sling's reach, psi from the constraint."""
    rng = np.random.default_rng(SEED + 1)
    out = []
    for p, _, qd in STATES[:n]:
        reach = math.acos(-p.h / p.La)
        theta = reach - rng.uniform(0.05, 0.6)
        psi, dpsi, *_ = eom.slide_constraint(theta, qd[0], p)
        out.append((p, theta, rng.uniform(-1.0, 1.0), qd[0], qd[1], psi, dpsi))
    return out


@pytest.mark.parametrize("state", _on_base_states(8), ids=lambda s: f"theta={s[1]:.3f}")
def test_slide_accelerations_and_normal_force_equal_the_constrained_lagrangian(lagrangian, state):
    p, theta, phi, dtheta, dphi, psi, dpsi = state
    dx = lagrangian.zero_momentum_rate(p, (theta, phi, psi, 0.0), (dtheta, dphi, dpsi))
    qdd, normal = lagrangian.on_base(p, (theta, phi, psi, 0.0), (dtheta, dphi, dpsi, dx))
    got = eom.slide_accelerations(theta, phi, dtheta, dphi, p)
    _close(got[:2], qdd[:2], "theta'', phi''")
    scale = max(abs(normal), p.mP * p.g, p.mP * p.La * max(dtheta ** 2, float(np.max(np.abs(qdd)))))
    _close(got[2], normal, "N", scale=scale)


def test_a_fixed_frame_is_the_limit_of_ever_heavier_rolling_ones():
    fixed = simulate(default_design(), histories=False)
    gaps = []
    for mass in (1e2, 1e4, 1e6):
        rolling = simulate(_rolling(mass), histories=False)
        gaps.append(abs(rolling.range / fixed.range - 1.0))
    # The frame's share of the motion goes as 1 / Mt: each 100x heavier frame, ~100x closer.
    assert gaps[0] > gaps[1] > gaps[2] and gaps[2] < 1e-6
    assert 30.0 < gaps[0] / gaps[1] < 300.0 and 30.0 < gaps[1] / gaps[2] < 300.0


@pytest.mark.parametrize("mass", [2.0, 20.0, 200.0])
def test_momentum_and_energy_are_conserved_through_the_shot(mass):
    shot = simulate(_rolling(mass))
    p = params(shot.design)
    # Energy: no loss anywhere in stages 1-2, relative to what the counterweight gives up.
    assert np.max(np.abs(shot.history.energy.total)) < 1e-7 * shot.counterweight_energy_released
    # Momentum: the frame's X' from zero momentum, checked against the frame's own path.
    x = shot.history.frame_x
    dx_numeric = np.gradient(x, shot.history.t)
    dx_model = np.array([eom.frame_velocity(*q, *qd, p) for q, qd in zip(shot.history.q, shot.history.qdot, strict=True)])
    inner = slice(2, -2)   # one-sided differences at the ends and at the stage change are cruder
    assert np.max(np.abs(dx_numeric[inner] - dx_model[inner])) < 1e-3 * np.max(np.abs(dx_model))


# --------------------------------------------------------------------------- #
# A whole shot, integrated independently
# --------------------------------------------------------------------------- #

def _independent_shot(lagrangian, design) -> tuple[float, float]:
    """Range and release speed of ``design`` (no drag, velocity rule) from the four-coordinate model."""
    p = params(design)
    psi0 = -0.5 * math.pi - p.theta0
    y = np.array([p.theta0, p.phi0, psi0, 0.0, 0.0, 0.0, 0.0, 0.0])
    tight = dict(method="DOP853", rtol=1e-12, atol=1e-12, dense_output=False)

    def slide(t, y):
        return np.concatenate([y[4:], lagrangian.on_base(p, y[:4], y[4:])[0]])

    def liftoff(t, y):
        return lagrangian.on_base(p, y[:4], y[4:])[1]
    liftoff.terminal, liftoff.direction = True, -1

    first = solve_ivp(slide, (0.0, p.t_limit), y, events=liftoff, **tight)
    assert first.status == 1, "no lift-off"

    def swing(t, y):
        return np.concatenate([y[4:], lagrangian.accelerations(p, y[:4], y[4:])])

    def release(t, y):
        vx, vy = lagrangian.projectile(p, y[:4], y[4:])[1]
        return math.sin(p.alpha) * vx - math.cos(p.alpha) * vy
    release.terminal, release.direction = True, 1

    second = solve_ivp(swing, (first.t[-1], p.t_limit), first.y[:, -1], events=release, **tight)
    assert second.status == 1, "no release"
    end = second.y[:, -1]
    position, velocity = lagrangian.projectile(p, end[:4], end[4:])
    vx, vy = velocity
    flight = (vy + math.sqrt(vy * vy + 2.0 * p.g * (position[1] + p.h))) / p.g
    return position[0] + vx * flight, math.hypot(vx, vy)


@pytest.mark.parametrize("mass", [2.0, 20.0, 200.0], ids=lambda m: f"{m:g}kg")
def test_whole_shot_equals_an_independent_integration_of_the_lagrangian(lagrangian, mass):
    design = _rolling(mass, dataclasses.replace(default_design(), projectile=dataclasses.replace(
        default_design().projectile, drag="none")))
    expected_range, expected_speed = _independent_shot(lagrangian, design)
    shot = simulate(design, histories=False)
    assert shot.ok
    assert abs(shot.range / expected_range - 1.0) < SHOT_REL
    assert abs(shot.release_speed / expected_speed - 1.0) < SHOT_REL


def test_the_derivative_of_stage_2_uses_the_rolling_system():
    p = params(_rolling(5.0))
    y = np.array([1.0, -0.7, -2.0, -3.0, 4.0, 9.0])
    out = np.empty(6)
    stages.derivative(states.SWING, y, p, DRAG_TABLE, out)
    assert tuple(out[3:]) == eom.swing_accelerations(*y, p)
    fixed = eom.swing_accelerations(*y, p._replace(rolling=0.0))
    assert not np.allclose(out[3:], fixed, rtol=1e-3)   # the frame's motion changes them visibly


# --------------------------------------------------------------------------- #
# Both paths, the batch and the optimiser on rolling frames
# --------------------------------------------------------------------------- #

#: The two paths' bound (the fast path's specification, as for fixed frames).
PATHS_RANGE_REL = 1e-7


def test_fast_path_and_batch_agree_with_the_reference_on_rolling_frames():
    from analytic import fast
    from crosscheck.cases import sample_cases

    designs = [_rolling(mass, case.design) for case in sample_cases(6, seed=3) for mass in (1.0, 30.0)]
    designs += [_rolling(mass) for mass in (0.5, 5.0, 500.0)]
    batch = fast.shoot(designs)
    for i, design in enumerate(designs):
        reference = simulate(design, histories=False)
        assert batch.status[i] is reference.status, design.name
        if reference.ok:
            assert abs(batch.range[i] / reference.range - 1.0) < PATHS_RANGE_REL, design.name
            single = fast.simulate_fast(design)
            assert single.frame_release_velocity == pytest.approx(reference.frame_release_velocity, rel=1e-7,
                                                                  abs=1e-12)


def _problem_text(base: str) -> str:
    from pathlib import Path

    text = (Path(__file__).parents[1] / "analytic" / "data" / "paper_problem.toml").read_text()
    return text.replace("[release]", f"[base]\n{base}\n\n[release]")


def test_a_problem_with_a_free_frame_mass_makes_it_the_seventh_variable(tmp_path):
    from analytic.design_space import FRAME_MASS, design_at, load_problem, variables_of

    path = tmp_path / "rolling.toml"
    path.write_text(_problem_text('mobility = "rolling"\nmass = { lower = 2.0, upper = 50.0 }'))
    problem = load_problem(path)
    assert problem.names[-1] == FRAME_MASS and len(problem.variables) == 7
    values = problem.complete(variables_of(default_design().machine))
    assert values[-1] == 2.0   # the lightest frame allowed
    design = design_at(problem, np.append(values[:6], 12.5))
    assert design.base == Base("rolling", 12.5)


def test_a_problem_with_a_fixed_frame_mass_keeps_six_variables(tmp_path):
    from analytic.design_space import design_at, load_problem, variables_of

    path = tmp_path / "rolling.toml"
    path.write_text(_problem_text('mobility = "rolling"\nmass = 20.0'))
    problem = load_problem(path)
    assert len(problem.variables) == 6
    assert design_at(problem, variables_of(default_design().machine)).base == Base("rolling", 20.0)


@pytest.mark.parametrize("base, field", [
    ('mobility = "fixed"\nmass = { lower = 2.0, upper = 50.0 }', "base.mass"),
    ('mobility = "rolling"\nmass = { lower = 50.0, upper = 2.0 }', "base.mass"),
    ('mobility = "rolling"\nmass = { lower = -1.0, upper = 2.0 }', "base.mass"),
    ('mobility = "rolling"', "base.mass"),
    ('mobility = "wheels"\nmass = 3.0', "base.mobility"),
], ids=["bounds-on-a-fixed-frame", "inverted", "negative", "missing", "unknown-mobility"])
def test_bad_frame_in_a_problem_names_the_field(tmp_path, base, field):
    from analytic.design import DesignError
    from analytic.design_space import load_problem

    path = tmp_path / "bad.toml"
    path.write_text(_problem_text(base))
    with pytest.raises(DesignError) as error:
        load_problem(path)
    assert error.value.field == field


# --------------------------------------------------------------------------- #
# The ground's push, and a frame too light to stay down
# --------------------------------------------------------------------------- #

@pytest.mark.parametrize("mass", [None, 5.0], ids=["fixed", "rolling-5kg"])
def test_ground_force_is_the_weight_plus_the_second_derivative_of_the_vertical_mass_moment(mass):
    from analytic.geometry import part_positions

    design = default_design() if mass is None else _rolling(mass)
    shot = simulate(design)
    p = params(design)
    m = design.machine
    heights = np.array([part_positions(*q, m.arm_long, m.arm_short, m.arm_cg, m.counterweight_link,
                                       m.sling_length)[1::2] for q in shot.history.q])   # (n, 5) ys
    moment = p.mA * heights[:, 2] + p.mW * heights[:, 3] + p.mP * heights[:, 4]
    swing = np.flatnonzero(shot.history.stage == 2)[2:-3]          # regular samples, away from the stage change
    step = shot.history.t[1] - shot.history.t[0]
    second = (moment[swing + 1] - 2.0 * moment[swing] + moment[swing - 1]) / step**2
    weight = (p.mA + p.mW + p.mP + (p.Mf if p.rolling else 0.0)) * p.g
    from analytic import eom
    model = np.array([eom.ground_force(*q, *qd, *stages.accelerations(states.SWING, np.concatenate([q, qd]), p), p)
                      for q, qd in zip(shot.history.q[swing], shot.history.qdot[swing], strict=True)])
    # The second difference errs by (step^2 / 12) moment'''' ~ 1e-3 of the largest push here.
    assert np.max(np.abs(model - (weight + second))) < 2e-3 * np.max(np.abs(model))


def test_a_frame_that_would_jump_is_flagged_and_a_heavier_one_is_not():
    light, heavy = simulate(_rolling(1.0)), simulate(_rolling(5.0))
    assert light.min_ground_force < 0.0 < heavy.min_ground_force
    assert len(light.warnings) == 1 and "the frame would jump" in light.warnings[0]
    assert heavy.warnings == ()
    assert light.to_json()["warnings"] == list(light.warnings)


@pytest.mark.parametrize("base, field", [
    ({"mobility": "rolling", "mass": -1.0}, "base.mass"),
    ({"mobility": "rolling", "mass": 0.0}, "base.mass"),
    ({"mobility": "rolling", "mass": "heavy"}, "base.mass"),
    ({"mobility": "rolling", "mass": float("inf")}, "base.mass"),
    ({"mobility": "rolling"}, "base.mass"),
    ({"mobility": "wheels", "mass": 3.0}, "base.mobility"),
], ids=["negative", "zero", "text", "infinite", "missing", "unknown-mobility"])
@pytest.mark.parametrize("command", ["analytic", "engine_model"])
def test_a_bad_frame_in_a_design_file_is_exit_2_naming_the_field(tmp_path, capsys, base, field, command):
    import importlib

    import tomli_w

    from analytic.design_file import design_to_dict

    layout = design_to_dict(default_design())
    layout["base"] = base
    path = tmp_path / "bad.toml"
    path.write_text(tomli_w.dumps(layout))   # TOML writes inf as inf
    main = importlib.import_module(f"{command}.cli").main
    assert main(["simulate", str(path), "--json"]) == 2
    assert field in capsys.readouterr().err
