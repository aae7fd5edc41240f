"""The workbench's server, without a browser: its API answers as the contract says, and refuses bad requests."""

from __future__ import annotations

import json
import re
import socket
import subprocess
import sys
import time

import numpy as np
import pytest

from analytic.design_file import default_design, design_to_dict
from analytic.reference import simulate
from analytic.result import JSON_KEYS
from workbench import jobs
from workbench.app import MAX_BODY
from support import page_client
from workbench.presets import PRESETS


#: What the page sends with every POST.
JSON = {"content-type": "application/json"}


@pytest.fixture(scope="module")
def client():
    return page_client()


#: ``simulate --json`` keys the page's compiled shot leaves null (``workbench.shot.shot_json``).
NOT_SAMPLED = {"min_sling_tension", "min_ground_force", "max_frame_speed"}


def _approx(value):
    """A ``simulate --json`` value to compare with the compiled path's: texts, flags and nulls exactly,
    numbers to 1e-7 (``tests/test_analytic_fast.py``'s agreement of the two paths)."""
    if value is None or isinstance(value, (str, bool)) or isinstance(value, list) and not value:
        return value
    return pytest.approx(value, rel=1e-7, abs=1e-9)


def tables():
    return json.loads(json.dumps(design_to_dict(default_design())))


def test_shot_answers_the_simulate_json_keys_and_history(client):
    answer = client.post("/api/shot", json={"design": tables()})
    assert answer.status_code == 200
    data = answer.json()
    assert set(data) == set(JSON_KEYS) | {"history", "summary"}
    # The numbers of python -m analytic simulate --json (the reference shot, in this process), as
    # closely as the compiled path gives them (``tests/test_analytic_fast.py``: 1e-7 of the range);
    # the keys the compiled path does not sample are null.
    expected = json.loads(json.dumps(simulate(default_design()).to_json()))
    for key in JSON_KEYS:
        if key in NOT_SAMPLED:
            assert data[key] is None, key
        else:
            assert data[key] == _approx(expected[key]), key
    history = data["history"]
    assert len(history["t"]) == len(history["parts"]["projectile"]) == len(history["frame_x"])
    # The last flight sample is the landing point (within the history's rounding to 10 um).
    assert history["flight_path"][-1][0] == pytest.approx(data["range"], abs=1e-5)


def test_shot_takes_values_with_units(client):
    design = tables()
    design["machine"]["sling_length"] = "61 cm"
    answer = client.post("/api/shot", json={"design": design}).json()
    assert answer["range"] == pytest.approx(simulate(default_design()).range, rel=1e-9)


@pytest.mark.parametrize("body, field", [
    ({"design": {"machine": {}}}, "machine.pivot_height"),
    ({"design": "paper"}, "design"),
    ({}, "design"),
    ({"design": {**tables(), "machine": {**tables()["machine"], "sling_length": -1}}}, "machine.sling_length"),
    ({"design": {**tables(), "machine": {**tables()["machine"], "sling_length": "3 kg"}}}, "machine.sling_length"),
    ({"design": {**tables(), "colour": "red"}}, "colour"),
], ids=["missing", "not-a-table", "no-design", "negative", "wrong-unit", "unknown-key"])
def test_invalid_design_is_400_naming_its_field(client, body, field):
    answer = client.post("/api/shot", json=body)
    assert answer.status_code == 400
    assert answer.json()["field"] == field
    assert "Traceback" not in answer.text


def test_malformed_and_oversized_bodies_are_refused(client):
    assert client.post("/api/shot", content=b"{not json", headers=JSON).status_code == 400
    assert client.post("/api/shot", content=b"[1, 2]", headers=JSON).json()["field"] == "body"
    assert client.post("/api/shot", content=b"[" * (MAX_BODY // 2), headers=JSON).status_code == 400   # nested past recursion
    big = client.post("/api/shot", content=b" " * (MAX_BODY + 1), headers=JSON)
    assert big.status_code == 413 and big.json()["field"] == "body"


def test_static_files_stay_in_the_package(client):
    assert client.get("/static/app.js").status_code == 200
    assert client.get("/static/../app.py").status_code == 404
    assert client.get("/static/%2e%2e/app.py").status_code == 404


def test_downloaded_toml_reads_back_to_the_same_design(client, tmp_path):
    from analytic.design_file import load_design

    text = client.post("/api/toml", json={"design": tables()}).text
    path = tmp_path / "design.toml"
    path.write_text(text)
    assert load_design(path).machine == default_design().machine
    back = client.post("/api/read", json={"toml": text}).json()["design"]
    assert back["machine"] == tables()["machine"]


def test_uploaded_bad_toml_names_its_field(client):
    answer = client.post("/api/read", json={"toml": '[machine]\nsling_length = "x"\n'})
    assert answer.status_code == 400 and answer.json()["field"] == "machine.sling_length"
    assert client.post("/api/read", json={"toml": "[[["}).json()["field"] == "file"
    assert client.post("/api/read", json={"file": "[machine]"}).json()["field"] == "toml"


@pytest.mark.parametrize("name", list(PRESETS))
def test_every_preset_throws(client, name):
    preset = next(p for p in client.get("/api/presets").json() if p["name"] == name)
    assert client.post("/api/shot", json={"design": preset["design"]}).json()["status"] == "ok"


def wait(client, job):
    while job["state"] == "running":
        time.sleep(0.05)
        job = client.get(f"/api/jobs/{job['id']}").json()
    return job


def test_best_pin_finds_a_longer_range_than_its_neighbours(client):
    job = wait(client, client.post("/api/jobs", json={"tool": "best_pin", "design": tables(), "client": "a"}).json())
    assert job["state"] == "done"
    best = job["result"]
    # The best pin beats every scanned angle, and a degree either side of it (fast path, same design).
    from analytic.fast import simulate_fast
    from analytic.fields import field

    assert best["range"] >= max(r for r in best["ranges"] if r is not None)
    angle = field("machine.release_angle")
    assert simulate_fast(angle.replace(default_design(), best["value"])).range == pytest.approx(best["range"], rel=1e-12)
    for offset in (-1.0, 1.0):
        assert simulate_fast(angle.replace(default_design(), best["value"] + offset)).range < best["range"]


def test_tool_inputs_are_checked_and_jobs_limited_per_client(client, monkeypatch):
    bad = client.post("/api/jobs", json={"tool": "aim", "design": tables(), "inputs": {"target": -3}})
    job = wait(client, bad.json())
    assert job["state"] == "error" and job["error"]["field"] == "target"
    assert client.post("/api/jobs", json={"tool": "nope", "design": tables()}).status_code == 400
    monkeypatch.setattr(jobs, "JOB_SECONDS", 0.0)   # the time limit stops a job at its first check
    stopped = wait(client, client.post("/api/jobs", json={"tool": "best_pin", "design": tables(),
                                                          "client": "b"}).json())
    assert stopped["state"] == "cancelled"


def test_a_second_job_of_one_client_waits_for_the_first(client):
    slow = {"tool": "what_if", "design": tables(), "client": "c",
            "inputs": {"field": "machine.sling_length", "low": 0.3, "high": 1.2, "steps": 201}}
    first = client.post("/api/jobs", json=slow).json()
    second = client.post("/api/jobs", json=slow)
    assert second.status_code == 429
    cancelled = client.post(f"/api/jobs/{first['id']}/cancel", json={}).json()
    assert cancelled["state"] == "cancelled"


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def test_command_prints_its_url_when_ready_and_warns_off_this_machine():
    port = free_port()
    server = subprocess.Popen([sys.executable, "-m", "workbench", "--port", str(port), "--no-browser",
                               "--host", "localhost"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        line = server.stdout.readline()
        assert re.search(rf"http://localhost:{port}/", line)
        with socket.create_connection(("localhost", port), timeout=5):
            pass   # listening once the line is printed
    finally:
        server.terminate()
        _, err = server.communicate(timeout=10)
    assert "warning: listening on localhost" in err


def test_summary_is_the_fast_paths_with_the_same_keys(client):
    answer = client.post("/api/summary", json={"design": tables()}).json()
    assert set(answer) == set(JSON_KEYS) | {"summary"}
    # The fast path agrees with the reference to its integrator's error (tests/test_analytic_fast.py),
    # far inside the readout's rounding (1 cm of 45 m).
    assert answer["range"] == pytest.approx(simulate(default_design()).range, rel=1e-6)
    assert client.post("/api/summary", json={"design": {"machine": {}}}).status_code == 400


def test_shot_takes_the_pages_spacings_and_gives_the_same_shot_sampled_less_often(client):
    sampling = client.get("/api/meta").json()["sampling"]
    default = client.post("/api/shot", json={"design": tables()}).json()
    coarse = client.post("/api/shot", json={"design": tables(), **sampling}).json()
    assert len(coarse["history"]["t"]) < len(default["history"]["t"]) / 3
    assert len(coarse["history"]["flight_t"]) < len(default["history"]["flight_t"]) / 3
    # the same shot: its summary (the samples are read off the same steps) and its last samples
    assert {k: coarse[k] for k in JSON_KEYS} == {k: default[k] for k in JSON_KEYS}
    for key in ("t", "flight_t", "flight_path"):
        assert coarse["history"][key][-1] == default["history"][key][-1]


@pytest.mark.parametrize("name, value", [("sample_step", 1e-5), ("sample_step", "2 ms"), ("flight_sample_step", 10),
                                         ("flight_sample_step", True)], ids=["fine", "text", "coarse", "bool"])
def test_a_spacing_out_of_bounds_is_400_naming_it(client, name, value):
    answer = client.post("/api/shot", json={"design": tables(), name: value})
    assert answer.status_code == 400
    assert answer.json()["field"] == name and name in answer.json()["error"]


@pytest.mark.parametrize("name", list(PRESETS))
def test_the_pages_spacing_draws_each_preset_within_half_a_pixel(name):
    from analytic.geometry import machine_points
    from workbench.shot import PAGE_FLIGHT_SAMPLE_STEP, PAGE_SAMPLE_STEP

    design = PRESETS[name][1]()
    fine = simulate(design, sampled_loads=False)
    coarse = simulate(design, sample_step=PAGE_SAMPLE_STEP, flight_sample_step=PAGE_FLIGHT_SAMPLE_STEP,
                      sampled_loads=False)
    # Half a pixel of the following camera (stage.js followWindow: 1.6 x 0.8 of arm and sling
    # across) on a stage 900 pixels wide, the desktop's.
    half_pixel = 0.5 * 1.6 * 0.8 * (design.machine.arm_long + design.machine.sling_length) / 900
    drawn, true = machine_points(coarse.history.q, design.machine), machine_points(fine.history.q, design.machine)
    for part in ("long_tip", "short_tip", "counterweight", "projectile"):
        for k in (0, 1):   # the page draws the straight line between two samples
            between = np.interp(fine.history.t, coarse.history.t, drawn[part][:, k])
            assert np.max(np.abs(between - true[part][:, k])) < half_pixel, part
    for k in (0, 1):
        between = np.interp(fine.history.flight_t, coarse.history.flight_t, coarse.history.flight_path[:, k])
        assert np.max(np.abs(between - fine.history.flight_path[:, k])) < half_pixel


def test_the_form_offers_a_trough_and_a_shot_on_one_is_the_reference_shot(client):
    import dataclasses

    from analytic.design import Base

    fields = {row["name"]: row for group in client.get("/api/meta").json()["groups"] for row in group["fields"]}
    assert fields["base.trough_height"]["kind"] == "length"
    design = tables()
    design["base"] = {"trough_height": "20 cm"}
    answer = client.post("/api/shot", json={"design": design}).json()
    expected = simulate(dataclasses.replace(default_design(), base=Base(trough_height=0.2)), histories=False)
    assert answer["range"] == pytest.approx(expected.range, rel=1e-7)
    design["base"] = {"trough_height": "1 m"}   # above the pivot (0.5942 m)
    refused = client.post("/api/shot", json={"design": design})
    assert refused.status_code == 400 and refused.json()["field"] == "base.trough_height"


def test_a_floating_arm_takes_the_bases_friction_on_the_page(client):
    """The page's form shows ``losses.base_friction`` for every kind; a floating arm's is simulated
    (no longer refused), as ``python -m analytic simulate`` throws it."""
    import dataclasses

    from analytic.design import Losses
    from analytic.design_file import load_design
    from support import TABLE3_FLOATING_FILE

    design = dataclasses.replace(load_design(TABLE3_FLOATING_FILE), losses=Losses(base_friction=0.3))
    answer = client.post("/api/shot", json={"design": json.loads(json.dumps(design_to_dict(design)))})
    assert answer.status_code == 200, answer.json()
    assert answer.json()["status"] == "ok"
    assert answer.json()["range"] == _approx(simulate(design).range)


def ideal_tables():
    """The default design under the ideal release rule, as the page sends it (no release angle)."""
    design = tables()
    design["machine"]["release_rule"] = "ideal"
    del design["machine"]["release_angle"]
    return design


def test_the_page_offers_the_ideal_rule_and_shoots_it(client):
    from analytic.fast import simulate_fast
    from analytic.geometry import RELEASE_RULES
    from crosscheck.cases import ideal

    rows = [row for group in client.get("/api/meta").json()["groups"] for row in group["fields"]]
    assert next(r for r in rows if r["name"] == "machine.release_rule")["choices"] == list(RELEASE_RULES)
    answer = client.post("/api/shot", json={"design": ideal_tables()})
    assert answer.status_code == 200
    data = answer.json()
    expected = simulate_fast(ideal(default_design(), "ideal"))
    assert data["status"] == "ok" and data["range"] == _approx(expected.range)
    assert data["launch_angle"] == _approx(np.degrees(expected.launch_angle))
    assert history_lands(data)


def history_lands(data) -> bool:
    """The drawn flight ends at the landing point (within the history's rounding to 10 um)."""
    return abs(data["history"]["flight_path"][-1][0] - data["range"]) <= 1e-5


def test_best_pin_on_an_ideal_design_is_its_launch_angle_without_a_scan(client):
    from analytic.fast import simulate_fast
    from analytic.fields import field

    job = wait(client, client.post("/api/jobs", json={"tool": "best_pin", "design": ideal_tables(),
                                                      "client": "i"}).json())
    assert job["state"] == "done"
    best = job["result"]
    assert best["ideal"] is True and best["values"] == []
    # The pin it gives, under the velocity rule, throws as far (tests/test_analytic_ideal_release.py).
    pinned = field("machine.release_angle").replace(default_design(), best["value"])
    assert simulate_fast(pinned).range == pytest.approx(best["range"], rel=1e-7)


@pytest.mark.parametrize("tool", ["aim", "what_if"])
def test_aim_and_what_if_refuse_the_release_angle_of_an_ideal_design(client, tool):
    inputs = {"field": "machine.release_angle", "target": 30.0, "low": 20.0, "high": 60.0}
    job = wait(client, client.post("/api/jobs", json={"tool": tool, "design": ideal_tables(), "inputs": inputs,
                                                      "client": f"r{tool}"}).json())
    assert job["state"] == "error"
    assert job["error"]["field"] == "field" and "machine.release_angle" in job["error"]["error"]
    assert "release_rule 'ideal'" in job["error"]["error"]


def test_the_form_offers_the_sling_and_pouch_masses_and_a_shot_with_them_is_the_command_lines(client, tmp_path):
    """Both masses are fields of the form, in the masses' units; a design with them shoots, its
    range ``python -m analytic simulate --json``'s for the same design file, and the sling keeps
    the energy the page shows as its share."""
    import tomli_w

    fields = {row["name"]: row for group in client.get("/api/meta").json()["groups"] for row in group["fields"]}
    # in the units of the other masses (kg, or lb on the imperial page)
    assert fields["machine.sling_mass"]["kind"] == fields["machine.pouch_mass"]["kind"] == "mass"
    assert fields["projectile.mass"]["kind"] == fields["machine.counterweight_mass"]["kind"] == "mass"
    design = tables()
    design["machine"].update(sling_mass="30 g", pouch_mass="12 g")
    answer = client.post("/api/shot", json={"design": design})
    assert answer.status_code == 200, answer.json()
    data = answer.json()
    path = tmp_path / "heavy-sling.toml"
    path.write_text(tomli_w.dumps(design))
    done = subprocess.run([sys.executable, "-m", "analytic", "simulate", str(path), "--json"],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    expected = json.loads(done.stdout)
    assert data["status"] == expected["status"] == "ok"
    assert data["range"] == _approx(expected["range"])
    assert data["range"] < client.post("/api/shot", json={"design": tables()}).json()["range"]   # it weighs
    assert data["history"]["energy"]["sling"] > 0.0
    massless = client.post("/api/shot", json={"design": tables()}).json()["history"]["energy"]
    assert massless["sling"] == 0.0


#: The page's energy bar closes to this fraction of the energy released: the sling's energy audit
#: closes to 1e-8 of it (tests/test_analytic_sling_mass.py's AUDIT_TOL), the drag during the swing
#: to 2.9e-8 at the default tolerances (its TOLERANCES, measured); ten times the larger.
BAR_TOL = 3e-7


def _bar_designs() -> dict:
    """The paper's machine, massless, and ``support.sling_designs`` (each kind, rolling, lossy, the swing's
    drag), as the page sends them."""
    from support import sling_designs

    designs = {"paper-table3": default_design(), **sling_designs()}
    return {name: json.loads(json.dumps(design_to_dict(design))) for name, design in designs.items()}


@pytest.mark.parametrize("name", list(_bar_designs()))
def test_the_energy_bars_shares_add_up_to_the_energy_released(client, name):
    """``history.energy``: the projectile's, the sling's and the pouch's, the arm's and counterweight's
    and every loss before release share out what the counterweight and the arm released, each once."""
    data = client.post("/api/shot", json={"design": _bar_designs()[name]}).json()
    assert data["status"] == "ok", data["message"]
    energy, lost = data["history"]["energy"], data["energy_dissipated"]
    shared = energy["projectile"] + energy["sling"] + energy["kept"] + sum(v for k, v in lost.items() if k != "drag")
    assert abs(shared - energy["released"]) <= BAR_TOL * energy["released"], (shared, energy)
    assert energy["kept"] > 0.0 and energy["sling"] >= 0.0



#: Trebuchator's presets' titles, as each design file's first line names them
#: (analytic/data/designs/trebuchator/*.toml: ``# Trebuchator's preset "backyard" (Backyard Classic), ...``).
TREBUCHATOR_TITLES = {"backyard": "Backyard Classic", "simple-fixed": "Bolted Weight", "floating-arm": "Floating Arm",
                      "punkin": "Pumpkin Hurler", "siege": "Siege Trebuchet, c. 1250",
                      "warwolf": "Warwolf, Stirling 1304", "man-thrower": "Man Thrower (8647 Edition)",
                      "lab": "Laboratory Reference"}


def test_every_trebuchator_preset_is_on_the_page_under_its_files_title(client):
    """Each of Trebuchator's presets entered as a design file is offered, with its title and design."""
    from analytic.design_file import load_design
    from workbench.presets import _TREBUCHATOR

    assert sorted(path.stem for path in _TREBUCHATOR.glob("*.toml")) == sorted(TREBUCHATOR_TITLES)
    offered = {p["name"]: p for p in client.get("/api/presets").json()}
    for name, title in TREBUCHATOR_TITLES.items():
        preset = offered[f"trebuchator-{name}"]
        assert preset["title"] == f"Trebuchator: {title}"
        assert preset["design"] == json.loads(json.dumps(design_to_dict(load_design(_TREBUCHATOR / f"{name}.toml"))))


#: The workbench's own presets (``workbench/presets/*.toml``), by their names on the page.
OWN_PRESETS = ("backyard", "pumpkin-hurler", "virtual-trebuchet", "warwolf-scale")


@pytest.mark.slow
@pytest.mark.parametrize("name", OWN_PRESETS)
def test_the_front_around_each_preset_is_of_its_machine_and_never_worse_than_it(client, name):
    from analytic.design_file import design_from_dict
    from analytic.fast import simulate_fast
    from analytic.optimise.search import Settings

    design = PRESETS[name][1]()
    body = {"tool": "optimise", "design": design_to_dict(design), "client": f"front-{name}",
            "inputs": {"front": True, "generations": 1}}
    job = wait(client, client.post("/api/jobs", json=body).json())
    assert job["state"] == "done", job["error"]
    start, points = job["result"]["start"], job["result"]["points"]
    assert start["violates"] == []
    # The search scores its start at its own integrator tolerance; the answer at the final one.
    assert points[0]["range"] >= start["range"] * (1 - 10 * Settings().search_tolerance)
    for point in points:
        # not dominated by the design on screen: it neither throws as far on less load nor farther on as much
        dominated = (start["range"] >= point["range"] and start["peak_axle_load"] <= point["peak_axle_load"]
                     and (start["range"], start["peak_axle_load"]) != (point["range"], point["peak_axle_load"]))
        assert not dominated, (start, point["range"], point["peak_axle_load"])
        tables = design_to_dict(design)
        for field, value in point["changes"].items():
            table, key = field.split(".")
            tables[table][key] = value
        adopted = design_from_dict(tables)
        kept = {k: v for k, v in tables["machine"].items() if "machine." + k not in point["changes"]}
        assert kept == {k: v for k, v in design_to_dict(design)["machine"].items() if "machine." + k not in point["changes"]}
        assert adopted.machine.kind == design.machine.kind
        assert simulate_fast(adopted).range == pytest.approx(point["range"], rel=1e-7)


def test_optimise_inputs_are_checked_naming_the_field(client):
    for inputs, field in (({"problem": "mine"}, "problem"), ({"generations": 0}, "generations"),
                          ({"bounds": {"arm": [1, 2]}}, "bounds"), ({"limits": {"max_height": "tall"}}, "limits.max_height"),
                          ({"bounds": {"sling_length": [2, 1]}}, "variables.sling_length")):
        job = wait(client, client.post("/api/jobs", json={"tool": "optimise", "design": tables(), "inputs": inputs,
                                                          "client": "checks"}).json())
        assert job["state"] == "error" and job["error"]["field"] == field, (inputs, job["error"])


def test_the_bounds_centre_on_the_design_on_screen(client):
    design = PRESETS["warwolf-scale"][1]()
    job = wait(client, client.post("/api/jobs", json={"tool": "around_bounds", "design": design_to_dict(design),
                                                      "client": "bounds"}).json())
    rows = {row["name"]: row for row in job["result"]["variables"]}
    # warwolf.toml: a 3 m short arm, a 10 m sling released at 45 deg, 9 m pivot, 10 m footprint (its sling)
    assert (rows["arm_short"]["lower"], rows["arm_short"]["upper"]) == (1.5, 6.0)
    assert (rows["release_angle"]["lower"], rows["release_angle"]["upper"]) == pytest.approx((25.0, 65.0))
    assert job["result"]["limits"]["max_height"] == 9.0
    assert job["result"]["limits"]["max_footprint"] == pytest.approx(10.0)
