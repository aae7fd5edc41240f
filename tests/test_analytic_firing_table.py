"""Firing tables: every entry shot here on the reference path lands within 1 mm, no crossing is missed,
bad input is refused before any shot, the files and the --json shape, and a calibrated table's band.

The synthetic calibration's shots are the reference path's own ranges at a known axle friction
plus seeded Gaussian noise of the stated uncertainty, so the only reference numbers are the true
parameter and the normal, binomial and chi-square laws.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.stats import binom, chi2
from support import DATA

from analytic import fast
from analytic.aim import AIM_TOLERANCE
from analytic.calibrate import calibrate, load_calibration
from analytic.calibrate.spec import with_fields
from analytic.cli import main
from analytic.design_file import load_design
from analytic.fields import field
from analytic.firing import firing_table
from analytic.firing.output import FILE_NAMES
from analytic.reference import simulate

PROTOTYPE_FILE = DATA / "designs" / "prototype-61.toml"
#: Settings of the independent scan that counts the crossings a table must find: five times aim's.
DENSE_POINTS = 801


def _landing(design, name, value, mass):
    """The reference path's range of ``design`` with the projectile's ``mass`` and ``name`` at ``value``."""
    design = field(name).replace(field("projectile.mass").replace(design, mass), value)
    shot = simulate(design, histories=False, loads=False)
    assert shot.ok, shot.message
    return shot.range


def _crossings(design, name, mass, target, bounds):
    """How often the fast path's range crosses ``target`` over a dense scan of ``bounds``."""
    base = field("projectile.mass").replace(design, mass)
    values = np.linspace(*bounds, DENSE_POINTS)
    shots = fast.shoot([field(name).replace(base, float(v)) for v in values], loads=False)
    miss = np.where(shots.ok, shots.range, np.nan) - target
    return int(np.sum(np.isfinite(miss[:-1]) & np.isfinite(miss[1:]) & (np.sign(miss[:-1]) != np.sign(miss[1:]))))


@pytest.fixture(scope="module")
def prototype():
    return load_design(PROTOTYPE_FILE)


def test_every_entry_lands_within_a_millimetre_and_no_crossing_is_missed(prototype):
    """The release pin against a target: a low and a high throw where the range curve rises and
    falls through it; 200 m is beyond the prototype's ~29 m (out of reach)."""
    name = "machine.release_angle"
    table = firing_table(prototype, name, [12.0, 22.0, 200.0], [0.040, 0.0456])
    assert [e.status for e in table.entries if e.target == 200.0] == ["out_of_reach"] * 2
    assert any(len(e.settings) == 2 for e in table.entries), "no two-solution entry"
    for e in table.entries:
        assert len(e.settings) == _crossings(prototype, name, e.projectile_mass, e.target, table.bounds)
        for value in e.settings:
            assert abs(_landing(prototype, name, value, e.projectile_mass) - e.target) <= AIM_TOLERANCE


def test_a_counterweight_table_lands_within_a_millimetre(prototype):
    name = "machine.counterweight_mass"
    table = firing_table(prototype, name, [20.0, 26.0])
    assert all(len(e.settings) == 1 for e in table.entries)
    for e in table.entries:
        assert abs(_landing(prototype, name, e.settings[0], e.projectile_mass) - e.target) <= AIM_TOLERANCE


@pytest.mark.parametrize("options, named, typed", [
    pytest.param(["--adjust", "machine.counterweight_mas"], "field", "machine.counterweight_mas", id="unknown-field"),
    pytest.param(["--targets", "30:20:3"], "--targets", "30:20:3", id="from-above-to"),
    pytest.param(["--targets", "20:30:0"], "--targets", "20:30:0", id="no-steps"),
    pytest.param(["--targets", "20:30:x"], "--targets", "20:30:x", id="steps-not-a-number"),
    pytest.param(["--targets", "-20:30:3"], "--targets", "-20:30:3", id="negative-target"),
    pytest.param(["--projectile-mass", "-0.05:0.05:3"], "--projectile-mass", "-0.05:0.05:3", id="negative-mass"),
    pytest.param(["--projectile-mass", "0.04:0.05:2", "--adjust", "projectile.mass"], "--projectile-mass", "given",
                 id="mass-adjusted-and-given"),
    pytest.param(["--targets", "20 kg:30:2"], "--targets", "20 kg:30:2", id="wrong-unit"),
])
def test_bad_input_is_refused_naming_the_option_and_value(tmp_path, capsys, options, named, typed):
    argv = {"--targets": "20:30:2", "--adjust": "machine.counterweight_mass"}
    rest = []
    for key, value in zip(options[::2], options[1::2], strict=True):
        if key in argv:
            argv[key] = value
        else:
            rest += [key, value]
    out = tmp_path / "out"
    code = main(["firing-table", str(PROTOTYPE_FILE), *[t for kv in argv.items() for t in kv], *rest,
                 "--out", str(out), "--quiet"])
    error = capsys.readouterr().err
    assert code == 2
    assert f"{named} = {typed!r}" in error, error
    assert not out.exists() or not any(out.iterdir())


def test_files_json_shape_units_and_no_overwrite(tmp_path, capsys):
    out = tmp_path / "table"
    argv = ["firing-table", str(PROTOTYPE_FILE), "--targets", "40:80:3", "--adjust", "release_angle",
            "--projectile-mass", "0.1:0.1:1", "--units", "imperial", "--out", str(out), "--json", "--quiet"]
    assert main(argv) == 0
    data = json.loads(capsys.readouterr().out)
    assert set(data) == {"rows", "units", "calibration"} and data["calibration"] is None
    rows = data["rows"]
    assert [set(r) for r in rows] == [{"target", "projectile_mass", "field", "settings", "status", "band"}] * 3
    # Typed in ft and lb (--units imperial), given in SI: 1 ft = 0.3048 m, 1 lb = 0.45359237 kg (exact).
    assert [r["target"] for r in rows] == pytest.approx([40 * 0.3048, 60 * 0.3048, 80 * 0.3048])
    assert [r["projectile_mass"] for r in rows] == pytest.approx([0.1 * 0.45359237] * 3)
    assert all(r["field"] == "machine.release_angle" and r["band"] is None for r in rows)
    assert data["units"]["settings"] == "rad"
    # The JSON's radians are the CSV's degrees, and each lands on its target.
    import csv

    with (out / FILE_NAMES["csv"]).open() as handle:
        degrees = [float(row["setting [deg]"]) for row in csv.DictReader(handle) if row["setting [deg]"]]
    assert [v for r in rows for v in r["settings"]] == pytest.approx(np.radians(degrees), rel=1e-12)
    design = load_design(PROTOTYPE_FILE)
    for r in rows:
        assert r["status"] == ("ok" if r["settings"] else "out_of_reach")
        for angle in r["settings"]:
            landed = _landing(design, "machine.release_angle", math.degrees(angle), r["projectile_mass"])
            assert abs(landed - r["target"]) <= AIM_TOLERANCE
    assert (out / FILE_NAMES["png"]).read_bytes()[:4] == b"\x89PNG"
    before = {name: (out / name).read_bytes() for name in FILE_NAMES.values()}
    assert main(argv) == 2
    assert "--force" in capsys.readouterr().err
    assert {name: (out / name).read_bytes() for name in FILE_NAMES.values()} == before
    assert main([*argv, "--force"]) == 0


# --------------------------------------------------------------------------- #
# A calibrated table's band
# --------------------------------------------------------------------------- #

#: The axle's radius of the prototype's calibration file (analytic/data/calibration/prototype.toml).
AXLE_RADIUS = 0.0064
#: The true axle friction of the synthetic machine: a middling Coulomb coefficient.
TRUE_FRICTION = 0.3
#: Counterweights of the measured shots, kg; one sd of a range read off a tape, m.
MEASURED = (5.0, 6.0, 7.5, 9.0)
RANGE_SD = 0.3
#: Targets of the tables, m (inside the measured series' ranges and beyond them); each seed aims at one,
#: so that the trials are independent (two entries of one fit share its error).
TARGETS = (21.0, 24.0, 27.0)
COVERAGE_SEEDS = range(40)
#: The probabilities a normal error falls within one and within two sd.
ONE_SD, TWO_SD = math.erf(1.0 / math.sqrt(2.0)), math.erf(2.0 / math.sqrt(2.0))


def _true_design(prototype, counterweight):
    return with_fields(prototype, {"machine.counterweight_mass": counterweight, "losses.axle_radius": AXLE_RADIUS,
                                   "losses.axle_friction": TRUE_FRICTION})


def _true_range(prototype, counterweight):
    shot = simulate(_true_design(prototype, counterweight), histories=False, loads=False)
    assert shot.ok, shot.message
    return shot.range


def _series(folder, prototype, seed, truth):
    rng = np.random.default_rng(seed)
    lines = ['fit = ["losses.axle_friction"]', f"design = {json.dumps(str(PROTOTYPE_FILE))}",
             "[given]", f'"losses.axle_radius" = {AXLE_RADIUS}']
    for mass, true in zip(MEASURED, truth, strict=True):
        lines += ["[[shot]]", f"range = {true + RANGE_SD * rng.standard_normal()!r}",
                  f"range_uncertainty = {RANGE_SD}", f'"machine.counterweight_mass" = {mass}']
    path = folder / f"series{seed}.toml"
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.slow
def test_a_calibrated_tables_band_covers_held_out_shots_at_its_stated_rate(tmp_path, prototype):
    """Each seed fits a noisy series, makes a one-target counterweight table from the fit, and
    shoots the true machine at the table's setting with a fresh shot's noise. If the band is right,
    z = (held-out - predicted) / range_sd is standard normal: within one sd with probability 68.3 %
    and within two with 95.4 %, so over the independent trials each count must fall in its binomial's
    central 99.8 %, and the squared z's must sum inside chi-square's central 99.8 % (which also fails
    bands too wide: twice too wide, the sum's expectation is a quarter of its count). Forty trials
    tell: the same seeds fail with the fit's spread alone (no shot scatter), with half the band
    and with twice it."""
    truth = [_true_range(prototype, m) for m in MEASURED]
    rng = np.random.default_rng(12345)
    z = []
    for seed in COVERAGE_SEEDS:
        result = calibrate(load_calibration(_series(tmp_path, prototype, seed, truth)))
        target = TARGETS[seed % len(TARGETS)]
        table = firing_table(prototype, "machine.counterweight_mass", [target], calibration=result)
        (entry,) = table.entries
        (setting,) = entry.settings
        assert table.fitted.shots == len(MEASURED)
        held_out = _true_range(prototype, setting) + RANGE_SD * rng.standard_normal()
        (predicted,), (sd,) = entry.predicted, entry.range_sd
        assert abs(predicted - target) < 1e-3   # the band is centred where the table aimed
        assert sd > RANGE_SD                   # a shot's scatter and the fit's both
        z.append((held_out - predicted) / sd)
    z = np.array(z)
    for sigmas, rate in ((1.0, ONE_SD), (2.0, TWO_SD)):
        low, high = binom.ppf([0.001, 0.999], len(z), rate)
        assert low <= np.sum(np.abs(z) <= sigmas) <= high, (sigmas, z)
    low, high = chi2.ppf([0.001, 0.999], len(z))
    assert low < np.sum(z * z) < high, z


def test_a_calibrated_table_refuses_a_fitted_field_and_says_its_shots(tmp_path, capsys, prototype):
    truth = [_true_range(prototype, m) for m in MEASURED]
    shots = _series(tmp_path, prototype, 0, truth)
    out = tmp_path / "out"
    code = main(["firing-table", str(PROTOTYPE_FILE), "--targets", "24:24:1", "--adjust", "losses.axle_friction",
                 "--calibration", str(shots), "--out", str(out), "--quiet"])
    assert code == 2 and "--adjust = 'losses.axle_friction'" in capsys.readouterr().err
    code = main(["firing-table", str(PROTOTYPE_FILE), "--targets", "22:26:2", "--adjust", "counterweight_mass",
                 "--calibration", str(shots), "--out", str(out), "--json", "--quiet"])
    assert code == 0
    data = json.loads(capsys.readouterr().out)
    assert data["calibration"]["shots"] == len(MEASURED)
    for row in data["rows"]:
        (one_low, one_high), (two_low, two_high) = row["band"]
        assert two_low < one_low < row["target"] < one_high < two_high
        assert two_high - two_low == pytest.approx(2 * (one_high - one_low))
    import csv

    with (out / FILE_NAMES["csv"]).open() as handle:
        assert {row["calibration_shots"] for row in csv.DictReader(handle)} == {str(len(MEASURED))}
