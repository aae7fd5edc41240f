"""The page shows the server's rules: its readouts are the shot's summary rows in the user's units, and
the energy bar's parts add up to the energy released (Debian's chromium through Playwright)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import tomli_w

from analytic.design_file import design_to_dict
from support import sling_designs
from test_workbench_browser import CHROMIUM, SHOT_WAIT, base_url, browser_type_launch_args, open_page, server  # noqa: F401

SHOTS = Path(__file__).resolve().parents[1] / "out" / "workbench"
#: 1 lbf = 0.45359237 kg x 9.80665 m/s^2 = 4.4482216152605 N (both exact by definition).
NEWTONS_PER_LBF = 4.4482216152605
#: The bar's shares, %, add up to 100 within the audit's closure (``tests/test_workbench_rules.py``' BAR_TOL).
BAR_TOL_PERCENT = 100 * 3e-7
#: The browser keeps six significant digits of a CSS width: a share under 100 % is off by at most 5e-5 %.
CSS_ROUNDING_PERCENT = 5e-5

pytestmark = pytest.mark.skipif(not Path(CHROMIUM).exists(), reason="needs Debian's chromium (make test installs it)")


def test_the_readouts_are_the_shots_summary_rows_in_the_users_units(page, server):
    open_page(page, server)
    rows = page.evaluate("window.workbench.state.shot.summary")
    shown = page.evaluate("[...document.querySelectorAll('#all-numbers dt')].map((dt) => dt.textContent)")
    assert shown == [row["label"] for row in rows]
    brief = page.evaluate("[...document.querySelectorAll('#numbers dt')].map((dt) => dt.textContent)")
    assert brief == [row["label"] for row in rows if row["brief"]]
    axle = next(row for row in rows if row["key"] == "peak_axle_load")
    value = "[...document.querySelectorAll('#numbers dt')].find((dt) => dt.dataset.key === '%s').nextElementSibling.textContent"
    assert page.evaluate(value % "peak_axle_load") == f"{axle['value']:.1f} N"
    page.get_by_test_id("units").select_option("imperial")
    assert page.evaluate(value % "peak_axle_load") == f"{axle['value'] / NEWTONS_PER_LBF:.1f} lbf"
    accel = next(row for row in rows if row["key"] == "peak_projectile_acceleration")
    assert page.evaluate(value % "peak_projectile_acceleration") == f"{accel['value']:.1f} g"
    page.get_by_test_id("units").select_option("metric")


def test_the_energy_bar_adds_up_on_a_floating_arm_with_guide_and_track_friction(page, server, tmp_path):
    path = tmp_path / "floating-lossy.toml"
    path.write_text(tomli_w.dumps(json.loads(json.dumps(design_to_dict(sling_designs()["sling-floating-lossy"])))))
    open_page(page, server)
    count = int(page.evaluate("document.body.dataset.shots"))
    page.get_by_test_id("upload").set_input_files(str(path))
    page.wait_for_function(f"Number(document.body.dataset.shots) > {count}", timeout=SHOT_WAIT)
    assert page.get_by_test_id("status").inner_text() == "ok"
    parts = page.evaluate("[...document.querySelectorAll('#energy span')].map((s) => "
                          "[s.dataset.part, parseFloat(s.style.width), s.title])")
    names = [name for name, _, _ in parts]
    assert {"guide", "track", "axle", "projectile", "kept"} <= set(names), parts
    assert abs(sum(width for _, width, _ in parts) - 100.0) <= BAR_TOL_PERCENT + len(parts) * CSS_ROUNDING_PERCENT, parts
    assert any(title.startswith("guide friction: ") for _, _, title in parts)
    page.get_by_test_id("energy").screenshot(path=str(SHOTS / "energy-floating-lossy.png"))
    page.screenshot(path=str(SHOTS / "readouts-floating-lossy.png"), full_page=True)
