"""Calibration charts: the CSV's rows and gaps, the figure, and bad input (exit 2, nothing written)."""

from __future__ import annotations

import csv
import dataclasses

import numpy as np
import pytest

from analytic import cli, fast
from analytic.chart import chart, chart_figure, vary
from analytic.design import Losses
from analytic.design_file import save_design
from analytic.fields import field


def _rows(path):
    with path.open() as handle:
        return list(csv.DictReader(handle))


def test_one_field_writes_a_row_a_design_with_the_loads(table3, tmp_path):
    path = tmp_path / "d.toml"
    save_design(table3, path)
    assert cli.main(["chart", str(path), "--vary", "counterweight_mass=1kg:3kg:9", "--out", str(tmp_path / "c")]) == 0
    rows = _rows(tmp_path / "c" / "chart.csv")
    assert len(rows) == 9
    assert list(rows[0])[:3] == ["machine.counterweight_mass [kg]", "status", "range [m]"]
    masses = [float(r["machine.counterweight_mass [kg]"]) for r in rows]
    assert masses == pytest.approx(np.linspace(1.0, 3.0, 9).tolist())
    # Each row is the fast path's shot of that design.
    shots = fast.shoot([field("counterweight_mass").replace(table3, m) for m in masses], loads=True)
    for row, i in zip(rows, range(9), strict=True):
        assert row["status"] == shots.status[i]
        assert float(row["range [m]"]) == shots.range[i]
        assert float(row["peak_axle_load [N]"]) == shots.peak_axle_load[i]
        assert float(row["peak_projectile_acceleration [m/s^2]"]) == shots.peak_projectile_acceleration[i]
    assert (tmp_path / "c" / "chart.png").stat().st_size > 10_000


def test_failures_are_gaps_with_their_status(table3, tmp_path):
    # A 10 g counterweight cannot lift the arm: never_fires, with an empty range, not a zero.
    result = chart(table3, [vary("counterweight_mass", 0.01, 6.5, 4)])
    assert result.status[0] == "never_fires" and np.isnan(result.range[0])
    assert np.all(np.isnan([result.loads[name][0] for name in result.loads]))
    path = tmp_path / "chart.csv"
    from analytic.chart import write_csv

    write_csv(result, path)
    first = _rows(path)[0]
    assert first["status"] == "never_fires" and first["range [m]"] == "" and first["peak_axle_load [N]"] == ""


def test_a_setting_that_cannot_be_built_is_a_gap_named_design_error(table3):
    # A link this long would strike the base: the design refuses it.
    result = chart(table3, [vary("counterweight_link", 0.1, 0.5, 5)])
    assert "design_error" in result.status.tolist() and "ok" in result.status.tolist()
    assert np.all(np.isnan(result.range[result.status == "design_error"]))


def test_two_fields_make_a_grid_and_a_map(table3, tmp_path):
    result = chart(table3, [vary("counterweight_mass", 2.0, 8.0, 20), vary("projectile.mass", 0.03, 0.2, 20)])
    assert result.settings.shape == (400, 2) and result.shape == (20, 20)
    # The last field varies fastest.
    assert result.settings[1, 0] == result.settings[0, 0] and result.settings[1, 1] > result.settings[0, 1]
    figure = chart_figure(result)
    assert len([ax for ax in figure.axes if ax.get_visible()]) >= 6


@pytest.mark.parametrize("varies, words", [
    (["release_rule=1:2:3"], ["machine.release_rule", "not a number"]),
    (["nothing=1:2:3"], ["machine.nothing", "no such field"]),
    (["counterweight_mass=3:3:5"], ["counterweight_mass", "empty range"]),
    (["counterweight_mass=1:3:1"], ["steps", "at least 2"]),
    (["counterweight_mass=1:3:many"], ["steps", "whole number"]),
    (["counterweight_mass=1m:3m:4"], ["counterweight_mass from = '1m'", "mass"]),
    (["counterweight_mass=1:3"], ["FIELD=FROM:TO:STEPS"]),
    (["counterweight_mass=1:3:3", "counterweight_mass=1:3:3"], ["same field twice"]),
    (["counterweight_mass=1:3:3", "sling_length=0.3:0.6:3", "projectile.mass=0.03:0.1:3"], ["one or two"]),
], ids=lambda v: " ".join(v) if isinstance(v, list) else None)
def test_bad_input_exits_2_and_writes_nothing(table3, tmp_path, capsys, varies, words):
    path = tmp_path / "d.toml"
    save_design(table3, path)
    argv = ["chart", str(path), "--out", str(tmp_path / "c")]
    for spec in varies:
        argv += ["--vary", spec]
    assert cli.main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("invalid input: ") and all(w in err for w in words), err
    assert not (tmp_path / "c").exists()


def test_a_coefficient_varied_from_zero_draws_its_first_point_as_the_ideal_machine(table3, tmp_path):
    # A bearing of known radius: at 0 it is frictionless, the ideal machine's shot bit for bit.
    bearing = dataclasses.replace(table3, losses=Losses(axle_friction=0.15, axle_radius=0.0064))
    path = tmp_path / "d.toml"
    save_design(bearing, path)
    assert cli.main(["chart", str(path), "--vary", "losses.axle_friction=0:0.2:5", "--out", str(tmp_path / "c")]) == 0
    rows = _rows(tmp_path / "c" / "chart.csv")
    assert [row["status"] for row in rows] == ["ok"] * 5
    ideal = fast.shoot([table3], loads=True)
    assert float(rows[0]["range [m]"]) == ideal.range[0]
    assert float(rows[0]["peak_axle_load [N]"]) == ideal.peak_axle_load[0]
    ranges = [float(row["range [m]"]) for row in rows]
    assert all(a > b for a, b in zip(ranges, ranges[1:], strict=False))   # friction takes range away


@pytest.mark.parametrize("spec, label", [("losses.axle_friction", "losses.axle_friction"),
                                         ("counterweight_mass", "machine.counterweight_mass (kg)"),
                                         ("release_angle", "machine.release_angle (deg)")])
def test_an_axis_names_its_field_and_a_unit_only_where_there_is_one(table3, spec, label):
    bearing = dataclasses.replace(table3, losses=Losses(axle_friction=0.15, axle_radius=0.0064))
    start = field(spec).check(bearing)
    line = chart_figure(chart(bearing, [vary(spec, start, 1.1 * start, 2)]))
    assert line.axes[2].get_xlabel() == label
    grid = chart_figure(chart(bearing, [vary("projectile.mass", 0.04, 0.05, 2), vary(spec, start, 1.1 * start, 2)]))
    assert {ax.get_xlabel() for ax in grid.axes if ax.get_visible() and ax.get_xlabel()} == {label}


def _map_panels(figure):
    """The visible map panels (not colour bars), by title."""
    return {ax.get_title(): ax for ax in figure.axes if ax.get_visible() and ax.get_title()}


def test_a_map_draws_tension_and_acceleration_once_where_they_are_proportional(table3):
    """With the projectile's weight fixed, peak sling tension / (m g) is the peak acceleration in g
    (after lift-off the sling's is the only pull on it): one panel, both scales on its colour bar;
    and every panel's contours are labelled."""
    result = chart(table3, [vary("counterweight_mass", 2.0, 8.0, 8), vary("sling_length", 0.4, 1.0, 8)])
    tension, acceleration = result.loads["peak_sling_tension"], result.loads["peak_projectile_acceleration"]
    np.testing.assert_allclose(tension / table3.projectile.mass, acceleration, rtol=1e-9)
    panels = _map_panels(chart_figure(result))
    assert not [title for title in panels if title.startswith("peak projectile acceleration")]
    (sling,) = [ax for title, ax in panels.items() if title.startswith("peak sling tension")]
    assert "acceleration" in sling.get_title()
    for title, ax in panels.items():
        if title != "outcome":
            assert ax.texts, f"{title}: contours without labels"
    # The colour bar's ticks name the force's unit, not that of a panel drawn after it.
    from matplotlib.ticker import FuncFormatter

    for units, unit in (("metric", "N"), ("imperial", "lbf")):
        figure = chart_figure(result, units)
        ticks = [ax.yaxis.get_major_formatter()(10.0, 0) for ax in figure.axes
                 if isinstance(ax.yaxis.get_major_formatter(), FuncFormatter)]
        assert len(ticks) == 1 and ticks[0].startswith(f"10 {unit} = "), ticks


def test_a_map_over_the_projectile_mass_keeps_the_acceleration_panel(table3):
    result = chart(table3, [vary("counterweight_mass", 2.0, 8.0, 6), vary("projectile.mass", 0.03, 0.2, 6)])
    assert "peak projectile acceleration (g)" in _map_panels(chart_figure(result))


def test_the_outcome_panel_is_left_out_when_every_setting_throws(table3):
    result = chart(table3, [vary("counterweight_mass", 5.0, 7.0, 4), vary("sling_length", 0.5, 0.7, 4)])
    assert set(result.status.tolist()) == {"ok"}
    assert "outcome" not in _map_panels(chart_figure(result))


def test_a_fixed_machines_chart_names_the_mount_not_a_hinge(table3):
    bolted = dataclasses.replace(table3, machine=dataclasses.replace(table3.machine, kind="fixed", counterweight_link=0.0))
    line = chart_figure(chart(bolted, [vary("machine.sling_length", 0.5, 0.6, 2)]))
    labels = [text.get_text() for ax in line.axes if ax.get_legend() for text in ax.get_legend().get_texts()]
    assert "peak mount load" in labels and "peak hinge load" not in labels
    grid = chart_figure(chart(bolted, [vary("projectile.mass", 0.04, 0.05, 2), vary("machine.sling_length", 0.5, 0.6, 2)]))
    titles = [ax.get_title() for ax in grid.axes]
    assert any(t.startswith("peak mount load") for t in titles) and not any("hinge" in t for t in titles)
