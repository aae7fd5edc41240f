"""Will it break: the arm's stress and safety factor, the projectile's limit, in files, shots, tools and the optimiser."""

from __future__ import annotations

import csv
import dataclasses
import json

import pytest
import tomli_w

from analytic import cli as analytic_cli
from analytic import fast
from analytic.chart import chart, save_chart, vary
from analytic.design import ArmSection, BeamArm, DesignError
from analytic.design_file import default_design, design_from_dict, load_design, save_design
from analytic.design_space import default_problem, design_at, problem_from_dict
from analytic.optimise.evaluate import Evaluator
from analytic.optimise.search import OUTCOME_FEASIBILITY, Settings, maximise
from analytic.result import JSON_KEYS, Shot, Status
from analytic.data.strength import MATERIALS, PROJECTILE_KINDS, STANDARD_GRAVITY, bending_stress
from engine_model import cli as engine_cli
from support import problem_dict, table3_file


def rated_file(**beam) -> dict:
    """The paper's Table III design file with its beam of pine (or ``beam``'s strength) and an egg."""
    data = table3_file()
    data["machine"]["arm_beam"].update(beam or {"material": "pine"})
    data["projectile"]["kind"] = "egg"
    return data


# --------------------------------------------------------------------------- #
# The formula, by hand
# --------------------------------------------------------------------------- #

def test_the_bending_stress_of_a_beam_is_the_hand_formula():
    # By hand: M = 100 N m on a 20 mm x 50 mm section (depth 50 mm in the swing plane):
    # sigma = 6 M / (w d^2) = 600 / (0.02 x 0.0025) = 600 / 5e-5 = 12.0e6 Pa.
    assert bending_stress(100.0, 0.02, 0.05) == pytest.approx(12.0e6, rel=1e-15)
    # The same section turned on its side bends about its weak axis: 600 / (0.05 x 0.0004) = 30.0e6 Pa.
    assert bending_stress(100.0, 0.05, 0.02) == pytest.approx(30.0e6, rel=1e-15)


def test_a_shot_reports_the_stress_and_the_safety_factor_of_its_peak_moment():
    machine = dataclasses.replace(default_design().machine, arm_section=ArmSection(0.02, 0.05, material="oak"))
    design = dataclasses.replace(default_design(), machine=machine)
    shot = Shot(design, Status.OK, "thrown", peak_arm_bending_moment=100.0)
    # By hand, as above: 12.0e6 Pa; oak's modulus of rupture 99 MPa (Wood Handbook, northern red oak)
    # over it: 99 / 12 = 8.25.
    assert shot.peak_arm_stress == pytest.approx(12.0e6, rel=1e-15)
    assert shot.arm_safety_factor == pytest.approx(8.25, rel=1e-15)
    no_strength = dataclasses.replace(machine, arm_section=ArmSection(0.02, 0.05))
    shot = Shot(dataclasses.replace(design, machine=no_strength), Status.OK, "thrown", peak_arm_bending_moment=100.0)
    assert (shot.peak_arm_stress, shot.arm_safety_factor) == (pytest.approx(12.0e6, rel=1e-15), None)
    given = dataclasses.replace(machine, arm_section=ArmSection(0.02, 0.05, strength=6.0e6))
    shot = Shot(dataclasses.replace(design, machine=given), Status.OK, "thrown", peak_arm_bending_moment=100.0)
    assert shot.arm_safety_factor == pytest.approx(0.5, rel=1e-15)   # 6 / 12: it breaks


def test_a_design_without_a_section_or_a_limit_reports_none():
    shot = fast.simulate_fast(default_design(), loads=True)
    assert shot.peak_arm_bending_moment > 0.0
    assert (shot.peak_arm_stress, shot.arm_safety_factor, shot.projectile_survives) == (None, None, None)


def test_the_projectile_survives_up_to_its_limit_and_not_past_it():
    design = design_from_dict(rated_file())
    limit = 30.0 * STANDARD_GRAVITY   # the egg's documented 30 g: 294.1995 m/s^2
    assert design.projectile.acceleration_limit == pytest.approx(294.1995, rel=1e-15)
    survives = [Shot(design, Status.OK, "thrown", peak_projectile_acceleration=a).projectile_survives
                for a in (limit * 0.999, limit, limit * 1.001)]
    assert survives == [True, True, False]


# --------------------------------------------------------------------------- #
# Files: the material lookup, the round trip, bad input
# --------------------------------------------------------------------------- #

@pytest.mark.parametrize("material, strength", [
    # USDA Wood Handbook FPL-GTR-282, Table 5-3a, modulus of rupture at 12 % moisture (kPa / 1000 = MPa).
    ("pine", 59e6), ("oak", 99e6), ("ash", 103e6), ("douglas-fir", 85e6),
    # 6061-T6 typical yield 40 ksi = 276 MPa (Aluminum Association); S235 235 MPa (EN 10025-2).
    ("aluminium-6061", 276e6), ("steel-s235", 235e6),
])
def test_a_material_is_looked_up_by_name(material, strength):
    design = design_from_dict(rated_file(material=material))
    assert design.machine.arm_section == ArmSection(0.019, 0.038, material=material)
    assert design.machine.arm_section.bending_strength == strength
    assert MATERIALS[material].source   # every value says where it comes from


def test_every_projectile_kind_says_its_basis():
    assert set(PROJECTILE_KINDS) == {"golf-ball", "pumpkin", "water-balloon", "egg", "softball"}
    assert all(kind.basis and kind.max_acceleration_g > 0.0 for kind in PROJECTILE_KINDS.values())


def test_a_strength_and_a_limit_with_units_are_read_in_si():
    data = rated_file(strength="8.5 ksi")
    data["projectile"].pop("kind")
    data["projectile"]["max_acceleration"] = 250
    design = design_from_dict(data)
    # 1 ksi = 6.894757293168361 MPa (pint's psi: 1 lbf / in^2); 250 g x 9.80665 m/s^2.
    assert design.machine.arm_section.bending_strength == pytest.approx(8.5 * 6.894757293168361e6, rel=1e-12)
    assert design.projectile.max_acceleration == pytest.approx(2451.6625, rel=1e-15)


@pytest.mark.parametrize("change", [
    lambda d: d["machine"]["arm_beam"].update(material="oak"),
    lambda d: (d["projectile"].pop("kind"), d["projectile"].update(max_acceleration=123.4)),
    lambda d: (d["machine"]["arm_beam"].pop("material"), d["machine"]["arm_beam"].update(strength=4.2e7)),
], ids=["material", "max-acceleration", "strength"])
def test_a_design_with_a_section_and_a_limit_reads_back_equal(change, tmp_path):
    data = rated_file()
    change(data)
    design = design_from_dict(data)
    save_design(design, tmp_path / "saved.toml")
    assert load_design(tmp_path / "saved.toml") == design


def test_a_section_alone_sits_beside_the_arms_own_numbers():
    direct = design_from_dict(table3_file())   # no strength: the design keeps no section, as before
    assert direct.machine.arm_section is None
    data = {"machine": {k: v for k, v in dataclasses.asdict(direct.machine).items()
                        if v is not None and k not in ("arm_section", "release_rule", "kind")},
            "projectile": table3_file()["projectile"]}
    data["machine"]["release_angle"] = 43.4
    data["machine"]["arm_beam"] = {"width": 0.019, "depth": 0.038, "material": "ash"}
    design = design_from_dict(data)
    assert design.machine.arm_mass == direct.machine.arm_mass
    assert design.machine.arm_section == ArmSection(0.019, 0.038, material="ash")


@pytest.mark.parametrize("table, values, field, shown", [
    ("arm_beam", {"material": "balsa"}, "machine.arm_beam.material", "'balsa'"),
    ("arm_beam", {"material": "pine", "strength": 4.0e7}, "machine.arm_beam.strength", "40000000.0"),
    ("arm_beam", {"strength": -4.0e7}, "machine.arm_beam.strength", "-40000000.0"),
    ("arm_beam", {"strength": "40 N"}, "machine.arm_beam.strength", "'40 N'"),
    ("projectile", {"max_acceleration": 0}, "projectile.max_acceleration", "0.0"),
    ("projectile", {"max_acceleration": -5}, "projectile.max_acceleration", "-5.0"),
    ("projectile", {"kind": "melon"}, "projectile.kind", "'melon'"),
    ("projectile", {"kind": "egg", "max_acceleration": 40}, "projectile.max_acceleration", "'40 g'"),
], ids=["unknown-material", "material-and-strength", "negative-strength", "strength-not-a-stress",
        "zero-acceleration", "negative-acceleration", "unknown-kind", "kind-and-acceleration"])
def test_bad_input_is_refused_naming_the_field_and_the_value(table, values, field, shown, tmp_path, capsys):
    data = table3_file()
    (data["machine"]["arm_beam"] if table == "arm_beam" else data["projectile"]).update(values)
    with pytest.raises(DesignError) as caught:
        design_from_dict(data)
    assert str(caught.value).startswith(f"{field} = {shown}: ")
    path = tmp_path / "bad.toml"
    path.write_text(tomli_w.dumps(data))
    for main in (analytic_cli.main, engine_cli.main):
        assert main(["simulate", str(path), "--json"]) == 2
        error = capsys.readouterr().err
        assert f"{field} = {shown}" in error and "Traceback" not in error


# --------------------------------------------------------------------------- #
# simulate --json, both models
# --------------------------------------------------------------------------- #

@pytest.mark.parametrize("main", [analytic_cli.main, engine_cli.main], ids=["analytic", "engine"])
def test_simulate_json_of_both_models_says_what_breaks(main, tmp_path, capsys):
    path = tmp_path / "rated.toml"
    path.write_text(tomli_w.dumps(rated_file()))
    assert main(["simulate", str(path), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert set(JSON_KEYS) <= set(data)
    # Each model's stress from its own peak moment, by the hand formula on the 19 x 38 mm pine beam.
    stress = 6.0 * data["peak_arm_bending_moment"] / (0.019 * 0.038 ** 2)
    assert data["peak_arm_stress"] == pytest.approx(stress, rel=1e-12)
    assert data["arm_safety_factor"] == pytest.approx(59e6 / stress, rel=1e-12)
    assert data["projectile_survives"] is (data["peak_projectile_acceleration"] <= 30.0 * STANDARD_GRAVITY)
    assert main(["simulate", "--json"]) == 0   # the default design: no strength, no limit
    data = json.loads(capsys.readouterr().out)
    assert (data["peak_arm_stress"], data["arm_safety_factor"], data["projectile_survives"]) == (None, None, None)


def test_the_text_report_says_what_breaks(tmp_path, capsys):
    path = tmp_path / "rated.toml"
    path.write_text(tomli_w.dumps(rated_file()))
    assert analytic_cli.main(["simulate", str(path)]) == 0
    text = capsys.readouterr().out
    assert "peak arm stress" in text and "arm safety factor" in text
    assert "projectile margin" in text and "it breaks: limit 30 g" in text


def test_the_summary_rows_carry_each_margins_verdict_to_the_page():
    # The page colours a row by its verdict (``analytic.summary.Row.verdict``): the paper's pine arm holds
    # (the text report's 5.46 above), its egg (30 g) at 78.8 g breaks.
    from analytic.reference import simulate
    from analytic.summary import summary_rows
    from support import page_client

    shot = simulate(design_from_dict(rated_file()), histories=False)
    rows = {row.key: row for row in summary_rows(shot)}
    assert rows["arm_safety_factor"].verdict is True and rows["projectile_margin"].verdict is False
    assert rows["projectile_margin"].value == pytest.approx(
        30.0 * STANDARD_GRAVITY / shot.peak_projectile_acceleration, rel=1e-12)
    assert rows["peak_arm_stress"].value == pytest.approx(shot.peak_arm_stress / 1e6, rel=1e-12)
    page = page_client().post("/api/shot", json={"design": rated_file()}).json()
    shown = {row["key"]: row for row in page["summary"]}
    assert (shown["arm_safety_factor"]["verdict"], shown["projectile_margin"]["verdict"]) == (True, False)
    assert shown["peak_arm_stress"]["kind"] == "stress (MPa)"
    units = page_client().get("/api/meta").json()["units"]["stress (MPa)"]
    # 1 MPa = 145.0377 psi (1 psi = 6894.757 Pa, NIST SP 811)
    assert units["imperial"]["label"] == "psi" and units["imperial"]["factor"] == pytest.approx(145.0377, rel=1e-6)


# --------------------------------------------------------------------------- #
# Charts and sweeps
# --------------------------------------------------------------------------- #

def test_a_chart_has_the_margins_of_a_design_that_has_them(tmp_path):
    design = design_from_dict(rated_file())
    result = chart(design, [vary("machine.counterweight_mass", 4.0, 9.0, 6)])
    csv_path, png_path = save_chart(result, tmp_path)
    with csv_path.open() as handle:
        rows = list(csv.DictReader(handle))
    section = design.machine.arm_section
    for row in rows:
        stress = bending_stress(float(row["peak_arm_bending_moment [N m]"]), section.width, section.depth)
        assert float(row["arm_safety_factor"]) == pytest.approx(59e6 / stress, rel=1e-12)
        assert float(row["projectile_margin"]) == pytest.approx(
            30.0 * STANDARD_GRAVITY / float(row["peak_projectile_acceleration [m/s^2]"]), rel=1e-12)
    plain = chart(default_design(), [vary("machine.counterweight_mass", 4.0, 9.0, 3)])
    save_chart(plain, tmp_path / "plain")
    assert "arm_safety_factor" not in (tmp_path / "plain" / "chart.csv").read_text()


def test_a_sweep_stores_what_breaks_row_by_row():
    from analytic.sweep.evaluate import chunk_table
    from analytic.sweep.sweep_file import sweep_from_dict

    sweep = sweep_from_dict({"design": "paper_table3.toml",
                             "grid": {"machine.counterweight_mass": {"from": 5.0, "to": 8.0, "steps": 2},
                                      "machine.arm_beam.depth": {"from": 0.03, "to": 0.05, "steps": 2}}})
    assert "arm_safety_factor" not in chunk_table(sweep, 0, threads=1)   # no strength: no columns, no loads
    rated = dataclasses.replace(sweep, base=dataclasses.replace(sweep.base, data=rated_file()))
    table = chunk_table(rated, 0, threads=1)
    for i, depth in enumerate(table["machine.arm_beam.depth"]):
        design = design_from_dict(rated_file(material="pine", depth=float(depth)))
        design = dataclasses.replace(design, machine=dataclasses.replace(
            design.machine, counterweight_mass=float(table["machine.counterweight_mass"][i])))
        shot = fast.simulate_fast(design, loads=True)
        assert table["peak_arm_stress"][i] == pytest.approx(shot.peak_arm_stress, rel=1e-9)
        assert table["arm_safety_factor"][i] == pytest.approx(shot.arm_safety_factor, rel=1e-9)
        assert table["projectile_survives"][i] == float(shot.projectile_survives)


# --------------------------------------------------------------------------- #
# The optimiser
# --------------------------------------------------------------------------- #

def test_a_problem_file_reads_the_breaking_constraints():
    data = problem_dict()
    data["arm_beam"]["material"] = "pine"
    data["constraints"].update(min_arm_safety_factor=2.0, max_projectile_acceleration="100 g0")
    problem = problem_from_dict(data)
    assert problem.min_arm_safety_factor == 2.0
    assert dict(problem.load_limits) == {"projectile_acceleration": pytest.approx(980.665, rel=1e-15)}
    assert problem.outcome_constraints == ("peak projectile acceleration <= 980.665", "arm safety factor >= 2")
    assert design_at(problem, problem.lower).machine.arm_section == ArmSection(0.019, 0.038, material="pine")


@pytest.mark.parametrize("change, field", [
    (lambda d: d["constraints"].update(min_arm_safety_factor=2.0), "constraints.min_arm_safety_factor"),
    (lambda d: (d["arm_beam"].update(material="pine"), d["constraints"].update(min_arm_safety_factor=-1.0)),
     "constraints.min_arm_safety_factor"),
    (lambda d: (d["constraints"].update(max_projectile_acceleration=500.0),
                d.update(loads={"max_projectile_acceleration": 400.0})), "constraints.max_projectile_acceleration"),
    (lambda d: d["arm_beam"].update(material="balsa"), "arm_beam.material"),
], ids=["no-strength", "negative", "given-twice", "unknown-material"])
def test_bad_breaking_constraints_name_the_field(change, field):
    data = problem_dict()
    change(data)
    with pytest.raises(DesignError) as caught:
        problem_from_dict(data)
    assert caught.value.field == field


def test_the_optimum_keeps_the_arms_least_safety_factor():
    problem = dataclasses.replace(default_problem(), arm=BeamArm(0.019, 0.038, 450.0, material="pine"))
    free = maximise(problem, Evaluator(problem), Settings())
    free_shot = fast.simulate_fast(design_at(problem, free.values), loads=True)
    least = 1.25 * free_shot.arm_safety_factor   # the longest throw's arm is weaker than this
    limited_problem = dataclasses.replace(problem, min_arm_safety_factor=least)
    limited = maximise(limited_problem, Evaluator(limited_problem), Settings())
    shot = fast.simulate_fast(design_at(limited_problem, limited.values), loads=True)
    assert shot.arm_safety_factor >= least * (1.0 - OUTCOME_FEASIBILITY)
    assert limited.score < free.score
    assert f"arm safety factor >= {least:g}" in limited.first_order.active_constraints
