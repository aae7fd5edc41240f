"""The shot plot: a laptop-sized layout, the loads zoomed on the stroke, the sling's tension and the
projectile's felt acceleration drawn as the one curve they are."""

from __future__ import annotations

import numpy as np
import pytest

from analytic.plot import shot_figure, stroke_window
from analytic.reference import simulate

#: A laptop screen's usable area at the default 110 dpi: 1440 x 900 pixels.
SCREEN_INCHES = (1440 / 110, 900 / 110)


@pytest.fixture(scope="module")
def shot(table3):
    return simulate(table3, histories=True, loads=True)


def _panel(figure, title_start):
    (ax,) = [ax for ax in figure.axes if ax.get_title().startswith(title_start)]
    return ax


def test_the_figure_fits_a_laptop_screen(shot):
    width, height = shot_figure(shot).get_size_inches()
    assert width <= SCREEN_INCHES[0] and height <= SCREEN_INCHES[1]


def test_the_loads_panel_shows_the_stroke_around_every_peak(shot):
    """The window holds every peak, and is a small part of the history (the paper's design: its
    loads rise in the last ~30 ms of a 0.38 s stroke, so under a third of it)."""
    figure = shot_figure(shot)
    start, end = _panel(figure, "joint loads").get_xlim()
    duration = float(shot.history.t[-1] - shot.history.t[0])
    assert (start, end) == pytest.approx(stroke_window(shot))
    assert end - start < duration / 3
    for when in (shot.peak_axle_load_time, shot.peak_hinge_load_time, shot.peak_sling_tension_time):
        assert start < when < end


def test_sling_tension_is_drawn_once_with_the_acceleration_as_its_second_scale(shot):
    """Tension / (m g) is the felt acceleration in g (the sling's is the only force but gravity):
    the right axis maps the peak tension onto the peak acceleration."""
    ax = _panel(shot_figure(shot), "sling")
    curves = [line for line in ax.get_lines() if len(line.get_xdata()) == len(shot.history.t)]
    assert len(curves) == 1
    (scale,) = [child for child in ax.child_axes]
    assert "acceleration" in scale.get_ylabel()
    g = shot.design.environment.gravity
    weight = shot.design.projectile.mass * g
    assert shot.peak_sling_tension / weight == pytest.approx(shot.peak_projectile_acceleration / g, rel=2e-2)
    assert np.all(np.isfinite(curves[0].get_ydata()))
