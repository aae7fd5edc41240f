"""The page built from the server's ``/api/meta``, in a real browser: a field left out shows its default in the
page's units, the what-if's loads are the server's, the front plot's axes and the firing table are in the
page's units and redrawn when they change.

Runs as ``tests/test_workbench_browser.py`` does (Debian's chromium through Playwright, the server as a
child process); screenshots go to ``out/workbench/``.
"""

from __future__ import annotations

import json
from urllib.parse import quote

import pytest

from analytic.design_file import design_to_dict, load_design
from analytic.result import PEAK_NAMES
from support import TABLE3_FILE, bolted
from test_workbench_bench_browser import LAYOUTS, RECORD_CANVAS_TEXTS, select_preset
from test_workbench_browser import (CHROMIUM, SHOTS, TOOL_WAIT, TEST_GENERATIONS, base_url,  # noqa: F401
                                    browser_type_launch_args, open_page, range_shown, server, shots,
                                    wait_for_next_shot, wait_until_current)

pytestmark = pytest.mark.skipif(not __import__("pathlib").Path(CHROMIUM).exists(),
                                reason="needs Debian's chromium (make test installs it)")

#: 1 ft = 0.3048 m and 1 lb = 0.45359237 kg, exactly (by definition); g_n = 9.80665 m/s^2.
FOOT, POUND = 0.3048, 0.45359237
#: The page's number boxes show six significant figures (form.js ``round``).
FIGURES = 6
#: Firing-table targets, ft: inside the Table III machine's reach (it throws 45.3 m, 148.6 ft, at its own pin).
TARGETS_FT = (100.0, 120.0, 140.0)
#: The readout's rounding (two decimals) and the firing table's aim (within a millimetre:
#: ``tests/test_workbench_firing.py``), in feet.
LANDS_WITHIN_FT = 0.005 + 0.001 / FOOT


def figures(value: float) -> str:
    return str(float(f"{value:.{FIGURES}g}")).removesuffix(".0")


def share_link(server: str, design: dict) -> str:
    return f"{server}#design={quote(json.dumps(design))}"


def open_all_tables(page) -> None:
    for box in page.locator("#fields > details").all():
        if box.get_attribute("open") is None:
            box.locator("summary").first.click()


def row(page, field: str):
    return page.locator(f'.field[data-field="{field}"]')


@pytest.mark.parametrize("layout", list(LAYOUTS))
def test_a_field_left_out_shows_its_default_greyed_in_the_pages_units(browser, server, layout):
    """A design without an ``[environment]`` table and with an axle's kinetic friction only: gravity and the
    air's density show ``analytic.design.Environment``'s defaults as greyed placeholders, in feet and pounds
    on the imperial page; the static coefficient shows the kinetic one; the drag factor 1, its slider there."""
    design = json.loads(json.dumps(design_to_dict(load_design(TABLE3_FILE))))
    del design["environment"]
    design["losses"] = {"axle_friction": 0.2, "axle_radius": 0.01}
    context = browser.new_context(viewport={"width": LAYOUTS[layout][0], "height": LAYOUTS[layout][1]})
    page = context.new_page()
    page.goto(share_link(server, design))
    page.wait_for_function("Number(document.body.dataset.shots || 0) >= 1", timeout=TOOL_WAIT)
    assert page.get_by_test_id("status").inner_text() == "ok"
    open_all_tables(page)
    placeholder = lambda name: page.locator(f'[name="{name}"]').get_attribute("placeholder")   # noqa: E731
    for system in ("metric", "imperial"):
        page.get_by_test_id("units").select_option(system)
        # Standard sea level (analytic.design.Environment): 9.81 m/s^2 and 1.225 kg/m^3.
        gravity, density = (9.81, 1.225) if system == "metric" else (9.81 / FOOT, 1.225 * FOOT**3 / POUND)
        assert placeholder("environment.gravity") == figures(gravity), system
        assert placeholder("environment.air_density") == figures(density), system
        assert page.locator('[name="environment.gravity"]').input_value() == ""
        assert "unset" in row(page, "environment.gravity").get_attribute("class")
        assert placeholder("losses.axle_static_friction") == "0.2"
        assert placeholder("projectile.drag_factor") == "1"
        SHOTS.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=SHOTS / f"{layout}-{system}-defaults.png", full_page=True)
    # The drag factor's slider stands at 1 on its span 0 to 3 (workbench.fields.SPANS).
    assert float(row(page, "projectile.drag_factor").locator(".slider").input_value()) == pytest.approx(400 / 3, abs=0.5)
    # Typing a value takes it; emptying the box gives the default back.
    count = shots(page)
    page.fill('[name="environment.gravity"]', "30")
    wait_for_next_shot(page, count)
    assert "unset" not in row(page, "environment.gravity").get_attribute("class")
    assert page.evaluate("window.workbench.state.design.environment.gravity") == pytest.approx(30 * FOOT)
    page.get_by_test_id("units").select_option("metric")
    context.close()


def test_the_what_ifs_loads_are_the_servers_named_as_on_the_machine_on_screen(page, server):
    """The load list: every peak load the server names (``analytic.result.PEAK_NAMES``), with its unit;
    a fixed machine's hinge load is its mount's."""
    open_page(page, server)
    options = lambda: page.locator("#whatif-load option").all_inner_texts()   # noqa: E731
    values = page.evaluate("[...document.querySelectorAll('#whatif-load option')].map((o) => o.value)")
    assert values == list(PEAK_NAMES)
    assert options()[:2] == ["peak axle load (N)", "peak hinge load (N)"]
    assert "peak projectile acceleration (g)" in options() and "peak arm bending moment (N m)" in options()
    page.get_by_test_id("whatif-load").select_option("peak_hinge_load")
    page.get_by_test_id("units").select_option("imperial")
    assert options()[:2] == ["peak axle load (lbf)", "peak hinge load (lbf)"]
    page.goto("about:blank")   # a new page: a link that differs only after its "#" loads nothing
    page.goto(share_link(server, json.loads(json.dumps(design_to_dict(bolted(load_design(TABLE3_FILE)))))))
    page.wait_for_function("Number(document.body.dataset.shots || 0) >= 1", timeout=TOOL_WAIT)
    assert options()[1] == "peak mount load (lbf)"
    page.get_by_test_id("units").select_option("metric")


@pytest.mark.slow
def test_the_front_plots_axes_are_titled_in_the_pages_units_and_redrawn_when_they_change(browser, server):
    """The front of range against peak axle load: each axis a title with its unit, ticks, and after a
    switch to imperial the same points on axes in feet and pounds-force."""
    context = browser.new_context(viewport={"width": 1400, "height": 900})
    context.add_init_script(RECORD_CANVAS_TEXTS)
    page = context.new_page()
    open_page(page, server)
    page.get_by_test_id("optimise-generations").fill(str(TEST_GENERATIONS))
    page.get_by_test_id("front").click()
    plot = page.get_by_test_id("front-plot")
    plot.wait_for(state="visible", timeout=TOOL_WAIT)
    texts = lambda: [t["text"] for t in page.evaluate("window.canvasTexts")["front-plot"]]   # noqa: E731
    assert "range (m)" in texts() and "peak axle load (N)" in texts()
    ticks = [float(t) for t in texts() if t.replace(".", "", 1).lstrip("-").isdigit()]
    assert len(ticks) >= 4, texts()
    points = json.loads(plot.get_attribute("data-points"))
    page.get_by_test_id("units").select_option("imperial")
    assert "range (ft)" in texts() and "peak axle load (lbf)" in texts()
    # The same machines, the same places: each axis's span scales with its unit.
    moved = json.loads(plot.get_attribute("data-points"))
    assert [c for p in moved for c in p] == pytest.approx([c for p in points for c in p], abs=1e-6)
    cells = page.locator("#optimise-table td:nth-child(2)").all_inner_texts()
    assert cells and all(cell.endswith(" ft") for cell in cells), cells
    page.get_by_test_id("stage").scroll_into_view_if_needed()
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.locator("#tools").screenshot(path=SHOTS / "desktop-imperial-front-axes.png")
    page.get_by_test_id("units").select_option("metric")
    context.close()


@pytest.mark.slow
@pytest.mark.parametrize("layout", list(LAYOUTS))
def test_the_firing_table_in_feet_and_a_setting_adopted(browser, server, layout):
    """On the default design, imperial: three targets in feet, the release angle for each in degrees, the
    projectile's mass in pounds; a setting clicked lands on its target; the table redrawn in metres after
    a switch of units."""
    context = browser.new_context(viewport={"width": LAYOUTS[layout][0], "height": LAYOUTS[layout][1]})
    page = context.new_page()
    open_page(page, server)
    page.get_by_test_id("units").select_option("imperial")
    # the tools' boxes keep what was typed, in feet: the page's 20 m target is 65.62 ft
    assert page.get_by_test_id("firing-from").input_value() == "65.62"
    page.get_by_test_id("firing-from").fill(str(TARGETS_FT[0]))
    page.get_by_test_id("firing-to").fill(str(TARGETS_FT[-1]))
    page.get_by_test_id("firing-steps").fill(str(len(TARGETS_FT)))
    page.get_by_test_id("firing-field").select_option("machine.release_angle")
    page.get_by_test_id("firing").click()
    table = page.get_by_test_id("firing-table")
    table.wait_for(state="visible", timeout=TOOL_WAIT)
    assert table.locator("caption").inner_text() == "machine.release_angle (deg) to land on each target"
    targets = table.locator("tr th:first-child").all_inner_texts()[1:]
    assert targets == [f"{t:.1f} ft" for t in TARGETS_FT]
    # Table III's projectile, 0.0456 kg (analytic/data/paper_table3.toml), in pounds
    assert table.locator("tr").first.locator("th").nth(1).inner_text() == f"{0.0456 / POUND:.3f} lb"
    settings = table.locator("tr").last.locator("button")
    assert settings.count() >= 1
    angle = float(settings.first.inner_text())
    assert 0 < angle < 89
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.locator("#tools").screenshot(path=SHOTS / f"{layout}-imperial-firing-table.png")
    count = shots(page)
    settings.first.click()
    wait_for_next_shot(page, count)
    wait_until_current(page)
    feet, unit = range_shown(page)
    assert unit == "ft" and feet == pytest.approx(TARGETS_FT[-1], abs=LANDS_WITHIN_FT)
    assert page.evaluate("window.workbench.state.design.machine.release_angle") == pytest.approx(angle, abs=0.05)
    page.get_by_test_id("units").select_option("metric")
    targets = table.locator("tr th:first-child").all_inner_texts()[1:]
    assert targets == [f"{t * FOOT:.1f} m" for t in TARGETS_FT]
    context.close()
