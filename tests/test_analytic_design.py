"""The design contract: validation names table.field, value and reason; TOML in and out; the paper's forms."""

from __future__ import annotations

import datetime
import math
import pickle
import re

import pytest
import tomli_w

from analytic.design import BeamArm, DesignError, MissingValueError, initial_angles, paper_geometry
from analytic.design_file import (default_design, design_from_dict, design_to_dict, dumps_design, load_design, save_design)

from support import NOT_NUMBERS, table3_file, with_environment, with_machine, with_projectile


def _raises(field: str, reason_part: str):
    return pytest.raises(DesignError, match=rf"^{re.escape(field)} = .*{reason_part}")


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


@pytest.mark.parametrize("field, value, reason", [
    ("pivot_height", 0.0, "must be positive"),
    ("arm_mass", -1.0, "must be positive"),
    ("sling_length", float("nan"), "must be finite"),
    ("counterweight_inertia", -0.1, "must not be negative"),
    ("sling_mass", -0.01, "must not be negative"),
    ("sling_mass", float("inf"), "must be finite"),
    ("pouch_mass", float("nan"), "must be finite"),
    ("pouch_mass", -2.0, "must not be negative"),
    ("arm_long", 0.5, "cannot reach the base"),
    ("counterweight_link", 0.4, "would strike the base"),
    ("arm_cg", 0.9, "must lie on the arm"),
    ("release_rule", "pin", "must be one of"),
    ("kind", "hinge", "must be one of hinged, fixed, floating-arm"),
], ids=lambda v: str(v))
def test_invalid_machine_names_field_value_and_reason(table3, field, value, reason):
    with _raises(f"machine.{field}", reason):
        with_machine(table3, **{field: value})


def test_release_angle_range_depends_on_the_rule(table3):
    with _raises("machine.release_angle", "between -90 and 90"):
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
    with pytest.raises(DesignError, match=rf"^projectile\.{field}[ :]"):
        with_projectile(table3, **changes)


def test_toml_round_trip(tmp_path, table3):
    path = tmp_path / "d.toml"
    save_design(table3, path)
    again = load_design(path)
    assert again.machine == table3.machine
    assert again.projectile == table3.projectile and again.environment == table3.environment


def test_a_hinged_machine_is_the_default_and_is_written_as_before(table3):
    assert table3.machine.kind == "hinged"
    assert "kind" not in design_to_dict(table3)["machine"]   # files read as they were written


@pytest.mark.parametrize("name", ["hinge_friction", "hinge_static_friction"])
def test_a_fixed_machine_refuses_hinge_friction(name):
    data = table3_file()
    data["machine"]["kind"] = "fixed"
    del data["machine"]["counterweight_link"]
    data["losses"] = {"hinge_radius": 0.01, name: 0.2}
    with pytest.raises(DesignError, match=rf"^losses\.{name} = 0\.2: a fixed machine has no hinge"):
        design_from_dict(data)


def test_a_fixed_machine_takes_a_frictionless_hinge_radius_and_axle_friction():
    data = table3_file()
    data["machine"]["kind"] = "fixed"
    del data["machine"]["counterweight_link"]
    data["losses"] = {"hinge_radius": 0.01, "axle_friction": 0.2, "axle_radius": 0.01}
    assert design_from_dict(data).losses.axle_friction == 0.2


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


@pytest.mark.parametrize("mutate, message", [
    (lambda d: d["machine"].pop("sling_length"), "machine.sling_length: required value is missing"),
    (lambda d: d["machine"].update(sling=0.5), "machine.sling = 0.5: unknown key"),
    (lambda d: d["projectile"].update(mass="heavy"), "projectile.mass = 'heavy': must be a number"),
    (lambda d: d["machine"].update(clearance=0.2), "machine.pivot_height = 0.5942: give either"),
    (lambda d: d.pop("projectile"), "projectile: required table is missing"),
], ids=["missing", "unknown", "not-a-number", "both-forms", "missing-table"])
def test_bad_files_name_the_field(mutate, message):
    data = design_to_dict(default_design())
    mutate(data)
    with pytest.raises(DesignError, match=f"^{re.escape(message)}"):
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


# --------------------------------------------------------------------------- #
# Every value of every table is checked before any arithmetic uses it
# --------------------------------------------------------------------------- #

#: Values of the wrong kind for a text choice (release_rule, drag).
NOT_CHOICES = {"number": 1.0, "list": ["velocity"], "table": {"rule": "velocity"}, "bool": False,
               "date": datetime.date(1979, 5, 27), "wrong-case": "Velocity"}


def _forms() -> dict[str, dict]:
    """The default design in each file form: direct, the paper's variables, an arm cut from a beam."""
    direct = design_to_dict(default_design())
    paper = design_to_dict(default_design())
    for key in ("pivot_height", "arm_long"):
        del paper["machine"][key]
    paper["machine"].update(clearance=0.16, starting_angle=58.0)
    beam = design_to_dict(default_design())
    for key in ("arm_mass", "arm_cg", "arm_inertia"):
        del beam["machine"][key]
    beam["machine"]["arm_beam"] = table3_file()["machine"]["arm_beam"]
    return {"direct": direct, "paper": paper, "beam": beam}


def _number_fields() -> list[tuple[str, tuple[str, ...]]]:
    """(form, path to the value) of every number a design file can hold, in one of its forms."""
    forms = _forms()
    fields = [("direct", ("machine", key)) for key, value in forms["direct"]["machine"].items()
              if not isinstance(value, str)]
    fields += [("paper", ("machine", key)) for key in ("clearance", "starting_angle")]
    fields += [("beam", ("machine", "arm_beam", key)) for key in ("width", "depth", "density")]
    fields += [("direct", ("projectile", key)) for key in ("mass", "diameter")]
    fields += [("direct", ("environment", key)) for key in forms["direct"]["environment"]]
    return fields


def _with(form: str, path: tuple[str, ...], value) -> dict:
    data = _forms()[form]
    table = data
    for key in path[:-1]:
        table = table[key]
    table[path[-1]] = value
    return data


@pytest.mark.parametrize("kind", NOT_NUMBERS)
@pytest.mark.parametrize("form, path", _number_fields(), ids=lambda v: ".".join(v) if isinstance(v, tuple) else v)
def test_a_number_of_the_wrong_kind_is_refused_naming_table_field_and_value(form, path, kind):
    value, reason = NOT_NUMBERS[kind]
    with pytest.raises(DesignError) as caught:
        design_from_dict(_with(form, path, value))
    error = caught.value
    assert (error.field, error.value) == (".".join(path), value)
    assert str(error) == f"{'.'.join(path)} = {value!r}: {error.reason}" and reason in error.reason


def test_drag_coefficient_of_the_wrong_kind_is_refused():
    data = _forms()["direct"]
    data["projectile"].update(drag="constant", drag_coefficient="0.45")
    with pytest.raises(DesignError, match=r"^projectile\.drag_coefficient = '0\.45': must be a number$"):
        design_from_dict(data)


@pytest.mark.parametrize("kind", NOT_CHOICES)
@pytest.mark.parametrize("path", [("machine", "release_rule"), ("machine", "kind"), ("projectile", "drag")],
                         ids=".".join)
def test_a_choice_of_the_wrong_kind_is_refused(path, kind):
    value = NOT_CHOICES[kind]
    with pytest.raises(DesignError, match=rf"^{re.escape('.'.join(path))} = .*: must be one of "):
        design_from_dict(_with("direct", path, value))


@pytest.mark.parametrize("form, path", [
    ("direct", ("machine", key)) for key in ("pivot_height", "arm_long", "arm_short", "arm_mass", "arm_cg",
                                             "arm_inertia", "counterweight_mass", "counterweight_link",
                                             "counterweight_inertia", "sling_length", "release_angle")
] + [("paper", ("machine", key)) for key in ("clearance", "starting_angle", "arm_short", "counterweight_link")]
  + [("beam", ("machine", "arm_beam", key)) for key in ("width", "depth", "density")]
  + [("beam", ("machine", key)) for key in ("pivot_height", "arm_long", "arm_short")]
  + [("direct", ("projectile", key)) for key in ("mass", "diameter", "drag")],
    ids=lambda v: ".".join(v) if isinstance(v, tuple) else v)
def test_a_missing_value_is_named_without_a_value(form, path):
    data = _forms()[form]
    table = data
    for key in path[:-1]:
        table = table[key]
    del table[path[-1]]
    with pytest.raises(DesignError) as caught:
        design_from_dict(data)
    assert str(caught.value) == f"{'.'.join(path)}: required value is missing"
    assert (caught.value.field, caught.value.value) == (".".join(path), None)


@pytest.mark.parametrize("table", ["machine", "projectile"])
def test_a_missing_table_is_named(table):
    data = _forms()["direct"]
    del data[table]
    with pytest.raises(DesignError, match=rf"^{table}: required table is missing$"):
        design_from_dict(data)


@pytest.mark.parametrize("path, value", [
    (("machine",), 3), (("projectile",), "golf ball"), (("environment",), [9.81]),
    (("machine", "arm_beam"), 0.019),
], ids=lambda v: ".".join(v) if isinstance(v, tuple) else type(v).__name__)
def test_a_value_where_a_table_belongs_is_refused(path, value):
    data = _with("beam", path, value) if path[-1] == "arm_beam" else _with("direct", path, value)
    with pytest.raises(DesignError, match=rf"^{re.escape('.'.join(path))} = {re.escape(repr(value))}: "
                                          rf"must be a table$"):
        design_from_dict(data)


@pytest.mark.parametrize("form, path", [
    ("direct", ("colour",)), ("direct", ("machine", "wheels")), ("direct", ("projectile", "colour")),
    ("direct", ("environment", "humidity")), ("beam", ("machine", "arm_beam", "colour")),
], ids=lambda v: ".".join(v) if isinstance(v, tuple) else v)
def test_an_unknown_key_is_named_with_its_table(form, path):
    with pytest.raises(DesignError, match=rf"^{re.escape('.'.join(path))} = 1\.0: unknown key; expected one of"):
        design_from_dict(_with(form, path, 1.0))


@pytest.mark.parametrize("value", [3, ["paper"], {"text": "paper"}, True], ids=lambda v: type(v).__name__)
def test_a_name_that_is_not_text_is_refused(value):
    with pytest.raises(DesignError, match=rf"^name = {re.escape(repr(value))}: must be text$"):
        design_from_dict(_with("direct", ("name",), value))


@pytest.mark.parametrize("build, message", [
    (lambda d: with_machine(d, arm_short=-0.24), "machine.arm_short = -0.24: must be positive"),
    (lambda d: with_machine(d, release_angle="43.4 deg"), "machine.release_angle = '43.4 deg': must be a number"),
    (lambda d: with_machine(d, release_rule=None), "machine.release_rule = None: must be one of velocity, sling, ideal"),
    (lambda d: with_projectile(d, mass=0), "projectile.mass = 0: must be positive"),
    (lambda d: with_projectile(d, drag="constant"),
     'projectile.drag_coefficient: required with drag = "constant"'),
    (lambda d: with_environment(d, gravity=[9.81]), "environment.gravity = [9.81]: must be a number"),
    (lambda d: BeamArm(width=0.019, depth=0.0, density=450.0), "machine.arm_beam.depth = 0.0: must be positive"),
    (lambda d: paper_geometry(0.24, 0.19, 0.16, "58 deg"), "machine.starting_angle = '58 deg': must be a number"),
    (lambda d: paper_geometry(-0.24, 0.19, 0.16, 1.0), "machine.arm_short = -0.24: must be positive"),
], ids=["machine-negative", "machine-text-angle", "machine-no-rule", "projectile-zero-mass",
        "projectile-constant-drag-without-coefficient", "environment-list", "beam-zero-depth",
        "paper-text-angle", "paper-negative-short-arm"])
def test_the_contract_names_fields_with_their_table_when_built_directly(table3, build, message):
    with pytest.raises(DesignError) as caught:
        build(table3)
    assert str(caught.value) == message


def test_errors_keep_their_parts_through_pickling():
    # A process pool sends errors back pickled: field, value and reason must survive.
    for error in (DesignError("machine.arm_short", -0.24, "must be positive"),
                  MissingValueError("machine.sling_length")):
        again = pickle.loads(pickle.dumps(error))
        assert type(again) is type(error) and str(again) == str(error)
        assert (again.field, again.value, again.reason) == (error.field, error.value, error.reason)


def _run_analytic(path):
    from analytic.cli import main
    return main(["simulate", str(path)])


def _run_engine(path):
    from engine_model.cli import main
    return main(["simulate", str(path)])


def _run_crosscheck(path):
    from crosscheck.cli import main
    return main([str(path), "--no-progress"])


@pytest.mark.parametrize("kind", ["text", "list", "table", "bool", "date", "nan", "huge-integer"])
@pytest.mark.parametrize("form, key", [("direct", "release_angle"), ("paper", "starting_angle")])
@pytest.mark.parametrize("command", [_run_analytic, _run_engine, _run_crosscheck],
                         ids=["analytic", "engine_model", "crosscheck"])
def test_every_command_refuses_a_bad_angle_with_exit_2(tmp_path, capsys, command, form, key, kind):
    value, reason = NOT_NUMBERS[kind]
    path = tmp_path / "bad.toml"
    path.write_text(tomli_w.dumps(_with(form, ("machine", key), value)))
    assert command(path) == 2
    err = capsys.readouterr().err
    assert f"invalid design: machine.{key} = " in err and reason in err


def test_a_beam_arm_past_the_float_range_is_refused_by_name():
    """Found by the fuzz test: a starting angle of 2e-246 deg makes the paper's arm 1.5e247 m long,
    whose beam inertia overflowed with an OverflowError instead of a DesignError."""
    with pytest.raises(DesignError, match=r"machine\.arm_beam .*past the float range"):
        BeamArm(0.05, 0.1, 700.0).properties(1.5e247, 0.3)
    mass, cg, inertia = BeamArm(0.05, 0.1, 700.0).properties(1.0, 0.3)
    assert (mass, cg) == (700.0 * 0.05 * 0.1 * 1.3, 0.35)   # the beam's own formulas (docstring)
    assert inertia == pytest.approx(mass * (1.3**2 + 0.1**2) / 12.0, rel=1e-15)


# --------------------------------------------------------------------------- #
# The floating arm's guide and track friction
# --------------------------------------------------------------------------- #

SLIDE_FIELDS = ["guide_friction", "track_friction", "guide_static_friction", "track_static_friction"]


def _floating_file(losses: dict) -> dict:
    data = table3_file()
    data["machine"]["kind"] = "floating-arm"
    del data["machine"]["counterweight_link"]
    return {**data, "losses": losses}


def test_a_floating_arm_reads_guide_and_track_friction_and_writes_it_back():
    design = design_from_dict(_floating_file({"guide_friction": 0.2, "track_friction": 0.1,
                                              "track_static_friction": 0.3}))
    losses = design.losses
    assert (losses.guide_friction, losses.track_friction) == (0.2, 0.1)
    # A static coefficient not given is the kinetic one; a given one is kept.
    assert (losses.static("guide"), losses.static("track")) == (0.2, 0.3)
    assert not losses.ideal
    assert design_from_dict(design_to_dict(design)) == design


def test_guide_and_track_friction_are_ideal_by_default():
    losses = design_from_dict(_floating_file({})).losses
    assert (losses.guide_friction, losses.track_friction, losses.static("guide"), losses.static("track")) == \
        (0.0, 0.0, 0.0, 0.0) and losses.ideal


@pytest.mark.parametrize("kind", ["hinged", "fixed"])
@pytest.mark.parametrize("name", SLIDE_FIELDS)
def test_other_kinds_refuse_guide_and_track_friction(kind, name):
    data = table3_file()
    data["machine"]["kind"] = kind
    if kind == "fixed":
        del data["machine"]["counterweight_link"]
    data["losses"] = {name: 0.25}
    with _raises(f"losses.{name}", f"only a floating-arm machine has a guide and a track; a {kind} machine"):
        design_from_dict(data)
    data["losses"] = {name: 0.0}   # zero is the ideal slide every machine has
    assert design_from_dict(data).losses.ideal


@pytest.mark.parametrize("value, reason", [(-0.1, "must not be negative"), (math.nan, "must be finite"),
                                           (math.inf, "must be finite"), ("0.2", "must be a number")],
                         ids=["negative", "nan", "inf", "text"])
@pytest.mark.parametrize("name", SLIDE_FIELDS)
def test_bad_guide_and_track_coefficients_are_refused_naming_the_field(name, value, reason):
    with _raises(f"losses.{name}", reason):
        design_from_dict(_floating_file({name: value}))


@pytest.mark.parametrize("slide", ["guide", "track"])
def test_a_static_slide_coefficient_below_its_kinetic_one_is_refused(slide):
    with _raises(f"losses.{slide}_static_friction", f"is below the kinetic coefficient losses.{slide}_friction"):
        design_from_dict(_floating_file({f"{slide}_friction": 0.3, f"{slide}_static_friction": 0.2}))


def test_the_slides_coefficients_reach_the_models_parameters():
    from analytic.parameters import params

    p = params(design_from_dict(_floating_file({"guide_friction": 0.2, "track_friction": 0.1,
                                                "guide_static_friction": 0.4})))
    assert (p.mug, p.mut, p.mug_s, p.mut_s) == (0.2, 0.1, 0.4, 0.1)


@pytest.mark.parametrize("name", ["losses.guide_friction", "losses.track_static_friction"])
def test_the_slides_coefficients_are_fields_the_tools_vary(name):
    from analytic.fields import field

    design = design_from_dict(_floating_file({"track_friction": 0.1}))
    chosen = field(name)
    assert chosen.unit == "" and chosen.label == name
    assert chosen.get(design) == (0.0 if name == "losses.guide_friction" else 0.1)   # static: the kinetic one
    assert chosen.get(chosen.replace(design, 0.5)) == 0.5


def test_the_cli_refuses_track_friction_on_a_hinged_machine_with_exit_2(tmp_path, capsys):
    from analytic.cli import EXIT_INVALID, main

    data = table3_file()
    data["losses"] = {"track_friction": 0.2}
    path = tmp_path / "hinged.toml"
    path.write_bytes(tomli_w.dumps(data).encode())
    assert main(["simulate", str(path)]) == EXIT_INVALID
    err = capsys.readouterr().err
    assert "losses.track_friction = 0.2" in err and "only a floating-arm machine" in err


def test_sling_and_pouch_are_massless_by_default_and_left_out_of_files(table3):
    assert (table3.machine.sling_mass, table3.machine.pouch_mass) == (0.0, 0.0)
    written = design_to_dict(table3)["machine"]
    assert "sling_mass" not in written and "pouch_mass" not in written   # files read as they were written


def test_sling_and_pouch_masses_are_read_and_written_back(tmp_path):
    data = table3_file()
    data["machine"].update(sling_mass="2 lb", pouch_mass=0.031)
    design = design_from_dict(data)
    assert design.machine.sling_mass == pytest.approx(0.90718474, rel=1e-12)   # 1 lb = 0.45359237 kg exactly
    assert design.machine.pouch_mass == 0.031
    path = tmp_path / "d.toml"
    save_design(design, path)
    assert load_design(path).machine == design.machine


@pytest.mark.parametrize("name", ["sling_mass", "pouch_mass"])
def test_a_bad_sling_or_pouch_mass_in_a_file_is_named_as_written(name):
    data = table3_file()
    data["machine"][name] = "-3 lb"
    with pytest.raises(DesignError, match=rf'^machine\.{name} = "-3 lb" \(-1\.36078 kg\): must not be negative'):
        design_from_dict(data)


@pytest.mark.parametrize("name", ["machine.sling_mass", "pouch_mass"])
def test_sling_and_pouch_masses_are_fields_the_tools_vary(table3, name):
    from analytic.fields import field

    chosen = field(name)
    assert chosen.unit == "kg"
    assert chosen.get(table3) == 0.0
    assert chosen.get(chosen.replace(table3, 0.25)) == 0.25
    with pytest.raises(DesignError, match="must not be negative"):
        chosen.replace(table3, -0.25)
