"""One source for each rule: the page's summary rows are the text report's, and its energy bar draws every loss."""

from __future__ import annotations

import json
import math

import pytest

from analytic.design_file import default_design, design_to_dict
from analytic.reference import simulate
from analytic.report import format_shot
from analytic.summary import LOSS_LABELS
from support import bolted, page_client, sling_designs

#: The bar's parts share out the energy released to the audit's closure: as
#: ``tests/test_workbench_api.py``'s ``BAR_TOL`` (ten times the drag before release's 2.9e-8).
BAR_TOL = 3e-7
#: The compiled path's shot agrees with the reference's to 1e-7 (``tests/test_analytic_fast.py``).
PATHS_TOL = 1e-6


@pytest.fixture(scope="module")
def client():
    return page_client()


def tables(design) -> dict:
    return json.loads(json.dumps(design_to_dict(design)))


def floating_with_guide_and_track(design=None):
    """The Table III floating arm with friction at its axle, guide and track (``support.sling_designs``)."""
    return sling_designs()["sling-floating-lossy"]


def report_labels(shot) -> list[str]:
    """The labels of ``python -m analytic simulate``'s table, as printed."""
    return [line.strip().split("  ")[0] for line in format_shot(shot).splitlines()[2:] if line.startswith("  ")]


@pytest.mark.parametrize("name", ["paper-table3", "fixed", "sling-floating-lossy", "sling-swing-drag"])
def test_the_pages_rows_are_the_text_reports_in_its_order(client, name):
    """Each row the page receives is a row of the text report, in the same order and with the same
    value as the reference shot's (the page's shot is the compiled path's); the report's rows the page
    lacks are the ones the compiled shot does not sample."""
    design = {"paper-table3": default_design(), "fixed": bolted(default_design()), **sling_designs()}[name]
    answer = client.post("/api/shot", json={"design": tables(design)}).json()
    reference = simulate(design)
    printed = report_labels(reference)
    rows = answer["summary"]
    labels = [row["label"] for row in rows]
    assert [label for label in printed if label in labels] == labels
    assert set(printed) - set(labels) <= {"min sling tension", "track force, min", "track force, max",
                                         "max guide force"}
    for row in rows:
        if row["key"].startswith("energy.") or row["key"] == "release_pin":
            continue
        expected = getattr(reference, row["key"]) if hasattr(reference, row["key"]) else None
        if row["key"] == "launch_angle":
            expected = math.degrees(expected)
        elif row["unit"] == "%":
            expected = 100 * expected
        elif row["unit"] == "g":   # the acceleration in g: times the design's gravity, m/s^2
            expected = expected / design.environment.gravity
        assert row["value"] == pytest.approx(expected, rel=PATHS_TOL, abs=1e-9), row
    assert ("peak mount load" in labels) == (design.machine.kind != "hinged")
    assert ("peak hinge load" in labels) == (design.machine.kind == "hinged")


def test_the_energy_bar_on_a_floating_arm_with_guide_and_track_friction_adds_up(client):
    """The parts the page's bar draws share out the energy released, each once, with the guide's and
    the track's friction among them (under-counted when the bar drew only the hinged machine's losses)."""
    design = floating_with_guide_and_track()
    assert design.losses.guide_friction > 0 and design.losses.track_friction > 0
    energy = client.post("/api/shot", json={"design": tables(design)}).json()["history"]["energy"]
    parts = {part["name"]: part for part in energy["parts"]}
    assert {"guide", "track", "axle"} <= set(parts)
    assert parts["guide"]["joules"] > 0 and parts["track"]["joules"] > 0
    assert parts["guide"]["label"] == LOSS_LABELS["guide"] and parts["track"]["label"] == LOSS_LABELS["track"]
    total = sum(part["joules"] for part in energy["parts"])
    assert abs(total - energy["released"]) <= BAR_TOL * energy["released"], (total, energy)
    assert all(part["joules"] >= 0 for part in energy["parts"])


def test_a_what_if_of_the_projectiles_acceleration_is_in_g(client):
    import time

    inputs = {"field": "machine.sling_length", "low": 0.5, "high": 0.9, "steps": 3, "load": "peak_projectile_acceleration"}
    job = client.post("/api/jobs", json={"tool": "what_if", "design": tables(default_design()), "inputs": inputs}).json()
    while job["state"] == "running":
        time.sleep(0.05)
        job = client.get(f"/api/jobs/{job['id']}").json()
    result = job["result"]
    assert result["load_kind"] == "g" and result["load_label"] == "peak projectile acceleration"
    gravity = default_design().environment.gravity
    assert [g * gravity for g in result["loads_shown"]] == pytest.approx(result["loads"], rel=1e-12)
