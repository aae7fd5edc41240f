"""Values with units in design and problem files (pint at the edge), and imperial output.

Reference conversions are the definitions: 1 ft = 0.3048 m, 1 in = 0.0254 m,
1 lb = 0.45359237 kg (the international yard and pound, 1959), 1 lbf =
0.45359237 kg x 9.80665 m/s^2 (standard gravity).
"""

from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
import tomli_w

from analytic import cli
from analytic.design import DesignError
from analytic.design_file import design_from_dict, design_to_dict, load_design, save_design
from analytic.design_space import problem_from_dict
from analytic.units import FIELD_KINDS, LENGTH, display, parse
from test_analytic_optimise_problem import problem_dict

FOOT, INCH, POUND, POUND_FORCE = 0.3048, 0.0254, 0.45359237, 0.45359237 * 9.80665
#: A value converted to another unit and back: pint's factor for a compound unit (lb/ft^3: a
#: pound and three feet) is a product of up to four defined factors, each rounding once, both
#: ways: at most ~9 units in the last place (measured: 4, for the air density).
ROUND_TRIP_REL = 2e-15


def _data(table3):
    return design_to_dict(table3)


@pytest.mark.parametrize("table, key, text, expected", [
    ("machine", "sling_length", "61 cm", 0.61),
    ("machine", "sling_length", "2 ft", 2 * FOOT),
    ("machine", "arm_short", "9.5 in", 9.5 * INCH),
    ("machine", "counterweight_mass", "14 lb", 14 * POUND),
    ("machine", "release_angle", "43.4 deg", math.radians(43.4)),
    ("machine", "release_angle", "0.76 rad", 0.76),
    ("machine", "counterweight_inertia", "93 kg cm^2", 93e-4),
    ("machine", "sling_mass", "2 lb", 2 * POUND),
    ("machine", "pouch_mass", "30 g", 0.03),
    ("projectile", "mass", "45.6 g", 0.0456),
    ("projectile", "diameter", "42.67 mm", 0.04267),
    ("environment", "air_density", "1.2 kg/m^3", 1.2),
    ("environment", "gravity", "1 g0", 9.80665),
    ("environment", "wind_speed", "-10 ft/s", -10 * FOOT),
    ("environment", "air_viscosity", "1.81e-5 Pa s", 1.81e-5),
], ids=lambda v: str(v))
def test_a_value_with_units_is_read_in_si(table3, table, key, text, expected):
    data = _data(table3)
    data[table][key] = text
    design = design_from_dict(data)
    assert getattr(getattr(design, table), key) == pytest.approx(expected, rel=1e-14)


def test_every_numeric_design_field_accepts_units_and_round_trips(table3, tmp_path):
    """Write every value with its unit, in the file's own units and in feet and pounds; read them back."""
    import dataclasses as dc

    from analytic.design import Base
    rolling = dc.replace(table3, base=Base("rolling", 20.0, trough_height=0.1),
                         environment=dc.replace(table3.environment, target_height=3.5),   # (0, the default, is left out)
                         machine=dc.replace(table3.machine, sling_mass=0.07, pouch_mass=0.02))
    for units in ({}, {"length": "ft", "mass": "lb", "speed": "ft / s", "acceleration": "ft / s ** 2",
                       "density": "lb / ft ** 3", "moment of inertia": "lb * ft ** 2", "angle": "rad"}):
        path = tmp_path / "units.toml"
        save_design(rolling, path, units)
        data = tomllib.loads(path.read_text())
        texts = [value for table in data.values() if isinstance(table, dict) for value in table.values()]
        numeric = [f.name for part in (rolling.machine, rolling.projectile, rolling.environment, rolling.base)
                   for f in dc.fields(part) if isinstance(getattr(part, f.name), float)]
        assert all(key in FIELD_KINDS for key in numeric)
        numeric.remove("drag_factor")   # 1.0, the default: left out of the file (design_to_dict)
        assert sum(isinstance(t, str) and " " in t for t in texts) == len(numeric)
        back = load_design(path)
        if not units:   # the file's own units: every value exactly
            assert back == rolling
        else:           # converted and back: each value to within the conversions' rounding
            for part in ("machine", "projectile", "environment", "base"):
                for f in dc.fields(getattr(rolling, part)):
                    a, b = getattr(getattr(rolling, part), f.name), getattr(getattr(back, part), f.name)
                    if isinstance(a, float):
                        assert b == pytest.approx(a, rel=ROUND_TRIP_REL, abs=1e-300), (part, f.name)
                    else:
                        assert a == b


@pytest.mark.parametrize("key, text, reason", [
    ("sling_length", "3 kg", "wrong kind of unit"),
    ("counterweight_mass", "2 ft", "wrong kind of unit"),
    ("release_angle", "3 m", "wrong kind of unit"),
    ("release_angle", "43.4", "must be a number"),
    ("sling_length", "61 furlongz", "unknown unit 'furlongz'"),
    ("arm_inertia", "0.02 kg m", "wrong kind of unit"),
    ("sling_length", "61 cm cm", "wrong kind of unit"),
    ("sling_length", "", "must be a number"),
    ("sling_length", "m", "there is no number"),
    ("sling_length", "1e999 m", "must be finite"),
], ids=lambda v: str(v))
def test_a_wrong_unit_names_the_field_the_value_and_the_expected_kind(table3, key, text, reason):
    data = _data(table3)
    data["machine"][key] = text
    with pytest.raises(DesignError) as caught:
        design_from_dict(data)
    error = caught.value
    assert (error.field, error.value) == (f"machine.{key}", text)
    assert reason in error.reason
    if "must be a number" not in reason or text:
        kind = FIELD_KINDS[key].name
        assert kind in str(error) or error.reason == "must be a number"


@pytest.mark.parametrize("text", ["3 kg", "61 furlongz"])
@pytest.mark.parametrize("command", ["simulate", "chart", "aim"])
def test_every_command_refuses_a_wrong_unit_with_exit_2(table3, tmp_path, capsys, text, command):
    data = _data(table3)
    data["machine"]["sling_length"] = text
    path = tmp_path / "bad.toml"
    path.write_text(tomli_w.dumps(data))
    argv = {"simulate": ["simulate", str(path)],
            "chart": ["chart", str(path), "--vary", "counterweight_mass=5:7:3", "--out", str(tmp_path / "c")],
            "aim": ["aim", str(path), "--target", "30", "--adjust", "release_angle"]}[command]
    assert cli.main(argv) == 2
    err = capsys.readouterr().err
    assert f"machine.sling_length = {text!r}" in err and "length" in err
    assert not (tmp_path / "c").exists()


def test_a_problem_file_reads_units_with_the_same_readers(tmp_path):
    data = problem_dict()
    data["variables"]["sling_length"] = {"lower": "1 cm", "upper": "2 ft"}
    data["variables"]["release_angle"] = {"lower": "-1.2 rad", "upper": "80 deg"}
    data["counterweight"]["mass"] = "14.33 lb"
    data["constraints"]["max_footprint"] = "2 ft"
    problem = problem_from_dict(data)
    sling = problem.variables[3]
    assert (sling.lower, sling.upper) == pytest.approx((0.01, 2 * FOOT), rel=1e-15)
    assert (problem.variables[5].lower, problem.variables[5].upper) == pytest.approx((-1.2, math.radians(80)))
    assert problem.counterweight_mass == pytest.approx(14.33 * POUND)
    data["variables"]["clearance"] = {"lower": "0.16 kg", "upper": 0.45}
    with pytest.raises(DesignError, match=r"^variables\.clearance\.lower = '0\.16 kg': has the wrong kind"):
        problem_from_dict(data)


def test_imperial_output_is_in_feet_pounds_and_json_stays_si(table3, tmp_path, capsys):
    path = tmp_path / "d.toml"
    save_design(table3, path)
    assert cli.main(["simulate", str(path), "--json"]) == 0
    shot = json.loads(capsys.readouterr().out)
    assert cli.main(["simulate", str(path), "--units", "imperial"]) == 0
    text = capsys.readouterr().out
    line = next(row for row in text.splitlines() if "range (from pivot)" in row)
    assert f"{shot['range'] / FOOT:.3f}" in line and line.rstrip().endswith("ft")
    line = next(row for row in text.splitlines() if "peak axle load" in row)
    assert f"{shot['peak_axle_load'] / POUND_FORCE:.3f}" in line and "lbf" in line
    line = next(row for row in text.splitlines() if "release speed" in row)
    assert f"{shot['release_speed'] / FOOT:.4f}" in line and "ft/s" in line
    # --units changes the table: the JSON's numbers stay SI, and it gains a block saying so.
    assert cli.main(["simulate", str(path), "--json", "--units", "imperial"]) == 0
    imperial = json.loads(capsys.readouterr().out)
    assert imperial.pop("units")["json"].startswith("SI") and imperial == shot


def test_display_converts_only_what_the_system_names():
    assert display(1.0, "m", "imperial") == pytest.approx((1 / FOOT, "ft"))
    assert display(1.0, "kg", "imperial") == pytest.approx((1 / POUND, "lb"))
    assert display(2.0, "s", "imperial") == (2.0, "s")
    assert display(3.0, "m", "metric") == (3.0, "m")
    assert parse("target", "100 ft", LENGTH) == pytest.approx(100 * FOOT)


def test_a_bare_number_keeps_its_meaning(table3):
    data = _data(table3)
    assert design_from_dict(data) == table3


@pytest.mark.slow   # three Python processes and a copy of pint
def test_units_still_read_after_another_environment_that_cached_pint_is_deleted(tmp_path):
    # Found on 2026-11-25: with pint's shared per-user cache (``cache_folder=":auto:"``) every
    # checkout on the machine refused "2 ft" once the checkout that first filled the cache was
    # deleted (pint 0.25 keeps the definition files' path in its cache). Here another
    # environment (a copy of pint) fills the per-user cache and is deleted; this environment's
    # units must still read.
    import pint

    other = tmp_path / "other-environment"
    shutil.copytree(Path(pint.__file__).parent, other / "pint")
    env = {**os.environ, "XDG_CACHE_HOME": str(tmp_path / "user-cache")}
    fill = "import pint; print(pint.UnitRegistry(cache_folder=':auto:').Quantity('2 ft').to('m').magnitude)"
    for _ in range(2):   # built, then read from the cache
        subprocess.run([sys.executable, "-c", fill], env={**env, "PYTHONPATH": str(other)}, check=True,
                       capture_output=True)
    assert any((tmp_path / "user-cache" / "pint").iterdir())
    shutil.rmtree(other)
    read = "from analytic import units; print(units.parse('machine.sling_length', '2 ft', units.LENGTH))"
    done = subprocess.run([sys.executable, "-c", read], env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-500:]
    assert float(done.stdout) == pytest.approx(0.6096, rel=1e-15)   # 2 ft = 0.6096 m exactly (international foot)


#: Texts that threads read at once, each as a value of its field: with units of several kinds.
FIRST_TEXTS = (("machine.pivot_height", "5 ft"), ("losses.axle_radius", "0.5 in"), ("machine.arm_mass", "14 lb"),
               ("machine.release_angle", "43 deg"), ("environment.air_density", "1.2 kg/m^3"),
               ("machine.arm_long", "61 cm"))
READ_AT_ONCE = f"""
import json, sys, threading
sys.setswitchinterval(1e-6)   # threads trade the interpreter as often as it allows
from analytic.units import from_file
texts = {list(FIRST_TEXTS) * 2!r}
barrier, read, errors = threading.Barrier(len(texts)), {{}}, []
def first_read(field, text):
    barrier.wait()
    try:
        read[text] = from_file(field, text)
    except Exception as error:
        errors.append(f"{{type(error).__name__}}: {{error}}")
threads = [threading.Thread(target=first_read, args=pair) for pair in texts]
for thread in threads: thread.start()
for thread in threads: thread.join()
print(json.dumps({{"read": read, "errors": errors}}))
"""


@pytest.mark.parametrize("attempt", range(3))
def test_threads_that_first_read_units_at_once_all_read_them(attempt):
    # Found on 2026-11-29: the workbench's page asks for its presets and its fields at once, and
    # on a fresh server the two threads built two unit registries; a quantity of one was not a
    # quantity of the other, and "5 ft" was refused as "must be a number (in m)" (HTTP 400). Each
    # attempt is a fresh process, whose first reads are the race; before the fix every attempt
    # of six refused three to six of the twelve texts.
    done = subprocess.run([sys.executable, "-c", READ_AT_ONCE], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-500:]
    answer = json.loads(done.stdout)
    assert answer["errors"] == []
    # The definitions (module docstring); 43 deg and 61 cm are in the file's own units.
    assert answer["read"] == pytest.approx({"5 ft": 5 * FOOT, "0.5 in": 0.5 * INCH, "14 lb": 14 * POUND,
                                            "43 deg": 43.0, "1.2 kg/m^3": 1.2, "61 cm": 0.61}, rel=1e-15)
