"""The optimisation problem: the paper's Table II in the default file, x -> design, constraints at rest."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
import tomli_w

from analytic.design import DesignError
from analytic.optimise import cli
from analytic.optimise.constraints import (CONSTRAINT_NAMES, axle_distance, constraint_values,
                                           feasible, footprint, rest_points)
from analytic.design_space import (VARIABLE_NAMES, default_problem, design_at, from_unit,
                                       problem_from_dict, to_unit, variables_of)
from analytic.optimise.report import format_constraints, format_tables, ratios
from support import NOT_NUMBERS, problem_dict, table3_beam


def test_default_bounds_are_table_ii():
    # Reference values: Corie, Park & Standring, Table II (cm and deg).
    table_ii = {"arm_short": (1.0, 30.0), "counterweight_link": (16.0, 45.0), "clearance": (16.0, 45.0),
                "sling_length": (1.0, 61.0), "starting_angle": (10.0, 80.0), "release_angle": (-80.0, 80.0)}
    problem = default_problem()
    for variable in problem.variables:
        scale = math.degrees(1.0) if variable.name.endswith("angle") else 100.0
        assert (variable.lower * scale, variable.upper * scale) == pytest.approx(table_ii[variable.name])
    # Section II.A: footprint and height at most 61 cm (2 ft); section III: 6.5 kg, 45.6 g.
    assert (problem.max_footprint, problem.max_height) == (0.61, 0.61)
    assert (problem.counterweight_mass, problem.projectile.mass) == (6.5, 0.0456)


def test_counterweight_sphere_matches_the_table3_file(table3):
    # paper_table3.toml: a cast-iron sphere of 6.5 kg has I = 0.009345 kg m^2 (4 significant digits).
    assert default_problem().counterweight_inertia == pytest.approx(
        table3.machine.counterweight_inertia, rel=5e-4)


def test_arm_beam_is_the_table3_files(table3):
    # Both files assume the same pine beam; the problem's arm must rebuild the default design's.
    problem = default_problem()
    m = table3.machine
    assert problem.arm == table3_beam()
    assert problem.arm.properties(m.arm_long, m.arm_short) == (m.arm_mass, m.arm_cg, m.arm_inertia)


def test_table3_design_round_trips(table3):
    # Table III's h = 59.42 cm = 24.05 + 19.37 + a clearance of 16.00 cm, theta0 = asin(59.42 / 70.06).
    values = variables_of(table3.machine)
    assert values[2] == pytest.approx(0.16, abs=1e-12)
    assert values[4] == pytest.approx(math.asin(0.5942 / 0.7006), abs=1e-12)
    rebuilt = design_at(default_problem(), values).machine
    for name in ("pivot_height", "arm_long", "arm_short", "arm_mass", "arm_cg", "arm_inertia",
                 "counterweight_link", "sling_length", "release_angle", "release_rule"):
        assert getattr(rebuilt, name) == pytest.approx(getattr(table3.machine, name), abs=1e-12), name


def test_table3_ratios_are_the_published_table_iv(table3):
    # Table IV: L_Al : L_As 2.91, L_S : L_Al 0.87, m_W : m_P 143 (rounded as published). The
    # report's Table IV prints the published column, and the Table III design's own ratios
    # beside it to the same digits.
    table_iv = (2.91, 0.87, 143.0)
    values = variables_of(table3.machine)
    long_short, sling_long, masses = ratios(default_problem(), values)
    assert (round(long_short, 2), round(sling_long, 2), round(masses)) == table_iv
    text = format_tables(default_problem(), [("Table III", values, 35.9)])
    rows = {line[:24].strip(): line[24:].split() for line in text.splitlines()}
    for label, published in zip(("L_Al : L_As", "L_S : L_Al", "m_W : m_P"), table_iv, strict=True):
        _, printed_published, printed_ours = rows[label]
        assert float(printed_published) == published and printed_ours == printed_published, rows[label]


def test_unit_coordinates_round_trip():
    problem = default_problem()
    values = variables_of(design_at(problem, from_unit(problem, np.full(6, 0.3))).machine)
    assert to_unit(problem, values) == pytest.approx(np.full(6, 0.3), abs=1e-12)
    assert from_unit(problem, np.zeros(6)) == pytest.approx(problem.lower)


def test_table3_footprint_is_its_sling_and_its_height_its_pivot(table3):
    # The brief's observation, checked: from the long-arm tip (x = -La cos theta0) to the ball
    # lying a sling length ahead is 61 cm exactly, and nothing sticks out further: the short
    # tip is at Lb cos theta0 = 0.2405 * 0.5298 = 0.1274 m, the ball at 0.6100 - 0.3712 = 0.2388 m.
    points = rest_points(table3.machine)
    assert points["long_tip"][0] == pytest.approx(-math.sqrt(0.7006**2 - 0.5942**2), abs=1e-12)
    assert points["short_tip"][0] == pytest.approx(0.2405 * math.sqrt(0.7006**2 - 0.5942**2) / 0.7006)
    assert footprint(table3.machine) == pytest.approx(0.61, abs=1e-12)
    g = constraint_values(default_problem(), table3.machine)
    assert g[0] == pytest.approx(0.0, abs=1e-12)               # at the footprint limit
    assert g[3] == pytest.approx(0.61 - 0.5942, abs=1e-12)     # pivot 59.42 cm under 61 cm
    assert feasible(default_problem(), table3.machine)


def test_table3_counterweight_hangs_just_above_the_axle(table3):
    # Hand calculation: short tip at (0.2405 cos t0, 0.2405 sin t0) = (0.12741, 0.20398) m; the
    # weight hangs 0.1937 m below it, 0.01028 m above the axle's level, so the link's closest
    # approach is the distance to the weight's centre, hypot(0.12741, 0.01028) = 0.12782 m.
    sin0, cos0 = 0.5942 / 0.7006, math.sqrt(0.7006**2 - 0.5942**2) / 0.7006
    expected = math.hypot(0.2405 * cos0, 0.2405 * sin0 - 0.1937)
    assert axle_distance(table3.machine) == pytest.approx(expected, abs=1e-12)
    assert expected == pytest.approx(0.12782, abs=1e-5)


def test_axle_distance_is_the_offset_when_the_weight_hangs_below_the_axle():
    problem = default_problem()
    # Long link: the weight hangs below the axle's level, so only the horizontal offset counts.
    machine = design_at(problem, np.array([0.10, 0.40, 0.16, 0.30, math.radians(60.0), 0.0])).machine
    assert axle_distance(machine) == pytest.approx(0.10 * math.cos(math.radians(60.0)), abs=1e-12)
    # 5 cm offset < 5.996 cm weight radius + 0.635 cm axle radius: violated.
    assert constraint_values(problem, machine)[4] < 0.0


def test_axle_distance_has_a_continuous_slope_where_the_weight_crosses_the_axle_level():
    problem = default_problem()
    start = math.radians(40.0)
    crossing = 0.2 * math.sin(start)   # link at which the weight's centre is level with the axle

    def distance(link: float) -> float:
        return axle_distance(design_at(problem, np.array([0.2, link, 0.16, 0.3, start, 0.0])).machine)

    h = 1e-5
    left = (distance(crossing) - distance(crossing - h)) / h
    right = (distance(crossing + h) - distance(crossing)) / h
    assert left == pytest.approx(0.0, abs=1e-4) and right == pytest.approx(0.0, abs=1e-12)


def test_footprint_is_led_by_the_short_arm_when_the_sling_is_short():
    problem = default_problem()
    theta0 = math.radians(30.0)
    machine = design_at(problem, np.array([0.30, 0.20, 0.20, 0.05, theta0, 0.0])).machine
    h = 0.70
    # La cos t0 = h / tan t0 behind; the short tip 0.30 cos t0 ahead; the sling's 5 cm stays behind it.
    assert footprint(machine) == pytest.approx(h / math.tan(theta0) + 0.30 * math.cos(theta0), abs=1e-12)
    assert CONSTRAINT_NAMES[2].startswith("footprint") and constraint_values(problem, machine)[2] < 0.0


def test_a_variable_can_be_fixed():
    data = problem_dict()
    data["variables"]["release_angle"] = {"value": 43.4}
    problem = problem_from_dict(data)
    assert list(problem.free) == [0, 1, 2, 3, 4]
    assert from_unit(problem, np.zeros(5))[5] == pytest.approx(math.radians(43.4))


@pytest.mark.parametrize("change, message", [
    (lambda d: d["variables"]["sling_length"].update(lower=0.7),
     "variables.sling_length = (0.7, 0.61): lower bound is above upper bound"),
    (lambda d: d["variables"]["starting_angle"].update(upper=95.0), "variables.starting_angle = "),
    (lambda d: d["variables"].update(arm_short={"lower": 0.01, "upper": 0.3, "step": 1}),
     "variables.arm_short.step = 1: unknown key"),
    (lambda d: d["variables"].update(arm_short={"value": 0.1, "lower": 0.01}),
     "variables.arm_short.lower = 0.01: unknown key"),
    (lambda d: d["variables"]["clearance"].pop("upper"), "variables.clearance.upper: required value is missing"),
    (lambda d: d["variables"].pop("clearance"), "variables.clearance: required table is missing"),
    (lambda d: d["constraints"].pop("max_height"), "constraints.max_height: required value is missing"),
    (lambda d: d["constraints"].update(max_footprint=-1.0), "constraints.max_footprint = -1.0: must be positive"),
    (lambda d: d["constraints"].update(axle_radius=-0.01), "constraints.axle_radius = -0.01: must not be negative"),
    (lambda d: d["counterweight"].update(density=0), "counterweight.density = 0.0: must be positive"),
    (lambda d: d["projectile"].update(colour="white"), "projectile.colour = 'white': unknown key"),
    (lambda d: d["projectile"].update(mass=0), "projectile.mass = 0.0: must be positive"),
    (lambda d: d["projectile"].pop("drag"), "projectile.drag: required value is missing"),
    (lambda d: d["environment"].update(gravity=-9.81), "environment.gravity = -9.81: must be positive"),
    (lambda d: d["arm_beam"].update(depth=0.0), "arm_beam.depth = 0.0: must be positive"),
    (lambda d: d["arm_beam"].pop("density"), "arm_beam.density: required value is missing"),
    (lambda d: d.pop("arm_beam"), "arm_beam: required table is missing"),
    (lambda d: d.update(release="velocity"), "release = 'velocity': must be a table"),
    (lambda d: d["release"].update(rule="late"), "release.rule = 'late': must be one of velocity, sling"),
    (lambda d: d.update(name=7), "name = 7: must be text"),
    (lambda d: d.update(solver="pso"), "solver = 'pso': unknown key"),
], ids=["bounds-crossed", "angle-out-of-range", "unknown-key", "value-and-bound", "missing-bound",
        "missing-variable", "missing-limit", "negative-limit", "negative-axle", "zero-density",
        "unknown-projectile-key", "zero-projectile-mass", "missing-drag", "negative-gravity", "zero-beam-depth",
        "missing-beam-density", "missing-table", "release-not-a-table", "bad-rule", "name-not-text",
        "unknown-table"])
def test_invalid_problems_name_field_and_reason(change, message):
    data = problem_dict()
    change(data)
    with pytest.raises(DesignError, match=f"^{re.escape(message)}"):
        problem_from_dict(data)


def _problem_numbers() -> list[tuple[str, ...]]:
    """Path to every number in the default problem file."""
    data = problem_dict()
    paths = [("variables", key, bound) for key in VARIABLE_NAMES for bound in ("lower", "upper")]
    paths += [(table, key) for table in ("constraints", "counterweight", "arm_beam", "projectile", "environment")
              for key, value in data[table].items() if not isinstance(value, str)]
    return paths


@pytest.mark.parametrize("kind", NOT_NUMBERS)
@pytest.mark.parametrize("path", _problem_numbers(), ids=".".join)
def test_a_problem_number_of_the_wrong_kind_is_refused_as_in_design_files(path, kind):
    value, reason = NOT_NUMBERS[kind]
    data = problem_dict()
    table = data
    for key in path[:-1]:
        table = table[key]
    table[path[-1]] = value
    with pytest.raises(DesignError) as caught:
        problem_from_dict(data)
    assert str(caught.value) == f"{'.'.join(path)} = {value!r}: {caught.value.reason}"
    assert reason in caught.value.reason


@pytest.mark.parametrize("table", ["variables", "constraints", "counterweight", "arm_beam", "projectile",
                                   "environment", "release"])
def test_a_value_where_a_problem_table_belongs_is_refused(table):
    data = problem_dict()
    data[table] = 3
    with pytest.raises(DesignError, match=rf"^{table} = 3: must be a table$"):
        problem_from_dict(data)


@pytest.mark.parametrize("content, message", [
    ("[variables\n", "file = "),
    ('name = "paper"\n', "variables: required table is missing"),
], ids=["not-toml", "empty"])
def test_the_command_refuses_a_bad_problem_file_with_exit_2(tmp_path, capsys, content, message):
    path = tmp_path / "bad.toml"
    path.write_text(content)
    assert cli.main([str(path), "--out", str(tmp_path / "out"), "--quiet"]) == cli.EXIT_INVALID
    err = capsys.readouterr().err
    assert err.startswith("invalid problem: ") and message in err


@pytest.mark.parametrize("kind", ["text", "list", "date", "huge-integer"])
def test_the_command_refuses_a_bad_problem_value_with_exit_2(tmp_path, capsys, kind):
    value, reason = NOT_NUMBERS[kind]
    data = problem_dict()
    data["variables"]["release_angle"]["lower"] = value
    path = tmp_path / "bad.toml"
    path.write_text(tomli_w.dumps(data))
    assert cli.main([str(path), "--out", str(tmp_path / "out"), "--quiet"]) == cli.EXIT_INVALID
    err = capsys.readouterr().err
    assert "invalid problem: variables.release_angle.lower = " in err and reason in err


def test_each_variable_lands_where_its_name_says():
    # Every vector is in VARIABLE_NAMES order: six distinct values, each found again in the
    # machine by what it means (clearance and starting angle through the paper's geometry).
    problem = default_problem()
    assert [variable.name for variable in problem.variables] == list(VARIABLE_NAMES)
    values = np.array([0.11, 0.22, 0.33, 0.44, math.radians(55.0), math.radians(-12.0)])
    m = design_at(problem, values).machine
    meaning = {"arm_short": m.arm_short, "counterweight_link": m.counterweight_link,
               "clearance": m.pivot_height - m.arm_short - m.counterweight_link, "sling_length": m.sling_length,
               "starting_angle": math.asin(m.pivot_height / m.arm_long), "release_angle": m.release_angle}
    assert [meaning[name] for name in VARIABLE_NAMES] == pytest.approx(values, abs=1e-12)
    assert variables_of(m) == pytest.approx(values, abs=1e-12)


def test_a_problems_losses_are_every_candidates():
    # [losses] in a problem file is read as in a design file and carried by every design.
    data = problem_dict()
    data["losses"] = {"axle_friction": 0.15, "axle_radius": "6.4 mm", "base_friction": 0.3}
    problem = problem_from_dict(data)
    assert (problem.losses.axle_friction, problem.losses.axle_radius, problem.losses.base_friction) == (
        0.15, pytest.approx(0.0064), 0.3)
    values = np.array([(v.lower + v.upper) / 2 for v in problem.variables])
    try:
        design = design_at(problem, values)
    except DesignError as error:   # non-ideal losses are refused until both models have friction
        assert error.field == "losses"
    else:
        assert design.losses == problem.losses
    assert default_problem().losses.ideal and design_at(default_problem(), values).losses.ideal


@pytest.mark.parametrize(("entry", "field"), [({"axle_friction": -0.1, "axle_radius": 0.01}, "losses.axle_friction"),
                                              ({"hinge_friction": 0.2}, "losses.hinge_friction"),
                                              ({"base_friction": "lots"}, "losses.base_friction"),
                                              ({"bearing": 0.1}, "losses.bearing")])
def test_a_problems_bad_losses_name_the_field(entry, field):
    data = problem_dict()
    data["losses"] = entry
    with pytest.raises(DesignError) as raised:
        problem_from_dict(data)
    assert raised.value.field == field


def test_the_report_tables_are_shown_in_the_chosen_units(table3):
    # 1 in = 2.54 cm and 1 ft = 0.3048 m by definition; the paper's tables are in cm and m.
    values = variables_of(table3.machine)
    rows = {}
    for system in ("metric", "imperial"):
        text = format_tables(default_problem(), [("Table III", values, 35.9)], system)
        rows[system] = {line[:24].strip(): line[24:].split() for line in text.splitlines()}
        assert f"lengths {'cm' if system == 'metric' else 'in'}, angles deg" in text
    assert float(rows["metric"]["L_S   sling"][0]) == pytest.approx(100 * table3.machine.sling_length, abs=5e-3)
    assert float(rows["imperial"]["L_S   sling"][0]) == pytest.approx(table3.machine.sling_length / 0.0254, abs=5e-3)
    assert rows["imperial"]["range (ft)"] == [f"{35.9 / 0.3048:.2f}"] and rows["metric"]["range (m)"] == ["35.90"]
    assert rows["imperial"]["theta release angle"] == rows["metric"]["theta release angle"]   # deg either way
    constraints = format_constraints(default_problem(), [("Table III", values, 35.9)], "imperial")
    assert constraints.startswith("Constraints at rest (in;")


def test_the_report_states_a_floating_arms_guide_and_track_friction(table3):
    import dataclasses

    from analytic.design import Losses
    from analytic.design_space import with_kind

    problem = dataclasses.replace(with_kind(default_problem(), "floating-arm"),
                                  losses=Losses(guide_friction=0.2, track_friction=0.1, track_static_friction=0.3))
    from support import floating

    text = format_tables(problem, [("Table III", variables_of(floating(table3).machine), 35.9)])
    line = next(line for line in text.splitlines() if line.startswith("with losses"))
    assert line.endswith("(Coulomb coefficients x pin radii), guide 0.2, track 0.1; static: track 0.3")
