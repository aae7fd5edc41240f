"""The workbench as a builder's bench, in a real browser: the stage frames the machine on every preset,
every number on an imperial page is in feet and pounds, and fields a choice leaves without effect are
disabled with the reason.

Runs as ``tests/test_workbench_browser.py`` does (Debian's chromium through Playwright, the server as a
child process); screenshots go to ``out/workbench/``.
"""

from __future__ import annotations

import json
import math
import re

import pytest

from test_workbench_browser import (CHROMIUM, SHOTS, SHOT_WAIT, TOOL_WAIT, base_url, browser_type_launch_args,  # noqa: F401
                                    open_page, range_shown, server, shots, wait_for_next_shot, wait_until_current)
from workbench.presets import PRESETS

pytestmark = pytest.mark.skipif(not __import__("pathlib").Path(CHROMIUM).exists(),
                                reason="needs Debian's chromium (make test installs it)")

LAYOUTS = {"desktop": (1400, 900), "phone": (390, 844)}
#: The least share of the stage's height the arm (long and short, end to end) is drawn at through the swing.
ARM_SHARE = 0.1
#: Moments of the swing the framing is checked at, as fractions of its last sample's time (release).
SWING = (0.0, 0.25, 0.5, 0.75, 1.0)
#: The stage's arm colour (stage.js ``COLORS.arm``, #6b4226).
ARM_RGB = (0x6b, 0x42, 0x26)


def select_preset(page, name: str) -> None:
    count = shots(page)
    page.get_by_test_id("preset").select_option(name)
    wait_for_next_shot(page, count)
    wait_until_current(page)


def draw_at(page, t: float) -> dict:
    """Draws the stage at ``t``; its main view ({scale, x0, y0}), its inset's box and its size, px."""
    return page.evaluate(f"""(() => {{ window.workbench.state.t = {t}; window.workbench.draw();
      const c = document.getElementById("stage");
      return {{view: JSON.parse(c.dataset.view), inset: c.dataset.inset ? JSON.parse(c.dataset.inset) : null,
               width: c.width, height: c.height}}; }})()""")


def parts_at(history: dict, t: float) -> dict[str, tuple[float, float]]:
    """Each drawn part's place at the last sample at or before ``t`` (m; the frame's shift added), and the pivot's."""
    i = max(k for k, tk in enumerate(history["t"]) if tk <= t + 1e-12)
    shift = history["frame_x"][i]
    parts = {name: (p[i][0] + shift, p[i][1]) for name, p in history["parts"].items()}
    parts["pivot"] = (shift, 0.0)
    return parts


@pytest.mark.parametrize("preset", list(PRESETS))
def test_the_default_camera_frames_the_whole_machine_through_the_swing(page, server, preset):
    """Every part of the machine inside the stage and clear of the inset, the arm at least ``ARM_SHARE``
    of the stage's height, at each moment of ``SWING``; the positions from the shot's own history, the
    drawing's scale from the stage (``data-view``)."""
    open_page(page, server)
    select_preset(page, preset)
    assert page.get_by_test_id("camera").input_value() == "auto"
    shot = page.evaluate("window.workbench.state.shot")
    machine = page.evaluate("window.workbench.state.design.machine")
    arm = machine["arm_long"] + machine["arm_short"]
    for fraction in SWING:
        t = fraction * shot["history"]["t"][-1]   # the swing's samples end at release
        drawn = draw_at(page, t)
        view, inset = drawn["view"], drawn["inset"]
        assert arm * view["scale"] >= ARM_SHARE * drawn["height"], (preset, fraction, arm * view["scale"])
        assert inset is not None and inset["shows"] == "field"
        for name, (x, y) in parts_at(shot["history"], t).items():
            px, py = view["x0"] + view["scale"] * x, view["y0"] - view["scale"] * y
            assert 0 <= px <= drawn["width"] and 0 <= py <= drawn["height"], (preset, fraction, name, px, py)
            under_inset = (inset["x"] <= px <= inset["x"] + inset["width"]
                           and inset["y"] <= py <= inset["y"] + inset["height"])
            assert not under_inset, (preset, fraction, name, px, py, inset)


def arm_extent(page, inset: dict | None) -> float:
    """The diagonal of the box round the stage's arm-coloured pixels outside the inset, px."""
    r, g, b = ARM_RGB
    skip = json.dumps(inset)
    return page.evaluate(f"""(() => {{
  const c = document.getElementById("stage"), d = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
  const inset = {skip};
  let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
  for (let y = 0; y < c.height; y++) for (let x = 0; x < c.width; x++) {{
    if (inset && x >= inset.x && x <= inset.x + inset.width && y >= inset.y && y <= inset.y + inset.height) continue;
    const i = 4 * (y * c.width + x);
    if (Math.abs(d[i] - {r}) < 10 && Math.abs(d[i + 1] - {g}) < 10 && Math.abs(d[i + 2] - {b}) < 10) {{
      x0 = Math.min(x0, x); x1 = Math.max(x1, x); y0 = Math.min(y0, y); y1 = Math.max(y1, y); }}
  }}
  return x1 < x0 ? 0 : Math.hypot(x1 - x0, y1 - y0);
}})()""")


@pytest.mark.parametrize("layout", list(LAYOUTS))
def test_the_warwolfs_arm_is_drawn_a_tenth_of_the_stage_tall_through_the_swing(browser, server, layout):
    """Counted on the canvas's pixels: the arm's colour spans at least ``ARM_SHARE`` of the stage's height
    at the default camera, mid-swing and at release; after landing the field fills the stage and the
    machine is in the inset (screenshots ``warwolf-*-stage.png``)."""
    width, height = LAYOUTS[layout]
    context = browser.new_context(viewport={"width": width, "height": height})
    page = context.new_page()
    open_page(page, server)
    select_preset(page, "warwolf-scale")
    release = page.evaluate("window.workbench.state.shot.release_time")
    SHOTS.mkdir(parents=True, exist_ok=True)
    for moment, t in (("mid-swing", 0.6 * release), ("release", release)):
        drawn = draw_at(page, t)
        extent = arm_extent(page, drawn["inset"])
        assert extent >= ARM_SHARE * drawn["height"], (moment, extent, drawn["height"])
        page.get_by_test_id("stage").screenshot(path=SHOTS / f"warwolf-{layout}-{moment}-stage.png")
    landed = draw_at(page, page.evaluate("window.workbench.state.shot.landing_time"))
    assert landed["inset"]["shows"] == "machine"
    # the whole flight in the main view: the range (584 m) across most of the stage
    assert landed["view"]["scale"] * page.evaluate("window.workbench.state.shot.range") > 0.5 * landed["width"]
    page.get_by_test_id("stage").screenshot(path=SHOTS / f"warwolf-{layout}-landed-stage.png")
    context.close()


#: Records the texts drawn on each canvas (since its last full clear) with the font's size on screen.
RECORD_CANVAS_TEXTS = """(() => {
  const fill = CanvasRenderingContext2D.prototype.fillText, clear = CanvasRenderingContext2D.prototype.clearRect;
  window.canvasTexts = {};
  CanvasRenderingContext2D.prototype.clearRect = function (x, y, w, h) {
    if (x <= 0 && y <= 0 && w >= this.canvas.width && h >= this.canvas.height) window.canvasTexts[this.canvas.id] = [];
    return clear.apply(this, arguments);
  };
  CanvasRenderingContext2D.prototype.fillText = function (text) {
    const c = this.canvas, px = parseFloat(this.font) * (c.clientWidth || c.width) / c.width;
    (window.canvasTexts[c.id] ||= []).push({text: String(text), px});
    return fill.apply(this, arguments);
  };
})();"""

#: A number followed by a unit of the SI (what the library writes), the unit ending the word.
SI_NUMBER = re.compile(r"\d\s?(?:kg m\^?2|kg m²|kg/m\^?3|kg/m³|m/s\^?2|m/s²|m/s|N m|Pa s|kg|N|J|m)(?![\w/²³^])")
#: The type's least size on screen in the plots, CSS px.
READABLE_PX = 12


def warwolf_cross_checked_in_feet(browser, server, viewport: tuple[int, int], init_script: str = ""):
    """A page (and its context) of the given size, imperial, the Warwolf on it and cross-checked."""
    context = browser.new_context(viewport={"width": viewport[0], "height": viewport[1]})
    if init_script:
        context.add_init_script(init_script)
    page = context.new_page()
    open_page(page, server)
    page.get_by_test_id("units").select_option("imperial")
    select_preset(page, "warwolf-scale")
    page.get_by_test_id("crosscheck").click()
    table = page.get_by_test_id("crosscheck-table")
    table.wait_for(state="visible", timeout=TOOL_WAIT)
    return context, page, table


def every_text(page) -> str:
    """The page's visible text, its controls' values and titles, and the texts drawn on its canvases."""
    return page.evaluate("""(() => [document.body.innerText,
      ...[...document.querySelectorAll("[title]")].map((e) => e.title),
      ...Object.values(window.canvasTexts).flat().map((t) => t.text)].join("\\n"))()""")


@pytest.mark.slow
def test_no_si_number_on_an_imperial_page(browser, server, tmp_path):
    """The Warwolf on the imperial page through every panel: the readouts, the stage, the cross-check's
    table, the what-if and front plots (their drawn texts), the optimiser's table, a field's error, a
    warning and a shot's message: no number in an SI unit, and feet and pounds-force where lengths and
    forces are shown."""
    context, page, _ = warwolf_cross_checked_in_feet(browser, server, LAYOUTS["desktop"], RECORD_CANVAS_TEXTS)
    units = dict(zip(*[page.locator(f"#crosscheck-table td:nth-child({n})").all_inner_texts() for n in (1, 2)]))
    assert units["range"] == "ft" and units["peak axle load"] == "lbf" and units["release speed"] == "ft/s"
    assert units["launch angle"] == "deg"
    page.get_by_test_id("whatif").click()
    page.get_by_test_id("whatif-plot").wait_for(state="visible", timeout=TOOL_WAIT)
    page.get_by_test_id("front").click()
    page.get_by_test_id("front-plot").wait_for(state="visible", timeout=TOOL_WAIT)
    page.wait_for_function("document.getElementById('optimise-table').rows.length > 1", timeout=TOOL_WAIT)
    plotted = page.evaluate("window.canvasTexts")
    for plot in ("whatif-plot", "front-plot"):
        texts = [t["text"] for t in plotted[plot]]
        assert "range (ft)" in texts, (plot, texts)
        assert min(t["px"] for t in plotted[plot]) >= READABLE_PX, (plot, plotted[plot])
    assert any(t.endswith("(lbf)") for t in (t["text"] for t in plotted["whatif-plot"]))
    assert "peak axle load (lbf)" in [t["text"] for t in plotted["front-plot"]]
    page.get_by_test_id("units").select_option("metric")   # back and forth: the tools' results redrawn
    page.get_by_test_id("units").select_option("imperial")
    text = every_text(page)
    assert SI_NUMBER.search(text) is None, SI_NUMBER.search(text)
    assert " ft" in text and " lbf" in text
    # A warning (the counterweight beyond the largest built: analytic.plausibility), in pounds.
    count = shots(page)
    page.fill('[name="machine.counterweight_mass"]', "2000000")
    wait_for_next_shot(page, count)
    warnings = page.get_by_test_id("warnings").inner_text()
    assert "machine.counterweight_mass = 2000000 lb is beyond" in warnings, warnings
    page.fill('[name="machine.counterweight_mass"]', "44092.5")
    # A refused value, echoed in feet as typed; a shot short of its raised target, its message in feet.
    page.fill('[name="machine.sling_length"]', "-2")
    error = page.locator('.field[data-field="machine.sling_length"] .error')
    error.wait_for(state="visible", timeout=SHOT_WAIT)
    assert error.inner_text().startswith("machine.sling_length = -2 ft: ")
    page.fill('[name="machine.sling_length"]', "32.8084")
    page.locator("#fields > details", has=page.locator('[name="environment.target_height"]')).locator("summary").first.click()
    count = shots(page)
    page.fill('[name="environment.target_height"]', "3000")
    wait_for_next_shot(page, count)
    wait_until_current(page)
    assert page.get_by_test_id("status").inner_text() == "short_of_target"
    assert " ft" in page.get_by_test_id("message").inner_text()
    text = every_text(page)
    assert SI_NUMBER.search(text) is None, SI_NUMBER.search(text)
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=SHOTS / "desktop-imperial-every-panel.png", full_page=True)
    page.get_by_test_id("units").select_option("metric")
    context.close()


@pytest.mark.slow
@pytest.mark.parametrize("layout", list(LAYOUTS))
def test_the_cross_check_table_fits_its_panel_in_feet(browser, server, layout):
    """Every cell of the table inside the tools panel, none cut off at its right edge, a verdict on
    each quantity (screenshots ``*-crosscheck-table.png``)."""
    width = LAYOUTS[layout][0]
    context, page, table = warwolf_cross_checked_in_feet(browser, server, LAYOUTS[layout])
    panel = page.evaluate("""(() => { const s = document.getElementById("tools"), r = s.getBoundingClientRect(),
      pad = parseFloat(getComputedStyle(s).paddingRight); return r.right - pad; })()""")
    rightmost = page.evaluate("Math.max(...[...document.querySelectorAll('#crosscheck-table td, #crosscheck-table th')]"
                              ".map((c) => c.getBoundingClientRect().right))")
    assert rightmost <= panel + 0.5, (rightmost, panel)
    assert page.evaluate("document.documentElement.scrollWidth") <= width
    verdicts = page.locator("#crosscheck-table td:last-child").all_inner_texts()
    assert verdicts and set(verdicts) <= {"agree", "sensitive", "DIFFER"}
    SHOTS.mkdir(parents=True, exist_ok=True)
    table.screenshot(path=SHOTS / f"{layout}-crosscheck-table.png")
    page.get_by_test_id("units").select_option("metric")
    context.close()


def row(page, field: str):
    return page.locator(f'.field[data-field="{field}"]')


def applies(page, field: str) -> bool:
    """Whether the field's row takes input; a row that does not says why."""
    r = row(page, field)
    enabled = r.locator("input, select").first.is_enabled()
    note = r.locator(".note")
    assert note.is_hidden() == enabled, field
    return enabled


def choose(page, field: str, value: str) -> None:
    count = shots(page)
    page.select_option(f'[name="{field}"]', value)
    wait_for_next_shot(page, count)
    wait_until_current(page)


def test_fields_a_choice_makes_irrelevant_are_disabled_with_the_reason_and_come_back(page, server):
    """analytic/design.py's rules, each way: the drag law and its coefficient, viscosity and air; the
    machine's kind and the hinge's and the slides' frictions; a floating arm's frame that cannot roll;
    a rolling frame's mass. Values the design contract refuses under the new choice are set aside
    (the shot stays ok) and come back with the choice."""
    open_page(page, server)
    for table in ("Projectile", "Environment", "Base", "Losses"):
        box = page.locator("#fields > details", has=page.locator("summary", has_text=table))
        if box.get_attribute("open") is None:
            box.locator("summary").first.click()
    design = lambda: page.evaluate("window.workbench.state.design")   # noqa: E731
    choose(page, "projectile.drag", "smooth-sphere")
    assert not applies(page, "projectile.drag_coefficient")
    assert "constant drag law" in row(page, "projectile.drag_coefficient").locator(".note").inner_text()
    assert applies(page, "environment.air_viscosity") and applies(page, "projectile.drag_factor")
    page.select_option('[name="projectile.drag"]', "constant")   # no coefficient yet: asked for at its field
    error = row(page, "projectile.drag_coefficient").locator(".error")
    error.wait_for(state="visible", timeout=SHOT_WAIT)
    assert "required" in error.inner_text()
    assert applies(page, "projectile.drag_coefficient") and not applies(page, "environment.air_viscosity")
    count = shots(page)
    page.fill('[name="projectile.drag_coefficient"]', "0.5")
    wait_for_next_shot(page, count)
    choose(page, "projectile.drag", "none")
    assert "drag_coefficient" not in design()["projectile"]
    assert page.get_by_test_id("status").inner_text() == "ok"
    for field in ("projectile.drag_coefficient", "projectile.drag_factor", "environment.air_density",
                  "environment.air_viscosity", "environment.wind_speed"):
        assert not applies(page, field), field
    choose(page, "projectile.drag", "constant")
    assert design()["projectile"]["drag_coefficient"] == 0.5   # set aside, and back
    choose(page, "projectile.drag", "smooth-sphere")
    # The hinge's friction, set on the hinged machine, set aside on a fixed one and back.
    assert not applies(page, "losses.hinge_radius")   # no hinge friction yet: nothing for a radius to do
    page.fill('[name="losses.hinge_friction"]', "0.2")
    assert applies(page, "losses.hinge_radius")   # a friction given: its radius matters (and is asked for)
    count = shots(page)
    page.fill('[name="losses.hinge_radius"]', "0.01")
    wait_for_next_shot(page, count)
    wait_until_current(page)
    assert page.get_by_test_id("status").inner_text() == "ok"
    assert not applies(page, "losses.guide_friction") and "floating-arm" in row(
        page, "losses.guide_friction").locator(".note").inner_text()
    choose(page, "machine.kind", "fixed")
    assert page.get_by_test_id("status").inner_text() == "ok"
    assert "hinge_friction" not in design()["losses"] and not applies(page, "losses.hinge_friction")
    assert row(page, "machine.counterweight_link").is_hidden()
    choose(page, "machine.kind", "floating-arm")
    assert applies(page, "losses.guide_friction") and applies(page, "losses.track_static_friction")
    assert not applies(page, "base.mobility")
    assert "cannot roll" in row(page, "base.mobility").locator(".note").inner_text()
    choose(page, "machine.kind", "hinged")
    assert design()["losses"]["hinge_friction"] == 0.2 and applies(page, "losses.hinge_friction")
    assert row(page, "machine.counterweight_link").is_visible()
    assert page.get_by_test_id("status").inner_text() == "ok"
    # The aim and the what-if cannot pick a field that does not apply.
    assert page.locator('#aim-field option[value="projectile.drag_coefficient"]').is_disabled()
    # A rolling frame's mass.
    assert not applies(page, "base.mass")
    page.select_option('[name="base.mobility"]', "rolling")
    assert applies(page, "base.mass")
    page.select_option('[name="base.mobility"]', "fixed")
    assert not applies(page, "base.mass")
    SHOTS.mkdir(parents=True, exist_ok=True)
    page.screenshot(path=SHOTS / "desktop-only-what-applies.png", full_page=True)


def test_the_camera_choices_keep_their_views(page, server):
    """"machine" keeps the machine's view after release (the field in its inset); "field" and "follow"
    have no inset."""
    open_page(page, server)
    landing = page.evaluate("window.workbench.state.shot.landing_time")
    for camera, inset in (("machine", "field"), ("field", None), ("follow", None), ("auto", "machine")):
        page.get_by_test_id("camera").select_option(camera)
        drawn = draw_at(page, landing)
        assert (drawn["inset"] or {}).get("shows") == inset, camera
    machine = page.evaluate("window.workbench.state.design.machine")
    page.get_by_test_id("camera").select_option("machine")
    drawn = draw_at(page, landing)
    assert drawn["view"]["scale"] * (machine["arm_long"] + machine["arm_short"]) >= ARM_SHARE * drawn["height"]
    assert math.isfinite(drawn["view"]["x0"])
