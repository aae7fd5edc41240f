"""The design contract: validation names field, value and reason; TOML in and out; the paper's forms."""

from __future__ import annotations

import math

import pytest

from analytic.design import BeamArm, DesignError, initial_angles, paper_geometry, sling_arm_angle
from analytic.design_file import (default_design, design_from_dict, design_to_dict, dumps_design,
                                  load_design, save_design)

from conftest import with_machine, with_projectile


def _raises(field: str, reason_part: str):
    return pytest.raises(DesignError, match=rf"^{field} = .*{reason_part}")


def test_default_design_is_the_papers_table3():
    # Reference values: Corie, Park & Standring, Table III (cm -> m) and section III.
    m = default_design().machine
    assert (m.arm_long, m.arm_short, m.sling_length, m.counterweight_link, m.pivot_height) == \
        (0.7006, 0.2405, 0.6100, 0.1937, 0.5942)
    assert math.degrees(m.release_angle) == pytest.approx(43.4, abs=1e-12)
    assert m.counterweight_mass == 6.5 and default_design().projectile.mass == 0.0456


def test_table3_is_consistent_with_the_papers_parametrisation():
    # Table III: h = 59.42 cm = L_As + L_W + clearance at its 16 cm lower bound (Table II).
    h, long_arm = paper_geometry(0.2405, 0.1937, 0.16, math.asin(0.5942 / 0.7006))
    assert h == pytest.approx(0.5942, abs=1e-12) and long_arm == pytest.approx(0.7006, abs=1e-12)


def test_beam_arm_matches_a_uniform_rod():
    # A uniform rod of length L about its centre: I = m L^2 / 12 (+ m d^2 / 12 for its depth).
    mass, cg, inertia = BeamArm(width=0.02, depth=0.04, density=500.0).properties(0.8, 0.2)
    assert mass == pytest.approx(500.0 * 0.02 * 0.04 * 1.0)
    assert cg == pytest.approx(0.3)
    assert inertia == pytest.approx(mass * (1.0 + 0.04**2) / 12.0)


def test_start_state_puts_tip_and_projectile_on_the_base(table3):
    m = table3.machine
    theta, phi, psi = initial_angles(m)
    assert m.arm_long * math.cos(theta) == pytest.approx(-m.pivot_height, abs=1e-15)
    assert theta + phi == 0.0                          # counterweight plumb
    assert -math.sin(theta + psi) == pytest.approx(1.0)  # sling points forward along the base


def test_sling_arm_angle_sign_convention():
    # Sling straight in line with the arm: 0; sling a quarter turn clockwise ahead: +90 deg.
    assert sling_arm_angle((0.0, 1.0), (0.0, 1.0)) == 0.0
    assert sling_arm_angle((0.0, 1.0), (1.0, 0.0)) == pytest.approx(math.pi / 2)
    assert sling_arm_angle((0.0, 1.0), (-1.0, 0.0)) == pytest.approx(-math.pi / 2)


@pytest.mark.parametrize("field, value, reason", [
    ("pivot_height", 0.0, "must be positive"),
    ("arm_mass", -1.0, "must be positive"),
    ("sling_length", float("nan"), "must be finite"),
    ("counterweight_inertia", -0.1, "must not be negative"),
    ("arm_long", 0.5, "cannot reach the base"),
    ("counterweight_link", 0.4, "would strike the base"),
    ("arm_cg", 0.9, "must lie on the arm"),
    ("release_rule", "pin", "must be one of"),
], ids=lambda v: str(v))
def test_invalid_machine_names_field_value_and_reason(table3, field, value, reason):
    with _raises(field, reason):
        with_machine(table3, **{field: value})


def test_release_angle_range_depends_on_the_rule(table3):
    with _raises("release_angle", "between -90 and 90"):
        with_machine(table3, release_angle=math.radians(95.0))
    with_machine(table3, release_angle=math.radians(95.0), release_rule="sling")  # allowed


@pytest.mark.parametrize("changes, field", [
    (dict(mass=0.0), "mass"),
    (dict(diameter=-0.01), "diameter"),
    (dict(drag="lead-shot"), "drag"),
    (dict(drag="constant"), "drag_coefficient"),
    (dict(drag_coefficient=0.4), "drag_coefficient"),  # given with golf-ball drag: not silently ignored
])
def test_invalid_projectile(table3, changes, field):
    with pytest.raises(DesignError, match=rf"^{field} = "):
        with_projectile(table3, **changes)


def test_toml_round_trip(tmp_path, table3):
    path = tmp_path / "d.toml"
    save_design(table3, path)
    again = load_design(path)
    assert again.machine == table3.machine
    assert again.projectile == table3.projectile and again.environment == table3.environment


def test_toml_accepts_the_papers_variables_and_a_beam():
    data = design_to_dict(default_design())
    machine = data["machine"]
    for key in ("pivot_height", "arm_long", "arm_mass", "arm_cg", "arm_inertia"):
        del machine[key]
    machine.update(clearance=0.16, starting_angle=60.0,
                   arm_beam={"width": 0.02, "depth": 0.04, "density": 500.0})
    m = design_from_dict(data).machine
    assert m.pivot_height == pytest.approx(0.2405 + 0.1937 + 0.16)
    assert m.arm_long == pytest.approx(m.pivot_height / math.sin(math.radians(60.0)))
    assert m.arm_mass == pytest.approx(500.0 * 0.02 * 0.04 * (m.arm_long + m.arm_short))


@pytest.mark.parametrize("mutate, field", [
    (lambda d: d["machine"].pop("sling_length"), "machine.sling_length"),
    (lambda d: d["machine"].update(sling=0.5), "machine.sling"),
    (lambda d: d["projectile"].update(mass="heavy"), "mass"),
    (lambda d: d["machine"].update(clearance=0.2), "machine.pivot_height"),
    (lambda d: d.pop("projectile"), r"\[projectile\]"),
], ids=["missing", "unknown", "not-a-number", "both-forms", "missing-table"])
def test_bad_files_name_the_field(mutate, field):
    data = design_to_dict(default_design())
    mutate(data)
    with pytest.raises(DesignError, match=rf"^{field}"):
        design_from_dict(data)


def test_environment_defaults_apply_when_omitted():
    data = design_to_dict(default_design())
    del data["environment"]
    env = design_from_dict(data).environment
    assert (env.gravity, env.air_density, env.air_viscosity, env.wind_speed) == (9.81, 1.225, 1.81e-5, 0.0)


def test_unreadable_file(tmp_path):
    with pytest.raises(DesignError, match="^file = .*cannot be read"):
        load_design(tmp_path / "missing.toml")
    (tmp_path / "bad.toml").write_text("[machine\n")
    with pytest.raises(DesignError, match="^file = .*not valid TOML"):
        load_design(tmp_path / "bad.toml")


def test_dumps_is_loadable_toml(table3):
    assert "release_angle = 43.4" in dumps_design(table3)
