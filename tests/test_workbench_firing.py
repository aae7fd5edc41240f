"""The page's firing-table tool (``workbench.tools.firing``) through the API: its settings land, bad input is named."""

from __future__ import annotations

import json
import time

import pytest

from analytic.aim import AIM_TOLERANCE
from analytic.design_file import default_design, design_to_dict
from analytic.fields import field
from analytic.reference import simulate
from support import page_client


@pytest.fixture(scope="module")
def client():
    return page_client()


def _run(client, inputs):
    body = {"tool": "firing_table", "design": json.loads(json.dumps(design_to_dict(default_design()))),
            "inputs": inputs, "client": "firing"}
    job = client.post("/api/jobs", json=body).json()
    while job["state"] == "running":
        time.sleep(0.05)
        job = client.get(f"/api/jobs/{job['id']}").json()
    return job


def test_the_pages_firing_table_lands_each_setting_within_a_millimetre(client):
    job = _run(client, {"field": "machine.counterweight_mass", "targets": [25.0, 35.0, 2], "masses": [0.08, 0.1, 2]})
    assert job["state"] == "done", job["error"]
    rows = job["result"]["rows"]
    assert len(rows) == 4 and all(r["status"] == "ok" for r in rows)
    design = default_design()
    for r in rows:
        (value,) = r["values"]
        shot = simulate(field("machine.counterweight_mass").replace(
            field("projectile.mass").replace(design, r["projectile_mass"]), value), histories=False, loads=False)
        assert abs(shot.range - r["target"]) <= AIM_TOLERANCE


@pytest.mark.parametrize("inputs, named", [
    pytest.param({"targets": [30.0, 20.0, 3]}, "targets", id="from-above-to"),
    pytest.param({"targets": [20.0, 30.0, 0]}, "targets", id="no-steps"),
    pytest.param({"targets": [20.0, 30.0, 3], "masses": [-0.1, 0.1, 2]}, "masses", id="negative-mass"),
    pytest.param({"targets": [20.0, 30.0, 3], "field": "machine.nope"}, "field", id="unknown-field"),
])
def test_bad_firing_table_inputs_are_named(client, inputs, named):
    job = _run(client, inputs)
    assert job["state"] == "error" and job["error"]["field"] == named, job
