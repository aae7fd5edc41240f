"""Calibration across a series of settings: shots that set design fields on one shared design,
``--predict`` with its delta-method band, the range-against-setting plot, fitted files written as
the user wrote the design, and the warnings for implausible or entangled fits.

Synthetic shots are the reference path's own ranges at a known axle friction plus seeded
Gaussian noise of the stated uncertainty, so the only reference numbers are the true
parameter and the normal and binomial laws.
"""

from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path

import pytest
from scipy.stats import binom, chi2
from support import DATA

from analytic.calibrate import calibrate, load_calibration
from analytic.calibrate.predict import parse_predict, predict_ranges
from analytic.calibrate.report import FITTED_FOLDER, PLOT_FILE
from analytic.cli import main
from analytic.design import DesignError
from analytic.design_file import load_design
from analytic.fields import field
from analytic.reference import simulate

PROTOTYPE_FILE = DATA / "designs" / "prototype-61.toml"
#: The axle's radius the prototype's calibration file assumes (analytic/data/calibration/prototype.toml).
AXLE_RADIUS = 0.0064
#: The true axle friction of the synthetic shots: a middling Coulomb coefficient (dry wood on
#: wood is 0.25-0.5, see analytic/plausibility.py).
TRUE_FRICTION = 0.3
#: Counterweights of the measured shots (kg), around the prototype's 6.5 kg; and the held-out
#: settings predicted: one inside the series, one beyond it.
MEASURED = (5.0, 6.0, 7.5, 9.0)
HELD_OUT = (6.75, 10.0)
#: One sd of a range read off a tape on a field, m.
RANGE_SD = 0.3
#: Seeds of the coverage check: one held-out prediction each (alternating the two settings), so
#: the trials are independent (two predictions of one fit share its error).
COVERAGE_SEEDS = range(16)
#: The probability a normal error falls within one sd.
ONE_SD = math.erf(1.0 / math.sqrt(2.0))


def true_range(counterweight: float) -> float:
    design = load_design(PROTOTYPE_FILE)
    from analytic.calibrate.spec import with_fields

    design = with_fields(design, {"machine.counterweight_mass": counterweight, "losses.axle_radius": AXLE_RADIUS,
                                  "losses.axle_friction": TRUE_FRICTION})
    shot = simulate(design, histories=False, loads=False)
    assert shot.ok
    return shot.range


def series_file(folder, seed: int | None, fit=("losses.axle_friction",), units="kg") -> str:
    """A calibration file of shots across the counterweight series on one shared design, ranges
    at the truth plus noise (none when ``seed`` is None); counterweights written in ``units``."""
    import numpy as np

    rng = np.random.default_rng(seed)
    lines = [f"fit = {json.dumps(list(fit))}", f"design = {json.dumps(str(PROTOTYPE_FILE))}",
             "[given]", f'"losses.axle_radius" = "{AXLE_RADIUS * 1000} mm"']
    for mass in MEASURED:
        noise = 0.0 if seed is None else RANGE_SD * rng.standard_normal()
        written = f"{mass} kg" if units == "kg" else f"{mass / 0.45359237:.6f} lb"
        lines += ["[[shot]]", f"range = {true_range(mass) + noise!r}", f"range_uncertainty = {RANGE_SD}",
                  f'"machine.counterweight_mass" = "{written}"']
    path = folder / f"series{seed}.toml"
    path.write_text("\n".join(lines) + "\n")
    tomllib.loads(path.read_text())
    return str(path)


def test_shots_set_design_fields_on_one_shared_design(tmp_path):
    spec = load_calibration(series_file(tmp_path, None, units="lb"))
    masses = [shot.design.machine.counterweight_mass for shot in spec.shots]
    assert masses == pytest.approx(MEASURED, rel=1e-6)   # written in lb to 6 decimals
    assert all(shot.design_file == str(PROTOTYPE_FILE) for shot in spec.shots)


@pytest.mark.parametrize("key, value, reason", [
    pytest.param('"machine.counterweight_mas"', '"5 kg"', "no such field", id="unknown-field"),
    pytest.param('"machine.counterweight_mass"', '"5 m"', "mass", id="wrong-unit"),
    pytest.param('"machine.counterweight_mass"', "-5", "positive", id="negative"),
    pytest.param('"losses.axle_friction"', "0.2", "fitted", id="sets-a-fitted-parameter"),
])
def test_a_bad_shot_setting_names_the_shot_and_the_field(tmp_path, key, value, reason):
    text = Path(series_file(tmp_path, None)).read_text()
    path = tmp_path / "bad.toml"
    path.write_text(text.replace('"machine.counterweight_mass" = "5.0 kg"', f"{key} = {value}", 1))
    with pytest.raises(DesignError) as error:
        load_calibration(path)
    assert str(error.value).startswith(f"shot[1].{key.strip(chr(34))}") and reason in str(error.value)


def test_noise_free_series_predicts_held_out_ranges_exactly(tmp_path):
    """Without noise the fit is the truth, so predictions are the true ranges (to the fit's
    tolerance, 1e-8 relative in the parameter: far under 1 mm of range)."""
    result = calibrate(load_calibration(series_file(tmp_path, None)))
    for p in predict_ranges(result, field("machine.counterweight_mass"), HELD_OUT):
        assert p.range == pytest.approx(true_range(p.value), abs=1e-3)
        assert 0.0 < p.range_sd < RANGE_SD   # four shots fix it better than one


@pytest.mark.slow
def test_held_out_predictions_fall_within_their_bands_at_the_stated_rate(tmp_path):
    """Each seed fits the noisy series and predicts one held-out setting. If the band is right,
    z = (predicted - true) / range_sd is standard normal, so the prediction is within its band
    with probability erf(1/sqrt 2) = 68.3 %: over 16 independent trials the count must fall in
    binomial(16, 0.683)'s central 99.8 %, [5, 16]. A count alone cannot see bands that are too
    wide, and sees bands half as wide only 20 % of the time, so the squared z's must also sum inside
    chi-square(16)'s central 99.8 %, [3.9, 39.3]: bands half as wide (expected sum 64) or twice as
    wide (4) fail that nearly always."""
    inside, squares = [], []
    for seed in COVERAGE_SEEDS:
        result = calibrate(load_calibration(series_file(tmp_path, seed)))
        setting = HELD_OUT[seed % 2]
        (p,) = predict_ranges(result, field("machine.counterweight_mass"), [setting])
        z = (p.range - true_range(setting)) / p.range_sd
        inside.append(abs(z) <= 1.0)
        squares.append(z * z)
    low, high = binom.ppf([0.001, 0.999], len(inside), ONE_SD)
    assert low <= sum(inside) <= high, (sum(inside), low, high)
    low, high = chi2.ppf([0.001, 0.999], len(squares))
    assert low < sum(squares) < high, (squares, low, high)


def test_predict_json_plot_and_fitted_files(tmp_path, capsys):
    path = series_file(tmp_path, 3, units="lb")
    out = tmp_path / "out"
    assert main(["calibrate", path, "--json", "--quiet", "--out", str(out),
                 "--predict", "machine.counterweight_mass=6.75,22 lb"]) == 0
    data = json.loads(capsys.readouterr().out)
    predictions = data["predictions"]
    assert [set(p) for p in predictions] == [{"field", "value", "range", "range_sd"}] * 2
    assert predictions[0]["field"] == "machine.counterweight_mass"
    assert [p["value"] for p in predictions] == pytest.approx([6.75, 22 * 0.45359237])   # SI: kg
    sd = data["parameters"]["losses.axle_friction"]["uncertainty"]
    assert all(0.0 < p["range_sd"] < 1.0 for p in predictions) and sd > 0.0
    assert (out / PLOT_FILE).read_bytes()[:4] == b"\x89PNG"
    fitted = sorted((out / FITTED_FOLDER).iterdir())
    assert len(fitted) == len(MEASURED)
    text = fitted[0].read_text()
    # The user's units (lb as the shot wrote it), the design's [machine.arm_beam] table, its comments.
    assert "lb" in text and "[machine.arm_beam]" in text and text.startswith("# The paper's prototype")
    assert "counterweight_mass" in fitted[0].stem and tomllib.loads(text)["name"] == fitted[0].stem
    # Rounded to two significant figures of the uncertainty (no float noise).
    written = tomllib.loads(text)["losses"]["axle_friction"]
    assert written == round(written, max(0, 1 - math.floor(math.log10(sd))))
    assert abs(written - data["parameters"]["losses.axle_friction"]["value"]) <= sd / 10
    mass = load_design(fitted[0]).machine.counterweight_mass
    assert any(mass == pytest.approx(m, rel=1e-6) for m in MEASURED)


@pytest.mark.parametrize("text, reason", [
    pytest.param("machine.counterweight_mass", "FIELD=VALUE", id="no-values"),
    pytest.param("machine.counterweigth=5", "no such field", id="unknown-field"),
    pytest.param("machine.counterweight_mass=5 m", "mass", id="wrong-unit"),
    pytest.param("machine.counterweight_mass=-5", "positive", id="unbuildable"),
])
def test_a_bad_predict_exits_2_before_the_fit(tmp_path, capsys, text, reason):
    assert main(["calibrate", series_file(tmp_path, None), "--quiet", "--predict", text]) == 2
    err = capsys.readouterr().err
    assert err.startswith("invalid input: --predict") and reason in err


def test_parse_predict_reads_units():
    target, values = parse_predict("machine.counterweight_mass=5, 14 lb")
    assert target.name == "machine.counterweight_mass" and values == pytest.approx([5.0, 14 * 0.45359237])


def test_an_implausible_or_entangled_fit_is_warned_of(tmp_path):
    """Ranges 3 m short of an ideal machine's at every counterweight, fitted with axle friction and
    drag together: the friction leaves its plausible range or the two correlate beyond 0.9 (a
    series of ranges cannot tell friction from drag well), and the warning says what that means."""
    path = series_file(tmp_path, None, fit=("losses.axle_friction", "drag_factor"))
    text = Path(path).read_text()
    for mass in MEASURED:
        text = text.replace(f"range = {true_range(mass)!r}", f"range = {true_range(mass) - 3.0!r}")
    bad = tmp_path / "short.toml"
    bad.write_text(text)
    result = calibrate(load_calibration(bad))
    lines = " ".join(result.warnings)
    assert "correlate at" in lines or "plausible range" in lines, result.warnings
    assert "probably" in lines or "combination" in lines


def test_designs_of_the_same_name_in_two_folders_get_a_fitted_file_each(tmp_path, capsys):
    for folder in ("a", "b"):
        (tmp_path / folder).mkdir()
        (tmp_path / folder / "p.toml").write_text(PROTOTYPE_FILE.read_text())
    path = tmp_path / "two.toml"
    path.write_text('fit = ["drag_factor"]\n'
                    '[[shot]]\ndesign = "a/p.toml"\nrange = 28.0\nrange_uncertainty = 0.5\n'
                    '[[shot]]\ndesign = "b/p.toml"\nrange = 28.4\nrange_uncertainty = 0.5\n')
    assert main(["calibrate", str(path), "--quiet", "--out", str(tmp_path / "out")]) == 0
    assert sorted(p.name for p in (tmp_path / "out" / FITTED_FOLDER).iterdir()) == ["p-shot2.toml", "p.toml"]


def test_the_shipped_counterweight_series_finds_the_drag_it_was_made_with():
    """analytic/data/calibration/counterweight-series.toml: six synthetic shots made with drag 1.3
    times the golf-ball curve (its header says how), fitted within 3 sd of 1.3."""
    result = calibrate(load_calibration(DATA / "calibration" / "counterweight-series.toml"))
    assert abs(result.values[0] - 1.3) < 3.0 * result.uncertainties[0] and not result.warnings
