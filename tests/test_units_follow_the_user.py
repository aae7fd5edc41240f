"""``--units metric|imperial`` on every command that prints or draws: bare numbers typed in the chosen
units, text and plots shown in them, JSON and CSV kept SI (with a ``units`` block when imperial),
and the default taken from the design file's own units.

Reference conversions are the definitions: 1 ft = 0.3048 m, 1 lb = 0.45359237 kg (the international
yard and pound, 1959).
"""

from __future__ import annotations

import csv
import json
import math
import re

import numpy as np
import pytest

from analytic.cli import EXIT_INVALID, EXIT_OK, main
from analytic.design_file import default_design, file_system, save_design
from analytic.result import JSON_KEYS
from support import TABLE3_FILE

FOOT, POUND = 0.3048, 0.45359237
#: Two conversions of a typed number (pint's factor, then 12 significant digits): exact to a few ulp.
CONVERSION_REL = 1e-12


def _json(capsys, argv: list[str]) -> dict:
    assert main(argv) == EXIT_OK, capsys.readouterr().err
    return json.loads(capsys.readouterr().out)


def test_a_bare_target_is_read_in_the_chosen_units(capsys):
    imperial = _json(capsys, ["aim", str(TABLE3_FILE), "--target", "150", "--adjust", "counterweight_mass",
                              "--units", "imperial", "--json"])
    written = _json(capsys, ["aim", str(TABLE3_FILE), "--target", "150 ft", "--adjust", "counterweight_mass",
                             "--json"])
    assert imperial["target"] == pytest.approx(150 * FOOT, rel=CONVERSION_REL)
    assert imperial["target"] == pytest.approx(written["target"], rel=CONVERSION_REL)
    # the same search (its root to the solver's tolerance, far inside 1e-9 of the setting)
    assert [s["value"] for s in imperial["solutions"]] == pytest.approx([s["value"] for s in written["solutions"]],
                                                                        rel=1e-9)
    assert "units" in imperial and "units" not in written


def test_an_unreachable_target_is_reported_in_the_chosen_units(capsys):
    code = main(["aim", str(TABLE3_FILE), "--target", "2000", "--adjust", "counterweight_mass", "--units", "imperial"])
    err = capsys.readouterr().err
    assert code != EXIT_OK
    assert "the target 2000 (2000 ft)" in err and err.rstrip().endswith("ft"), err


def test_json_stays_si_and_says_so_when_imperial_is_asked(capsys):
    metric = _json(capsys, ["simulate", "--json"])
    imperial = _json(capsys, ["simulate", "--json", "--units", "imperial"])
    assert set(metric) == set(JSON_KEYS)   # metric: the keys as they always were
    assert {key: imperial[key] for key in JSON_KEYS} == metric
    assert imperial["units"]["json"].startswith("SI") and imperial["units"]["shown_as"]["m"] == "ft"


def test_the_default_units_are_the_design_files_own(tmp_path, capsys):
    path = tmp_path / "backyard.toml"
    save_design(default_design(), path, units={"length": "ft", "mass": "lb"})
    assert file_system(path) == "imperial" and file_system(TABLE3_FILE) == "metric"
    assert main(["simulate", str(path)]) == EXIT_OK
    imperial = capsys.readouterr().out
    assert main(["simulate", str(path), "--units", "metric"]) == EXIT_OK
    metric = capsys.readouterr().out
    range_ft = next(line for line in imperial.splitlines() if "range (from pivot)" in line)
    range_m = next(line for line in metric.splitlines() if "range (from pivot)" in line)
    assert range_ft.endswith("ft") and range_m.endswith("m")
    assert float(range_ft.split()[-2]) == pytest.approx(float(range_m.split()[-2]) / FOOT, abs=2e-3)


def test_the_shot_plot_is_shown_in_the_chosen_units():
    from analytic.plot import shot_figure
    from analytic.reference import simulate

    shot = simulate(default_design())
    figure = shot_figure(shot, "imperial")
    flight, machine, energy, loads = figure.axes[:4]
    assert flight.get_xlabel() == "x from pivot (ft)" and loads.get_ylabel() == "force (lbf)"
    assert energy.get_ylabel().endswith("(ft lbf)")
    assert flight.xaxis.get_major_formatter()(20 * FOOT, 0) == "20"   # data in m, ticks read in ft
    # the title's "range 45.31 m" (4 significant digits) is shown to as many, "148.7 ft": off the
    # exact value by the metre figure's rounding (0.005 m, 0.016 ft) and the foot figure's (0.05 ft)
    title = figure._suptitle.get_text()
    shown = title.split("range ")[1].split(" ft")[0]
    assert len(shown.replace(".", "")) == 4 and float(shown) == pytest.approx(shot.range / FOOT, abs=0.067)
    assert all(tick % 1 == 0 for tick in flight.xaxis.get_major_locator()() / FOOT * 1e6 // 1e6)
    # the peaks' annotations too: no figure in newtons or metres is left on an imperial plot
    annotations = [text.get_text() for ax in figure.axes for text in ax.texts]
    assert any("lbf" in text for text in annotations)
    assert not any(re.search(r"\d (N|m)\b", text) for text in annotations)


def test_chart_reads_bare_settings_in_the_chosen_units_and_keeps_its_csv_si(tmp_path, capsys):
    out = tmp_path / "chart"
    assert main(["chart", str(TABLE3_FILE), "--vary", "counterweight_mass=10:20:3", "--units", "imperial",
                 "--out", str(out)]) == EXIT_OK
    with (out / "chart.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    masses = [float(row["machine.counterweight_mass [kg]"]) for row in rows]
    assert masses == pytest.approx([10 * POUND, 15 * POUND, 20 * POUND], rel=CONVERSION_REL)
    # the typed ends carry no conversion noise (10 lb is 4.5359237 kg by definition)
    assert rows[0]["machine.counterweight_mass [kg]"] == "4.5359237"


def test_a_value_with_a_unit_is_echoed_as_written(tmp_path, capsys):
    text = TABLE3_FILE.read_text().replace("counterweight_mass = 6.5", 'counterweight_mass = "-200 lb"')
    path = tmp_path / "negative.toml"
    path.write_text(text)
    assert main(["simulate", str(path)]) == EXIT_INVALID
    err = capsys.readouterr().err
    assert f'machine.counterweight_mass = "-200 lb" ({-200 * POUND:.6g} kg): must be positive' in err, err


def test_the_engines_table_is_shown_in_the_chosen_units(capsys):
    from engine_model.cli import main as engine_main

    assert engine_main(["simulate", "--units", "imperial"]) == EXIT_OK
    imperial = capsys.readouterr().out
    assert engine_main(["simulate", "--json"]) == EXIT_OK
    metric = json.loads(capsys.readouterr().out)
    line = next(line for line in imperial.splitlines() if line.startswith("range from pivot"))
    assert line.endswith("ft") and float(line.split()[-2]) == pytest.approx(metric["range"] / FOOT, abs=1e-4)
    assert math.isfinite(metric["range"])


def test_calibrate_prints_its_shots_in_the_chosen_units(capsys):
    from support import DATA

    shots = str(DATA / "calibration" / "prototype.toml")   # one shot: 26.8 m measured, +- 0.5 m
    assert main(["calibrate", shots, "--units", "imperial", "--quiet"]) == EXIT_OK
    line = next(line for line in capsys.readouterr().out.splitlines() if line.strip().startswith("range"))
    assert f"measured {26.8 / FOOT:.4f} +- {0.5 / FOOT:.4g} ft" in line and line.count(" ft") == 3, line
    assert main(["calibrate", shots, "--units", "imperial", "--quiet", "--json"]) == EXIT_OK
    data = json.loads(capsys.readouterr().out)
    assert data["shots"][0]["measured"] == 26.8 and data["units"]["json"].startswith("SI")


def test_the_optimise_report_is_written_in_the_chosen_units(tmp_path, capsys):
    import tomli_w

    from support import release_angle_problem_dict

    problem = tmp_path / "release-angle.toml"
    problem.write_text(tomli_w.dumps(release_angle_problem_dict()))
    assert main(["optimise", str(problem), "--units", "imperial", "--out", str(tmp_path / "out"), "--quiet"]) == 0
    report = (tmp_path / "out" / "report.txt").read_text()
    assert "lengths in, angles deg" in report and "range (ft)" in report and "axle load (lbf)" in report


def test_a_refused_option_is_echoed_as_typed(capsys):
    code = main(["aim", str(TABLE3_FILE), "--target", "-10", "--units", "imperial", "--adjust", "counterweight_mass"])
    assert code == EXIT_INVALID
    assert f'target = "-10" ({-10 * FOOT:.6g} m): must be a positive distance' in capsys.readouterr().err
    code = main(["aim", str(TABLE3_FILE), "--target", "30", "--bounds", "20lb:2lb", "--adjust", "counterweight_mass"])
    assert code == EXIT_INVALID
    assert f'bounds = "20lb:2lb" ({20 * POUND:.6g}, {2 * POUND:.6g} kg): inverted' in capsys.readouterr().err


@pytest.mark.parametrize("units", ["metric", "imperial"])
def test_the_shot_plots_labels_stay_inside_their_panels(units):
    """Every label on the shot figure's panels (the peaks' "hinge 356.8 lbf", longer in lbf than in N)
    lies inside its panel, clear of the frame's sides by a few pixels."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from analytic.plot import shot_figure
    from analytic.reference import simulate

    figure = shot_figure(simulate(default_design()), units)
    FigureCanvasAgg(figure).draw()
    renderer = figure.canvas.get_renderer()
    for ax in figure.axes:
        panel = ax.get_window_extent(renderer)
        for text in ax.texts:
            box = text.get_window_extent(renderer)
            assert panel.x0 + 2 <= box.x0 and box.x1 <= panel.x1 - 2, (text.get_text(), box, panel)
            assert panel.y0 <= box.y0 and box.y1 <= panel.y1 + 0.5, (text.get_text(), box, panel)


#: A metric unit an imperial figure must not show: in an axis label's brackets, or after a figure.
_SI_LABEL = re.compile(r"\((m|cm|mm|kg|N|J|m/s|m/s\^2)\)\s*$")
_SI_FIGURE = re.compile(r"\d (m|cm|kg|N|J|m/s)\b")


def _metric_left(figure) -> list[str]:
    """Every text of ``figure`` (axis labels, titles, annotations, legends, the suptitle) still in a metric unit."""
    texts = [figure._suptitle.get_text()] if figure._suptitle is not None else []
    for ax in figure.axes:
        texts += [ax.get_xlabel(), ax.get_ylabel(), ax.get_title()] + [text.get_text() for text in ax.texts]
        texts += [text.get_text() for text in ax.get_legend().get_texts()] if ax.get_legend() is not None else []
    return [text for text in texts if _SI_LABEL.search(text) or _SI_FIGURE.search(text)]


def _figures_saved(monkeypatch, module: str) -> list:
    """The figures ``module.save_figure`` is given from now on (still written)."""
    import importlib

    target = importlib.import_module(module)
    saved, save = [], target.save_figure

    def keep(figure, path, *args, **kwargs):
        saved.append(figure)
        return save(figure, path, *args, **kwargs)

    monkeypatch.setattr(target, "save_figure", keep)
    return saved


def test_the_optimisers_plots_are_drawn_in_the_chosen_units(tmp_path, monkeypatch, capsys):
    """``optimise --units imperial``'s convergence and sensitivity plots: the sling in inches, the
    range in feet (on the log axis too), no metric unit left; the data stay SI underneath."""
    import tomli_w

    from support import release_angle_problem_dict

    data = release_angle_problem_dict()
    data["variables"]["sling_length"] = {"lower": 0.3, "upper": 1.2}   # a length on the plot, m
    problem = tmp_path / "sling-and-angle.toml"
    problem.write_text(tomli_w.dumps(data))
    saved = _figures_saved(monkeypatch, "analytic.optimise.plot")
    assert main(["optimise", str(problem), "--units", "imperial", "--out", str(tmp_path / "out"), "--quiet"]) == 0
    convergence, sensitivity = saved
    for figure in saved:
        assert not _metric_left(figure), _metric_left(figure)
    best, gap = convergence.axes
    assert best.get_ylabel().endswith("(ft)") and gap.get_ylabel().endswith("(ft)")
    assert best.yaxis.get_major_formatter()(100 * FOOT, 0) == "100"
    assert gap.get_yscale() == "log" and "10^{0}" in gap.yaxis.get_major_formatter()(1 * FOOT, 0)
    sling = next(ax for ax in sensitivity.axes if ax.get_visible() and "sling" in ax.get_xlabel())
    assert sling.get_xlabel().endswith("(in)") and sling.get_ylabel() == "range (ft)"
    curve = sling.get_lines()[0].get_xdata()
    assert [curve[0], curve[-1]] == pytest.approx([0.3 / 0.0254, 1.2 / 0.0254], rel=1e-12)   # 1 in = 2.54 cm
    # metric: the paper's cm and m, as before
    saved.clear()
    assert main(["optimise", str(problem), "--out", str(tmp_path / "metric"), "--quiet"]) == 0
    sling = next(ax for ax in saved[1].axes if ax.get_visible() and "sling" in ax.get_xlabel())
    assert sling.get_xlabel().endswith("(cm)") and sling.get_ylabel() == "range (m)"


def test_calibrates_report_and_plot_are_written_in_the_chosen_units(tmp_path, monkeypatch, capsys):
    """``calibrate --out DIR --units imperial``: report.txt in feet and pounds like the printed
    report, the plot in them too (its predictions labelled as the report gives them), the JSON SI."""
    from support import DATA

    shots = DATA / "calibration" / "counterweight-series.toml"   # six shots, 4.5 to 9.5 kg
    saved = _figures_saved(monkeypatch, "analytic.plot")
    out = tmp_path / "out"
    assert main(["calibrate", str(shots), "--predict", "machine.counterweight_mass=7", "--units", "imperial",
                 "--out", str(out), "--quiet"]) == EXIT_OK
    printed = capsys.readouterr().out
    report = (out / "report.txt").read_text()
    assert report.rstrip() in printed   # the file is the printed report
    assert "ft" in report and not re.search(r"\d m\b", report), report
    prediction = next(line for line in report.splitlines() if "counterweight_mass =" in line)
    assert f"= {7 / POUND:g} lb:" in prediction and prediction.endswith("ft"), prediction
    [figure] = saved
    assert not _metric_left(figure), _metric_left(figure)
    against = figure.axes[0]
    assert against.get_xlabel().endswith("(lb)") and against.get_ylabel() == "range (ft)"
    label = next(text.get_text() for text in against.texts)
    assert label == prediction.split(": ")[1], (label, prediction)
    data = json.loads((out / "calibration.json").read_text())
    assert data["predictions"][0]["value"] == pytest.approx(7.0, rel=CONVERSION_REL)   # kg


def test_no_metric_unit_is_left_in_the_engines_imperial_table(capsys):
    """Every row of ``python -m engine_model simulate --units imperial``, its diagnostics too (the
    joints' drift), in ft, lb, lbf or ft lbf; the drift is the JSON's max_joint_drift (m) in ft."""
    from engine_model.cli import main as engine_main

    assert engine_main(["simulate", "--units", "imperial", "--dt", "4e-4"]) == EXIT_OK
    table = capsys.readouterr().out
    left = [line for line in table.splitlines() if re.search(r"\s(m|kg|N|J|m/s)(\s|$)", line)]
    assert not left, left
    assert engine_main(["simulate", "--json", "--dt", "4e-4"]) == EXIT_OK
    drift = json.loads(capsys.readouterr().out)["max_joint_drift"]
    line = next(line for line in table.splitlines() if line.startswith("max joint drift"))
    assert line.endswith(" ft") and float(line.split()[-2]) == pytest.approx(drift / FOOT, rel=5e-3)   # 3 digits


def test_the_charts_maps_are_coloured_and_labelled_in_the_chosen_units():
    """A two-field chart under imperial: every panel's title, colours, colour bar and contour labels
    in ft or lbf (the axes too, through in_units), none left in m or N; metric as it was."""
    from analytic.chart import chart, chart_figure, vary
    from analytic.plot_units import in_units

    result = chart(default_design(), [vary("counterweight_mass", 4.0, 8.0, 4), vary("sling_length", 0.4, 1.0, 4)])
    figure = in_units(chart_figure(result, "imperial"), "imperial")
    assert not _metric_left(figure), _metric_left(figure)
    panels = {ax.get_title(): ax for ax in figure.axes if ax.get_visible() and ax.get_title()}
    assert {"range (ft)", "peak axle load (lbf)", "peak hinge load (lbf)"} <= set(panels)
    colours = panels["range (ft)"].collections[0].get_array()
    np.testing.assert_allclose(colours.ravel(), result.range / FOOT, rtol=1e-12)
    lbf = 4.4482216152605   # N, by definition (1 lbf = 1 lb x 9.80665 m/s^2)
    axle = panels["peak axle load (lbf)"].collections[0].get_array()
    np.testing.assert_allclose(axle.ravel(), result.loads["peak_axle_load"] / lbf, rtol=1e-9)
    metric = {ax.get_title() for ax in chart_figure(result).axes if ax.get_visible() and ax.get_title()}
    assert {"range (m)", "peak axle load (N)"} <= metric
